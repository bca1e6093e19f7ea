// The mesh: nodes, cells, and named node, cell and edge sets.
//
// Coordinates in m. Axisymmetric: x = r (radius, >= 0), y = z (vertical, up).
#pragma once

#include "stratum/cell_type.hpp"
#include "stratum/error.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace stratum {

/// A cell: its type and up to max_cell_slots node slots in the type's numbering
/// (stratum/cell_type.hpp), -1 for an absent slot.
struct Cell {
  std::array<int, max_cell_slots> nodes{-1, -1, -1, -1, -1, -1, -1, -1};
  CellType type = CellType::quadrilateral;

  /// Bitmask of the present slots.
  [[nodiscard]] unsigned shape() const {
    unsigned s = 0;
    for (int i = 0; i < max_cell_slots; ++i)
      if (nodes[static_cast<std::size_t>(i)] >= 0) s |= 1u << i;
    return s;
  }
  [[nodiscard]] int count() const {
    int n = 0;
    for (int v : nodes) n += v >= 0;
    return n;
  }
};

/// A boundary edge: its two end nodes and the midside node (-1 for a straight 2-node edge).
/// a -> b follows the body's counter-clockwise boundary, so with d = x_b - x_a the
/// outward normal is (d_y, -d_x)/|d|.
struct Edge {
  int a = -1, b = -1, mid = -1;
};

struct Mesh {
  std::vector<Eigen::Vector2d> nodes;
  std::vector<Cell> cells;
  std::map<std::string, std::vector<int>> node_sets;
  std::map<std::string, std::vector<int>> cell_sets;
  std::map<std::string, std::vector<Edge>> edge_sets;

  /// Adds an edge set and the node set of the same name (all its nodes, sorted, unique).
  void add_edge_set(const std::string& name, std::vector<Edge> edges);
  /// All cells in one set called "all" (added by the readers).
  void add_all_set();
  /// Throws Error when a cell references a missing node, a corner is absent, or a cell
  /// has non-positive area at a corner (the message names the cell).
  void check() const;
};

} // namespace stratum
