// Mohr-Coulomb plasticity, perfectly plastic, with non-associated flow and an
// optional tension cut-off. Two forms of the yield surface:
//
//  * exact:   the hexagonal pyramid. The return is done in principal stress space
//             as a multi-surface closest-point projection onto the six Mohr-Coulomb
//             planes and the three tension cut-off planes (plane, edge and apex
//             returns), then rotated back; the consistent tangent includes the spin
//             terms of the principal directions.
//  * rounded: the Gudehus (1973) rounding of the corners, thesis (2.80)-(2.85), a
//             smooth surface except at its apex. Integrated by the shared library
//             (plasticity::integrate, integrator chosen per material); the apex is
//             a closed-form special case handled before the library is called.
//
// Header only, so the tests run exactly the plugin's code; mohr_coulomb.cpp adds
// the factory. Equations, regimes and sources: README.md in this folder.
//
// Tension positive, Voigt order and engineering shear as in stratum/voigt.hpp.
#pragma once

#include "common/material_checks.hpp"
#include "stratum/elasticity.hpp"
#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/parameters.hpp"
#include "stratum/plasticity/integrate.hpp"
#include "stratum/plasticity/invariants.hpp"
#include "stratum/plasticity/model.hpp"
#include "stratum/stress.hpp"
#include "stratum/voigt.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

namespace stratum::mohr_coulomb {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

enum class Form { exact, rounded };

/// Material constants. Angles in degrees, stresses in kPa.
struct Parameters {
  double E = 0.0;        ///< Young's modulus
  double nu = 0.3;       ///< Poisson's ratio
  double c = 0.0;        ///< cohesion (>= 0)
  double phi = 30.0;     ///< friction angle, [0, 90); 0 is Tresca (then c > 0)
  double psi = 0.0;      ///< dilatancy angle, [0, phi]
  double tension = -1.0; ///< tension cut-off on the largest principal stress; < 0: none
  Form form = Form::exact;
};

[[nodiscard]] inline double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

/// Isotropic elastic stiffness (Voigt, engineering shear).
[[nodiscard]] inline Mat6 elastic_stiffness(double E, double nu) {
  return stratum::isotropic_stiffness(E, nu);
}

/// Apex of the Mohr-Coulomb pyramid (and of the rounded cone): sigma_m = c cot(phi); +infinity
/// for phi = 0 (Tresca: a prism, no apex).
[[nodiscard]] inline double apex(const Parameters& p) {
  return p.phi == 0.0 ? std::numeric_limits<double>::infinity() : p.c / std::tan(radians(p.phi));
}

/// The tension cut-off in effect: none (a negative value) when the given value is negative or
/// not below the apex, where it could never be reached.
[[nodiscard]] inline double effective_tension(const Parameters& p) {
  return (p.tension >= 0.0 && p.tension < apex(p)) ? p.tension : -1.0;
}

/// Accumulated plastic strain increment (thesis (2.49)): sqrt(2/3 deps_p : deps_p) for an
/// engineering-shear Voigt plastic strain increment.
[[nodiscard]] inline double equivalent_plastic_strain(const Vec6& dep) {
  const double t = dep[0] * dep[0] + dep[1] * dep[1] + dep[2] * dep[2] +
                   0.5 * (dep[3] * dep[3] + dep[4] * dep[4] + dep[5] * dep[5]);
  return std::sqrt(2.0 / 3.0 * t);
}

// ------------------------------------------------------------------------------------------
// Invariants with first and second derivatives with respect to the six Voigt stress entries.

struct InvariantDerivatives {
  double J2 = 0.0, J3 = 0.0;
  Vec6 dJ2, dJ3;   ///< gradients (shear entries twice the tensor derivative)
  Mat6 d2J2, d2J3; ///< Hessians
};

/// J2 = s_ij s_ij / 2 and J3 = det s with derivatives. Written as functions of the deviator d
/// (d = M sigma, M the deviatoric projector in Voigt form) and chained through M.
[[nodiscard]] inline InvariantDerivatives invariant_derivatives(const Vec6& sigma) {
  const Vec6 d = plasticity::deviator(sigma);
  const Mat6 M = plasticity::deviatoric_projector();

  InvariantDerivatives r;
  r.J2 = 0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + d[3] * d[3] + d[4] * d[4] + d[5] * d[5];
  r.J3 = d[0] * d[1] * d[2] + 2.0 * d[3] * d[4] * d[5] - d[0] * d[4] * d[4] - d[1] * d[5] * d[5] -
         d[2] * d[3] * d[3];

  Vec6 g2;
  g2 << d[0], d[1], d[2], 2.0 * d[3], 2.0 * d[4], 2.0 * d[5];
  Vec6 h2;
  h2 << 1.0, 1.0, 1.0, 2.0, 2.0, 2.0;

  Vec6 g3;
  g3 << d[1] * d[2] - d[4] * d[4], d[0] * d[2] - d[5] * d[5], d[0] * d[1] - d[3] * d[3],
      2.0 * (d[4] * d[5] - d[2] * d[3]), 2.0 * (d[3] * d[5] - d[0] * d[4]), 2.0 * (d[3] * d[4] - d[1] * d[5]);
  Mat6 h3 = Mat6::Zero();
  auto set = [&h3](int i, int j, double v) { h3(i, j) = h3(j, i) = v; };
  set(0, 1, d[2]);
  set(0, 2, d[1]);
  set(1, 2, d[0]);
  set(0, 4, -2.0 * d[4]);
  set(1, 5, -2.0 * d[5]);
  set(2, 3, -2.0 * d[3]);
  set(3, 3, -2.0 * d[2]);
  set(4, 4, -2.0 * d[0]);
  set(5, 5, -2.0 * d[1]);
  set(3, 4, 2.0 * d[5]);
  set(3, 5, 2.0 * d[4]);
  set(4, 5, 2.0 * d[3]);

  r.dJ2 = M * g2;
  r.dJ3 = M * g3;
  r.d2J2 = M * h2.asDiagonal() * M;
  r.d2J3 = M * h3 * M;
  return r;
}

// ------------------------------------------------------------------------------------------
// Rounded form (Gudehus 1973; thesis (2.80)-(2.85)).
//
//   f = sin(phi) sigma_m + b sqrt(J2) / g(theta) - c cos(phi),   b = (3 - sin phi) / (2 sqrt 3)
//   g(theta) = 2 K / ((1 + K) - (1 - K) sin 3 theta),           K = (3 - sin phi) / (3 + sin phi)
//
// With sin 3 theta = -(3 sqrt 3 / 2) J3 / J2^(3/2) the Lode term is a polynomial in the
// invariants:  b sqrt(J2) / g = beta1 sqrt(J2) + beta2 J3 / J2,
//   beta1 = b (1 + K) / (2 K),  beta2 = b (1 - K) 3 sqrt(3) / (4 K).

/// Constants of the rounded surface for one angle (phi for the yield function, psi for the potential).
struct Rounding {
  double sin_angle = 0.0;
  double kbar = 1.0; ///< (3 - sin) / (3 + sin) = g(-30 deg)
  double b = 0.0;    ///< (3 - sin) / (2 sqrt 3)
  double beta1 = 0.0, beta2 = 0.0;
};

[[nodiscard]] inline Rounding rounding(double angle_radians) {
  Rounding r;
  const double s = std::sin(angle_radians);
  r.sin_angle = s;
  r.kbar = (3.0 - s) / (3.0 + s);
  r.b = (3.0 - s) / (2.0 * std::sqrt(3.0));
  r.beta1 = r.b * (1.0 + r.kbar) / (2.0 * r.kbar);
  r.beta2 = r.b * (1.0 - r.kbar) * 3.0 * std::sqrt(3.0) / (4.0 * r.kbar);
  return r;
}

/// Gudehus' g(theta), thesis (2.83): g(30 deg) = 1 (compression), g(-30 deg) = K (extension).
[[nodiscard]] inline double gudehus_g(double theta, double kbar) {
  return 2.0 * kbar / ((1.0 + kbar) - (1.0 - kbar) * std::sin(3.0 * theta));
}

/// The Lode-dependent deviatoric term beta1 sqrt(J2) + beta2 J3 / J2 with its gradient and
/// Hessian. At the apex (J2 = 0) the term is 0 and its derivatives are set to zero.
struct LodeTerm {
  double value = 0.0;
  Vec6 grad = Vec6::Zero();
  Mat6 hess = Mat6::Zero();
};

[[nodiscard]] inline LodeTerm lode_term(const Rounding& r, const Vec6& sigma) {
  LodeTerm t;
  const InvariantDerivatives v = invariant_derivatives(sigma);
  const double scale2 = sigma.squaredNorm();
  if (!(v.J2 > 1e-28 * scale2) || v.J2 <= 0.0) return t;
  const double sj = std::sqrt(v.J2), J2 = v.J2, J3 = v.J3;
  t.value = r.beta1 * sj + r.beta2 * J3 / J2;
  t.grad = r.beta1 * v.dJ2 / (2.0 * sj) + r.beta2 * (v.dJ3 / J2 - J3 * v.dJ2 / (J2 * J2));
  t.hess = r.beta1 * (v.d2J2 / (2.0 * sj) - v.dJ2 * v.dJ2.transpose() / (4.0 * J2 * sj)) +
           r.beta2 * (v.d2J3 / J2 - (v.dJ3 * v.dJ2.transpose() + v.dJ2 * v.dJ3.transpose()) / (J2 * J2) -
                      J3 * v.d2J2 / (J2 * J2) + 2.0 * J3 * v.dJ2 * v.dJ2.transpose() / (J2 * J2 * J2));
  return t;
}

/// The rounded Mohr-Coulomb surface as a plasticity::Model: one surface, no internal variables,
/// potential of the same form with psi in place of phi (thesis (2.86) with the Gudehus g).
class RoundedModel final : public plasticity::Model {
public:
  explicit RoundedModel(const Parameters& p)
      : D_(elastic_stiffness(p.E, p.nu)), yield_(rounding(radians(p.phi))),
        potential_(rounding(radians(p.psi))), c_cos_phi_(p.c * std::cos(radians(p.phi))), c_(p.c) {}

  [[nodiscard]] int internal_size() const override { return 0; }
  [[nodiscard]] Mat6 elastic(const Vec6&, std::span<const double>) const override { return D_; }

  [[nodiscard]] double yield(int, const Vec6& s, std::span<const double>) const override {
    return yield_.sin_angle * plasticity::mean(s) + lode_term(yield_, s).value - c_cos_phi_;
  }
  [[nodiscard]] Vec6 yield_gradient(int, const Vec6& s, std::span<const double>) const override {
    return yield_.sin_angle / 3.0 * plasticity::identity() + lode_term(yield_, s).grad;
  }
  [[nodiscard]] plasticity::VecX yield_gradient_q(int, const Vec6&, std::span<const double>) const override {
    return plasticity::VecX::Zero(0);
  }
  [[nodiscard]] Vec6 flow(int, const Vec6& s, std::span<const double>) const override {
    return potential_.sin_angle / 3.0 * plasticity::identity() + lode_term(potential_, s).grad;
  }
  [[nodiscard]] plasticity::VecX hardening(int, const Vec6&, std::span<const double>) const override {
    return plasticity::VecX::Zero(0);
  }
  [[nodiscard]] Mat6 flow_gradient(int, const Vec6& s, std::span<const double>) const override {
    return lode_term(potential_, s).hess;
  }
  [[nodiscard]] plasticity::MatX flow_gradient_q(int, const Vec6&, std::span<const double>) const override {
    return plasticity::MatX::Zero(6, 0);
  }
  [[nodiscard]] plasticity::MatX hardening_gradient(int, const Vec6&,
                                                    std::span<const double>) const override {
    return plasticity::MatX::Zero(0, 6);
  }
  [[nodiscard]] plasticity::MatX hardening_gradient_q(int, const Vec6&,
                                                      std::span<const double>) const override {
    return plasticity::MatX::Zero(0, 0);
  }
  [[nodiscard]] double stress_scale(const Vec6& s, std::span<const double>) const override {
    return std::max({c_cos_phi_,
                     yield_.sin_angle * std::abs(plasticity::mean(s)) + std::sqrt(plasticity::j2(s)),
                     1e-9 * D_(3, 3)});
  }

  /// Mean stress at the apex, c cot(phi); +infinity for phi = 0 (a cylinder, no apex).
  [[nodiscard]] double apex() const {
    if (yield_.sin_angle == 0.0) return std::numeric_limits<double>::infinity();
    return c_ * std::sqrt(1.0 - yield_.sin_angle * yield_.sin_angle) / yield_.sin_angle;
  }
  [[nodiscard]] const Rounding& yield_rounding() const { return yield_; }
  [[nodiscard]] const Rounding& potential_rounding() const { return potential_; }

private:
  Mat6 D_;
  Rounding yield_, potential_;
  double c_cos_phi_ = 0.0, c_ = 0.0;
};

/// A deviatoric principal stress state (diagonal) with sqrt(J2) = 1 and Lode angle theta
/// (tension positive, theta = +30 deg in triaxial compression).
[[nodiscard]] inline Vec6 unit_deviator(double theta) {
  const double a = 2.0 / std::sqrt(3.0), third = 2.0 * std::numbers::pi / 3.0;
  Vec6 s = Vec6::Zero();
  s[0] = a * std::sin(theta + third);
  s[1] = a * std::sin(theta);
  s[2] = a * std::sin(theta - third);
  return s;
}

/// True when the trial stress of the rounded form lies in the apex region: the return along the
/// potential would pass through the apex before reaching the surface. With isotropic elasticity
/// the return keeps the principal axes, and the deviatoric trial stress at the boundary of the
/// region is s_tr = 2 G lambda r_dev(theta*) for the Lode angle theta* whose potential normal has
/// the Lode angle of s_tr; lambda follows from |s_tr|, and the trial lies beyond the region's
/// boundary when sigma_m^tr - c cot(phi) >= K lambda sin(psi).
[[nodiscard]] inline bool rounded_apex_regime(const RoundedModel& model, double G, double K,
                                              const Vec6& trial) {
  const double pm = plasticity::mean(trial) - model.apex();
  if (pm < 0.0) return false;
  const double J2 = plasticity::j2(trial);
  if (J2 <= 1e-28 * trial.squaredNorm()) return true;
  const double target = plasticity::lode(trial);
  auto normal_lode = [&model](double theta) {
    return plasticity::lode(plasticity::deviator(model.flow(0, unit_deviator(theta), {})));
  };
  double lo = -std::numbers::pi / 6.0, hi = std::numbers::pi / 6.0;
  for (int it = 0; it < 80 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    (normal_lode(mid) < target ? lo : hi) = mid;
  }
  const Vec6 r = plasticity::deviator(model.flow(0, unit_deviator(0.5 * (lo + hi)), {}));
  const double r_norm = r.head<3>().norm(); // diagonal: tensor norm
  const double lambda = std::sqrt(2.0 * J2) / (2.0 * G * r_norm);
  return pm >= K * lambda * model.potential_rounding().sin_angle;
}

// ------------------------------------------------------------------------------------------
// Exact form: multi-surface return in principal stress space.
//
// Planes a . sigma <= k with flow direction b (principal components):
//   Mohr-Coulomb, for each ordered pair (i, j), i != j:
//     a = (1 + sin phi) e_i - (1 - sin phi) e_j,  k = 2 c cos phi,
//     b = (1 + sin psi) e_i - (1 - sin psi) e_j;
//   tension cut-off, for each i:  a = b = e_i,  k = T (T = c cot phi, the apex, when no cut-off
//   is in effect: these planes then touch the pyramid only at its apex).
// The return solves, for an active set S, sigma = sigma_tr - D_p sum_{s in S} lambda_s b_s with
// a_s . sigma = k_s, and accepts the first S (smallest first) with lambda >= 0 and all planes
// satisfied. Sets of up to three planes cover faces, edges and vertices (a vertex where four
// planes meet is reached through any three of them that are independent).

struct Plane {
  Vec3 a;
  double k = 0.0;
  Vec3 b;
};

/// Result of a return in principal space.
struct PrincipalReturn {
  Vec3 sigma = Vec3::Zero();        ///< returned principal stresses, in the order of the trial values
  Mat3 jacobian = Mat3::Identity(); ///< d sigma_i / d trial_j
  unsigned active = 0;              ///< bitmask of the active planes (0: elastic)
  bool ok = true;
};

class ExactReturn {
public:
  explicit ExactReturn(const Parameters& p) {
    const double sp = std::sin(radians(p.phi)), cp = std::cos(radians(p.phi)), sq = std::sin(radians(p.psi));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (i == j) continue;
        Plane pl;
        pl.a = (1.0 + sp) * Vec3::Unit(i) - (1.0 - sp) * Vec3::Unit(j);
        pl.k = 2.0 * p.c * cp;
        pl.b = (1.0 + sq) * Vec3::Unit(i) - (1.0 - sq) * Vec3::Unit(j);
        planes_.push_back(pl);
      }
    // Without a cut-off the three tension planes pass through the apex, where they only add
    // their normals to the apex's normal cone (a volumetric mechanism needed when psi = 0).
    // Tresca (phi = 0) without a cut-off is a prism with no apex: no tension planes at all
    // (planes at infinity would only bring infinities into the active-set solves).
    const double T = effective_tension(p) >= 0.0 ? effective_tension(p) : apex(p);
    if (std::isfinite(T))
      for (int i = 0; i < 3; ++i) planes_.push_back({Vec3::Unit(i), T, Vec3::Unit(i)});
    const double lambda = p.E * p.nu / ((1.0 + p.nu) * (1.0 - 2.0 * p.nu)), G = p.E / (2.0 * (1.0 + p.nu));
    Dp_.setConstant(lambda);
    Dp_.diagonal().array() += 2.0 * G;
    strength_ = std::max(2.0 * p.c * cp, 1e-9 * p.E);
    const int n = static_cast<int>(planes_.size());
    for (int size = 1; size <= 3; ++size)
      for (unsigned mask = 1; mask < (1u << n); ++mask)
        if (std::popcount(mask) == size) sets_.push_back(mask);
  }

  [[nodiscard]] int planes() const { return static_cast<int>(planes_.size()); }
  [[nodiscard]] const Plane& plane(int k) const { return planes_[static_cast<std::size_t>(k)]; }
  /// Principal elastic stiffness (3 x 3 normal block of the isotropic D).
  [[nodiscard]] const Mat3& stiffness() const { return Dp_; }
  /// Value of plane k at principal stresses s.
  [[nodiscard]] double yield(int k, const Vec3& s) const { return plane(k).a.dot(s) - plane(k).k; }
  /// Largest plane value.
  [[nodiscard]] double max_yield(const Vec3& s) const {
    double m = -1e300;
    for (int k = 0; k < planes(); ++k) m = std::max(m, yield(k, s));
    return m;
  }
  /// Stress scale of relative yield tolerances.
  [[nodiscard]] double scale(const Vec3& s) const { return std::max(strength_, s.cwiseAbs().maxCoeff()); }

  [[nodiscard]] PrincipalReturn operator()(const Vec3& trial) const {
    PrincipalReturn r;
    r.sigma = trial;
    const double tol = 1e-11 * scale(trial);
    if (max_yield(trial) <= tol) return r;
    for (unsigned mask : sets_) {
      int idx[3], m = 0;
      for (int k = 0; k < planes(); ++k)
        if (mask & (1u << k)) idx[m++] = k;
      // Fixed maximum sizes: no heap allocation in this loop.
      using Cols = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3>;
      using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
      using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;
      Cols A(3, m), B(3, m);
      SmallVec rhs(m);
      for (int j = 0; j < m; ++j) {
        A.col(j) = plane(idx[j]).a;
        B.col(j) = Dp_ * plane(idx[j]).b;
        rhs[j] = yield(idx[j], trial);
      }
      const Small Mx = A.transpose() * B;
      Eigen::FullPivLU<Small> lu(Mx);
      lu.setThreshold(1e-10);
      if (!lu.isInvertible()) continue;
      const SmallVec lambda = lu.solve(rhs);
      const double lam_tol = 1e-12 * lambda.cwiseAbs().maxCoeff();
      if ((lambda.array() < -lam_tol).any()) continue;
      const Vec3 s = trial - B * lambda;
      if (max_yield(s) > tol) continue;
      r.sigma = s;
      r.jacobian = Mat3::Identity() - B * lu.inverse() * A.transpose();
      r.active = mask;
      return r;
    }
    r.ok = false;
    return r;
  }

private:
  std::vector<Plane> planes_;
  std::vector<unsigned> sets_; ///< candidate active sets, smallest first
  Mat3 Dp_;
  double strength_ = 1.0;
};

/// Result of the exact return in general stress space.
struct ExactResult {
  Vec6 sigma = Vec6::Zero();
  Mat6 dsigma_dtrial = Mat6::Identity(); ///< d sigma / d sigma_trial (stress Voigt to stress Voigt)
  unsigned active = 0;
  bool ok = true;
};

/// Spectral return: principal values and directions of the trial stress, return in principal
/// space, rotation back. The derivative is that of an isotropic tensor function:
///   d sigma = sum_ij (d sigma_i / d tr_j) (n_j . d tr n_j) n_i n_i^T
///           + sum_{i<k} (sigma_i - sigma_k) / (tr_i - tr_k) (n_i . d tr n_k)(n_i n_k^T + n_k n_i^T),
/// the ratio replaced by its limit d sigma_i / d tr_i - d sigma_i / d tr_k for (nearly) equal
/// trial values.
[[nodiscard]] inline ExactResult exact_return(const ExactReturn& ret, const Vec6& trial,
                                              bool want_tangent = true) {
  ExactResult out;
  const Eigen::SelfAdjointEigenSolver<Mat3> es(stress_tensor(trial));
  const Vec3& lam = es.eigenvalues();
  const Mat3& V = es.eigenvectors();
  const PrincipalReturn pr = ret(lam);
  out.ok = pr.ok;
  out.active = pr.active;
  if (!pr.ok) {
    out.sigma = trial;
    return out;
  }
  if (pr.active == 0) {
    out.sigma = trial;
    out.dsigma_dtrial.setIdentity();
    return out;
  }
  out.sigma = stress_voigt(V * pr.sigma.asDiagonal() * V.transpose());
  // A residual-only evaluation (MaterialInput::want_tangent false) skips the spectral derivative.
  if (want_tangent)
    out.dsigma_dtrial = spectral_tangent(lam, V, pr.sigma, pr.jacobian, 1e-9 * ret.scale(lam));
  return out;
}

// ------------------------------------------------------------------------------------------
// The material.

class MohrCoulomb final : public Material {
public:
  /// The parameters must be valid (the factory checks them); settings apply to the rounded form.
  MohrCoulomb(const Parameters& p, const plasticity::Settings& settings)
      : p_(p), settings_(settings), D_(elastic_stiffness(p.E, p.nu)), S_(isotropic_compliance(p.E, p.nu)),
        rounded_(p), exact_(p), G_(p.E / (2.0 * (1.0 + p.nu))), K_(p.E / (3.0 * (1.0 - 2.0 * p.nu))) {}

  /// history[0]: accumulated plastic strain (thesis (2.49)), for output.
  [[nodiscard]] int history_size() const override { return 1; }
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"eps_bar_p", "-"}});
  }
  [[nodiscard]] bool symmetric_tangent() const override {
    // Both forms give a symmetric tangent for associated flow (the apex tangent is zero);
    // non-associated flow makes it non-symmetric.
    return p_.psi == p_.phi;
  }

  /// The regime of the committed stress, from its principal values t1 >= t2 >= t3 (tension
  /// positive), "on" a plane within 1e-6 of the stress scale max(2 c cos phi, |t1|, |t3|):
  /// 0 elastic; 1 on one Mohr-Coulomb face (Tresca: one side of the prism); 2 on an edge of two
  /// faces (t2 = t1: triaxial extension, t2 = t3: triaxial compression); 3 at the tension
  /// cut-off (t1 = T, alone or with shear); 4 at the apex (t1 = t2 = t3 on the surface: c cot
  /// phi, or T with a cut-off). The rounded form has no edges and no cut-off: 0, 1 or 4.
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> /*history*/) const override {
    const Eigen::Vector3d t = principal_tension(stress); // ascending
    const double t1 = t[2], t2 = t[1], t3 = t[0];
    const double sp = std::sin(radians(p_.phi)), cp = std::cos(radians(p_.phi));
    const double tol = 1e-6 * std::max({2.0 * p_.c * cp, std::abs(t1), std::abs(t3), 1e-9 * p_.E});
    const bool equal = t1 - t3 <= tol;
    if (p_.form == Form::rounded) {
      const double scale = rounded_.stress_scale(stress, {});
      if (rounded_.yield(0, stress, {}) < -1e-6 * scale) return 0;
      return equal ? 4 : 1;
    }
    const double T = effective_tension(p_);
    const bool tension = T >= 0.0 && t1 >= T - tol;
    const double f = (1.0 + sp) * t1 - (1.0 - sp) * t3 - 2.0 * p_.c * cp;
    if (equal && (tension || f >= -tol)) return 4;
    if (tension) return 3;
    if (f < -tol) return 0;
    return (t1 - t2 <= tol || t2 - t3 <= tol) ? 2 : 1;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"elastic", "shear (on a face)", "shear (on an edge)", "tension cut-off", "apex"};
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    if (Outcome o = material_checks::finite_input(in, "mohr_coulomb"); !o.ok()) return o;
    const Vec6 trial = in.stress_n + D_ * in.dstrain;
    if (p_.form == Form::exact) {
      const ExactResult r = exact_return(exact_, trial, in.want_tangent);
      if (!r.ok)
        return Outcome::failure(Status::material_failure,
                                "mohr_coulomb: no admissible return found in principal space" +
                                    material_checks::where(in));
      out.stress = r.sigma;
      if (in.want_tangent) out.tangent = r.dsigma_dtrial * D_;
    } else {
      const bool beyond = rounded_.yield(0, trial, {}) > 0.0 && rounded_apex_regime(rounded_, G_, K_, trial);
      if (beyond) {
        out.stress = rounded_.apex() * plasticity::identity();
        if (in.want_tangent) out.tangent.setZero();
      } else {
        const plasticity::Result r =
            plasticity::integrate(rounded_, settings_, in.stress_n, in.dstrain, out.stress, {}, out.tangent,
                                  nullptr, in.want_tangent);
        if (!r.outcome.ok())
          return Outcome::failure(r.outcome.status,
                                  "mohr_coulomb: " + r.outcome.message + material_checks::where(in));
      }
    }
    if (!out.stress.allFinite() || (in.want_tangent && !out.tangent.allFinite()))
      return Outcome::failure(Status::non_finite,
                              "mohr_coulomb: non-finite stress or tangent" + material_checks::where(in));
    const Vec6 dep = in.dstrain - S_ * (out.stress - in.stress_n);
    out.history[0] = (in.history_n.empty() ? 0.0 : in.history_n[0]) + equivalent_plastic_strain(dep);
    return Outcome::success();
  }

  [[nodiscard]] const Parameters& parameters() const { return p_; }
  [[nodiscard]] const RoundedModel& rounded_model() const { return rounded_; }
  [[nodiscard]] const ExactReturn& exact() const { return exact_; }
  [[nodiscard]] const Mat6& stiffness() const { return D_; }

private:
  Parameters p_;
  plasticity::Settings settings_;
  Mat6 D_, S_;
  RoundedModel rounded_;
  ExactReturn exact_;
  double G_ = 0.0, K_ = 0.0;
};

} // namespace stratum::mohr_coulomb
