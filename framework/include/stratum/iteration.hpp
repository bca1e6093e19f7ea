// Building blocks shared by the iterative Solver plugins (newton, modified_newton,
// initial_stiffness, arc_length, displacement_control): the convergence test of
// one iterate and a backtracking line search. Header-only so that plugins built
// against an installed framework get them without a new exported symbol.
#pragma once

#include "stratum/solver.hpp"

#include <algorithm>
#include <cmath>

namespace stratum::iteration {

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
  k.force = residual <= std::max(c.force_rtol * force_scale, c.force_atol);
  if (c.energy_rtol > 0) k.energy = have_correction && work <= std::max(c.energy_rtol * work0, c.energy_atol);
  if (c.displacement_test)
    k.displacement = have_correction && correction <= std::max(c.disp_rtol * step, c.disp_atol);
  return k;
}

/// Backtracking: the largest step 2^-k (k < max_halvings) with |R(u + s du)| < |R(u)| = rn,
/// evaluated without the tangent; 2^-max_halvings when none decreases the residual. Returns 1
/// when max_halvings == 0. The trial state is left at the last evaluated point: the caller
/// re-evaluates at the accepted one.
[[nodiscard]] inline double line_search(NonlinearProblem& problem, const Eigen::VectorXd& u,
                                        const Eigen::VectorXd& du, double lambda, double rn,
                                        int max_halvings) {
  double s = 1.0;
  Eigen::VectorXd rt;
  for (int k = 0; k < max_halvings; ++k) {
    const Outcome o = problem.evaluate(u + s * du, lambda, rt, nullptr);
    if (o.ok() && rt.allFinite() && rt.norm() < rn) break;
    s *= 0.5;
  }
  return s;
}

} // namespace stratum::iteration
