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

/// The axisymmetric bored-pile mesh (x = r, y = z, ground at y = 0). Zones, each graded towards
/// the pile: the pile column [0, a] x [-L, 0]; a near zone r <= near_radius, y >= -near_depth
/// (nonlinear soil); the far zone beyond it (linear soil) out to domain_radius and down to
/// domain_depth.
struct PileMesh {
  double radius = 0.135, length = 3.0;
  double near_radius = 1.0, near_depth = 4.5;
  double domain_radius = 6.0, domain_depth = 9.0;
  int nodes_per_cell = 8;
  int n_pile = 2;   ///< cells across the pile radius
  int n_shaft = 12; ///< cells along the pile
  int n_near = 8;   ///< cells from the shaft to near_radius
  int n_far = 5;    ///< cells from near_radius to domain_radius
  int n_below = 6;  ///< cells from the pile base to near_depth
  int n_deep = 3;   ///< cells from near_depth to domain_depth
  double grade_near = 6.0, grade_far = 3.0, grade_below = 4.0, grade_deep = 2.0;
};

/// Builds the pile mesh. Cell sets: "pile" (the concrete, own nodes on its shaft and base only
/// after an interface split; before that it shares the nodes of "bore"), "bore" (the soil the
/// auger removes, same place as "pile"), "near", "far", "soil" (near and far), "all". Edge and
/// node sets: "hole" (the soil side of the borehole: shaft then base, counter-clockwise for the
/// soil, for the fresh-concrete pressure and for an interface split with cells = "pile"),
/// "shaft", "base" (its two parts), "axis", "surface", "far_side", "bottom". Throws Error on
/// inconsistent dimensions.
[[nodiscard]] Mesh generate_pile(const PileMesh& spec);

/// Reads a Gmsh 4.1 ASCII file. Quadrangles (4- and 8-node; 9-node with the centre
/// dropped) become cells; physical groups of dimension 2 become cell sets, of dimension 1
/// edge sets (and node sets), of dimension 0 node sets. Other element types of
/// dimension 2 are an error. Errors name file:line.
[[nodiscard]] Mesh read_gmsh(const std::string& path);

} // namespace stratum
