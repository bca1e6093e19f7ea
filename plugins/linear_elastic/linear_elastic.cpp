// Plugin entry point of the "linear_elastic" material: the factory and its parameters, each
// declared once (stratum/parameters.hpp) and bound to its member. The material itself lives in
// elastic_math.hpp (shared with the tests).
#include "elastic_math.hpp"

#include "common/material_plugin.hpp"
#include "stratum/parameters.hpp"

#include <memory>
#include <string>

namespace {

using stratum::Params;
using stratum::Problem;
namespace le = stratum::linear_elastic;

stratum::Declared<le::Settings> declare() {
  using S = le::Settings;
  stratum::Declared<S> d;
  d.choice(&S::cross_anisotropic, "anisotropy", {{"isotropic", false}, {"cross_anisotropic", true}},
           "isotropic, or cross-anisotropic (transversely isotropic about the vertical y axis)")
      .defaults_to(std::string("isotropic"));
  stratum::declare_isotropic_elastic(d, &S::E, &S::nu,
                                     "Young's modulus; the horizontal modulus Eh when cross-anisotropic",
                                     "Poisson's ratio; nu_hh (horizontal-horizontal) when cross-anisotropic");
  d.real(&S::Ev, "Ev", "kPa", "cross-anisotropic only: vertical Young's modulus; 0 means Ev = E")
      .at_least(0.0)
      .defaults_to(0.0);
  d.real(&S::nu_vh, "nu_vh", "-",
         "cross-anisotropic only: horizontal strain per vertical strain under vertical stress "
         "(eps_h = -nu_vh sigma_v / Ev); -1 means nu_vh = nu")
      .at_least(-1.0)
      .defaults_to(-1.0);
  d.real(&S::Gvh, "Gvh", "kPa",
         "cross-anisotropic only: shear modulus in vertical planes; 0 means Ev / (2 (1 + nu_vh))")
      .at_least(0.0)
      .defaults_to(0.0);
  d.check([](const S& s, const Params& p) -> std::optional<Problem> {
    // The cross-anisotropic constants are meaningless when isotropic: refuse them rather than ignore them.
    if (!s.cross_anisotropic) {
      for (const char* name : {"Ev", "nu_vh", "Gvh"})
        if (p.where(name).known())
          return Problem{name, std::string(name) + " is only used with anisotropy = \"cross_anisotropic\""};
      return std::nullopt;
    }
    const le::CrossAnisotropic c = le::resolve(s);
    if (auto problem = le::check(c)) return problem;
    if (!le::positive_definite(le::cross_anisotropic_stiffness(c)))
      return Problem{"nu_vh", "the cross-anisotropic stiffness is not positive definite"};
    return std::nullopt;
  });
  return d;
}

std::unique_ptr<stratum::Material> create(const le::Settings& s, const Params&) {
  if (!s.cross_anisotropic) return std::make_unique<le::LinearElastic>(le::isotropic_stiffness(s.E, s.nu));
  return std::make_unique<le::LinearElastic>(le::cross_anisotropic_stiffness(le::resolve(s)));
}

} // namespace

STRATUM_MATERIAL_PLUGIN("linear_elastic",
                        "linear elastic solid, isotropic or cross-anisotropic (vertical y axis of symmetry)",
                        declare(), create)
