// Modified Newton-Raphson (thesis (4.12)) and the initial-stiffness method for one
// load step: the tangent is formed and factorized at the start of the step (and,
// for modified_newton, again every `refresh_every` iterations); the iterations in
// between reuse the factorization and only evaluate residuals.
//
// initial_stiffness factorizes the tangent of the first state it sees (the start
// of the analysis: the elastic stiffness) once, in a linear solver of its own, and
// reuses it for every later step.
#include "stratum/iteration.hpp"
#include "stratum/plugin.hpp"

#include <cmath>
#include <sstream>

namespace {

using namespace stratum;

enum class Mode { step_start, initial };

class ModifiedNewton final : public Solver {
public:
  ModifiedNewton(const Params& p, Mode mode)
      : mode_(mode), divergence_factor_(p.real("divergence_factor")),
        line_search_(static_cast<int>(p.integer("line_search"))),
        refresh_every_(mode == Mode::step_start ? static_cast<int>(p.integer("refresh_every")) : 0) {}

  StepReport solve(NonlinearProblem& problem, const StepRequest& req, Eigen::VectorXd& u) const override {
    StepReport rep;
    rep.lambda = req.lambda;
    const Convergence& c = req.convergence;
    LinearSolver* ls = &problem.linear_solver();
    SparseMatrix k;
    if (mode_ == Mode::initial) {
      // The initial stiffness: formed once per problem (at its first state) and kept factorized.
      if (initial_for_ != &problem || initial_size_ != problem.size() || !initial_) {
        k = problem.make_tangent();
        Eigen::VectorXd r;
        if (auto o = problem.evaluate(u, req.lambda_n, r, &k); !o.ok()) return fail(rep, o);
        auto own = make_linear_solver("auto", is_symmetric(k), problem.size());
        if (auto o = own->analyze(k); !o.ok()) return fail(rep, o);
        if (auto o = own->factorize(k); !o.ok()) return fail(rep, o);
        ++rep.factorizations;
        initial_ = std::move(own);
        initial_for_ = &problem;
        initial_size_ = problem.size();
      }
      ls = initial_.get();
    } else {
      k = problem.make_tangent();
    }
    const Eigen::VectorXd u_n = u;
    Eigen::VectorXd r, du;
    double r0 = -1.0, e0 = -1.0;
    bool current = false; // r (and k when refreshed) already belong to u (from the line search)
    auto refresh_at = [&](int it) {
      return mode_ == Mode::step_start && (it <= 1 || (refresh_every_ > 0 && it % refresh_every_ == 0));
    };
    for (int it = 0;; ++it) {
      const bool refresh = refresh_at(it);
      if (!current)
        if (auto o = problem.evaluate(u, req.lambda, r, refresh ? &k : nullptr); !o.ok()) return fail(rep, o);
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
        m << name() << " diverged: |R| = " << rn << " after " << it << " iterations (first |R| = " << r0
          << ")";
        return fail(rep, {Status::diverged, m.str()});
      }
      if (it >= c.max_iterations) {
        std::ostringstream m;
        m << name() << " did not converge in " << c.max_iterations << " iterations: |R| = " << rn
          << ", bound " << iteration::force_bound(c, scale);
        return fail(rep, {Status::not_converged, m.str()});
      }
      if (refresh) {
        if (auto o = ls->factorize(k); !o.ok()) return fail(rep, o);
        ++rep.factorizations;
      }
      if (auto o = ls->solve(r, du); !o.ok()) return fail(rep, o);
      ++rep.iterations;
      ++rep.solves;
      if (e0 < 0) e0 = std::abs(du.dot(r));
      const iteration::Backtrack b = iteration::line_search(problem, u, du, req.lambda, rn, line_search_, r,
                                                            refresh_at(it + 1) ? &k : nullptr);
      du *= b.step;
      u += du;
      current = b.evaluated;
    }
  }

private:
  [[nodiscard]] const char* name() const {
    return mode_ == Mode::initial ? "initial stiffness" : "modified Newton";
  }
  static bool is_symmetric(const SparseMatrix& k) {
    const SparseMatrix t = k.transpose();
    return (k - t).norm() <= 1e-12 * k.norm();
  }
  static StepReport& fail(StepReport& rep, Outcome o) {
    rep.outcome = std::move(o);
    return rep;
  }
  Mode mode_;
  double divergence_factor_;
  int line_search_;
  int refresh_every_;
  // initial_stiffness: the factorized initial tangent and the problem it belongs to (a cache
  // owned by this solver object, not global state).
  mutable std::unique_ptr<LinearSolver> initial_;
  mutable const NonlinearProblem* initial_for_ = nullptr;
  mutable Eigen::Index initial_size_ = -1;
};

Schema common_schema() {
  Schema s;
  s.real("divergence_factor", "-", "stop when |R| exceeds this multiple of the first residual")
      .greater_than(1)
      .defaults_to(1e6);
  s.integer("line_search", "-",
            "backtracking halvings allowed when a correction increases |R| (0: no line search)")
      .at_least(0)
      .at_most(30)
      .defaults_to(0LL);
  return s;
}

} // namespace

STRATUM_PLUGIN(registry) {
  Schema m = common_schema();
  m.integer("refresh_every", "-",
            "re-form and refactorize the tangent every k iterations (0: only at the step start)")
      .at_least(0)
      .defaults_to(0LL);
  registry.add(Factory<Solver>{
      .name = "modified_newton",
      .summary =
          "modified Newton-Raphson: tangent at the step start (or every k iterations), factorization reused",
      .schema = std::move(m),
      .create = [](const Params& p) { return std::make_unique<ModifiedNewton>(p, Mode::step_start); },
      .library = {}});
  registry.add(Factory<Solver>{
      .name = "initial_stiffness",
      .summary = "initial-stiffness method: the first tangent factorized once and reused for every step",
      .schema = common_schema(),
      .create = [](const Params& p) { return std::make_unique<ModifiedNewton>(p, Mode::initial); },
      .library = {}});
}
