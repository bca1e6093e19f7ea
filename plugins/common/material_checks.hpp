// What the material models of this project (drucker_prager, hardening_soil, lade, mohr_coulomb)
// check and say alike in Material::update: where the point is, for the end of a failure
// message, and the test of the input for NaN and Inf.
#pragma once

#include "stratum/error.hpp"
#include "stratum/material.hpp"

#include <string>

namespace stratum::material_checks {

/// " at element E, point P": the point being updated, for the end of a failure message.
[[nodiscard]] inline std::string where(const MaterialInput& in) {
  return " at element " + std::to_string(in.where.element) + ", point " + std::to_string(in.where.point);
}

/// A non_finite failure of `model` when the strain increment or the stress at the start of the
/// update is not finite; success otherwise.
[[nodiscard]] inline Outcome finite_input(const MaterialInput& in, const std::string& model) {
  if (!in.dstrain.allFinite() || !in.stress_n.allFinite())
    return Outcome::failure(Status::non_finite,
                            model + ": non-finite strain increment or stress" + where(in));
  return Outcome::success();
}

} // namespace stratum::material_checks
