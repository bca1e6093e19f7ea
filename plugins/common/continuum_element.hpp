// What the small-strain continuum elements of this project (quad, tri3/tri6, hex8) do alike:
// the checks at the start of Element::compute, the constant-stiffness test and the integration
// point weights.
#pragma once

#include "stratum/element.hpp"
#include "stratum/error.hpp"

#include <Eigen/Core>

#include <cmath>
#include <string>

namespace stratum::continuum {

/// What a material learns of point `point` of `cell`: the indices, the load step
/// (ElementData::clock), the point's coordinates x (2 or 3 entries) and the cell's characteristic
/// length: sqrt(area) of a two-dimensional cell (the area in the plane, also in axisymmetry),
/// cbrt(volume) of a three-dimensional one; `size` is that area or volume (0 when unknown).
template <class Coordinates>
[[nodiscard]] PointContext point_context(const ElementData& cell, int point, const Coordinates& x,
                                         double size) {
  PointContext c{cell.id, point, cell.clock, {}, 0.0};
  for (Eigen::Index k = 0; k < x.size() && k < 3; ++k) c.x[static_cast<std::size_t>(k)] = x(k);
  if (size > 0.0) c.length = x.size() >= 3 ? std::cbrt(size) : std::sqrt(size);
  return c;
}

/// Throws stratum::Error unless u and u_n hold the two displacement components of each of the
/// cell's n nodes; `cell_kind` names the cell in the message ("quadrilateral", "triangle").
inline void require_plane_displacements(const ElementData& cell, const Eigen::VectorXd& u,
                                        const Eigen::VectorXd& u_n, int n, const std::string& cell_kind) {
  if (u.size() != 2 * n || u_n.size() != 2 * n)
    throw Error("element " + std::to_string(cell.id) + ": displacement vector of size " +
                std::to_string(u.size()) + " for a " + std::to_string(n) + "-node " + cell_kind);
}

/// The failure of a continuum element `element` given no Material.
[[nodiscard]] inline Outcome no_material(const ElementData& cell, const std::string& element) {
  return Outcome::failure(Status::material_failure, "element " + std::to_string(cell.id) + ": the " +
                                                        element +
                                                        " element needs a Material (none was given)");
}

/// The end of Element::compute: the element's force and, when asked for, its stiffness, go to out.
template <class Force, class Stiffness>
[[nodiscard]] Outcome deliver(ElementResult& out, const Force& f, const Stiffness& K, bool want_tangent) {
  out.force = f;
  if (want_tangent) out.stiffness = K;
  return Outcome::success();
}

/// Small-strain element: with a linear material its stiffness is the cell's constant B^T D B.
[[nodiscard]] inline bool constant_stiffness(const Constitutive& law) {
  return law.material != nullptr && law.material->is_linear();
}

/// The point volumes dV_i in w become weights dV_i / sum dV; equal weights for a degenerate cell
/// whose volume is not positive (or not finite).
inline void normalize_weights(Eigen::VectorXd& w) {
  const double total = w.sum();
  if (total > 0.0 && w.allFinite())
    w /= total;
  else
    w.setConstant(1.0 / static_cast<double>(w.size()));
}

} // namespace stratum::continuum
