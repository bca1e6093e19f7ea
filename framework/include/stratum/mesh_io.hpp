// Mesh sources: the built-in structured generator and Gmsh .msh 4.1 ASCII import.
#pragma once

#include "stratum/mesh.hpp"

#include <string>
#include <vector>

namespace stratum {

/// One graded rectangular block [x0, x1] x [y0, y1] with nx x ny cells.
/// Grading: ratio of the last cell size to the first along each direction
/// (1 = uniform, > 1 grows towards x1 / y1). The cells are quads of `nodes_per_cell`
/// nodes (4 or 8; 8 = serendipity with midside nodes).
struct Block {
  std::string name; ///< cell set name; its edges make sets "<name>.left|right|bottom|top"
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  int nx = 1, ny = 1;
  double grade_x = 1.0, grade_y = 1.0;
};

/// Builds a mesh of blocks sharing nodes where they coincide (within 1e-9 of the whole
/// mesh's bounding-box size). Sets: per block "<name>" (cells) and "<name>.left" etc. (edges and
/// nodes); for the whole mesh "all" (cells) and "left", "right", "bottom", "top"
/// (edges and nodes on the bounding box). Throws Error on bad arguments.
[[nodiscard]] Mesh generate_blocks(const std::vector<Block>& blocks, int nodes_per_cell);

/// Reads a Gmsh 4.1 ASCII file. Quadrangles (4- and 8-node; 9-node with the centre
/// dropped) become cells; physical groups of dimension 2 become cell sets, of dimension 1
/// edge sets (and node sets), of dimension 0 node sets. Other element types of
/// dimension 2 are an error. Errors name file:line.
[[nodiscard]] Mesh read_gmsh(const std::string& path);

} // namespace stratum
