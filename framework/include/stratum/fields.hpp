// Fields: the unknowns a node carries, by name.
//
// An element declares the fields of its nodes (Element::node_fields): the displacement
// components of its dimension ("ux", "uy", and "uz" in 3D), and scalar fields such as the pore
// pressure "p", possibly on a subset of its nodes (the corners of a Taylor-Hood cell). The model
// numbers its unknowns from these declarations (DofMap in stratum/model.hpp): node by node, and
// within a node in the model's field order (the displacement components first), so a model of
// two-dimensional displacement elements keeps the numbering "2 per node, x then y".
//
// Local order of an element's vectors (force, stiffness rows, u): node by node in slot order,
// and within a node the fields it carries in the element's declared order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stratum/cell_type.hpp"

namespace stratum {

/// One unknown of a node. Units are the framework's (kN, m, kPa, s); a scene's [units] relabel them.
struct Field {
  std::string name;          ///< "ux", "uy", "uz", "p", ...: how constraints, loads, recorders name it
  std::string unit;          ///< unit of the unknown: "m" for a displacement, "kPa" for a pressure
  std::string reaction_unit; ///< unit of its conjugate in the residual: "kN" for a force, "m3/s" for a flow
  friend bool operator==(const Field&, const Field&) = default;
};

/// The ids of the displacement components in every model (DofMap: they are its first fields).
inline constexpr int field_ux = 0, field_uy = 1, field_uz = 2;

/// The displacement components of a space of this dimension (2: ux, uy; 3: ux, uy, uz).
[[nodiscard]] inline std::vector<Field> displacement_fields(int dim) {
  std::vector<Field> f{{"ux", "m", "kN"}, {"uy", "m", "kN"}};
  if (dim == 3) f.push_back({"uz", "m", "kN"});
  return f;
}

/// What the nodes of one cell carry, as an element declares it.
struct NodeFields {
  std::vector<Field> fields; ///< the element's fields, in its local order within a node
  /// Per present node (slot order): bit f set when the node carries fields[f]. Empty: every
  /// node carries every field.
  std::vector<std::uint32_t> carried;

  /// Bitmask of the fields node `i` (0-based among the present nodes) carries.
  [[nodiscard]] std::uint32_t at(std::size_t i) const {
    return carried.empty() ? (fields.size() >= 32 ? ~0u : (1u << fields.size()) - 1u) : carried[i];
  }
};

} // namespace stratum
