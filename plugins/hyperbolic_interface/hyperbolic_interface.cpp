// Plugin entry point of the "hyperbolic_interface" contact law and its calibration target
// (hyperbolic_interface.hpp).
#include "hyperbolic_interface.hpp"
#include "hyperbolic_interface_calibration.hpp"

#include "stratum/plugin.hpp"

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::ContactLaw> f;
  f.name = "hyperbolic_interface";
  f.summary = "Clough-Duncan hyperbolic interface (thesis 3.65): nonlinear-elastic shear, sliding at tau_f";
  f.schema = stratum::hyperbolic_interface::schema();
  f.create = stratum::hyperbolic_interface::create;
  registry.add(std::move(f));
  stratum::hyperbolic_interface::register_calibration(registry);
}
