// Plugin entry point of the example_kg_elastic material: its parameters, each declared once and
// bound to the member it fills, and the factory made from them.
#include "kg_elastic.hpp"

#include <stratum/parameters.hpp>
#include <stratum/plugin.hpp>

#include <memory>

namespace {

/// What the parameters fill.
struct Constants {
  double K = 0.0; ///< bulk modulus (kPa)
  double G = 0.0; ///< shear modulus (kPa)
};

/// Each parameter spelled once: the member it fills, its key, unit, meaning and range.
stratum::Declared<Constants> parameters() {
  stratum::Declared<Constants> d;
  d.real(&Constants::K, "K", "kPa", "bulk modulus: mean stress per volumetric strain").greater_than(0.0);
  d.real(&Constants::G, "G", "kPa", "shear modulus: shear stress per engineering shear strain")
      .greater_than(0.0);
  // The scene reader checks presence, type and range before create() runs: K > 0 and G > 0
  // is all an isotropic solid needs to be stable, so there is no check on several parameters.
  return d;
}

} // namespace

STRATUM_PLUGIN(registry) {
  registry.add(stratum::material_factory(
      "example_kg_elastic", // what scenes write as  model = "example_kg_elastic"
      "isotropic linear elastic solid given by bulk modulus K and shear modulus G (SDK example)",
      parameters(), [](const Constants& c, const stratum::Params&) {
        return std::make_unique<example_kg::KGElastic>(c.K, c.G);
      }));
}
