// Stress invariants shared by the soil models (header only).
//
// Framework stresses are tension positive. Soil mechanics' p and q are
// compression positive: p = -tr(sigma)/3, q = sqrt(3 J2). Lode angle theta in
// [-30, 30] degrees with theta = +30 in triaxial compression (tension-positive
// sigma, thesis (2.79d) with the factor 2 restored).
#pragma once

#include "stratum/voigt.hpp"

#include <algorithm>
#include <cmath>

namespace stratum::plasticity {

/// Mean stress, tension positive: (s_xx + s_yy + s_zz) / 3.
inline double mean(const Vec6& s) { return (s[0] + s[1] + s[2]) / 3.0; }

/// Deviator in Voigt form (shear entries are tensor components, as in stress).
inline Vec6 deviator(const Vec6& s) {
  Vec6 d = s;
  const double m = mean(s);
  d[0] -= m, d[1] -= m, d[2] -= m;
  return d;
}

/// J2 = s_ij s_ij / 2 for a stress-like Voigt vector.
inline double j2(const Vec6& s) {
  const Vec6 d = deviator(s);
  return 0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + d[3] * d[3] + d[4] * d[4] + d[5] * d[5];
}

/// J3 = det(deviator).
inline double j3(const Vec6& s) {
  const Vec6 d = deviator(s);
  return d[0] * d[1] * d[2] + 2 * d[3] * d[4] * d[5] - d[0] * d[4] * d[4] - d[1] * d[5] * d[5] -
         d[2] * d[3] * d[3];
}

/// Soil-mechanics mean pressure, compression positive.
inline double p_comp(const Vec6& s) { return -mean(s); }
/// Von Mises equivalent stress q = sqrt(3 J2).
inline double q_mises(const Vec6& s) { return std::sqrt(3.0 * j2(s)); }

/// Lode angle in radians, in [-pi/6, pi/6]; +pi/6 in triaxial compression (tension positive).
inline double lode(const Vec6& s) {
  const double J2 = j2(s);
  if (J2 <= 1e-30) return 0.0;
  const double x = std::clamp(-1.5 * std::sqrt(3.0) * j3(s) / std::pow(J2, 1.5), -1.0, 1.0);
  return std::asin(x) / 3.0;
}

/// Voigt identity (1, 1, 1, 0, 0, 0).
inline Vec6 identity() {
  Vec6 i;
  i << 1, 1, 1, 0, 0, 0;
  return i;
}

/// Converts a stress-like gradient (tensor shear components) to the strain-like
/// Voigt form used for flow directions: shear entries doubled.
inline Vec6 to_strain_like(Vec6 v) {
  v[3] *= 2, v[4] *= 2, v[5] *= 2;
  return v;
}

/// The deviatoric projector on stress-like Voigt vectors: deviator(s) = deviatoric_projector() s
/// (I - (1/3) 1 1^T on the normal block, identity on the shear entries).
inline Mat6 deviatoric_projector() {
  Mat6 M = Mat6::Identity();
  M.topLeftCorner<3, 3>().array() -= 1.0 / 3.0;
  return M;
}

/// d shat / d sigma with shat = to_strain_like(deviator(sigma)) = d J2 / d sigma: the projector
/// with the shear rows doubled, i.e. the Hessian d2 J2 / d sigma2 in the Voigt gradient
/// convention of model.hpp (symmetric).
inline Mat6 deviatoric_projector_strain_like() {
  Mat6 P = Mat6::Zero();
  P.topLeftCorner<3, 3>().setConstant(-1.0 / 3.0);
  for (int i = 0; i < 3; ++i) P(i, i) += 1.0;
  for (int i = 3; i < 6; ++i) P(i, i) = 2.0;
  return P;
}

} // namespace stratum::plasticity
