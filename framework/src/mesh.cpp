#include "stratum/mesh.hpp"

#include "suggest.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

namespace stratum {

namespace {

std::string cell_name(std::size_t c) { return "mesh cell " + std::to_string(c) + " (0-based)"; }

// Throws when a set refers to an index outside [0, size).
void check_indices(const char* kind, const std::string& set, const std::vector<int>& indices,
                   std::size_t size, const char* what) {
  for (int i : indices)
    if (i < 0 || static_cast<std::size_t>(i) >= size)
      throw Error(std::string("mesh ") + kind + " set '" + set + "': " + what + " " + std::to_string(i) +
                  " does not exist (the mesh has " + std::to_string(size) + " " + what + "s)");
}

} // namespace

void Mesh::add_edge_set(const std::string& name, std::vector<Edge> edges) {
  std::vector<int> ids;
  ids.reserve(3 * edges.size());
  for (const Edge& e : edges)
    for (int n : {e.a, e.b, e.mid})
      if (n >= 0) ids.push_back(n);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  node_sets[name] = std::move(ids);
  edge_sets[name] = std::move(edges);
}

void Mesh::add_all_set() {
  std::vector<int> all(cells.size());
  std::iota(all.begin(), all.end(), 0);
  cell_sets["all"] = std::move(all);
}

void Mesh::check() const {
  const std::size_t n = nodes.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!nodes[i].allFinite())
      throw Error("mesh node " + std::to_string(i) + " (0-based) has a coordinate that is not finite");

  for (std::size_t c = 0; c < cells.size(); ++c) {
    const Cell& cell = cells[c];
    for (int s = 0; s < 8; ++s) {
      const int v = cell.nodes[s];
      if (v < -1 || (v >= 0 && static_cast<std::size_t>(v) >= n))
        throw Error(cell_name(c) + ": slot " + std::to_string(s) + " refers to node " + std::to_string(v) +
                    ", which does not exist (the mesh has " + std::to_string(n) + " nodes)");
    }
    if (!is_solid(cell.type)) continue; // interface cells: zero thickness by design
    if (cell_dimension(cell.type) != 2)
      throw Error(cell_name(c) + ": a " + to_string(cell.type) +
                  " in a mesh of two-dimensional nodes; three-dimensional meshes are not read yet");
    // A triangle is a solid cell without corner 3 and its edge's midside slot 7.
    const int nc = cell.nodes[3] < 0 && cell.nodes[7] < 0 ? 3 : 4;
    if ((nc == 3) != (cell.type == CellType::triangle))
      throw Error(cell_name(c) + ": a " + to_string(cell.type) + " with " + std::to_string(nc) + " corners");
    for (int s = 0; s < nc; ++s)
      if (cell.nodes[s] < 0) throw Error(cell_name(c) + ": corner slot " + std::to_string(s) + " is empty");
    for (int s = 0; s < nc; ++s) {
      const Eigen::Vector2d& p = nodes[cell.nodes[s]];
      const Eigen::Vector2d next = nodes[cell.nodes[(s + 1) % nc]] - p;
      const Eigen::Vector2d prev = nodes[cell.nodes[(s + nc - 1) % nc]] - p;
      const double cross = next.x() * prev.y() - next.y() * prev.x();
      if (!(cross > 0.0))
        throw Error(cell_name(c) + ": corner " + std::to_string(s) + " (node " +
                    std::to_string(cell.nodes[s]) + " at " + number_text(p.x()) + ", " + number_text(p.y()) +
                    ") has a non-positive area; the corners must be counter-clockwise and the cell convex");
    }
  }

  for (const auto& [name, ids] : node_sets) check_indices("node", name, ids, n, "node");
  for (const auto& [name, ids] : cell_sets) check_indices("cell", name, ids, cells.size(), "cell");
  for (const auto& [name, edges] : edge_sets)
    for (const Edge& e : edges) {
      const bool ends_ok = e.a >= 0 && e.b >= 0 && static_cast<std::size_t>(e.a) < n &&
                           static_cast<std::size_t>(e.b) < n && e.a != e.b;
      const bool mid_ok = e.mid == -1 || (e.mid >= 0 && static_cast<std::size_t>(e.mid) < n);
      if (!ends_ok || !mid_ok)
        throw Error("mesh edge set '" + name + "': edge {" + std::to_string(e.a) + ", " +
                    std::to_string(e.b) + ", " + std::to_string(e.mid) +
                    "} refers to a missing node (the mesh has " + std::to_string(n) + " nodes)");
    }
}

} // namespace stratum
