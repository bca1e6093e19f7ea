// What an Analysis holds: the model its scene built (model/), the observers the scene asks for
// (recorders and checks), and the state of the run that steps it (run/). The outputs (output/)
// see it through a RunView. Internal to the framework.
#pragma once

#include "model/scene_model.hpp"
#include "output/recorders.hpp"
#include "output/run_view.hpp"
#include "stratum/analysis.hpp"
#include "stratum/load.hpp"

#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace stratum {

struct PileObservation; // output/pile_monitor.hpp

struct Analysis::Impl {
  std::string path;
  RunOptions options;
  SceneModel sm;                   ///< the model and the plugin objects (model/scene_model.hpp)
  std::vector<Recorder> recorders; ///< [[output.history]]
  std::vector<Check> checks;       ///< [[checks]]

  // ---- the run (run/run.cpp, run/run_stage.cpp)
  std::unique_ptr<Solver> solver;     ///< the running stage's
  std::vector<stage::LoadSpec> loads; ///< loads applied at the current state, in order
  RunState state;                     ///< what the outputs say about where the run stands
  std::string out_dir;                ///< where the run writes
  std::chrono::steady_clock::time_point last_tables = std::chrono::steady_clock::now();

  /// The outputs' read-only view of the run.
  [[nodiscard]] RunView view() const {
    return {sm.model, sm.units, sm.settings, sm.interfaces, state, path, out_dir};
  }
  /// Runs stage k; false when the run ends here (failure in summary.outcome, or an early stop).
  bool run_stage(std::size_t k, RunSummary& summary, VtkSeriesWriter* writer);
  /// The stage's loads for the VTK field data, from the loads before the stage's actions and
  /// `loads` after them.
  void record_stage_loads(const std::vector<LoadSpec>& before);
  /// Adds what a pile monitor observed to the curves, the axial and shaft rows and the VTK field
  /// data's head load and settlement (nothing when it monitors no head).
  void record_pile(const PileObservation& o, RunSummary& summary);
  /// Writes the tables (when the run writes output) and notes when.
  void update_tables(const RunSummary& summary, const std::vector<StepRecord>& live);
};

} // namespace stratum
