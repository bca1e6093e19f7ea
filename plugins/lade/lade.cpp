// Plugin entry point of the "lade" material: the factory and its parameters, each declared once
// (stratum/parameters.hpp) and bound to its member. The model and its two-surface return live
// in lade.hpp (shared with the tests); README.md explains the equations, the integration and the
// parameter set.
#include "lade.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <memory>
#include <string>

namespace {

namespace ld = stratum::lade;

stratum::Declared<ld::Constants> declare() {
  using C = ld::Constants;
  stratum::Declared<C> d;
  d.real(&C::pa, "pa", "kPa", "atmospheric pressure used to normalise stresses and work")
      .greater_than(0.0)
      .defaults_to(100.0);
  d.real(&C::Kur, "K_ur", "-", "unload-reload modulus number: E_ur = K_ur pa (sigma3/pa)^n")
      .greater_than(0.0);
  d.real(&C::n, "n", "-", "unload-reload modulus exponent").at_least(0.0).less_than(1.0);
  d.real(&C::nu, "nu", "-", "Poisson's ratio (constant)").greater_than(-1.0).less_than(0.5).defaults_to(0.2);
  d.real(&C::eta1, "eta1", "-", "cone: value of (I1^3/I3 - 27)(I1/pa)^m at failure").greater_than(0.0);
  d.real(&C::m, "m", "-", "cone: curvature of the meridians (0 = straight)").at_least(0.0).less_than(1.5);
  d.real(&C::P, "P", "-", "cone hardening: plastic work at peak W_peak = P pa (sigma3/pa)^l")
      .greater_than(0.0);
  d.real(&C::l, "l", "-", "cone hardening: exponent of W_peak").defaults_to(1.0);
  d.real(&C::alpha, "alpha", "-", "cone hardening: q = alpha + beta sigma3/pa").greater_than(0.0);
  d.real(&C::beta, "beta", "-", "cone hardening: slope of q in sigma3/pa").defaults_to(0.0);
  d.real(&C::t, "t", "-", "plastic potential: eta2 = t + R sqrt(sigma3/pa) + S f_p").defaults_to(0.0);
  d.real(&C::R, "R", "-", "plastic potential: sqrt(sigma3/pa) coefficient of eta2").defaults_to(0.0);
  d.real(&C::S, "S", "-", "plastic potential: f_p coefficient of eta2").defaults_to(0.0);
  d.real(&C::C, "C", "-", "cap: collapse work W_c = C pa (f_c/pa^2)^p").greater_than(0.0);
  d.real(&C::p, "p", "-", "cap: collapse work exponent").greater_than(0.0);
  d.real(&C::s3_min, "sigma3_min", "kPa",
         "floor on sigma3 in E_ur, q, W_peak and eta2 (Lade's laws vanish at sigma3 = 0)")
      .greater_than(0.0)
      .defaults_to(1.0);
  d.integer(&C::substeps, "substeps", "-",
            "minimum number of equal substeps per update (the stress-dependent moduli and hardening "
            "constants are held at the start of each update; the count is doubled while the return fails)")
      .at_least(1)
      .at_most(1000)
      .defaults_to(1);
  d.check([](const C& c) { return ld::check(c); });
  return d;
}

} // namespace

STRATUM_MATERIAL_PLUGIN(
    "lade",
    "Lade (1977) double-hardening model: non-associated work-hardening cone, associated work-hardening "
    "spherical cap, stress-dependent unload-reload modulus; unsymmetric tangent",
    declare(), stratum::material_plugin::from_input<ld::Lade>)
