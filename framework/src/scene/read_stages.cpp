// Reading [[stages]] (or the [[loads]] of a scene without stages) and what a stage inherits.
#include "analysis_impl.hpp"
#include "scene/plugin_table.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "stages/builtin_actions.hpp"
#include "toml_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace stratum {

using io::check_table;
using io::location;
using io::require_string;
using scene::table_list;

void Analysis::Impl::read_stages(const toml::table& root) {
  const auto ndof = static_cast<Eigen::Index>(model.mesh.nodes.size() * DofMap::per_node);
  // ---- loads of a scene without stages, and the stages
  const auto legacy_loads = table_list(root, "loads");
  const auto stage_list = table_list(root, "stages");
  if (const auto* st = root.get("stages"); st && stage_list.empty())
    throw Error(location(*st), "stages = [] holds no stage; give at least one [[stages]] table, or leave "
                               "the key out and load the scene with [[loads]]");
  // Nothing holds the model: its matrix is singular (found on 997ba04: one "converged" iteration).
  // A head pushed down by a prescribed settlement holds it too.
  if (table_list(root, "constraints").empty()) {
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
  if (stage_list.empty() && legacy_loads.empty() && model.prescribed.cwiseAbs().maxCoeff() == 0.0)
    throw Error(location(root), "the scene applies nothing: no [[loads]], no [[stages]] and no non-zero "
                                "[[constraints]] value; a run would solve a zero load");
  if (!stage_list.empty() && !legacy_loads.empty())
    throw Error(location(*legacy_loads.front()),
                "[[loads]] cannot be combined with [[stages]]; give loads as actions of a stage");
  initial_prescribed = model.prescribed;
  model.prescribed_base = Eigen::VectorXd::Zero(ndof);
  model.load_base = Eigen::VectorXd::Zero(ndof);
  model.load_ref = Eigen::VectorXd::Zero(ndof);
  std::set<std::string> load_names;
  if (stage_list.empty()) {
    stage::Stage st;
    st.name = "load";
    st.where = location(root);
    st.steps = stepping.steps;
    st.increments = stepping.increments;
    st.max_cutbacks = stepping.max_cutbacks;
    st.error_tolerance = stepping.error_tolerance;
    st.every = every;
    st.vtk = vtk;
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
      st.actions.push_back(
          parse_action(t, "[[loads]]", "load#" + std::to_string(i + 1), load_names, st.reset_after));
    }
    stages.push_back(std::move(st));
  } else {
    for (std::size_t i = 0; i < stage_list.size(); ++i)
      stages.push_back(parse_stage(*stage_list[i], "[[stages]] #" + std::to_string(i + 1), load_names));
    // What a stage inherits (docs/scene.md "What a stage inherits"): [analysis] max_cutbacks,
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
    for (std::size_t i = 0; i + 1 < stages.size(); ++i)
      if (stages[i].until_failure || stages[i].stop_settlement > 0)
        throw Error(stages[i].where,
                    "[[stages]] \"" + stages[i].name + "\" has " +
                        (stages[i].until_failure ? "until_failure = true" : "stop_settlement") +
                        ", which ends the run, but stage \"" + stages[i + 1].name +
                        "\" follows it; only the last stage may load to failure or to a "
                        "settlement limit");
    std::set<std::string> seen;
    for (const auto& st : stages)
      if (!seen.insert(st.name).second)
        throw Error(st.where,
                    "[[stages]] name = \"" + st.name + "\" is used twice; stage names must be unique");
  }
}

std::unique_ptr<StageAction> Analysis::Impl::parse_action(const toml::table& at, const std::string& actx,
                                                          const std::string& default_load_name,
                                                          std::set<std::string>& load_names,
                                                          bool& reset_after) {
  const Schema action_keys = scene::action_schema(); // type (the action's own keys follow its schema)
  const std::string type = require_string(at, "type", actx);
  const std::string ctx = actx + " type = \"" + type + "\"";
  const SourceLocation type_at = location(*at.get("type"));
  if (!registry.has(PluginKind::stage_action, type)) {
    const auto plugins = catalog->known(PluginKind::stage_action);
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
  auto action = scene::plugin_from_table<StageAction>(*catalog, registry, type, type_at, ctx, at, ctx,
                                                      scene::key_names(action_keys), units);
  StageCheck check{model.mesh, ctx, location(at), load_names, default_load_name, false};
  action->check(check);
  reset_after = reset_after || check.reset_after;
  return action;
}

stage::Stage Analysis::Impl::parse_stage(const toml::table& t, const std::string& ctx,
                                         std::set<std::string>& load_names) {
  const scene::TableKeys keys =
      scene::stage_keys(stepping.max_cutbacks, stepping.error_tolerance, vtk, static_cast<long long>(every));
  const auto p = check_table(t, keys.schema, ctx, keys.other_names(), units);
  stage::Stage st;
  st.name = p.text("name");
  st.where = location(t);
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
  if (!st.monitor.empty() && !model.mesh.node_sets.count(st.monitor))
    throw Error(p.where("monitor"),
                ctx + " monitor = \"" + st.monitor +
                    "\" is not a node or edge set of the mesh; known: " + key_list(model.mesh.node_sets));
  st.vtk = p.flag("vtk");
  st.every = static_cast<int>(p.integer("every"));
  st.checkpoint = p.flag("checkpoint");

  const auto actions = table_list(t, "actions");
  for (std::size_t i = 0; i < actions.size(); ++i) {
    const std::string actx = ctx + " [[stages.actions]] #" + std::to_string(i + 1);
    const std::string type = require_string(*actions[i], "type", actx);
    st.actions.push_back(parse_action(*actions[i], actx, type + "@" + st.name, load_names, st.reset_after));
  }
  return st;
}

} // namespace stratum
