// Plugin entry point of the "nonlinear_elastic_no_tension" material: its parameters, each declared
// once (stratum/parameters.hpp) and bound to its member (model in the header).
#include "nonlinear_elastic_no_tension.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <memory>

namespace {

namespace ne = stratum::nonlinear_elastic;

stratum::Declared<ne::Constants> declare() {
  using C = ne::Constants;
  stratum::Declared<C> d;
  d.real(&C::A, "A", "-", "bulk modulus number: K_t = A p_a (p/p_a)^n (2.18)").greater_than(0.0);
  d.real(&C::n, "n", "-", "bulk modulus exponent (2.18), about 1/3 to 1/2").at_least(0.0).less_than(1.0);
  d.real(&C::B, "B", "-", "shear modulus number: G_t = B p_a (p/p_a)^m (2.19)").greater_than(0.0);
  d.real(&C::m, "m", "-", "shear modulus exponent (2.19)").at_least(0.0).less_than(1.0);
  d.real(&C::p_a, "p_a", "kPa", "atmospheric pressure").greater_than(0.0).defaults_to(100.0);
  d.real(&C::p_min, "p_min", "kPa", "smallest mean pressure used in the moduli")
      .greater_than(0.0)
      .defaults_to(1.0);
  d.real(&C::tensile_strength, "tensile_strength", "kPa",
         "largest principal stress (tension positive) the material carries")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(&C::max_substep_strain, "max_substep_strain", "-", "largest strain component change per substep")
      .greater_than(0.0)
      .defaults_to(1e-4);
  return d;
}

} // namespace

STRATUM_MATERIAL_PLUGIN("nonlinear_elastic_no_tension",
                        "hypoelastic K_t = A p_a (p/p_a)^n, G_t = B p_a (p/p_a)^m (Hertz "
                        "type, (2.18)-(2.19)) with a principal-stress "
                        "tension cut-off",
                        declare(), stratum::material_plugin::from_input<ne::NoTension>)
