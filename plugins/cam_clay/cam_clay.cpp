// Plugin entry point of the "cam_clay" and "modified_cam_clay" materials: the two
// factories with their schema. The models live in cam_clay.hpp (shared with the tests).
#include "cam_clay.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
using stratum::Schema;
namespace cc = stratum::cam_clay;

void declare(Schema& s) {
  s.real("M", "-", "critical-state stress ratio q/p in triaxial compression").greater_than(0.0);
  s.real("lambda", "-", "slope of the normal compression line, v against ln p").greater_than(0.0);
  s.real("kappa", "-", "slope of the swelling line, v against ln p; must be smaller than lambda")
      .greater_than(0.0);
  s.real("e0", "-", "initial void ratio; v0 = 1 + e0 is the specific volume used throughout")
      .greater_than(0.0);
  s.real("nu", "-",
         "Poisson's ratio giving G = 3 K (1 - 2 nu) / (2 (1 + nu)) with K = v0 p / kappa (when G = 0)")
      .greater_than(-1.0)
      .less_than(0.5)
      .defaults_to(0.3);
  s.real("G", "kPa", "constant shear modulus; 0 means G proportional to p through nu")
      .at_least(0.0)
      .defaults_to(0.0);
  s.real(
       "ocr", "-",
       "isotropic overconsolidation ratio: p_c0 = ocr times the p_c of the yield surface through the initial "
       "stress (ocr * p0 for an isotropic p0)")
      .at_least(1.0)
      .defaults_to(1.0);
  s.real("pc0", "kPa", "explicit initial preconsolidation pressure p_c0; 0 means use ocr")
      .at_least(0.0)
      .defaults_to(0.0);
  s.real("p_min", "kPa",
         "smallest mean effective stress: the stiffness below it is that at p_min, and an increment that "
         "pulls p "
         "below it fails (no tension)")
      .greater_than(0.0)
      .defaults_to(1.0);
  stratum::plasticity::add_integrator_parameters(s, stratum::plasticity::Scheme::closest_point);
}

std::unique_ptr<stratum::Material> create(cc::Variant variant, const Params& p) {
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";
  cc::Constants c;
  c.variant = variant;
  c.M = p.real("M");
  c.lambda = p.real("lambda");
  c.kappa = p.real("kappa");
  c.e0 = p.real("e0");
  c.nu = p.real("nu");
  c.G = p.real("G");
  c.p_min = p.real("p_min");
  if (const auto problem = cc::check(c)) throw Error(p.where(problem->parameter), prefix + problem->message);
  if (c.G > 0.0 && p.where("nu").known())
    throw Error(p.where("nu"), prefix + "give nu or a constant G, not both (nu is unused when G > 0)");
  cc::Initial init;
  init.ocr = p.real("ocr");
  init.pc0 = p.real("pc0");
  if (init.pc0 > 0.0 && p.where("ocr").known())
    throw Error(p.where("ocr"), prefix + "give ocr or pc0, not both");
  return std::make_unique<cc::CamClay>(c, init, stratum::plasticity::read_integrator_parameters(p));
}

} // namespace

STRATUM_PLUGIN(registry) {
  {
    stratum::Factory<stratum::Material> f;
    f.name = "cam_clay";
    f.summary = "original Cam-Clay (Roscoe & Schofield): yield eta = M ln(p_c/p), associated flow, "
                "v-ln p hardening, pressure-dependent elasticity";
    declare(f.schema);
    f.create = [](const Params& p) { return create(cc::Variant::original, p); };
    registry.add(std::move(f));
  }
  {
    stratum::Factory<stratum::Material> f;
    f.name = "modified_cam_clay";
    f.summary = "Modified Cam-Clay (Roscoe & Burland): elliptic yield locus q^2 + M^2 p (p - p_c) = 0, "
                "associated flow, v-ln p hardening, pressure-dependent elasticity";
    declare(f.schema);
    f.create = [](const Params& p) { return create(cc::Variant::modified, p); };
    registry.add(std::move(f));
  }
}
