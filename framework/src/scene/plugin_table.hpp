// "Plugin from a table": find the plugin a scene names (opening its library), check the
// scene's table against the schema the plugin declares, create it. Every place where a scene
// names a plugin (materials, elements, contact laws, interface elements, the solver, stage
// actions, mesh generators, the point driver's material) goes through here.
#pragma once

#include "scene/toml_check.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"

#include <toml++/toml.h>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace stratum::scene {

/// Makes sure `name` of `kind` is registered, opening the library that provides it. Errors are
/// located at `at` and start with `what`, e.g. `[materials.soil] model = "x"`.
void require_plugin(PluginCatalog& catalog, Registry& registry, PluginKind kind, const std::string& name,
                    const SourceLocation& at, const std::string& what);

/// A plugin's factory and the scene's table checked against its schema.
template <class T> struct PluginTable {
  const Factory<T>* factory = nullptr;
  Params params;
  [[nodiscard]] std::unique_ptr<T> create() const { return factory->create(params); }
};

/// Finds the plugin `name` (kind from T) and checks `table` against its schema; the keys in
/// `extra` belong to the scene (e.g. `model`), not to the plugin. `ctx` names the table; `units`
/// are the scene's (defaults convert into them, io::check_table).
template <class T>
PluginTable<T> plugin_table(PluginCatalog& catalog, Registry& registry, const std::string& name,
                            const SourceLocation& at, const std::string& what, const toml::table& table,
                            const std::string& ctx, const std::vector<std::string_view>& extra = {},
                            const Units& units = {}) {
  require_plugin(catalog, registry, plugin_kind_of<T>(), name, at, what);
  const auto& f = registry.factory<T>(name);
  return {&f, io::check_table(table, f.schema, ctx, extra, units)};
}

/// The same, and creates the plugin.
template <class T>
std::unique_ptr<T> plugin_from_table(PluginCatalog& catalog, Registry& registry, const std::string& name,
                                     const SourceLocation& at, const std::string& what,
                                     const toml::table& table, const std::string& ctx,
                                     const std::vector<std::string_view>& extra = {},
                                     const Units& units = {}) {
  return plugin_table<T>(catalog, registry, name, at, what, table, ctx, extra, units).create();
}

/// An element's formulation follows [analysis] unless its table states it; then they must agree.
void follow_formulation(const Schema& schema, const toml::table& table, Params& params, Formulation form,
                        const std::string& ctx);

} // namespace stratum::scene
