// Step control of one stage: the sequence of load steps from lambda_start to
// lambda_end over a NonlinearProblem, solved step by step by a Solver.
//
// Load control (the solver sets no load factor itself): an explicit list of
// increments or `steps` equal ones; a failed step is reverted and halved (at
// most max_cutbacks halvings below the nominal increment); after a cut the
// increment doubles back to the nominal one; with `automatic` it also grows by
// `growth` after a step that converged in at most `fast_iterations` iterations,
// up to max_increment.
//
// With error_tolerance > 0 a converged step is also checked against the materials' local
// error estimate (NonlinearProblem::step_error): above the tolerance it is reverted and repeated
// with a smaller increment (never below max_cutbacks halvings of the nominal one), and the next
// increment is chosen from the estimate (at most the nominal one, landing on the listed
// boundaries as without error control).
//
// Path following (Solver::path_following(): arc length, displacement control):
// the controller passes a step size and the solver returns the load factor it
// reached. The first size is `arc_length` (0: the solver derives it from the
// first load increment); afterwards the measured size of the last step (thesis
// (4.19)) times beta, where beta = growth after fast convergence (automatic) and
// 1 otherwise; a failure halves it. The stage ends when lambda passes lambda_end,
// after max_steps steps, or when the stop predicate says so.
//
// The controller never reads TOML or writes files: Analysis::run() fills the
// settings and the callbacks.
#pragma once

#include "stratum/solver.hpp"

#include <functional>
#include <string>
#include <vector>

namespace stratum {

struct StepSettings {
  double lambda_start = 0.0;      ///< load factor at the start of the stage
  double lambda_end = 1.0;        ///< target load factor of the stage (may be below lambda_start)
  int steps = 1;                  ///< equal increments when `increments` is empty
  std::vector<double> increments; ///< explicit increments (their sign is ignored); the last one repeats
  bool automatic = false;         ///< grow the increment after fast convergence
  int max_cutbacks = 4;           ///< halvings below the nominal increment before the stage fails
  int fast_iterations = 4;        ///< a step converged in at most this many iterations counts as fast
  double growth = 1.5;            ///< increment (or arc length) factor after a fast step
  double max_increment = 0.0;     ///< bound on a grown load increment; 0: the stage range
  double arc_length = 0.0;        ///< path following: first step size; 0: from the first increment
  double max_arc_length = 0.0;    ///< path following: bound on a grown step size; 0: none
  int max_steps = 10000; ///< accepted steps per stage (path following stops here, load control fails)
  /// Load control: bound on NonlinearProblem::step_error() of a converged step; above it the step
  /// is repeated smaller, below it the next one grows (at most to the listed increment). 0: off.
  double error_tolerance = 0.0;
  Convergence convergence;
};

/// Diagnostics of one attempted step.
struct StepRecord {
  int stage = 1; ///< stage number (1-based) in a staged run
  int step = 0;  ///< number of the accepted step (an attempt that failed carries the number it tried)
  bool accepted = false;
  double lambda_n = 0.0, lambda = 0.0; ///< load factor at the start and reached (or targeted)
  int iterations = 0;
  int factorizations = 0;
  std::vector<double> residual_norms;
  double order = 0.0;       ///< observed convergence order log(r3/r2)/log(r2/r1) of the last three residuals
  double contraction = 0.0; ///< last residual ratio r_k / r_(k-1) (linear rate)
  double seconds = 0.0;
  int cutbacks = 0;        ///< failed attempts before this one at the same step
  double arc_length = 0.0; ///< path following: step size used
  std::string message;     ///< the failure message of a failed attempt
};

struct StepCallbacks {
  std::function<void()> commit; ///< accept the trial states of the last evaluation
  std::function<void()> revert; ///< throw them away
  /// After every accepted step (with its record and the converged unknowns).
  std::function<void(const StepRecord&, const StepReport&, const Eigen::VectorXd& u)> accepted;
  /// After every accepted step: true ends the stage successfully (e.g. "settlement beyond x").
  std::function<bool(double lambda, const Eigen::VectorXd& u)> stop;
  /// Load control: optional predictor for a step from lambda_n to lambda (u holds u_n on entry).
  std::function<void(NonlinearProblem&, double lambda_n, double lambda, Eigen::VectorXd& u)> predict;
};

struct StageResult {
  Outcome outcome;
  std::vector<StepRecord> records; ///< every attempt, failed ones included, in order
  std::vector<StepReport> reports; ///< the solver's report of every attempt
  int steps_done = 0;
  int cutbacks = 0;
  int error_rejections = 0; ///< converged steps repeated smaller because of the error estimate
  double lambda = 0.0;      ///< load factor reached
  bool stopped = false;     ///< ended by the stop predicate or max_steps (path following)
};

/// Runs the steps of one stage. On entry u holds the converged unknowns at
/// settings.lambda_start; on return the last accepted ones. Numerical failure comes back
/// in StageResult::outcome; the states are then those of the last accepted step.
[[nodiscard]] StageResult run_stage(NonlinearProblem& problem, const Solver& solver,
                                    const StepSettings& settings, const StepCallbacks& callbacks,
                                    Eigen::VectorXd& u);

/// Observed order and contraction of a residual history (0 when too short).
void convergence_rates(const std::vector<double>& r, double& order, double& contraction);

/// Writes the records as CSV (one row per attempt) to `path`, through a temporary file renamed
/// into place. Throws Error when the file cannot be written.
void write_step_records(const std::string& path, const std::vector<StepRecord>& records);

} // namespace stratum
