// Global solvers and step control (issue 6): the softening bar S1, exact revert
// after a cut-back, and (below) the strip footing and the Newton variants.
#include "solver_helpers.hpp"

#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace stratum;
using stratum::testing::load_solver;
using stratum::testing::SofteningBar;

namespace {

StepCallbacks bar_callbacks(SofteningBar& bar) {
  StepCallbacks cb;
  cb.commit = [&bar] { bar.commit(); };
  cb.revert = [&bar] { bar.revert(); };
  return cb;
}

/// Fails the `fail_at`-th call after one iteration of the wrapped solver (which leaves trial
/// states and u dirty), as a numerically failing step would.
class FailOnce final : public Solver {
public:
  FailOnce(const Solver& inner, int fail_at) : inner_(inner), fail_at_(fail_at) {}
  StepReport solve(NonlinearProblem& p, const StepRequest& req, Eigen::VectorXd& u) const override {
    if (++calls_ != fail_at_) return inner_.solve(p, req, u);
    StepRequest r = req;
    r.convergence.max_iterations = 1;
    StepReport rep = inner_.solve(p, r, u);
    rep.outcome = Outcome::failure(Status::not_converged, "forced failure");
    return rep;
  }
  bool path_following() const override { return inner_.path_following(); }

private:
  const Solver& inner_;
  int fail_at_;
  mutable int calls_ = 0;
};

} // namespace

// S1 parameters: L = 1 m, 10 elements (l_s = 0.1 m), E = 100 kPa, f_t = 1 kPa, H = -20 kPa.
// Snap-back because (L - l_s)/E = 0.009 > l_s/|H| = 0.005; on the softening branch
// u = 0.004 sigma + 0.006 m, which decreases from u_peak = 0.01 m as sigma drops.
TEST_CASE("S1 softening bar: arc length follows the snap-back branch", "[solver]") {
  SofteningBar bar(10, 1.0, 100.0, 1.0, -20.0);
  CHECK(bar.softening_u(1.0) == Approx(0.01).epsilon(1e-14));
  CHECK(bar.softening_u(0.0) == Approx(0.006).epsilon(1e-14));
  for (const std::string constraint : {"cylindrical", "spherical"}) {
    SECTION(constraint) {
      auto s = load_solver("arc_length", "constraint = \"" + constraint +
                                             "\"\npredictor_sign = \"determinant\"\nroot = \"" +
                                             (constraint == "cylindrical" ? "angle" : "residual") + "\"");
      SofteningBar b(10, 1.0, 100.0, 1.0, -20.0);
      StepSettings set;
      set.lambda_end = 2.0; // never reached: the bar fails at lambda = 1
      set.steps = 37;       // first arc length from a load increment of 1/15
      set.max_steps = 400;
      set.convergence.force_rtol = 1e-12;
      set.convergence.force_atol = 1e-14;
      auto cb = bar_callbacks(b);
      double peak = 0, u_min_after_peak = 1;
      int on_branch = 0, worst_step = -1;
      double worst = 0;
      cb.accepted = [&](const StepRecord& rec, const StepReport&, const Eigen::VectorXd& u) {
        const double sigma = rec.lambda, uend = u[9];
        peak = std::max(peak, sigma);
        double exact = sigma * 1.0 / 100.0; // elastic branch
        if (b.kappa() > b.eps_t()) {
          exact = b.softening_u(sigma);
          ++on_branch;
          u_min_after_peak = std::min(u_min_after_peak, uend);
        }
        const double err = std::abs(uend - exact) / exact;
        if (err > worst) worst = err, worst_step = rec.step;
      };
      cb.stop = [&](double lambda, const Eigen::VectorXd&) { return b.kappa() > b.eps_t() && lambda < 0.2; };
      Eigen::VectorXd u = Eigen::VectorXd::Zero(10);
      const auto res = run_stage(b, *s->solver, set, cb, u);
      INFO(res.outcome.message << "; worst relative error " << worst << " at step " << worst_step);
      REQUIRE(res.outcome.ok());
      CHECK(res.stopped);
      CHECK(peak > 0.9);
      CHECK(peak <= 1.0 + 1e-9);
      CHECK(on_branch >= 5);
      CHECK(u_min_after_peak < 0.007); // far down the branch of decreasing u (u -> 0.006)
      CHECK(worst < 1e-6);
    }
  }
}

TEST_CASE("S1 softening bar: displacement control fails cleanly at the turning point", "[solver]") {
  SofteningBar b(10, 1.0, 100.0, 1.0, -20.0);
  auto s = load_solver("displacement_control", "dof = 9\nincrement = 0.001");
  StepSettings set;
  set.lambda_end = 2.0;
  set.max_cutbacks = 6;
  set.convergence.max_iterations = 30;
  auto cb = bar_callbacks(b);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(10);
  const auto res = run_stage(b, *s->solver, set, cb, u);
  INFO(res.outcome.message);
  CHECK_FALSE(res.outcome.ok());
  CHECK((res.outcome.status == Status::not_converged || res.outcome.status == Status::diverged));
  CHECK(res.outcome.message.find("failed") != std::string::npos);
  // It got to the turning point u = 0.01 m, lambda = 1, and no further.
  CHECK(res.lambda == Approx(1.0).epsilon(1e-9));
  CHECK(u[9] == Approx(0.01).epsilon(1e-9));
  CHECK(res.steps_done == 10);
  CHECK(res.cutbacks == 6); // every allowed halving failed, then it gave up
}

TEST_CASE("a failed step is reverted exactly: cut-back equals the smaller step from the start", "[solver]") {
  // Hardening bar (H > 0): plastic beyond lambda = 1. Run A forces the second step (0.6 -> 1.2)
  // to fail after one dirtying iteration; the controller halves it (0.6 -> 0.9 -> 1.2).
  // Run B uses those increments from the start. Both must agree bit for bit.
  auto newton = load_solver("newton");
  auto run = [&](const Solver& solver, std::vector<double> inc, StageResult& res) {
    SofteningBar b(10, 1.0, 100.0, 1.0, 30.0);
    StepSettings set;
    set.lambda_end = 1.8;
    set.increments = std::move(inc);
    set.convergence.force_rtol = 1e-12;
    auto cb = bar_callbacks(b);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(10);
    res = run_stage(b, solver, set, cb, u);
    return std::make_pair(u, b.states().committed_data());
  };
  StageResult ra, rb;
  FailOnce failing(*newton->solver, 2);
  const auto a = run(failing, {0.6}, ra);
  const auto b = run(*newton->solver, {0.6, 0.3, 0.3, 0.6}, rb);
  REQUIRE(ra.outcome.ok());
  REQUIRE(rb.outcome.ok());
  CHECK(ra.cutbacks == 1);
  CHECK(ra.steps_done == 4);
  CHECK(rb.steps_done == 4);
  REQUIRE(ra.records.size() == 5);
  CHECK_FALSE(ra.records[1].accepted);
  CHECK(ra.records[2].lambda == Approx(0.9).epsilon(1e-15));
  CHECK(a.second[12] > 0.012); // plastic: the largest strain beyond f_t/E = 0.01
  CHECK(a.first == b.first);   // bit for bit
  CHECK(a.second == b.second);
}
