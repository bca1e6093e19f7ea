// The Duncan-Chang calibration target: `stratum fit duncan_chang CURVES.csv [--form E_nu|E_B]`
// fits this plugin's material parameters to drained triaxial curves (duncan_chang_calibration.cpp,
// docs/calibration.md).
#pragma once

#include "stratum/registry.hpp"

namespace stratum::duncan_chang {

/// Adds the calibration target "duncan_chang" (called by the plugin's entry point).
void register_calibration(Registry& registry);

} // namespace stratum::duncan_chang
