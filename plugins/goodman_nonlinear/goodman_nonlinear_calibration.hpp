// The nonlinear Goodman calibration target: `stratum fit goodman_nonlinear DIRECT_SHEAR.csv
// [--k_s0 VALUE]` (also `stratum fit contact`) fits this plugin's contact-law parameters to
// direct-shear curves (goodman_nonlinear_calibration.cpp, docs/calibration.md).
#pragma once

#include "stratum/registry.hpp"

namespace stratum::goodman {

/// Adds the calibration targets "goodman_nonlinear" and "contact" (called by the entry point).
void register_calibration(Registry& registry);

} // namespace stratum::goodman
