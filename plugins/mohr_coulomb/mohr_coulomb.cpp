// Plugin entry point of the "mohr_coulomb" material: the factory and its parameters, each
// declared once (stratum/parameters.hpp) and bound to its member. The models and the material
// live in mohr_coulomb.hpp (shared with the tests).
#include "mohr_coulomb.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Params;
using stratum::Problem;
namespace mc = stratum::mohr_coulomb;
namespace pl = stratum::plasticity;

stratum::Declared<mc::Parameters> declare() {
  using P = mc::Parameters;
  stratum::Declared<P> d;
  stratum::declare_isotropic_elastic(d, &P::E, &P::nu);
  stratum::StrengthText strength;
  strength.friction =
      "friction angle; 0 gives Tresca with (sigma_1 - sigma_3) / 2 = c (then psi = 0 and c > 0)";
  strength.zero_friction = true;
  stratum::declare_strength(d, &P::c, &P::phi, &P::psi, strength);
  d.real(&P::tension, "tension", "kPa",
         "tension cut-off: largest allowed principal stress (exact form only); -1: none, i.e. the apex "
         "c cot(phi)")
      .at_least(-1.0)
      .defaults_to(-1.0);
  d.choice(&P::form, "form", {{"exact", mc::Form::exact}, {"rounded", mc::Form::rounded}},
           "exact hexagonal pyramid, or corners rounded after Gudehus (smooth except at the apex)")
      .defaults_to(std::string("exact"));
  pl::add_integrator_parameters(d.schema());
  d.check([](const P& m) -> std::optional<Problem> {
    if (m.phi == 0.0 && m.c <= 0.0)
      return Problem{"c", "phi = 0 (Tresca) needs a cohesion c > 0 (the undrained strength s_u); with c = 0 "
                          "the material has no strength"};
    if (m.tension < 0.0 && m.tension != -1.0)
      return Problem{"tension", "tension must be >= 0, or -1 for no cut-off"};
    if (m.form == mc::Form::rounded && mc::effective_tension(m) >= 0.0)
      return Problem{"tension",
                     "the tension cut-off needs form = \"exact\" (the rounded form has no cut-off planes)"};
    return std::nullopt;
  });
  d.check([](const P& m, const Params& p) -> std::optional<Problem> {
    const pl::Scheme scheme = pl::read_integrator_parameters(p).scheme;
    if (m.form == mc::Form::exact && p.where("integrator").known() && scheme != pl::Scheme::closest_point)
      return Problem{"integrator",
                     "form = \"exact\" always uses its closed-form closest-point return in principal "
                     "space; integrator = \"" +
                         std::string(pl::to_string(scheme)) + "\" applies to form = \"rounded\" only"};
    return std::nullopt;
  });
  return d;
}

} // namespace

STRATUM_MATERIAL_PLUGIN(
    "mohr_coulomb",
    "perfectly plastic Mohr-Coulomb, exact pyramid (principal-space return, tension cut-off) or "
    "Gudehus-rounded, non-associated flow",
    declare(), stratum::material_plugin::with_integrator<mc::MohrCoulomb>)
