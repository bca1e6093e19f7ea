// Modified Newton-Raphson (thesis (4.12)) and the initial-stiffness method for one
// load step: the tangent is formed and factorized at the start of the step (and,
// for modified_newton, again every `refresh_every` iterations); the iterations in
// between reuse the factorization and only evaluate residuals.
//
// initial_stiffness factorizes the tangent of the first state it sees (the start
// of the analysis: the elastic stiffness) once, in a linear solver of its own, and
// reuses it for every later step.
#include "common/solver_steps.hpp"
#include "stratum/plugin.hpp"

#include <cmath>

namespace {

using namespace stratum;
using solver_steps::fail;

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
      if (auto o = solver_steps::record_residual(rep, rn); !o.ok()) return fail(rep, o);
      const double scale = problem.force_scale(req.lambda);
      const auto chk = solver_steps::check(c, it, rn, scale, du, r, (u - u_n).norm(), e0);
      if (chk.converged()) return rep;
      if (r0 < 0) r0 = rn;
      if (auto o = solver_steps::divergence(name(), divergence_factor_, c, it, rn, r0); !o.ok())
        return fail(rep, o);
      if (auto o = solver_steps::iteration_limit(name(), c, it, rn, scale); !o.ok()) return fail(rep, o);
      if (auto o = solver_steps::correction(*ls, refresh ? &k : nullptr, r, du, rep); !o.ok())
        return fail(rep, o);
      if (e0 < 0) e0 = std::abs(du.dot(r));
      current = solver_steps::take_correction(problem, u, du, req.lambda, rn, line_search_, r,
                                              refresh_at(it + 1) ? &k : nullptr);
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

} // namespace

STRATUM_PLUGIN(registry) {
  Schema m = solver_steps::newton_parameters("no line search");
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
      .schema = solver_steps::newton_parameters("no line search"),
      .create = [](const Params& p) { return std::make_unique<ModifiedNewton>(p, Mode::initial); },
      .library = {}});
}
