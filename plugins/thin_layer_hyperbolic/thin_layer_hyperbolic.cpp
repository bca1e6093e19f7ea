// Plugin entry point of the "thin_layer_hyperbolic" material: the factory and its parameters, each
// declared once (stratum/parameters.hpp) and bound to its member. The material itself lives in
// thin_layer_hyperbolic.hpp (shared with the tests).
#include "thin_layer_hyperbolic.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Params;
using stratum::Problem;
namespace tl = stratum::thin_layer_hyperbolic;

stratum::Declared<tl::Constants> declare() {
  using C = tl::Constants;
  stratum::Declared<C> d;
  stratum::declare_isotropic_elastic(d, &C::E, &C::nu,
                                     "Young's modulus of the normal behaviour (C1, C2 of (3.64))",
                                     "Poisson's ratio of the normal behaviour");
  d.real(&C::K_I, "K_I", "-",
         "modulus number: K_I gamma_w (sigma_n/p_a)^n is the shear modulus G_i (kPa) when thickness = 0, "
         "the interface shear stiffness k_s (kPa/m, G_i = thickness k_s) when thickness > 0")
      .greater_than(0.0);
  d.real(&C::n, "n", "-", "stress exponent of the shear modulus").at_least(0.0).defaults_to(0.5);
  d.real(&C::R_f, "R_f", "-", "failure ratio tau_f / tau_ult")
      .greater_than(0.0)
      .at_most(1.0)
      .defaults_to(0.9);
  d.real(&C::c_a, "c_a", "kPa", "adhesion").at_least(0.0).defaults_to(0.0);
  d.real(&C::delta, "delta", "deg", "interface friction angle")
      .at_least(0.0)
      .less_than(90.0)
      .defaults_to(0.0);
  d.real(&C::gamma_w, "gamma_w", "kN/m3", "unit weight of water in (3.65)")
      .greater_than(0.0)
      .defaults_to(9.81);
  d.real(&C::p_a, "p_a", "kPa", "atmospheric pressure").greater_than(0.0).defaults_to(100.0);
  d.real(&C::thickness, "thickness", "m",
         "layer thickness t: 0 reads K_I gamma_w (.)^n as G; > 0 reads it as k_s with G = t k_s (3.66)")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(&C::sigma_n_floor, "sigma_n_floor", "-",
         "lowest compressive normal stress used in G_i and tau_f, as a fraction of p_a (tension, zero)")
      .greater_than(0.0)
      .defaults_to(0.01);
  d.real(&C::residual, "residual_ratio", "-", "tangent shear modulus at failure as a fraction of G_i")
      .at_least(0.0)
      .defaults_to(1e-4);
  d.choice(&C::vertical, "orientation", {{"vertical", true}, {"horizontal", false}},
           "vertical: layer normal x, tangent y (pile shaft); horizontal: layer normal y, tangent x")
      .defaults_to(std::string("vertical"));
  d.check([](const C& c, const Params& p) -> std::optional<Problem> {
    if (!(c.tau_f(0.0) > 0.0))
      return Problem{
          p.where("c_a").known() ? "c_a" : "delta",
          "the strength c_a + sigma_n tan(delta) is zero at the floor sigma_n = sigma_n_floor p_a; "
          "allowed: c_a > 0 or delta > 0"};
    return std::nullopt;
  });
  return d;
}

} // namespace

STRATUM_MATERIAL_PLUGIN(
    "thin_layer_hyperbolic",
    "Desai-Zaman thin-layer interface material: plane-strain elastic normal behaviour, hyperbolic "
    "(Clough-Duncan) shear modulus (3.63)-(3.67)",
    declare(), stratum::material_plugin::from_input<tl::ThinLayerHyperbolic>)
