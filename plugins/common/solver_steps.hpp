// The pieces of one load step that the iterative solver plugins of this project (newton,
// modified_newton / initial_stiffness, arc_length, displacement_control) write the same way:
// recording a failure, recording and testing a residual, the divergence and iteration-limit
// tests with their messages, and (Newton-type solvers) the corrector with its line search.
// The convergence tests themselves are the framework's (stratum/iteration.hpp).
#pragma once

#include "stratum/iteration.hpp"
#include "stratum/params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>

namespace stratum::solver_steps {

/// Ends a step with a failure: the outcome goes into the report, which is returned.
inline StepReport& fail(StepReport& rep, Outcome o) {
  rep.outcome = std::move(o);
  return rep;
}

/// Records |R| = rn of an iterate in the report; a NaN or Inf residual is a failure.
[[nodiscard]] inline Outcome record_residual(StepReport& rep, double rn) {
  rep.residual_norms.push_back(rn);
  if (!std::isfinite(rn)) return {Status::non_finite, "residual is NaN or Inf"};
  return {};
}

/// The convergence tests (iteration::check) of iterate `it` with residual r, |r| = rn, reached by
/// the correction `correction` (there is none before the first iterate, it == 0); `step` is the
/// size of the step's displacement so far and `work0` the first iteration's |du . R|.
[[nodiscard]] inline iteration::Check check(const Convergence& c, int it, double rn, double force_scale,
                                            const Eigen::VectorXd& correction, const Eigen::VectorXd& r,
                                            double step, double work0) {
  const bool have = it > 0;
  return iteration::check(c, rn, force_scale, have, have ? correction.norm() : 0.0, step,
                          have ? std::abs(correction.dot(r)) : 0.0, work0);
}

/// Newton-type solvers: after the second iteration, |R| = rn above `factor` times the first
/// residual r0 (or force_atol when that is larger) is divergence.
[[nodiscard]] inline Outcome divergence(std::string_view solver, double factor, const Convergence& c, int it,
                                        double rn, double r0) {
  if (it > 1 && rn > factor * std::max(r0, c.force_atol)) {
    std::ostringstream m;
    m << solver << " diverged: |R| = " << rn << " after " << it << " iterations (first |R| = " << r0 << ")";
    return {Status::diverged, m.str()};
  }
  return {};
}

/// Newton-type solvers: iterate `it` with |R| = rn is the last one allowed (max_iterations).
[[nodiscard]] inline Outcome iteration_limit(std::string_view solver, const Convergence& c, int it, double rn,
                                             double force_scale) {
  if (it >= c.max_iterations) {
    std::ostringstream m;
    m << solver << " did not converge in " << c.max_iterations << " iterations: |R| = " << rn << ", bound "
      << iteration::force_bound(c, force_scale);
    return {Status::not_converged, m.str()};
  }
  return {};
}

/// Path-following solvers: iterate `it` with |R| = rn at load factor `lambda` is the last one
/// allowed (max_iterations); `hint` is added to the message.
[[nodiscard]] inline Outcome iteration_limit_at(std::string_view solver, const Convergence& c, int it,
                                                double rn, double lambda, std::string_view hint = {}) {
  if (it >= c.max_iterations) {
    std::ostringstream m;
    m << solver << " did not converge in " << c.max_iterations << " iterations: |R| = " << rn
      << " at load factor " << lambda << hint;
    return {Status::not_converged, m.str()};
  }
  return {};
}

/// Newton-type solvers: the correction K du = R. The tangent k is factorized first when it is given
/// (not null); otherwise the solver's current factorization is used. Counts what it did in the report.
[[nodiscard]] inline Outcome correction(LinearSolver& ls, const SparseMatrix* k, const Eigen::VectorXd& r,
                                        Eigen::VectorXd& du, StepReport& rep) {
  if (k) {
    if (auto o = ls.factorize(*k); !o.ok()) return o;
    ++rep.factorizations;
  }
  if (auto o = ls.solve(r, du); !o.ok()) return o;
  ++rep.iterations;
  ++rep.solves;
  return {};
}

/// Newton-type solvers: moves u by the correction du, cut back by the line search
/// (iteration::line_search, at most `halvings` halvings); du becomes the step taken. Returns
/// whether r (and the tangent, when one was passed) already belong to the new u.
[[nodiscard]] inline bool take_correction(NonlinearProblem& problem, Eigen::VectorXd& u, Eigen::VectorXd& du,
                                          double lambda, double rn, int halvings, Eigen::VectorXd& r,
                                          SparseMatrix* tangent) {
  const iteration::Backtrack b = iteration::line_search(problem, u, du, lambda, rn, halvings, r, tangent);
  du *= b.step;
  u += du;
  return b.evaluated;
}

/// The parameters every Newton-type solver takes: divergence_factor and line_search (what
/// line_search = 0 means is `line_search_off`, as the solver's help words it; its default is the
/// solver's: newton 4, measured in plugins/newton/README.md, the modified schemes 0).
[[nodiscard]] inline Schema newton_parameters(std::string_view line_search_off,
                                              long long line_search_default = 0) {
  Schema s;
  s.real("divergence_factor", "-", "stop when |R| exceeds this multiple of the first residual")
      .greater_than(1)
      .defaults_to(1e6);
  s.integer("line_search", "-",
            "backtracking halvings allowed when a correction increases |R| (0: " +
                std::string(line_search_off) + ")")
      .at_least(0)
      .at_most(30)
      .defaults_to(line_search_default);
  return s;
}

} // namespace stratum::solver_steps
