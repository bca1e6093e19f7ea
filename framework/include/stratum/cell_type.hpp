// What a cell is geometrically: its type, its dimension and its node slots.
//
// A cell is a list of node slots of its type (-1 for an absent slot) and the type itself; the
// slot numbering is the type's own:
//  * quadrilateral: slots 0-3 the corners counter-clockwise, 4 the midside node of edge 0-1,
//    5 of 1-2, 6 of 2-3, 7 of 3-0; any midside node may be absent (5- to 7-node transition cells);
//  * triangle: corners 0 1 2 counter-clockwise, midside 4 (edge 0-1), 5 (1-2), 6 (2-0); slots 3
//    and 7 are empty (the quadrilateral family's numbering, which the triangles were written in);
//  * hexahedron: slots 0-3 the bottom face (zeta = -1) counter-clockwise seen from above (+zeta),
//    4-7 the top face above them (VTK_HEXAHEDRON's order);
//  * tetrahedron: corners 0-3, with (x1 - x0) x (x2 - x0) . (x3 - x0) > 0 (VTK_TETRA's order);
//  * wedge: 0-2 the bottom triangle, 3-5 the top triangle above them (VTK_WEDGE's order);
//  * node_pair: a two-node contact cell (framework/src/model/body_interfaces.hpp): slot 0 the node of body 1,
//    slot 1 its coincident partner of body 2, slots 2 and 3 the body-1 nodes before and after slot 0
//    along the interface, for the direction and tributary length;
//  * line_interface: a zero-thickness quadrilateral: slots 0, 1 (and midside 4) on body 1, slots 2,
//    3 (and midside 6) on body 2, slot 3 coincident with 0, 2 with 1, 6 with 4.
// A cell's `shape` is the bitmask of its present slots; an element sees the type, the mask and
// the coordinates of the present nodes in slot order.
#pragma once

#include "stratum/enum_names.hpp"

#include <array>
#include <cstdint>

namespace stratum {

enum class CellType : std::uint8_t {
  quadrilateral = 0,
  triangle = 1,
  node_pair = 2,
  line_interface = 3,
  hexahedron = 4,
  tetrahedron = 5,
  wedge = 6,
};

/// Most node slots a cell of any type has (a cell stores this many, -1 for an absent slot).
inline constexpr int max_cell_slots = 8;

/// The dimension of the space a cell of this type lives in: 2 (plane or axisymmetric) or 3.
[[nodiscard]] constexpr int cell_dimension(CellType t) {
  return t == CellType::hexahedron || t == CellType::tetrahedron || t == CellType::wedge ? 3 : 2;
}

/// True for the cells of a continuum (quadrilaterals, triangles, hexahedra, tetrahedra, wedges).
[[nodiscard]] constexpr bool is_solid(CellType t) {
  return t != CellType::node_pair && t != CellType::line_interface;
}

/// The slots of the corners of a full cell of this type (the nodes a linear field lives on).
[[nodiscard]] constexpr unsigned corner_slots(CellType t) {
  switch (t) {
  case CellType::quadrilateral:
    return 0x0Fu;
  case CellType::triangle:
    return 0x07u;
  case CellType::hexahedron:
    return 0xFFu;
  case CellType::tetrahedron:
    return 0x0Fu;
  case CellType::wedge:
    return 0x3Fu;
  case CellType::node_pair:
    return 0x03u;
  case CellType::line_interface:
    return 0x0Fu;
  }
  return 0u;
}

/// The name of the type, for messages and `stratum describe`.
[[nodiscard]] constexpr const char* to_string(CellType t) {
  constexpr std::array<const char*, 7> names{"quadrilateral", "triangle",    "node_pair", "line_interface",
                                             "hexahedron",    "tetrahedron", "wedge"};
  return enum_name(t, names);
}

} // namespace stratum
