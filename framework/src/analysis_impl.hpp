// What an Analysis holds: the scene as read (framework/src/scene/), the stages
// (framework/src/stages/), and the state the run loop (framework/src/run/) and the
// outputs (framework/src/output/) share. Internal to the framework.
#pragma once

#include "recorders.hpp"
#include "scene/scene.hpp"
#include "scene/scene_fingerprint.hpp"
#include "scene/scene_interfaces.hpp"
#include "stages/stage.hpp"
#include "stratum/analysis.hpp"
#include "stratum/vtk_output.hpp"

#include <toml++/toml.h>

#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace stratum {

struct PileObservation; // output/pile_monitor.hpp

/// The text of <out>/summary.toml for a run of `scene` with `stages` stages.
[[nodiscard]] std::string summary_toml(const RunSummary& summary, const std::string& scene,
                                       std::size_t stages);

struct Analysis::Impl {
  std::string path, title;
  RunOptions options;
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::vector<std::unique_ptr<Material>> materials;
  std::vector<std::unique_ptr<Element>> elements;
  SceneInterfaces interfaces; ///< contact laws, interface elements, named interfaces
  /// The stage's solver: created afresh for every stage from the factory and its checked
  /// parameters, so that nothing a solver keeps (a reference load, a factorization) outlives
  /// the stage it was made for.
  std::unique_ptr<Solver> solver;
  const Factory<Solver>* solver_factory = nullptr;
  Params solver_params;
  Model model;
  Units units; ///< [units]: the scene's force and length (stratum/units.hpp)
  /// [analysis], [convergence] and [output] as read (threads resolved: 0 = the machine's cores).
  scene::Settings settings;
  std::vector<stage::Stage> stages;
  std::vector<stage::LoadSpec> loads; ///< loads applied at the current state, in order
  Eigen::VectorXd initial_prescribed; ///< [[constraints]] values, applied over the first stage
  std::string fingerprint;
  std::vector<std::string> warnings;  ///< Analysis::warnings()
  std::vector<FingerprintPart> parts; ///< checked on restart (scene_fingerprint.hpp)
  /// Adds the plugin libraries' parts to `parts` (once): only a run that writes or reads a
  /// checkpoint reads the library files.
  void add_library_parts() {
    if (library_parts_added) return;
    for (auto& part : library_parts(catalog->opened())) parts.push_back(std::move(part));
    library_parts_added = true;
  }
  bool library_parts_added = false;
  double time = 0.0; ///< output time: stage number - 1 + load factor
  // What the VTK field data of a step says (write_step): the stage running, its step, and the
  // pile head's load and settlement where a head is monitored (NaN otherwise).
  std::string stage_name = "initial";
  int stage_number = 0, stage_step = 0;
  double last_head_load = std::numeric_limits<double>::quiet_NaN(),
         last_head_settlement = std::numeric_limits<double>::quiet_NaN();
  /// The loads of the running stage for the VTK field data (write_step): name, how the stage
  /// applies it (0: on throughout, +1: applied over the stage, its value lambda x the full one,
  /// -1: removed over the stage, 1 - lambda) and its full vertical resultant (kN, y up).
  struct StageLoad {
    std::string name;
    int ramp = 0;
    double fy = 0.0;
  };
  std::vector<StageLoad> stage_loads;
  std::string out_dir; ///< where the run writes (for the interface CSV files)

  // Building the run's state from the scene as read (framework/src/scene/scene.hpp), in this
  // order; each step checks what needs the mesh and creates the plugins.
  void build(scene::Scene scene);
  void build_mesh(const scene::Scene& scene);
  void unused_physical_groups(const std::set<std::string>& named, const SourceLocation& at,
                              const std::string& file);
  void build_domains(const scene::Scene& scene);
  void build_constraints(const scene::Scene& scene);
  void build_stages(scene::Scene& scene); ///< moves the stage settings out of the scene
  /// Runs stage k; false when the run ends here (failure in summary.outcome, or an early stop).
  /// stage_loads from the loads before the stage's actions and `loads` after them (run_stage).
  void record_stage_loads(const std::vector<LoadSpec>& before);
  bool run_stage(std::size_t k, RunSummary& summary, VtkSeriesWriter* writer,
                 std::vector<std::array<double, 3>>& axial_rows);
  /// Adds what a pile monitor observed to the curves, the axial and shaft rows and the VTK field
  /// data's head load and settlement (nothing when it monitors no head; run_stage).
  void record_pile(const PileObservation& o, RunSummary& summary,
                   std::vector<std::array<double, 3>>& axial_rows);
  std::vector<std::array<double, 6>> shaft_rows; ///< load, y, shear, normal, slip (mm), status
  std::vector<Recorder> recorders;               ///< [[output.history]]
  std::vector<Check> checks;                     ///< [[checks]]
  void write_tables(const RunSummary& summary, const std::vector<std::array<double, 3>>& axial_rows,
                    const std::vector<StepRecord>& live);
  std::chrono::steady_clock::time_point last_tables = std::chrono::steady_clock::now();
  void write_step(VtkSeriesWriter& w, double time) const;
  /// <out>/summary.toml: how the run ended (output/write_summary.cpp).
  void write_summary(const RunSummary& summary) const;
};

} // namespace stratum
