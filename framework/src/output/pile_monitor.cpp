#include "output/pile_monitor.hpp"
#include "output/interface_output.hpp"
#include "output/pile_curves.hpp"
#include "stratum/load.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace stratum {

PileMonitor::PileMonitor(const Model& model, const stage::Stage& stage, const LoadSpec* head,
                         const std::vector<LoadSpec>& before, const std::vector<int>& head_disp,
                         const std::vector<int>* pile, std::vector<std::size_t> interface_domains,
                         const Units& units)
    : stop_settlement_(stage.stop_settlement), pile_(pile), interface_domains_(std::move(interface_domains)),
      small_(units.small_length_factor()), per_unit_(1e6 * units.length_in_m()) {
  if (!stage.monitor.empty()) monitored_ = &model.mesh.node_sets.at(stage.monitor);
  if (head) head_nodes_ = load_nodes(model, *head);
  displaced_head_ = !head && !head_disp.empty();
  if (displaced_head_) head_nodes_ = head_disp;
  has_head_ = head || displaced_head_;
  if (!monitored_ && has_head_) monitored_ = &head_nodes_;
  force_ = head ? head->total_force : 0.0;
  // A head load that replaces the one of an earlier stage on the same head (removed in this stage)
  // takes over from it: the load vector goes from the old total to the new one over the stage.
  if (head)
    for (const auto& l : before)
      if (l.kind == head->kind && std::isfinite(l.total_force) && l.top_of_cells == head->top_of_cells &&
          l.set == head->set && l.name != head->name)
        start_force_ += l.total_force;
}

// m.reactions holds the internal forces; a fixed DOF's external load is in load_base.
double PileMonitor::head_load(const Model& m, bool stepped) const {
  if (!displaced_head_) return start_force_ + m.lambda * (force_ - start_force_);
  double P = 0.0;
  if (stepped)
    for (int n : head_nodes_) {
      const int d = m.dofs.dof(n, field_uy);
      P -= m.reactions[d] - m.load_base[d];
    }
  return P;
}

// Shaft tractions: the points of the interface cells that lie on the vertical wall (every
// point at the largest radius); a cell of the base that only touches the wall at its
// corner is not the shaft's (its traction is the base's shear and vertical normal).
void PileMonitor::shaft_rows(const Model& m, double load, std::vector<std::array<double, 6>>& rows) const {
  for (std::size_t domain : interface_domains_) {
    const auto pts = interface_points(m, m.domains[domain]);
    double rmax = 0.0;
    for (const auto& q : pts) rmax = std::max(rmax, q.x.x());
    const double tol = 1e-9 * std::max(1.0, rmax); // relative: any length unit
    std::set<int> off_wall;
    for (const auto& q : pts)
      if (q.x.x() <= rmax - tol) off_wall.insert(q.cell);
    for (const auto& q : pts)
      if (!off_wall.count(q.cell))
        rows.push_back({load, q.x.y(), q.traction[0], q.traction[1], small_ * q.jump[0],
                        static_cast<double>(static_cast<int>(q.state))});
  }
}

PileObservation PileMonitor::observe(Model& m, bool stepped) {
  PileObservation o;
  if (!has_head_) return o;
  o.recorded = true;
  o.load = head_load(m, stepped);
  o.settlement = small_ * mean_settlement(m, head_nodes_);
  if (pile_) {
    if (!components_) components_.emplace(m, *pile_, interface_domains_);
    o.components = components_->row(m, o.load, small_);
    for (const auto& [y, n] : axial_profile(m, *pile_, per_unit_)) o.axial.push_back({o.load, y, n});
  }
  shaft_rows(m, o.load, o.shaft);
  return o;
}

bool PileMonitor::settlement_reached(const Model& m) const {
  return mean_settlement(m, *monitored_) > stop_settlement_;
}

} // namespace stratum
