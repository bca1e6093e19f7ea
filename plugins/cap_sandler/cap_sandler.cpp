// Plugin entry point of the "cap_sandler" material: the factory and its parameters, each
// declared once (stratum/parameters.hpp) and bound to its member. The model and both
// integrators live in cap_sandler.hpp (shared with the tests); README.md explains the equations
// and the reading of the thesis' parameter names.
#include "cap_sandler.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <cmath>
#include <memory>
#include <string>

namespace {

using stratum::Params;
using stratum::Problem;
namespace cs = stratum::cap_sandler;

/// What the parameters fill: the constants and the choice of integrator.
struct Input {
  cs::Constants c;
  cs::Integration integration = cs::Integration::sandler_rubin;
  cs::Corner corner = cs::Corner::two_surface;
  double F_CUT = 0.0; ///< optional check value
};

stratum::Declared<Input> declare() {
  using stratum::nested;
  using C = cs::Constants;
  stratum::Declared<Input> d;
  stratum::declare_isotropic_elastic(d, nested(&Input::c, &C::E), nested(&Input::c, &C::nu),
                                     "Young's modulus (constant)", "Poisson's ratio (constant)");
  d.real(nested(&Input::c, &C::A), "A", "kPa",
         "envelope F_e = A - C exp(-B J1) + theta J1: sqrt(J2) strength at large J1")
      .greater_than(0.0);
  d.real(nested(&Input::c, &C::B), "B", "1/kPa", "envelope: exponential rate in J1 (J1 compression positive)")
      .greater_than(0.0);
  d.real(nested(&Input::c, &C::C), "C", "kPa", "envelope: A - C is the sqrt(J2) strength at J1 = 0")
      .greater_than(0.0);
  d.real(nested(&Input::c, &C::theta), "theta", "-", "envelope: linear slope in J1")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(nested(&Input::c, &C::D), "D", "1/kPa", "cap hardening rate in eps_v^p = W (1 - exp(-D (X - Z)))")
      .greater_than(0.0);
  d.real(nested(&Input::c, &C::W), "W", "-", "maximum plastic volumetric compaction")
      .greater_than(0.0)
      .less_than(1.0);
  d.real(nested(&Input::c, &C::R), "R", "-", "cap ellipse axis ratio (J1 axis over sqrt(J2) axis)")
      .greater_than(0.0);
  d.real(nested(&Input::c, &C::T), "T_CUT", "kPa", "tension cut-off on J1: hydrostatic tension J1 >= -T_CUT")
      .at_least(0.0);
  d.real(nested(&Input::c, &C::Z), "Z", "kPa",
         "initial cap position X0 in J1 (a stress outside the cap widens it at the start)")
      .defaults_to(0.0);
  d.choice(nested(&Input::c, &C::free_retraction), "retraction", {{"free", true}, {"above_initial", false}},
           "free: the hardening law (2.148) extended to dilatant eps_v^p < 0, the cap retracts without bound "
           "(tension and envelope flow can empty the elastic domain); above_initial: the cap tip never moves "
           "below its initial position X0 = Z")
      .defaults_to(std::string("free"));
  d.real(&Input::F_CUT, "F_CUT", "kPa",
         "optional check value: J1 tension where the envelope vanishes, ln(A/C)/B (the thesis prints it)")
      .greater_than(0.0)
      .defaults_to_computed(1.0, "ln(A/C)/B, computed");
  d.choice(
       &Input::integration, "integrator",
       {{"sandler_rubin", cs::Integration::sandler_rubin}, {"closest_point", cs::Integration::closest_point}},
       "sandler_rubin: the thesis' algorithm (4.51)-(4.69), continuum tangent; closest_point: "
       "backward-Euler return with the consistent tangent")
      .defaults_to(std::string("sandler_rubin"));
  d.choice(&Input::corner, "corner",
           {{"two_surface", cs::Corner::two_surface}, {"thesis", cs::Corner::thesis}},
           "sandler_rubin corner (envelope meets cap): two_surface = backward-Euler return on both surfaces; "
           "thesis = (4.61), stress held at the old corner with kappa kept (cannot follow stress-controlled "
           "paths through the corner)")
      .defaults_to(std::string("two_surface"));
  d.check([](const Input& in) { return cs::check(in.c); });
  // F_CUT is not independent: it is the J1 (tension) at which the envelope reaches sqrt(J2) = 0.
  d.check([](const Input& in, const Params& p) -> std::optional<Problem> {
    if (!p.where("F_CUT").known()) return std::nullopt;
    const double apex = -in.c.envelope_apex();
    if (std::abs(in.F_CUT - apex) > 1e-3 * apex)
      return Problem{"F_CUT", "F_CUT = " + stratum::number(in.F_CUT) +
                                  " must equal the hydrostatic tension at which the envelope vanishes, "
                                  "ln(A/C)/B = " +
                                  stratum::number(apex) + " kPa (to 0.1 %); omit it to have it computed"};
    return std::nullopt;
  });
  d.check([](const Input& in, const Params& p) -> std::optional<Problem> {
    if (in.integration == cs::Integration::closest_point && p.where("corner").known())
      return Problem{"corner", "corner applies to integrator = \"sandler_rubin\" only"};
    return std::nullopt;
  });
  return d;
}

std::unique_ptr<stratum::Material> create(const Input& in, const Params&) {
  return std::make_unique<cs::CapSandler>(in.c, in.integration, in.corner);
}

} // namespace

STRATUM_MATERIAL_PLUGIN(
    "cap_sandler",
    "DiMaggio-Sandler cap model: exponential failure envelope, elliptic hardening cap, tension cut-off, "
    "associated flow; Sandler-Rubin or closest-point integration",
    declare(), create)
