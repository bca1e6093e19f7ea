// Plugin entry point of the "cam_clay" and "modified_cam_clay" materials: the two
// factories with their parameters, each declared once (stratum/parameters.hpp) and bound to
// its member. The models live in cam_clay.hpp (shared with the tests).
#include "cam_clay.hpp"

#include "stratum/parameters.hpp"
#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Params;
using stratum::Problem;
namespace cc = stratum::cam_clay;
namespace pl = stratum::plasticity;

/// What the parameters fill: the constants and the initial state.
struct Input {
  cc::Constants c;
  cc::Initial init;
};

stratum::Declared<Input> declare() {
  using stratum::nested;
  stratum::Declared<Input> d;
  d.real(nested(&Input::c, &cc::Constants::M), "M", "-",
         "critical-state stress ratio q/p in triaxial compression")
      .greater_than(0.0);
  d.real(nested(&Input::c, &cc::Constants::lambda), "lambda", "-",
         "slope of the normal compression line, v against ln p")
      .greater_than(0.0);
  d.real(nested(&Input::c, &cc::Constants::kappa), "kappa", "-",
         "slope of the swelling line, v against ln p; must be smaller than lambda")
      .greater_than(0.0);
  d.real(nested(&Input::c, &cc::Constants::e0), "e0", "-",
         "initial void ratio; v0 = 1 + e0 is the specific volume used throughout")
      .greater_than(0.0);
  d.real(nested(&Input::c, &cc::Constants::nu), "nu", "-",
         "Poisson's ratio giving G = 3 K (1 - 2 nu) / (2 (1 + nu)) with K = v0 p / kappa (when G = 0)")
      .greater_than(-1.0)
      .less_than(0.5)
      .defaults_to(0.3);
  d.real(nested(&Input::c, &cc::Constants::G), "G", "kPa",
         "constant shear modulus; 0 means G proportional to p through nu")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(
       nested(&Input::init, &cc::Initial::ocr), "ocr", "-",
       "isotropic overconsolidation ratio: p_c0 = ocr times the p_c of the yield surface through the initial "
       "stress (ocr * p0 for an isotropic p0)")
      .at_least(1.0)
      .defaults_to(1.0);
  d.real(nested(&Input::init, &cc::Initial::pc0), "pc0", "kPa",
         "explicit initial preconsolidation pressure p_c0; 0 means use ocr")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(nested(&Input::c, &cc::Constants::p_min), "p_min", "kPa",
         "smallest mean effective stress: the stiffness below it is that at p_min, and an increment that "
         "pulls p below it fails (no tension)")
      .greater_than(0.0)
      .defaults_to(1.0);
  pl::add_integrator_parameters(d.schema(), pl::Scheme::closest_point);
  d.check([](const Input& in) { return cc::check(in.c); });
  d.check([](const Input& in, const Params& p) -> std::optional<Problem> {
    if (in.c.G > 0.0 && p.where("nu").known())
      return Problem{"nu", "give nu or a constant G, not both (nu is unused when G > 0)"};
    if (in.init.pc0 > 0.0 && p.where("ocr").known()) return Problem{"ocr", "give ocr or pc0, not both"};
    return std::nullopt;
  });
  return d;
}

std::unique_ptr<stratum::Material> create(const Input& in, const Params& p) {
  return std::make_unique<cc::CamClay>(in.c, in.init, pl::read_integrator_parameters(p));
}

/// The start of the reading: the variant, which no parameter sets.
Input variant(cc::Variant v) {
  Input in;
  in.c.variant = v;
  return in;
}

} // namespace

STRATUM_PLUGIN(registry) {
  registry.add(stratum::material_factory(
      "cam_clay",
      "original Cam-Clay (Roscoe & Schofield): yield eta = M ln(p_c/p), associated flow, v-ln p hardening, "
      "pressure-dependent elasticity",
      declare(), create, variant(cc::Variant::original)));
  registry.add(stratum::material_factory("modified_cam_clay",
                                         "Modified Cam-Clay (Roscoe & Burland): elliptic yield locus q^2 + "
                                         "M^2 p (p - p_c) = 0, associated flow, "
                                         "v-ln p hardening, pressure-dependent elasticity",
                                         declare(), create, variant(cc::Variant::modified)));
}
