// Plugin entry point of the "hardening_soil" material: the factory and its parameters, each
// declared once (stratum/parameters.hpp) and bound to its member. The model lives in
// hardening_soil.hpp (shared with the tests); README.md gives the equations.
#include "hardening_soil.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <cmath>
#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::number;
using stratum::Params;
using stratum::Problem;
namespace hs = stratum::hardening_soil;

stratum::Declared<hs::Parameters> declare() {
  using P = hs::Parameters;
  stratum::Declared<P> d;
  d.real(&P::E50_ref, "E50_ref", "kPa",
         "secant stiffness at 50 % of the strength in drained triaxial compression at sigma_3 = p_ref")
      .greater_than(0.0);
  d.real(&P::Eoed_ref, "Eoed_ref", "kPa", "tangent oedometer stiffness at sigma_1 = p_ref (K0_nc loading)")
      .greater_than(0.0);
  d.real(&P::Eur_ref, "Eur_ref", "kPa", "unloading-reloading Young's modulus at sigma_3 = p_ref")
      .greater_than(0.0);
  d.real(&P::m, "m", "-", "stress exponent of the stiffness laws")
      .at_least(0.0)
      .at_most(1.0)
      .defaults_to(0.5);
  d.real(&P::p_ref, "p_ref", "kPa", "reference stress").greater_than(0.0).defaults_to(100.0);
  d.real(&P::nu_ur, "nu_ur", "-", "unloading-reloading Poisson's ratio")
      .greater_than(-1.0)
      .less_than(0.5)
      .defaults_to(0.2);
  stratum::StrengthText text;
  text.cohesion_default = 0.0;
  text.dilatancy = "dilatancy angle (at most phi)";
  stratum::declare_strength(d, &P::c, &P::phi, &P::psi, text);
  d.real(&P::Rf, "Rf", "-", "failure ratio q_f / q_a").greater_than(0.0).less_than(1.0).defaults_to(0.9);
  d.real(&P::K0_nc, "K0_nc", "-", "K0 of normal consolidation (default 1 - sin phi)")
      .greater_than(0.0)
      .less_than(1.0)
      .defaults_to_computed(0.5, "1 - sin phi");
  d.real(&P::alpha, "alpha", "-", "cap shape (derived from K0_nc and Eoed_ref unless given together with H)")
      .greater_than(0.0)
      .defaults_to_computed(1.0, "derived from K0_nc and Eoed_ref (README)");
  d.real(&P::H, "H", "kPa", "cap hardening modulus at p_p = p_ref (derived unless given with alpha)")
      .greater_than(0.0)
      .defaults_to_computed(1.0, "derived from K0_nc and Eoed_ref (README)");
  d.real(&P::tension, "tension", "kPa",
         "tension cut-off: largest principal stress (tension positive) at most this")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(&P::sigma_min, "sigma_min", "kPa",
         "floor of sigma_3 in the stiffness laws (keeps the moduli positive)")
      .greater_than(0.0)
      .defaults_to(1.0);
  d.real(&P::OCR, "OCR", "-", "initial cap pressure p_p0 = OCR p_eq(initial stress)")
      .at_least(1.0)
      .defaults_to(1.0);
  d.real(&P::p_p0, "p_p0", "kPa", "lower bound of the initial cap pressure").at_least(0.0).defaults_to(0.0);
  d.flag(&P::small_strain, "small_strain",
         "small-strain overlay (Benz 2007: strain history tensor, reversals per principal direction; README)")
      .defaults_to(false);
  d.real(&P::G0_ref, "G0_ref", "kPa", "small-strain shear modulus at sigma_3 = p_ref (small_strain only)")
      .greater_than(0.0)
      .defaults_to_computed(1.0, "none: required when small_strain = true");
  d.real(&P::gamma_07, "gamma_07", "-", "shear strain at which G_s = 0.722 G0 (small_strain only)")
      .greater_than(0.0)
      .defaults_to_computed(1e-4, "none: required when small_strain = true");
  d.check([](const P& m, const Params& p) -> std::optional<Problem> {
    if (m.Eur_ref <= 2.0 * m.E50_ref)
      return Problem{"Eur_ref", "Eur_ref = " + number(m.Eur_ref) +
                                    " must exceed 2 E50_ref = " + number(2.0 * m.E50_ref) +
                                    " (the shear hyperbola needs q_a/E50 > 2/E_ur at q = 0)"};
    const double apex = m.c * std::cos(hs::radians(m.phi)) / std::sin(hs::radians(m.phi));
    if (m.tension > apex + 1e-12)
      return Problem{"tension", "tension = " + number(m.tension) +
                                    " must not exceed the Mohr-Coulomb apex c cot(phi) = " + number(apex)};
    if (m.small_strain) {
      if (!p.where("G0_ref").known() || !p.where("gamma_07").known())
        return Problem{"small_strain", "small_strain = true needs G0_ref and gamma_07"};
      if (m.G0_ref <= m.Eur_ref / (2.0 * (1.0 + m.nu_ur)))
        return Problem{"G0_ref", "G0_ref = " + number(m.G0_ref) +
                                     " must exceed G_ur_ref = Eur_ref / (2 (1 + nu_ur)) = " +
                                     number(m.Eur_ref / (2.0 * (1.0 + m.nu_ur)))};
    }
    const bool given_alpha = p.where("alpha").known(), given_H = p.where("H").known();
    if (given_alpha != given_H)
      return Problem{given_alpha ? "alpha" : "H",
                     "give both alpha and H, or neither (then both are derived from K0_nc and Eoed_ref)"};
    return std::nullopt;
  });
  return d;
}

std::unique_ptr<stratum::Material> create(hs::Parameters m, const Params& p) {
  if (!p.where("K0_nc").known()) m.K0_nc = 1.0 - std::sin(hs::radians(m.phi));
  if (!p.where("alpha").known()) {
    m.alpha = m.H = 0.0; // derived below (the calibration does not read them)
    const auto cap = hs::calibrate_cap(m);
    if (!cap)
      throw Error(p.where("Eoed_ref").known() ? p.where("Eoed_ref") : p.where("K0_nc"),
                  stratum::message_prefix(p) + "no cap (alpha, H) reproduces K0_nc = " + number(m.K0_nc) +
                      " and Eoed_ref = " + number(m.Eoed_ref) +
                      " on the oedometer path at sigma_1 = p_ref (Eoed_ref too large for the shear "
                      "hardening alone, or K0_nc outside what the cap can give); give alpha and H instead");
    m.alpha = (*cap)[0];
    m.H = (*cap)[1];
  }
  return std::make_unique<hs::HardeningSoil>(m, m.alpha, m.H);
}

} // namespace

STRATUM_MATERIAL_PLUGIN(
    "hardening_soil",
    "Hardening Soil (Schanz et al. 1999): hyperbolic shear hardening, Mohr-Coulomb failure, volumetric "
    "cap, tension cut-off, stress-dependent stiffness; optional small-strain overlay (Benz 2007, strain "
    "history tensor)",
    declare(), create)
