// The Element interface: one kind of finite element (continuum or interface).
//
// An Element object is a const "kind" (parameters: formulation, integration,
// ...) applied to every cell of its domain. For one cell it computes the
// internal force vector and the tangent from the cell's coordinates, its trial
// and committed displacements and the states of its integration points, calling
// the Material (or ContactLaw) at each point. It never writes files and never
// sees stages or TOML.
//
// Local DOF order: node by node in slot order, and within a node the fields it carries in the
// order the element declares them (node_fields; stratum/fields.hpp); for the default, the
// displacement components, x then y (axisymmetric r then z) (then z in 3D). Units: m, kN, kPa.
#pragma once

#include "stratum/cell_type.hpp"
#include "stratum/contact_law.hpp"
#include "stratum/error.hpp"
#include "stratum/fields.hpp"
#include "stratum/material.hpp"
#include "stratum/state_store.hpp"

#include <Eigen/Core>

namespace stratum {

/// How a continuum element maps its cell: plane strain and axisymmetry (x = r, y = z) on
/// two-dimensional cells, three_d on three-dimensional ones.
enum class Formulation { plane_strain, axisymmetric, three_d };

/// The geometry of one cell as an element sees it.
///
/// `type` and `shape` say what the cell is (stratum/cell_type.hpp: the type's slot numbering and
/// the bitmask of the present slots); rows of `x` are the present nodes in slot order, columns
/// their coordinates (2 in a plane or axisymmetric model, 3 in a three-dimensional one). A 4-node
/// quadrilateral has shape 0x0F and 4 rows, an 8-node one 0xFF and 8 rows; a triangle leaves
/// slots 3 and 7 empty (shape 0x07 or 0x77); a hexahedron has shape 0xFF and 8 rows of 3.
struct ElementData {
  int id = -1;                        ///< global cell index (for messages)
  unsigned shape = 0;                 ///< present node slots
  const Eigen::MatrixXd* x = nullptr; ///< coordinates of the present nodes, n x dim
  CellType type = CellType::quadrilateral;
  /// The load step being evaluated (stratum/material.hpp); an element copies it into the
  /// PointContext of every point it hands to its material, with the point's coordinates and
  /// the cell's characteristic length.
  StepClock clock{};
};

/// The constitutive law of the element's domain: exactly one is set.
struct Constitutive {
  const Material* material = nullptr;
  const ContactLaw* contact = nullptr;
};

struct ElementResult {
  Eigen::VectorXd
      force; ///< internal force (kN for a displacement; axisymmetric: the full circle), local order
  Eigen::MatrixXd stiffness; ///< tangent d force / d u in the local order (only when requested)
};

/// The cells an element is made for: the area cells of a [[domains]] entry, or the cells an
/// [[interfaces]] entry creates when it splits the mesh along an edge set.
enum class ElementCells {
  area,           ///< quads, triangles, thin layers: cells of the mesh, given in [[domains]]
  node_pairs,     ///< one cell per pair of coincident nodes (two-node contact elements)
  interface_lines ///< one cell per pair of coincident edges (2 + 2 or 3 + 3 nodes)
};

class Element {
public:
  virtual ~Element() = default;

  /// The cells the element works on; the scene reader creates interface cells of this kind for an
  /// [[interfaces]] entry, and refuses an interface element in [[domains]] and the other way round.
  [[nodiscard]] virtual ElementCells cells() const { return ElementCells::area; }

  /// True when the element works on cells of this type. The default: the two-dimensional
  /// continuum types (quadrilateral, triangle) for an area element, node pairs and interface
  /// lines for the interface kinds. The scene reader refuses a domain cell of another type.
  [[nodiscard]] virtual bool accepts(CellType type) const {
    switch (cells()) {
    case ElementCells::node_pairs:
      return type == CellType::node_pair;
    case ElementCells::interface_lines:
      return type == CellType::line_interface;
    case ElementCells::area:
      break;
    }
    return type == CellType::quadrilateral || type == CellType::triangle;
  }

  /// True when the element's domain must name a material (a [[domains]] `material`): the
  /// default for area elements. An element that needs none (e.g. one of a scalar field that
  /// carries its own conductivity) returns false; its domain then names none, and compute()
  /// gets a placeholder material that it must not call.
  [[nodiscard]] virtual bool needs_material() const { return true; }

  /// The unknowns the nodes of a cell of this type and shape carry (stratum/fields.hpp), which
  /// also fixes the local order of u, force and stiffness. The default: the displacement
  /// components of the cell's dimension at every node.
  [[nodiscard]] virtual NodeFields node_fields(CellType type, unsigned /*shape*/) const {
    return NodeFields{displacement_fields(cell_dimension(type)), {}};
  }

  /// Number of integration points (each with a StateStore slot) of a cell of this shape.
  [[nodiscard]] virtual int num_points(unsigned shape) const = 0;

  /// Throws stratum::Error when a cell of this shape cannot be handled by this element.
  virtual void check_shape(unsigned shape) const = 0;

  /// Throws stratum::Error when the geometry of a cell is unsuitable (called once per cell
  /// before the run, after check_shape); the default accepts every cell.
  virtual void check_geometry(const ElementData& /*cell*/) const {}

  /// Internal force and (when want_tangent) tangent at the trial displacement u.
  /// u and u_n are the total trial and committed values of the cell's unknowns (local order).
  /// Reads states.committed(first_point + i), writes states.trial(first_point + i).
  [[nodiscard]] virtual Outcome compute(const ElementData& cell, const Eigen::VectorXd& u,
                                        const Eigen::VectorXd& u_n, const Constitutive& law,
                                        StateStore& states, std::size_t first_point, bool want_tangent,
                                        ElementResult& out) const = 0;

  /// Consistent nodal forces of a body force b (kN/m3, one component per dimension, e.g.
  /// (0, -gamma)), in the local order (zero at unknowns that are not displacements).
  virtual void body_force(const ElementData& cell, const Eigen::VectorXd& b, Eigen::VectorXd& f) const = 0;

  /// Coordinates of the integration points, num_points x dim (for point-cloud output).
  virtual void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const = 0;

  /// Weight of each integration point in a cell average (for cell output), sums to 1.
  virtual void point_weights(const ElementData& cell, Eigen::VectorXd& w) const = 0;

  /// The values of the cell's field `field` (an index into node_fields(...).fields) at its
  /// integration points in point order, interpolated from the cell's unknowns u (local order);
  /// false, with `values` untouched, when the element does not interpolate that field (the
  /// default). The writers and recorders read a pore pressure at the points so.
  [[nodiscard]] virtual bool point_field(const ElementData& /*cell*/, const Eigen::VectorXd& /*u*/,
                                         int /*field*/, Eigen::VectorXd& /*values*/) const {
    return false;
  }

  /// True when, with this law, the tangent of compute() depends on the cell's geometry only
  /// (small strain and a linear material): the assembler then computes it once per stage and
  /// asks compute() for the force and the point states alone. The default (false) is always safe.
  [[nodiscard]] virtual bool constant_stiffness(const Constitutive& /*law*/) const { return false; }
};

} // namespace stratum
