// The mesh: nodes, cells, and named node, cell and edge sets.
//
// Coordinates in m. Axisymmetric: x = r (radius, >= 0), y = z (vertical, up).
#pragma once

#include "stratum/error.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace stratum {

/// What a cell is geometrically (for checks and output; elements only see its nodes).
///  * solid: a quadrilateral of the continuum (slots as below), or a triangle: slots 3 and 7
///    empty, corners 0 1 2 counter-clockwise, midside 4 (edge 0-1), 5 (1-2), 6 (2-0);
///  * node_pair: a two-node contact cell (stratum/body_interfaces.hpp): slot 0 the node of body 1,
///    slot 1 its coincident partner of body 2, slots 2 and 3 the body-1 nodes before and after
///    slot 0 along the interface (slot 0 itself at an end), for the direction and tributary length;
///  * line_interface: a zero-thickness quadrilateral: slots 0, 1 (and midside 4) on body 1, slots
///    2, 3 (and midside 6) on body 2, slot 3 coincident with 0, 2 with 1, 6 with 4.
enum class CellKind : std::uint8_t { solid = 0, node_pair = 1, line_interface = 2 };

/// A cell: up to 8 node slots, -1 for an absent slot. For the quadrilateral
/// family the slots follow element.hpp (0-3 corners counter-clockwise, 4-7 midside).
struct Cell {
  std::array<int, 8> nodes{-1, -1, -1, -1, -1, -1, -1, -1};
  CellKind kind = CellKind::solid;

  /// Bitmask of the present slots.
  [[nodiscard]] unsigned shape() const {
    unsigned s = 0;
    for (int i = 0; i < 8; ++i)
      if (nodes[i] >= 0) s |= 1u << i;
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
