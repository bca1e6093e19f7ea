// Stress tensors and principal stresses, shared by the material plugins (header only).
//
// Framework stresses are tension positive, Voigt xx, yy, zz, xy, yz, zx (voigt.hpp); soil
// models often think in compression-positive principal stresses s1 >= s2 >= s3. Both orderings
// are here so that a plugin states which one it uses instead of negating by hand.
#pragma once

#include "stratum/voigt.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <utility>

namespace stratum {

/// Symmetric 3 x 3 tensor of a stress-like Voigt vector (shear entries are tensor components).
[[nodiscard]] inline Eigen::Matrix3d stress_tensor(const Vec6& s) {
  Eigen::Matrix3d t;
  t << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return t;
}
/// Symmetric 3 x 3 tensor of a strain-like Voigt vector (engineering shear halved).
[[nodiscard]] inline Eigen::Matrix3d strain_tensor(const Vec6& e) {
  Eigen::Matrix3d t;
  t << e[0], 0.5 * e[3], 0.5 * e[5], 0.5 * e[3], e[1], 0.5 * e[4], 0.5 * e[5], 0.5 * e[4], e[2];
  return t;
}
/// Stress-like Voigt vector of a symmetric tensor.
[[nodiscard]] inline Vec6 stress_voigt(const Eigen::Matrix3d& t) {
  Vec6 s;
  s << t(0, 0), t(1, 1), t(2, 2), t(0, 1), t(1, 2), t(0, 2);
  return s;
}

/// True for a 2D state (plane strain, axisymmetry): s_yz = s_zx = 0, so s_zz is principal.
[[nodiscard]] inline bool is_2d(const Vec6& s) { return s[4] == 0.0 && s[5] == 0.0; }

/// The in-plane principal pair of a 2D state: mean m, half-difference h of s_xx and s_yy,
/// Mohr radius r (principal values m - r, m + r). Closed form, exact to round-off.
struct InPlane {
  double m = 0, h = 0, r = 0;
};
[[nodiscard]] inline InPlane in_plane(const Vec6& s) {
  const double h = 0.5 * (s[0] - s[1]);
  return {0.5 * (s[0] + s[1]), h, std::hypot(h, s[3])};
}

/// Principal values of a tension-positive stress, tension positive and ascending: v[0] <= v[1] <=
/// v[2] (v[0] is the major compression). Closed form for 2D states, eigen-solver otherwise.
[[nodiscard]] inline Eigen::Vector3d principal_tension(const Vec6& sigma) {
  if (is_2d(sigma)) {
    const auto [m, h, r] = in_plane(sigma);
    double a = m - r, b = m + r, c = sigma[2];
    if (c < a) std::swap(a, c);
    if (c < b) std::swap(b, c);
    if (b < a) std::swap(a, b);
    return {a, b, c};
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(stress_tensor(sigma), Eigen::EigenvaluesOnly);
  return es.eigenvalues();
}

/// Compression-positive principal stresses s1 >= s2 >= s3 (soil mechanics' sigma_1, sigma_3).
struct Principal {
  double s1 = 0, s2 = 0, s3 = 0;
};
/// The compression-positive principal stresses of a tension-positive stress.
[[nodiscard]] inline Principal principal_compression(const Vec6& sigma) {
  const Eigen::Vector3d v = principal_tension(sigma);
  return {-v[0], -v[1], -v[2]};
}

/// d sigma / d sigma_trial of an isotropic stress function sigma = V diag(sig) V^T of a trial
/// stress with principal values lam and eigenvectors V (columns), from the principal Jacobian
/// jac = d sig / d lam (the spin terms of the principal directions included). Principal values
/// closer than `tie` count as equal (then the limit jac(i, i) - jac(i, k) is used).
[[nodiscard]] inline Mat6 spectral_tangent(const Eigen::Vector3d& lam, const Eigen::Matrix3d& V,
                                           const Eigen::Vector3d& sig, const Eigen::Matrix3d& jac,
                                           double tie) {
  using Mat3 = Eigen::Matrix3d;
  Mat6 out;
  Mat3 coef = Mat3::Zero();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      if (i == k) continue;
      const double d = lam[i] - lam[k];
      coef(i, k) = std::abs(d) > tie ? (sig[i] - sig[k]) / d : jac(i, i) - jac(i, k);
    }
  for (int j = 0; j < 6; ++j) {
    Mat3 E = Mat3::Zero();
    if (j < 3) {
      E(j, j) = 1.0;
    } else {
      const int a = j == 3 ? 0 : (j == 4 ? 1 : 2), b = j == 3 ? 1 : (j == 4 ? 2 : 0);
      E(a, b) = E(b, a) = 1.0;
    }
    const Mat3 W = V.transpose() * E * V; // components in the principal frame
    const Eigen::Vector3d dsp = jac * W.diagonal();
    Mat3 dS = dsp.asDiagonal();
    for (int i = 0; i < 3; ++i)
      for (int k = i + 1; k < 3; ++k) dS(i, k) = dS(k, i) = 0.5 * (coef(i, k) + coef(k, i)) * W(i, k);
    out.col(j) = stress_voigt(V * dS * V.transpose());
  }
  return out;
}

} // namespace stratum
