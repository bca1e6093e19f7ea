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

#include <vector>

namespace stratum {

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
};

/// Convergence criteria; a test is passed when either its relative or absolute bound holds.
struct Convergence {
  double force_rtol = 1e-8;  ///< |R| <= force_rtol * force scale
  double force_atol = 1e-10; ///< kN
  double disp_rtol = 1e-8;   ///< |du| <= disp_rtol * |u - u_n|
  double disp_atol = 1e-14;  ///< m
  double energy_rtol = 0.0;  ///< thesis (4.21); 0 disables
  int max_iterations = 25;
};

struct StepRequest {
  double lambda_n = 0.0; ///< load factor at the start of the step
  double lambda = 1.0;   ///< target load factor
  Convergence convergence;
};

struct StepReport {
  Outcome outcome;
  int iterations = 0;                 ///< linear solves performed
  std::vector<double> residual_norms; ///< |R| at every evaluation
  double lambda = 0.0;                ///< load factor reached
};

class Solver {
public:
  virtual ~Solver() = default;
  /// On entry u holds the converged solution at lambda_n; on success it holds the solution at
  /// report.lambda. On failure u is unspecified and the caller reverts the state.
  [[nodiscard]] virtual StepReport solve(NonlinearProblem& problem, const StepRequest& request,
                                         Eigen::VectorXd& u) const = 0;
};

} // namespace stratum
