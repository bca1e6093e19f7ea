// Tests of the `newton` solver plugin on spring systems with closed-form equilibria
// (tests/spring_problems.hpp):
// - two springs in series (sinh and tanh laws, statically determinate): u_0 = e0 asinh(P/F0),
//   u_1 = u_0 + e1 atanh(P/F1), to 1e-10 relative, in one step and along load steps;
// - the iterates are those of the Newton recurrence u_(k+1) = u_k + (P - f(u_k))/f'(u_k) (1e-12
//   relative on every residual above round-off), and the convergence is quadratic with the
//   asymptotic constant r_(k+1)/r_k^2 -> f''(u*)/(2 f'(u*)^2) (within 5 %);
// - failures come back as statuses (not_converged after max_iterations, diverged, non_finite,
//   singular, a material failure passed through), never as exceptions; the backtracking line
//   search turns the diverging case into a converged one on the closed form.
#include "solver_helpers.hpp"
#include "spring_problems.hpp"

#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace test_newton {

using namespace stratum;
using stratum::testing::load_solver;
using stratum::testing::SpringChain;

namespace {

// Spring A: F0 = 10 kN, e0 = 0.01 m (hardening); spring B: F1 = 50 kN, e1 = 0.02 m (softening).
constexpr double F0 = 10.0, e0 = 0.01, F1 = 50.0, e1 = 0.02;

SpringChain series(double P) {
  return SpringChain({stratum::testing::sinh_spring(F0, e0), stratum::testing::tanh_spring(F1, e1)}, P);
}
double u0_exact(double f) { return e0 * std::asinh(f / F0); }
double u1_exact(double f) { return u0_exact(f) + e1 * std::atanh(f / F1); }

StepRequest request(double lambda_n, double lambda, double rtol = 1e-13) {
  StepRequest r;
  r.lambda_n = lambda_n;
  r.lambda = lambda;
  r.convergence.force_rtol = rtol;
  r.convergence.force_atol = 1e-14;
  return r;
}

} // namespace

TEST_CASE("newton: two springs in series reach the closed-form equilibrium in one step",
          "[plugins][newton]") {
  auto s = load_solver("newton");
  REQUIRE_FALSE(s->solver->path_following());
  for (const double P : {5.0, 25.0, 40.0}) {
    SpringChain chain = series(P);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
    const StepReport rep = s->solver->solve(chain, request(0.0, 1.0), u);
    INFO("P = " << P << ": " << rep.outcome.message << ", " << rep.iterations << " iterations");
    REQUIRE(rep.outcome.ok());
    CHECK(rep.lambda == 1.0);
    CHECK(u[0] == Approx(u0_exact(P)).epsilon(1e-10));
    CHECK(u[1] == Approx(u1_exact(P)).epsilon(1e-10));
    // One factorization per linear solve (the tangent is re-formed every iteration).
    CHECK(rep.factorizations == rep.iterations);
    CHECK(rep.iterations <= 10);
  }
}

TEST_CASE("newton: iterates follow the Newton recurrence and converge quadratically", "[plugins][newton]") {
  // One sinh spring, P = 40 kN (P/F0 = 4): from u = 0 the first step overshoots (convex law) and
  // the iteration then descends to u* = e0 asinh(4) = 2.0947 e0.
  const double P = 40.0;
  SpringChain one({stratum::testing::sinh_spring(F0, e0)}, P);
  auto s = load_solver("newton", "line_search = 0"); // plain Newton: its recurrence is the closed form
  Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  const StepReport rep = s->solver->solve(one, request(0.0, 1.0, 1e-15), u);
  REQUIRE(rep.outcome.ok());
  const double us = u0_exact(P);
  CHECK(u[0] == Approx(us).epsilon(1e-12));
  // The scalar recurrence, written out here.
  std::vector<double> r_exact;
  double x = 0.0;
  for (int k = 0; k < 40; ++k) {
    const double r = P - F0 * std::sinh(x / e0);
    r_exact.push_back(std::abs(r));
    if (std::abs(r) < 1e-12) break;
    x += r / (F0 / e0 * std::cosh(x / e0));
  }
  REQUIRE(rep.residual_norms.size() >= 4);
  for (std::size_t k = 0; k < rep.residual_norms.size() && k < r_exact.size(); ++k) {
    if (r_exact[k] < 1e-9) break; // round-off decides below this
    INFO("iteration " << k);
    CHECK(rep.residual_norms[k] == Approx(r_exact[k]).epsilon(1e-12));
  }
  // Quadratic: r_(k+1) = C r_k^2 (1 + O(r_k)), C = f''/(2 f'^2) at u* = sinh/(2 F0 cosh^2).
  const double C = std::sinh(us / e0) / (2.0 * F0 * std::cosh(us / e0) * std::cosh(us / e0));
  const double dev = stratum::testing::quadratic_constant_deviation(rep.residual_norms, C, 1e-2, 1e-11);
  INFO("residuals: " << Catch::Detail::stringify(rep.residual_norms) << "; C = " << C);
  REQUIRE(dev >= 0.0); // at least one pair in the asymptotic range
  CHECK(dev < 0.05);
}

TEST_CASE("newton: load steps stay on the closed-form path", "[plugins][newton]") {
  const double P = 45.0; // 0.9 F1: the tanh spring is far into its softening range
  SpringChain chain = series(P);
  auto s = load_solver("newton");
  StepSettings set;
  set.steps = 6;
  set.convergence.force_rtol = 1e-13;
  set.convergence.force_atol = 1e-14;
  StepCallbacks cb;
  cb.commit = [] {};
  cb.revert = [] {};
  int checked = 0;
  cb.accepted = [&](const StepRecord& rec, const StepReport&, const Eigen::VectorXd& u) {
    const double f = rec.lambda * P;
    CHECK(u[0] == Approx(u0_exact(f)).epsilon(1e-10));
    CHECK(u[1] == Approx(u1_exact(f)).epsilon(1e-10));
    CHECK(rec.iterations <= 6); // each step starts from the last converged state
    ++checked;
  };
  Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
  const StageResult res = run_stage(chain, *s->solver, set, cb, u);
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  CHECK(res.steps_done == 6);
  CHECK(checked == 6);
  CHECK(res.lambda == 1.0);
}

TEST_CASE("newton: failures are statuses, not exceptions", "[plugins][newton]") {
  auto s = load_solver("newton", "line_search = 0"); // plain Newton, whose failures the sections provoke
  SECTION("not_converged after max_iterations") {
    SpringChain chain = series(40.0);
    StepRequest req = request(0.0, 1.0);
    req.convergence.max_iterations = 2;
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(chain, req, u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::not_converged);
    CHECK(rep.iterations == 2);
    CHECK(rep.outcome.message.find("did not converge in 2 iterations") != std::string::npos);
  }
  SECTION("diverged: the residual grows beyond divergence_factor") {
    // sinh spring, P = 1000 kN: the first correction jumps to u = P e0/F0 = 1 m where
    // f = F0 sinh(100) = 1.3e44 kN; the next iterate (u = 0.99 m) is still 4.9e43 kN > 1e6 P.
    SpringChain one({stratum::testing::sinh_spring(F0, e0)}, 1000.0);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(one, request(0.0, 1.0), u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::diverged);
    CHECK(rep.residual_norms.size() == 3);
    CHECK(rep.residual_norms[1] == Approx(F0 * std::sinh(100.0) - 1000.0).epsilon(1e-12));
  }
  SECTION("the line search turns the same step into a converged one") {
    SpringChain one({stratum::testing::sinh_spring(F0, e0)}, 1000.0);
    auto ls = load_solver("newton", "line_search = 8");
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    StepRequest req = request(0.0, 1.0);
    req.convergence.max_iterations = 60;
    const StepReport rep = ls->solver->solve(one, req, u);
    INFO(rep.outcome.message);
    REQUIRE(rep.outcome.ok());
    CHECK(u[0] == Approx(u0_exact(1000.0)).epsilon(1e-12));
  }
  SECTION("non_finite: the residual overflows") {
    // P = 1e6 kN: the first correction gives u = 1000 m, sinh(1e5) = Inf.
    SpringChain one({stratum::testing::sinh_spring(F0, e0)}, 1e6);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(one, request(0.0, 1.0), u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::non_finite);
  }
  SECTION("singular: a zero tangent") {
    // f(e) = c e^3 has f'(0) = 0: the first factorization fails.
    stratum::testing::SpringLaw cubic{[](double e) { return 100.0 * e * e * e; },
                                      [](double e) { return 300.0 * e * e; },
                                      [](double e) { return 600.0 * e; }};
    SpringChain one({cubic}, 1.0);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(one, request(0.0, 1.0), u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::singular);
    CHECK(rep.iterations == 0);
  }
  SECTION("a failing evaluation passes its status and message through") {
    SpringChain chain = series(40.0);
    chain.fail_when = [](const Eigen::VectorXd& u) {
      return u[1] > 0.01 ? Outcome::failure(Status::material_failure, "spring B broke") : Outcome::success();
    };
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(chain, request(0.0, 1.0), u));
    CHECK(rep.outcome.status == Status::material_failure);
    CHECK(rep.outcome.message == "spring B broke");
  }
}

} // namespace test_newton
