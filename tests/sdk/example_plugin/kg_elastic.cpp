// Plugin entry point of the example_kg_elastic material: one factory with its schema.
#include "kg_elastic.hpp"

#include <stratum/plugin.hpp>

#include <memory>

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "example_kg_elastic"; // what scenes write as  model = "example_kg_elastic"
  f.summary = "isotropic linear elastic solid given by bulk modulus K and shear modulus G (SDK example)";
  f.schema.real("K", "kPa", "bulk modulus: mean stress per volumetric strain").greater_than(0.0);
  f.schema.real("G", "kPa", "shear modulus: shear stress per engineering shear strain").greater_than(0.0);
  // The scene reader has already checked presence, type and range: K > 0 and G > 0
  // is all an isotropic solid needs to be stable, so create() has nothing left to check.
  f.create = [](const stratum::Params& p) -> std::unique_ptr<stratum::Material> {
    return std::make_unique<example_kg::KGElastic>(p.real("K"), p.real("G"));
  };
  registry.add(std::move(f));
}
