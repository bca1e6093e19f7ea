// Plugin entry point of the "drucker_prager" material: the factory with its schema.
// The model and the material live in drucker_prager.hpp (shared with the tests).
#include "drucker_prager.hpp"

#include "stratum/elasticity.hpp"
#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
namespace dp = stratum::drucker_prager;

dp::Cone parse_cone(const std::string& name) {
  if (name == "extension") return dp::Cone::extension;
  if (name == "plane_strain") return dp::Cone::plane_strain;
  if (name == "inscribed") return dp::Cone::inscribed;
  return dp::Cone::compression;
}

std::unique_ptr<stratum::Material> create(const Params& p) {
  dp::Parameters m;
  m.E = p.real("E");
  m.nu = p.real("nu");
  m.c = p.real("c");
  m.phi = p.real("phi");
  m.psi = p.real("psi");
  m.H_c = p.real("H_c");
  m.cone = parse_cone(p.text("cone"));
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  if (m.psi > m.phi)
    throw Error(p.where("psi"), prefix + "the dilatancy angle psi = " + std::to_string(m.psi) +
                                    " must not exceed the friction angle phi = " + std::to_string(m.phi));
  return std::make_unique<dp::DruckerPrager>(m, stratum::plasticity::read_integrator_parameters(p));
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "drucker_prager";
  f.summary = "Drucker-Prager cone matched to Mohr-Coulomb, non-associated flow, linear cohesion hardening, "
              "closed-form apex return";
  stratum::add_isotropic_elastic_parameters(f.schema);
  f.schema.real("c", "kPa", "cohesion (initial value when H_c > 0)").at_least(0.0);
  f.schema.real("phi", "deg", "friction angle").greater_than(0.0).less_than(90.0);
  f.schema
      .real("psi", "deg",
            "dilatancy angle of the plastic potential, at most phi (psi = phi: associated flow)")
      .at_least(0.0)
      .less_than(90.0)
      .defaults_to(0.0);
  f.schema
      .text("cone", {"compression", "extension", "plane_strain", "inscribed"},
            "Mohr-Coulomb matching: through the compression corners (outer), through the extension corners, "
            "same plane-strain strength, or inscribed")
      .defaults_to(std::string("compression"));
  f.schema
      .real("H_c", "kPa", "linear hardening of the cohesion per unit accumulated plastic strain eps_bar_p")
      .at_least(0.0)
      .defaults_to(0.0);
  stratum::plasticity::add_integrator_parameters(f.schema);
  f.create = create;
  registry.add(std::move(f));
}
