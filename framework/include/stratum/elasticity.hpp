// Isotropic linear elasticity, shared by the material plugins (header only).
//
// Voigt order xx, yy, zz, xy, yz, zx with engineering shear strains (voigt.hpp).
#pragma once

#include "stratum/params.hpp"
#include "stratum/voigt.hpp"

namespace stratum {

/// Bulk modulus K = E / (3 (1 - 2 nu)).
[[nodiscard]] inline double bulk_modulus(double E, double nu) { return E / (3.0 * (1.0 - 2.0 * nu)); }
/// Shear modulus G = E / (2 (1 + nu)).
[[nodiscard]] inline double shear_modulus(double E, double nu) { return E / (2.0 * (1.0 + nu)); }

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

/// Isotropic stiffness from the bulk modulus K and the shear modulus G (kPa): K - 2G/3 off the
/// diagonal of the normal block, K + 4G/3 on it, G for the (engineering) shear entries.
[[nodiscard]] inline Mat6 stiffness_kg(double K, double G) {
  Mat6 D = Mat6::Zero();
  D.topLeftCorner<3, 3>().setConstant(K - 2.0 * G / 3.0);
  for (int i = 0; i < 3; ++i) D(i, i) = K + 4.0 * G / 3.0;
  for (int i = 3; i < 6; ++i) D(i, i) = G;
  return D;
}

/// Isotropic compliance, the inverse of isotropic_stiffness(E, nu).
[[nodiscard]] inline Mat6 isotropic_compliance(double E, double nu) {
  Mat6 S = Mat6::Zero();
  S.topLeftCorner<3, 3>().setConstant(-nu / E);
  for (int i = 0; i < 3; ++i) S(i, i) = 1.0 / E;
  for (int i = 3; i < 6; ++i) S(i, i) = 2.0 * (1.0 + nu) / E;
  return S;
}

/// Declares E (kPa, > 0, required) and nu ((-1, 0.5), default 0.3) in a material's schema.
inline void add_isotropic_elastic_parameters(Schema& s) {
  s.real("E", "kPa", "Young's modulus").greater_than(0.0);
  s.real("nu", "-", "Poisson's ratio").greater_than(-1.0).less_than(0.5).defaults_to(0.3);
}

} // namespace stratum
