// Full Newton-Raphson for one load step: the tangent is reassembled and
// refactorized at every iteration (the symbolic analysis is the problem's, done
// once per pattern). A linear scene converges after one solve.
//
// Convergence: |R| <= max(force_rtol * force scale, force_atol), and, when
// energy_rtol > 0, also the thesis' energy test (4.21) |du.R| <= energy_rtol |du_1.R_0|,
// and with displacement_test |du| <= max(disp_rtol |u - u_n|, disp_atol)
// (stratum/iteration.hpp, shared with the other iterative solvers).
#include "stratum/iteration.hpp"
#include "stratum/plugin.hpp"

#include <cmath>
#include <sstream>

namespace {

using namespace stratum;

class Newton final : public Solver {
public:
  explicit Newton(const Params& p)
      : divergence_factor_(p.real("divergence_factor")),
        line_search_(static_cast<int>(p.integer("line_search"))) {}

  StepReport solve(NonlinearProblem& problem, const StepRequest& req, Eigen::VectorXd& u) const override {
    StepReport rep;
    rep.lambda = req.lambda;
    const Convergence& c = req.convergence;
    SparseMatrix k = problem.make_tangent();
    const Eigen::VectorXd u_n = u;
    Eigen::VectorXd r, du;
    double r0 = -1.0, e0 = -1.0;
    bool current = false; // r, k and the trial states already belong to u (from the line search)
    for (int it = 0;; ++it) {
      if (!current)
        if (auto o = problem.evaluate(u, req.lambda, r, &k); !o.ok()) return fail(rep, o);
      const double rn = r.norm();
      rep.residual_norms.push_back(rn);
      if (!std::isfinite(rn)) return fail(rep, {Status::non_finite, "residual is NaN or Inf"});
      const double scale = problem.force_scale(req.lambda);
      const bool have = it > 0;
      const auto chk = iteration::check(c, rn, scale, have, have ? du.norm() : 0.0, (u - u_n).norm(),
                                        have ? std::abs(du.dot(r)) : 0.0, e0);
      if (chk.converged()) return rep;
      if (r0 < 0) r0 = rn;
      if (it > 1 && rn > divergence_factor_ * std::max(r0, c.force_atol)) {
        std::ostringstream m;
        m << "Newton diverged: |R| = " << rn << " after " << it << " iterations (first |R| = " << r0 << ")";
        return fail(rep, {Status::diverged, m.str()});
      }
      if (it >= c.max_iterations) {
        std::ostringstream m;
        m << "Newton did not converge in " << c.max_iterations << " iterations: |R| = " << rn << ", bound "
          << std::max(c.force_rtol * scale, c.force_atol);
        return fail(rep, {Status::not_converged, m.str()});
      }
      if (auto o = problem.linear_solver().factorize(k); !o.ok()) return fail(rep, o);
      ++rep.factorizations;
      if (auto o = problem.linear_solver().solve(r, du); !o.ok()) return fail(rep, o);
      ++rep.iterations;
      ++rep.solves;
      if (e0 < 0) e0 = std::abs(du.dot(r));
      // Backtracking: halve the correction while the residual grows (at most line_search times).
      // The full step is tried with the tangent, so an accepted full step is not evaluated twice.
      const iteration::Backtrack b =
          iteration::line_search(problem, u, du, req.lambda, rn, line_search_, r, &k);
      du *= b.step;
      u += du;
      current = b.evaluated;
    }
  }

private:
  static StepReport& fail(StepReport& rep, Outcome o) {
    rep.outcome = std::move(o);
    return rep;
  }
  double divergence_factor_;
  int line_search_;
};

} // namespace

STRATUM_PLUGIN(registry) {
  Schema s;
  s.real("divergence_factor", "-", "stop when |R| exceeds this multiple of the first residual")
      .greater_than(1)
      .defaults_to(1e6);
  s.integer("line_search", "-",
            "backtracking halvings allowed when a correction increases |R| (0: plain Newton)")
      .at_least(0)
      .at_most(30)
      .defaults_to(0LL);
  registry.add(Factory<Solver>{.name = "newton",
                               .summary = "full Newton-Raphson, tangent refactorized every iteration",
                               .schema = std::move(s),
                               .create = [](const Params& p) { return std::make_unique<Newton>(p); },
                               .library = {}});
}
