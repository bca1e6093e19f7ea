#include "scene/plugin_table.hpp"

namespace stratum::scene {

void require_plugin(PluginCatalog& catalog, Registry& registry, PluginKind kind, const std::string& name,
                    const SourceLocation& at, const std::string& what) {
  if (registry.has(kind, name)) return; // built in, or its library is open already
  try {
    catalog.require(registry, kind, name);
  } catch (const Error& e) {
    throw Error(at, what + ": " + e.message());
  }
}

void follow_formulation(const Schema& schema, const toml::table& table, Params& params, Formulation form,
                        const std::string& ctx) {
  if (!schema.find("formulation")) return;
  const std::string name = form == Formulation::axisymmetric ? "axisymmetric" : "plane_strain";
  if (const auto* fv = table.get("formulation"); fv && params.text("formulation") != name)
    throw Error(io::location(*fv), ctx + " formulation = " + io::show(*fv) +
                                       " contradicts [analysis] formulation = \"" + name + "\"");
  params.set("formulation", name, params.where("formulation"));
}

} // namespace stratum::scene
