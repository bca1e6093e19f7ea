// Branch-consistent Newton for the explicit Duncan-Chang update (plugins/duncan_chang/README.md,
// "Branch decisions within a load step"; docs/design.md): each point decides its branch at the
// step's first evaluation and keeps it while Newton iterates; at convergence every point decides
// again from the converged increment, and a step in which a point changed its branch is solved
// again. Checked on one point under oedometric strain, unloaded from its maximum: the first
// decision (from the zero increment) is E_t, the converged increment unloads, so the step must
// end on E_ur with the closed-form increment, not on the E_t one.
#include "duncan_chang/duncan_chang.hpp"
#include "solver_helpers.hpp"
#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace dc = stratum::duncan_chang;

dc::Constants loess_explicit(bool keep) {
  dc::Set s;
  s.K = 500, s.n = 0.82, s.R_f = 0.80, s.phi = 26, s.c = 10, s.K_ur = 800, s.G = 0.18, s.F = 0.22, s.d = 20;
  dc::Constants c;
  c.update = dc::Update::explicit_step;
  c.keep_decisions = keep;
  c.sets = {s};
  return c;
}

/// One material point whose only unknown is the axial (yy) strain increment u; the lateral
/// strains stay zero (oedometer). R(u, lambda) = sigma_yy,n + lambda dsigma - sigma_yy(u). Its trial
/// history persists between evaluations like a StateStore's trial slot; renew_decisions() clears
/// the decision slot when `renews` is set (a problem that does not renew stands for an iteration
/// that never re-checks the kept decisions).
class OnePoint final : public stratum::NonlinearProblem {
public:
  OnePoint(const dc::DuncanChang& m, Vec6 s_n, std::vector<double> h_n, double dsigma, bool renews)
      : m_(m), s_n_(std::move(s_n)), h_n_(std::move(h_n)), trial_(h_n_), dsigma_(dsigma), renews_(renews),
        ls_(stratum::make_linear_solver("eigen_lu", false, 1)) {
    ref_ = Eigen::VectorXd::Constant(1, dsigma);
  }
  Eigen::Index size() const override { return 1; }
  stratum::Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r,
                            stratum::SparseMatrix* k) override {
    const Vec6 de = (Vec6() << 0, u[0], 0, 0, 0, 0).finished();
    Mat6 tangent;
    stratum::MaterialOutput out{stress_, trial_, tangent};
    const Vec6 e_n = Vec6::Zero();
    const stratum::Outcome o = m_.update(stratum::MaterialInput{s_n_, e_n, h_n_, de, {0, 0}}, out);
    if (!o.ok()) return o;
    r = Eigen::VectorXd::Constant(1, s_n_[1] + lambda * dsigma_ - stress_[1]);
    if (k) {
      k->resize(1, 1);
      k->insert(0, 0) = tangent(1, 1);
      k->makeCompressed();
    }
    return {};
  }
  stratum::SparseMatrix make_tangent() const override { return stratum::SparseMatrix(1, 1); }
  const Eigen::VectorXd& reference_load() const override { return ref_; }
  stratum::LinearSolver& linear_solver() override { return *ls_; }
  double force_scale(double lambda) const override { return std::abs(s_n_[1] + lambda * dsigma_); }
  bool renew_decisions() override {
    if (!renews_ || m_.decision_slot() < 0) return false;
    trial_[static_cast<std::size_t>(m_.decision_slot())] = 0.0;
    return true;
  }
  [[nodiscard]] double code() const { return trial_[8]; }

private:
  const dc::DuncanChang& m_;
  Vec6 s_n_, stress_;
  std::vector<double> h_n_, trial_;
  double dsigma_;
  bool renews_;
  Eigen::VectorXd ref_;
  std::unique_ptr<stratum::LinearSolver> ls_;
};

} // namespace

TEST_CASE("branch-consistent Newton re-solves a step whose point changed its branch",
          "[duncan_chang][newton]") {
  const dc::DuncanChang m(loess_explicit(true));
  // A triaxial state at half its strength, at its maximum (history = its own F_sr and q), away
  // from the kink sigma_2 = sigma_3.
  const double s3 = 100.0;
  Vec6 s = (Vec6() << -s3, -s3, -s3 - 20.0, 0, 0, 0).finished();
  const double q_f = m.point(s).q_f;
  s[1] = -s3 - 0.5 * q_f;
  std::vector<double> h(10, 0.0);
  m.init_history(s, h);
  REQUIRE(h[0] == Approx(0.5).margin(0.02)); // at its maximum F_sr
  // Unload the axial stress by a fifth of the deviator (less compression: dsigma > 0).
  const double dsigma = 0.2 * (m.point(s).q);
  const Mat6 D_t = m.explicit_stiffness(m.point(s), 0.0), D_ur = m.explicit_stiffness(m.point(s), 1.0);
  const double u_ur = dsigma / D_ur(1, 1), u_t = dsigma / D_t(1, 1); // closed forms of each branch
  REQUIRE(std::abs(u_t - u_ur) > 0.2 * u_ur);                        // the branches differ clearly

  stratum::StepRequest req;
  req.lambda_n = 0.0;
  req.lambda = 1.0;
  req.convergence.force_rtol = 1e-10;
  req.convergence.force_atol = 1e-12;
  req.convergence.max_iterations = 20;

  SECTION("with the re-check: the step ends on E_ur, the rule's branch at the converged increment") {
    auto solver = stratum::testing::load_solver("newton");
    OnePoint p(m, s, h, dsigma, true);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    const stratum::StepReport rep = solver->solver->solve(p, req, u);
    INFO(rep.outcome.message);
    REQUIRE(rep.outcome.ok());
    CHECK(u[0] == Approx(u_ur).epsilon(1e-9));
    CHECK(p.code() == 1.0); // E_ur
    // The first solve converged on E_t (one factorization), the re-check found the point
    // unloading, the second solve converged on E_ur, whose re-check confirmed it.
    CHECK(rep.factorizations == 2);
    REQUIRE(rep.residual_norms.size() >= 4);
    // The free rule at the returned increment agrees with the returned state: a fresh update of
    // the same increment gives the same stress.
    std::vector<double> fresh(10, 0.0);
    Vec6 stress;
    Mat6 tangent;
    stratum::MaterialOutput out{stress, fresh, tangent};
    const Vec6 de = (Vec6() << 0, u[0], 0, 0, 0, 0).finished(), e_n = Vec6::Zero();
    REQUIRE(m.update(stratum::MaterialInput{s, e_n, h, de, {0, 0}}, out).ok());
    CHECK(stress[1] == Approx(s[1] + dsigma).epsilon(1e-10));
    CHECK(fresh[8] == 1.0);
  }
  SECTION("without it the kept first decision would stay: E_t, the wrong branch") {
    // A problem that never renews: the decision made at the first evaluation (E_t, from the
    // zero increment) is kept to convergence. This is what the re-check prevents.
    auto solver = stratum::testing::load_solver("newton");
    OnePoint p(m, s, h, dsigma, false);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    const stratum::StepReport rep = solver->solver->solve(p, req, u);
    REQUIRE(rep.outcome.ok());
    CHECK(u[0] == Approx(u_t).epsilon(1e-9));
    CHECK(p.code() == 3.0); // E_t
  }
  SECTION("the free iteration (the original) reaches the same E_ur increment") {
    const dc::DuncanChang free_m(loess_explicit(false));
    std::vector<double> h8(h.begin(), h.begin() + 8);
    auto solver = stratum::testing::load_solver("newton");
    OnePoint p(free_m, s, h8, dsigma, true);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
    const stratum::StepReport rep = solver->solver->solve(p, req, u);
    REQUIRE(rep.outcome.ok());
    CHECK(u[0] == Approx(u_ur).epsilon(1e-9));
  }
}

TEST_CASE("the explicit update's error estimate is Heun minus Euler, second order in the increment",
          "[duncan_chang]") {
  const dc::DuncanChang m(loess_explicit(true));
  const Vec6 s = (Vec6() << -100.0, -160.0, -110.0, 5.0, 0, 0).finished();
  std::vector<double> h(10, 0.0);
  m.init_history(s, h);
  const Vec6 de = (Vec6() << 1e-4, -6e-4, 5e-5, 2e-5, 0, 0).finished(); // loading (E_t)
  auto error = [&](double scale, Vec6* stress_out = nullptr) {
    std::vector<double> out_h(10, 0.0);
    Vec6 stress;
    Mat6 tangent;
    stratum::MaterialOutput out{stress, out_h, tangent};
    const Vec6 e_n = Vec6::Zero(), d = scale * de;
    REQUIRE(m.update(stratum::MaterialInput{s, e_n, h, d, {0, 0}}, out).ok());
    REQUIRE(out_h[8] == 3.0); // E_t
    if (stress_out) *stress_out = stress;
    return m.step_error(out_h);
  };
  Vec6 euler;
  const double e1 = error(1.0, &euler), e2 = error(0.5);
  // Closed form: Heun's stress with the moduli averaged between the start and the Euler end.
  const Vec6 heun =
      s + 0.5 * (m.explicit_stiffness(m.point(s), 0.0) + m.explicit_stiffness(m.point(euler), 0.0)) * de;
  CHECK(e1 == Approx((heun - euler).norm() / std::max(heun.norm(), 100.0)).epsilon(1e-12));
  CHECK(e1 > 0.0);
  CHECK(e1 / e2 == Approx(4.0).epsilon(0.1)); // second order: halving the increment quarters it
  // The stress itself stays Euler's (the model of the scene).
  CHECK((euler - (s + m.explicit_stiffness(m.point(s), 0.0) * de)).norm() < 1e-12 * s.norm());
}

namespace {

/// R(u, lambda) = lambda - u (unit spring) whose materials would report a local error
/// C (lambda - lambda_n)^2 of the step (second order in the step, like the Duncan-Chang estimate).
class ErrorSpring final : public stratum::NonlinearProblem {
public:
  explicit ErrorSpring(double c) : c_(c), ls_(stratum::make_linear_solver("eigen_lu", false, 1)) {
    ref_ = Eigen::VectorXd::Ones(1);
  }
  Eigen::Index size() const override { return 1; }
  stratum::Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r,
                            stratum::SparseMatrix* k) override {
    lambda_ = lambda;
    r = Eigen::VectorXd::Constant(1, lambda - u[0]);
    if (k) {
      k->resize(1, 1);
      k->insert(0, 0) = 1.0;
      k->makeCompressed();
    }
    return {};
  }
  stratum::SparseMatrix make_tangent() const override { return stratum::SparseMatrix(1, 1); }
  const Eigen::VectorXd& reference_load() const override { return ref_; }
  stratum::LinearSolver& linear_solver() override { return *ls_; }
  double force_scale(double lambda) const override { return std::max(1.0, std::abs(lambda)); }
  double step_error() const override { return c_ * (lambda_ - committed_) * (lambda_ - committed_); }
  void commit() { committed_ = lambda_; }

private:
  double c_, lambda_ = 0.0, committed_ = 0.0;
  Eigen::VectorXd ref_;
  std::unique_ptr<stratum::LinearSolver> ls_;
};

} // namespace

TEST_CASE("error-controlled load steps keep every accepted step within the tolerance", "[solver]") {
  auto solver = stratum::testing::load_solver("newton");
  const double C = 100.0, tol = 1e-2; // steps of at most sqrt(tol / C) = 0.01 pass
  stratum::StepSettings s;
  s.steps = 4; // nominal 0.25: the controller must go well below it
  s.max_cutbacks = 10;
  s.error_tolerance = tol;
  s.convergence.force_rtol = 1e-12;
  ErrorSpring p(C);
  stratum::StepCallbacks cb;
  cb.commit = [&] { p.commit(); };
  cb.revert = [] {};
  Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  const stratum::StageResult res = stratum::run_stage(p, *solver->solver, s, cb, u);
  REQUIRE(res.outcome.ok());
  CHECK(res.lambda == Approx(1.0));
  CHECK(u[0] == Approx(1.0));
  CHECK(res.error_rejections > 0);
  int accepted = 0;
  for (const auto& r : res.records) {
    if (!r.accepted) continue;
    ++accepted;
    CHECK(C * (r.lambda - r.lambda_n) * (r.lambda - r.lambda_n) <= tol * (1 + 1e-9));
  }
  // At least 1 / 0.01 steps, and not many more: after the first rejection the steps stay near
  // the largest one allowed (0.9 of it by the safety factor, landing on the listed boundaries).
  CHECK(accepted >= 100);
  CHECK(accepted <= 130);
  // Without the control the four listed steps are taken.
  s.error_tolerance = 0.0;
  ErrorSpring q(C);
  cb.commit = [&] { q.commit(); };
  u.setZero();
  const stratum::StageResult plain = stratum::run_stage(q, *solver->solver, s, cb, u);
  REQUIRE(plain.outcome.ok());
  CHECK(plain.steps_done == 4);
}
