// Cam-Clay (original, "cam_clay") and Modified Cam-Clay ("modified_cam_clay").
//
// Header only, so that the tests use the plugin's own code; cam_clay.cpp only adds
// the two factories. Equations, parameters and sources: README.md in this folder.
//
// Inside the model p and q are compression positive (p = -tr(sigma)/3, q = sqrt(3 J2));
// the framework's stresses and strains are tension positive (stratum/voigt.hpp).
//
//   elasticity   p = p_n exp(v0 de_v^e / kappa)  (K = v0 p / kappa, exactly integrated),
//                deviator: constant G, or G = 3 K (1 - 2 nu) / (2 (1 + nu)) integrated
//                with the mean of G over the elastic increment
//   yield (OCC)  f = q + M p ln(p / p_c)                      [kPa]
//   yield (MCC)  f = (q^2 / M^2 + p^2) / p_c - p              [kPa] (= the ellipse
//                q^2 + M^2 p (p - p_c) = 0 divided by M^2 p_c)
//   flow         associated, d eps^p = dlambda df/dsigma
//   hardening    p_c = p_c0 exp(v0 eps_v^p / (lambda - kappa)), eps_v^p compression positive
//
// The internal variable of the plasticity::Model is xi = ln(p_c / 1 kPa): the hardening
// law is then linear in the plastic volumetric strain (d xi = v0 / (lambda - kappa)
// d eps_v^p), so every integrator that integrates eps_v^p exactly (the closest-point
// return does) integrates p_c exactly too. The material's history stores p_c itself.
#pragma once

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
#include <cstdio>
#include <optional>
#include <span>
#include <string>

namespace stratum::cam_clay {

enum class Variant {
  original, ///< Roscoe & Schofield's Cam-Clay: eta = M ln(p_c / p)
  modified, ///< Roscoe & Burland's Modified Cam-Clay: elliptic yield locus
};

/// The material constants (see README.md for units, ranges and defaults).
struct Constants {
  Variant variant = Variant::modified;
  double M = 1.2;        ///< critical-state stress ratio q/p (-)
  double lambda = 0.077; ///< slope of the normal compression line in v-ln p (-)
  double kappa = 0.0066; ///< slope of the swelling line in v-ln p (-)
  double e0 = 1.0;       ///< initial void ratio; v0 = 1 + e0 is held fixed (small strain)
  double nu = 0.3;       ///< Poisson's ratio, used when G = 0
  double G = 0.0;        ///< constant shear modulus (kPa); 0 means G = 3 K (1 - 2 nu) / (2 (1 + nu))
  double p_min = 1.0;    ///< smallest admissible mean effective stress (kPa)

  [[nodiscard]] double v0() const { return 1.0 + e0; }
  /// d xi / d eps_v^p with xi = ln p_c.
  [[nodiscard]] double hardening_rate() const { return v0() / (lambda - kappa); }
  /// Ratio G / p when G is proportional to p (the nu option).
  [[nodiscard]] double shear_ratio() const {
    return 3.0 * v0() / kappa * (1.0 - 2.0 * nu) / (2.0 * (1.0 + nu));
  }
};

/// Checks what the schema ranges cannot: kappa < lambda, and finite, positive constants.
[[nodiscard]] inline std::optional<Problem> check(const Constants& c) {
  if (!(c.M > 0.0)) return Problem{"M", "M = " + number(c.M) + " must be positive"};
  if (!(c.lambda > 0.0)) return Problem{"lambda", "lambda = " + number(c.lambda) + " must be positive"};
  if (!(c.kappa > 0.0)) return Problem{"kappa", "kappa = " + number(c.kappa) + " must be positive"};
  if (!(c.kappa < c.lambda))
    return Problem{"kappa",
                   "kappa = " + number(c.kappa) + " must be smaller than lambda = " + number(c.lambda)};
  if (!(c.e0 > 0.0)) return Problem{"e0", "e0 = " + number(c.e0) + " must be positive"};
  if (!(c.nu > -1.0 && c.nu < 0.5)) return Problem{"nu", "nu = " + number(c.nu) + " must lie in (-1, 0.5)"};
  if (!(c.G >= 0.0)) return Problem{"G", "G = " + number(c.G) + " must not be negative"};
  if (!(c.p_min > 0.0)) return Problem{"p_min", "p_min = " + number(c.p_min) + " must be positive"};
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------
// Small helpers (tension-positive Voigt vectors)

/// Compression-positive mean effective stress.
[[nodiscard]] inline double pressure(const Vec6& s) { return plasticity::p_comp(s); }

/// phi(x) = (e^x - 1) / x, the mean of e^(x t) over t in [0, 1].
[[nodiscard]] inline double phi(double x) { return x == 0.0 ? 1.0 : std::expm1(x) / x; }
/// phi'(x), by its series near 0 where the closed form cancels.
[[nodiscard]] inline double phi_prime(double x) {
  if (std::abs(x) < 1e-2) return 0.5 + x * (1.0 / 3.0 + x * (1.0 / 8.0 + x * (1.0 / 30.0 + x / 144.0)));
  return (x * std::exp(x) - std::expm1(x)) / (x * x);
}

/// The p_c of the yield surface through a stress (q and p compression positive, p > 0).
[[nodiscard]] inline double equivalent_pc(Variant v, double M, double p, double q) {
  if (v == Variant::modified) return p + q * q / (M * M * p);
  return p * std::exp(q / (M * p));
}

// ---------------------------------------------------------------------------------------
/// The elastoplastic model in the form of the shared integration library.
/// Internal variable: q[0] = xi = ln(p_c / kPa).
class Model final : public plasticity::Model {
public:
  explicit Model(const Constants& c) : c_(c), P_(plasticity::deviatoric_projector_strain_like()) {}

  [[nodiscard]] const Constants& constants() const { return c_; }

  [[nodiscard]] int internal_size() const override { return 1; }

  // ---- elasticity
  /// Tangent stiffness K = v0 p / kappa, G constant or proportional to p; p below p_min is
  /// replaced by p_min so that the stiffness stays positive.
  [[nodiscard]] Mat6 elastic(const Vec6& sigma, std::span<const double> /*q*/) const override {
    const double pe = std::max(pressure(sigma), c_.p_min);
    return stiffness(c_.v0() * pe / c_.kappa, shear_modulus(pe));
  }

  /// Exact integration along the elastic increment de (straight strain path):
  ///   p = p_n + pe (exp(x) - 1), x = -v0 tr(de) / kappa, pe = max(p_n, p_min)
  /// (= p_n exp(x), the swelling line, whenever p_n >= p_min);
  ///   s = s_n + 2 Gbar dev(de), Gbar = G, or Gbar = (G/p) pe phi(x), the mean of G over the path.
  [[nodiscard]] Vec6 elastic_update(const Vec6& sigma_n, std::span<const double> /*q*/,
                                    const Vec6& de) const override {
    const double pn = pressure(sigma_n);
    const double pe = std::max(pn, c_.p_min);
    const double x = volumetric_exponent(de);
    const double p = pn + pe * std::expm1(x);
    const double Gbar = c_.G > 0.0 ? c_.G : c_.shear_ratio() * pe * phi(x);
    Vec6 s = plasticity::deviator(sigma_n);
    const double ev = de[0] + de[1] + de[2];
    for (int i = 0; i < 3; ++i) s[i] += 2.0 * Gbar * (de[i] - ev / 3.0);
    for (int i = 3; i < 6; ++i) s[i] += Gbar * de[i];
    for (int i = 0; i < 3; ++i) s[i] -= p;
    return s;
  }

  [[nodiscard]] Mat6 elastic_update_tangent(const Vec6& sigma_n, std::span<const double> /*q*/,
                                            const Vec6& de) const override {
    const double pn = pressure(sigma_n);
    const double pe = std::max(pn, c_.p_min);
    const double x = volumetric_exponent(de);
    const double dx = -c_.v0() / c_.kappa; // d x / d de_i, i < 3
    const Vec6 I = plasticity::identity();
    const double K = pe * std::exp(x) * c_.v0() / c_.kappa; // = -d p / d de_i (i < 3): the end bulk modulus
    const double Gbar = c_.G > 0.0 ? c_.G : c_.shear_ratio() * pe * phi(x);
    Mat6 D = stiffness(K, Gbar);
    if (c_.G <= 0.0) {
      // d(2 Gbar e)/d de through Gbar(x): 2 e (dGbar/dx) dx I^T, e the tensor deviatoric strain
      Vec6 e = de;
      const double ev = de[0] + de[1] + de[2];
      for (int i = 0; i < 3; ++i) e[i] -= ev / 3.0;
      for (int i = 3; i < 6; ++i) e[i] *= 0.5;
      D += (2.0 * c_.shear_ratio() * pe * phi_prime(x) * dx) * e * I.transpose();
    }
    return D;
  }

  // ---- yield surface
  [[nodiscard]] double yield(int /*k*/, const Vec6& sigma, std::span<const double> q) const override {
    const double p = pressure(sigma), qq = plasticity::q_mises(sigma), pc = std::exp(q[0]);
    if (c_.variant == Variant::modified) return (qq * qq / (c_.M * c_.M) + p * p) / pc - p;
    return qq + c_.M * p * log_ratio(p, q[0]);
  }

  [[nodiscard]] Vec6 yield_gradient(int /*k*/, const Vec6& sigma, std::span<const double> q) const override {
    const Vec6 I = plasticity::identity();
    const double p = pressure(sigma), pc = std::exp(q[0]);
    const Vec6 shat = plasticity::to_strain_like(plasticity::deviator(sigma));
    if (c_.variant == Variant::modified)
      return ((3.0 / (c_.M * c_.M)) * shat - (2.0 * p / 3.0) * I) / pc + I / 3.0;
    return dq_dsigma(sigma, shat, q[0]) - (c_.M / 3.0) * (log_ratio(p, q[0]) + 1.0) * I;
  }

  [[nodiscard]] plasticity::VecX yield_gradient_q(int /*k*/, const Vec6& sigma,
                                                  std::span<const double> q) const override {
    plasticity::VecX g(1);
    const double p = pressure(sigma), pc = std::exp(q[0]);
    if (c_.variant == Variant::modified) {
      const double qq = plasticity::q_mises(sigma);
      g[0] = -(qq * qq / (c_.M * c_.M) + p * p) / pc;
    } else {
      g[0] = -c_.M * p;
    }
    return g;
  }

  // ---- associated flow and hardening
  [[nodiscard]] Vec6 flow(int k, const Vec6& sigma, std::span<const double> q) const override {
    return yield_gradient(k, sigma, q);
  }

  /// d xi = dlambda v0 / (lambda - kappa) df/dp (df/dp = -tr(r) = d eps_v^p / dlambda).
  [[nodiscard]] plasticity::VecX hardening(int /*k*/, const Vec6& sigma,
                                           std::span<const double> q) const override {
    plasticity::VecX h(1);
    h[0] = c_.hardening_rate() * df_dp(pressure(sigma), q[0]);
    return h;
  }

  [[nodiscard]] Mat6 flow_gradient(int /*k*/, const Vec6& sigma, std::span<const double> q) const override {
    const Vec6 I = plasticity::identity();
    const double p = pressure(sigma), pc = std::exp(q[0]);
    if (c_.variant == Variant::modified)
      return ((3.0 / (c_.M * c_.M)) * P_ + (2.0 / 9.0) * I * I.transpose()) / pc;
    // d/dsigma of dq/dsigma = 3 shat / (2 q), plus the pressure term M / (9 p) I I^T
    Mat6 H = (c_.M / (9.0 * positive(p, q[0]))) * I * I.transpose();
    const double qq = plasticity::q_mises(sigma);
    if (qq > vertex_tolerance(q[0])) {
      const Vec6 shat = plasticity::to_strain_like(plasticity::deviator(sigma));
      H += (1.5 / qq) * P_ - (9.0 / (4.0 * qq * qq * qq)) * shat * shat.transpose();
    }
    return H;
  }

  [[nodiscard]] plasticity::MatX flow_gradient_q(int /*k*/, const Vec6& sigma,
                                                 std::span<const double> q) const override {
    const Vec6 I = plasticity::identity();
    plasticity::MatX G(6, 1);
    if (c_.variant == Variant::modified) {
      const double p = pressure(sigma), pc = std::exp(q[0]);
      const Vec6 shat = plasticity::to_strain_like(plasticity::deviator(sigma));
      G.col(0) = -((3.0 / (c_.M * c_.M)) * shat - (2.0 * p / 3.0) * I) / pc;
    } else {
      G.col(0) = (c_.M / 3.0) * I;
    }
    return G;
  }

  [[nodiscard]] plasticity::MatX hardening_gradient(int /*k*/, const Vec6& sigma,
                                                    std::span<const double> q) const override {
    // d(df/dp)/dsigma = d(df/dp)/dp * (-I^T / 3)
    const Vec6 I = plasticity::identity();
    const double p = pressure(sigma), pc = std::exp(q[0]);
    const double d2 = c_.variant == Variant::modified ? 2.0 / pc : c_.M / positive(p, q[0]);
    plasticity::MatX H(1, 6);
    H.row(0) = (-c_.hardening_rate() * d2 / 3.0) * I.transpose();
    return H;
  }

  [[nodiscard]] plasticity::MatX hardening_gradient_q(int /*k*/, const Vec6& sigma,
                                                      std::span<const double> q) const override {
    const double p = pressure(sigma), pc = std::exp(q[0]);
    plasticity::MatX H(1, 1);
    H(0, 0) = c_.hardening_rate() * (c_.variant == Variant::modified ? -2.0 * p / pc : -c_.M);
    return H;
  }

  /// Finite internal variable (p_c neither 0 nor infinite) and a finite stress.
  [[nodiscard]] bool admissible(const Vec6& sigma, std::span<const double> q) const override {
    return std::isfinite(q[0]) && std::abs(q[0]) < 700.0 && sigma.allFinite();
  }

  /// p_c: the size of the yield surface.
  [[nodiscard]] double stress_scale(const Vec6& /*sigma*/, std::span<const double> q) const override {
    return std::max(std::exp(q[0]), c_.p_min);
  }

  /// df/dp (compression positive p); = d eps_v^p / dlambda.
  [[nodiscard]] double df_dp(double p, double xi) const {
    if (c_.variant == Variant::modified) return 2.0 * p / std::exp(xi) - 1.0;
    return c_.M * (log_ratio(p, xi) + 1.0);
  }

private:
  [[nodiscard]] static Mat6 stiffness(double K, double G) { return stratum::stiffness_kg(K, G); }
  [[nodiscard]] double shear_modulus(double pe) const { return c_.G > 0.0 ? c_.G : c_.shear_ratio() * pe; }
  /// x = v0 de_v / kappa with de_v the compression-positive volumetric strain increment.
  [[nodiscard]] double volumetric_exponent(const Vec6& de) const {
    return -c_.v0() * (de[0] + de[1] + de[2]) / c_.kappa;
  }
  /// The original Cam-Clay works with ln(p / p_c); p is kept above a tiny fraction of p_c
  /// so that iterates that stray to p <= 0 give finite numbers (the material rejects
  /// such states at the end of the update).
  [[nodiscard]] static double positive(double p, double xi) { return std::max(p, 1e-12 * std::exp(xi)); }
  [[nodiscard]] static double log_ratio(double p, double xi) { return std::log(positive(p, xi)) - xi; }
  /// Below this q the original Cam-Clay sits on its vertex (the isotropic axis), where
  /// dq/dsigma is taken as 0 (the subgradient that gives purely volumetric flow).
  [[nodiscard]] static double vertex_tolerance(double xi) { return 1e-12 * std::exp(xi); }
  [[nodiscard]] static Vec6 dq_dsigma(const Vec6& sigma, const Vec6& shat, double xi) {
    const double qq = plasticity::q_mises(sigma);
    if (qq > vertex_tolerance(xi)) return (1.5 / qq) * shat;
    return Vec6::Zero();
  }

  Constants c_;
  Mat6 P_;
};

// ---------------------------------------------------------------------------------------
/// How the preconsolidation pressure of a virgin point is chosen.
struct Initial {
  double ocr = 1.0; ///< overconsolidation ratio p_c0 / p_c(initial stress) (>= 1)
  double pc0 = 0.0; ///< explicit p_c0 (kPa); 0 means use ocr
};

/// The Material: history = [p_c] (kPa).
class CamClay final : public Material {
public:
  CamClay(const Constants& c, const Initial& init, const plasticity::Settings& settings)
      : model_(c), init_(init), settings_(settings) {}

  [[nodiscard]] const Model& model() const { return model_; }
  [[nodiscard]] const plasticity::Settings& settings() const { return settings_; }

  [[nodiscard]] int history_size() const override { return 1; }
  /// The preconsolidation pressure, written to the VTK output as "p_c [kPa]".
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"p_c", "kPa"}});
  }

  /// p_c0 = ocr * p_eq with p_eq the p_c of the yield surface through the initial stress
  /// (p_eq = p0 for an isotropic stress). A mean stress below p_min counts as p_min. An
  /// explicit pc0 is used as given unless the initial stress lies outside that surface, in
  /// which case the surface is widened to pass through the stress.
  void init_history(const Vec6& stress, std::span<double> history) const override {
    const Constants& c = model_.constants();
    const double p = std::max(pressure(stress), c.p_min);
    const double peq = equivalent_pc(c.variant, c.M, p, plasticity::q_mises(stress));
    history[0] = init_.pc0 > 0.0 ? std::max(init_.pc0, peq) : init_.ocr * peq;
  }

  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  /// 0 elastic (inside the yield locus); on it (f >= -1e-6 p_c): 1 hardening, the wet side
  /// eta = q / p < M (plastic compaction, p_c grows), 2 softening, the dry side eta > M
  /// (dilation, p_c shrinks), 3 at the critical state |eta - M| <= 1e-3 M (no volume change).
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> h) const override {
    if (h.empty() || !(h[0] > 0.0)) return -1;
    const std::array<double, 1> xi{std::log(h[0])};
    if (model_.yield(0, stress, xi) < -1e-6 * h[0]) return 0;
    const double M = model_.constants().M, p = pressure(stress), q = plasticity::q_mises(stress);
    if (std::abs(q - M * p) <= 1e-3 * M * std::abs(p)) return 3;
    return q < M * p ? 1 : 2;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"elastic", "hardening (wet side, q/p < M)", "softening (dry side, q/p > M)",
            "critical state (q/p = M)"};
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    const Constants& c = model_.constants();
    auto where = [&] {
      return "cam-clay at element " + std::to_string(in.where.element) + ", point " +
             std::to_string(in.where.point) + ": ";
    };
    const double pc_n = in.history_n[0];
    if (!(pc_n > 0.0) || !std::isfinite(pc_n))
      return Outcome::failure(Status::material_failure, where() + "preconsolidation pressure p_c = " +
                                                            number(pc_n) + " kPa is not positive");
    const double xi_n = std::log(pc_n);
    if (pressure(in.stress_n) < 0.0)
      return Outcome::failure(Status::material_failure, where() + "the committed stress is tensile (p = " +
                                                            number(pressure(in.stress_n)) +
                                                            " kPa); Cam-Clay carries no tension");
    std::array<double, 1> xi{xi_n};
    const plasticity::Result r = plasticity::integrate(model_, settings_, in.stress_n, in.dstrain, out.stress,
                                                       xi, out.tangent, nullptr, in.want_tangent);
    if (!r.outcome.ok()) return Outcome::failure(r.outcome.status, where() + r.outcome.message);
    if (!out.stress.allFinite() || (in.want_tangent && !out.tangent.allFinite()) || !std::isfinite(xi[0]))
      return Outcome::failure(Status::non_finite, where() + "the stress update produced NaN or Inf");
    // No tension: p must not be driven below p_min (a point that starts below p_min, e.g.
    // from a zero initial stress, may be compressed up through it).
    const double p_n = pressure(in.stress_n), p = pressure(out.stress);
    if (p < c.p_min && !(p > p_n))
      return Outcome::failure(
          Status::material_failure,
          where() + "mean effective stress p = " + number(p) + " kPa fell below p_min = " + number(c.p_min) +
              " kPa (Cam-Clay carries no tension); step too large or soil " + "pulled apart");
    out.history[0] = pc_n * std::exp(xi[0] - xi_n); // bit-exact p_c_n after an elastic step
    return Outcome::success();
  }

private:
  Model model_;
  Initial init_;
  plasticity::Settings settings_;
};

} // namespace stratum::cam_clay
