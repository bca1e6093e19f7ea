// The framework's own stage actions. Each declares the keys of its table (its Schema), checks
// what it names against the scene, and applies itself when its stage starts.
#include "stages/builtin_actions.hpp"

#include "stages/stage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace stratum::stage {

namespace {

/// A load on an empty set would act on nothing: a located error at the key naming the set.
template <class Sets>
void require_loaded(const StageCheck& scene, const Params& p, const std::string& key, const Sets& sets,
                    const char* what) {
  const auto it = sets.find(p.text(key));
  if (it == sets.end() || !it->second.empty()) return; // a missing set is require_*_set's error
  throw Error(p.where(key).known() ? p.where(key) : scene.where,
              scene.context + " " + key + " = \"" + p.text(key) + "\" is an empty " + what +
                  ": the load would act on nothing; name a set with members");
}

/// geostatic: the initial (at-rest) stress of soil cells and their self-weight as a load; the
/// stage's displacements are zeroed at its end.
class Geostatic final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.text("cells", {}, "cells that receive the initial stress and their self-weight")
        .defaults_to(std::string("all"));
    g.real("gamma", "kN/m3", "unit weight (above the water table when `water_level` is given)").at_least(0);
    g.real("K0", "-", "earth pressure coefficient at rest, on effective stresses: sigma'_h = K0 sigma'_v")
        .greater_than(0);
    g.real("surface", "m", "ground level y").defaults_to(0.0);
    g.real("surcharge", "kPa", "vertical stress acting on the surface (compression positive)")
        .at_least(0)
        .defaults_to(0.0);
    g.real("water_level", "m",
           "phreatic level y (horizontal): below it the pore water is hydrostatic, p = gamma_w (water_level "
           "- y), the stress set is effective and the self-weight buoyant; absent: dry (or water_line_x/_y)")
        .defaults_to_computed(0.0, "none (dry)");
    declare_phreatic_line(g, "water_line");
    g.real("gamma_sat", "kN/m3", "unit weight below the water table")
        .at_least(0)
        .defaults_to_computed(0.0, "gamma");
    g.real("gamma_w", "kN/m3", "unit weight of the pore water").greater_than(0).defaults_to(9.81);
    g.text("name", {}, "name of the self-weight load it adds").defaults_to(std::string("self_weight"));
    return g;
  }
  explicit Geostatic(const Params& p) : p_(p) {
    state_.gamma = p.real("gamma");
    state_.gamma_sat = p.where("gamma_sat").known() ? p.real("gamma_sat") : state_.gamma;
    state_.K0 = p.real("K0");
    state_.surface = p.real("surface");
    state_.surcharge = p.real("surcharge");
    state_.water = read_phreatic_level(p, "water_level", "water_line", "geostatic");
    state_.gamma_w = p.real("gamma_w");
    load_.kind = LoadSpec::Kind::gravity;
    load_.name = p.text("name"), load_.set = p.text("cells"), load_.gamma = state_.gamma;
    // Below the water table the skeleton weighs its buoyant unit weight: the steady pore pressure
    // (hydrostatic in each vertical, not an unknown) carries the rest, and under a sloped level
    // pushes the skeleton along its steady flow (the seepage force).
    load_.water = state_.water;
    load_.gamma_below = state_.gamma_sat - state_.gamma_w;
    load_.gamma_w = state_.gamma_w;
    if (state_.water.present() && load_.gamma_below < 0.0)
      throw Error(p.where(p.where("gamma_sat").known()     ? "gamma_sat"
                          : p.where("water_level").known() ? "water_level"
                                                           : "water_line_y"),
                  "geostatic: gamma_sat = " + std::to_string(state_.gamma_sat) + " is below gamma_w = " +
                      std::to_string(state_.gamma_w) + "; a saturated soil weighs more than water");
  }
  void check(StageCheck& scene) override {
    scene.require_cell_set(p_, "cells");
    require_loaded(scene, p_, "cells", scene.mesh.cell_sets, "cell set");
    require_line_spans_mesh(scene, p_, state_.water, "water_line");
    scene.add_load_name(load_.name);
    scene.reset_after = true;
  }
  void apply(StageState& s) const override {
    set_geostatic(s.model, s.model.mesh.cell_sets.at(load_.set), state_);
    if (state_.water.present()) s.model.water = Water{state_.water, state_.gamma_w};
    s.loads.push_back(load_);
  }

private:
  Params p_;
  AtRest state_;
  LoadSpec load_;
};

/// deactivate: cells leave the model (excavation, boring).
class Deactivate final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.text("cells", {}, "cell set");
    return g;
  }
  explicit Deactivate(const Params& p) : cells_(p.text("cells")), p_(p) {}
  void check(StageCheck& scene) override { scene.require_cell_set(p_, "cells"); }
  void apply(StageState& s) const override {
    for (int c : s.model.mesh.cell_sets.at(cells_)) s.model.active[static_cast<std::size_t>(c)] = 0;
  }

private:
  std::string cells_;
  Params p_;
};

/// activate: cells enter the model (placing concrete), unstressed or with a fluid's pressure.
class Activate final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.text("cells", {}, "cell set");
    g.text("stress", {"zero", "hydrostatic"},
           "initial stress of the placed cells: none, or a fluid's -gamma (surface - y) in all directions")
        .defaults_to(std::string("zero"));
    g.real("gamma", "kN/m3", "unit weight of the fluid for stress = \"hydrostatic\"")
        .at_least(0)
        .defaults_to(0.0);
    g.real("surface", "m", "fluid surface level y").defaults_to(0.0);
    return g;
  }
  explicit Activate(const Params& p) : p_(p) {}
  void check(StageCheck& scene) override { scene.require_cell_set(p_, "cells"); }
  void apply(StageState& s) const override {
    const auto& cells = s.model.mesh.cell_sets.at(p_.text("cells"));
    for (int c : cells) s.model.active[static_cast<std::size_t>(c)] = 1;
    set_placed_stress(s.model, cells, p_.text("stress") == "hydrostatic", p_.real("gamma"),
                      p_.real("surface"));
  }

private:
  Params p_;
};

/// change_material: a domain's points continue with another material from the stage's start
/// (concrete that hardens, ground improved): each keeps its stress and strain, and the new
/// material's history starts from that stress (Material::init_history), as a placed point's does.
class ChangeMaterial final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.text("domain", {}, "the [[domains]] entry, named by its cell set (its `cells`)");
    g.text("material", {}, "name of a [materials.<name>] table the domain continues with");
    return g;
  }
  explicit ChangeMaterial(const Params& p) : p_(p) {}
  void check(StageCheck& scene) override {
    if (!scene.domains || !scene.materials)
      throw Error(scene.where, scene.context + " needs the scene's domains");
    const std::string& name = p_.text("domain");
    const auto where = [&](const char* key) { return p_.where(key).known() ? p_.where(key) : scene.where; };
    std::string known;
    for (std::size_t d = 0; d < scene.domains->size(); ++d) {
      const Domain& dm = (*scene.domains)[d];
      if (!dm.law.contact && dm.element && dm.element->needs_material())
        known += (known.empty() ? "" : ", ") + dm.name;
      if (dm.name == name) domain_ = static_cast<int>(d);
    }
    if (domain_ < 0)
      throw Error(where("domain"),
                  scene.context + " domain = \"" + name +
                      "\" is not a [[domains]] entry (a domain is named by its cells); known: " + known);
    const Domain& dm = (*scene.domains)[static_cast<std::size_t>(domain_)];
    if (dm.law.contact || !dm.element->needs_material())
      throw Error(where("domain"), scene.context + " domain = \"" + name +
                                       "\" has no material to change (an interface or an element without "
                                       "one); allowed: " +
                                       known);
    if (dm.drainage == "undrained")
      throw Error(where("domain"),
                  scene.context + " domain = \"" + name +
                      "\" is undrained (drainage = \"undrained\"): its points carry the excess pore pressure "
                      "in the material's history, which a change would drop; allowed: domains drained, "
                      "non_porous or undrained_total");
    const auto it = scene.materials->find(p_.text("material"));
    if (it == scene.materials->end()) {
      std::string names;
      for (const auto& [n, m] : *scene.materials) names += (names.empty() ? "" : ", ") + n;
      throw Error(where("material"), scene.context + " material = \"" + p_.text("material") +
                                         "\" is not a [materials.<name>] table; known: " + names);
    }
    material_ = it->second;
  }
  void apply(StageState& s) const override {
    Domain& dm = s.model.domains[static_cast<std::size_t>(domain_)];
    const StateStore before = dm.states;
    resume(s.model);
    for (std::size_t p = 0; p < dm.states.points(); ++p) {
      const auto old = before.committed(p);
      auto slot = dm.states.committed_for_init(p);
      slot.stress() = old.stress();
      slot.strain() = old.strain();
      material_->init_history(old.stress(), slot.history());
    }
    dm.states.revert(); // trial = committed
  }
  void resume(Model& model) const override {
    Domain& dm = model.domains[static_cast<std::size_t>(domain_)];
    dm.law.material = material_;
    dm.states = StateStore(dm.states.points(), material_->history_size());
  }

private:
  Params p_;
  int domain_ = -1;
  const Material* material_ = nullptr;
};

/// remove: a load added by an earlier action stops acting.
class Remove final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.text("name", {}, "name of an applied load");
    return g;
  }
  explicit Remove(const Params& p) : p_(p) {}
  void check(StageCheck& scene) override {
    const std::string& name = p_.text("name");
    if (scene.load_names.erase(name)) return;
    std::string known;
    for (const auto& n : scene.load_names) known += (known.empty() ? "" : ", ") + n;
    throw Error(p_.where("name"),
                scene.context + " name = \"" + name +
                    "\" is not an applied load; applied: " + (known.empty() ? "(none)" : known));
  }
  void apply(StageState& s) const override {
    std::erase_if(s.loads, [&](const LoadSpec& l) { return l.name == p_.text("name"); });
  }

private:
  Params p_;
};

/// displacement: a node set's displacement grows by (ux, uy) over the stage's steps.
class Displacement final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.text("nodes", {}, "node set");
    g.real("ux", "m", "x displacement increment over the stage").defaults_to(0.0);
    g.real("uy", "m", "y displacement increment over the stage").defaults_to(0.0);
    return g;
  }
  explicit Displacement(const Params& p) : p_(p) {}
  void check(StageCheck& scene) override {
    scene.require_node_set(p_, "nodes");
    if (!p_.where("ux").known() && !p_.where("uy").known())
      throw Error(scene.where, scene.context + " prescribes nothing; give ux and/or uy");
  }
  void apply(StageState& s) const override {
    Model& m = s.model;
    const bool x = p_.where("ux").known(), y = p_.where("uy").known();
    for (int n : m.mesh.node_sets.at(p_.text("nodes"))) {
      if (const int d = m.dofs.dof(n, field_ux); x && d >= 0)
        m.constrained[d] = 1, m.prescribed[d] = p_.real("ux");
      if (const int d = m.dofs.dof(n, field_uy); y && d >= 0)
        m.constrained[d] = 1, m.prescribed[d] = p_.real("uy");
    }
  }

private:
  Params p_;
};

/// reset_displacements: the displacements start again from zero (the stresses stay).
class ResetDisplacements final : public StageAction {
public:
  explicit ResetDisplacements(const Params& /*no keys*/) {}
  void apply(StageState& s) const override {
    s.model.u.setZero();
    s.model.prescribed_base.setZero();
  }
};

/// pressure, force, gravity: a load that stays applied until a `remove` action.
class AddLoad final : public StageAction {
public:
  static Schema pressure_schema() {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load (default: pressure@<stage>)")
        .defaults_to(std::string());
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
    return s;
  }
  static Schema force_schema() {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load (default: force@<stage>)")
        .defaults_to(std::string());
    s.text("nodes", {}, "node set");
    s.real("fx", "kN", "force per node along x (axisymmetric: total over the circle)").defaults_to(0.0);
    s.real("fy", "kN", "force per node along y (axisymmetric: total over the circle)").defaults_to(0.0);
    return s;
  }
  static Schema gravity_schema() {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load (default: gravity@<stage>)")
        .defaults_to(std::string());
    s.text("cells", {}, "cell set (only its active cells are loaded)").defaults_to(std::string("all"));
    s.real("gamma", "kN/m3", "unit weight, acting downwards (-y)").at_least(0);
    return s;
  }
  AddLoad(const Params& p, LoadSpec::Kind kind) : p_(p) {
    spec_.kind = kind;
    spec_.name = p.text("name");
    switch (kind) {
    case LoadSpec::Kind::pressure:
      spec_.set = p.text("edges");
      spec_.p = p.real("p"), spec_.gamma = p.real("gamma"), spec_.surface = p.real("surface");
      spec_.critical_depth = p.real("critical_depth");
      break;
    case LoadSpec::Kind::force:
      spec_.set = p.text("nodes");
      spec_.fx = p.real("fx"), spec_.fy = p.real("fy");
      break;
    case LoadSpec::Kind::gravity:
      spec_.set = p.text("cells");
      spec_.gamma = p.real("gamma");
      break;
    case LoadSpec::Kind::inflow: // its own action (stages/water_actions.cpp)
      break;
    }
  }
  void check(StageCheck& scene) override {
    switch (spec_.kind) {
    case LoadSpec::Kind::pressure:
      scene.require_edge_set(p_, "edges");
      require_loaded(scene, p_, "edges", scene.mesh.edge_sets, "edge set");
      break;
    case LoadSpec::Kind::force:
      scene.require_node_set(p_, "nodes");
      require_loaded(scene, p_, "nodes", scene.mesh.node_sets, "node set");
      break;
    case LoadSpec::Kind::gravity:
      scene.require_cell_set(p_, "cells");
      require_loaded(scene, p_, "cells", scene.mesh.cell_sets, "cell set");
      break;
    case LoadSpec::Kind::inflow:
      break;
    }
    if (spec_.name.empty()) spec_.name = scene.default_load_name;
    scene.add_load_name(spec_.name);
  }
  void apply(StageState& s) const override { s.loads.push_back(spec_); }

private:
  Params p_;
  LoadSpec spec_;
};

/// load: the pile head's load. Either a total downward force, spread as a uniform pressure
/// over edges or over the top faces of a cell set (the head), or a downward head displacement
/// `settlement` of those top faces (the head load is then their reaction).
class HeadLoad final : public StageAction {
public:
  static Schema schema() {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(std::string("head"));
    s.text("edges", {}, "edge set carrying the load").defaults_to(std::string());
    s.text("cells", {}, "or: a cell set whose top faces carry it (a pile head)").defaults_to(std::string());
    // One of force and settlement is required (check()); NaN marks the one not given.
    constexpr double none = std::numeric_limits<double>::quiet_NaN();
    s.real("force", "kN",
           "total downward force at the end of the stage (axisymmetric: whole circle); required unless "
           "settlement is given")
        .defaults_to(none);
    s.real("settlement", "m",
           "instead of force: downward displacement of the head (the top faces of `cells`) at the end of "
           "the stage")
        .greater_than(0)
        .defaults_to(none);
    return s;
  }
  explicit HeadLoad(const Params& p) : p_(p), displaced_(p.where("settlement").known()) {
    spec_.kind = LoadSpec::Kind::pressure;
    spec_.name = p.text("name");
    spec_.top_of_cells = p.text("edges").empty();
    spec_.set = spec_.top_of_cells ? p.text("cells") : p.text("edges");
    spec_.total_force = p.real("force");
  }
  void check(StageCheck& scene) override {
    if (displaced_) {
      for (const char* key : {"force", "edges", "name"})
        if (p_.where(key).known())
          throw Error(p_.where(key), scene.context + " " + key +
                                         " cannot act with settlement (a head displacement pushes the top "
                                         "faces of `cells` down); give cells and settlement only");
      if (p_.text("cells").empty())
        throw Error(scene.where, scene.context + " settlement needs cells = \"<cell set>\" (the pile head)");
      scene.require_cell_set(p_, "cells");
      require_loaded(scene, p_, "cells", scene.mesh.cell_sets, "cell set");
      return;
    }
    if (p_.text("edges").empty() == p_.text("cells").empty())
      throw Error(scene.where,
                  scene.context + " needs exactly one of edges = \"<edge set>\" or cells = \"<cell set>\"");
    if (!p_.where("force").known())
      throw Error(scene.where,
                  scene.context + " needs force = <kN> (or settlement = <m> for a head displacement)");
    if (spec_.top_of_cells) {
      scene.require_cell_set(p_, "cells");
      require_loaded(scene, p_, "cells", scene.mesh.cell_sets, "cell set");
    } else {
      scene.require_edge_set(p_, "edges");
      require_loaded(scene, p_, "edges", scene.mesh.edge_sets, "edge set");
    }
    scene.add_load_name(spec_.name);
  }
  void apply(StageState& s) const override {
    if (!displaced_) {
      s.loads.push_back(spec_);
      s.head_load = &spec_;
      return;
    }
    // The head's current top nodes are pushed down by `settlement` over the stage.
    s.head_nodes = load_nodes(s.model, spec_);
    const double uy = -p_.real("settlement");
    for (int n : s.head_nodes)
      if (const int d = s.model.dofs.dof(n, field_uy); d >= 0)
        s.model.constrained[d] = 1, s.model.prescribed[d] = uy;
  }

private:
  Params p_;
  bool displaced_;
  LoadSpec spec_;
};

template <class A> Factory<StageAction> factory(std::string name, std::string summary, Schema schema) {
  return {std::move(name),
          std::move(summary),
          std::move(schema),
          [](const Params& p) -> std::unique_ptr<StageAction> { return std::make_unique<A>(p); },
          {}};
}

Factory<StageAction> load_factory(std::string name, std::string summary, Schema schema, LoadSpec::Kind kind) {
  return {
      std::move(name),
      std::move(summary),
      std::move(schema),
      [kind](const Params& p) -> std::unique_ptr<StageAction> { return std::make_unique<AddLoad>(p, kind); },
      {}};
}

} // namespace

void register_builtin_actions(Registry& r) {
  r.add(factory<Geostatic>("geostatic", "at-rest initial stress of soil cells and their self-weight",
                           Geostatic::schema()));
  r.add(
      factory<Deactivate>("deactivate", "cells leave the model (boring, excavation)", Deactivate::schema()));
  r.add(factory<Activate>("activate",
                          "cells enter the model (placing), unstressed or under a fluid's pressure",
                          Activate::schema()));
  r.add(load_factory("pressure", "a pressure on an edge set, growing with depth if asked",
                     AddLoad::pressure_schema(), LoadSpec::Kind::pressure));
  r.add(factory<HeadLoad>("load", "the pile head's load: a total force or a head displacement",
                          HeadLoad::schema()));
  r.add(load_factory("force", "forces on the nodes of a node set", AddLoad::force_schema(),
                     LoadSpec::Kind::force));
  r.add(load_factory("gravity", "the self-weight of a cell set", AddLoad::gravity_schema(),
                     LoadSpec::Kind::gravity));
  r.add(factory<Remove>("remove", "an applied load stops acting", Remove::schema()));
  r.add(factory<Displacement>("displacement", "a node set's displacement grows over the stage",
                              Displacement::schema()));
  register_water_actions(r); // stages/water_actions.cpp: drain, seal, water_level, inflow
  r.add(factory<ResetDisplacements>("reset_displacements", "displacements start again from zero", Schema{}));
  r.add(factory<ChangeMaterial>("change_material",
                                "a domain continues with another material, its stresses kept",
                                ChangeMaterial::schema()));
}

const std::vector<std::string>& builtin_action_types() {
  static const std::vector<std::string> types{
      "geostatic", "deactivate", "activate",    "pressure",     "load",
      "force",     "gravity",    "remove",      "displacement", "reset_displacements",
      "drain",     "seal",       "water_level", "inflow",       "change_material"};
  return types;
}

} // namespace stratum::stage
