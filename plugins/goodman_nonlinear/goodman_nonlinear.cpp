// Plugin entry point of the "goodman_nonlinear" contact law and its calibration target
// (goodman_nonlinear.hpp).
#include "goodman_nonlinear.hpp"
#include "goodman_nonlinear_calibration.hpp"

#include "stratum/plugin.hpp"

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::ContactLaw> f;
  f.name = "goodman_nonlinear";
  f.summary =
      "the thesis' nonlinear two-node interface law: tau-du curve with peak, residual and Q_max memory";
  f.schema = stratum::goodman::schema();
  f.create = stratum::goodman::create;
  registry.add(std::move(f));
  stratum::goodman::register_calibration(registry);
}
