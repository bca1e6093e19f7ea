// The stage actions of the pore water: the hydraulic boundary (drain, seal) and the phreatic
// level (water_level); docs/groundwater.md.
#include "stages/builtin_actions.hpp"

#include "stages/stage.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cmath>
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

/// inflow: a volume per unit area and time enters through an edge set (a recharge, an injection;
/// negative: a prescribed outflow) while the load stays applied; it flows only in consolidation
/// stages (a static stage takes no time). Its rate acts at the nodes that carry the pore pressure,
/// through Model::inflow.
class Inflow final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.text("name", {}, "name by which a later stage removes the inflow (default: inflow@<stage>)")
        .defaults_to(std::string());
    g.text("edges", {}, "edge set the water enters through (only the nodes that carry p take part)");
    g.real("q", "m/s",
           "volume entering per unit area and unit time (a Darcy velocity into the body; < 0: out)");
    return g;
  }
  explicit Inflow(const Params& p) : p_(p) {
    spec_.kind = LoadSpec::Kind::inflow;
    spec_.name = p.text("name");
    spec_.set = p.text("edges");
    spec_.q = p.real("q");
  }
  void check(StageCheck& scene) override {
    scene.require_edge_set(p_, "edges");
    if (spec_.name.empty()) spec_.name = scene.default_load_name;
    scene.add_load_name(spec_.name);
  }
  void apply(StageState& s) const override {
    const Model& m = s.model;
    const int f = m.dofs.field("p");
    bool any = false;
    if (f >= 0)
      for (const Edge& e : m.mesh.edge_sets.at(spec_.set))
        for (int n : {e.a, e.b, e.mid}) any = any || (n >= 0 && m.dofs.dof(n, f) >= 0);
    if (!any)
      throw Error(p_.where("edges"), "inflow: no node of edge set \"" + spec_.set +
                                         "\" carries a pore pressure p; the set must bound cells of a porous "
                                         "element (quad8p4, tri6p3)");
    s.loads.push_back(spec_);
  }

private:
  Params p_;
  LoadSpec spec_;
};

/// water_level: the phreatic level moves (horizontal or a polyline, from this stage on). The self-weight load
/// of the geostatic stage follows it (a cell weighs gamma above the level, the buoyant gamma_sat - gamma_w
/// below it) at once, from the stage's first step (StageState::load_jumps): the soil answers the change of
/// buoyancy undrained, so that lowered by dh the water below the new level carries nearly gamma_w dh as an
/// excess pressure at first (B gamma_w dh, B = (K_w/n) / (M + K_w/n)), which drains in a consolidation stage
/// to the effective stress of the new level.
class WaterLevel final : public StageAction {
public:
  static Schema schema() {
    Schema g;
    g.real("level", "m", "the new phreatic level y (horizontal; or line_x and line_y)")
        .defaults_to_computed(0.0, "none (line_x, line_y)");
    declare_phreatic_line(g, "line");
    g.text("load", {}, "the self-weight load (of a geostatic action with water_level) whose buoyancy follows")
        .defaults_to(std::string("self_weight"));
    return g;
  }
  explicit WaterLevel(const Params& p)
      : p_(p), level_(read_phreatic_level(p, "level", "line", "water_level")) {}
  void check(StageCheck& scene) override {
    if (!level_.present())
      throw Error(scene.where, scene.context +
                                   " water_level needs level = <y> (horizontal) or line_x = [...] "
                                   "and line_y = [...] (a polyline)");
    require_line_spans_mesh(scene, p_, level_, "line");
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
    auto where = p_.where(p_.where("level").known() ? "level" : "line_y");
    if (!m.water.present())
      throw Error(where,
                  "water_level: the model has no water table; a geostatic action with water_level sets "
                  "one first (the level moves, it does not appear)");
    auto load = std::find_if(s.loads.begin(), s.loads.end(), [&](const LoadSpec& l) {
      return l.name == p_.text("load") && l.kind == LoadSpec::Kind::gravity;
    });
    if (load == s.loads.end() || !load->water.present())
      throw Error(where, "water_level: load \"" + p_.text("load") +
                             "\" is not the self-weight of a geostatic action with water_level");
    for (const auto& d : m.domains)
      if (d.drainage == "undrained")
        throw Error(where, "water_level: a domain with drainage = \"undrained\" keeps its excess pressure at "
                           "its points; a moving level is verified with porous elements only (quad8p4, "
                           "tri6p3), use them where the level moves");
    s.load_jumps.emplace_back(*load, *load); // (before, after)
    load->water = level_;
    s.load_jumps.back().second.water = level_;
    m.water.level = level_;
  }

private:
  Params p_;
  PhreaticLevel level_;
};

} // namespace

void declare_phreatic_line(Schema& g, const std::string& line_key) {
  g.real_list(line_key + "_x", "m",
              "x of the points of a phreatic polyline (strictly increasing; the line must span the mesh)")
      .defaults_to(std::vector<double>{});
  g.real_list(line_key + "_y", "m", "the level y at those points (linear between them)")
      .defaults_to(std::vector<double>{});
}

PhreaticLevel read_phreatic_level(const Params& p, const std::string& level_key, const std::string& line_key,
                                  const std::string& context) {
  const std::string kx = line_key + "_x", ky = line_key + "_y";
  const auto& x = p.real_list(kx);
  const auto& y = p.real_list(ky);
  const bool line = p.where(kx).known() || p.where(ky).known();
  if (line && p.where(level_key).known())
    throw Error(p.where(kx).known() ? p.where(kx) : p.where(ky),
                context + ": give either " + level_key + " (a horizontal level) or " + kx + " and " + ky +
                    " (a polyline), not both");
  if (!line)
    return p.where(level_key).known() ? PhreaticLevel::horizontal(p.real(level_key)) : PhreaticLevel{};
  if (x.size() != y.size() || x.size() < 2)
    throw Error(p.where(x.size() < 2 ? kx : ky),
                context + ": " + kx + " has " + std::to_string(x.size()) + " and " + ky + " " +
                    std::to_string(y.size()) +
                    " values; a phreatic polyline needs the same number, at least 2 (a horizontal level: " +
                    level_key + " = <y>)");
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw Error(p.where(std::isfinite(x[i]) ? ky : kx),
                  context + ": point " + std::to_string(i + 1) + " of the phreatic polyline is not finite");
    if (i > 0 && !(x[i] > x[i - 1]))
      throw Error(p.where(kx), context + ": " + kx + " must increase strictly; " + number_text(x[i]) +
                                   " follows " + number_text(x[i - 1]) + " (point " + std::to_string(i + 1) +
                                   ")");
  }
  return PhreaticLevel{x, y};
}

void require_line_spans_mesh(const StageCheck& scene, const Params& p, const PhreaticLevel& level,
                             const std::string& line_key) {
  if (level.x.size() < 2 || scene.mesh.nodes.empty()) return; // horizontal or none
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& n : scene.mesh.nodes) lo = std::min(lo, n.x()), hi = std::max(hi, n.x());
  const double tol = 1e-9 * std::max({1.0, std::abs(lo), std::abs(hi)});
  if (level.x.front() <= lo + tol && level.x.back() >= hi - tol) return;
  throw Error(p.where(line_key + "_x"),
              scene.context + " " + line_key + "_x runs from " + number_text(level.x.front()) + " to " +
                  number_text(level.x.back()) + " but the mesh from x = " + number_text(lo) + " to " +
                  number_text(hi) +
                  ": the phreatic polyline lies partly outside the mesh; its points must reach both sides "
                  "(first x <= " +
                  number_text(lo) + ", last x >= " + number_text(hi) + ")");
}

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
  r.add({"inflow",
         "water enters through an edge set at a given rate (volume per area and time) while applied",
         Inflow::schema(),
         [](const Params& p) -> std::unique_ptr<StageAction> { return std::make_unique<Inflow>(p); },
         {}});
}

} // namespace stratum::stage
