// What the outputs see of a run: the model and the scene's settings, and where the run stands,
// all read-only. The run (run/) keeps a RunState up to date; the writers here (the VTK step,
// the tables, the summary) take a RunView and change nothing. Internal to the framework.
#pragma once

#include "model/scene_interfaces.hpp"
#include "scene/scene.hpp"
#include "stratum/model.hpp"
#include "stratum/units.hpp"

#include <array>
#include <limits>
#include <string>
#include <vector>

namespace stratum {

/// Where a run stands, for what its outputs say about it.
struct RunState {
  std::string stage_name = "initial"; ///< the stage running
  int stage_number = 0, stage_step = 0;
  double time = 0.0; ///< output time: stage number - 1 + load factor
  /// The pile head's load and settlement where a head is monitored (NaN otherwise).
  double head_load = std::numeric_limits<double>::quiet_NaN(),
         head_settlement = std::numeric_limits<double>::quiet_NaN();
  /// The loads of the running stage: name, how the stage applies it (0: on throughout, +1:
  /// applied over the stage, its value lambda x the full one, -1: removed over the stage,
  /// 1 - lambda) and its full vertical resultant (kN, y up).
  struct StageLoad {
    std::string name;
    int ramp = 0;
    double fy = 0.0;
  };
  std::vector<StageLoad> stage_loads;
  /// What the pile monitor observed (output/pile_monitor.hpp): (load, depth, axial force) and
  /// (load, y, shear, normal, slip (mm), status) rows of every recorded step.
  std::vector<std::array<double, 3>> axial_rows;
  std::vector<std::array<double, 6>> shaft_rows;
};

/// A read-only view of a run for its outputs.
struct RunView {
  const Model& model;
  const Units& units;
  const scene::Settings& settings;
  const SceneInterfaces& interfaces;
  const RunState& state;
  const std::string& scene_path; ///< names the output files (its stem)
  const std::string& out_dir;
};

class VtkSeriesWriter;
struct RunSummary;
struct StepRecord;
class Recorder;

/// One VTK step of the run's current state (output/write_step.cpp), and the CSV of every named
/// interface that asks for one.
void write_step(VtkSeriesWriter& writer, const RunView& run);

/// diagnostics.csv, the recorders' histories and the pile curves (curves/*.csv), each replaced
/// atomically (output/write_tables.cpp). `live`: the accepted steps of the running stage (its
/// failed attempts join at the stage's end).
void write_tables(const RunView& run, const RunSummary& summary, const std::vector<Recorder>& recorders,
                  const std::vector<StepRecord>& live);

/// The text of <out>/summary.toml for a run of `scene` with `stages` stages. `error`: the run
/// ended by an error of its environment (a result file that could not be written, memory that
/// ran out): ended = "failed", status = "error", message = `error`.
[[nodiscard]] std::string summary_toml(const RunSummary& summary, const std::string& scene,
                                       std::size_t stages, const std::string& error = {});
/// Writes <out>/summary.toml: how the run ended (output/write_summary.cpp).
void write_summary(const RunSummary& summary, const std::string& scene, std::size_t stages,
                   const std::string& error = {});

} // namespace stratum
