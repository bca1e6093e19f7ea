// Staged analysis: a stage (its steps, its stop rules, its output) and its actions (small
// objects registered by `type`, stratum/stage_action.hpp; the framework's own in
// builtin_actions.cpp). Read from [[stages]] by scene/read_stages.cpp; run by run/run_stage.cpp.
#pragma once

#include "stratum/error.hpp"
#include "stratum/load.hpp"
#include "stratum/model.hpp"
#include "stratum/stage_action.hpp"

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

/// Sets the geostatic stress sigma_v = -gamma (surface - y), sigma_h = K0 sigma_v at every
/// integration point of the active cells in `cells` (history initialised for that stress).
void set_geostatic(Model& model, const std::vector<int>& cells, double gamma, double K0, double surface);

/// Initial stress of freshly placed cells: zero, or the fluid's hydrostatic -gamma (surface - y) I.
void set_placed_stress(Model& model, const std::vector<int>& cells, bool hydrostatic, double gamma,
                       double surface);

} // namespace stratum::stage
