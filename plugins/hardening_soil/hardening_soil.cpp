// Plugin entry point of the "hardening_soil" material: the factory and its schema. The model
// lives in hardening_soil.hpp (shared with the tests); README.md gives the equations.
#include "hardening_soil.hpp"

#include "stratum/plugin.hpp"

#include <cmath>
#include <memory>
#include <sstream>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
namespace hs = stratum::hardening_soil;

std::string num(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

std::unique_ptr<stratum::Material> create(const Params& p) {
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  hs::Parameters m;
  m.E50_ref = p.real("E50_ref");
  m.Eoed_ref = p.real("Eoed_ref");
  m.Eur_ref = p.real("Eur_ref");
  m.m = p.real("m");
  m.p_ref = p.real("p_ref");
  m.nu_ur = p.real("nu_ur");
  m.c = p.real("c");
  m.phi = p.real("phi");
  m.psi = p.real("psi");
  m.Rf = p.real("Rf");
  const double sphi = std::sin(hs::radians(m.phi));
  m.K0_nc = p.where("K0_nc").known() ? p.real("K0_nc") : 1.0 - sphi;
  m.tension = p.real("tension");
  m.sigma_min = p.real("sigma_min");
  m.OCR = p.real("OCR");
  m.p_p0 = p.real("p_p0");
  m.small_strain = p.flag("small_strain");
  m.G0_ref = p.real("G0_ref");
  m.gamma_07 = p.real("gamma_07");
  if (m.psi > m.phi)
    throw Error(p.where("psi"), prefix + "psi = " + num(m.psi) + " must not exceed phi = " + num(m.phi));
  if (m.Eur_ref <= 2.0 * m.E50_ref)
    throw Error(p.where("Eur_ref"), prefix + "Eur_ref = " + num(m.Eur_ref) +
                                        " must exceed 2 E50_ref = " + num(2.0 * m.E50_ref) +
                                        " (the shear hyperbola needs q_a/E50 > 2/E_ur at q = 0)");
  const double apex = m.c * std::cos(hs::radians(m.phi)) / sphi;
  if (m.tension > apex + 1e-12)
    throw Error(p.where("tension"), prefix + "tension = " + num(m.tension) +
                                        " must not exceed the Mohr-Coulomb apex c cot(phi) = " + num(apex));
  if (m.small_strain) {
    if (!p.where("G0_ref").known() || !p.where("gamma_07").known())
      throw Error(p.where("small_strain"), prefix + "small_strain = true needs G0_ref and gamma_07");
    if (m.G0_ref <= m.Eur_ref / (2.0 * (1.0 + m.nu_ur)))
      throw Error(p.where("G0_ref"), prefix + "G0_ref = " + num(m.G0_ref) +
                                         " must exceed G_ur_ref = Eur_ref / (2 (1 + nu_ur)) = " +
                                         num(m.Eur_ref / (2.0 * (1.0 + m.nu_ur))));
  }
  const bool given_alpha = p.where("alpha").known(), given_H = p.where("H").known();
  if (given_alpha != given_H)
    throw Error(p.where(given_alpha ? "alpha" : "H"),
                prefix + "give both alpha and H, or neither (then both are derived from K0_nc and Eoed_ref)");
  double alpha = p.real("alpha"), H = p.real("H");
  if (!given_alpha) {
    const auto cap = hs::calibrate_cap(m);
    if (!cap)
      throw Error(p.where("Eoed_ref").known() ? p.where("Eoed_ref") : p.where("K0_nc"),
                  prefix + "no cap (alpha, H) reproduces K0_nc = " + num(m.K0_nc) +
                      " and Eoed_ref = " + num(m.Eoed_ref) +
                      " on the oedometer path at sigma_1 = p_ref (Eoed_ref too large for the shear "
                      "hardening alone, or K0_nc outside what the cap can give); give alpha and H instead");
    alpha = (*cap)[0];
    H = (*cap)[1];
  }
  m.alpha = alpha;
  m.H = H;
  return std::make_unique<hs::HardeningSoil>(m, alpha, H);
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "hardening_soil";
  f.summary = "Hardening Soil (Schanz et al. 1999): hyperbolic shear hardening, Mohr-Coulomb failure, "
              "volumetric cap, tension cut-off, stress-dependent stiffness; optional small-strain stiffness "
              "(Benz 2007, scalar history)";
  auto& s = f.schema;
  s.real("E50_ref", "kPa",
         "secant stiffness at 50 % of the strength in drained triaxial compression at "
         "sigma_3 = p_ref")
      .greater_than(0.0);
  s.real("Eoed_ref", "kPa", "tangent oedometer stiffness at sigma_1 = p_ref (K0_nc loading)")
      .greater_than(0.0);
  s.real("Eur_ref", "kPa", "unloading-reloading Young's modulus at sigma_3 = p_ref").greater_than(0.0);
  s.real("m", "-", "stress exponent of the stiffness laws").at_least(0.0).at_most(1.0).defaults_to(0.5);
  s.real("p_ref", "kPa", "reference stress").greater_than(0.0).defaults_to(100.0);
  s.real("nu_ur", "-", "unloading-reloading Poisson's ratio")
      .greater_than(-1.0)
      .less_than(0.5)
      .defaults_to(0.2);
  s.real("c", "kPa", "cohesion").at_least(0.0).defaults_to(0.0);
  s.real("phi", "deg", "friction angle").greater_than(0.0).less_than(90.0);
  s.real("psi", "deg", "dilatancy angle (at most phi)").at_least(0.0).less_than(90.0).defaults_to(0.0);
  s.real("Rf", "-", "failure ratio q_f / q_a").greater_than(0.0).less_than(1.0).defaults_to(0.9);
  s.real("K0_nc", "-", "K0 of normal consolidation (default 1 - sin phi)")
      .greater_than(0.0)
      .less_than(1.0)
      .defaults_to(0.5);
  s.real("alpha", "-", "cap shape (derived from K0_nc and Eoed_ref unless given together with H)")
      .greater_than(0.0)
      .defaults_to(1.0);
  s.real("H", "kPa", "cap hardening modulus at p_p = p_ref (derived unless given with alpha)")
      .greater_than(0.0)
      .defaults_to(1.0);
  s.real("tension", "kPa", "tension cut-off: largest principal stress (tension positive) at most this")
      .at_least(0.0)
      .defaults_to(0.0);
  s.real("sigma_min", "kPa", "floor of sigma_3 in the stiffness laws (keeps the moduli positive)")
      .greater_than(0.0)
      .defaults_to(1.0);
  s.real("OCR", "-", "initial cap pressure p_p0 = OCR p_eq(initial stress)").at_least(1.0).defaults_to(1.0);
  s.real("p_p0", "kPa", "lower bound of the initial cap pressure").at_least(0.0).defaults_to(0.0);
  s.boolean("small_strain", "small-strain stiffness (Benz 2007, scalar history; README)").defaults_to(false);
  s.real("G0_ref", "kPa", "small-strain shear modulus at sigma_3 = p_ref (small_strain only)")
      .greater_than(0.0)
      .defaults_to(1.0);
  s.real("gamma_07", "-", "shear strain at which G_s = 0.722 G0 (small_strain only)")
      .greater_than(0.0)
      .defaults_to(1e-4);
  f.create = create;
  registry.add(std::move(f));
}
