// SceneModel::rehearse_stages: the stages' actions applied in order to a copy of the model, without
// solving anything, so that what would only go wrong when a stage starts is found while the scene
// is built (and so by `stratum check`): a load that acts on nothing, two pile-head loads at once,
// a part of the mesh that no constraint holds (its stiffness is singular).
#include "model/scene_model.hpp"

#include "stratum/load.hpp"
#include "stratum/solver.hpp"
#include "stratum/stage_action.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

namespace stratum {

namespace {

/// Which full-size DOFs the active cells of the domains carry (as Model::rebuild_dofs counts).
std::vector<char> carried_dofs(const Model& m) {
  std::vector<char> used(static_cast<std::size_t>(m.dofs.total()), 0);
  std::vector<int> ld;
  for (const auto& dm : m.domains)
    for (int c : dm.cells)
      if (m.is_active(c)) {
        m.cell_dofs(dm, c, ld);
        for (int d : ld)
          if (d >= 0) used[static_cast<std::size_t>(d)] = 1;
      }
  return used;
}

std::string describe(const LoadSpec& l) {
  switch (l.kind) {
  case LoadSpec::Kind::pressure:
    return std::string(std::isfinite(l.total_force) ? "head load" : "pressure") + " on " +
           (l.top_of_cells ? "the top of cell set '" : "edge set '") + l.set + "'";
  case LoadSpec::Kind::force:
    return "force on node set '" + l.set + "'";
  case LoadSpec::Kind::gravity:
    return "gravity on cell set '" + l.set + "'";
  case LoadSpec::Kind::inflow:
    return "inflow through edge set '" + l.set + "'";
  }
  return {};
}

/// The nodes a load acts at: reached (carried by an active cell of a domain) and in total. Gravity
/// acts on cells: counted as the set's cells and those active in a domain.
std::pair<std::size_t, std::size_t> reach(const Model& m, const LoadSpec& l,
                                          const std::vector<char>& carried) {
  if (l.kind == LoadSpec::Kind::gravity) {
    std::vector<char> in_domain(m.mesh.cells.size(), 0);
    for (const auto& dm : m.domains)
      for (int c : dm.cells) in_domain[static_cast<std::size_t>(c)] = 1;
    const auto& cells = m.mesh.cell_sets.at(l.set);
    const auto n = std::count_if(cells.begin(), cells.end(), [&](int c) {
      return m.is_active(c) && in_domain[static_cast<std::size_t>(c)];
    });
    return {static_cast<std::size_t>(n), cells.size()};
  }
  const std::vector<int> nodes = load_nodes(m, l);
  std::size_t n = 0, total = 0;
  // An inflow acts at the nodes that carry a pore pressure (a Taylor-Hood cell's corners), the
  // others at the displacements of every node.
  const bool inflow = l.kind == LoadSpec::Kind::inflow;
  const int field = inflow ? m.dofs.field("p") : field_uy;
  for (int node : nodes) {
    const int d = m.dofs.dof(node, field);
    total += !inflow || d >= 0;
    n += d >= 0 && carried[static_cast<std::size_t>(d)];
  }
  return {n, inflow ? std::max<std::size_t>(total, 1) : total};
}

/// Smallest root of a node's part (union-find with path halving).
int root(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i)
    i = parent[static_cast<std::size_t>(i)] =
        parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
  return i;
}

/// The first part of the active mesh (cells joined by shared nodes, interfaces included) in which
/// no DOF of a field with a rigid-body mode is held; empty when every part is held.
std::string unheld_part(const Model& m, const std::vector<char>& carried, const Units& units) {
  const std::size_t nn = m.mesh.nodes.size();
  std::vector<int> parent(nn);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> used(nn, 0);
  for (const auto& dm : m.domains)
    for (int c : dm.cells) {
      if (!m.is_active(c)) continue;
      int first = -1;
      for (int n : m.mesh.cells[static_cast<std::size_t>(c)].nodes) {
        if (n < 0) continue;
        used[static_cast<std::size_t>(n)] = 1;
        if (first < 0)
          first = n;
        else
          parent[static_cast<std::size_t>(root(parent, n))] = root(parent, first);
      }
    }
  // The displacement fields whose rigid motion a part must be held against: both in plane strain
  // (and 3D), only the axial one in axisymmetry (a radial motion strains the hoop direction).
  // A field is looked up by name: a scene of scalar-field elements (a flow problem) has none.
  std::vector<int> fields;
  for (int f = 0; f < m.dim(); ++f)
    if ((m.formulation != Formulation::axisymmetric || f == field_uy) &&
        m.dofs.field(std::string("u") + "xyz"[f]) == f)
      fields.push_back(f);
  // Per part root: a bit per field that some constrained DOF holds; the part's node count and a node.
  std::vector<unsigned> held(nn, 0), carries(nn, 0);
  std::vector<std::size_t> size(nn, 0);
  for (std::size_t n = 0; n < nn; ++n) {
    if (!used[n]) continue;
    const auto r = static_cast<std::size_t>(root(parent, static_cast<int>(n)));
    ++size[r];
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const int d = m.dofs.dof(static_cast<int>(n), fields[k]);
      if (d >= 0 && carried[static_cast<std::size_t>(d)]) carries[r] |= 1U << k;
      if (d >= 0 && carried[static_cast<std::size_t>(d)] && m.constrained[static_cast<std::size_t>(d)])
        held[r] |= 1U << k;
    }
  }
  for (std::size_t r = 0; r < nn; ++r) {
    if (!size[r] || held[r] == carries[r] || root(parent, static_cast<int>(r)) != static_cast<int>(r))
      continue;
    std::string free_fields;
    for (std::size_t k = 0; k < fields.size(); ++k)
      if ((carries[r] & ~held[r]) & (1U << k))
        free_fields += std::string(free_fields.empty() ? "" : " and ") + std::string(1, "xyz"[fields[k]]);
    std::size_t cells = 0;
    for (const auto& dm : m.domains)
      for (int c : dm.cells) {
        const int first = m.mesh.cells[static_cast<std::size_t>(c)].nodes[0];
        cells += m.is_active(c) && first >= 0 && root(parent, first) == static_cast<int>(r);
      }
    const auto& x = m.mesh.nodes[r];
    std::ostringstream o;
    o.precision(6);
    o << "a part of the mesh (" << cells << (cells == 1 ? " cell" : " cells") << ", " << size[r]
      << " nodes, one at (" << x.x() << ", " << x.y() << ") " << units.length()
      << ") is held by no constraint in " << free_fields
      << ": its stiffness is singular; constrain it, or join it to the rest (shared nodes or an interface)";
    return o.str();
  }
  return {};
}

/// Pairs of nodes of the cells at one place that no interface joins: the mesh is cut there (two
/// Gmsh surfaces meshed without sharing their boundary, a duplicated node). A warning: the cut
/// may be meant, but a body that falls apart there is rarely what a scene wants.
std::string coincident_nodes(const Model& m, const Units& units) {
  const std::size_t nn = m.mesh.nodes.size();
  std::vector<char> used(nn, 0), joined(nn, 0);
  for (const auto& dm : m.domains)
    for (int c : dm.cells)
      for (int n : m.mesh.cells[static_cast<std::size_t>(c)].nodes)
        if (n >= 0) (dm.law.contact ? joined : used)[static_cast<std::size_t>(n)] = 1;
  std::vector<int> order;
  for (std::size_t n = 0; n < nn; ++n)
    if (used[n]) order.push_back(static_cast<int>(n));
  if (order.empty()) return {};
  Eigen::Vector2d lo = m.mesh.nodes[static_cast<std::size_t>(order[0])], hi = lo;
  for (int n : order)
    lo = lo.cwiseMin(m.mesh.nodes[static_cast<std::size_t>(n)]),
    hi = hi.cwiseMax(m.mesh.nodes[static_cast<std::size_t>(n)]);
  const double tol = 1e-9 * std::max((hi - lo).norm(), 1e-300);
  const auto x = [&](int n) -> const Eigen::Vector2d& { return m.mesh.nodes[static_cast<std::size_t>(n)]; };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return x(a).x() < x(b).x(); });
  std::size_t pairs = 0;
  int first_a = -1, first_b = -1;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (std::size_t j = i + 1; j < order.size() && x(order[j]).x() - x(order[i]).x() <= tol; ++j) {
      const int a = order[i], b = order[j];
      if ((x(a) - x(b)).norm() > tol ||
          (joined[static_cast<std::size_t>(a)] && joined[static_cast<std::size_t>(b)]))
        continue;
      if (pairs++ == 0) first_a = std::min(a, b), first_b = std::max(a, b);
    }
  if (pairs == 0) return {};
  std::ostringstream o;
  o.precision(6);
  o << "[mesh] " << pairs << (pairs == 1 ? " pair" : " pairs")
    << " of nodes at one place with no interface between " << (pairs == 1 ? "them" : "each")
    << ", e.g. nodes " << first_a << " and " << first_b << " at (" << x(first_a).x() << ", " << x(first_a).y()
    << ") " << units.length()
    << ": the mesh is cut there (surfaces meshed without a shared boundary, or a duplicated node); join "
       "them, or put an interface there if the cut is meant";
  return o.str();
}

/// A consolidation stage needs a pore pressure to flow (an error without one) and, to drain, a
/// node where it is held (a warning without: the water only redistributes inside the model).
void check_consolidation(const Model& m, const stage::Stage& st, const std::string& ctx,
                         std::vector<std::string>& warnings) {
  const int f = m.dofs.field("p");
  if (f < 0)
    throw Error(st.where, ctx +
                              ": type = \"consolidation\", but no domain carries a pore pressure p; give "
                              "the saturated soil a porous element (element = \"quad8p4\" or \"tri6p3\"), or "
                              "make the stage static");
  for (std::size_t n = 0; n + 1 < m.dofs.node_first.size(); ++n)
    if (const int d = m.dofs.dof(static_cast<int>(n), f);
        d >= 0 && m.constrained[static_cast<std::size_t>(d)])
      return;
  warnings.push_back(
      st.where.str() + " " + ctx +
      ": a consolidation stage with no drained boundary (no node holds p): the water cannot "
      "leave, the excess pore pressure only evens out; open one with a [[stages.actions]] type "
      "= \"drain\" or a [[constraints]] field = \"p\"");
}

} // namespace

void SceneModel::rehearse_stages() {
  if (std::string cut = coincident_nodes(model, units); !cut.empty()) warnings.push_back(std::move(cut));
  Model m = model;
  const std::unique_ptr<Solver> solver = solver_factory->create(solver_params);
  std::vector<LoadSpec> loads;
  for (std::size_t k = 0; k < stages.size(); ++k) {
    const stage::Stage& st = stages[k];
    const std::string ctx = "stage \"" + st.name + "\"";
    m.prescribed = k == 0 ? initial_prescribed : Eigen::VectorXd::Zero(m.u.size());
    StageState actions{m, loads, nullptr, {}, {}};
    for (const auto& a : st.actions) a->apply(actions);
    const std::vector<char> carried = carried_dofs(m);

    std::map<std::pair<bool, std::string>, std::vector<std::string>> heads; // per head (set): its loads
    for (const auto& l : loads) {
      if (l.kind == LoadSpec::Kind::pressure && std::isfinite(l.total_force))
        heads[{l.top_of_cells, l.set}].push_back(l.name);
      const auto [reached, total] = reach(m, l, carried);
      if (reached == 0)
        throw Error(st.where,
                    ctx + ": the load '" + l.name + "' (" + describe(l) + ") acts on nothing: none of its " +
                        (l.kind == LoadSpec::Kind::gravity ? "cells is active in a domain"
                                                           : "nodes belongs to an active cell of a domain") +
                        " in this stage; remove it, or activate its cells");
      if (reached < total && l.kind != LoadSpec::Kind::gravity)
        warnings.push_back(
            st.where.str() + " " + ctx + ": the load '" + l.name + "' (" + describe(l) + ") acts on " +
            std::to_string(reached) + " of its " + std::to_string(total) +
            " nodes; the others belong to no active cell of a domain, and their share is dropped");
    }
    for (const auto& [head, names] : heads)
      if (names.size() > 1)
        throw Error(st.where,
                    ctx + ": the head loads '" + names[0] + "' and '" + names[1] + "' act together on " +
                        (head.first ? "the top of cell set '" : "edge set '") + head.second +
                        "', but the pile curve follows one head load; remove '" + names[0] +
                        "' in this stage (type = \"remove\") and give '" + names[1] + "' the total force");
    if (const std::string why = unheld_part(m, carried, units); !why.empty())
      throw Error(st.where, ctx + ": " + why);
    m.rebuild_dofs();
    if (st.consolidation) {
      check_consolidation(m, st, ctx, warnings);
      if (solver->path_following())
        throw Error(st.where,
                    ctx +
                        ": type = \"consolidation\" needs a load-controlled solver: its load factor "
                        "is time, which a path-following solver (" +
                        solver_factory->name +
                        ") would run backwards; use solver = \"newton\" (or "
                        "modified_newton, kinsol)");
    }
    solver->check(SolverCheck{m, ctx});
  }
}

} // namespace stratum
