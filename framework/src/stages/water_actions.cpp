// The stage actions of the pore water: the hydraulic boundary (drain, seal) and the phreatic
// level (water_level); docs/groundwater.md.
#include "stages/builtin_actions.hpp"

#include "stages/stage.hpp"

#include <algorithm>
#include <limits>
#include <memory>

namespace stratum::stage {

namespace {

/// drain and seal: the hydraulic boundary of a node set. `drain` prescribes the excess pore
/// pressure p (0: drained to the steady water pressure) from the stage's first step on: the value
/// jumps there, as a drainage opened at the stage's start does, and the first step's storage term
/// sees the jump. `seal` frees p again: no flow through the nodes (the default of a boundary).
class Hydraulic final : public StageAction {
public:
  static Schema drain_schema() {
    Schema g;
    g.text("nodes", {}, "node or edge set of the drained boundary (only the nodes that carry p take part)");
    g.real("p", "kPa", "excess pore pressure held at these nodes from the stage's first step on")
        .defaults_to(0.0);
    return g;
  }
  static Schema seal_schema() {
    Schema g;
    g.text("nodes", {}, "node or edge set whose excess pore pressure is no longer prescribed (no flow)");
    return g;
  }
  Hydraulic(const Params& p, bool drain) : p_(p), drain_(drain) {}
  void check(StageCheck& scene) override { scene.require_node_set(p_, "nodes"); }
  void apply(StageState& s) const override {
    Model& m = s.model;
    const int f = m.dofs.field("p");
    int count = 0;
    if (f >= 0)
      for (int n : m.mesh.node_sets.at(p_.text("nodes")))
        if (const int d = m.dofs.dof(n, f); d >= 0) {
          ++count;
          m.constrained[static_cast<std::size_t>(d)] = drain_ ? 1 : 0;
          if (drain_) m.prescribed_base[d] = p_.real("p"), m.prescribed[d] = 0.0;
        }
    if (count == 0)
      throw Error(p_.where("nodes"), std::string(drain_ ? "drain" : "seal") + ": no node of set \"" +
                                         p_.text("nodes") +
                                         "\" carries a pore pressure p; the set must touch cells of a porous "
                                         "element (quad8p4, tri6p3)");
  }

private:
  Params p_;
  bool drain_;
};

/// water_level: the phreatic level moves (horizontal, from this stage on). The self-weight load of
/// the geostatic stage follows it (a cell weighs gamma above the level, the buoyant gamma_sat -
/// gamma_w below it) at once, from the stage's first step (StageState::load_jumps): the soil answers
/// the change of buoyancy undrained, so that lowered by dh the water below the new level carries
/// nearly gamma_w dh as an excess pressure at first (B gamma_w dh, B = (K_w/n) / (M + K_w/n)), which
/// drains in a consolidation stage to the effective stress of the new level.
class WaterLevel final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.real("level", "m", "the new phreatic level y (horizontal)");
    g.text("load", {}, "the self-weight load (of a geostatic action with water_level) whose buoyancy follows")
        .defaults_to(std::string("self_weight"));
    return g;
  }
  explicit WaterLevel(const Params& p) : p_(p) {}
  void check(StageCheck& scene) override {
    if (scene.load_names.count(p_.text("load"))) return;
    std::string known;
    for (const auto& n : scene.load_names) known += (known.empty() ? "" : ", ") + n;
    throw Error(p_.where("load").known() ? p_.where("load") : p_.where("level"),
                scene.context + " water_level: load = \"" + p_.text("load") +
                    "\" is not an applied load; the level needs the self-weight load of a geostatic action "
                    "with water_level (applied: " +
                    (known.empty() ? "(none)" : known) + ")");
  }
  void apply(StageState& s) const override {
    Model& m = s.model;
    auto where = p_.where("level");
    if (!m.water.present())
      throw Error(where,
                  "water_level: the model has no water table; a geostatic action with water_level sets "
                  "one first (the level moves, it does not appear)");
    auto load = std::find_if(s.loads.begin(), s.loads.end(), [&](const LoadSpec& l) {
      return l.name == p_.text("load") && l.kind == LoadSpec::Kind::gravity;
    });
    if (load == s.loads.end() || !(load->water_level > -std::numeric_limits<double>::infinity()))
      throw Error(where, "water_level: load \"" + p_.text("load") +
                             "\" is not the self-weight of a geostatic action with water_level");
    for (const auto& d : m.domains)
      if (d.law.material && !d.law.material->history_names().empty() &&
          d.law.material->history_names().front() == "p_excess")
        throw Error(where, "water_level: a domain with drainage = \"undrained\" keeps its excess pressure at "
                           "its points; a moving level is verified with porous elements only (quad8p4, "
                           "tri6p3), use them where the level moves");
    const double now = p_.real("level");
    s.load_jumps.emplace_back(*load, *load); // (before, after)
    load->water_level = now;
    s.load_jumps.back().second.water_level = now;
    m.water.level = now;
  }

private:
  Params p_;
};

} // namespace

void register_water_actions(Registry& r) {
  r.add({"drain",
         "a node set's excess pore pressure is held (a drained boundary opens)",
         Hydraulic::drain_schema(),
         [](const Params& p) -> std::unique_ptr<StageAction> { return std::make_unique<Hydraulic>(p, true); },
         {}});
  r.add(
      {"seal",
       "a node set's excess pore pressure is free again (no flow: a boundary closes)",
       Hydraulic::seal_schema(),
       [](const Params& p) -> std::unique_ptr<StageAction> { return std::make_unique<Hydraulic>(p, false); },
       {}});
  r.add({"water_level",
         "the phreatic level moves; the buoyancy changes at once and the soil answers undrained",
         WaterLevel::schema(),
         [](const Params& p) -> std::unique_ptr<StageAction> { return std::make_unique<WaterLevel>(p); },
         {}});
}

} // namespace stratum::stage
