// Global solvers and step control (issue 6): the softening bar S1, exact revert
// after a cut-back, and (below) the strip footing and the Newton variants.
#include "solver_helpers.hpp"

#include "scene_helpers.hpp"
#include "stratum/iteration.hpp"
#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <numbers>
#include <numeric>
#include <unistd.h>

namespace test_solvers {

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

// The constant-work switch of arc_length on a hardening bar (S1 with H = +2 kPa): elastic to
// lambda = 1 (compliance C_e = L / E = 0.01 m), then linear hardening (C_p = (L - l_s) / E + l_s / H
// = 0.059 m), so Bergan's stiffness parameter of a step is S = C_e / (F.du / dl): 1 while elastic,
// C_e / C_p = 0.169 on the hardening branch. With a constant step size (automatic = false, so
// beta = 1) the two modes leave different invariants between consecutive steps:
//   arc length (4.15):    |du_k| = |du_(k-1)|  (cylindrical, psi = 0)
//   constant work (4.17): W_k = W_(k-1), W_k = (lambda_(k-1) + dl_k / 2) F.du_k (exact on a linear
//                         branch: the first iterate lies on the path)
// and on a linear branch of rising load no step keeps both.
TEST_CASE("S1 hardening bar: the constant-work switch engages after the first step with S < work_switch",
          "[solver]") {
  const double E = 100.0, H = 2.0, L = 1.0, ls = 0.1;
  const double Ce = L / E, Cp = (L - ls) / E + ls / H;
  struct Run {
    std::vector<double> lambda, du_norm, work, S;
    std::vector<int> work_steps, arc_steps; ///< accepted steps (1-based) classified by their invariant
    double path_error = 0;
    StageResult res;
  };
  auto run = [&](double work_switch) {
    Run out;
    auto s = load_solver("arc_length", "work_switch = " + std::to_string(work_switch));
    SofteningBar b(10, L, E, 1.0, H);
    StepSettings set;
    set.lambda_end = 5.0; // never reached
    set.steps = 20;       // first step: load increment 0.25 (elastic steps end on the yield point)
    set.max_steps = 12;
    set.convergence.force_rtol = 1e-12;
    set.convergence.force_atol = 1e-14;
    auto cb = bar_callbacks(b);
    Eigen::VectorXd u_prev = Eigen::VectorXd::Zero(10);
    double lambda_prev = 0;
    cb.accepted = [&](const StepRecord& rec, const StepReport&, const Eigen::VectorXd& u) {
      const Eigen::VectorXd du = u - u_prev;
      const double dl = rec.lambda - lambda_prev;
      out.lambda.push_back(rec.lambda);
      out.du_norm.push_back(du.norm());
      out.work.push_back((lambda_prev + 0.5 * dl) * du[9]); // F = unit force at the free end
      out.S.push_back(Ce / (du[9] / dl));
      const double exact = Ce * rec.lambda + (ls / H - ls / E) * std::max(0.0, rec.lambda - 1.0);
      out.path_error = std::max(out.path_error, std::abs(u[9] - exact) / exact);
      u_prev = u;
      lambda_prev = rec.lambda;
    };
    Eigen::VectorXd u = Eigen::VectorXd::Zero(10);
    out.res = run_stage(b, *s->solver, set, cb, u);
    for (std::size_t k = 1; k < out.lambda.size(); ++k) {
      if (std::abs(out.work[k] - out.work[k - 1]) < 1e-9 * out.work[k - 1])
        out.work_steps.push_back(static_cast<int>(k) + 1);
      if (std::abs(out.du_norm[k] - out.du_norm[k - 1]) < 1e-9 * out.du_norm[k - 1])
        out.arc_steps.push_back(static_cast<int>(k) + 1);
    }
    return out;
  };
  auto steps = [](const std::vector<int>& v) {
    std::ostringstream o;
    for (int k : v) o << ' ' << k;
    return o.str();
  };

  const Run on = run(0.3);
  INFO("work_switch = 0.3: " << on.res.outcome.message << "; work-mode steps:" << steps(on.work_steps)
                             << "; arc-length steps:" << steps(on.arc_steps));
  REQUIRE(on.res.outcome.ok());
  REQUIRE(on.res.steps_done == 12);
  CHECK(on.path_error < 1e-9); // every converged point on the bilinear load-displacement path
  // Steps 1-4 elastic (S = 1) up to the yield point, step 5 the first on the hardening branch
  // (S = C_e / C_p = 0.169 < 0.3): the switch engages from step 6 and holds to the last step.
  CHECK(on.lambda[3] == Approx(1.0).epsilon(1e-9));
  CHECK(on.S[3] == Approx(1.0).epsilon(1e-9));
  CHECK(on.S[4] == Approx(Ce / Cp).epsilon(1e-9));
  CHECK(on.arc_steps == std::vector<int>{2, 3, 4, 5});
  CHECK(on.work_steps == std::vector<int>{6, 7, 8, 9, 10, 11, 12});
  // Every work-mode step does the work of step 5, the last arc-length step, to round-off ...
  for (int k = 6; k <= 12; ++k)
    CHECK(on.work[static_cast<std::size_t>(k - 1)] == Approx(on.work[4]).epsilon(1e-9));
  // ... and, as the load rises, takes ever smaller increments (the arc length would keep them).
  CHECK(on.du_norm[11] < 0.95 * on.du_norm[5]);

  // With the switch off (work_switch = 0) or below S on the hardening branch (0.15 < 0.169), every
  // step keeps the arc length and the work per step grows: none is taken in work mode.
  for (const double off : {0.0, 0.15}) {
    const Run r = run(off);
    INFO("work_switch = " << off << ": " << r.res.outcome.message << "; work-mode steps:"
                          << steps(r.work_steps) << "; arc-length steps:" << steps(r.arc_steps));
    REQUIRE(r.res.outcome.ok());
    CHECK(r.path_error < 1e-9);
    CHECK(r.work_steps.empty());
    CHECK(r.arc_steps == std::vector<int>{2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    CHECK(r.work[11] > 1.1 * r.work[4]);
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

namespace {

/// tests/scenes/solvers/footing.toml (catalogue P4, a strip footing on von Mises soil, limit
/// (2 + pi) k = 514.16 kPa) with `analysis` and `solver` lines added to [analysis] and [solver] and
/// [convergence] max_iterations set.
std::string footing(const std::string& analysis, const std::string& solver, int max_iterations = 30) {
  using stratum::testing::replace_once;
  std::string t = stratum::testing::read_text(stratum::testing::scene_path("solvers/footing.toml"));
  t = replace_once(t, "formulation = \"plane_strain\"\n",
                   "formulation = \"plane_strain\"\n" + analysis + "\n");
  t = replace_once(t, "[solver]\n", "[solver]\n" + solver + "\n");
  return replace_once(t, "max_iterations = 30\n",
                      "max_iterations = " + std::to_string(max_iterations) + "\n");
}

struct Curve {
  std::vector<double> q, s; ///< footing pressure (kPa) and settlement under its centre (m)
};

} // namespace

TEST_CASE("P4 strip footing: load control with cut-back and arc length reach (2 + pi) k", "[solver]") {
  const double q_lim = (2 + std::numbers::pi) * 100.0;
  // Load control: 12 steps towards 600 kPa; near the limit the steps fail and are halved
  // until max_cutbacks, which ends the run with a clean status just below the limit.
  auto run = [&](const std::string& analysis, const std::string& solver, Curve& curve, int its = 30) {
    const Model* model = nullptr;
    int centre = -1;
    RunOptions o;
    o.plugin_dirs = {STRATUM_PLUGIN_DIR};
    o.write_output = false;
    o.on_record = [&curve, &model, &centre](const StepRecord& r) {
      curve.q.push_back(600.0 * r.lambda);
      curve.s.push_back(-model->u[2 * centre + 1]);
    };
    auto an2 = Analysis::from_string(footing(analysis, solver, its), "footing.toml", o);
    model = &an2->model();
    centre = stratum::testing::node_at(*model, 0.0, 0.0);
    return an2->run();
  };
  Curve lc, al;
  const auto a = run("steps = 12\nmax_cutbacks = 7", "line_search = 8", lc, 12);
  INFO("load control: " << a.outcome.message);
  CHECK_FALSE(a.outcome.ok()); // the limit cannot be passed under load control
  CHECK(a.cutbacks >= 7);
  REQUIRE(!lc.q.empty());
  const double q_lc = lc.q.back();
  const auto b =
      run("solver = \"arc_length\"\nsteps = 12\nautomatic = true\nmax_steps = 25\nmax_cutbacks = 6", "", al);
  INFO("arc length: " << b.outcome.message);
  REQUIRE(!al.q.empty());
  const double q_al = *std::max_element(al.q.begin(), al.q.end());
  INFO("q_lim = " << q_lim << " kPa; load control " << q_lc << ", arc length " << q_al);
  CHECK(std::abs(q_lc - q_lim) / q_lim < 0.03);
  CHECK(std::abs(q_al - q_lim) / q_lim < 0.03);
  // The same curve where both converge: load control through the load factors the arc-length
  // run reached (below 0.99 q_lim) lands on the same states.
  std::string list = "increments = [";
  std::size_t n = 0;
  for (; n < al.q.size() && al.q[n] < 0.99 * q_lim; ++n) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%.17g", n ? ", " : "", (al.q[n] - (n ? al.q[n - 1] : 0.0)) / 600.0);
    list += buf;
  }
  list += "]\nmax_cutbacks = 0";
  Curve follow;
  const auto c = run(list, "line_search = 8", follow);
  REQUIRE(n >= 8);
  REQUIRE(follow.q.size() >= n);
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    CHECK(follow.q[i] == Approx(al.q[i]).epsilon(1e-12));
    worst = std::max(worst, std::abs(follow.s[i] - al.s[i]) / al.s[i]);
  }
  INFO("compared " << n << " points up to " << al.q[n - 1] << " kPa: worst relative settlement difference "
                   << worst);
  CHECK(worst < 1e-6);
}

namespace {
/// The coarse footing under load control to 0.7 q_lim (plastic from about 0.5 q_lim).
std::unique_ptr<Analysis> footing_to_70(const std::string& solver_name, const std::string& params) {
  std::string t =
      footing("solver = \"" + solver_name + "\"\nincrements = [0.6, 0.05]\nmax_cutbacks = 0", params, 400);
  t.replace(t.find("p = 600.0"), 9, "p = 360.0"); // 0.7 q_lim
  t.replace(t.find("force_rtol = 1e-11"), 18, "force_rtol = 1e-10");
  return stratum::testing::scene(t, "footing90.toml");
}
Eigen::VectorXd run_footing(Analysis& an, RunSummary& s) {
  s = an.run();
  return an.model().u;
}
} // namespace

TEST_CASE("Newton: order close to 2, modified Newton linear, same solution", "[solver]") {
  RunSummary sn, sm, si;
  auto n = footing_to_70("newton", "");
  auto m = footing_to_70("modified_newton", "");
  auto i = footing_to_70("initial_stiffness", "line_search = 0");
  const Eigen::VectorXd un = run_footing(*n, sn), um = run_footing(*m, sm), ui = run_footing(*i, si);
  INFO(sn.outcome.message << " | " << sm.outcome.message << " | " << si.outcome.message);
  REQUIRE(sn.outcome.ok());
  REQUIRE(sm.outcome.ok());
  REQUIRE(n->model().lambda == 1.0);
  double best = 0;
  for (const auto& r : sn.records) best = std::max(best, r.order);
  // Modified Newton: a linear rate, the contraction factor stays roughly constant, order ~ 1.
  int newton_its = 0, modified_its = 0;
  for (const auto& r : sn.records) newton_its += r.iterations;
  double order_m = 0;
  for (const auto& r : sm.records) {
    modified_its += r.iterations;
    CHECK(r.factorizations <= 2);
    if (r.residual_norms.size() >= 5) order_m = std::max(order_m, r.order);
  }
  const double diff = (un - um).norm() / un.norm();
  INFO("cut-backs " << sn.cutbacks << " " << sm.cutbacks);
  INFO("Newton order " << best << " (" << newton_its << " iterations), modified Newton order " << order_m
                       << " (" << modified_its << " iterations), relative difference " << diff);
  CHECK(best > 1.8);
  CHECK(order_m < 1.3);
  CHECK(order_m > 0.7);
  CHECK(modified_its > 2 * newton_its);
  CHECK(diff < 1e-8);
  if (si.outcome.ok()) CHECK((un - ui).norm() / un.norm() < 1e-8);
}

TEST_CASE("KINSOL strategies agree with the built-in Newton, failure is a status", "[solver]") {
  RunSummary sn;
  auto n = footing_to_70("newton", "");
  const Eigen::VectorXd un = run_footing(*n, sn);
  REQUIRE(sn.outcome.ok());
  for (const std::string strategy : {"newton", "picard", "fixed_point"}) {
    SECTION(strategy) {
      RunSummary sk;
      auto k = footing_to_70("kinsol", "strategy = \"" + strategy + "\"");
      const Eigen::VectorXd uk = run_footing(*k, sk);
      int its = 0;
      for (const auto& r : sk.records) its += r.iterations;
      INFO(strategy << ": " << sk.outcome.message << "; " << its << " iterations");
      REQUIRE(sk.outcome.ok());
      CHECK(k->model().lambda == 1.0);
      const double diff = (uk - un).norm() / un.norm();
      INFO("relative difference to Newton " << diff);
      CHECK(diff < 1e-8);
    }
  }
  SECTION("failure beyond the limit load") {
    std::string t = footing("solver = \"kinsol\"\nsteps = 1\nmax_cutbacks = 0", "", 20);
    auto k = stratum::testing::scene(t, "kinsol_fail.toml"); // 600 kPa in one step: 1.17 q_lim
    const auto s = k->run();
    INFO(s.outcome.message);
    CHECK_FALSE(s.outcome.ok());
    CHECK(s.outcome.message.find("KINSOL") != std::string::npos);
    CHECK(s.steps_done == 0);
  }
}

TEST_CASE("step control: listed increments, automatic growth", "[solver]") {
  auto newton = load_solver("newton");
  auto lambdas = [&](StepSettings set) {
    SofteningBar b(4, 1.0, 100.0, 1e6, -20.0); // f_t never reached: linear, one iteration per step
    auto cb = bar_callbacks(b);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(4);
    const auto res = run_stage(b, *newton->solver, set, cb, u);
    REQUIRE(res.outcome.ok());
    CHECK(u[3] == Approx(0.01).epsilon(1e-12)); // u = lambda L / E at lambda = 1
    std::vector<double> l;
    for (const auto& r : res.records) l.push_back(r.lambda);
    return l;
  };
  StepSettings listed;
  listed.increments = {0.1, 0.2, 0.7};
  CHECK(lambdas(listed) == std::vector<double>{0.1, 0.30000000000000004, 1.0});
  StepSettings grow;
  grow.steps = 10;
  grow.automatic = true;
  grow.fast_iterations = 1;
  grow.growth = 2.0;
  grow.max_increment = 0.4;
  const auto g = lambdas(grow); // 0.1, then 0.2, 0.4, 0.4 (bounded), clipped at 1
  REQUIRE(g.size() == 4);
  CHECK(g[0] == Approx(0.1));
  CHECK(g[1] == Approx(0.3));
  CHECK(g[2] == Approx(0.7));
  CHECK(g[3] == 1.0);
}

TEST_CASE("diagnostics: CSV beside the results and stratum run --verbose", "[solver]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("stratum_diag_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string text = footing("steps = 3", "", 30);
  std::string scene = text;
  scene.replace(scene.find("p = 600.0"), 9, "p = 300.0");
  const fs::path file = dir / "diag.toml";
  std::ofstream(file) << scene;
  const fs::path out = dir / "out", err = dir / "stderr.txt";
  const std::string cmd = std::string("STRATUM_PLUGIN_PATH= ") + STRATUM_EXE + " run " + file.string() +
                          " --out " + out.string() + " --verbose 2>" + err.string() + " >/dev/null";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream csv(out / "diagnostics.csv");
  REQUIRE(csv.good());
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(csv, line)) rows.push_back(line);
  REQUIRE(rows.size() == 4); // header + 3 accepted steps
  CHECK(rows[0].rfind("stage,step,accepted,lambda_n,lambda,iterations", 0) == 0);
  CHECK(rows[3].rfind("1,3,1,0.6666666667,1,", 0) == 0);
  CHECK_FALSE(fs::exists(out / ".diagnostics.csv.tmp"));
  std::ifstream e(err);
  std::stringstream ss;
  ss << e.rdbuf();
  INFO(ss.str());
  CHECK(ss.str().find("step 3 lambda 1 iterations ") != std::string::npos);
  CHECK(ss.str().find(" cut-backs 0 rate ") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("P4 strip footing: displacement control of a node set and the constant-work arc length",
          "[solver]") {
  const double q_lim = (2 + std::numbers::pi) * 100.0;
  auto peak = [&](const std::string& analysis, const std::string& solver, RunSummary& s) {
    auto an = stratum::testing::scene(footing(analysis, solver), "footing_dc.toml");
    s = an->run();
    double q = 0;
    for (const auto& r : s.records)
      if (r.accepted) q = std::max(q, 600.0 * r.lambda);
    return q;
  };
  RunSummary dc, wk;
  const double q_dc = peak("solver = \"displacement_control\"\nmax_steps = 25",
                           "nodes = \"foot.top\"\ncomponent = \"y\"\nincrement = -0.002", dc);
  INFO("displacement control: " << dc.outcome.message << ", q = " << q_dc);
  CHECK(dc.outcome.ok()); // stopped by max_steps, on the plateau
  CHECK(dc.steps_done == 25);
  CHECK(std::abs(q_dc - q_lim) / q_lim < 0.03);
  const double q_wk =
      peak("solver = \"arc_length\"\nsteps = 12\nautomatic = true\nmax_steps = 25", "work_switch = 0.3", wk);
  INFO("arc length with the constant-work switch: " << wk.outcome.message << ", q = " << q_wk);
  CHECK(wk.outcome.ok());
  CHECK(std::abs(q_wk - q_lim) / q_lim < 0.03);

  // Which steps took the constant-work increment. The step controller asks for the last step's
  // measured size times 1.5 after a fast step (automatic: at most 4 iterations, no cut-back) and
  // times 1 otherwise; the cylindrical arc length returns exactly that size, a constant-work step
  // a size of its own. A step after a cut-back is not classified.
  auto modes = [](const RunSummary& s, std::vector<int>& arc, std::vector<int>& work) {
    const StepRecord* prev = nullptr;
    for (const auto& r : s.records) {
      if (!r.accepted) continue;
      if (prev && r.cutbacks == 0 && prev->cutbacks == 0) {
        const double asked = prev->arc_length * (prev->iterations <= 4 ? 1.5 : 1.0);
        (std::abs(r.arc_length - asked) < 1e-9 * asked ? arc : work).push_back(r.step);
      }
      prev = &r;
    }
  };
  std::vector<int> arc, work;
  modes(wk, arc, work);
  CAPTURE(arc, work);
  // README: the stiffness parameter of step 5 is 0.26 < 0.3, so from step 6 to the last (25th)
  // every step is a constant-work step.
  REQUIRE(wk.steps_done == 25);
  CHECK(arc == std::vector<int>{2, 3, 4, 5});
  std::vector<int> from6(20);
  std::iota(from6.begin(), from6.end(), 6);
  CHECK(work == from6);
  // The same analysis without the switch keeps the arc length in every step.
  RunSummary al;
  (void)peak("solver = \"arc_length\"\nsteps = 12\nautomatic = true\nmax_steps = 25", "work_switch = 0.0",
             al);
  std::vector<int> arc0, work0;
  modes(al, arc0, work0);
  CAPTURE(arc0, work0);
  CHECK(al.outcome.ok());
  CHECK(work0.empty());
  CHECK(arc0.size() == 24);
}

TEST_CASE("convergence tests: force, energy (4.21) and displacement, relative or absolute", "[solver]") {
  Convergence c;
  c.force_rtol = 1e-6;
  c.force_atol = 1e-3;
  // Force: |R| <= max(1e-6 * 1e4, 1e-3) = 1e-2.
  CHECK(iteration::check(c, 0.0099, 1e4, false, 0, 0, 0, 0).converged());
  CHECK_FALSE(iteration::check(c, 0.0101, 1e4, false, 0, 0, 0, 0).converged());
  CHECK(iteration::check(c, 0.0009, 1.0, false, 0, 0, 0, 0).converged()); // the absolute bound
  // Energy: |du.R| <= max(energy_rtol |du_1.R_0|, energy_atol); needs a correction.
  c.energy_rtol = 1e-4;
  CHECK_FALSE(iteration::check(c, 0.001, 1e4, false, 0, 0, 0, 0).converged());
  CHECK(iteration::check(c, 0.001, 1e4, true, 1, 1, 0.99e-2, 100.0).converged());
  CHECK_FALSE(iteration::check(c, 0.001, 1e4, true, 1, 1, 1.01e-2, 100.0).converged());
  c.energy_atol = 0.02;
  CHECK(iteration::check(c, 0.001, 1e4, true, 1, 1, 1.01e-2, 100.0).converged());
  // Displacement: |du| <= max(disp_rtol |u - u_n|, disp_atol), when enabled.
  c.energy_rtol = 0;
  c.displacement_test = true;
  c.disp_rtol = 1e-3;
  c.disp_atol = 1e-9;
  CHECK(iteration::check(c, 0.001, 1e4, true, 0.99e-5, 1e-2, 0, 0).converged());
  CHECK_FALSE(iteration::check(c, 0.001, 1e4, true, 1.01e-5, 1e-2, 0, 0).converged());
  CHECK(iteration::check(c, 0.001, 1e4, true, 0.9e-9, 0.0, 0, 0).converged());      // absolute
  CHECK_FALSE(iteration::check(c, 0.02, 1e4, true, 0.9e-9, 0.0, 0, 0).converged()); // force still applies
}

TEST_CASE("the line search hands its accepted evaluation to the next iteration", "[solver]") {
  // Hardening bar (H = 30 kPa), one step to lambda = 1.5, beyond f_t = 1: Newton's full steps
  // decrease |R| and are accepted. With line_search > 0 the full step is evaluated with the
  // tangent and that evaluation is the next iterate's, so every iterate is evaluated exactly once
  // (a separate evaluation of the accepted point would double the count); the iterates and the
  // result are those of plain Newton bit for bit, and the result is the closed form.
  class Counting final : public NonlinearProblem {
  public:
    explicit Counting(NonlinearProblem& p) : p_(p) {}
    Eigen::Index size() const override { return p_.size(); }
    Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r, SparseMatrix* k) override {
      points.push_back(u);
      tangents += k != nullptr;
      return p_.evaluate(u, lambda, r, k);
    }
    SparseMatrix make_tangent() const override { return p_.make_tangent(); }
    const Eigen::VectorXd& reference_load() const override { return p_.reference_load(); }
    LinearSolver& linear_solver() override { return p_.linear_solver(); }
    double force_scale(double lambda) const override { return p_.force_scale(lambda); }
    std::vector<Eigen::VectorXd> points;
    int tangents = 0;

  private:
    NonlinearProblem& p_;
  };
  struct Run {
    StepReport rep;
    Eigen::VectorXd u;
    std::vector<Eigen::VectorXd> points;
    int tangents = 0;
  };
  auto run = [](const std::string& solver, const std::string& params) {
    auto s = load_solver(solver, params);
    SofteningBar bar(10, 1.0, 100.0, 1.0, 30.0);
    Counting counting(bar);
    StepRequest req;
    req.lambda_n = 0.0;
    req.lambda = 1.5;
    req.convergence.force_rtol = 1e-12;
    req.convergence.max_iterations = 40;
    Run r;
    r.u = Eigen::VectorXd::Zero(10);
    r.rep = s->solver->solve(counting, req, r.u);
    r.points = counting.points;
    r.tangents = counting.tangents;
    return r;
  };
  // u(L) = 0.9 m * 1.5 / E + 0.1 m * (f_t / E + (1.5 - f_t) / H)
  const double u_end = 0.9 * 1.5 / 100.0 + 0.1 * (1.0 / 100.0 + 0.5 / 30.0);
  const Run plain = run("newton", "line_search = 0");
  const Run searched = run("newton", "line_search = 8");
  REQUIRE(plain.rep.outcome.ok());
  REQUIRE(searched.rep.outcome.ok());
  CHECK(plain.u[9] == Approx(u_end).epsilon(1e-10));
  REQUIRE(searched.rep.iterations >= 2); // the plastic step needs more than one correction
  CHECK(searched.u == plain.u);          // bit for bit
  CHECK(searched.rep.residual_norms == plain.rep.residual_norms);
  // every iterate evaluated once, with the tangent; no point evaluated twice
  CHECK(searched.points.size() == searched.rep.residual_norms.size());
  CHECK(searched.tangents == static_cast<int>(searched.points.size()));
  for (std::size_t i = 1; i < searched.points.size(); ++i)
    CHECK(searched.points[i] != searched.points[i - 1]);

  // modified Newton: the tangent is refreshed at iterations 0 and 1 only; the accepted trials'
  // residuals are handed on the same way, with the tangent only where the next iteration needs it.
  const Run mplain = run("modified_newton", "line_search = 0");
  const Run msearched = run("modified_newton", "line_search = 8");
  REQUIRE(mplain.rep.outcome.ok());
  REQUIRE(msearched.rep.outcome.ok());
  CHECK(mplain.u[9] == Approx(u_end).epsilon(1e-10));
  CHECK(msearched.u == mplain.u);
  CHECK(msearched.rep.residual_norms == mplain.rep.residual_norms);
  CHECK(msearched.points.size() == msearched.rep.residual_norms.size());
  CHECK(msearched.tangents == 2);
}

} // namespace test_solvers
