// The elastoplastic Coulomb interface law of the thesis ((3.56)-(3.60)): elastic stiffnesses
// k_s, k_n, Coulomb yield f = |tau| + sigma tan(phi) - c, plastic potential
// g = |tau| + sigma tan(psi) (non-associated when psi != phi), tension cut-off.
// Header-only so the tests use the plugin's code. Equations: README.md in this folder.
//
// Components (contact_law.hpp): 0 = shear, 1 = normal; sigma tension positive, opening positive.
#pragma once

#include "common/contact_history.hpp"
#include "stratum/contact_law.hpp"
#include "stratum/parameters.hpp"
#include "stratum/params.hpp"

#include <cmath>
#include <memory>
#include <numbers>
#include <string>

namespace stratum::coulomb_interface {

struct Constants {
  double k_s = 0.0, k_n = 0.0; ///< elastic stiffnesses (kPa/m)
  double c = 0.0;              ///< cohesion (adhesion) (kPa)
  double phi = 0.0, psi = 0.0; ///< friction and dilation angles (rad)
  double sigma_t = 0.0;        ///< tensile strength of the intact interface (kPa)
};

/// History: [0] plastic slip u_p, [1] plastic (dilatant) opening v_p, [2] 1 after tensile failure,
/// [3] state of the last update (0 stick, 1 slip, 2 open).
class CoulombInterface final : public ContactLaw {
public:
  explicit CoulombInterface(const Constants& c) : c_(c) {}
  [[nodiscard]] const Constants& constants() const { return c_; }

  [[nodiscard]] int history_size() const override { return 4; }
  [[nodiscard]] bool symmetric_tangent() const override { return c_.psi == c_.phi; }

  [[nodiscard]] Outcome update(const ContactInput& in, ContactOutput& out) const override {
    const Vec2 jump = in.jump_n + in.djump;
    double up = in.history_n[0], vp = in.history_n[1], failed = in.history_n[2];
    const double tan_phi = std::tan(c_.phi), tan_psi = std::tan(c_.psi);
    const double tau_tr = c_.k_s * (jump[0] - up), sig_tr = c_.k_n * (jump[1] - vp);
    double state = 0.0;
    out.tangent.setZero();
    const bool intact = failed < 0.5 && c_.sigma_t > 0.0;
    if (sig_tr > (intact ? c_.sigma_t : 0.0)) {
      // Open: no traction; the faces slide freely, the elastic jump is zero when they touch again.
      if (intact) failed = 1.0; // tension cut-off: the strength is gone for good
      out.traction.setZero();
      up = jump[0];
      state = 2.0;
    } else {
      const double s = tau_tr >= 0.0 ? 1.0 : -1.0;
      const double f = std::abs(tau_tr) + sig_tr * tan_phi - c_.c;
      if (f <= 0.0) {
        out.traction = Vec2(tau_tr, sig_tr);
        out.tangent(0, 0) = c_.k_s;
        out.tangent(1, 1) = c_.k_n;
      } else {
        // Return along C^E dg/dt; the yield function is linear, so one step is exact.
        const double H = c_.k_s + c_.k_n * tan_phi * tan_psi;
        const double dl = f / H;
        out.traction = Vec2(tau_tr - c_.k_s * s * dl, sig_tr - c_.k_n * tan_psi * dl);
        up += s * dl;
        vp += tan_psi * dl;
        // C^EP = C^E - (C^E g)(C^E f)^T / H, f = (s, tan phi), g = (s, tan psi)   (3.56)-(3.57)
        const Vec2 Cg(c_.k_s * s, c_.k_n * tan_psi), Cf(c_.k_s * s, c_.k_n * tan_phi);
        out.tangent << c_.k_s, 0.0, 0.0, c_.k_n;
        out.tangent -= Cg * Cf.transpose() / H;
        state = 1.0;
      }
    }
    contact_history::store(out.history, {up, vp, failed, state});
    return {};
  }

  [[nodiscard]] ContactState state(const Vec2& /*traction*/, std::span<const double> h) const override {
    return contact_history::state(h[3]);
  }

private:
  Constants c_;
};

/// The parameters, each declared once and bound to its member of Constants (the angles in degrees
/// as written; create() converts them to radians).
inline Declared<Constants> declaration() {
  Declared<Constants> d;
  d.real(&Constants::k_s, "k_s", "kPa/m", "elastic shear stiffness").greater_than(0.0);
  d.real(&Constants::k_n, "k_n", "kPa/m", "elastic normal stiffness").greater_than(0.0);
  StrengthText text;
  text.cohesion = "cohesion (adhesion) of the interface";
  text.friction = "interface friction angle";
  text.dilatancy = "dilation angle (psi = phi: associated)";
  text.cohesion_default = 0.0;
  text.frictionless = true;
  declare_strength(d, &Constants::c, &Constants::phi, &Constants::psi, text);
  d.real(&Constants::sigma_t, "sigma_t", "kPa", "tensile strength of the intact interface; 0: no tension")
      .at_least(0.0)
      .defaults_to(0.0);
  return d;
}

inline Schema schema() { return declaration().schema(); }

inline std::unique_ptr<ContactLaw> create(const Params& p) {
  Constants c = declaration().read(p);
  c.phi = c.phi * std::numbers::pi / 180.0; // as (phi pi) / 180, the rounding of the results
  c.psi = c.psi * std::numbers::pi / 180.0;
  return std::make_unique<CoulombInterface>(c);
}

} // namespace stratum::coulomb_interface
