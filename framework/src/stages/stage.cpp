#include "stage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

namespace stratum::stage {

namespace {

/// (domain, index within the domain) of every cell; (-1, -1) when no domain owns it.
std::vector<std::pair<int, int>> cell_owners(const Model& m) {
  std::vector<std::pair<int, int>> owner(m.mesh.cells.size(), {-1, -1});
  for (std::size_t d = 0; d < m.domains.size(); ++d)
    for (std::size_t i = 0; i < m.domains[d].cells.size(); ++i)
      owner[static_cast<std::size_t>(m.domains[d].cells[i])] = {static_cast<int>(d), static_cast<int>(i)};
  return owner;
}

/// Walks the given cells whose domain `takes` (e.g. has a material): calls
/// fn(dm, cell, first, last, xp) with the domain's point range of the cell and the points'
/// coordinates (rows of xp), then holds those points' committed states (the stage set them).
template <class Takes, class Fn>
void for_cells(Model& m, const std::vector<int>& cells, Takes&& takes, Fn&& fn) {
  const auto owner = cell_owners(m);
  std::vector<int> nodes;
  Eigen::MatrixXd x, xp;
  for (int c : cells) {
    const auto [d, i] = owner[static_cast<std::size_t>(c)];
    if (d < 0) continue;
    auto& dm = m.domains[static_cast<std::size_t>(d)];
    if (!takes(dm)) continue;
    m.cell_nodes(c, nodes, x);
    dm.element->point_coordinates(m.element_data(c, x), xp);
    const auto first = dm.first_point[static_cast<std::size_t>(i)];
    const auto last = dm.first_point[static_cast<std::size_t>(i) + 1];
    fn(dm, c, first, last, xp);
    dm.states.hold(first, last);
  }
}

/// Calls fn(dm, slot, x) for every integration point of the given cells that have a material.
template <class Fn> void for_points(Model& m, const std::vector<int>& cells, Fn&& fn) {
  for_cells(
      m, cells, [](const Domain& dm) { return dm.law.material != nullptr; },
      [&](Domain& dm, int, std::size_t first, std::size_t last, const Eigen::MatrixXd& xp) {
        for (std::size_t p = first; p < last; ++p) {
          auto slot = dm.states.committed_for_init(p);
          fn(dm, slot, Eigen::Vector2d(xp.row(static_cast<Eigen::Index>(p - first))));
        }
      });
}

/// Puts the interface points of the given cells under a normal compression p(cell, x) (kPa) with
/// zero shear: the normal jump is found by Newton iterations on the law itself, so that any law
/// (including those whose normal stress follows the total jump) starts from that traction.
template <class Pressure>
void set_interface_compression(Model& m, const std::vector<int>& cells, Pressure&& p) {
  for_cells(
      m, cells, [](const Domain& dm) { return dm.law.contact != nullptr; },
      [&](Domain& dm, int c, std::size_t first, std::size_t last, const Eigen::MatrixXd& xp) {
        std::vector<double> h0(static_cast<std::size_t>(dm.law.contact->history_size()));
        std::vector<double> h1(h0.size());
        for (std::size_t q = first; q < last; ++q) {
          auto slot = dm.states.committed_for_init(q);
          dm.law.contact->init_history(h0);
          const double target = -p(c, Eigen::Vector2d(xp.row(static_cast<Eigen::Index>(q - first))));
          const Vec2 zero = Vec2::Zero();
          Vec2 jump = Vec2::Zero(), traction = Vec2::Zero();
          Mat2 tangent = Mat2::Zero();
          for (int it = 0; it < 50; ++it) {
            ContactOutput out{traction, h1, tangent};
            if (!dm.law.contact
                     ->update(
                         ContactInput{zero, zero, h0, jump, PointContext{c, static_cast<int>(q - first)}},
                         out)
                     .ok())
              break;
            const double r = traction[1] - target;
            if (std::abs(r) <= 1e-12 * std::max(1.0, std::abs(target)) || !(tangent(1, 1) > 0)) break;
            jump[1] -= r / tangent(1, 1);
          }
          slot.stress().setZero();
          slot.stress()[0] = traction[0];
          slot.stress()[1] = traction[1];
          slot.strain().setZero();
          slot.strain()[0] = jump[0];
          slot.strain()[1] = jump[1];
          std::copy(h1.begin(), h1.end(), slot.history().begin());
        }
      });
}

} // namespace

void set_geostatic(Model& model, const std::vector<int>& cells, const AtRest& state) {
  const double K0 = state.K0;
  std::vector<int> active;
  for (int c : cells)
    if (model.is_active(c)) active.push_back(c);
  for_points(model, active, [&](const Domain& dm, PointSlot<double>& slot, const Eigen::Vector2d& x) {
    const double sv = state.vertical_effective(x.x(), x.y());
    Vec6 s = Vec6::Zero();
    s[voigt::xx] = K0 * sv;
    s[voigt::yy] = sv;
    s[voigt::zz] = K0 * sv;
    slot.stress() = s;
    slot.strain().setZero();
    dm.law.material->init_history(s, slot.history());
  });
  // Interface cells (e.g. boundary springs on the far side) carry the geostatic traction on
  // their plane, n.sigma.n, and no shear: K0 nx^2 + ny^2 times the vertical stress.
  std::vector<int> interfaces;
  std::vector<double> lateral(model.mesh.cells.size(), 0.0);
  for (int c : active) {
    const auto& cell = model.mesh.cells[static_cast<std::size_t>(c)];
    if (is_solid(cell.type)) continue;
    // A line interface runs from node 0 to node 1; a node pair along its neighbours (slots 2, 3).
    const int a = cell.type == CellType::node_pair ? cell.nodes[2] : cell.nodes[0];
    const int b = cell.type == CellType::node_pair ? cell.nodes[3] : cell.nodes[1];
    const Eigen::Vector2d t =
        model.mesh.nodes[static_cast<std::size_t>(b)] - model.mesh.nodes[static_cast<std::size_t>(a)];
    if (!(t.norm() > 0)) continue;
    interfaces.push_back(c);
    const double nx2 = t.y() * t.y() / t.squaredNorm(), ny2 = t.x() * t.x() / t.squaredNorm();
    lateral[static_cast<std::size_t>(c)] = K0 * nx2 + ny2;
  }
  set_interface_compression(model, interfaces, [&](int c, const Eigen::Vector2d& x) {
    return -state.vertical_effective(x.x(), x.y()) * lateral[static_cast<std::size_t>(c)];
  });
}

void set_placed_stress(Model& model, const std::vector<int>& cells, bool hydrostatic, double gamma,
                       double surface) {
  if (hydrostatic)
    set_interface_compression(
        model, cells, [&](int, const Eigen::Vector2d& x) { return gamma * std::max(surface - x.y(), 0.0); });
  for_points(model, cells, [&](const Domain& dm, PointSlot<double>& slot, const Eigen::Vector2d& x) {
    Vec6 s = Vec6::Zero();
    if (hydrostatic) {
      const double p = gamma * std::max(surface - x.y(), 0.0);
      s[voigt::xx] = s[voigt::yy] = s[voigt::zz] = -p;
    }
    slot.stress() = s;
    slot.strain().setZero();
    dm.law.material->init_history(s, slot.history());
  });
}

} // namespace stratum::stage
