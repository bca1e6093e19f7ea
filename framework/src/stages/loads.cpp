// The nodal forces of the loads a stage applies (stratum/load.hpp).
#include "stratum/load.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

namespace stratum {

double projected_area(const Model& model, const std::vector<Edge>& edges) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.dofs.total());
  add_edge_pressure(model, edges, 1.0, f);
  double fy = 0.0;
  for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n)
    if (const int d = model.dofs.dof(static_cast<int>(n), field_uy); d >= 0) fy += f[d];
  return std::abs(fy);
}

std::vector<Edge> load_edges(const Model& model, const LoadSpec& spec) {
  if (!spec.top_of_cells) return model.mesh.edge_sets.at(spec.set);
  double top = -std::numeric_limits<double>::infinity();
  const auto& cells = model.mesh.cell_sets.at(spec.set);
  for (int c : cells) {
    if (!model.is_active(c)) continue;
    const auto& n = model.mesh.cells[c].nodes;
    top = std::max(top, model.mesh.nodes[n[2]].y());
    if (n[3] < 0) // a triangle's top may be any of its corners
      top = std::max({top, model.mesh.nodes[n[0]].y(), model.mesh.nodes[n[1]].y()});
  }
  std::vector<Edge> edges;
  const double tol = 1e-9 * std::max(1.0, std::abs(top)); // relative: any length unit ([units])
  for (int c : cells) {
    if (!model.is_active(c)) continue;
    const auto& n = model.mesh.cells[c].nodes;
    if (n[3] < 0) { // triangle (slot 3 empty): any of its edges k -> k+1 (midside 4 + k) on the top
      for (int k = 0; k < 3; ++k) {
        const int a = n[k], b = n[(k + 1) % 3];
        if (std::abs(model.mesh.nodes[a].y() - top) < tol && std::abs(model.mesh.nodes[b].y() - top) < tol)
          edges.push_back(Edge{a, b, n[4 + k]});
      }
      continue;
    }
    // Top side of a quadrilateral cell, counter-clockwise: corner 2 -> corner 3, midside 6.
    if (std::abs(model.mesh.nodes[n[2]].y() - top) < tol && std::abs(model.mesh.nodes[n[3]].y() - top) < tol)
      edges.push_back(Edge{n[2], n[3], n[6]});
  }
  return edges;
}

std::vector<int> load_nodes(const Model& model, const LoadSpec& spec) {
  if (spec.kind == LoadSpec::Kind::force) return model.mesh.node_sets.at(spec.set);
  std::vector<int> ids;
  for (const Edge& e : load_edges(model, spec))
    for (int n : {e.a, e.b, e.mid})
      if (n >= 0) ids.push_back(n);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

void add_load(const Model& model, const LoadSpec& spec, Eigen::VectorXd& f) {
  switch (spec.kind) {
  case LoadSpec::Kind::pressure: {
    const auto edges = load_edges(model, spec);
    if (std::isfinite(spec.total_force)) {
      const double area = projected_area(model, edges);
      const double p = area > 0 ? spec.total_force / area : 0.0;
      add_edge_pressure(model, edges, p, f);
    } else {
      const LoadSpec& s = spec;
      add_edge_pressure(
          model, edges,
          [&s](const Eigen::Vector2d& x) {
            return s.p + s.gamma * std::min(std::max(s.surface - x.y(), 0.0), s.critical_depth);
          },
          f);
    }
    break;
  }
  case LoadSpec::Kind::force:
    for (int n : model.mesh.node_sets.at(spec.set)) {
      if (const int d = model.dofs.dof(n, field_ux); d >= 0) f[d] += spec.fx;
      if (const int d = model.dofs.dof(n, field_uy); d >= 0) f[d] += spec.fy;
    }
    break;
  case LoadSpec::Kind::gravity: {
    const auto& set = model.mesh.cell_sets.at(spec.set);
    const std::set<int> in_set(set.begin(), set.end());
    Eigen::VectorXd b = Eigen::VectorXd::Zero(2);
    b[field_uy] = -spec.gamma;
    std::vector<int> nodes, dofs;
    Eigen::MatrixXd x;
    Eigen::VectorXd fe;
    for (const auto& dm : model.domains)
      for (int c : dm.cells) {
        if (!model.is_active(c) || !in_set.count(c)) continue;
        model.cell_nodes(c, nodes, x);
        // Below the level (at the cell's centroid) the skeleton is buoyant; the steady pore
        // pressure gamma_w (level(x) - y) of each vertical also pushes it along the level's fall.
        const double xc = x.col(0).mean();
        const bool wet = x.col(1).mean() < spec.water.at(xc);
        b[field_ux] = wet ? -spec.gamma_w * spec.water.slope(xc) : 0.0;
        b[field_uy] = wet ? -spec.gamma_below : -spec.gamma;
        dm.element->body_force(model.element_data(c, x), b, fe);
        model.cell_dofs(dm, c, dofs);
        for (std::size_t i = 0; i < dofs.size(); ++i)
          if (dofs[i] >= 0) f[dofs[i]] += fe[static_cast<Eigen::Index>(i)];
      }
    break;
  }
  case LoadSpec::Kind::inflow: // no force: add_inflow
    break;
  }
}

void add_inflow(const Model& model, const LoadSpec& spec, Eigen::VectorXd& rate) {
  if (spec.kind != LoadSpec::Kind::inflow) return;
  const int f = model.dofs.field("p");
  const bool axi = model.formulation == Formulation::axisymmetric;
  // Three Gauss points along each edge: the edge's geometry is quadratic through its midside
  // node, the pressure linear between its corners (Taylor-Hood), or quadratic where the midside
  // node carries one too.
  constexpr double g = 0.7745966692414834, w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  constexpr double s3[3] = {-g, 0.0, g};
  bool any = false;
  for (const Edge& e : model.mesh.edge_sets.at(spec.set)) {
    const int da = f >= 0 ? model.dofs.dof(e.a, f) : -1, db = f >= 0 ? model.dofs.dof(e.b, f) : -1;
    const int dm = f >= 0 && e.mid >= 0 ? model.dofs.dof(e.mid, f) : -1;
    if (da < 0 && db < 0 && dm < 0) continue;
    any = true;
    const Eigen::Vector2d xa = model.mesh.nodes[static_cast<std::size_t>(e.a)];
    const Eigen::Vector2d xb = model.mesh.nodes[static_cast<std::size_t>(e.b)];
    const Eigen::Vector2d xm =
        e.mid >= 0 ? model.mesh.nodes[static_cast<std::size_t>(e.mid)] : 0.5 * (xa + xb);
    for (int k = 0; k < 3; ++k) {
      const double t = s3[k];
      const Eigen::Vector2d x = 0.5 * t * (t - 1.0) * xa + 0.5 * t * (t + 1.0) * xb + (1.0 - t * t) * xm;
      const Eigen::Vector2d dx = (t - 0.5) * xa + (t + 0.5) * xb - 2.0 * t * xm;
      const double ds = w[k] * dx.norm() * (axi ? 2.0 * std::numbers::pi * x.x() : 1.0);
      const double na = dm >= 0 ? 0.5 * t * (t - 1.0) : 0.5 * (1.0 - t);
      const double nb = dm >= 0 ? 0.5 * t * (t + 1.0) : 0.5 * (1.0 + t);
      if (da >= 0) rate[da] += spec.q * na * ds;
      if (db >= 0) rate[db] += spec.q * nb * ds;
      if (dm >= 0) rate[dm] += spec.q * (1.0 - t * t) * ds;
    }
  }
  if (!any)
    throw Error(
        "inflow '" + spec.name + "': no node of edge set '" + spec.set +
        "' carries a pore pressure p (the set must bound cells of a porous element: quad8p4, tri6p3)");
}

} // namespace stratum
