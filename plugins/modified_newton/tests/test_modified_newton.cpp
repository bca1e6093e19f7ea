// Tests of the `modified_newton` and `initial_stiffness` solver plugins on a softening tanh spring
// f(u) = F1 tanh(u/e1) (tests/spring_problems.hpp), whose equilibrium is u* = e1 atanh(P/F1):
// - modified_newton: the tangent is formed at the first two iterates (u_n and u_1) and kept, so
//   the iterates are those of the recurrence u_(k+1) = u_k + (P - f(u_k))/K with K = f'(u_0) for
//   the first correction and K = f'(u_1) for the rest (residuals to 1e-12 relative), the rate is
//   linear with the contraction rho = |1 - f'(u*)/f'(u_1)| (late residual ratios within 1e-3),
//   two factorizations per step, the converged u on the closed form to 1e-10;
// - refresh_every = 1: a tangent every iteration, i.e. full Newton, with the quadratic constant
//   r_(k+1)/r_k^2 -> |f''(u*)|/(2 f'(u*)^2) (within 5 %);
// - initial_stiffness: K = f'(0) of the first state for every step (one factorization in the
//   whole stage), contraction rho = |1 - f'(u*)/f'(0)|;
// - failures as statuses (not_converged, a failing evaluation passed through).
#include "solver_helpers.hpp"
#include "spring_problems.hpp"

#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace test_modified_newton {

using namespace stratum;
using stratum::testing::load_solver;
using stratum::testing::SpringChain;

namespace {

constexpr double F1 = 50.0, e1 = 0.02; // kN, m

double f(double u) { return F1 * std::tanh(u / e1); }
double df(double u) { return F1 / (e1 * std::cosh(u / e1) * std::cosh(u / e1)); }
double u_exact(double P) { return e1 * std::atanh(P / F1); }

SpringChain spring(double P) { return SpringChain({stratum::testing::tanh_spring(F1, e1)}, P); }

StepRequest request(double lambda_n, double lambda, int max_iterations = 80) {
  StepRequest r;
  r.lambda_n = lambda_n;
  r.lambda = lambda;
  r.convergence.force_rtol = 1e-13;
  r.convergence.force_atol = 1e-14;
  r.convergence.max_iterations = max_iterations;
  return r;
}

/// Largest |r_(k+1)/r_k - rho|/rho over pairs with r_k <= upper and r_(k+1) >= lower.
double contraction_deviation(const std::vector<double>& r, double rho, double upper, double lower) {
  double worst = -1.0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k)
    if (r[k] <= upper && r[k + 1] >= lower) worst = std::max(worst, std::abs(r[k + 1] / r[k] - rho) / rho);
  return worst;
}

} // namespace

TEST_CASE("modified_newton: the tangent of the first two iterates, linear rate rho = |1 - f'(u*)/f'(u_1)|",
          "[plugins][modified_newton]") {
  const double P = 40.0; // 0.8 F1
  SpringChain one = spring(P);
  auto s = load_solver("modified_newton");
  Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  const StepReport rep = s->solver->solve(one, request(0.0, 1.0), u);
  INFO(rep.outcome.message);
  REQUIRE(rep.outcome.ok());
  const double us = u_exact(P);
  CHECK(u[0] == Approx(us).epsilon(1e-10));
  CHECK(rep.factorizations == 2);
  CHECK(one.tangents == 2);
  // The recurrence: first correction with f'(0), every later one with f'(u_1).
  const double u1 = P / df(0.0);
  std::vector<double> r_exact;
  double x = 0.0;
  for (int k = 0; k < 80; ++k) {
    const double r = P - f(x);
    r_exact.push_back(std::abs(r));
    x += r / (k == 0 ? df(0.0) : df(u1));
  }
  for (std::size_t k = 0; k < rep.residual_norms.size(); ++k) {
    if (r_exact[k] < 1e-9) break;
    INFO("iteration " << k);
    CHECK(rep.residual_norms[k] == Approx(r_exact[k]).epsilon(1e-12));
  }
  // rho = 1 - f'(u*)/f'(u_1) = 1 - 0.36/sech^2(0.8) = 0.356: the late ratios approach it.
  const double rho = std::abs(1.0 - df(us) / df(u1));
  CHECK(rho == Approx(1.0 - 0.36 * std::cosh(0.8) * std::cosh(0.8)).epsilon(1e-12));
  const double dev = contraction_deviation(rep.residual_norms, rho, 1e-5, 1e-10);
  INFO("rho = " << rho << ", residuals " << Catch::Detail::stringify(rep.residual_norms));
  REQUIRE(dev >= 0.0);
  CHECK(dev < 1e-3);
  CHECK(rep.iterations > 15); // linear: log(1e-13 P / P) / log(rho) ~ 29
}

TEST_CASE("modified_newton: refresh_every = 1 is full Newton with the quadratic constant",
          "[plugins][modified_newton]") {
  const double P = 40.0;
  SpringChain one = spring(P);
  auto s = load_solver("modified_newton", "refresh_every = 1");
  Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  const StepReport rep = s->solver->solve(one, request(0.0, 1.0), u);
  REQUIRE(rep.outcome.ok());
  const double us = u_exact(P);
  CHECK(u[0] == Approx(us).epsilon(1e-10));
  CHECK(rep.factorizations == rep.iterations);
  // |f''| / (2 f'^2) at u*: f'' = -2 (F1/e1^2) tanh sech^2.
  const double t = P / F1, sech2 = 1.0 - t * t;
  const double C = (2.0 * F1 / (e1 * e1) * t * sech2) / (2.0 * df(us) * df(us));
  const double dev = stratum::testing::quadratic_constant_deviation(rep.residual_norms, C, 1e-2, 1e-11);
  INFO("C = " << C << ", residuals " << Catch::Detail::stringify(rep.residual_norms));
  REQUIRE(dev >= 0.0);
  CHECK(dev < 0.05);
  CHECK(rep.iterations <= 7);
}

TEST_CASE("initial_stiffness: the first tangent for every step, rho = |1 - f'(u*)/f'(0)|",
          "[plugins][modified_newton]") {
  const double P = 40.0;
  SpringChain one = spring(P);
  auto s = load_solver("initial_stiffness");
  StepSettings set;
  set.increments = {0.5};
  set.convergence.force_rtol = 1e-13;
  set.convergence.force_atol = 1e-14;
  set.convergence.max_iterations = 120;
  StepCallbacks cb;
  cb.commit = [] {};
  cb.revert = [] {};
  std::vector<StepReport> reports;
  std::vector<double> lambdas, us;
  cb.accepted = [&](const StepRecord& rec, const StepReport& rep, const Eigen::VectorXd& u) {
    reports.push_back(rep);
    lambdas.push_back(rec.lambda);
    us.push_back(u[0]);
  };
  Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  const StageResult res = run_stage(one, *s->solver, set, cb, u);
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  REQUIRE(reports.size() == 2);
  CHECK(reports[0].factorizations == 1); // K_0 = f'(0), factorized once ...
  CHECK(reports[1].factorizations == 0); // ... and kept for the next step
  CHECK(one.tangents == 1);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(us[i] == Approx(u_exact(lambdas[i] * P)).epsilon(1e-10));
    const double rho = std::abs(1.0 - df(us[i]) / df(0.0));
    const double dev = contraction_deviation(reports[i].residual_norms, rho, 1e-5, 1e-10);
    INFO("step " << i + 1 << ": rho = " << rho << ", residuals "
                 << Catch::Detail::stringify(reports[i].residual_norms));
    REQUIRE(dev >= 0.0);
    CHECK(dev < 1e-3);
  }
}

TEST_CASE("modified_newton, initial_stiffness: failures are statuses", "[plugins][modified_newton]") {
  for (const std::string name : {"modified_newton", "initial_stiffness"}) {
    SECTION(name + ": not_converged after max_iterations") {
      SpringChain one = spring(40.0);
      auto s = load_solver(name);
      Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
      StepReport rep;
      REQUIRE_NOTHROW(rep = s->solver->solve(one, request(0.0, 1.0, 5), u));
      INFO(rep.outcome.message);
      CHECK(rep.outcome.status == Status::not_converged);
      CHECK(rep.iterations == 5);
      CHECK(rep.outcome.message.find(name == "modified_newton"
                                         ? "modified Newton did not converge in 5"
                                         : "initial stiffness did not converge in 5") != std::string::npos);
    }
    SECTION(name + ": no solution beyond the asymptote F1") {
      // P = 1.2 F1: |R| >= 0.2 F1 at every iterate; it must end as a status.
      SpringChain one = spring(60.0);
      auto s = load_solver(name);
      Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
      StepReport rep;
      REQUIRE_NOTHROW(rep = s->solver->solve(one, request(0.0, 1.0, 30), u));
      INFO(rep.outcome.message);
      CHECK_FALSE(rep.outcome.ok());
      for (double r : rep.residual_norms)
        if (std::isfinite(r)) CHECK(r >= 0.2 * F1 * (1 - 1e-12));
    }
    SECTION(name + ": a failing evaluation passes its status through") {
      SpringChain one = spring(40.0);
      one.fail_when = [](const Eigen::VectorXd& u) {
        return u[0] > 0.01 ? Outcome::failure(Status::material_failure, "spring broke") : Outcome::success();
      };
      auto s = load_solver(name);
      Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
      StepReport rep;
      REQUIRE_NOTHROW(rep = s->solver->solve(one, request(0.0, 1.0), u));
      CHECK(rep.outcome.status == Status::material_failure);
      CHECK(rep.outcome.message == "spring broke");
    }
  }
}

} // namespace test_modified_newton
