// Plugin entry point of the "thin_layer_hyperbolic" material: the factory with its schema.
// The material itself lives in thin_layer_hyperbolic.hpp (shared with the tests).
#include "thin_layer_hyperbolic.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
namespace tl = stratum::thin_layer_hyperbolic;

std::unique_ptr<stratum::Material> create(const Params& p) {
  tl::Constants c;
  c.E = p.real("E"), c.nu = p.real("nu");
  c.K_I = p.real("K_I"), c.n = p.real("n"), c.R_f = p.real("R_f");
  c.c_a = p.real("c_a"), c.delta = p.real("delta");
  c.gamma_w = p.real("gamma_w"), c.p_a = p.real("p_a");
  c.thickness = p.real("thickness");
  c.sigma_n_floor = p.real("sigma_n_floor");
  c.residual = p.real("residual_ratio");
  c.vertical = p.text("orientation") == "vertical";
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  if (!(c.tau_f(0.0) > 0.0))
    throw Error(p.where("c_a").known() ? p.where("c_a") : p.where("delta"),
                prefix +
                    "the strength c_a + sigma_n tan(delta) is zero at the floor sigma_n = sigma_n_floor p_a; "
                    "allowed: c_a > 0 or delta > 0");
  return std::make_unique<tl::ThinLayerHyperbolic>(c);
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "thin_layer_hyperbolic";
  f.summary = "Desai-Zaman thin-layer interface material: plane-strain elastic normal behaviour, "
              "hyperbolic (Clough-Duncan) shear modulus (3.63)-(3.67)";
  f.schema.real("E", "kPa", "Young's modulus of the normal behaviour (C1, C2 of (3.64))").greater_than(0.0);
  f.schema.real("nu", "-", "Poisson's ratio of the normal behaviour")
      .greater_than(-1.0)
      .less_than(0.5)
      .defaults_to(0.3);
  f.schema
      .real("K_I", "-",
            "modulus number: K_I gamma_w (sigma_n/p_a)^n is the shear modulus G_i (kPa) when thickness = 0, "
            "the interface shear stiffness k_s (kPa/m, G_i = thickness k_s) when thickness > 0")
      .greater_than(0.0);
  f.schema.real("n", "-", "stress exponent of the shear modulus").at_least(0.0).defaults_to(0.5);
  f.schema.real("R_f", "-", "failure ratio tau_f / tau_ult").greater_than(0.0).at_most(1.0).defaults_to(0.9);
  f.schema.real("c_a", "kPa", "adhesion").at_least(0.0).defaults_to(0.0);
  f.schema.real("delta", "deg", "interface friction angle").at_least(0.0).less_than(90.0).defaults_to(0.0);
  f.schema.real("gamma_w", "kN/m3", "unit weight of water in (3.65)").greater_than(0.0).defaults_to(9.81);
  f.schema.real("p_a", "kPa", "atmospheric pressure").greater_than(0.0).defaults_to(100.0);
  f.schema
      .real("thickness", "m",
            "layer thickness t: 0 reads K_I gamma_w (.)^n as G; > 0 reads it as k_s with G = t k_s (3.66)")
      .at_least(0.0)
      .defaults_to(0.0);
  f.schema
      .real("sigma_n_floor", "-",
            "lowest compressive normal stress used in G_i and tau_f, as a fraction of p_a (tension, zero)")
      .greater_than(0.0)
      .defaults_to(0.01);
  f.schema.real("residual_ratio", "-", "tangent shear modulus at failure as a fraction of G_i")
      .at_least(0.0)
      .defaults_to(1e-4);
  f.schema
      .text("orientation", {"vertical", "horizontal"},
            "vertical: layer normal x, tangent y (pile shaft); horizontal: layer normal y, tangent x")
      .defaults_to(std::string("vertical"));
  f.create = create;
  registry.add(std::move(f));
}
