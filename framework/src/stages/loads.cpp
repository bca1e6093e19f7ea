// The nodal forces of the loads a stage applies (stratum/load.hpp).
#include "stratum/load.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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
        b[field_uy] = x.col(1).mean() < spec.water_level ? -spec.gamma_below : -spec.gamma;
        dm.element->body_force(model.element_data(c, x), b, fe);
        model.cell_dofs(dm, c, dofs);
        for (std::size_t i = 0; i < dofs.size(); ++i)
          if (dofs[i] >= 0) f[dofs[i]] += fe[static_cast<Eigen::Index>(i)];
      }
    break;
  }
  }
}

} // namespace stratum
