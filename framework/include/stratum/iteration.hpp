// Building blocks shared by the iterative Solver plugins (newton, modified_newton,
// initial_stiffness, arc_length, displacement_control; kinsol takes its force test and
// its tolerance from here): the bound of a convergence test, the convergence test of
// one iterate and a backtracking line search. Header-only so that plugins built
// against an installed framework get them without a new exported symbol.
#pragma once

#include "stratum/solver.hpp"

#include <algorithm>
#include <cmath>

namespace stratum::iteration {

/// The bound of a convergence test, written once for every solver: a quantity passes when it is at
/// most the relative bound rtol * scale or the absolute bound atol, whichever is larger.
[[nodiscard]] inline double bound(double rtol, double scale, double atol) {
  return std::max(rtol * scale, atol);
}

/// The force test's bound at a force scale (NonlinearProblem::force_scale):
/// max(force_rtol * force_scale, force_atol).
[[nodiscard]] inline double force_bound(const Convergence& c, double force_scale) {
  return bound(c.force_rtol, force_scale, c.force_atol);
}

/// The force test: |R| = residual within force_bound (false for NaN).
[[nodiscard]] inline bool force_test(const Convergence& c, double residual, double force_scale) {
  return residual <= force_bound(c, force_scale);
}

/// The convergence tests of Convergence at one iterate. `residual` is |R| at the iterate,
/// `correction` the last correction du that led to it (empty before the first one),
/// `step` the displacement of the step so far (u - u_n), `work0` = |du_1 . R_0| of the first
/// iteration (the denominator of the thesis' energy test (4.21)), `work` = |du . R| of the
/// current one. Force is always tested; energy when energy_rtol > 0; displacement when
/// Convergence::displacement_test is set. Each test passes when its relative or absolute bound holds.
struct Check {
  bool force = false, energy = true, displacement = true;
  [[nodiscard]] bool converged() const { return force && energy && displacement; }
};

[[nodiscard]] inline Check check(const Convergence& c, double residual, double force_scale,
                                 bool have_correction, double correction, double step, double work,
                                 double work0) {
  Check k;
  k.force = force_test(c, residual, force_scale);
  if (c.energy_rtol > 0) k.energy = have_correction && work <= bound(c.energy_rtol, work0, c.energy_atol);
  if (c.displacement_test)
    k.displacement = have_correction && correction <= bound(c.disp_rtol, step, c.disp_atol);
  return k;
}

/// The outcome of a backtracking line search.
struct Backtrack {
  double step = 1.0;      ///< the accepted fraction s of the correction
  bool evaluated = false; ///< `residual` (and the tangent, when one was passed) hold R(u + s du)
};

/// Backtracking: the largest step s = 2^-k (k < max_halvings) with |R(u + s du)| < |R(u)| = rn;
/// s = 2^-max_halvings, not evaluated, when none decreases the residual; s = 1, not evaluated,
/// when max_halvings == 0. Every trial is evaluated into `residual`; the full step s = 1 also
/// with the tangent when `tangent` is not null (a caller that needs the tangent at the next
/// iterate passes it; when the full step is accepted, as it mostly is, that evaluation is the
/// next iterate's). When Backtrack::evaluated is set, `residual` (and the tangent, if asked for)
/// and the trial states belong to the accepted point u + s du, so the caller need not evaluate
/// it again; otherwise it must.
[[nodiscard]] inline Backtrack line_search(NonlinearProblem& problem, const Eigen::VectorXd& u,
                                           const Eigen::VectorXd& du, double lambda, double rn,
                                           int max_halvings, Eigen::VectorXd& residual,
                                           SparseMatrix* tangent) {
  Backtrack b;
  for (int k = 0; k < max_halvings; ++k) {
    SparseMatrix* t = k == 0 ? tangent : nullptr;
    const Outcome o = problem.evaluate(u + b.step * du, lambda, residual, t);
    if (o.ok() && residual.allFinite() && residual.norm() < rn) {
      b.evaluated = tangent == nullptr || k == 0;
      return b;
    }
    b.step *= 0.5;
  }
  return b;
}

} // namespace stratum::iteration
