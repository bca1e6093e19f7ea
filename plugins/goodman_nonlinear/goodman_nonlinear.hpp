// The thesis' nonlinear two-node interface law (section 3.2.3): normal behaviour with an initial
// gap, a tensile strength with cut-off and a large compressive stiffness; shear along a
// piecewise-linear tau-du curve O-A-B-C with K_s = K_so + alpha (sigma_n/p_a)^m (3.53), peak and
// residual Mohr-Coulomb strengths (3.54), the Q/Q_max memory of point A (3.55) choosing K_s2
// (virgin) or K_s4 (unload/reload). Header-only so the tests use the plugin's code.
// Equations, the reconstruction of the missing figures and the defaults: README.md here.
//
// Components (contact_law.hpp): 0 = shear, 1 = normal; sigma tension positive, opening positive.
// Inside, p = -sigma is the compressive normal stress of the thesis.
#pragma once

#include "common/contact_history.hpp"
#include "stratum/contact_law.hpp"
#include "stratum/parameters.hpp"
#include "stratum/params.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

namespace stratum::goodman {

struct Constants {
  double k_s0 = 0.0, alpha = 0.0, m = 0.0, p_a = 100.0; ///< (3.53)
  double c_peak = 0.0, tan_peak = 0.0;                  ///< peak criterion (3.54)
  double c_res = 0.0, tan_res = 0.0;                    ///< residual strength
  double c_A = 0.0, tan_A = 0.0;                        ///< point A (3.55)
  double r2 = 0.5, r3 = 1.0, r4 = 1.0;                  ///< K_s2, K_s3, K_s4 as multiples of K_s1
  double k_n = 1e6;                                     ///< normal stiffness in contact (kPa/m)
  double sigma_t = 0.0;                                 ///< tensile strength (kPa)
  double gap = 0.0;                                     ///< initial gap delta_v (m)
};

/// Result of the shear path at a fixed compressive normal stress p.
struct Shear {
  double tau = 0.0, q_max = 0.0;
  bool failed = false;  ///< the peak has been passed (residual from now on)
  bool sliding = false; ///< at the strength limit (perfectly plastic)
  double k = 0.0;       ///< d tau / d du on the last segment
};

/// History: [0] Q_max, [1] 1 after the peak (shear failure), [2] 1 after tensile failure,
/// [3] state of the last update (0 stick, 1 slip, 2 open).
class GoodmanNonlinear final : public ContactLaw {
public:
  explicit GoodmanNonlinear(const Constants& c) : c_(c) {}
  [[nodiscard]] const Constants& constants() const { return c_; }

  [[nodiscard]] int history_size() const override { return 4; }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  /// K_s1 = K_so + alpha (p/p_a)^m (3.53), p clipped at 0.
  [[nodiscard]] double k_s1(double p) const {
    return c_.k_s0 + c_.alpha * std::pow(std::max(p, 0.0) / c_.p_a, c_.m);
  }
  [[nodiscard]] double tau_A(double p) const { return std::max(0.0, c_.c_A + p * c_.tan_A); }
  [[nodiscard]] double tau_peak(double p) const { return std::max(0.0, c_.c_peak + p * c_.tan_peak); }
  [[nodiscard]] double tau_residual(double p) const { return std::max(0.0, c_.c_res + p * c_.tan_res); }

  /// Follows the tau-du curve from tau by the slip increment du at compressive stress p.
  [[nodiscard]] Shear shear_path(double tau, double du, double p, double q_max, bool failed) const {
    const double k1 = k_s1(p), k2 = c_.r2 * k1, k3 = c_.r3 * k1, k4 = c_.r4 * k1;
    const double tA = tau_A(p), tP = tau_peak(p), tR = tau_residual(p);
    Shear r;
    r.q_max = q_max;
    r.failed = failed;
    double rem = du;
    r.k = failed ? k3 : (q_max > 0.0 ? k4 : k1);
    for (int segment = 0; segment < 16 && rem != 0.0; ++segment) {
      if (r.failed) { // residual: elastic K_s3 up to the residual strength, then sliding
        const double t = tau + k3 * rem;
        if (std::abs(t) >= tR) {
          tau = t >= 0.0 ? tR : -tR;
          r.sliding = true;
          r.k = 0.0;
        } else {
          tau = t;
          r.sliding = false;
          r.k = k3;
        }
        rem = 0.0;
        break;
      }
      const double s = rem > 0.0 ? 1.0 : -1.0;
      const double a = std::abs(tau);
      if (tau * s < 0.0) { // unloading towards tau = 0 on the unload/reload branch
        const double K = r.q_max > 0.0 ? k4 : k1;
        const double need = a / K; // |du| to reach tau = 0
        r.k = K;
        if (std::abs(rem) <= need) {
          tau += K * rem;
          rem = 0.0;
        } else {
          tau = 0.0;
          rem -= s * need;
        }
        continue;
      }
      // Loading away from zero: which branch, up to which |tau|?
      double K, target;
      bool virgin = false;
      if (a >= tP) { // at or beyond the peak (e.g. p has dropped): fails now
        target = a;
        K = k2;
        virgin = true;
      } else if (r.q_max <= 0.0 && a < tA) {
        K = k1, target = tA; // O-A, (3.53)
      } else if (r.q_max > 0.0 && a < tA + r.q_max) {
        K = k4, target = std::min(tA + r.q_max, tP); // reloading below the memory Q_max
      } else {
        K = k2, target = tP, virgin = true; // A-B, virgin
      }
      r.k = K;
      const double need = (target - a) / K;
      if (std::abs(rem) < need) {
        tau += K * rem;
        rem = 0.0;
        if (virgin) r.q_max = std::max(r.q_max, std::abs(tau) - tA);
      } else {
        tau = s * target;
        rem -= s * need;
        if (virgin) {
          r.q_max = std::max(r.q_max, target - tA);
          if (target >= tP) { // B: the peak is reached; drop to the residual strength (C)
            r.failed = true;
            tau = s * std::min(tR, tP);
            r.sliding = true;
            r.k = 0.0;
          }
        } else if (target >= tA && r.q_max <= 0.0) {
          r.q_max = 0.0; // at A: the virgin branch starts (Q = 0)
        }
      }
    }
    r.tau = tau;
    return r;
  }

  [[nodiscard]] Outcome update(const ContactInput& in, ContactOutput& out) const override {
    const Vec2 jump = in.jump_n + in.djump;
    const double q_max_n = in.history_n[0];
    const bool failed_n = in.history_n[1] > 0.5;
    double tension_failed = in.history_n[2];
    out.tangent.setZero();
    // Normal: contact when v + gap < 0; tension only for an intact, initially closed interface.
    const double v = jump[1] + c_.gap;
    const bool intact = tension_failed < 0.5 && c_.gap <= 0.0 && c_.sigma_t > 0.0;
    double sigma = 0.0;
    bool open = false;
    if (v <= 0.0 || (intact && c_.k_n * v <= c_.sigma_t)) {
      sigma = c_.k_n * v;
      out.tangent(1, 1) = c_.k_n;
    } else {
      if (intact) tension_failed = 1.0; // cut-off: sigma drops to zero for good
      open = true;
    }
    double state = 2.0;
    Shear sh;
    sh.q_max = q_max_n;
    sh.failed = failed_n;
    if (!open) {
      const double p = -sigma;
      // An interface that was open starts shearing from zero traction when it recloses.
      const double tau_n = in.history_n[3] > 1.5 ? 0.0 : in.traction_n[0];
      sh = shear_path(tau_n, in.djump[0], p, q_max_n, failed_n);
      out.tangent(0, 0) = sh.k;
      // d tau / d p by a central difference of the (cheap, piecewise smooth) path; dp/dv = -k_n.
      const double h = 1e-7 * std::max(std::abs(p), c_.p_a);
      const double tp = shear_path(tau_n, in.djump[0], p + h, q_max_n, failed_n).tau;
      const double tm = shear_path(tau_n, in.djump[0], p - h, q_max_n, failed_n).tau;
      out.tangent(0, 1) = -(tp - tm) / (2 * h) * c_.k_n;
      state = sh.sliding ? 1.0 : 0.0;
    }
    out.traction = Vec2(open ? 0.0 : sh.tau, sigma);
    contact_history::store(out.history, {sh.q_max, sh.failed ? 1.0 : 0.0, tension_failed, state});
    return {};
  }

  [[nodiscard]] ContactState state(const Vec2& /*traction*/, std::span<const double> h) const override {
    return contact_history::state(h[3]);
  }

private:
  Constants c_;
};

/// What the parameters fill: the constants, and the angles in degrees with the point-A values as
/// written (create() derives the tangents and the point-A defaults).
struct Input {
  Constants c;
  double phi_peak = 0.0, phi_residual = 0.0, c_A = -1.0, phi_A = -1.0;
};

/// The parameters, each declared once and bound to its member.
inline Declared<Input> declaration() {
  using C = Constants;
  Declared<Input> d;
  d.real(nested(&Input::c, &C::k_s0), "k_s0", "kPa/m", "shear stiffness K_so at zero normal stress (3.53)")
      .greater_than(0.0);
  d.real(nested(&Input::c, &C::alpha), "alpha", "kPa/m",
         "stress-dependent part of the shear stiffness (3.53)")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(nested(&Input::c, &C::m), "m", "-", "exponent of sigma_n/p_a in the shear stiffness (3.53)")
      .at_least(0.0)
      .defaults_to(1.0);
  d.real(nested(&Input::c, &C::p_a), "p_a", "kPa", "atmospheric pressure")
      .greater_than(0.0)
      .defaults_to(100.0);
  d.real(nested(&Input::c, &C::c_peak), "c_peak", "kPa", "peak adhesion c_p (3.54)")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(&Input::phi_peak, "phi_peak", "deg", "peak friction angle phi_p (3.54)")
      .at_least(0.0)
      .less_than(90.0);
  d.real(nested(&Input::c, &C::c_res), "c_residual", "kPa", "residual adhesion c_r")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(&Input::phi_residual, "phi_residual", "deg", "residual friction angle phi_r")
      .at_least(0.0)
      .less_than(90.0);
  d.real(&Input::c_A, "c_A", "kPa", "adhesion of point A (3.55); -1: 0.7 c_peak")
      .at_least(-1.0)
      .defaults_to(-1.0);
  d.real(&Input::phi_A, "phi_A", "deg", "friction angle of point A (3.55); -1: tan phi_A = 0.7 tan phi_peak")
      .at_least(-1.0)
      .less_than(90.0)
      .defaults_to(-1.0);
  d.real(nested(&Input::c, &C::r2), "k_s2_ratio", "-", "K_s2 / K_s1: virgin branch A-B")
      .greater_than(0.0)
      .defaults_to(0.5);
  d.real(nested(&Input::c, &C::r3), "k_s3_ratio", "-", "K_s3 / K_s1: elastic stiffness after the peak")
      .greater_than(0.0)
      .defaults_to(1.0);
  d.real(nested(&Input::c, &C::r4), "k_s4_ratio", "-", "K_s4 / K_s1: unload/reload below Q_max")
      .greater_than(0.0)
      .defaults_to(1.0);
  d.real(nested(&Input::c, &C::k_n), "k_n", "kPa/m",
         "normal stiffness in contact (large: no normal deformability)")
      .greater_than(0.0)
      .defaults_to(1e6);
  d.real(nested(&Input::c, &C::sigma_t), "sigma_t", "kPa", "tensile strength sigma_T; 0: no tension")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(nested(&Input::c, &C::gap), "gap", "m", "initial gap delta_v: contact starts after this closure")
      .at_least(0.0)
      .defaults_to(0.0);
  return d;
}

inline Schema schema() { return declaration().schema(); }

/// The constants of validated parameters: tangents of the angles, point A's defaults, and the checks
/// on them.
inline Constants constants(const Params& p) {
  constexpr double deg = std::numbers::pi / 180.0;
  const Input in = declaration().read(p);
  Constants c = in.c;
  c.tan_peak = std::tan(in.phi_peak * deg);
  c.tan_res = std::tan(in.phi_residual * deg);
  c.c_A = in.c_A < 0.0 ? 0.7 * c.c_peak : in.c_A;
  c.tan_A = in.phi_A < 0.0 ? 0.7 * c.tan_peak : std::tan(in.phi_A * deg);
  if (c.c_res > c.c_peak || c.tan_res > c.tan_peak)
    fail(p, {"phi_residual",
             "the residual strength (c_residual, phi_residual) exceeds the peak (c_peak, phi_peak); "
             "allowed: residual <= peak"});
  if (c.c_A > c.c_peak || c.tan_A > c.tan_peak)
    fail(p, {"phi_A", "point A (c_A, phi_A) lies above the peak; allowed: A <= peak"});
  return c;
}

inline std::unique_ptr<ContactLaw> create(const Params& p) {
  return std::make_unique<GoodmanNonlinear>(constants(p));
}

} // namespace stratum::goodman
