// Full Newton-Raphson for one load step: the tangent is reassembled and
// refactorized at every iteration (the symbolic analysis is the problem's, done
// once per pattern). A linear scene converges after one solve.
//
// Convergence: |R| <= max(force_rtol * force scale, force_atol), and, when
// energy_rtol > 0, also the thesis' energy test (4.21) |du.R| <= energy_rtol |du_1.R_0|,
// and with displacement_test |du| <= max(disp_rtol |u - u_n|, disp_atol)
// (stratum/iteration.hpp, shared with the other iterative solvers).
#include "common/solver_steps.hpp"
#include "stratum/plugin.hpp"

#include <cmath>
#include <sstream>
#include <vector>

namespace {

using namespace stratum;
using solver_steps::fail;

class Newton final : public Solver {
public:
  explicit Newton(const Params& p)
      : divergence_factor_(p.real("divergence_factor")),
        line_search_(static_cast<int>(p.integer("line_search"))),
        stall_iterations_(static_cast<int>(p.integer("stall_iterations"))),
        stall_factor_(p.real("stall_factor")), max_resolves_(static_cast<int>(p.integer("max_resolves"))) {}

  StepReport solve(NonlinearProblem& problem, const StepRequest& req, Eigen::VectorXd& u) const override {
    StepReport rep;
    rep.lambda = req.lambda;
    const Convergence& c = req.convergence;
    SparseMatrix k = problem.make_tangent();
    const Eigen::VectorXd u_n = u;
    Eigen::VectorXd r, du;
    double r0 = -1.0, e0 = -1.0;
    bool current = false; // r, k and the trial states already belong to u (from the line search)
    // Branch decisions (Material::decision_slot): made afresh at the first evaluation of the step
    // and kept while Newton iterates; at convergence every point decides again from the
    // converged increment, and only when that evaluation also passes the tests is the step done.
    const bool memory = problem.renew_decisions();
    if (memory && req.previous_increment && req.previous_dlambda != 0.0 &&
        req.previous_increment->size() == u.size()) {
      // The first decisions are made at this iterate: extrapolate the last step's increment so
      // that they see a realistic increment rather than none.
      u += ((req.lambda - req.lambda_n) / req.previous_dlambda) * (*req.previous_increment);
    }
    bool renewed = true;     // the next evaluation decides afresh
    bool free = false;       // after max_resolves: every evaluation decides afresh
    bool rechecking = false; // that evaluation is the check of a converged iterate
    int resolves = 0;
    std::vector<double> window; // residuals since the last decisions (the contraction test)
    for (int it = 0;; ++it) {
      bool decided = false;
      if (free && !current) (void)problem.renew_decisions();
      if (!current) {
        if (auto o = problem.evaluate(u, req.lambda, r, &k); !o.ok()) return fail(rep, o);
        decided = renewed || free;
        renewed = false;
      } else
        decided = free;
      const double rn = r.norm();
      if (auto o = solver_steps::record_residual(rep, rn); !o.ok()) return fail(rep, o);
      const double scale = problem.force_scale(req.lambda);
      const auto chk = solver_steps::check(c, it, rn, scale, du, r, (u - u_n).norm(), e0);
      if (chk.converged()) {
        if (!memory || decided) return rep;
        // Converged with the step's decisions: check them against the converged increment.
        if (!problem.renew_decisions()) return rep;
        renewed = rechecking = true;
        current = false;
        continue;
      }
      if (rechecking) {
        // Some point changed its branch at the converged increment: solve again from here
        // with the new decisions (they are now the kept ones).
        rechecking = false;
        window.clear();
        // Decisions that keep changing (a point whose two branches each ask for the other):
        // iterate on with every evaluation deciding afresh, the original iteration, whose
        // converged states are the same rule's; the contraction test ends it if it stalls.
        if (++resolves >= max_resolves_) free = true;
      }
      if (r0 < 0) r0 = rn;
      if (auto o = solver_steps::divergence("Newton", divergence_factor_, c, it, rn, r0); !o.ok())
        return fail(rep, o);
      window.push_back(rn);
      if (stall_iterations_ > 0 && static_cast<int>(window.size()) > stall_iterations_) {
        const double before = window[window.size() - 1 - static_cast<std::size_t>(stall_iterations_)];
        if (rn > stall_factor_ * before) {
          std::ostringstream m;
          m << "Newton not converging: |R| = " << rn << " after " << it << " iterations, above "
            << stall_factor_ << " x its value " << stall_iterations_ << " iterations before (" << before
            << "), bound " << iteration::force_bound(c, scale);
          return fail(rep, {Status::not_converged, m.str()});
        }
      }
      if (auto o = solver_steps::iteration_limit("Newton", c, it, rn, scale); !o.ok()) return fail(rep, o);
      if (auto o = solver_steps::correction(problem.linear_solver(), &k, r, du, rep); !o.ok())
        return fail(rep, o);
      if (e0 < 0) e0 = std::abs(du.dot(r));
      // Backtracking: halve the correction while the residual grows (at most line_search times).
      // The full step is tried with the tangent, so an accepted full step is not evaluated twice.
      current = solver_steps::take_correction(problem, u, du, req.lambda, rn, line_search_, r, &k);
    }
  }

private:
  double divergence_factor_;
  int line_search_;
  int stall_iterations_;
  double stall_factor_;
  int max_resolves_;
};

} // namespace

STRATUM_PLUGIN(registry) {
  // Backtracking on by default (4 halvings): without it the plasticity scenes cut back many
  // times and the loess pile stops at a spurious collapse (plugins/newton/README.md, measured).
  Schema s = solver_steps::newton_parameters("plain Newton", 4);
  s.integer("stall_iterations", "-",
            "contraction test: stop (and let the step be cut back) when |R| has not fallen below "
            "stall_factor times its value this many iterations before; 0: off (only max_iterations)")
      .at_least(0)
      .at_most(100)
      .defaults_to(0LL);
  s.real("stall_factor", "-", "contraction required over stall_iterations iterations")
      .greater_than(0)
      .less_than(1)
      .defaults_to(0.5);
  s.integer("max_resolves", "-",
            "materials that keep branch decisions within a step: how often a step whose converged "
            "increment changed a decision is solved again before it fails (and is cut back)")
      .at_least(0)
      .at_most(100)
      .defaults_to(4LL);
  registry.add(Factory<Solver>{.name = "newton",
                               .summary = "full Newton-Raphson, tangent refactorized every iteration",
                               .schema = std::move(s),
                               .create = [](const Params& p) { return std::make_unique<Newton>(p); },
                               .library = {}});
}
