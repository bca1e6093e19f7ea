// Plugin entry point of the "coulomb_elastoplastic" contact law (coulomb_elastoplastic.hpp).
#include "coulomb_elastoplastic.hpp"

#include "stratum/plugin.hpp"

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::ContactLaw> f;
  f.name = "coulomb_elastoplastic";
  f.summary = "elastoplastic Coulomb interface (thesis 3.56-3.60), dilation angle, tension cut-off";
  f.schema = stratum::coulomb_interface::schema();
  f.create = stratum::coulomb_interface::create;
  registry.add(std::move(f));
}
