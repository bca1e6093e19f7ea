// [materials], [[domains]] and [[constraints]]: read into the Scene (scene.hpp), then built
// against the mesh.
#include "scene/plugin_table.hpp"
#include "scene/scene.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "scene/toml_check.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace stratum {

using io::check_table;
using io::location;
using io::require_string;
using scene::optional_table;
using scene::table_list;

namespace {

/// A domain's drainage and, for an undrained one, its fluid stiffness.
void read_drainage(const toml::table& t, const std::string& ctx, scene::DomainSpec& d) {
  const Schema keys = scene::domain_schema();
  if (const toml::node* n = t.get("drainage")) {
    d.drainage = require_string(t, "drainage", ctx);
    d.drainage_at = location(*n);
    const ParamSpec& spec = *keys.find("drainage");
    if (std::find(spec.choices.begin(), spec.choices.end(), d.drainage) == spec.choices.end())
      throw Error(d.drainage_at, ctx + " drainage = \"" + d.drainage + "\" is not allowed; allowed: " +
                                     spec.allowed() + did_you_mean(d.drainage, spec.choices));
  }
  const toml::node* k = t.get("fluid_stiffness");
  if (d.drainage == "undrained" && !k)
    throw Error(d.drainage_at, ctx + " drainage = \"undrained\" needs fluid_stiffness = K_w / n (kPa), "
                                     "e.g. 5.5e6 for water at n = 0.4");
  if (k && d.drainage != "undrained")
    throw Error(location(*k), ctx + " fluid_stiffness acts only with drainage = \"undrained\" (here: \"" +
                                  d.drainage + "\")");
  if (k) {
    const auto v = k->value<double>();
    if (!v || !(*v > 0.0) || !std::isfinite(*v))
      throw Error(location(*k), ctx + " fluid_stiffness must be a number in (0, inf)");
    d.fluid_stiffness = *v;
  }
}

} // namespace

void scene::read_domains(const toml::table& root, PluginCatalog& catalog, Registry& registry, Scene& sc) {
  // ---- materials
  std::map<std::string, std::size_t> material_by_name;
  {
    const auto& mats = optional_table(root, "materials");
    const Schema material_keys = scene::material_schema();
    for (auto&& [key, value] : mats) {
      const std::string name(key.str());
      const std::string ctx = "[materials." + name + "]";
      const auto* t = value.as_table();
      if (!t) throw Error(location(value), ctx + " must be a table");
      const std::string model_name = require_string(*t, "model", ctx);
      sc.materials.push_back(
          {name, scene::plugin_table<Material>(catalog, registry, model_name, location(*t->get("model")),
                                               ctx + " model = \"" + model_name + "\"", *t, ctx,
                                               scene::key_names(material_keys), sc.units)});
      material_by_name[name] = sc.materials.size() - 1;
    }
  }

  // ---- domains
  // (A scene without [[domains]] is refused when it is built, after its mesh: a scene being
  // written meets the problems in the order of its sections.)
  const auto domain_list = table_list(root, "domains");
  if (const auto* d = root.get("domains")) sc.domains_at = location(*d);
  const Schema domain_keys = scene::domain_schema();
  for (std::size_t i = 0; i < domain_list.size(); ++i) {
    const auto& t = *domain_list[i];
    DomainSpec d;
    d.context = "[[domains]] #" + std::to_string(i + 1);
    const std::string& ctx = d.context;
    d.cells = require_string(t, "cells", ctx);
    d.element = require_string(t, "element", ctx);
    d.cells_at = location(*t.get("cells"));
    d.element_at = location(*t.get("element"));
    if (t.get("material")) {
      d.material = require_string(t, "material", ctx);
      d.material_at = location(*t.get("material"));
      auto mat = material_by_name.find(d.material);
      if (mat == material_by_name.end())
        throw Error(d.material_at, ctx + " material = \"" + d.material + "\" is not defined; defined: " +
                                       key_list(material_by_name, d.material));
      d.material_index = mat->second;
    }
    read_drainage(t, ctx, d);
    d.plugin = scene::plugin_table<Element>(catalog, registry, d.element, d.element_at,
                                            ctx + " element = \"" + d.element + "\"", t, ctx,
                                            scene::key_names(domain_keys), sc.units);
    scene::follow_formulation(d.plugin.factory->schema, t, d.plugin.params, sc.settings.formulation, ctx);
    sc.domains.push_back(std::move(d));
  }
}

void scene::read_constraints(const toml::table& root, Scene& sc) {
  for (const auto* t : table_list(root, "constraints")) {
    const std::string ctx = "[[constraints]] at line " + std::to_string(location(*t).line);
    ConstraintSpec c;
    c.at = location(*t);
    (void)require_string(*t, "nodes", ctx); // "needs nodes", located, before the key check
    const auto p = check_table(*t, scene::constraint_schema(), "[[constraints]]");
    c.nodes = p.text("nodes");
    c.nodes_at = p.where("nodes");
    for (int k = 0; k < 2; ++k) {
      const char* key = k == 0 ? "ux" : "uy";
      if (!t->get(key)) continue;
      c.value[static_cast<std::size_t>(k)] = p.real(key);
      c.value_at[static_cast<std::size_t>(k)] = p.where(key);
    }
    if (t->get("field") || t->get("value")) {
      if (!t->get("field") || !t->get("value"))
        throw Error(c.at, "[[constraints]] nodes = \"" + c.nodes + "\": `field` and `value` go together");
      c.field = p.text("field"), c.field_at = p.where("field");
      c.field_value = p.real("value"), c.field_value_at = p.where("value");
      if (c.field == "ux" || c.field == "uy")
        throw Error(c.field_at, "[[constraints]] field = \"" + c.field + "\": write the displacement as " +
                                    c.field + " = VALUE");
    }
    if (!c.value[0] && !c.value[1] && c.field.empty())
      throw Error(c.at, "[[constraints]] nodes = \"" + c.nodes +
                            "\" constrains nothing; give ux and/or uy, or field and value");
    io::require_read(p, scene::constraint_schema(), "[[constraints]]");
    sc.constraints.push_back(std::move(c));
  }
}

} // namespace stratum
