// Plugin entry point of the "drucker_prager" material: the factory and its parameters, each
// declared once (stratum/parameters.hpp) and bound to its member. The model and the material
// live in drucker_prager.hpp (shared with the tests).
#include "drucker_prager.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <memory>
#include <string>

namespace {

namespace dp = stratum::drucker_prager;
namespace pl = stratum::plasticity;

stratum::Declared<dp::Parameters> declare() {
  using P = dp::Parameters;
  stratum::Declared<P> d;
  stratum::declare_isotropic_elastic(d, &P::E, &P::nu);
  stratum::StrengthText text;
  text.cohesion = "cohesion (initial value when H_c > 0)";
  stratum::declare_strength(d, &P::c, &P::phi, &P::psi, text);
  d.choice(&P::cone, "cone",
           {{"compression", dp::Cone::compression},
            {"extension", dp::Cone::extension},
            {"plane_strain", dp::Cone::plane_strain},
            {"inscribed", dp::Cone::inscribed}},
           "Mohr-Coulomb matching: through the compression corners (outer), through the extension corners, "
           "same plane-strain strength, or inscribed")
      .defaults_to(std::string("compression"));
  d.real(&P::H_c, "H_c", "kPa",
         "linear hardening of the cohesion per unit accumulated plastic strain eps_bar_p")
      .at_least(0.0)
      .defaults_to(0.0);
  pl::add_integrator_parameters(d.schema());
  return d;
}

} // namespace

STRATUM_MATERIAL_PLUGIN(
    "drucker_prager",
    "Drucker-Prager cone matched to Mohr-Coulomb, non-associated flow, linear cohesion hardening, "
    "closed-form apex return",
    declare(), stratum::material_plugin::with_integrator<dp::DruckerPrager>)
