#include "pile_components.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace stratum {

namespace {

// The edges of a quadrilateral cell by slot: corners a, b and the midside slot (thesis numbering).
constexpr int edge_slots[4][3] = {{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}};

/// int f(x) w(x) ds over the edge a-(mid)-b, w = r in axisymmetry and 1 in plane strain, with
/// f interpolated from nodal values like the geometry (quadratic when the midside node exists).
/// Three Gauss points: exact for the polynomials of a straight quadratic edge.
template <class F> double edge_integral(const Model& m, int a, int b, int mid, F&& f) {
  const double g = std::sqrt(0.6);
  const double xs[3] = {-g, 0.0, g}, ws[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  double sum = 0.0;
  for (int q = 0; q < 3; ++q) {
    const double s = xs[q];
    double N[3], dN[3];
    if (mid >= 0) {
      N[0] = 0.5 * s * (s - 1), N[1] = 0.5 * s * (s + 1), N[2] = 1 - s * s;
      dN[0] = s - 0.5, dN[1] = s + 0.5, dN[2] = -2 * s;
    } else {
      N[0] = 0.5 * (1 - s), N[1] = 0.5 * (1 + s), N[2] = 0.0;
      dN[0] = -0.5, dN[1] = 0.5, dN[2] = 0.0;
    }
    const int ids[3] = {a, b, mid};
    Eigen::Vector2d x = Eigen::Vector2d::Zero(), dx = Eigen::Vector2d::Zero();
    double v = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (ids[k] < 0) continue;
      x += N[k] * m.mesh.nodes[static_cast<std::size_t>(ids[k])];
      dx += dN[k] * m.mesh.nodes[static_cast<std::size_t>(ids[k])];
      v += N[k] * f(ids[k]);
    }
    const double w = m.formulation == Formulation::axisymmetric ? x.x() : 1.0;
    sum += ws[q] * v * w * dx.norm();
  }
  return sum;
}

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
}

PileComponents::Raw PileComponents::measure(Model& m) const {
  Raw r;
  const double tol = 1e-9 * std::max(1.0, top_ - bottom_);
  auto settlement = [&](int n) { return -m.u[2 * n + 1]; };

  // Head and toe: area means over the horizontal edges of the pile cells at its top and bottom.
  double head = 0, head_area = 0, toe = 0, toe_area = 0, volume_strain = 0;
  for (int c : pile_cells_) {
    const Cell& cell = m.mesh.cells[static_cast<std::size_t>(c)];
    for (const auto& e : edge_slots) {
      const int a = cell.nodes[static_cast<std::size_t>(e[0])],
                b = cell.nodes[static_cast<std::size_t>(e[1])];
      const int mid = cell.nodes[static_cast<std::size_t>(e[2])];
      const double ya = m.mesh.nodes[static_cast<std::size_t>(a)].y();
      const double yb = m.mesh.nodes[static_cast<std::size_t>(b)].y();
      if (std::abs(ya - yb) > tol) continue;
      const bool at_top = std::abs(ya - top_) <= tol, at_toe = std::abs(ya - bottom_) <= tol;
      if (!at_top && !at_toe) continue;
      const double area = edge_integral(m, a, b, mid, [](int) { return 1.0; });
      const double s = edge_integral(m, a, b, mid, settlement);
      (at_top ? head : toe) += s;
      (at_top ? head_area : toe_area) += area;
    }
  }
  // Shortening: the integral of the vertical strain over the pile cells, at their points.
  std::vector<int> nodes;
  Eigen::MatrixX2d x;
  Eigen::VectorXd w;
  for (const auto& dm : m.domains) {
    if (!dm.law.material) continue;
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const int c = dm.cells[ci];
      if (!m.is_active(c) || !std::binary_search(pile_cells_.begin(), pile_cells_.end(), c)) continue;
      m.cell_nodes(c, nodes, x);
      const Cell& cell = m.mesh.cells[static_cast<std::size_t>(c)];
      dm.element->point_weights(ElementData{c, cell.shape(), &x}, w);
      double mean = 0.0;
      for (Eigen::Index p = 0; p < w.size(); ++p)
        mean +=
            w[p] * dm.states.committed(dm.first_point[ci] + static_cast<std::size_t>(p)).strain()[voigt::yy];
      volume_strain += mean * cell_measure(m, cell, m.formulation);
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.head = head_area > 0 ? head / head_area : nan;
  r.base = toe_area > 0 ? toe / toe_area : nan;
  r.shortening = head_area > 0 ? -volume_strain / head_area : nan;

  // Interfaces: the vertical force on the pile's nodes and the slip of the shaft's node pairs.
  std::map<int, std::array<double, 2>> slips; // pile node -> (y, slip)
  r.shaft = r.base_load = interface_domains_.empty() ? nan : 0.0;
  Eigen::VectorXd ue;
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
      ue.resize(2 * static_cast<Eigen::Index>(nodes.size()));
      for (std::size_t i = 0; i < nodes.size(); ++i)
        for (int k = 0; k < 2; ++k) ue[static_cast<Eigen::Index>(2 * i) + k] = m.u[2 * nodes[i] + k];
      // u = u_n: a zero increment, so the law returns its committed tractions.
      if (!dm.element
               ->compute(ElementData{c, cell.shape(), &x}, ue, ue, dm.law, scratch, dm.first_point[ci], false,
                         res)
               .ok()) {
        r.shaft = r.base_load = nan;
        continue;
      }
      double fy = 0.0;
      for (std::size_t i = 0; i < nodes.size(); ++i)
        if (pile_node_[static_cast<std::size_t>(nodes[i])])
          fy += res.force[static_cast<Eigen::Index>(2 * i + 1)];
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

std::array<double, 8> PileComponents::row(Model& model, double load_kN) {
  const Raw now = measure(model);
  if (!have_reference_) reference_ = now, have_reference_ = true;
  const Raw& z = reference_;
  return {load_kN,
          1e3 * (now.head - z.head),
          1e3 * (now.shortening - z.shortening),
          1e3 * (now.base - z.base),
          1e3 * (now.slip_mean - z.slip_mean),
          1e3 * (now.slip_top - z.slip_top),
          now.shaft - z.shaft,
          now.base_load - z.base_load};
}

} // namespace stratum
