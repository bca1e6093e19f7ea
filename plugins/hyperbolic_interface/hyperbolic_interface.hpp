// Hyperbolic (Clough & Duncan 1971) interface law: nonlinear-elastic shear along
//   tau = du / (1/K_i + R_f |du| / tau_f),  K_i = K_I gamma_w (p/p_a)^n,  tau_f = c_a + p tan(delta),
// whose tangent is the thesis' (3.65) K_st = K_i (1 - R_f tau/tau_f)^2; sliding at tau_f; linear
// normal stiffness in compression, no tension. Header-only so the tests use the plugin's code.
// Equations: README.md in this folder.
//
// Components (contact_law.hpp): 0 = shear, 1 = normal; sigma tension positive, opening positive.
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

namespace stratum::hyperbolic_interface {

struct Constants {
  double K_I = 0.0, n = 0.0, R_f = 0.9; ///< stiffness number, exponent, failure ratio
  double c_a = 0.0, tan_delta = 0.0;    ///< adhesion (kPa), tan of the friction angle
  double gamma_w = 9.81, p_a = 100.0;   ///< kN/m3, kPa
  double k_n = 1e6;                     ///< normal stiffness (kPa/m)
};

/// Hyperbola at compressive stress p and elastic slip ue: tau, d tau/d ue, d tau/d p.
struct Hyperbola {
  double tau = 0.0, dtau_du = 0.0, dtau_dp = 0.0;
};

/// History: [0] plastic slip u_p, [1] state of the last update (0 stick, 1 slip, 2 open).
class HyperbolicInterface final : public ContactLaw {
public:
  explicit HyperbolicInterface(const Constants& c) : c_(c) {}
  [[nodiscard]] const Constants& constants() const { return c_; }
  [[nodiscard]] int history_size() const override { return 2; }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  [[nodiscard]] double k_i(double p) const { return c_.K_I * c_.gamma_w * std::pow(p / c_.p_a, c_.n); }
  [[nodiscard]] double tau_f(double p) const { return c_.c_a + p * c_.tan_delta; }
  /// Elastic slip at which the hyperbola reaches tau_f (infinite for R_f = 1).
  [[nodiscard]] double slip_at_failure(double p) const {
    return c_.R_f < 1.0 ? tau_f(p) / (k_i(p) * (1.0 - c_.R_f)) : HUGE_VAL;
  }

  [[nodiscard]] Hyperbola hyperbola(double ue, double p) const {
    const double K = k_i(p), tf = tau_f(p), a = std::abs(ue);
    const double D = 1.0 / K + c_.R_f * a / tf;
    Hyperbola h;
    h.tau = ue / D;
    h.dtau_du = K * std::pow(1.0 - c_.R_f * std::abs(h.tau) / tf, 2); // (3.65)
    const double dD_dp = -(c_.n * K / p) / (K * K) - c_.R_f * a * c_.tan_delta / (tf * tf);
    h.dtau_dp = -ue / (D * D) * dD_dp;
    return h;
  }

  [[nodiscard]] Outcome update(const ContactInput& in, ContactOutput& out) const override {
    const Vec2 jump = in.jump_n + in.djump;
    double up = in.history_n[0];
    out.tangent.setZero();
    const double sigma = c_.k_n * jump[1];
    const double p = -sigma;
    double state = 2.0;
    if (!(p > 0.0) || !(tau_f(p) > 0.0)) { // open (or touching without stress): no shear resistance
      out.traction.setZero();
      up = jump[0];
    } else {
      out.tangent(1, 1) = c_.k_n;
      const double ue = jump[0] - up, uf = slip_at_failure(p);
      if (std::abs(ue) < uf) {
        const Hyperbola h = hyperbola(ue, p);
        out.traction = Vec2(h.tau, sigma);
        out.tangent(0, 0) = h.dtau_du;
        out.tangent(0, 1) = -h.dtau_dp * c_.k_n;
        state = 0.0;
      } else { // sliding at tau_f; the elastic slip stays at the failure slip
        const double s = ue >= 0.0 ? 1.0 : -1.0;
        up = jump[0] - s * uf;
        out.traction = Vec2(s * tau_f(p), sigma);
        out.tangent(0, 1) = -s * c_.tan_delta * c_.k_n;
        state = 1.0;
      }
    }
    contact_history::store(out.history, {up, state});
    return {};
  }

  [[nodiscard]] ContactState state(const Vec2& /*traction*/, std::span<const double> h) const override {
    return contact_history::state(h[1]);
  }

private:
  Constants c_;
};

/// What the parameters fill: the constants and the friction angle in degrees.
struct Input {
  Constants c;
  double delta = 0.0;
};

/// The parameters, each declared once and bound to its member.
inline Declared<Input> declaration() {
  using C = Constants;
  Declared<Input> d;
  d.real(nested(&Input::c, &C::K_I), "K_I", "-",
         "stiffness number of the initial shear stiffness K_I gamma_w (p/p_a)^n (3.65)")
      .greater_than(0.0);
  d.real(nested(&Input::c, &C::n), "n", "-", "stiffness exponent (3.65)").at_least(0.0).defaults_to(0.5);
  d.real(nested(&Input::c, &C::R_f), "R_f", "-", "failure ratio tau_f / tau_ult (3.65)")
      .greater_than(0.0)
      .at_most(1.0)
      .defaults_to(0.9);
  d.real(nested(&Input::c, &C::c_a), "c_a", "kPa", "adhesion").at_least(0.0).defaults_to(0.0);
  d.real(&Input::delta, "delta", "deg", "interface friction angle").at_least(0.0).less_than(90.0);
  d.real(nested(&Input::c, &C::gamma_w), "gamma_w", "kN/m3",
         "unit weight of water (makes K_I gamma_w a stiffness per length)")
      .greater_than(0.0)
      .defaults_to(9.81);
  d.real(nested(&Input::c, &C::p_a), "p_a", "kPa", "atmospheric pressure")
      .greater_than(0.0)
      .defaults_to(100.0);
  d.real(nested(&Input::c, &C::k_n), "k_n", "kPa/m", "normal stiffness in compression")
      .greater_than(0.0)
      .defaults_to(1e6);
  return d;
}

inline Schema schema() { return declaration().schema(); }

inline std::unique_ptr<ContactLaw> create(const Params& p) {
  const Input in = declaration().read(p);
  Constants c = in.c;
  c.tan_delta = std::tan(in.delta * std::numbers::pi / 180.0);
  return std::make_unique<HyperbolicInterface>(c);
}

} // namespace stratum::hyperbolic_interface
