// Staged analysis: a stage (its steps, its stop rules, its output) and its actions (small
// objects registered by `type`, stratum/stage_action.hpp; the framework's own in
// builtin_actions.cpp). Read from [[stages]] by scene/read_stages.cpp; run by run/run_stage.cpp.
#pragma once

#include "stratum/error.hpp"
#include "stratum/load.hpp"
#include "stratum/model.hpp"
#include "stratum/stage_action.hpp"

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace stratum::stage {

using stratum::LoadSpec;

struct Stage {
  std::string name;
  SourceLocation where;
  /// A consolidation stage lasts `duration` seconds of physical time (StepClock::transient), its
  /// load factor being the fraction elapsed; a static one takes none (undrained).
  bool consolidation = false;
  double duration = 0.0;              ///< s; 0 in a static stage
  double until_excess_pressure = 0.0; ///< consolidation: end once max |p| < this (kPa); 0: never
  int steps = 1;
  std::vector<double> increments; ///< load-factor increments (sum 1); empty: `steps` equal ones
  int max_cutbacks = 4;
  double error_tolerance = 0.0; ///< error-controlled load steps (step_control.hpp); 0: off
  std::vector<std::unique_ptr<StageAction>> actions; ///< applied in order when the stage starts
  bool reset_after = false;                          ///< zero the displacements at the end (geostatic stages)
  bool until_failure = false; ///< a step that fails after its cut-backs ends the run normally
  double collapse_stiffness =
      0.1;                      ///< until_failure: current-stiffness ratio below which a stop is a collapse
  double stop_settlement = 0.0; ///< > 0: stop once the monitored settlement exceeds it (m)
  std::string monitor;          ///< edge or node set whose mean vertical displacement is monitored
  bool vtk = true;
  int every = 1;
  bool checkpoint = true;
};

/// The at-rest state of a layer: a surcharge on the surface, the unit weight above the water table
/// and the saturated one below it, pore water hydrostatic in every vertical below a phreatic level
/// (horizontal or a polyline).
struct AtRest {
  double gamma = 0.0;     ///< unit weight above the water table (everywhere without one), kN/m3
  double gamma_sat = 0.0; ///< unit weight below the water table, kN/m3
  double K0 = 1.0;
  double surface = 0.0;   ///< ground level y, m
  double surcharge = 0.0; ///< vertical stress on the surface, kPa (compression positive)
  PhreaticLevel water;    ///< none: dry
  double gamma_w = 9.81;  ///< unit weight of water, kN/m3
  /// The steady pore pressure at (x, y), compression positive: gamma_w (level(x) - y) below the level.
  [[nodiscard]] double pore_pressure(double x, double y) const {
    const double top = water.at(x);
    return y < top ? gamma_w * (top - y) : 0.0;
  }
  /// The vertical effective stress at (x, y) (tension positive; 0 above the surface): the total
  /// weight of the soil (and of water standing above the surface) above it in its vertical, plus
  /// the surcharge, less the pore pressure.
  [[nodiscard]] double vertical_effective(double x, double y) const {
    if (!(y < surface)) return 0.0;
    const double level = water.at(x);
    const double wet_top = std::min(surface, level);
    const double below = std::max(wet_top - y, 0.0); // thickness under the water table
    const double above = (surface - y) - below;
    const double standing = level > surface ? gamma_w * (level - surface) : 0.0;
    return -(surcharge + standing + gamma * above + gamma_sat * below) + pore_pressure(x, y);
  }
};

/// Sets the geostatic effective stress sigma'_v = AtRest::vertical_effective(y), sigma'_h = K0
/// sigma'_v at every integration point of the active cells in `cells` (history initialised for
/// that stress); interface cells carry the normal traction on their plane.
void set_geostatic(Model& model, const std::vector<int>& cells, const AtRest& state);

/// Initial stress of freshly placed cells: zero, or the fluid's hydrostatic -gamma (surface - y) I.
void set_placed_stress(Model& model, const std::vector<int>& cells, bool hydrostatic, double gamma,
                       double surface);

} // namespace stratum::stage
