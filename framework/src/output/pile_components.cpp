#include "pile_components.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace stratum {

namespace {

// The edges of a quadrilateral cell by slot: corners a, b and the midside slot (thesis numbering).
constexpr int edge_slots[4][3] = {{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}};

/// int w dA of a straight-sided quadrilateral cell (its corners), w as in edge_integral:
/// the area, times the centroid's radius in axisymmetry (Pappus).
double cell_measure(const Model& m, const Cell& cell, Formulation f) {
  double A = 0.0, cx = 0.0;
  for (int i = 0; i < 4; ++i) {
    const auto& p = m.mesh.nodes[static_cast<std::size_t>(cell.nodes[static_cast<std::size_t>(i)])];
    const auto& q = m.mesh.nodes[static_cast<std::size_t>(cell.nodes[static_cast<std::size_t>((i + 1) % 4)])];
    const double cr = p.x() * q.y() - q.x() * p.y();
    A += 0.5 * cr;
    cx += (p.x() + q.x()) * cr / 6.0;
  }
  if (f == Formulation::axisymmetric) return std::abs(cx); // = A * centroid radius
  return std::abs(A);
}

} // namespace

PileComponents::PileComponents(const Model& model, std::vector<int> pile_cells,
                               std::vector<std::size_t> interface_domains)
    : pile_cells_(std::move(pile_cells)), interface_domains_(std::move(interface_domains)) {
  std::sort(pile_cells_.begin(), pile_cells_.end());
  pile_node_.assign(model.mesh.nodes.size(), 0);
  top_ = -std::numeric_limits<double>::infinity();
  bottom_ = std::numeric_limits<double>::infinity();
  for (int c : pile_cells_)
    for (int n : model.mesh.cells[static_cast<std::size_t>(c)].nodes)
      if (n >= 0) {
        pile_node_[static_cast<std::size_t>(n)] = 1;
        top_ = std::max(top_, model.mesh.nodes[static_cast<std::size_t>(n)].y());
        bottom_ = std::min(bottom_, model.mesh.nodes[static_cast<std::size_t>(n)].y());
      }
  // Head and toe: the horizontal edges of the pile cells at its top and bottom. The area mean of
  // a nodal field over them is sum_a w_a v_a with w_a the consistent nodal load of a unit
  // pressure (add_edge_pressure: exact for straight or parabolic edges, 2 pi r in axisymmetry)
  // over its total, computed once here.
  const double tol = 1e-9 * std::max(1.0, top_ - bottom_);
  std::vector<Edge> head, toe;
  for (int c : pile_cells_) {
    const Cell& cell = model.mesh.cells[static_cast<std::size_t>(c)];
    for (const auto& e : edge_slots) {
      const Edge edge{cell.nodes[static_cast<std::size_t>(e[0])], cell.nodes[static_cast<std::size_t>(e[1])],
                      cell.nodes[static_cast<std::size_t>(e[2])]};
      const double ya = model.mesh.nodes[static_cast<std::size_t>(edge.a)].y();
      const double yb = model.mesh.nodes[static_cast<std::size_t>(edge.b)].y();
      if (std::abs(ya - yb) > tol) continue;
      if (std::abs(ya - top_) <= tol) head.push_back(edge);
      if (std::abs(ya - bottom_) <= tol) toe.push_back(edge);
    }
  }
  auto weights = [&](const std::vector<Edge>& edges, std::vector<std::pair<int, double>>& w) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(model.dofs.total());
    add_edge_pressure(model, edges, 1.0, f);
    double total = 0.0;
    for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n) {
      const int d = model.dofs.dof(static_cast<int>(n), field_uy);
      if (d >= 0 && f[d] != 0.0) w.emplace_back(static_cast<int>(n), f[d]), total += f[d];
    }
    for (auto& [n, x] : w) x /= total;
    return std::abs(total);
  };
  area_ = weights(head, head_weights_);
  weights(toe, toe_weights_);
  area_ /= model.formulation == Formulation::axisymmetric ? 2 * std::numbers::pi : 1.0;
}

PileComponents::Raw PileComponents::measure(Model& m) const {
  Raw r;
  auto settlement = [&](int n) { return -m.u[m.dofs.dof(n, field_uy)]; };

  double volume_strain = 0;
  // Shortening: the integral of the vertical strain over the pile cells, at their points.
  std::vector<int> nodes;
  Eigen::MatrixXd x;
  Eigen::VectorXd w;
  for (const auto& dm : m.domains) {
    if (!dm.law.material) continue;
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const int c = dm.cells[ci];
      if (!m.is_active(c) || !std::binary_search(pile_cells_.begin(), pile_cells_.end(), c)) continue;
      m.cell_nodes(c, nodes, x);
      const Cell& cell = m.mesh.cells[static_cast<std::size_t>(c)];
      dm.element->point_weights(m.element_data(c, x), w);
      double mean = 0.0;
      for (Eigen::Index p = 0; p < w.size(); ++p)
        mean +=
            w[p] * dm.states.committed(dm.first_point[ci] + static_cast<std::size_t>(p)).strain()[voigt::yy];
      volume_strain += mean * cell_measure(m, cell, m.formulation);
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto area_mean = [&](const std::vector<std::pair<int, double>>& w) {
    double v = 0.0;
    for (const auto& [n, x] : w) v += x * settlement(n);
    return w.empty() ? nan : v;
  };
  r.head = area_mean(head_weights_);
  r.base = area_mean(toe_weights_);
  r.shortening = area_ > 0 ? -volume_strain / area_ : nan;

  // Interfaces: the vertical force on the pile's nodes and the slip of the shaft's node pairs.
  std::map<int, std::array<double, 2>> slips; // pile node -> (y, slip)
  r.shaft = r.base_load = interface_domains_.empty() ? nan : 0.0;
  Eigen::VectorXd ue;
  std::vector<int> dofs;
  ElementResult res;
  for (std::size_t d : interface_domains_) {
    const Domain& dm = m.domains[d];
    StateStore scratch = dm.states; // compute() writes trial states: keep the model's untouched
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const int c = dm.cells[ci];
      if (!m.is_active(c)) continue;
      const Cell& cell = m.mesh.cells[static_cast<std::size_t>(c)];
      m.cell_nodes(c, nodes, x);
      const bool vertical = std::abs(x(1, 0) - x(0, 0)) < std::abs(x(1, 1) - x(0, 1));
      m.cell_dofs(dm, c, dofs);
      ue.resize(static_cast<Eigen::Index>(dofs.size()));
      for (std::size_t i = 0; i < dofs.size(); ++i)
        ue[static_cast<Eigen::Index>(i)] = dofs[i] >= 0 ? m.u[dofs[i]] : 0.0;
      // u = u_n: a zero increment, so the law returns its committed tractions.
      if (!dm.element->compute(m.element_data(c, x), ue, ue, dm.law, scratch, dm.first_point[ci], false, res)
               .ok()) {
        r.shaft = r.base_load = nan;
        continue;
      }
      // The vertical components of the pile nodes' forces, in the cell's local order.
      double fy = 0.0;
      for (std::size_t i = 0; i < dofs.size(); ++i)
        for (int n : nodes)
          if (pile_node_[static_cast<std::size_t>(n)] && dofs[i] >= 0 && dofs[i] == m.dofs.dof(n, field_uy))
            fy += res.force[static_cast<Eigen::Index>(i)];
      (vertical ? r.shaft : r.base_load) -= fy;
      if (!vertical) continue;
      // Node pairs of a line-interface cell: slots (0, 3), (1, 2), (4, 6).
      for (const auto& [s1, s2] : {std::pair{0, 3}, std::pair{1, 2}, std::pair{4, 6}}) {
        const int n1 = cell.nodes[static_cast<std::size_t>(s1)],
                  n2 = cell.nodes[static_cast<std::size_t>(s2)];
        if (n1 < 0 || n2 < 0) continue;
        const bool p1 = pile_node_[static_cast<std::size_t>(n1)] != 0;
        if (p1 == (pile_node_[static_cast<std::size_t>(n2)] != 0)) continue;
        const int pile = p1 ? n1 : n2, soil = p1 ? n2 : n1;
        slips[pile] = {m.mesh.nodes[static_cast<std::size_t>(pile)].y(), settlement(pile) - settlement(soil)};
      }
    }
  }
  if (slips.empty()) {
    r.slip_mean = r.slip_top = nan;
  } else {
    double top = -std::numeric_limits<double>::infinity();
    for (const auto& [n, v] : slips) {
      r.slip_mean += v[1] / static_cast<double>(slips.size());
      if (v[0] > top) top = v[0], r.slip_top = v[1];
    }
  }
  return r;
}

std::string PileComponents::header(const Units& u) {
  const std::string s = "_" + u.small_length();
  return u.column("load", "kN") + ",head" + s + ",pile_shortening" + s + ",base" + s + ",shaft_slip_mean" +
         s + ",shaft_slip_top" + s + "," + u.column("shaft_load", "kN") + "," + u.column("base_load", "kN");
}

std::array<double, 8> PileComponents::row(Model& model, double load_kN, double small) {
  const Raw now = measure(model);
  if (!have_reference_) reference_ = now, have_reference_ = true;
  const Raw& z = reference_;
  return {load_kN,
          small * (now.head - z.head),
          small * (now.shortening - z.shortening),
          small * (now.base - z.base),
          small * (now.slip_mean - z.slip_mean),
          small * (now.slip_top - z.slip_top),
          now.shaft - z.shaft,
          now.base_load - z.base_load};
}

} // namespace stratum
