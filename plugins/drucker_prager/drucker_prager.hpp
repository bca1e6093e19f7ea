// Drucker-Prager plasticity with linear cohesion hardening and non-associated flow.
//
//   f = alpha I1 + sqrt(J2) - K,   K = k (c + H_c eps_bar_p)     (thesis (2.88), tension positive)
//   g = alpha_psi I1 + sqrt(J2)                                   (plastic potential)
//
// alpha and k come from one of four matchings to Mohr-Coulomb (cone_constants). The smooth
// cone is integrated by the shared library (plasticity::integrate, integrator chosen per
// material); the apex, where the gradient of sqrt(J2) does not exist, is a closed-form special
// case detected from the trial stress before the library is called (apex_regime, apex_return).
//
// Header only, so the tests run exactly the plugin's code; drucker_prager.cpp adds the factory.
// Equations, derivations and sources: README.md in this folder.
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
#include "stratum/voigt.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <string>

namespace stratum::drucker_prager {

/// Which Mohr-Coulomb corners the cone passes through.
enum class Cone {
  compression,  ///< outer cone, through the triaxial-compression corners (theta = +30 deg), thesis (2.90)
  extension,    ///< through the triaxial-extension corners (theta = -30 deg)
  plane_strain, ///< same plane-strain strength as Mohr-Coulomb (associated flow)
  inscribed,    ///< inscribed in the pyramid; thesis (2.91), which mislabels it "theta = -30 deg"
};

/// f = alpha I1 + sqrt(J2) - k c: alpha and the strength per unit cohesion k.
struct ConeConstants {
  double alpha = 0.0;
  double k = 0.0;
};

/// Constants of a cone for a friction (or dilatancy) angle in radians.
[[nodiscard]] inline ConeConstants cone_constants(Cone cone, double angle) {
  const double s = std::sin(angle), c = std::cos(angle), t = std::tan(angle), r3 = std::sqrt(3.0);
  switch (cone) {
  case Cone::compression:
    return {2.0 * s / (r3 * (3.0 - s)), 6.0 * c / (r3 * (3.0 - s))};
  case Cone::extension:
    return {2.0 * s / (r3 * (3.0 + s)), 6.0 * c / (r3 * (3.0 + s))};
  case Cone::plane_strain: {
    const double d = std::sqrt(9.0 + 12.0 * t * t);
    return {t / d, 3.0 / d};
  }
  case Cone::inscribed: {
    const double d = std::sqrt(9.0 + 3.0 * s * s);
    return {s / d, 3.0 * c / d};
  }
  }
  return {};
}

[[nodiscard]] inline double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

/// Material constants. Angles in degrees, stresses in kPa.
struct Parameters {
  double E = 0.0;    ///< Young's modulus
  double nu = 0.3;   ///< Poisson's ratio
  double c = 0.0;    ///< initial cohesion (>= 0)
  double phi = 30.0; ///< friction angle, (0, 90)
  double psi = 0.0;  ///< dilatancy angle, [0, phi]
  double H_c = 0.0;  ///< cohesion hardening modulus: c = c0 + H_c eps_bar_p (>= 0)
  Cone cone = Cone::compression;
};

/// Isotropic elastic stiffness (Voigt, engineering shear).
[[nodiscard]] inline Mat6 elastic_stiffness(double E, double nu) {
  return stratum::isotropic_stiffness(E, nu);
}

/// sqrt(J2) with its gradient and Hessian with respect to the Voigt stress entries. At J2 = 0
/// the derivatives do not exist; they are returned as zero (the apex is handled separately).
struct SqrtJ2 {
  double value = 0.0;
  Vec6 grad = Vec6::Zero();
  Mat6 hess = Mat6::Zero();
};

[[nodiscard]] inline SqrtJ2 sqrt_j2(const Vec6& sigma) {
  SqrtJ2 r;
  const double J2 = plasticity::j2(sigma);
  if (!(J2 > 1e-28 * sigma.squaredNorm()) || J2 <= 0.0) return r;
  r.value = std::sqrt(J2);
  const Vec6 a = plasticity::to_strain_like(plasticity::deviator(sigma)); // d J2 / d sigma
  const Mat6 P = plasticity::deviatoric_projector_strain_like();          // d2 J2 / d sigma2
  r.grad = a / (2.0 * r.value);
  r.hess = P / (2.0 * r.value) - a * a.transpose() / (4.0 * J2 * r.value);
  return r;
}

/// The Drucker-Prager cone as a plasticity::Model: one surface, one internal variable
/// q = eps_bar_p (thesis (2.49)), dq = h_q dlambda with h_q = sqrt(1/3 + 2 alpha_psi^2).
class Model final : public plasticity::Model {
public:
  explicit Model(const Parameters& p)
      : D_(elastic_stiffness(p.E, p.nu)), yield_(cone_constants(p.cone, radians(p.phi))),
        potential_(cone_constants(p.cone, radians(p.psi))), c_(p.c), H_(p.H_c),
        hq_(std::sqrt(1.0 / 3.0 + 2.0 * potential_.alpha * potential_.alpha)) {}

  [[nodiscard]] int internal_size() const override { return 1; }
  [[nodiscard]] Mat6 elastic(const Vec6&, std::span<const double>) const override { return D_; }

  [[nodiscard]] double yield(int, const Vec6& s, std::span<const double> q) const override {
    return yield_.alpha * 3.0 * plasticity::mean(s) + std::sqrt(std::max(0.0, plasticity::j2(s))) -
           strength(q[0]);
  }
  [[nodiscard]] Vec6 yield_gradient(int, const Vec6& s, std::span<const double>) const override {
    return yield_.alpha * plasticity::identity() + sqrt_j2(s).grad;
  }
  [[nodiscard]] plasticity::VecX yield_gradient_q(int, const Vec6&, std::span<const double>) const override {
    return plasticity::VecX::Constant(1, -yield_.k * H_);
  }
  [[nodiscard]] Vec6 flow(int, const Vec6& s, std::span<const double>) const override {
    return potential_.alpha * plasticity::identity() + sqrt_j2(s).grad;
  }
  [[nodiscard]] plasticity::VecX hardening(int, const Vec6&, std::span<const double>) const override {
    return plasticity::VecX::Constant(1, hq_);
  }
  [[nodiscard]] Mat6 flow_gradient(int, const Vec6& s, std::span<const double>) const override {
    return sqrt_j2(s).hess;
  }
  [[nodiscard]] plasticity::MatX flow_gradient_q(int, const Vec6&, std::span<const double>) const override {
    return plasticity::MatX::Zero(6, 1);
  }
  [[nodiscard]] plasticity::MatX hardening_gradient(int, const Vec6&,
                                                    std::span<const double>) const override {
    return plasticity::MatX::Zero(1, 6);
  }
  [[nodiscard]] plasticity::MatX hardening_gradient_q(int, const Vec6&,
                                                      std::span<const double>) const override {
    return plasticity::MatX::Zero(1, 1);
  }
  [[nodiscard]] bool admissible(const Vec6&, std::span<const double> q) const override { return q[0] >= 0.0; }
  [[nodiscard]] double stress_scale(const Vec6& s, std::span<const double> q) const override {
    return std::max(
        {strength(q[0]),
         std::sqrt(std::max(0.0, plasticity::j2(s))) + 3.0 * yield_.alpha * std::abs(plasticity::mean(s)),
         1e-9 * D_(3, 3)});
  }

  /// K(q) = k (c + H_c q).
  [[nodiscard]] double strength(double q) const { return yield_.k * (c_ + H_ * q); }
  /// Mean stress at the apex, K / (3 alpha) (thesis (2.89)).
  [[nodiscard]] double apex(double q) const { return strength(q) / (3.0 * yield_.alpha); }
  [[nodiscard]] const ConeConstants& yield_cone() const { return yield_; }
  [[nodiscard]] const ConeConstants& potential_cone() const { return potential_; }
  [[nodiscard]] double hardening_modulus() const { return H_; }
  /// dq / dlambda on the cone.
  [[nodiscard]] double h_q() const { return hq_; }

private:
  Mat6 D_;
  ConeConstants yield_, potential_;
  double c_ = 0.0, H_ = 0.0, hq_ = 0.0;
};

/// The implicit (closest-point) plastic multiplier of the cone return, exact for this model:
///   dlambda = f_tr / (G + 9 K alpha alpha_psi + k H_c h_q).
[[nodiscard]] inline double cone_multiplier(const Model& m, double G, double K, const Vec6& trial,
                                            double q_n) {
  const std::array<double, 1> q{q_n};
  return m.yield(0, trial, q) / (G + 9.0 * K * m.yield_cone().alpha * m.potential_cone().alpha +
                                 m.yield_cone().k * m.hardening_modulus() * m.h_q());
}

/// True when the trial stress lies in the apex region: it is outside the cone and the cone
/// return would carry the deviator through zero, sqrt(J2_tr) - G dlambda < 0.
[[nodiscard]] inline bool apex_regime(const Model& m, double G, double K, const Vec6& trial, double q_n) {
  const std::array<double, 1> q{q_n};
  if (!(m.yield(0, trial, q) > 0.0)) return false;
  return std::sqrt(std::max(0.0, plasticity::j2(trial))) - G * cone_multiplier(m, G, K, trial, q_n) < 0.0;
}

/// Result of the apex return.
struct ApexResult {
  Vec6 sigma = Vec6::Zero();
  double q = 0.0;
  Mat6 tangent = Mat6::Zero();
  bool ok = false;
};

/// Return to the apex. The plastic strain removes the whole trial deviator, through the cone
/// mechanism with dlambda_1 = sqrt(J2_tr) / G, and brings the mean stress to the (hardened)
/// apex with a volumetric plastic strain x = d eps_v^p >= 3 alpha_psi dlambda_1:
///   sigma_m^tr - K x = K(q) / (3 alpha),   q = q_n + sqrt(2/3) |d eps^p| = q_n + sqrt(dl1^2/3 + 2 x^2/9).
/// Solved by Newton (one step without hardening). The consistent tangent is
///   C = 1 (x) K P' (m_x 1 + m_l s_tr / sqrt(J2_tr)) / (K + P' m_x),
/// P' = k H_c / (3 alpha), m_x = dq/dx = 2x / (9 m), m_l = dq/d dl1 = dl1 / (3 m), m = q - q_n;
/// it is zero for perfect plasticity. See README.md for the derivation.
[[nodiscard]] inline ApexResult apex_return(const Model& m, double G, double K, const Vec6& trial,
                                            double q_n) {
  ApexResult r;
  const double sj = std::sqrt(std::max(0.0, plasticity::j2(trial)));
  const double dl1 = sj / G;
  const double sm_tr = plasticity::mean(trial);
  const double alpha = m.yield_cone().alpha;
  const double Pp = m.yield_cone().k * m.hardening_modulus() / (3.0 * alpha);
  auto mq = [dl1](double x) { return std::sqrt(dl1 * dl1 / 3.0 + 2.0 * x * x / 9.0); };
  auto residual = [&](double x) { return sm_tr - K * x - m.apex(q_n + mq(x)); };

  double x = 3.0 * m.potential_cone().alpha * dl1;
  const double tol = 1e-14 * std::max({std::abs(sm_tr), std::abs(m.apex(q_n)), 1e-9 * K});
  bool converged = false;
  for (int it = 0; it < 60; ++it) {
    const double res = residual(x);
    if (std::abs(res) <= tol) {
      converged = true;
      break;
    }
    const double mm = mq(x);
    const double dmdx = mm > 0.0 ? 2.0 * x / (9.0 * mm) : std::sqrt(2.0) / 3.0;
    x -= res / (-K - Pp * dmdx);
  }
  if (!converged || !(x >= 0.0)) return r;

  const double mm = mq(x);
  r.q = q_n + mm;
  const double p = m.apex(r.q);
  r.sigma = p * plasticity::identity();
  const double mx = mm > 0.0 ? 2.0 * x / (9.0 * mm) : std::sqrt(2.0) / 3.0;
  const double ml = mm > 0.0 ? dl1 / (3.0 * mm) : 0.0;
  Vec6 row = mx * plasticity::identity();
  if (sj > 0.0) row += ml * plasticity::deviator(trial) / sj;
  r.tangent = plasticity::identity() * (K * Pp / (K + Pp * mx) * row).transpose();
  r.ok = true;
  return r;
}

/// The Drucker-Prager material: closed-form apex return, library integration elsewhere.
class DruckerPrager final : public Material {
public:
  /// The parameters must be valid (the factory checks them).
  DruckerPrager(const Parameters& p, const plasticity::Settings& settings)
      : p_(p), settings_(settings), model_(p), D_(elastic_stiffness(p.E, p.nu)),
        G_(p.E / (2.0 * (1.0 + p.nu))), K_(p.E / (3.0 * (1.0 - 2.0 * p.nu))) {}

  /// history[0]: q = eps_bar_p, the accumulated plastic strain (thesis (2.49)).
  [[nodiscard]] int history_size() const override { return 1; }
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"eps_bar_p", "-"}});
  }
  [[nodiscard]] bool symmetric_tangent() const override {
    // Non-associated flow breaks symmetry everywhere; hardening breaks it at the apex.
    return p_.psi == p_.phi && p_.H_c == 0.0;
  }

  /// 0 elastic (inside the cone), 1 on the cone (shear yielding), 2 at the apex (sqrt(J2) = 0 on
  /// the surface: the mean stress is at K(q) / (3 alpha), tensile failure). "On" within a
  /// relative 1e-6 of the model's stress scale.
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> h) const override {
    const std::array<double, 1> q{h.empty() ? 0.0 : h[0]};
    const double scale = model_.stress_scale(stress, q);
    if (model_.yield(0, stress, q) < -1e-6 * scale) return 0;
    return std::sqrt(std::max(0.0, plasticity::j2(stress))) <= 1e-6 * scale ? 2 : 1;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"elastic", "shear (on the cone)", "apex (tension)"};
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    if (Outcome o = material_checks::finite_input(in, "drucker_prager"); !o.ok()) return o;
    const double q_n = in.history_n.empty() ? 0.0 : in.history_n[0];
    const Vec6 trial = in.stress_n + D_ * in.dstrain;
    if (apex_regime(model_, G_, K_, trial, q_n)) {
      const ApexResult r = apex_return(model_, G_, K_, trial, q_n);
      if (!r.ok)
        return Outcome::failure(Status::not_converged, "drucker_prager: the apex return did not converge" +
                                                           material_checks::where(in));
      out.stress = r.sigma;
      out.tangent = r.tangent;
      out.history[0] = r.q;
      return Outcome::success();
    }
    std::array<double, 1> q{q_n};
    const plasticity::Result r = plasticity::integrate(model_, settings_, in.stress_n, in.dstrain, out.stress,
                                                       q, out.tangent, nullptr, in.want_tangent);
    if (!r.outcome.ok())
      return Outcome::failure(r.outcome.status,
                              "drucker_prager: " + r.outcome.message + material_checks::where(in));
    if (!out.stress.allFinite() || (in.want_tangent && !out.tangent.allFinite()))
      return Outcome::failure(Status::non_finite,
                              "drucker_prager: non-finite stress or tangent" + material_checks::where(in));
    out.history[0] = q[0];
    return Outcome::success();
  }

  [[nodiscard]] const Parameters& parameters() const { return p_; }
  [[nodiscard]] const Model& model() const { return model_; }
  [[nodiscard]] const Mat6& stiffness() const { return D_; }
  [[nodiscard]] double shear_modulus() const { return G_; }
  [[nodiscard]] double bulk_modulus() const { return K_; }

private:
  Parameters p_;
  plasticity::Settings settings_;
  Model model_;
  Mat6 D_;
  double G_ = 0.0, K_ = 0.0;
};

} // namespace stratum::drucker_prager
