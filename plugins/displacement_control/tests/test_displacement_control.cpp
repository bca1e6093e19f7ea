// Tests of the `displacement_control` solver plugin on spring systems with closed-form paths
// (tests/spring_problems.hpp):
// - a sinh spring driven to a prescribed displacement: after n steps of d the controlled DOF is
//   n d (1e-12) and the load factor F0 sinh(n d/e0)/P (1e-10), in either direction;
// - the shallow Mises truss (apex force F(w) = 2 k (L0 - L)(h - w)/L) under control of the apex:
//   through both limit points of the load (snap-through under load control), every step
//   w = k d (1e-12) and lambda P = F(w) (1e-9 of the force scale), the measured step size d;
// - the truss on a soft spring k_s, load on its top v = w + F(w)/k_s, which snaps back where
//   F'(w) < -k_s: controlling the apex (dof 0, or the node set "apex") passes the snap-back on the
//   closed form; controlling the mean of both unknowns keeps (w + v)/2 = k d; controlling v jumps
//   over the branch where v falls (between the turning points F'(w) = -k_s, bisection of the
//   closed-form F') to the far branch, with every point on the closed form;
// - in one unknown a single correction gives lambda = f(d)/P (R is linear in lambda at fixed u);
//   configuration errors (unknown node set, dof out of range, neither given) and max_iterations
//   are statuses, not exceptions.
#include "solver_helpers.hpp"
#include "spring_problems.hpp"

#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace test_displacement_control {

using namespace stratum;
using stratum::testing::load_solver;
using stratum::testing::MisesTruss;
using stratum::testing::SpringChain;

namespace {

struct Point {
  int step;
  double lambda;
  Eigen::VectorXd u;
  double size;
};

std::vector<Point> drive(SpringChain& problem, const std::string& params, int max_steps, StageResult& res,
                         int max_cutbacks = 4) {
  auto solver = load_solver("displacement_control", params);
  REQUIRE(solver->solver->path_following());
  StepSettings set;
  set.lambda_end = 1e6; // never reached: max_steps ends the stage
  set.max_steps = max_steps;
  set.max_cutbacks = max_cutbacks;
  set.convergence.force_rtol = 1e-12;
  set.convergence.force_atol = 1e-12;
  set.convergence.max_iterations = 30;
  StepCallbacks cb;
  cb.commit = [] {};
  cb.revert = [] {};
  std::vector<Point> pts;
  cb.accepted = [&](const StepRecord& rec, const StepReport&, const Eigen::VectorXd& u) {
    pts.push_back({rec.step, rec.lambda, u, rec.arc_length});
  };
  Eigen::VectorXd u = Eigen::VectorXd::Zero(problem.size());
  res = run_stage(problem, *solver->solver, set, cb, u);
  return pts;
}

stratum::testing::SpringLaw linear(double k) {
  return {[k](double e) { return k * e; }, [k](double) { return k; }, [](double) { return 0.0; }};
}

} // namespace

TEST_CASE("displacement_control: a hardening spring driven to a prescribed displacement",
          "[plugins][displacement_control]") {
  const double F0 = 10.0, e0 = 0.01, P = 5.0, d = 0.004;
  SpringChain one({stratum::testing::sinh_spring(F0, e0)}, P);
  StageResult res;
  const auto pts = drive(one, "dof = 0\nincrement = 0.004", 10, res);
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  CHECK(res.stopped); // by max_steps
  REQUIRE(pts.size() == 10);
  for (const Point& p : pts) {
    const double w = p.step * d;
    CHECK(p.u[0] == Approx(w).epsilon(1e-12));
    CHECK(p.lambda == Approx(F0 * std::sinh(w / e0) / P).epsilon(1e-10));
    CHECK(p.size == Approx(d).epsilon(1e-12));
  }
  // The prescribed 0.04 m is reached: lambda = F0 sinh(4)/P = 54.58.
  CHECK(pts.back().u[0] == Approx(0.04).epsilon(1e-12));
  CHECK(res.lambda == Approx(2.0 * std::sinh(4.0)).epsilon(1e-10));
  // A negative increment drives the spring the other way (lambda < 0 on the odd law).
  SpringChain back({stratum::testing::sinh_spring(F0, e0)}, P);
  const auto neg = drive(back, "dof = 0\nincrement = -0.004", 3, res);
  REQUIRE(res.outcome.ok());
  REQUIRE(neg.size() == 3);
  CHECK(neg.back().u[0] == Approx(-0.012).epsilon(1e-12));
  CHECK(neg.back().lambda == Approx(-F0 * std::sinh(1.2) / P).epsilon(1e-10));
}

TEST_CASE("displacement_control: the Mises truss through both limit loads",
          "[plugins][displacement_control]") {
  const MisesTruss truss; // k = 1000 kN/m, a = 1 m, h = 0.5 m
  const double P = 1.0, d = 0.02;
  SpringChain one({truss.law()}, P);
  StageResult res;
  const auto pts = drive(one, "dof = 0\nincrement = 0.02", 60, res); // to w = 1.2 m
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  REQUIRE(pts.size() == 60);
  double top = -1e300, bottom = 1e300, worst = 0.0;
  for (const Point& p : pts) {
    const double w = p.step * d;
    CHECK(p.u[0] == Approx(w).epsilon(1e-12));
    worst = std::max(worst, std::abs(p.lambda * P - truss.F(w)) / (std::abs(p.lambda * P) + 1.0));
    if (w < truss.h) top = std::max(top, p.lambda);
    if (w < 2 * truss.h) bottom = std::min(bottom, p.lambda);
  }
  CHECK(worst < 1e-9);
  // The grid w = k d brackets both limit points; the extreme load factors are the closed form's
  // maximum and minimum over the grid, and below |F(w_max)| = 42.91 kN.
  double grid_top = -1e300, grid_bottom = 1e300;
  for (int k = 1; k * d < 2 * truss.h; ++k) {
    if (k * d < truss.h) grid_top = std::max(grid_top, truss.F(k * d));
    grid_bottom = std::min(grid_bottom, truss.F(k * d));
  }
  CHECK(top == Approx(grid_top / P).epsilon(1e-10));
  CHECK(bottom == Approx(grid_bottom / P).epsilon(1e-10));
  CHECK(top <= truss.F(truss.w_max()) / P);
  CHECK(bottom >= truss.F(truss.w_min()) / P);
  CHECK(pts.back().lambda == Approx(truss.F(1.2) / P).epsilon(1e-10));
}

TEST_CASE("displacement_control: snap-back: control of the apex follows it, control of the top jumps it",
          "[plugins][displacement_control]") {
  const MisesTruss truss;
  const double ks = 100.0, P = 1.0, d = 0.02;
  auto v_of = [&](double w) { return w + truss.F(w) / ks; };
  auto check_path = [&](const std::vector<Point>& pts) {
    double worst = 0.0;
    for (const Point& p : pts) {
      worst = std::max(worst, std::abs(p.lambda * P - truss.F(p.u[0])) / (std::abs(p.lambda * P) + 1.0));
      worst = std::max(worst, std::abs(p.u[1] - v_of(p.u[0])));
    }
    return worst;
  };
  SECTION("the apex by dof and by node set") {
    for (const std::string params : {"dof = 0\nincrement = 0.02", "nodes = \"apex\"\nincrement = 0.02"}) {
      SpringChain two({truss.law(), linear(ks)}, P);
      two.sets["apex"] = {0};
      StageResult res;
      const auto pts = drive(two, params, 60, res);
      INFO(params << ": " << res.outcome.message);
      REQUIRE(res.outcome.ok());
      REQUIRE(pts.size() == 60);
      for (const Point& p : pts) CHECK(p.u[0] == Approx(p.step * d).epsilon(1e-12));
      CHECK(check_path(pts) < 1e-9);
      // v went back and forth: its largest value is before the snap-back, above the final one.
      double vmax = -1e300;
      for (const Point& p : pts) vmax = std::max(vmax, p.u[1]);
      CHECK(vmax > pts[30].u[1]);
    }
  }
  SECTION("the mean of both unknowns (a node set of two)") {
    SpringChain two({truss.law(), linear(ks)}, P);
    two.sets["both"] = {0, 1};
    StageResult res;
    const auto pts = drive(two, "nodes = \"both\"\ncomponent = \"y\"\nincrement = 0.01", 20, res);
    INFO(res.outcome.message);
    REQUIRE(res.outcome.ok());
    REQUIRE(pts.size() == 20);
    for (const Point& p : pts) CHECK(0.5 * (p.u[0] + p.u[1]) == Approx(0.01 * p.step).epsilon(1e-12));
    CHECK(check_path(pts) < 1e-9);
  }
  SECTION("the top v: the snap-back branch is jumped over") {
    // v's turning points: F'(w) = -k_s on either side of h (bisection of the closed-form F').
    auto root = [&](double lo, double hi) {
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((truss.dF(lo) + ks) * (truss.dF(mid) + ks) <= 0 ? hi : lo) = mid;
      }
      return 0.5 * (lo + hi);
    };
    const double wa = root(truss.w_max(), truss.h), wb = root(truss.h, truss.w_min());
    const double v_turn = v_of(wa);
    // Under control of v, which only grows, the branch wa < w < wb (where v falls) is never an
    // equilibrium of a step: the first target beyond v_turn lies on the far branch w > wb, where v
    // rises again (v = v_turn there at w = 0.95 m).
    SpringChain two({truss.law(), linear(ks)}, P);
    StageResult res;
    std::vector<Point> pts;
    REQUIRE_NOTHROW(pts = drive(two, "dof = 1\nincrement = 0.02", 60, res, 6));
    INFO(res.outcome.message << "; turning points w = " << wa << ", " << wb << ", v_turn = " << v_turn);
    REQUIRE(res.outcome.ok());
    REQUIRE(pts.size() == 60);
    CHECK(check_path(pts) < 1e-9);
    int jumped = 0;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const double w = pts[k].u[0], v = pts[k].u[1];
      // Each step advances v by its size (d, or d/2^k after cut-backs at the jump).
      CHECK(v - (k > 0 ? pts[k - 1].u[1] : 0.0) == Approx(pts[k].size).epsilon(1e-10));
      CHECK(pts[k].size <= d * (1 + 1e-12));
      CHECK((w <= wa || w >= wb)); // never on the falling branch
      if (v > v_turn) {
        CHECK(w > wb);
        if (k > 0 && pts[k - 1].u[1] <= v_turn) {
          ++jumped; // the snap: w jumps across (wa, wb), the load drops to a negative value
          CHECK(pts[k - 1].u[0] <= wa);
          CHECK(pts[k].lambda < 0.0);
          CHECK(pts[k - 1].lambda > 0.0);
        }
      } else {
        CHECK(w <= wa);
      }
    }
    CHECK(jumped == 1);
  }
}

TEST_CASE("displacement_control: configuration errors are statuses", "[plugins][displacement_control]") {
  SpringChain one({stratum::testing::sinh_spring(10.0, 0.01)}, 1.0);
  for (const std::string params :
       {"nodes = \"nowhere\"\nincrement = 0.01", "dof = 5\nincrement = 0.01", "increment = 0.01"}) {
    auto s = load_solver("displacement_control", params);
    StepRequest req;
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(one, req, u));
    INFO(params << ": " << rep.outcome.message);
    CHECK(rep.outcome.status == Status::singular);
    CHECK(rep.outcome.message.find("displacement control") != std::string::npos);
  }
  // In one unknown the controlled displacement fixes u, and R is linear in lambda: one correction
  // gives lambda = F0 sinh(3)/P exactly (round-off).
  {
    auto s = load_solver("displacement_control", "dof = 0\nincrement = 0.03");
    StepRequest req;
    req.convergence.force_rtol = 1e-12;
    req.convergence.force_atol = 1e-12;
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    const StepReport rep = s->solver->solve(one, req, u);
    INFO(rep.outcome.message);
    REQUIRE(rep.outcome.ok());
    CHECK(rep.iterations == 1);
    CHECK(u[0] == Approx(0.03).epsilon(1e-14));
    CHECK(rep.lambda == Approx(10.0 * std::sinh(3.0)).epsilon(1e-12));
  }
  // Two springs in series (sinh, tanh): one correction cannot reach 1e-14; max_iterations = 1 fails.
  {
    SpringChain two({stratum::testing::sinh_spring(10.0, 0.01), stratum::testing::tanh_spring(50.0, 0.02)},
                    1.0);
    auto s = load_solver("displacement_control", "dof = 1\nincrement = 0.04");
    StepRequest req;
    req.convergence.force_rtol = 1e-14;
    req.convergence.force_atol = 1e-14;
    req.convergence.max_iterations = 1;
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(two, req, u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::not_converged);
    CHECK(rep.outcome.message.find("displacement control did not converge in 1 iterations") !=
          std::string::npos);
  }
}

} // namespace test_displacement_control
