// Plugin entry point of the "variable_kg" material: the Duncan-Chang hyperbola with a bulk modulus
// from E_i and a shear modulus from E_t (digest §3.2, "K_t, G_t model"; thesis §4.2.7 and the
// material list of DIS, §4.3). The model is duncan_chang::DuncanChang with Form::K_G.
#include "duncan_chang/duncan_chang_schema.hpp"

#include "stratum/plugin.hpp"

#include <memory>

STRATUM_PLUGIN(registry) {
  namespace dc = stratum::duncan_chang;
  stratum::Factory<stratum::Material> f;
  f.name = "variable_kg";
  f.summary = "hypoelastic K_t/G_t model: K_t = E_i/(3(1-2nu)), G_t = E_t/(2(1+nu)) with the Duncan-Chang "
              "E_i and E_t; E_ur on unloading (F_sr or maximum-deviator criterion)";
  dc::declare(f.schema, dc::Family::variable_kg);
  f.create = [](const stratum::Params& p) -> std::unique_ptr<stratum::Material> {
    return std::make_unique<dc::DuncanChang>(dc::read(p, dc::Family::variable_kg));
  };
  registry.add(std::move(f));
}
