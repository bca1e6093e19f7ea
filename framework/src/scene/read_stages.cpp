// [[stages]] (or the [[loads]] of a scene without stages) and what a stage inherits: read into
// the Scene (scene.hpp), then built (actions created and checked against the mesh in order).
#include "scene/plugin_table.hpp"
#include "scene/scene.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "scene/toml_check.hpp"
#include "stages/builtin_actions.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace stratum {

using io::check_table;
using io::location;
using io::require_string;
using scene::table_list;

namespace {

/// One [[stages.actions]] (or [[loads]]) table: its action's factory from the registry by `type`
/// and the table checked against the action's schema.
scene::ActionSpec read_action(const toml::table& at, const std::string& actx,
                              const std::string& default_load_name, PluginCatalog& catalog,
                              Registry& registry, const Units& units) {
  const Schema action_keys = scene::action_schema(); // type (the action's own keys follow its schema)
  const std::string type = require_string(at, "type", actx);
  const std::string ctx = actx + " type = \"" + type + "\"";
  const SourceLocation type_at = location(*at.get("type"));
  if (!registry.has(PluginKind::stage_action, type)) {
    const auto plugins = catalog.known(PluginKind::stage_action);
    if (std::find(plugins.begin(), plugins.end(), type) == plugins.end()) {
      std::vector<std::string> all = stage::builtin_action_types();
      for (const auto& list : {registry.names(PluginKind::stage_action), plugins})
        for (const auto& n : list)
          if (std::find(all.begin(), all.end(), n) == all.end()) all.push_back(n);
      std::string allowed;
      for (const auto& n : all) allowed += (allowed.empty() ? "" : ", ") + n;
      throw Error(type_at, ctx + " is not allowed; allowed: one of: " + allowed + did_you_mean(type, all));
    }
  }
  return {ctx, default_load_name, location(at),
          scene::plugin_table<StageAction>(catalog, registry, type, type_at, ctx, at, ctx,
                                           scene::key_names(action_keys), units)};
}

scene::StageSpec read_stage(const toml::table& t, const std::string& ctx, const scene::Settings& s,
                            PluginCatalog& catalog, Registry& registry, const Units& units) {
  const scene::TableKeys keys = scene::stage_keys(s.stepping.max_cutbacks, s.stepping.error_tolerance, s.vtk,
                                                  static_cast<long long>(s.every));
  const auto p = check_table(t, keys.schema, ctx, keys.other_names(), units);
  scene::StageSpec spec;
  stage::Stage& st = spec.settings;
  st.name = p.text("name");
  scene::require_file_name(st.name, p.where("name"), ctx, "name");
  st.where = location(t);
  st.consolidation = p.text("type") == "consolidation";
  if (st.consolidation) {
    if (!t.get("duration"))
      throw Error(p.where("type"),
                  ctx + " a consolidation stage needs its duration (s), e.g. duration = 86400.0");
    st.duration = p.real("duration");
    st.until_excess_pressure = p.real("until_excess_pressure");
  } else {
    for (const char* key : {"duration", "until_excess_pressure"})
      if (t.get(key))
        throw Error(p.where(key), ctx + " " + key + " acts only in a stage with type = \"consolidation\"");
  }
  st.steps = static_cast<int>(p.integer("steps"));
  st.increments = p.real_list("increments");
  if (!st.increments.empty()) {
    double sum = 0.0;
    for (double v : st.increments) {
      if (!(v > 0)) throw Error(p.where("increments"), ctx + " increments must all be > 0");
      sum += v;
    }
    if (std::abs(sum - 1.0) > 1e-9)
      throw Error(p.where("increments"),
                  ctx + " increments sum to " + std::to_string(sum) + "; they must sum to 1");
    if (t.get("steps")) throw Error(p.where("steps"), ctx + " give either steps or increments, not both");
  }
  st.max_cutbacks = static_cast<int>(p.integer("max_cutbacks"));
  st.error_tolerance = p.real("error_tolerance");
  st.until_failure = p.flag("until_failure");
  st.collapse_stiffness = p.real("collapse_stiffness");
  if (t.get("collapse_stiffness") && !st.until_failure)
    throw Error(p.where("collapse_stiffness"),
                ctx + " collapse_stiffness acts only in a stage with until_failure = true");
  st.stop_settlement = p.real("stop_settlement");
  st.monitor = p.text("monitor");
  spec.monitor_at = p.where("monitor");
  st.vtk = p.flag("vtk");
  st.every = static_cast<int>(p.integer("every"));
  st.checkpoint = p.flag("checkpoint");

  const auto actions = table_list(t, "actions");
  for (std::size_t i = 0; i < actions.size(); ++i) {
    const std::string actx = ctx + " [[stages.actions]] #" + std::to_string(i + 1);
    const std::string type = require_string(*actions[i], "type", actx);
    spec.actions.push_back(read_action(*actions[i], actx, type + "@" + st.name, catalog, registry, units));
  }
  io::require_read(p, keys.schema, ctx);
  return spec;
}

} // namespace

void scene::read_stages(const toml::table& root, PluginCatalog& catalog, Registry& registry, Scene& sc) {
  // ---- loads of a scene without stages, and the stages
  const auto legacy_loads = table_list(root, "loads");
  const auto stage_list = table_list(root, "stages");
  if (const auto* st = root.get("stages"); st && stage_list.empty())
    throw Error(location(*st), "stages = [] holds no stage; give at least one [[stages]] table, or leave "
                               "the key out and load the scene with [[loads]]");
  for (const auto* st : stage_list)
    for (const auto* a : table_list(*st, "actions"))
      if (const auto* type = a->get("type"); type && type->value<std::string>() == std::string("load"))
        sc.settings.pile_head = true;
  // Nothing holds the model: its matrix is singular (found on 997ba04: one "converged" iteration).
  // A head pushed down by a prescribed settlement holds it too.
  if (sc.constraints.empty()) {
    bool prescribed = false;
    for (const auto* st : stage_list)
      for (const auto* a : table_list(*st, "actions")) prescribed = prescribed || a->get("settlement");
    if (!prescribed)
      throw Error(location(root),
                  "the scene has no [[constraints]]: nothing holds the model against rigid-body "
                  "motion (its matrix is singular); fix some nodes, e.g. [[constraints]] nodes = "
                  "\"bottom\", ux = 0.0, uy = 0.0");
  }
  // A scene without stages whose [[loads]] are absent and whose constraints prescribe nothing.
  bool moves = false;
  for (const auto& c : sc.constraints) {
    for (const auto& v : c.value) moves = moves || (v && *v != 0.0);
    moves = moves || (!c.field.empty() && c.field_value != 0.0); // e.g. a head held at a value
  }
  if (stage_list.empty() && legacy_loads.empty() && !moves)
    throw Error(location(root), "the scene applies nothing: no [[loads]], no [[stages]] and no non-zero "
                                "[[constraints]] value; a run would solve a zero load");
  if (!stage_list.empty() && !legacy_loads.empty())
    throw Error(location(*legacy_loads.front()),
                "[[loads]] cannot be combined with [[stages]]; give loads as actions of a stage");
  const Settings& s = sc.settings;
  sc.staged = !stage_list.empty();
  if (stage_list.empty()) {
    StageSpec spec;
    stage::Stage& st = spec.settings;
    st.name = "load";
    st.where = location(root);
    st.steps = s.stepping.steps;
    st.increments = s.stepping.increments;
    st.max_cutbacks = s.stepping.max_cutbacks;
    st.error_tolerance = s.stepping.error_tolerance;
    st.every = s.every;
    st.vtk = s.vtk;
    st.checkpoint = false;
    // [[loads]]: the loads of a scene without stages, read by the pressure, force and gravity actions.
    const Schema load_keys = scene::loads_schema();
    const ParamSpec& load_type_spec = *load_keys.find("type");
    for (std::size_t i = 0; i < legacy_loads.size(); ++i) {
      const auto& t = *legacy_loads[i];
      const std::string type = require_string(t, "type", "[[loads]]");
      const std::string ctx = "[[loads]] type = \"" + type + "\"";
      if (type == "load") throw Error(location(*t.get("type")), ctx + " is only allowed as a stage action");
      const auto& load_types = load_type_spec.choices; // pressure, force, gravity
      if (std::find(load_types.begin(), load_types.end(), type) == load_types.end())
        throw Error(location(*t.get("type")), ctx + " is not allowed; allowed: " + load_type_spec.allowed());
      spec.actions.push_back(
          read_action(t, "[[loads]]", "load#" + std::to_string(i + 1), catalog, registry, sc.units));
    }
    sc.stages.push_back(std::move(spec));
    return;
  }
  for (std::size_t i = 0; i < stage_list.size(); ++i)
    sc.stages.push_back(
        read_stage(*stage_list[i], "[[stages]] #" + std::to_string(i + 1), s, catalog, registry, sc.units));
  // What a stage inherits (README.md "What a stage inherits"): [analysis] max_cutbacks,
  // error_tolerance, the step-control keys, and [output] vtk and every are defaults of every
  // stage; [analysis] steps and increments describe the one load case of a scene without
  // stages and cannot act here (found on 997ba04: steps = 10 silently ran 1 step per stage).
  if (const auto* at = root["analysis"].as_table())
    for (const char* key : {"steps", "increments"})
      if (const auto* v = at->get(key))
        throw Error(location(*v), std::string("[analysis] ") + key +
                                      " cannot act in a scene with [[stages]]: each stage gives its own " +
                                      key + " (steps default to 1); move it into the stages");
  // A stage that may end the run early (until_failure, stop_settlement) must be the last one:
  // otherwise the later stages would silently never run.
  for (std::size_t i = 0; i + 1 < sc.stages.size(); ++i) {
    const stage::Stage& st = sc.stages[i].settings;
    if (st.until_failure || st.stop_settlement > 0)
      throw Error(st.where, "[[stages]] \"" + st.name + "\" has " +
                                (st.until_failure ? "until_failure = true" : "stop_settlement") +
                                ", which ends the run, but stage \"" + sc.stages[i + 1].settings.name +
                                "\" follows it; only the last stage may load to failure or to a "
                                "settlement limit");
  }
  std::set<std::string> seen;
  for (const auto& spec : sc.stages)
    if (!seen.insert(spec.settings.name).second)
      throw Error(spec.settings.where, "[[stages]] name = \"" + spec.settings.name +
                                           "\" is used twice; stage names must be unique");
}

} // namespace stratum
