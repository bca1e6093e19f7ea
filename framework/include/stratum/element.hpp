// The Element interface: one kind of finite element (continuum or interface).
//
// An Element object is a const "kind" (parameters: formulation, integration,
// ...) applied to every cell of its domain. For one cell it computes the
// internal force vector and the tangent from the cell's coordinates, its trial
// and committed displacements and the states of its integration points, calling
// the Material (or ContactLaw) at each point. It never writes files and never
// sees stages or TOML.
//
// Local DOF order: 2 per present node (x then y; axisymmetric r then z), nodes
// in slot order (see ElementData). Units: m, kN, kPa.
#pragma once

#include "stratum/contact_law.hpp"
#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/state_store.hpp"

#include <Eigen/Core>

namespace stratum {

enum class Formulation { plane_strain, axisymmetric };

/// The geometry of one cell as an element sees it.
///
/// `shape` is a bitmask of the node slots that are present. Quadrilateral
/// family (thesis numbering): slots 0-3 are the corners counter-clockwise,
/// slot 4 the midside node of edge 0-1, 5 of 1-2, 6 of 2-3, 7 of 3-0.
/// Rows of `x` are the present nodes in slot order (corners first), so a
/// 4-node quad has shape 0x0F and 4 rows, an 8-node quad 0xFF and 8 rows.
/// A triangle leaves slots 3 and 7 empty: corners 0-2, midside 4 (edge 0-1),
/// 5 (1-2), 6 (2-0); shape 0x07 (3 nodes) or 0x77 (6 nodes).
struct ElementData {
  int id = -1;               ///< global cell index (for messages)
  unsigned shape = 0;        ///< present node slots
  const Eigen::MatrixX2d* x; ///< coordinates of the present nodes, n x 2
};

/// The constitutive law of the element's domain: exactly one is set.
struct Constitutive {
  const Material* material = nullptr;
  const ContactLaw* contact = nullptr;
};

struct ElementResult {
  Eigen::VectorXd force;     ///< internal force, 2n (kN; per radian x 2 pi in axisymmetry: see quad README)
  Eigen::MatrixXd stiffness; ///< tangent d force / d u, 2n x 2n (only when requested)
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

  /// Number of integration points (each with a StateStore slot) of a cell of this shape.
  [[nodiscard]] virtual int num_points(unsigned shape) const = 0;

  /// Throws stratum::Error when a cell of this shape cannot be handled by this element.
  virtual void check_shape(unsigned shape) const = 0;

  /// Throws stratum::Error when the geometry of a cell is unsuitable (called once per cell
  /// before the run, after check_shape); the default accepts every cell.
  virtual void check_geometry(const ElementData& /*cell*/) const {}

  /// Internal force and (when want_tangent) tangent at the trial displacement u.
  /// u and u_n are the total trial and committed displacements of the cell's DOFs.
  /// Reads states.committed(first_point + i), writes states.trial(first_point + i).
  [[nodiscard]] virtual Outcome compute(const ElementData& cell, const Eigen::VectorXd& u,
                                        const Eigen::VectorXd& u_n, const Constitutive& law,
                                        StateStore& states, std::size_t first_point, bool want_tangent,
                                        ElementResult& out) const = 0;

  /// Consistent nodal forces of a body force b (kN/m3, e.g. (0, -gamma)).
  virtual void body_force(const ElementData& cell, const Vec2& b, Eigen::VectorXd& f) const = 0;

  /// Coordinates of the integration points, num_points x 2 (for point-cloud output).
  virtual void point_coordinates(const ElementData& cell, Eigen::MatrixX2d& xp) const = 0;

  /// Weight of each integration point in a cell average (for cell output), sums to 1.
  virtual void point_weights(const ElementData& cell, Eigen::VectorXd& w) const = 0;

  /// True when, with this law, the tangent of compute() depends on the cell's geometry only
  /// (small strain and a linear material): the assembler then computes it once per stage and
  /// asks compute() for the force and the point states alone. The default (false) is always safe.
  [[nodiscard]] virtual bool constant_stiffness(const Constitutive& /*law*/) const { return false; }
};

} // namespace stratum
