// The Desai & Zaman thin-layer interface material (thesis (3.63)-(3.67)): linear elastic
// plane-strain normal behaviour (C1, C2) and a hyperbolic shear modulus independent of it
// (Clough & Duncan, (3.65)). Header-only so the tests use the plugin's own code;
// thin_layer_hyperbolic.cpp only adds the factory. Equations and conventions: README.md.
#pragma once

#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/parameters.hpp"
#include "stratum/voigt.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <string>

namespace stratum::thin_layer_hyperbolic {

struct Constants {
  double E = 0.0, nu = 0.3;    ///< normal behaviour (kPa, -)
  double K_I = 0.0;            ///< modulus number (-); see README for its basis
  double n = 0.5;              ///< exponent (-)
  double R_f = 0.9;            ///< failure ratio (0, 1]
  double c_a = 0.0;            ///< adhesion (kPa)
  double delta = 0.0;          ///< interface friction angle (deg)
  double gamma_w = 9.81;       ///< unit weight of water (kN/m3)
  double p_a = 100.0;          ///< atmospheric pressure (kPa)
  double thickness = 0.0;      ///< 0: K_I gamma_w (.)^n is G (kPa); > 0: it is k_s (kPa/m), G = t k_s
  double sigma_n_floor = 0.01; ///< lowest sigma_n used in G_i and tau_f, as a fraction of p_a
  double residual = 1e-4;      ///< tangent shear modulus at failure, as a fraction of G_i
  bool vertical = true;        ///< layer normal x (vertical layer) or y (horizontal layer)

  /// Voigt index of the normal stress across the layer.
  [[nodiscard]] int normal() const { return vertical ? voigt::xx : voigt::yy; }
  [[nodiscard]] double tan_delta() const { return std::tan(delta * std::numbers::pi / 180.0); }
  [[nodiscard]] double floor() const { return sigma_n_floor * p_a; }
  /// The compressive normal stress that enters G_i and tau_f.
  [[nodiscard]] double effective_sigma_n(double sn) const { return std::max(sn, floor()); }
  /// Initial shear modulus G_i = [t] K_I gamma_w (sigma_n / p_a)^n (kPa).
  [[nodiscard]] double G_i(double sn) const {
    return (thickness > 0.0 ? thickness : 1.0) * K_I * gamma_w * std::pow(effective_sigma_n(sn) / p_a, n);
  }
  /// Shear strength tau_f = c_a + sigma_n tan delta (kPa).
  [[nodiscard]] double tau_f(double sn) const { return c_a + effective_sigma_n(sn) * tan_delta(); }
  /// Plane-strain constants (3.64).
  [[nodiscard]] double C1() const { return E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)); }
  [[nodiscard]] double C2() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
  [[nodiscard]] double G_elastic() const { return E / (2 * (1 + nu)); }
};

/// A value with its derivatives with respect to the shear strain increment (g) and to the
/// compressive normal stress sigma_n (s): forward-mode differentiation of the shear update.
struct Dual {
  double v = 0.0, g = 0.0, s = 0.0;
};
inline Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.g + b.g, a.s + b.s}; }
inline Dual operator-(Dual a, Dual b) { return {a.v - b.v, a.g - b.g, a.s - b.s}; }
inline Dual operator*(Dual a, Dual b) { return {a.v * b.v, a.g * b.v + a.v * b.g, a.s * b.v + a.v * b.s}; }
inline Dual operator/(Dual a, Dual b) {
  const double q = a.v / b.v;
  return {q, (a.g - q * b.g) / b.v, (a.s - q * b.s) / b.v};
}
inline Dual operator*(double c, Dual a) { return {c * a.v, c * a.g, c * a.s}; }
inline Dual constant(double c) { return {c, 0.0, 0.0}; }

/// Result of the shear update of one point.
struct ShearResult {
  Dual tau;               ///< tau_{n+1} with d/d dgamma and d/d sigma_n
  double level_max = 0.0; ///< updated memory of the largest stress level |tau| / tau_f
  bool failed = false;    ///< tau sits at the strength
  double G_i = 0.0;       ///< initial modulus at sigma_n (kPa)
};

/// Integrates d tau / d gamma = G_t (3.65) at the end-of-step sigma_n, exactly: on primary loading
/// (|tau| at or above the remembered stress level, moving away from zero) the hyperbola
/// tau = gamma / (1/G_i + R_f gamma / tau_f) is followed from the equivalent strain of tau_n;
/// otherwise (unloading, reloading below the memory) the modulus is G_i. tau is capped at tau_f.
[[nodiscard]] inline ShearResult shear_update(const Constants& c, double tau_n, double level_max_n,
                                              double dgamma, double sigma_n, bool failed_n = false) {
  ShearResult r;
  const Dual dg{dgamma, 1.0, 0.0};
  const bool floored = sigma_n <= c.floor();
  const Dual sn = floored ? constant(c.floor()) : Dual{sigma_n, 0.0, 1.0};
  const double scale = (c.thickness > 0.0 ? c.thickness : 1.0) * c.K_I * c.gamma_w;
  const double pw = std::pow(sn.v / c.p_a, c.n);
  const Dual Gi{scale * pw, 0.0, sn.s * scale * c.n * pw / sn.v};
  const Dual tf = constant(c.c_a) + c.tan_delta() * sn;
  r.G_i = Gi.v;
  // Direction of the increment; with no increment, the direction of the current shear.
  const double s = dgamma > 0.0 ? 1.0 : dgamma < 0.0 ? -1.0 : (tau_n < 0.0 ? -1.0 : 1.0);
  const Dual rem_total = s * dg; // |dgamma| >= 0
  const double t0 = s * tau_n;   // current shear in the loading direction
  const Dual memory = level_max_n * tf;
  Dual tau; // in the loading direction
  Dual start = constant(t0), rem = rem_total;
  // A point that failed and keeps shearing the same way slides at the strength of the new
  // sigma_n (no stiff G_i reloading when tau_f grew by a small change of sigma_n).
  bool primary = t0 >= memory.v * (1.0 - 1e-12) || (failed_n && t0 > 0.0);
  if (failed_n && t0 > 0.0) start = tf;
  if (!primary) {
    const Dual to_memory = (memory - constant(t0)) / Gi;
    if (rem_total.v <= to_memory.v) {
      tau = constant(t0) + Gi * rem_total;
    } else {
      primary = true;
      start = memory;
      rem = rem_total - to_memory;
    }
  }
  if (primary) {
    if (start.v >= tf.v) {
      tau = tf;
      r.failed = true;
    } else {
      const Dual a = constant(1.0) / Gi, b = c.R_f * (constant(1.0) / tf);
      const Dual g0 = a * start / (constant(1.0) - b * start);
      const Dual g1 = g0 + rem;
      tau = g1 / (a + b * g1);
    }
  }
  if (tau.v >= tf.v) {
    tau = tf;
    r.failed = true;
  } else if (tau.v < -tf.v) {
    tau = constant(-1.0) * tf;
    r.failed = true;
  }
  r.tau = s * tau;
  r.level_max = std::min(1.0, std::max(level_max_n, std::abs(tau.v) / tf.v));
  return r;
}

class ThinLayerHyperbolic final : public Material {
public:
  explicit ThinLayerHyperbolic(const Constants& c) : c_(c) {}

  [[nodiscard]] int history_size() const override { return 2; }
  /// The VTK names of the history: the largest stress level reached and the failure flag.
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"S_max", "-"}, {"failed", "-"}});
  }
  /// history[0]: largest stress level |tau| / tau_f reached; history[1]: 1 at failure, else 0.
  void init_history(const Vec6& stress, std::span<double> h) const override {
    const double sn = -stress[c_.normal()];
    h[0] = std::min(1.0, std::abs(stress[voigt::xy]) / c_.tau_f(sn));
    h[1] = h[0] >= 1.0 ? 1.0 : 0.0;
  }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  /// 0 below failure (|tau| < tau_f), 1 failed in shear (history[1], |tau| = tau_f), 2 the
  /// normal stress across the layer is tensile (sigma_n > 0: the layer carries tension, tau_f at
  /// its floor), whether or not failed.
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> h) const override {
    if (stress[c_.normal()] > 0.0) return 2;
    return h.size() > 1 && h[1] > 0.5 ? 1 : 0;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"below failure", "failed in shear", "tension across the layer"};
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    Mat6 D = Mat6::Zero();
    const int N[3] = {voigt::xx, voigt::yy, voigt::zz};
    for (int i : N)
      for (int j : N) D(i, j) = i == j ? c_.C1() : c_.C2();
    D(voigt::yz, voigt::yz) = D(voigt::zx, voigt::zx) = c_.G_elastic();
    Vec6 s = in.stress_n + D * in.dstrain;
    const int k = c_.normal();
    const double sn = -s[k];
    const auto r = shear_update(c_, in.stress_n[voigt::xy], in.history_n[0], in.dstrain[voigt::xy], sn,
                                in.history_n[1] > 0.5);
    if (!std::isfinite(r.tau.v) || !std::isfinite(r.tau.g) || !std::isfinite(r.tau.s))
      return Outcome::failure(Status::material_failure,
                              "thin_layer_hyperbolic: non-finite shear stress at element " +
                                  std::to_string(in.where.element) + " point " +
                                  std::to_string(in.where.point));
    s[voigt::xy] = r.tau.v;
    // d tau / d eps_j = d tau / d sigma_n * d sigma_n / d eps_j, sigma_n = -sigma_k.
    for (int j : N) D(voigt::xy, j) = -r.tau.s * D(k, j);
    D(voigt::xy, voigt::xy) = r.failed ? c_.residual * r.G_i : r.tau.g;
    out.stress = s;
    out.tangent = D;
    out.history[0] = r.level_max;
    out.history[1] = r.failed ? 1.0 : 0.0;
    return Outcome::success();
  }

  [[nodiscard]] const Constants& constants() const { return c_; }

private:
  Constants c_;
};

} // namespace stratum::thin_layer_hyperbolic
