// Plugin entry point of the "von_mises" material: the factory with its schema.
// The model and the material live in von_mises.hpp (shared with the tests).
#include "von_mises.hpp"

#include "stratum/plugin.hpp"

#include <utility>

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Material> f;
  f.name = "von_mises";
  f.summary = "von Mises elastoplasticity with linear isotropic hardening (shared stress integrators)";
  f.schema = stratum::von_mises::schema();
  f.create = stratum::von_mises::create;
  registry.add(std::move(f));
}
