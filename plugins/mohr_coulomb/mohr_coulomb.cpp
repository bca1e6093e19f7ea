// Plugin entry point of the "mohr_coulomb" material: the factory with its schema.
// The models and the material live in mohr_coulomb.hpp (shared with the tests).
#include "mohr_coulomb.hpp"

#include "stratum/elasticity.hpp"
#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
namespace mc = stratum::mohr_coulomb;
namespace pl = stratum::plasticity;

std::unique_ptr<stratum::Material> create(const Params& p) {
  mc::Parameters m;
  m.E = p.real("E");
  m.nu = p.real("nu");
  m.c = p.real("c");
  m.phi = p.real("phi");
  m.psi = p.real("psi");
  m.tension = p.real("tension");
  m.form = p.text("form") == "rounded" ? mc::Form::rounded : mc::Form::exact;
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  if (m.psi > m.phi)
    throw Error(p.where("psi"), prefix + "the dilatancy angle psi = " + std::to_string(m.psi) +
                                    " must not exceed the friction angle phi = " + std::to_string(m.phi));
  if (m.phi == 0.0 && m.c <= 0.0)
    throw Error(p.where("c"), prefix +
                                  "phi = 0 (Tresca) needs a cohesion c > 0 (the undrained strength s_u); "
                                  "with c = 0 the material has no strength");
  if (m.tension < 0.0 && m.tension != -1.0)
    throw Error(p.where("tension"), prefix + "tension must be >= 0, or -1 for no cut-off");
  if (m.form == mc::Form::rounded && mc::effective_tension(m) >= 0.0)
    throw Error(p.where("tension"), prefix + "the tension cut-off needs form = \"exact\" (the rounded form "
                                             "has no cut-off planes)");
  const pl::Settings settings = pl::read_integrator_parameters(p);
  if (m.form == mc::Form::exact && p.where("integrator").known() &&
      settings.scheme != pl::Scheme::closest_point)
    throw Error(p.where("integrator"), prefix +
                                           "form = \"exact\" always uses its closed-form closest-point "
                                           "return in principal space; integrator = \"" +
                                           std::string(pl::to_string(settings.scheme)) +
                                           "\" applies to form = \"rounded\" only");
  return std::make_unique<mc::MohrCoulomb>(m, settings);
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "mohr_coulomb";
  f.summary = "perfectly plastic Mohr-Coulomb, exact pyramid (principal-space return, tension cut-off) or "
              "Gudehus-rounded, non-associated flow";
  stratum::add_isotropic_elastic_parameters(f.schema);
  f.schema.real("c", "kPa", "cohesion").at_least(0.0);
  f.schema
      .real("phi", "deg",
            "friction angle; 0 gives Tresca with (sigma_1 - sigma_3) / 2 = c (then psi = 0 and c > 0)")
      .at_least(0.0)
      .less_than(90.0);
  f.schema
      .real("psi", "deg",
            "dilatancy angle of the plastic potential, at most phi (psi = phi: associated flow)")
      .at_least(0.0)
      .less_than(90.0)
      .defaults_to(0.0);
  f.schema
      .real("tension", "kPa",
            "tension cut-off: largest allowed principal stress (exact form only); -1: none, i.e. the apex "
            "c cot(phi) (none at all for phi = 0)")
      .at_least(-1.0)
      .defaults_to(-1.0);
  f.schema
      .text("form", {"exact", "rounded"},
            "exact hexagonal pyramid, or corners rounded after Gudehus (smooth except at the apex)")
      .defaults_to(std::string("exact"));
  pl::add_integrator_parameters(f.schema);
  f.create = create;
  registry.add(std::move(f));
}
