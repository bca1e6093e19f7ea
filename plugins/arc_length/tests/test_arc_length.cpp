// Tests of the `arc_length` solver plugin on the shallow two-bar (von Mises) truss, whose
// equilibrium path is known in closed form (tests/spring_problems.hpp): apex force
//   F(w) = 2 k (L0 - L) (h - w)/L,  L = sqrt(a^2 + (h - w)^2),
// with limit points where L^3 = a^2 L0, at w = h -+ sqrt(L*^2 - a^2) (F_max = -F_min); between
// them the truss snaps through (the load falls, turns negative and rises again).
// - One unknown (the apex), cylindrical constraint: every converged point on lambda P = F(w)
//   (1e-9 of the force scale), every step |dw| = s (1e-12), the path passes both limit points, and
//   the largest / smallest load factor reached is within the discretisation bound
//   |F''| (s/2)^2 / 2 of F(w_max) / F(w_min);
// - the spherical constraint keeps dw^2 + psi^2 dl^2 = s^2 (1e-10) on the same path;
// - two unknowns (a soft spring k_s on the apex, the load on its top v = w + F(w)/k_s): snap-back
//   where F'(w) < -k_s; arc length follows the branch of decreasing v with every point on the
//   closed form and the turning points of v (F'(w) = -k_s, found by bisection of the closed-form
//   F') bracketing the points where v turns;
// - failures are statuses (not_converged after max_iterations, a failing evaluation passed
//   through), never exceptions.
#include "solver_helpers.hpp"
#include "spring_problems.hpp"

#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace test_arc_length {

using namespace stratum;
using stratum::testing::load_solver;
using stratum::testing::MisesTruss;
using stratum::testing::SpringChain;

namespace {

struct Point {
  double lambda;
  Eigen::VectorXd u;
  double arc_length;
};

/// Runs arc length from the unloaded state with the step size s until the apex passes w_stop.
std::vector<Point> trace(SpringChain& problem, const std::string& params, double s, double w_stop,
                         StageResult& res, int max_steps = 400) {
  auto solver = load_solver("arc_length", params);
  REQUIRE(solver->solver->path_following());
  StepSettings set;
  set.lambda_end = 1e6; // never reached: the stop rule ends the stage
  set.arc_length = s;
  set.max_steps = max_steps;
  set.convergence.force_rtol = 1e-12;
  set.convergence.force_atol = 1e-12;
  set.convergence.max_iterations = 30;
  StepCallbacks cb;
  cb.commit = [] {};
  cb.revert = [] {};
  std::vector<Point> pts;
  cb.accepted = [&](const StepRecord& rec, const StepReport&, const Eigen::VectorXd& u) {
    pts.push_back({rec.lambda, u, rec.arc_length});
  };
  cb.stop = [w_stop](double, const Eigen::VectorXd& u) { return u[0] > w_stop; };
  Eigen::VectorXd u = Eigen::VectorXd::Zero(problem.size());
  res = run_stage(problem, *solver->solver, set, cb, u);
  return pts;
}

/// |F''| bound near w (central difference of the closed-form F', for the discretisation bound only).
double curvature(const MisesTruss& t, double w) {
  const double d = 1e-5;
  return std::abs(t.dF(w + d) - t.dF(w - d)) / (2 * d);
}

} // namespace

TEST_CASE("arc_length: the Mises truss snaps through both limit points on the closed-form path",
          "[plugins][arc_length]") {
  const MisesTruss truss; // k = 1000 kN/m, a = 1 m, h = 0.5 m
  // Guards on the closed form: F(0) = F(h) = F(2h) = 0, F' = 0 at the limit points, antisymmetry.
  CHECK(truss.F(truss.h) == Approx(0.0).margin(1e-12));
  CHECK(truss.F(2 * truss.h) == Approx(0.0).margin(1e-12));
  CHECK(truss.dF(truss.w_max()) == Approx(0.0).margin(1e-9));
  CHECK(truss.dF(truss.w_min()) == Approx(0.0).margin(1e-9));
  CHECK(truss.dF(0.0) == Approx(2 * truss.k * truss.h * truss.h / (truss.L0() * truss.L0())).epsilon(1e-14));
  CHECK(truss.F(truss.w_min()) == Approx(-truss.F(truss.w_max())).epsilon(1e-12));
  const double P = 1.0, s = 0.01;
  const double lmax = truss.F(truss.w_max()) / P, lmin = truss.F(truss.w_min()) / P;
  SpringChain one({truss.law()}, P);
  StageResult res;
  const auto pts = trace(one, "", s, 1.2, res);
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  REQUIRE(res.stopped);
  REQUIRE(pts.size() >= 120);
  double top = -1e300, bottom = 1e300, w_prev = 0.0, worst_path = 0.0, worst_step = 0.0;
  for (const Point& p : pts) {
    const double w = p.u[0];
    worst_path = std::max(worst_path, std::abs(p.lambda * P - truss.F(w)) / (std::abs(p.lambda * P) + 1.0));
    worst_step = std::max(worst_step, std::abs((w - w_prev) - s) / s); // the apex never turns back
    w_prev = w;
    if (w < truss.h) top = std::max(top, p.lambda);           // the first (rising) branch
    if (w < 2 * truss.h) bottom = std::min(bottom, p.lambda); // before the stiffening branch
  }
  INFO("worst path error " << worst_path << ", worst |dw| - s " << worst_step << "; lambda reached " << top
                           << " / " << bottom << " against " << lmax << " / " << lmin);
  CHECK(worst_path < 1e-9);
  CHECK(worst_step < 1e-12);
  // Closed-form limit loads: the points are at most s/2 from the limit point along w.
  CHECK(top <= lmax * (1 + 1e-12));
  CHECK(top >= lmax - 0.5 * curvature(truss, truss.w_max()) * 0.25 * s * s * 1.5);
  CHECK(bottom >= lmin * (1 + 1e-12));
  CHECK(bottom <= lmin + 0.5 * curvature(truss, truss.w_min()) * 0.25 * s * s * 1.5);
  // Past both limit points: the last point is on the stiffening branch beyond w = 2h with F > 0.
  CHECK(pts.back().u[0] > 2 * truss.h);
  CHECK(pts.back().lambda > 0.0);
}

TEST_CASE("arc_length: the spherical constraint keeps dw^2 + psi^2 dlambda^2 = s^2",
          "[plugins][arc_length]") {
  const MisesTruss truss;
  const double P = 1.0, s = 0.02, psi = 1e-3; // psi in m per unit load factor
  SpringChain one({truss.law()}, P);
  StageResult res;
  const auto pts = trace(one, "constraint = \"spherical\"\npsi = 0.001", s, 1.2, res);
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  REQUIRE(pts.size() >= 20);
  double w_prev = 0.0, l_prev = 0.0, worst_size = 0.0, worst_path = 0.0, top = -1e300;
  for (const Point& p : pts) {
    const double dw = p.u[0] - w_prev, dl = p.lambda - l_prev;
    worst_size = std::max(worst_size, std::abs(std::sqrt(dw * dw + psi * psi * dl * dl) - s) / s);
    worst_path = std::max(worst_path, std::abs(p.lambda * P - truss.F(p.u[0])) / (std::abs(p.lambda) + 1.0));
    CHECK(dw > 0.0);
    CHECK(p.arc_length == Approx(s).epsilon(1e-10)); // the measured size (4.19) is the constraint's
    w_prev = p.u[0], l_prev = p.lambda;
    if (p.u[0] < truss.h) top = std::max(top, p.lambda);
  }
  INFO("worst relative step-size error " << worst_size << ", worst path error " << worst_path);
  CHECK(worst_size < 1e-10);
  CHECK(worst_path < 1e-9);
  CHECK(top <= truss.F(truss.w_max()) / P * (1 + 1e-12));
  CHECK(pts.back().u[0] > 2 * truss.h);
}

TEST_CASE("arc_length: snap-back of the truss on a soft spring follows the branch of decreasing v",
          "[plugins][arc_length]") {
  // Unknowns (w, v): the truss apex and the top of a spring k_s = 100 kN/m on it, loaded at v.
  // Equilibrium: k_s (v - w) = lambda P = F(w), so v(w) = w + F(w)/k_s; dv/dw = 1 + F'(w)/k_s < 0
  // where F'(w) < -k_s (F'(h) = 2 k (a - L0)/a = -236 kN/m): v turns back twice.
  const MisesTruss truss;
  const double ks = 100.0, P = 1.0, s = 0.01;
  REQUIRE(truss.dF(truss.h) == Approx(2 * truss.k * (truss.a - truss.L0()) / truss.a).epsilon(1e-14));
  REQUIRE(truss.dF(truss.h) < -ks);
  // Turning points of v: F'(w) = -k_s on either side of h, by bisection of the closed-form F'.
  auto root = [&](double lo, double hi) {
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((truss.dF(lo) + ks) * (truss.dF(mid) + ks) <= 0 ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  };
  const double wa = root(truss.w_max(), truss.h), wb = root(truss.h, truss.w_min());
  auto v_of = [&](double w) { return w + truss.F(w) / ks; };
  const stratum::testing::SpringLaw linear{[ks](double e) { return ks * e; }, [ks](double) { return ks; },
                                           [](double) { return 0.0; }};
  SpringChain two({truss.law(), linear}, P);
  StageResult res;
  const auto pts = trace(two, "", s, 1.2, res, 600);
  INFO(res.outcome.message);
  REQUIRE(res.outcome.ok());
  REQUIRE(res.stopped);
  double worst = 0.0, w_prev = 0.0, v_prev = 0.0, v_peak = -1e300, v_valley = 1e300;
  int falling = 0;
  for (const Point& p : pts) {
    const double w = p.u[0], v = p.u[1];
    worst = std::max(worst, std::abs(p.lambda * P - truss.F(w)) / (std::abs(p.lambda) + 1.0));
    worst = std::max(worst, std::abs(v - v_of(w)));
    CHECK(w > w_prev); // the path parameter along the truss never reverses
    if (v < v_prev) {
      ++falling;
      // v falls only between the two turning points (one step of tolerance on either side).
      CHECK(w >= wa - s);
      CHECK(w_prev <= wb + s);
      v_peak = std::max(v_peak, v_prev);
      v_valley = std::min(v_valley, v);
    }
    w_prev = w, v_prev = v;
  }
  INFO("worst path error " << worst << "; v falls in " << falling << " steps; turning points w = " << wa
                           << ", " << wb);
  CHECK(worst < 1e-9);
  CHECK(falling >= 5);
  // The highest and lowest v reached around the snap-back stay within the closed-form turning values.
  CHECK(v_peak <= v_of(wa) + 1e-12);
  CHECK(v_valley >= v_of(wb) - 1e-12);
  CHECK(pts.back().u[0] > 2 * truss.h);
}

TEST_CASE("arc_length: failures are statuses, not exceptions", "[plugins][arc_length]") {
  const MisesTruss truss;
  auto s = load_solver("arc_length");
  SECTION("not_converged after max_iterations") {
    SpringChain two({stratum::testing::sinh_spring(10.0, 0.01), stratum::testing::tanh_spring(50.0, 0.02)},
                    1.0);
    StepRequest req;
    req.lambda_n = 0.0;
    req.lambda = 40.0;
    req.convergence.force_rtol = 1e-14;
    req.convergence.force_atol = 1e-14;
    req.convergence.max_iterations = 1;
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2);
    StepReport rep;
    REQUIRE_NOTHROW(rep = s->solver->solve(two, req, u));
    INFO(rep.outcome.message);
    CHECK(rep.outcome.status == Status::not_converged);
    CHECK(rep.outcome.message.find("arc length did not converge in 1 iterations") != std::string::npos);
  }
  SECTION("a failing evaluation passes its status through") {
    // Evaluations beyond w = 0.055 m fail: the steps before are accepted, the cut-backs end in
    // the evaluation's status.
    SpringChain one({truss.law()}, 1.0);
    one.fail_when = [](const Eigen::VectorXd& u) {
      return u[0] > 0.055 ? Outcome::failure(Status::material_failure, "bar buckled") : Outcome::success();
    };
    StageResult res;
    std::vector<Point> pts;
    REQUIRE_NOTHROW(pts = trace(one, "", 0.01, 1.2, res));
    INFO(res.outcome.message);
    CHECK(res.outcome.status == Status::material_failure);
    CHECK(res.outcome.message.find("bar buckled") != std::string::npos);
    REQUIRE(pts.size() >= 5);
    for (const Point& p : pts) {
      CHECK(p.u[0] <= 0.055);
      CHECK(p.lambda == Approx(truss.F(p.u[0])).epsilon(1e-9));
    }
  }
}

} // namespace test_arc_length
