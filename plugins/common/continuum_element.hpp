// What the small-strain continuum elements of this project (quad, tri3/tri6, hex8) do alike:
// the checks at the start of Element::compute, the constant-stiffness test and the integration
// point weights.
#pragma once

#include "stratum/element.hpp"
#include "stratum/error.hpp"

#include <Eigen/Core>

#include <string>

namespace stratum::continuum {

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
