// Interfaces between bodies: splitting the mesh along an edge set (duplicated nodes and
// interface cells between the copies). Used when a scene's [[interfaces]] are built and by mesh
// generators (e.g. a pile mesh); their points' states for output: output/interface_output.hpp.
//
// Conventions (see contact_law.hpp): at an interface point the tangent t follows the edges
// a -> b (body 1's counter-clockwise boundary) and the normal n = (t_y, -t_x) points out of
// body 1 into body 2. The jump is u(body 2) - u(body 1) in (t, n): slip, opening (> 0 = open).
#pragma once

#include "stratum/contact_law.hpp"
#include "stratum/mesh.hpp"
#include "stratum/model.hpp"

#include <string>
#include <vector>

namespace stratum {

/// Which interface cells split_interface() creates.
enum class InterfaceCells {
  node_pairs, ///< one CellType::node_pair cell per duplicated node (two-node contact elements)
  line,       ///< one CellType::line_interface cell per edge (2 + 2 or 3 + 3 nodes)
};

/// What split_interface() did to the mesh.
struct InterfaceSplit {
  std::vector<int> side1; ///< the interface nodes of body 1 (sorted)
  std::vector<int> side2; ///< their copies, side2[i] pairs with side1[i]
  std::vector<int> cells; ///< the interface cells appended to the mesh
};

/// Splits the mesh along `edges` (each a -> b on body 1's counter-clockwise boundary; body 1
/// keeps the original nodes). Every node of the edges is duplicated at the same place; the
/// cells `body2_cells` get the copies instead of the originals (empty: the copies belong to
/// nothing but the interface, e.g. a rigid body driven through constraints). Interface cells
/// of `kind` are appended to mesh.cells. Sets added: cell set `name` (the interface cells),
/// node sets `name.side1`, `name.side2`, edge set `name.side2` (the copied edges, reversed so
/// that they follow body 2's counter-clockwise boundary). Throws Error for an empty or
/// malformed edge set or a name already used.
InterfaceSplit split_interface(Mesh& mesh, const std::string& name, const std::vector<Edge>& edges,
                               const std::vector<int>& body2_cells, InterfaceCells kind);

} // namespace stratum
