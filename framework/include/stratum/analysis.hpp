// From a scene file to results: read and validate the TOML, open the plugins
// the scene names, build the model, run the load steps, write the output.
//
// Everything that can be wrong with the input is found by prepare() (what
// `stratum check` runs) before any step is solved.
#pragma once

#include "stratum/model.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"
#include "stratum/solver.hpp"
#include "stratum/step_control.hpp"
#include "stratum/units.hpp"

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace stratum {

struct RunOptions {
  std::string out_dir;                  ///< empty: out/<scene stem> under the working directory
  std::string restart_from;             ///< a checkpoint to continue from (its later stages run)
  std::vector<std::string> plugin_dirs; ///< empty: PluginCatalog::default_directories()
  bool write_output = true;             ///< false: solve only (tests, benchmarks)
  /// Called after every accepted step (progress line, verbose diagnostics); may be empty.
  std::function<void(int step, int steps, double lambda, const StepReport&)> on_step;
  /// Called when a stage starts (before its first step): its name, its number (1-based) and the
  /// number of stages; may be empty. The progress line names the stage from it.
  std::function<void(const std::string& stage, int number, int count)> on_stage;
  /// Called after every accepted step with its diagnostics record; may be empty.
  std::function<void(const StepRecord&)> on_record;
  /// Polled after every accepted step; true ends the run there like an early stop
  /// (StopReason::interrupted): what was computed is written. The CLI sets it from SIGINT/SIGTERM.
  std::function<bool()> interrupted;
};

/// Where a run's time went (seconds, std::chrono::steady_clock) and how often each part ran.
struct RunTimes {
  double assembly = 0.0;  ///< residual and tangent assembly, the material updates included
  double analyze = 0.0;   ///< symbolic factorization (once per stage)
  double factorize = 0.0; ///< numeric factorizations
  double solve = 0.0;     ///< forward and back substitutions
  double output = 0.0;    ///< VTK steps, curves, diagnostics
  double checkpoint = 0.0;
  double total = 0.0; ///< the whole Analysis::run()
  long assemblies = 0, analyses = 0, factorizations = 0, solves = 0;
};

/// One [[checks]] entry after the run (framework/src/output/recorders.hpp).
struct CheckResult {
  std::string label; ///< recorder.quantity
  std::string unit;  ///< the quantity's unit as kN, m, kPa spell it ("m", "kPa", "-"; Units::label)
  double value = 0.0, expected = 0.0, tolerance = 0.0;
  bool pass = false;
};

/// Why a stage ended the run early: collapse or numerical (a step of an until_failure stage
/// failed; see RunSummary::stiffness_ratio), the stage's settlement limit, or an interruption.
enum class StopReason { none, collapse, numerical, settlement, interrupted };

/// The name summary.toml and the CLI give a stop reason: "collapse", "numerical", "settlement",
/// "interrupted" ("" for none).
[[nodiscard]] const char* stop_reason_name(StopReason reason);

struct RunSummary {
  Outcome outcome;
  RunTimes times;
  int steps_done = 0;
  int cutbacks = 0;
  std::vector<StepReport> reports; ///< every attempted step, failed ones included
  std::vector<StepRecord> records; ///< diagnostics of every attempt (also in <out_dir>/diagnostics.csv)
  std::string pvd;                 ///< the .pvd collection written ("" when no output)
  std::string out_dir;
  int stages_done = 0;                       ///< stages completed (counting those before a restart)
  StopReason stop_reason = StopReason::none; ///< why a stage ended early (none: it did not)
  std::string stop_message; ///< for "collapse"/"numerical": the failed step's message (stage, load factors,
                            ///< solver, cut-backs)
  /// For "collapse"/"numerical": the current stiffness of the last converged step over that of the
  /// stage's first (1 when there was none); below the stage's collapse_stiffness it is a collapse.
  double stiffness_ratio = 1.0;
  /// For "collapse"/"numerical": the current stiffness the step that ended the stage showed in its
  /// last attempt (load control: its load-factor increment over the farthest displacement along the
  /// load pattern its iterations reached) over that of the stage's first step; infinite when that
  /// attempt gives no evidence (path following, a failure by NaN or Inf or by a material's update).
  /// Below collapse_stiffness it is a collapse too (docs/design.md, "How a stage ends").
  double attempt_stiffness_ratio = std::numeric_limits<double>::infinity();
  double collapse_stiffness = 0.1;      ///< for "collapse"/"numerical": the stage's collapse_stiffness
  std::vector<std::string> checkpoints; ///< written, in order
  std::vector<CheckResult> checks;      ///< the scene's [[checks]] on the last recorded values
  /// Head load (kN) and settlement (mm; in other [units]: force, Units::small_length) per converged level of
  /// the stage(s) with a `load` action (starting at 0, 0): the head is that action's `edges` or the top
  /// faces of its `cells`, loaded by its force or pushed down by its `settlement` (StageState::head_load).
  std::vector<std::array<double, 2>> load_settlement;
  /// With [output] pile_cells as well: per recorded level, load_kN, head_mm, pile_shortening_mm,
  /// base_mm, shaft_slip_mean_mm, shaft_slip_top_mm, shaft_load_kN, base_load_kN, each a change
  /// since the start of the loaded stage (curves/settlement_components.csv;
  /// framework/src/output/pile_components.hpp).
  std::vector<std::array<double, 8>> settlement_components;
};

/// What one [[output.history]] recorder took during a run: its columns (stage, step, lambda, then
/// its quantities, as its CSV) and a row per recorded step (an interface recorder: per step and
/// point).
struct RecordedTable {
  std::string name;
  std::string kind; ///< node, nodes, point, global, interface
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};

/// Registers the framework's own stage actions and mesh generators, as an Analysis does before
/// it reads a scene (`stratum plugins` lists them with the plugins' factories).
void register_builtin_factories(Registry& registry);

class Analysis {
public:
  /// Reads, validates and builds everything. Throws Error (with file:line:col) on bad input.
  static std::unique_ptr<Analysis> from_file(const std::string& path, RunOptions options = {});
  /// The same from TOML text; `path` names it in messages and anchors relative paths.
  static std::unique_ptr<Analysis> from_string(const std::string& text, const std::string& path,
                                               RunOptions options = {});
  ~Analysis();

  /// Runs all load steps. Numerical failure comes back in the summary, never as an exception;
  /// an exception means an environment problem (e.g. an unwritable output directory).
  RunSummary run();

  [[nodiscard]] const Model& model() const;
  [[nodiscard]] Model& model();
  /// Libraries opened for this scene.
  [[nodiscard]] std::vector<std::string> opened_libraries() const;
  [[nodiscard]] std::string title() const;
  /// What the reader found suspicious but not wrong, one located line each (`stratum check`
  /// prints them): cells that no [[domains]] entry covers, sets the user named in a Gmsh file
  /// that the scene never names.
  [[nodiscard]] std::vector<std::string> warnings() const;
  /// The scene's [units] (kN, m when it declares none): every value the scene writes and every
  /// result is in them (stratum/units.hpp).
  [[nodiscard]] const Units& units() const;
  /// The recorders' tables so far (after run(): the whole run), in the scene's order.
  [[nodiscard]] std::vector<RecordedTable> recorded() const;

  struct Impl;

private:
  explicit Analysis(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

} // namespace stratum
