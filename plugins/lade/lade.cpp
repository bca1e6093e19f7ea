// Plugin entry point of the "lade" material: the factory and its schema. The model and its
// two-surface return live in lade.hpp (shared with the tests); README.md explains the
// equations, the integration and the parameter set.
#include "lade.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
namespace ld = stratum::lade;

std::unique_ptr<stratum::Material> create(const Params& p) {
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  ld::Constants c;
  c.pa = p.real("pa");
  c.Kur = p.real("K_ur");
  c.n = p.real("n");
  c.nu = p.real("nu");
  c.eta1 = p.real("eta1");
  c.m = p.real("m");
  c.P = p.real("P");
  c.l = p.real("l");
  c.alpha = p.real("alpha");
  c.beta = p.real("beta");
  c.t = p.real("t");
  c.R = p.real("R");
  c.S = p.real("S");
  c.C = p.real("C");
  c.p = p.real("p");
  c.s3_min = p.real("sigma3_min");
  c.substeps = static_cast<int>(p.integer("substeps"));
  if (const auto problem = ld::check(c)) throw Error(p.where(problem->parameter), prefix + problem->message);
  return std::make_unique<ld::Lade>(c);
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "lade";
  f.summary = "Lade (1977) double-hardening model: non-associated work-hardening cone, associated "
              "work-hardening spherical cap, stress-dependent unload-reload modulus; unsymmetric tangent";
  auto& s = f.schema;
  s.real("pa", "kPa", "atmospheric pressure used to normalise stresses and work")
      .greater_than(0.0)
      .defaults_to(100.0);
  s.real("K_ur", "-", "unload-reload modulus number: E_ur = K_ur pa (sigma3/pa)^n").greater_than(0.0);
  s.real("n", "-", "unload-reload modulus exponent").at_least(0.0).less_than(1.0);
  s.real("nu", "-", "Poisson's ratio (constant)").greater_than(-1.0).less_than(0.5).defaults_to(0.2);
  s.real("eta1", "-", "cone: value of (I1^3/I3 - 27)(I1/pa)^m at failure").greater_than(0.0);
  s.real("m", "-", "cone: curvature of the meridians (0 = straight)").at_least(0.0).less_than(1.5);
  s.real("P", "-", "cone hardening: plastic work at peak W_peak = P pa (sigma3/pa)^l").greater_than(0.0);
  s.real("l", "-", "cone hardening: exponent of W_peak").defaults_to(1.0);
  s.real("alpha", "-", "cone hardening: q = alpha + beta sigma3/pa").greater_than(0.0);
  s.real("beta", "-", "cone hardening: slope of q in sigma3/pa").defaults_to(0.0);
  s.real("t", "-", "plastic potential: eta2 = t + R sqrt(sigma3/pa) + S f_p").defaults_to(0.0);
  s.real("R", "-", "plastic potential: sqrt(sigma3/pa) coefficient of eta2").defaults_to(0.0);
  s.real("S", "-", "plastic potential: f_p coefficient of eta2").defaults_to(0.0);
  s.real("C", "-", "cap: collapse work W_c = C pa (f_c/pa^2)^p").greater_than(0.0);
  s.real("p", "-", "cap: collapse work exponent").greater_than(0.0);
  s.real("sigma3_min", "kPa",
         "floor on sigma3 in E_ur, q, W_peak and eta2 (Lade's laws vanish at sigma3 = 0)")
      .greater_than(0.0)
      .defaults_to(1.0);
  s.integer("substeps", "-",
            "minimum number of equal substeps per update (the stress-dependent moduli and hardening "
            "constants are held at the start of each update; the count is doubled while the return fails)")
      .at_least(1)
      .at_most(1000)
      .defaults_to(1);
  f.create = create;
  registry.add(std::move(f));
}
