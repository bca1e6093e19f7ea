// Tests of the `kinsol` solver plugin (SUNDIALS KINSOL) on spring systems with closed-form
// equilibria (tests/spring_problems.hpp):
// - two springs in series (sinh, tanh): u_0 = e0 asinh(P/F0), u_1 = u_0 + e1 atanh(P/F1), reached
//   by each strategy (newton, picard, fixed_point) to 1e-9 relative, also along load steps;
// - strategy newton: quadratic convergence on one sinh spring, the residual ratio
//   r_(k+1)/r_k^2 -> f''(u*)/(2 f'(u*)^2) (within 5 %), one factorization per iteration;
// - strategies picard and fixed_point (anderson = 0): the tangent of the step start only (one
//   factorization), the linear rate rho = max_i |1 - k_i(u*)/k_i(0)| of springs in series (late
//   residual ratios within 1 %), and divergence (a status) where rho > 1;
// - failures come back as statuses with the KINSOL flag named: no solution beyond the asymptote
//   of a tanh spring (not_converged or diverged), max_iterations reached, a failing evaluation
//   (its own status and message), never as exceptions.
#include "solver_helpers.hpp"
#include "spring_problems.hpp"

#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace test_kinsol {

using namespace stratum;
using stratum::testing::load_solver;
using stratum::testing::SpringChain;

namespace {

constexpr double F0 = 10.0, e0 = 0.01, F1 = 50.0, e1 = 0.02;

SpringChain series(double P) {
  return SpringChain({stratum::testing::sinh_spring(F0, e0), stratum::testing::tanh_spring(F1, e1)}, P);
}
double u0_exact(double f) { return e0 * std::asinh(f / F0); }
double u1_exact(double f) { return u0_exact(f) + e1 * std::atanh(f / F1); }

StepRequest request(double lambda, int max_iterations = 200) {
  StepRequest r;
  r.lambda_n = 0.0;
  r.lambda = lambda;
  r.convergence.force_rtol = 1e-12;
  r.convergence.force_atol = 1e-13;
  r.convergence.max_iterations = max_iterations;
  return r;
}

} // namespace

TEST_CASE("kinsol: every strategy reaches the closed-form equilibrium of two springs in series",
          "[plugins][kinsol]") {
  // Picard and fixed point iterate with K_0 = K(u_n); on a chain of springs in series
  // K_0^-1 K(u*) has the eigenvalues k_i(u*)/k_i(0), so the error contracts by
  // rho = max_i |1 - k_i(u*)/k_i(0)|: for P = 10 kN the sinh spring's cosh(asinh(1)) - 1 = 0.414
  // (the tanh spring's 1 - sech^2(atanh(0.2)) = 0.04). Anderson acceleration is off (anderson = 0):
  // the plain iterations have this closed-form rate. (With the default depth 5 KINSOL's Anderson
  // step produced NaN after 3-4 iterations on these chains, whose iterates span only as many
  // directions as there are distinct springs: a degenerate least-squares history. Not tested here.)
  for (const std::string strategy : {"newton", "picard", "fixed_point"}) {
    SECTION(strategy) {
      auto s = load_solver("kinsol", "strategy = \"" + strategy + "\"\nanderson = 0");
      REQUIRE_FALSE(s->solver->path_following());
      for (const double P : {5.0, 10.0}) {
        SpringChain chain = series(P);
        Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
        const StepReport rep = s->solver->solve(chain, request(1.0), u);
        INFO(strategy << ", P = " << P << ": " << rep.outcome.message << ", " << rep.iterations
                      << " iterations; residuals " << Catch::Detail::stringify(rep.residual_norms));
        REQUIRE(rep.outcome.ok());
        CHECK(u[0] == Approx(u0_exact(P)).epsilon(1e-9));
        CHECK(u[1] == Approx(u1_exact(P)).epsilon(1e-9));
        // The plugin's own force test at KINSOL's answer: |R| <= 1e-12 (|lambda P| + 1).
        CHECK(rep.residual_norms.back() <= 1e-12 * (P + 1.0));
        if (strategy == "newton") continue;
        CHECK(rep.factorizations == 1); // the step-start tangent only
        const double rho = std::max(std::cosh(std::asinh(P / F0)) - 1.0,
                                    1.0 - 1.0 / std::pow(std::cosh(std::atanh(P / F1)), 2));
        double worst = -1.0;
        const auto& r = rep.residual_norms;
        for (std::size_t k = 0; k + 1 < r.size(); ++k)
          if (r[k] < 1e-4 * P && r[k + 1] > 1e-10 * P)
            worst = std::max(worst, std::abs(r[k + 1] / r[k] - rho) / rho);
        INFO("rho = " << rho);
        REQUIRE(worst >= 0.0);
        CHECK(worst < 0.01);
      }
    }
  }
}

TEST_CASE("kinsol: load steps through run_stage stay on the closed-form path", "[plugins][kinsol]") {
  const double P = 45.0; // 0.9 F1
  SpringChain chain = series(P);
  auto s = load_solver("kinsol");
  StepSettings set;
  set.steps = 5;
  set.convergence.force_rtol = 1e-12;
  set.convergence.force_atol = 1e-13;
  StepCallbacks cb;
  cb.commit = [] {};
  cb.revert = [] {};
  int checked = 0;
  cb.accepted = [&](const StepRecord& rec, const StepReport&, const Eigen::VectorXd& u) {
    CHECK(u[0] == Approx(u0_exact(rec.lambda * P)).epsilon(1e-9));
    CHECK(u[1] == Approx(u1_exact(rec.lambda * P)).epsilon(1e-9));
    ++checked;
  };
  Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
  const StageResult res = run_stage(chain, *s->solver, set, cb, u);
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  CHECK(checked == 5);
  CHECK(res.lambda == 1.0);
}

TEST_CASE("kinsol: strategy newton converges quadratically", "[plugins][kinsol]") {
  // One sinh spring, P = 40 kN: C = f''/(2 f'^2) at u* = sinh/(2 F0 cosh^2).
  const double P = 40.0;
  SpringChain one({stratum::testing::sinh_spring(F0, e0)}, P);
  auto s = load_solver("kinsol", "strategy = \"newton\"");
  Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  StepRequest req = request(1.0);
  req.convergence.force_rtol = 1e-15;
  req.convergence.force_atol = 1e-15;
  const StepReport rep = s->solver->solve(one, req, u);
  INFO(rep.outcome.message << "; residuals " << Catch::Detail::stringify(rep.residual_norms));
  // KINSOL may stop a little above 1e-15 (round-off); what matters here is the rate on the way.
  const double us = u0_exact(P);
  CHECK(u[0] == Approx(us).epsilon(1e-12));
  const double C = std::sinh(us / e0) / (2.0 * F0 * std::cosh(us / e0) * std::cosh(us / e0));
  const double dev = stratum::testing::quadratic_constant_deviation(rep.residual_norms, C, 1e-2, 1e-11);
  REQUIRE(dev >= 0.0);
  CHECK(dev < 0.05);
  CHECK(rep.factorizations <= rep.iterations + 1); // the Jacobian re-formed every iteration
  CHECK(rep.iterations <= 12);
}

TEST_CASE("kinsol: failures are statuses naming the KINSOL flag", "[plugins][kinsol]") {
  SECTION("no solution beyond the asymptote of a tanh spring") {
    for (const std::string strategy : {"newton", "picard", "fixed_point"}) {
      SpringChain one({stratum::testing::tanh_spring(F1, e1)}, 1.2 * F1);
      auto s = load_solver("kinsol", "strategy = \"" + strategy + "\"");
      Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
      StepReport rep;
      REQUIRE_NOTHROW(rep = s->solver->solve(one, request(1.0, 50), u));
      INFO(strategy << ": " << rep.outcome.message);
      CHECK_FALSE(rep.outcome.ok());
      CHECK(rep.outcome.message.find("KINSOL") != std::string::npos);
    }
  }
  SECTION("plain Picard and fixed point diverge when k(u*)/k(0) > 2") {
    // P = 25 kN: cosh(asinh(2.5)) = 2.69, so rho = 1.69 > 1: no convergence, a status.
    for (const std::string strategy : {"picard", "fixed_point"}) {
      SpringChain chain = series(25.0);
      auto s = load_solver("kinsol", "strategy = \"" + strategy + "\"\nanderson = 0");
      Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
      StepReport rep;
      REQUIRE_NOTHROW(rep = s->solver->solve(chain, request(1.0, 50), u));
      INFO(strategy << ": " << rep.outcome.message);
      CHECK_FALSE(rep.outcome.ok());
      CHECK(rep.outcome.message.find("KINSOL") != std::string::npos);
    }
  }
  SECTION("max_iterations reached") {
    SpringChain chain = series(40.0);
    auto s = load_solver("kinsol");
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(chain, request(1.0, 1), u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::not_converged);
    CHECK(rep.outcome.message.find("KIN_MAXITER_REACHED") != std::string::npos);
  }
  SECTION("a failing evaluation keeps its status and message") {
    SpringChain chain = series(40.0);
    chain.fail_when = [](const Eigen::VectorXd& u) {
      return u[1] > 0.01 ? Outcome::failure(Status::material_failure, "spring B broke") : Outcome::success();
    };
    auto s = load_solver("kinsol");
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(chain, request(1.0), u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::material_failure);
    CHECK(rep.outcome.message.find("spring B broke") != std::string::npos);
    CHECK(rep.outcome.message.find("inside KINSOL") != std::string::npos);
  }
}

} // namespace test_kinsol
