// Plugin entry point of the "nonlinear_elastic_no_tension" material (model in the header).
#include "nonlinear_elastic_no_tension.hpp"

#include "stratum/plugin.hpp"

#include <memory>

STRATUM_PLUGIN(registry) {
  namespace ne = stratum::nonlinear_elastic;
  stratum::Factory<stratum::Material> f;
  f.name = "nonlinear_elastic_no_tension";
  f.summary = "hypoelastic K_t = A p_a (p/p_a)^n, G_t = B p_a (p/p_a)^m (Hertz type, (2.18)-(2.19)) with a "
              "principal-stress tension cut-off";
  auto& s = f.schema;
  s.real("A", "-", "bulk modulus number: K_t = A p_a (p/p_a)^n (2.18)").greater_than(0.0);
  s.real("n", "-", "bulk modulus exponent (2.18), about 1/3 to 1/2").at_least(0.0).less_than(1.0);
  s.real("B", "-", "shear modulus number: G_t = B p_a (p/p_a)^m (2.19)").greater_than(0.0);
  s.real("m", "-", "shear modulus exponent (2.19)").at_least(0.0).less_than(1.0);
  s.real("p_a", "kPa", "atmospheric pressure").greater_than(0.0).defaults_to(100.0);
  s.real("p_min", "kPa", "smallest mean pressure used in the moduli").greater_than(0.0).defaults_to(1.0);
  s.real("tensile_strength", "kPa", "largest principal stress (tension positive) the material carries")
      .at_least(0.0)
      .defaults_to(0.0);
  s.real("max_substep_strain", "-", "largest strain component change per substep")
      .greater_than(0.0)
      .defaults_to(1e-4);
  f.create = [](const stratum::Params& p) -> std::unique_ptr<stratum::Material> {
    ne::Constants c;
    c.A = p.real("A");
    c.n = p.real("n");
    c.B = p.real("B");
    c.m = p.real("m");
    c.p_a = p.real("p_a");
    c.p_min = p.real("p_min");
    c.tensile_strength = p.real("tensile_strength");
    c.max_substep_strain = p.real("max_substep_strain");
    return std::make_unique<ne::NoTension>(c);
  };
  registry.add(std::move(f));
}
