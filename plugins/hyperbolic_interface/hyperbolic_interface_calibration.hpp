// The hyperbolic (Clough-Duncan) interface calibration target: `stratum fit hyperbolic_interface
// DIRECT_SHEAR.csv` fits this plugin's contact-law parameters to direct-shear curves
// (hyperbolic_interface_calibration.cpp, docs/calibration.md).
#pragma once

#include "stratum/registry.hpp"

namespace stratum::hyperbolic_interface {

/// Adds the calibration target "hyperbolic_interface" (called by the plugin's entry point).
void register_calibration(Registry& registry);

} // namespace stratum::hyperbolic_interface
