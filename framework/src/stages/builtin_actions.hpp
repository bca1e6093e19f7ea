// The framework's own stage actions, registered into every Analysis's registry before the
// scene is read (a plugin adds its own through its entry point; stratum/stage_action.hpp).
#pragma once

#include "stratum/model.hpp"
#include "stratum/registry.hpp"
#include "stratum/stage_action.hpp"

#include <string>
#include <vector>

namespace stratum::stage {

/// geostatic, deactivate, activate, pressure, load, force, gravity, remove, displacement,
/// reset_displacements, and those of register_water_actions.
void register_builtin_actions(Registry& registry);

/// drain, seal, water_level, inflow (stages/water_actions.cpp).
void register_water_actions(Registry& registry);

/// The phreatic level an action's keys give: `level_key` (a horizontal level) or the polyline
/// `<line_key>_x`, `<line_key>_y` (points of strictly increasing x); none when neither is given.
/// Throws a located Error when both are given, the lists differ in length, hold fewer than two
/// points or their x does not increase.
[[nodiscard]] PhreaticLevel read_phreatic_level(const Params& p, const std::string& level_key,
                                                const std::string& line_key, const std::string& context);
/// Adds the keys read_phreatic_level reads for a polyline to a schema.
void declare_phreatic_line(Schema& g, const std::string& line_key);
/// A polyline that does not reach both sides of the mesh (its ends inside the mesh's x range)
/// leaves part of the mesh to a guess: a located Error at `<line_key>_x`.
void require_line_spans_mesh(const StageCheck& scene, const Params& p, const PhreaticLevel& level,
                             const std::string& line_key);

/// Their `type` names in the order the documentation and the messages list them.
[[nodiscard]] const std::vector<std::string>& builtin_action_types();

} // namespace stratum::stage
