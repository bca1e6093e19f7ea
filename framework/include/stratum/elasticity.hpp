// Isotropic linear elasticity, shared by the material plugins (header only).
#pragma once

#include "stratum/params.hpp"
#include "stratum/voigt.hpp"

namespace stratum {

/// Isotropic stiffness in Voigt form with engineering shear strains:
/// lambda = E nu / ((1 + nu)(1 - 2 nu)), G = E / (2 (1 + nu)). E in kPa.
[[nodiscard]] inline Mat6 isotropic_stiffness(double E, double nu) {
  const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  const double G = E / (2.0 * (1.0 + nu));
  Mat6 D = Mat6::Zero();
  D.topLeftCorner<3, 3>().setConstant(lambda);
  for (int i = 0; i < 3; ++i) D(i, i) += 2.0 * G;
  for (int i = 3; i < 6; ++i) D(i, i) = G;
  return D;
}

/// Declares E (kPa, > 0, required) and nu ((-1, 0.5), default 0.3) in a material's schema.
inline void add_isotropic_elastic_parameters(Schema& s) {
  s.real("E", "kPa", "Young's modulus").greater_than(0.0);
  s.real("nu", "-", "Poisson's ratio").greater_than(-1.0).less_than(0.5).defaults_to(0.3);
}

} // namespace stratum
