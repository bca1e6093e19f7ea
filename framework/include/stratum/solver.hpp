// The Solver interface: solves one load step of a NonlinearProblem.
//
// The problem is R(u, lambda) = lambda * F_ref + F_fixed - F_int(u) = 0 over the
// free DOFs u, where F_int includes the effect of prescribed displacements
// (scaled with lambda). A Solver never sees TOML, stages or files: it gets the
// problem, the target load factor and the convergence criteria, and returns a
// status plus diagnostics.
#pragma once

#include "stratum/error.hpp"
#include "stratum/linear_solver.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace stratum {

struct Model;

/// What a solver may check before anything runs: a stage's model as it will be when the stage
/// starts (its actions applied, its DOFs numbered: stratum/model.hpp).
struct SolverCheck {
  const Model& model;
  std::string context; ///< `stage "name"`, to begin messages with
};

class NonlinearProblem {
public:
  virtual ~NonlinearProblem() = default;

  /// Number of free unknowns.
  [[nodiscard]] virtual Eigen::Index size() const = 0;

  /// Residual R(u, lambda) (out-of-balance force, kN) and, when tangent != nullptr,
  /// the tangent K = -dR/du in the fixed pattern. Updates the trial state.
  [[nodiscard]] virtual Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& residual,
                                         SparseMatrix* tangent) = 0;

  /// A matrix with the tangent's fixed sparsity pattern (values zero), to pass to evaluate().
  [[nodiscard]] virtual SparseMatrix make_tangent() const = 0;

  /// dR/dlambda at fixed u for load-only scaling (the reference load), used by arc-length.
  [[nodiscard]] virtual const Eigen::VectorXd& reference_load() const = 0;

  /// The linear solver bound to this problem's pattern (analyzed once per pattern).
  [[nodiscard]] virtual LinearSolver& linear_solver() = 0;

  /// A force scale for relative convergence tests (norm of external plus reaction forces).
  [[nodiscard]] virtual double force_scale(double lambda) const = 0;

  /// Asks the materials that keep branch decisions within a step (Material::decision_slot) to
  /// decide afresh at the next evaluation. False (the default) when no material keeps any: the
  /// evaluations are then functions of u alone.
  [[nodiscard]] virtual bool renew_decisions() { return false; }

  /// The largest local error estimate (Material::step_error) of the last evaluation's trial
  /// states; 0 (the default) when no material gives one.
  [[nodiscard]] virtual double step_error() const { return 0.0; }

  /// Free-unknown indices of a named node set's component (0 = x, 1 = y), for displacement
  /// control; empty when the problem has no such set (the default).
  [[nodiscard]] virtual std::vector<Eigen::Index> node_set_dofs(const std::string& /*set*/,
                                                                int /*component*/) const {
    return {};
  }
};

/// Convergence criteria; a test is passed when either its relative or absolute bound holds.
struct Convergence {
  double force_rtol = 1e-8;       ///< |R| <= force_rtol * force scale
  double force_atol = 1e-10;      ///< kN
  double disp_rtol = 1e-8;        ///< |du| <= disp_rtol * |u - u_n|
  double disp_atol = 1e-14;       ///< m
  double energy_rtol = 0.0;       ///< thesis (4.21); 0 disables
  double energy_atol = 0.0;       ///< kN m, absolute bound of the energy test
  bool displacement_test = false; ///< also require the displacement test
  int max_iterations = 25;
};

struct StepRequest {
  double lambda_n = 0.0; ///< load factor at the start of the step
  double lambda = 1.0;   ///< target load factor (path-following solvers: sizes the first step only)
  Convergence convergence;
  /// Path-following solvers: the step size (arc length; displacement control: the increment of
  /// the controlled displacement). <= 0: the solver chooses (from lambda - lambda_n, or its parameters).
  double arc_length = 0.0;
  /// The displacement increment of the last accepted step (predictor sign), or nullptr.
  const Eigen::VectorXd* previous_increment = nullptr;
  double previous_dlambda = 0.0; ///< its load-factor increment
};

struct StepReport {
  Outcome outcome;
  int iterations = 0;                 ///< linear solves performed
  std::vector<double> residual_norms; ///< |R| at every evaluation
  double lambda = 0.0;                ///< load factor reached
  double arc_length = 0.0;            ///< path following: the step size used (measured, thesis (4.19))
  int factorizations = 0;             ///< numeric factorizations performed
  int solves = 0;                     ///< right-hand sides solved with a factorization
};

class Solver {
public:
  virtual ~Solver() = default;
  /// On entry u holds the converged solution at lambda_n; on success it holds the solution at
  /// report.lambda. On failure u is unspecified and the caller reverts the state.
  [[nodiscard]] virtual StepReport solve(NonlinearProblem& problem, const StepRequest& request,
                                         Eigen::VectorXd& u) const = 0;
  /// True for solvers that choose the load factor themselves (arc length, displacement control):
  /// the step controller passes StepRequest::arc_length and reads StepReport::lambda.
  [[nodiscard]] virtual bool path_following() const { return false; }
  /// Called for every stage while the scene is built (so by `stratum check` too): throws a
  /// located Error (Params::where) for a parameter that cannot work in that stage, e.g. a node
  /// set the mesh lacks. Default: nothing to check.
  virtual void check(const SolverCheck& stage) const { (void)stage; }
};

} // namespace stratum
