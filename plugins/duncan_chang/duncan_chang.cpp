// Plugin entry point of the "duncan_chang" material: the factory with its schema, and the
// calibration target of the same name (`stratum fit duncan_chang`, duncan_chang_calibration.cpp).
// The model lives in duncan_chang.hpp, the schema in duncan_chang_schema.hpp (shared with the tests).
#include "duncan_chang_calibration.hpp"
#include "duncan_chang_schema.hpp"

#include "stratum/plugin.hpp"

#include <memory>

STRATUM_PLUGIN(registry) {
  namespace dc = stratum::duncan_chang;
  stratum::Factory<stratum::Material> f;
  f.name = "duncan_chang";
  f.summary = "Duncan-Chang hyperbolic hypoelastic model (E-nu or E-B form), unloading with E_ur by the F_sr "
              "or maximum-deviator criterion, stress recovery from total strain or incremental update, "
              "parameter sets by sigma_3 level";
  dc::declare(f.schema, dc::Family::duncan_chang);
  f.create = [](const stratum::Params& p) -> std::unique_ptr<stratum::Material> {
    return std::make_unique<dc::DuncanChang>(dc::read(p, dc::Family::duncan_chang));
  };
  registry.add(std::move(f));
  dc::register_calibration(registry);
}
