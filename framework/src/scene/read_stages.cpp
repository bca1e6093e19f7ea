// Reading [[stages]] (or the [[loads]] of a scene without stages) and what a stage inherits.
#include "run/analysis_impl.hpp"
#include "scene/tables.hpp"
#include "toml_check.hpp"

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
    for (std::size_t i = 0; i < legacy_loads.size(); ++i) {
      stage::Action a;
      a.kind = stage::Action::Kind::add_load;
      a.where = location(*legacy_loads[i]);
      a.load = parse_load(*legacy_loads[i], "[[loads]]", "load#" + std::to_string(i + 1));
      st.actions.push_back(a);
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

stage::LoadSpec Analysis::Impl::parse_load(const toml::table& t, const std::string& where_ctx,
                                           const std::string& default_name) {
  const std::string type = require_string(t, "type", where_ctx);
  const std::string ctx = where_ctx + " type = \"" + type + "\"";
  stage::LoadSpec spec;
  auto check_set = [&](const auto& sets, const Params& p, const char* key, const char* what) {
    if (!sets.count(p.text(key)))
      throw Error(p.where(key).known() ? p.where(key) : location(t),
                  ctx + " " + key + " = \"" + p.text(key) + "\" is not " + what +
                      " of the mesh; known: " + key_list(sets, p.text(key)));
  };
  if (type == "pressure") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(default_name);
    s.text("edges", {}, "edge set");
    s.real("p", "kPa", "normal pressure at and above the surface, positive pushing into the body")
        .defaults_to(0.0);
    s.real("gamma", "kN/m3", "pressure gradient with depth below `surface` (fresh concrete: its unit weight)")
        .at_least(0)
        .defaults_to(0.0);
    s.real("surface", "m", "level y where the depth-dependent part starts").defaults_to(0.0);
    s.real("critical_depth", "m", "depth below which the pressure stops growing (bilinear envelope)")
        .greater_than(0)
        .defaults_to(std::numeric_limits<double>::infinity());
    const auto p = check_table(t, s, ctx, {"type"});
    check_set(model.mesh.edge_sets, p, "edges", "an edge set");
    spec.kind = stage::LoadSpec::Kind::pressure;
    spec.name = p.text("name"), spec.set = p.text("edges");
    spec.p = p.real("p"), spec.gamma = p.real("gamma"), spec.surface = p.real("surface");
    spec.critical_depth = p.real("critical_depth");
  } else if (type == "load") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(std::string("head"));
    s.text("edges", {}, "edge set carrying the load").defaults_to(std::string());
    s.text("cells", {}, "or: a cell set whose top faces carry it (a pile head)").defaults_to(std::string());
    s.real("force", "kN", "total downward force at the end of the stage (axisymmetric: whole circle)");
    const auto p = check_table(t, s, ctx, {"type"});
    if (p.text("edges").empty() == p.text("cells").empty())
      throw Error(location(t),
                  ctx + " needs exactly one of edges = \"<edge set>\" or cells = \"<cell set>\"");
    spec.kind = stage::LoadSpec::Kind::pressure;
    spec.name = p.text("name");
    if (!p.text("edges").empty()) {
      check_set(model.mesh.edge_sets, p, "edges", "an edge set");
      spec.set = p.text("edges");
    } else {
      check_set(model.mesh.cell_sets, p, "cells", "a cell set");
      spec.set = p.text("cells");
      spec.top_of_cells = true;
    }
    spec.total_force = p.real("force");
  } else if (type == "force") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(default_name);
    s.text("nodes", {}, "node set");
    s.real("fx", "kN", "force per node along x (axisymmetric: total over the circle)").defaults_to(0.0);
    s.real("fy", "kN", "force per node along y (axisymmetric: total over the circle)").defaults_to(0.0);
    const auto p = check_table(t, s, ctx, {"type"});
    check_set(model.mesh.node_sets, p, "nodes", "a node set");
    spec.kind = stage::LoadSpec::Kind::force;
    spec.name = p.text("name"), spec.set = p.text("nodes");
    spec.fx = p.real("fx"), spec.fy = p.real("fy");
  } else if (type == "gravity") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(default_name);
    s.text("cells", {}, "cell set (only its active cells are loaded)").defaults_to(std::string("all"));
    s.real("gamma", "kN/m3", "unit weight, acting downwards (-y)").at_least(0);
    const auto p = check_table(t, s, ctx, {"type"});
    check_set(model.mesh.cell_sets, p, "cells", "a cell set");
    spec.kind = stage::LoadSpec::Kind::gravity;
    spec.name = p.text("name"), spec.set = p.text("cells");
    spec.gamma = p.real("gamma");
  } else {
    throw Error(location(*t.get("type")), ctx + " is not allowed; allowed: one of: pressure, force, gravity" +
                                              std::string(where_ctx == "[[loads]]" ? "" : ", load"));
  }
  if (where_ctx == "[[loads]]" && type == "load")
    throw Error(location(*t.get("type")), ctx + " is only allowed as a stage action");
  return spec;
}

stage::Stage Analysis::Impl::parse_stage(const toml::table& t, const std::string& ctx,
                                         std::set<std::string>& load_names) {
  using stage::Action;
  Schema s;
  s.text("name", {}, "stage name (checkpoints and output are named after it)");
  s.integer("steps", "-", "equal load increments of the stage").at_least(1).defaults_to(1LL);
  s.real_list("increments", "-", "load-factor increments summing to 1 (instead of steps)")
      .defaults_to(std::vector<double>{});
  s.integer("max_cutbacks", "-", "halvings of a failed step before the stage fails")
      .at_least(0)
      .at_most(30)
      .defaults_to(static_cast<long long>(stepping.max_cutbacks));
  s.real("error_tolerance", "-",
         "error-controlled load steps in this stage ([analysis] error_tolerance: the meaning and "
         "the default); 0: the steps as listed")
      .at_least(0)
      .defaults_to(stepping.error_tolerance);
  s.boolean("until_failure", "a step failing after its cut-backs ends the run normally (loading to failure)")
      .defaults_to(false);
  s.real("collapse_stiffness", "-",
         "with until_failure: the stop counts as a collapse when the least current stiffness of the "
         "steps over the last tenth of the load reached (Bergan's parameter: dlambda / (F_ref . du) "
         "under load control) is below this fraction of the stage's first step; otherwise it is a "
         "numerical failure (exit 4)")
      .greater_than(0)
      .at_most(1)
      .defaults_to(0.1);
  s.real("stop_settlement", "m", "stop once the mean settlement of `monitor` exceeds this (0: never)")
      .at_least(0)
      .defaults_to(0.0);
  s.text("monitor", {}, "edge or node set whose mean downward displacement is the settlement")
      .defaults_to(std::string());
  s.boolean("vtk", "write VTK output during this stage").defaults_to(vtk);
  s.integer("every", "-", "write every n-th step").at_least(1).defaults_to(static_cast<long long>(every));
  s.boolean("checkpoint", "write a checkpoint at the end of the stage").defaults_to(true);
  const auto p = check_table(t, s, ctx, {"actions"});
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
    const auto& at = *actions[i];
    const std::string actx = ctx + " [[stages.actions]] #" + std::to_string(i + 1);
    const std::string type = require_string(at, "type", actx);
    Action a;
    a.where = location(at);
    auto cell_set = [&](const Params& q, const char* key) {
      if (!model.mesh.cell_sets.count(q.text(key)))
        throw Error(q.where(key).known() ? q.where(key) : a.where,
                    actx + " " + key + " = \"" + q.text(key) +
                        "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
      return q.text(key);
    };
    if (type == "geostatic") {
      Schema g;
      g.text("cells", {}, "cells that receive the initial stress and their self-weight")
          .defaults_to(std::string("all"));
      g.real("gamma", "kN/m3", "unit weight").greater_than(0);
      g.real("K0", "-", "earth pressure coefficient at rest, sigma_h = K0 sigma_v").greater_than(0);
      g.real("surface", "m", "ground level y").defaults_to(0.0);
      g.text("name", {}, "name of the self-weight load it adds").defaults_to(std::string("self_weight"));
      const auto q = check_table(at, g, actx + " type = \"geostatic\"", {"type"});
      a.kind = Action::Kind::geostatic;
      a.cells = cell_set(q, "cells");
      a.gamma = q.real("gamma"), a.K0 = q.real("K0"), a.surface = q.real("surface");
      a.load.kind = stage::LoadSpec::Kind::gravity;
      a.load.name = q.text("name"), a.load.set = a.cells, a.load.gamma = a.gamma;
      if (!load_names.insert(a.load.name).second)
        throw Error(a.where, actx + " adds a load named \"" + a.load.name + "\", which is already applied");
      st.reset_after = true;
    } else if (type == "deactivate" || type == "activate") {
      Schema g;
      g.text("cells", {}, "cell set");
      if (type == "activate") {
        g.text(
             "stress", {"zero", "hydrostatic"},
             "initial stress of the placed cells: none, or a fluid's -gamma (surface - y) in all directions")
            .defaults_to(std::string("zero"));
        g.real("gamma", "kN/m3", "unit weight of the fluid for stress = \"hydrostatic\"")
            .at_least(0)
            .defaults_to(0.0);
        g.real("surface", "m", "fluid surface level y").defaults_to(0.0);
      }
      const auto q = check_table(at, g, actx + " type = \"" + type + "\"", {"type"});
      a.kind = type == "activate" ? Action::Kind::activate : Action::Kind::deactivate;
      a.cells = cell_set(q, "cells");
      if (type == "activate") {
        a.hydrostatic = q.text("stress") == "hydrostatic";
        a.gamma = q.real("gamma"), a.surface = q.real("surface");
      }
    } else if (type == "remove") {
      Schema g;
      g.text("name", {}, "name of an applied load");
      const auto q = check_table(at, g, actx + " type = \"remove\"", {"type"});
      if (!load_names.erase(q.text("name"))) {
        std::string known;
        for (const auto& n : load_names) known += (known.empty() ? "" : ", ") + n;
        throw Error(q.where("name"),
                    actx + " name = \"" + q.text("name") +
                        "\" is not an applied load; applied: " + (known.empty() ? "(none)" : known));
      }
      a.kind = Action::Kind::remove_load;
      a.name = q.text("name");
    } else if (type == "displacement") {
      Schema g;
      g.text("nodes", {}, "node set");
      g.real("ux", "m", "x displacement increment over the stage").defaults_to(0.0);
      g.real("uy", "m", "y displacement increment over the stage").defaults_to(0.0);
      const auto q = check_table(at, g, actx + " type = \"displacement\"", {"type"});
      if (!model.mesh.node_sets.count(q.text("nodes")))
        throw Error(q.where("nodes"),
                    actx + " nodes = \"" + q.text("nodes") +
                        "\" is not a node set of the mesh; known: " + key_list(model.mesh.node_sets));
      if (!at.get("ux") && !at.get("uy"))
        throw Error(a.where, actx + " prescribes nothing; give ux and/or uy");
      a.kind = Action::Kind::displacement;
      a.nodes = q.text("nodes");
      if (at.get("ux")) a.ux = q.real("ux");
      if (at.get("uy")) a.uy = q.real("uy");
    } else if (type == "load" && at.get("settlement")) {
      // Head displacement: the top faces of a cell set (a pile head) pushed down by `settlement`
      // over the stage; the head load is then the reaction on those nodes.
      Schema g;
      g.text("cells", {}, "cell set whose top faces are pushed down (a pile head)");
      g.real("settlement", "m", "downward head displacement at the end of the stage").greater_than(0);
      const auto q = check_table(at, g, actx + " type = \"load\" (head displacement)", {"type"});
      a.kind = Action::Kind::displacement;
      a.cells = cell_set(q, "cells");
      a.uy = -q.real("settlement");
    } else if (type == "reset_displacements") {
      (void)check_table(at, Schema{}, actx + " type = \"reset_displacements\"", {"type"});
      a.kind = Action::Kind::reset_displacements;
    } else if (type == "pressure" || type == "force" || type == "gravity" || type == "load") {
      a.kind = Action::Kind::add_load;
      a.load = parse_load(at, actx, type + "@" + st.name);
      if (!load_names.insert(a.load.name).second)
        throw Error(a.where, actx + " adds a load named \"" + a.load.name +
                                 "\", which is already applied; remove it first or choose another name");
    } else {
      throw Error(
          location(*at.get("type")),
          actx + " type = \"" + type +
              "\" is not allowed; allowed: one of: geostatic, deactivate, activate, pressure, load, force, "
              "gravity, remove, displacement, reset_displacements");
    }
    st.actions.push_back(std::move(a));
  }
  return st;
}

} // namespace stratum
