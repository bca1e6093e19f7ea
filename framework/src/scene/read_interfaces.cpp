// [contact_laws.<name>] and [[interfaces]]: read into the Scene (scene.hpp); built by
// model/body_interfaces.cpp.
#include "scene/plugin_table.hpp"
#include "scene/scene.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "scene/toml_check.hpp"
#include "suggest.hpp"

#include <map>
#include <set>

namespace stratum {

namespace {

using io::check_table;
using io::location;
using io::require_string;

} // namespace

void scene::read_interfaces(const toml::table& root, PluginCatalog& catalog, Registry& registry, Scene& sc) {
  // [contact_laws.<name>]
  std::map<std::string, std::size_t> law_by_name;
  if (const toml::node* n = root.get("contact_laws")) {
    const auto* laws = n->as_table();
    if (!laws) throw Error(location(*n), "contact_laws must be a table of [contact_laws.<name>] tables");
    const Schema law_keys = scene::contact_law_schema();
    for (auto&& [key, value] : *laws) {
      const std::string name(key.str());
      const std::string ctx = "[contact_laws." + name + "]";
      const auto* t = value.as_table();
      if (!t) throw Error(location(value), ctx + " must be a table");
      const std::string model_name = require_string(*t, "model", ctx);
      sc.contact_laws.push_back(
          {name, scene::plugin_table<ContactLaw>(catalog, registry, model_name, location(*t->get("model")),
                                                 ctx + " model = \"" + model_name + "\"", *t, ctx,
                                                 scene::key_names(law_keys), sc.units)});
      law_by_name[name] = sc.contact_laws.size() - 1;
    }
  }

  // [[interfaces]]
  const toml::node* list = root.get("interfaces");
  if (!list) return;
  const auto* arr = list->as_array();
  if (!arr) throw Error(location(*list), "interfaces must be an array of tables [[interfaces]]");
  int index = 0;
  const Schema interface_keys = scene::interface_schema();
  for (const auto& entry : *arr) {
    ++index;
    const auto* t = entry.as_table();
    if (!t) throw Error(location(entry), "interfaces entries must be tables [[interfaces]]");
    InterfaceSpec f;
    f.context = "[[interfaces]] #" + std::to_string(index);
    const std::string& ctx = f.context;
    f.at = location(*t);
    f.edges = require_string(*t, "edges", ctx);
    f.element = require_string(*t, "element", ctx);
    const std::string law = require_string(*t, "law", ctx);
    f.edges_at = location(*t->get("edges"));
    f.element_at = location(*t->get("element"));
    f.name = f.edges;
    if (const auto* v = t->get("name")) {
      if (!v->is_string()) throw Error(location(*v), ctx + " name must be a string");
      f.name = v->as_string()->get();
      scene::require_file_name(f.name, location(*v), ctx, "name");
    }
    if (const auto* v = t->get("cells")) {
      if (!v->is_string()) throw Error(location(*v), ctx + " cells must be a string (a cell set)");
      f.cells = v->as_string()->get();
      f.cells_at = location(*v);
    }
    if (const auto* v = t->get("csv")) {
      if (!v->is_boolean()) throw Error(location(*v), ctx + " csv must be true or false");
      f.csv = v->as_boolean()->get();
    }
    auto lw = law_by_name.find(law);
    if (lw == law_by_name.end())
      throw Error(location(*t->get("law")),
                  ctx + " law = \"" + law +
                      "\" is not defined; defined [contact_laws]: " + key_list(law_by_name, law));
    f.law_index = lw->second;
    f.plugin = scene::plugin_table<Element>(catalog, registry, f.element, f.element_at,
                                            ctx + " element = \"" + f.element + "\"", *t, ctx,
                                            scene::key_names(interface_keys), sc.units);
    scene::follow_formulation(f.plugin.factory->schema, *t, f.plugin.params, sc.settings.formulation, ctx);
    sc.interfaces.push_back(std::move(f));
  }
}

} // namespace stratum
