// Full Newton-Raphson for one load step: the tangent is reassembled and
// refactorized at every iteration (the symbolic analysis is the problem's, done
// once per pattern). A linear scene converges after one solve.
//
// Convergence: |R| <= max(force_rtol * force scale, force_atol), and, when
// energy_rtol > 0, also the thesis' energy test (4.21) |du.R| <= energy_rtol |du_1.R_0|.
// The displacement criteria of [convergence] are used by the solvers of issue 6.
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
    Eigen::VectorXd r, du;
    double r0 = -1.0, e0 = -1.0;
    for (int it = 0;; ++it) {
      if (auto o = problem.evaluate(u, req.lambda, r, &k); !o.ok()) return fail(rep, o);
      const double rn = r.norm();
      rep.residual_norms.push_back(rn);
      if (!std::isfinite(rn)) return fail(rep, {Status::non_finite, "residual is NaN or Inf"});
      const double scale = problem.force_scale(req.lambda);
      bool converged = rn <= std::max(c.force_rtol * scale, c.force_atol);
      if (it > 0 && c.energy_rtol > 0) {
        const double e = std::abs(du.dot(r));
        converged = converged && e <= c.energy_rtol * e0;
      }
      if (converged) return rep;
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
      if (auto o = problem.linear_solver().solve(r, du); !o.ok()) return fail(rep, o);
      ++rep.iterations;
      if (e0 < 0) e0 = std::abs(du.dot(r));
      // Backtracking: halve the correction while the residual grows (at most line_search times).
      // The residual of the accepted point is re-evaluated with the tangent at the loop top.
      double step = 1.0;
      for (int ls = 0; ls < line_search_; ++ls) {
        Eigen::VectorXd rt;
        const Outcome o = problem.evaluate(u + step * du, req.lambda, rt, nullptr);
        if (o.ok() && rt.allFinite() && rt.norm() < rn) break;
        step *= 0.5;
      }
      u += step * du;
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
