// Plugin entry point of the "linear_elastic" material: the factory with its schema.
// The material itself lives in elastic_math.hpp (shared with the tests).
#include "elastic_math.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Error;
using stratum::Params;
namespace le = stratum::linear_elastic;

std::unique_ptr<stratum::Material> create(const Params& p) {
  le::Settings s;
  s.cross_anisotropic = p.text("anisotropy") == "cross_anisotropic";
  s.E = p.real("E");
  s.nu = p.real("nu");
  s.Ev = p.real("Ev");
  s.nu_vh = p.real("nu_vh");
  s.Gvh = p.real("Gvh");
  const std::string prefix = p.context.empty() ? std::string() : p.context + " ";

  if (!s.cross_anisotropic) {
    // The cross-anisotropic constants are meaningless here: refuse them rather than ignore them.
    for (const char* name : {"Ev", "nu_vh", "Gvh"})
      if (p.where(name).known())
        throw Error(p.where(name), prefix + name + " is only used with anisotropy = \"cross_anisotropic\"");
    return std::make_unique<le::LinearElastic>(le::isotropic_stiffness(s.E, s.nu));
  }

  const le::CrossAnisotropic c = le::resolve(s);
  if (const auto problem = le::check(c)) throw Error(p.where(problem->parameter), prefix + problem->message);
  const stratum::Mat6 D = le::cross_anisotropic_stiffness(c);
  if (!le::positive_definite(D))
    throw Error(p.where("nu_vh"), prefix + "the cross-anisotropic stiffness is not positive definite");
  return std::make_unique<le::LinearElastic>(D);
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "linear_elastic";
  f.summary = "linear elastic solid, isotropic or cross-anisotropic (vertical y axis of symmetry)";
  f.schema
      .text("anisotropy", {"isotropic", "cross_anisotropic"},
            "isotropic, or cross-anisotropic (transversely isotropic about the vertical y axis)")
      .defaults_to(std::string("isotropic"));
  f.schema.real("E", "kPa", "Young's modulus; the horizontal modulus Eh when cross-anisotropic")
      .greater_than(0.0);
  f.schema.real("nu", "-", "Poisson's ratio; nu_hh (horizontal-horizontal) when cross-anisotropic")
      .greater_than(-1.0)
      .less_than(0.5)
      .defaults_to(0.3);
  f.schema.real("Ev", "kPa", "cross-anisotropic only: vertical Young's modulus; 0 means Ev = E")
      .at_least(0.0)
      .defaults_to(0.0);
  f.schema
      .real("nu_vh", "-",
            "cross-anisotropic only: horizontal strain per vertical strain under vertical stress "
            "(eps_h = -nu_vh sigma_v / Ev); -1 means nu_vh = nu")
      .at_least(-1.0)
      .defaults_to(-1.0);
  f.schema
      .real("Gvh", "kPa",
            "cross-anisotropic only: shear modulus in vertical planes; 0 means Ev / (2 (1 + nu_vh))")
      .at_least(0.0)
      .defaults_to(0.0);
  f.create = create;
  registry.add(std::move(f));
}
