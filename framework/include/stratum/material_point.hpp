// Toolkit for element authors: the update of one material point of a continuum element.
//
// A continuum element computes the strain increment of each integration point from its
// displacement change (B (u - u_n)) and hands it to its Material. What happens then is the same
// in every such element (the framework's quad and tri use this): the material reads the
// committed state of the point, writes its trial stress, history and tangent, and the element
// keeps the trial strain as the committed strain plus the increment, so a stage that resets the
// displacements keeps the strains. A non-finite result is a failure of the step (Status::
// non_finite, naming the element and point), never a number that reaches the assembly.
#pragma once

#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/state_store.hpp"
#include "stratum/voigt.hpp"

#include <cstddef>
#include <string>

namespace stratum {

/// Updates point `p` of `states` for the strain increment `dstrain` (engineering shear):
/// Material::update on the committed stress, strain and history, into `stress` and `tangent`
/// (the tangent only when `want_tangent`) and the trial slot's history; then the trial strain
/// and stress are set. Returns the material's Outcome, or Status::non_finite when the stress
/// (or a requested tangent) holds NaN or Inf.
[[nodiscard]] inline Outcome update_material_point(const Material& material, StateStore& states,
                                                   std::size_t p, const Vec6& dstrain, PointContext where,
                                                   bool want_tangent, Vec6& stress, Mat6& tangent) {
  const auto committed = states.committed(p);
  const auto trial = states.trial(p);
  const Vec6 strain_n = committed.strain();
  const Vec6 stress_n = committed.stress();
  const MaterialInput in{stress_n, strain_n, committed.history(), dstrain, where, want_tangent};
  MaterialOutput out{stress, trial.history(), tangent};
  Outcome r = material.update(in, out);
  if (!r.ok()) return r;
  if (!stress.allFinite() || (want_tangent && !tangent.allFinite()))
    return Outcome::failure(
        Status::non_finite,
        "element " + std::to_string(where.element) +
            ": the material returned a non-finite stress or tangent at integration point " +
            std::to_string(where.point));
  trial.strain() = strain_n + dstrain;
  trial.stress() = stress;
  return r;
}

} // namespace stratum
