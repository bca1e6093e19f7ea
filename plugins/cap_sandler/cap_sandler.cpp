// Plugin entry point of the "cap_sandler" material: the factory and its schema. The model
// and both integrators live in cap_sandler.hpp (shared with the tests); README.md explains
// the equations and the reading of the thesis' parameter names.
#include "cap_sandler.hpp"

#include "stratum/plugin.hpp"

#include <cmath>
#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
namespace cs = stratum::cap_sandler;

std::unique_ptr<stratum::Material> create(const Params& p) {
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  cs::Constants c;
  c.E = p.real("E");
  c.nu = p.real("nu");
  c.A = p.real("A");
  c.B = p.real("B");
  c.C = p.real("C");
  c.theta = p.real("theta");
  c.D = p.real("D");
  c.W = p.real("W");
  c.R = p.real("R");
  c.T = p.real("T_CUT");
  c.Z = p.real("Z");
  c.free_retraction = p.text("retraction") == "free";
  if (const auto problem = cs::check(c)) throw Error(p.where(problem->parameter), prefix + problem->message);
  // F_CUT is not independent: it is the J1 (tension) at which the envelope reaches sqrt(J2) = 0.
  if (p.where("F_CUT").known()) {
    const double fcut = p.real("F_CUT"), apex = -c.envelope_apex();
    if (std::abs(fcut - apex) > 1e-3 * apex)
      throw Error(p.where("F_CUT"),
                  prefix + "F_CUT = " + cs::number(fcut) +
                      " must equal the hydrostatic tension at which the envelope vanishes, ln(A/C)/B = " +
                      cs::number(apex) + " kPa (to 0.1 %); omit it to have it computed");
  }
  const std::string& integ = p.text("integration");
  const cs::Integration integration =
      integ == "closest_point" ? cs::Integration::closest_point : cs::Integration::sandler_rubin;
  const cs::Corner corner = p.text("corner") == "thesis" ? cs::Corner::thesis : cs::Corner::two_surface;
  if (integration == cs::Integration::closest_point && p.where("corner").known())
    throw Error(p.where("corner"), prefix + "corner applies to integration = \"sandler_rubin\" only");
  return std::make_unique<cs::CapSandler>(c, integration, corner);
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "cap_sandler";
  f.summary = "DiMaggio-Sandler cap model: exponential failure envelope, elliptic hardening cap, tension "
              "cut-off, associated flow; Sandler-Rubin or closest-point integration";
  auto& s = f.schema;
  s.real("E", "kPa", "Young's modulus (constant)").greater_than(0.0);
  s.real("nu", "-", "Poisson's ratio (constant)").greater_than(-1.0).less_than(0.5).defaults_to(0.3);
  s.real("A", "kPa", "envelope F_e = A - C exp(-B J1) + theta J1: sqrt(J2) strength at large J1")
      .greater_than(0.0);
  s.real("B", "1/kPa", "envelope: exponential rate in J1 (J1 compression positive)").greater_than(0.0);
  s.real("C", "kPa", "envelope: A - C is the sqrt(J2) strength at J1 = 0").greater_than(0.0);
  s.real("theta", "-", "envelope: linear slope in J1").at_least(0.0).defaults_to(0.0);
  s.real("D", "1/kPa", "cap hardening rate in eps_v^p = W (1 - exp(-D (X - Z)))").greater_than(0.0);
  s.real("W", "-", "maximum plastic volumetric compaction").greater_than(0.0).less_than(1.0);
  s.real("R", "-", "cap ellipse axis ratio (J1 axis over sqrt(J2) axis)").greater_than(0.0);
  s.real("T_CUT", "kPa", "tension cut-off on J1: hydrostatic tension J1 >= -T_CUT").at_least(0.0);
  s.real("Z", "kPa", "initial cap position X0 in J1 (a stress outside the cap widens it at the start)")
      .defaults_to(0.0);
  s.text("retraction", {"free", "above_initial"},
         "free: the hardening law (2.148) extended to dilatant eps_v^p < 0, the cap retracts without "
         "bound (tension and envelope flow can empty the elastic domain); above_initial: the cap tip never "
         "moves below its initial position X0 = Z")
      .defaults_to(std::string("free"));
  s.real("F_CUT", "kPa",
         "optional check value: J1 tension where the envelope vanishes, ln(A/C)/B (the thesis prints it)")
      .greater_than(0.0)
      .defaults_to(1.0);
  s.text("integration", {"sandler_rubin", "closest_point"},
         "sandler_rubin: the thesis' algorithm (4.51)-(4.69), continuum tangent; closest_point: "
         "backward-Euler return with the consistent tangent")
      .defaults_to(std::string("sandler_rubin"));
  s.text("corner", {"two_surface", "thesis"},
         "sandler_rubin corner (envelope meets cap): two_surface = backward-Euler return on both surfaces; "
         "thesis = (4.61), stress held at the old corner with kappa kept (cannot follow stress-controlled "
         "paths through the corner)")
      .defaults_to(std::string("two_surface"));
  f.create = create;
  registry.add(std::move(f));
}
