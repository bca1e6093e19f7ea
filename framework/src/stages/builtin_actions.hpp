// The framework's own stage actions, registered into every Analysis's registry before the
// scene is read (a plugin adds its own through its entry point; stratum/stage_action.hpp).
#pragma once

#include "stratum/registry.hpp"

#include <string>
#include <vector>

namespace stratum::stage {

/// geostatic, deactivate, activate, pressure, load, force, gravity, remove, displacement,
/// reset_displacements, and those of register_water_actions.
void register_builtin_actions(Registry& registry);

/// drain, seal, water_level (stages/water_actions.cpp).
void register_water_actions(Registry& registry);

/// Their `type` names in the order the documentation and the messages list them.
[[nodiscard]] const std::vector<std::string>& builtin_action_types();

} // namespace stratum::stage
