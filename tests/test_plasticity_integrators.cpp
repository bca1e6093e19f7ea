// Tests of the shared stress integrators (framework/src/plasticity/plasticity_integrate.cpp):
// Krieg & Krieg's exact von Mises solution (verification.md M3), Sloan's error-controlled
// substepping (M4), the multi-surface active-set strategy against an exact projection,
// continuum tangents, parameters, and failures returned as Outcomes.
#include "von_mises/von_mises.hpp"

#include "stratum/plasticity/integrate.hpp"
#include "stratum/plasticity/invariants.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace test_plasticity_integrators { // one namespace per test file: the test files build in batches
                                        // (unity)

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace pl = stratum::plasticity;
namespace vm = stratum::von_mises;
using pl::MatX;
using pl::VecX;

const std::vector<pl::Scheme> all_schemes = {pl::Scheme::forward_euler, pl::Scheme::modified_euler,
                                             pl::Scheme::trapezoidal,   pl::Scheme::midpoint,
                                             pl::Scheme::cutting_plane, pl::Scheme::closest_point};

std::span<const double> sp(const VecX& v) { return {v.data(), static_cast<std::size_t>(v.size())}; }

/// Tensor norm of a stress-like Voigt vector.
double tnorm(const Vec6& s) { return std::sqrt(s.head<3>().squaredNorm() + 2.0 * s.tail<3>().squaredNorm()); }

pl::Settings settings_for(pl::Scheme s) {
  pl::Settings st;
  st.scheme = s;
  st.substeps = 1; // forward_euler: the tests split the increment themselves
  st.alpha = 0.5;
  return st;
}

/// Krieg & Krieg (1977): perfectly plastic von Mises under a constant deviatoric strain rate
/// de = a n0 + b t0 from s0 = R n0 on the surface |s| = R (verification.md M3).
struct Krieg {
  double G = 1.0, R = 1.0, a = 0.5, b = 0.5;
  Vec6 n0, t0; ///< unit deviatoric tensors, stress-like Voigt (tensor shear components)

  Krieg(double a_, double b_, bool shear_t0) : a(a_), b(b_) {
    n0 << 1.0 / std::sqrt(2.0), -1.0 / std::sqrt(2.0), 0, 0, 0, 0;
    if (shear_t0)
      t0 << 0, 0, 0, 1.0 / std::sqrt(2.0), 0, 0; // xy
    else
      t0 << 1.0 / std::sqrt(6.0), 1.0 / std::sqrt(6.0), -2.0 / std::sqrt(6.0), 0, 0, 0;
  }
  [[nodiscard]] vm::Constants constants() const {
    vm::Constants c;
    c.nu = 0.3;
    c.E = 2.0 * G * (1.0 + c.nu);
    c.sigma_y = std::sqrt(1.5) * R; // |s| = sqrt(2/3) sigma_y on the surface
    c.H = 0.0;
    return c;
  }
  /// The strain increment in Voigt form (engineering shear).
  [[nodiscard]] Vec6 de() const { return a * pl::to_strain_like(n0) + b * pl::to_strain_like(t0); }
  [[nodiscard]] Vec6 start() const { return R * n0; }
  [[nodiscard]] Vec6 exact() const {
    const double rho = std::hypot(a, b), phi = std::atan2(a, b), k = 2.0 * G * rho / R;
    const double chi = 2.0 * (std::atan(std::tan(phi / 2.0 + M_PI / 4.0) * std::exp(k)) - M_PI / 4.0);
    const double psi = chi - phi;
    return R * (std::cos(psi) * n0 + std::sin(psi) * t0);
  }
};

struct Run {
  Vec6 sigma;
  VecX q;
  Mat6 tangent;
  bool ok = true;
  std::string message;
  pl::Counters counters;
};

/// Integrates de in N equal steps.
Run run(const pl::Model& m, const pl::Settings& s, const Vec6& sigma0, VecX q0, const Vec6& de, int N) {
  Run r;
  r.sigma = sigma0;
  r.q = q0;
  for (int i = 0; i < N && r.ok; ++i) {
    Vec6 out;
    const pl::Result res = pl::integrate(m, s, r.sigma, de / N, out, {r.q.data(), std::size_t(r.q.size())},
                                         r.tangent, &r.counters);
    r.ok = res.outcome.ok();
    r.message = res.outcome.message;
    if (r.ok) r.sigma = out;
  }
  return r;
}

/// Relative error of the Krieg & Krieg case after N steps.
double krieg_error(const Krieg& k, const pl::Settings& s, int N) {
  const vm::VonMisesModel m(k.constants());
  const Run r = run(m, s, k.start(), VecX::Zero(1), k.de(), N);
  INFO(r.message);
  REQUIRE(r.ok);
  return tnorm(r.sigma - k.exact()) / tnorm(k.exact());
}

/// Two tension cut-offs, f_0 = sigma_xx - t and f_1 = sigma_yy - t, perfectly plastic and
/// associated: two planes meeting in a corner. Elasticity isotropic.
class TwoCutoffs final : public pl::Model {
public:
  TwoCutoffs(double E, double nu, double t) : D_(vm::isotropic_stiffness(E, nu)), t_(t) {}
  int internal_size() const override { return 0; }
  int surfaces() const override { return 2; }
  Mat6 elastic(const Vec6&, std::span<const double>) const override { return D_; }
  double yield(int k, const Vec6& s, std::span<const double>) const override { return s[k] - t_; }
  Vec6 yield_gradient(int k, const Vec6&, std::span<const double>) const override { return Vec6::Unit(k); }
  VecX yield_gradient_q(int, const Vec6&, std::span<const double>) const override { return VecX(0); }
  Vec6 flow(int k, const Vec6&, std::span<const double>) const override { return Vec6::Unit(k); }
  VecX hardening(int, const Vec6&, std::span<const double>) const override { return VecX(0); }
  Mat6 flow_gradient(int, const Vec6&, std::span<const double>) const override { return Mat6::Zero(); }
  MatX flow_gradient_q(int, const Vec6&, std::span<const double>) const override { return MatX(6, 0); }
  MatX hardening_gradient(int, const Vec6&, std::span<const double>) const override { return MatX(0, 6); }
  MatX hardening_gradient_q(int, const Vec6&, std::span<const double>) const override { return MatX(0, 0); }
  double stress_scale(const Vec6&, std::span<const double>) const override { return t_; }
  const Mat6& D() const { return D_; }

private:
  Mat6 D_;
  double t_;
};

/// The exact closest-point projection for TwoCutoffs: the one subset of surfaces whose
/// equality-constrained return has nonnegative multipliers and violates no other surface (KKT).
Vec6 cutoff_projection(const TwoCutoffs& m, const Vec6& trial, double t, std::vector<int>& active) {
  const std::vector<std::vector<int>> subsets = {{}, {0}, {1}, {0, 1}};
  for (const auto& set : subsets) {
    const int a = static_cast<int>(set.size());
    MatX L(a, a);
    VecX f(a);
    for (int i = 0; i < a; ++i) {
      f[i] = trial[set[i]] - t;
      for (int j = 0; j < a; ++j) L(i, j) = m.D()(set[i], set[j]);
    }
    const VecX dl = a ? VecX(L.lu().solve(f)) : VecX(0);
    Vec6 s = trial;
    for (int i = 0; i < a; ++i) s -= dl[i] * m.D().col(set[i]);
    bool ok = a == 0 || dl.minCoeff() >= 0.0;
    for (int k = 0; k < 2; ++k) ok = ok && s[k] - t <= 1e-12 * t;
    if (ok) {
      active = set;
      return s;
    }
  }
  FAIL("no KKT point");
  return trial;
}

/// Von Mises with saturating (Voce) hardening: sigma_y(e) = s_inf - (s_inf - s_y) exp(-d e).
/// Needs several Newton iterations, unlike linear hardening.
class VoceMises final : public pl::Model {
public:
  VoceMises(const vm::Constants& c, double s_inf, double d) : vm_(c), s_inf_(s_inf), d_(d) {}
  int internal_size() const override { return 1; }
  Mat6 elastic(const Vec6& s, std::span<const double> q) const override { return vm_.elastic(s, q); }
  double yield(int, const Vec6& s, std::span<const double> q) const override {
    return pl::q_mises(s) - strength(q[0]);
  }
  Vec6 yield_gradient(int k, const Vec6& s, std::span<const double> q) const override {
    return vm_.yield_gradient(k, s, q);
  }
  VecX yield_gradient_q(int, const Vec6&, std::span<const double> q) const override {
    const double sy = vm_.constants().sigma_y;
    return VecX::Constant(1, -(s_inf_ - sy) * d_ * std::exp(-d_ * q[0]));
  }
  Vec6 flow(int k, const Vec6& s, std::span<const double> q) const override { return vm_.flow(k, s, q); }
  VecX hardening(int k, const Vec6& s, std::span<const double> q) const override {
    return vm_.hardening(k, s, q);
  }
  Mat6 flow_gradient(int k, const Vec6& s, std::span<const double> q) const override {
    return vm_.flow_gradient(k, s, q);
  }
  MatX flow_gradient_q(int, const Vec6&, std::span<const double>) const override { return MatX::Zero(6, 1); }
  MatX hardening_gradient(int, const Vec6&, std::span<const double>) const override {
    return MatX::Zero(1, 6);
  }
  MatX hardening_gradient_q(int, const Vec6&, std::span<const double>) const override {
    return MatX::Zero(1, 1);
  }
  double stress_scale(const Vec6&, std::span<const double> q) const override { return strength(q[0]); }
  double strength(double e) const {
    const double sy = vm_.constants().sigma_y;
    return s_inf_ - (s_inf_ - sy) * std::exp(-d_ * e);
  }

private:
  vm::VonMisesModel vm_;
  double s_inf_, d_;
};

} // namespace

TEST_CASE("plasticity: one-step radial return error of Krieg & Krieg's case is 12.095 %", "[point]") {
  for (bool shear : {true, false}) {
    INFO((shear ? "t0 = xy shear" : "t0 = diag(1, 1, -2)/sqrt(6)"));
    const Krieg k(0.5, 0.5, shear);
    CHECK(tnorm(k.exact()) == Approx(k.R).epsilon(1e-14)); // the exact solution stays on the surface
    const double e_cp = 100.0 * krieg_error(k, settings_for(pl::Scheme::closest_point), 1);
    CHECK(e_cp == Approx(12.095).margin(5e-4));
    // the cutting plane reduces to the radial return for von Mises
    const double e_cut = 100.0 * krieg_error(k, settings_for(pl::Scheme::cutting_plane), 1);
    CHECK(e_cut == Approx(e_cp).epsilon(1e-8));
  }
}

TEST_CASE("plasticity: every integrator converges to Krieg & Krieg's exact solution", "[point]") {
  const Krieg k(0.5, 0.5, true);
  const std::vector<int> steps = {1, 10, 100, 1000};
  for (pl::Scheme s : all_schemes) {
    INFO(pl::to_string(s));
    std::vector<double> err;
    for (int N : steps) err.push_back(krieg_error(k, settings_for(s), N));
    INFO("errors " << err[0] << " " << err[1] << " " << err[2] << " " << err[3]);
    CHECK(err[3] < 1e-3);
    if (s == pl::Scheme::modified_euler) {
      // error-controlled: the error is set by stol (1e-6), not by the number of steps
      for (double e : err) CHECK(e < 1e-6);
      continue;
    }
    for (std::size_t i = 1; i < err.size(); ++i) CHECK(err[i] < err[i - 1]);
    if (s == pl::Scheme::closest_point || s == pl::Scheme::cutting_plane || s == pl::Scheme::forward_euler) {
      // first order: ten times more steps, ten times smaller error
      CHECK(err[2] / err[3] == Approx(10.0).epsilon(0.05));
    }
    if (s == pl::Scheme::midpoint) {
      CHECK(err[3] < 1e-7);                                  // measured 4.7e-8
      CHECK(err[1] / err[2] == Approx(100.0).epsilon(0.05)); // second order for alpha = 1/2
    }
    if (s == pl::Scheme::trapezoidal) CHECK(err[3] < 1e-6); // measured 1.6e-7
  }
  // The radial return is first order: its error after 1000 steps is 1.8e-4, far above 1e-5.
  CHECK(krieg_error(k, settings_for(pl::Scheme::closest_point), 1000) == Approx(1.784e-4).epsilon(0.01));
}

TEST_CASE("plasticity: generalized trapezoidal and midpoint rules are first order except at alpha = 1/2",
          "[point]") {
  const Krieg k(0.5, 0.5, true);
  for (pl::Scheme s : {pl::Scheme::trapezoidal, pl::Scheme::midpoint}) {
    for (double alpha : {0.0, 0.25, 0.5, 1.0}) {
      INFO(pl::to_string(s) << " alpha " << alpha);
      pl::Settings st = settings_for(s);
      st.alpha = alpha;
      const double e10 = krieg_error(k, st, 10), e100 = krieg_error(k, st, 100);
      if (alpha == 0.5)
        CHECK(e10 / e100 == Approx(100.0).epsilon(0.05));
      else
        CHECK(e10 / e100 == Approx(10.0).epsilon(0.1));
    }
  }
  // alpha = 1 of either rule is the closest-point return
  pl::Settings mid = settings_for(pl::Scheme::midpoint), trap = settings_for(pl::Scheme::trapezoidal);
  mid.alpha = trap.alpha = 1.0;
  const double cp = krieg_error(k, settings_for(pl::Scheme::closest_point), 10);
  CHECK(krieg_error(k, mid, 10) == Approx(cp).epsilon(1e-6));
  CHECK(krieg_error(k, trap, 10) == Approx(cp).epsilon(1e-6));
}

TEST_CASE("plasticity: the local Newton iterations of the implicit schemes converge in a few steps",
          "[point]") {
  // A wrong Jacobian still converges, but linearly: the iteration counts guard the derivatives.
  for (const auto& [a, b] : {std::pair{0.5, 0.5}, std::pair{1.0, 3.0}, std::pair{3.0, 1.0}}) {
    const Krieg k(a, b, true);
    const vm::VonMisesModel m(k.constants());
    for (pl::Scheme s : {pl::Scheme::trapezoidal, pl::Scheme::midpoint, pl::Scheme::closest_point}) {
      INFO(pl::to_string(s) << " (a, b) = (" << a << ", " << b << ")");
      const Run r = run(m, settings_for(s), k.start(), VecX::Zero(1), k.de(), 1);
      REQUIRE(r.ok);
      CHECK(r.counters.iterations <= (s == pl::Scheme::closest_point ? 1 : 10)); // measured 1, 3-8
    }
  }
  // nonlinear (saturating) hardening, a general increment of about 20 yield strains
  vm::Constants c;
  c.E = 2.0e4, c.nu = 0.3, c.sigma_y = 100.0;
  const VoceMises m(c, 300.0, 50.0);
  Vec6 de;
  de << 0.1, -0.04, -0.02, 0.06, 0.0, 0.02;
  for (pl::Scheme s : {pl::Scheme::trapezoidal, pl::Scheme::midpoint, pl::Scheme::closest_point}) {
    INFO(pl::to_string(s));
    const Run r = run(m, settings_for(s), Vec6::Zero(), VecX::Zero(1), de, 1);
    REQUIRE(r.ok);
    CHECK(r.counters.iterations <= 8);
    CHECK(std::abs(m.yield(0, r.sigma, sp(r.q))) <= 1e-9 * m.stress_scale(r.sigma, sp(r.q)));
  }
}

TEST_CASE("plasticity: modified_euler error scales with stol and ends on the yield surface", "[point]") {
  const Krieg k(0.5, 0.5, true);
  double previous_error = 1.0;
  long previous_substeps = 0;
  for (double stol : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    INFO("stol " << stol);
    pl::Settings s = settings_for(pl::Scheme::modified_euler);
    s.stol = stol;
    const vm::VonMisesModel m(k.constants());
    const Run r = run(m, s, k.start(), VecX::Zero(1), k.de(), 1);
    REQUIRE(r.ok);
    const double err = tnorm(r.sigma - k.exact()) / tnorm(k.exact());
    CHECK(err < stol);                 // measured about 0.2 stol
    CHECK(err < 0.3 * previous_error); // about ten times smaller per decade
    CHECK(r.counters.substeps > previous_substeps);
    const double f = m.yield(0, r.sigma, sp(r.q));
    CHECK(std::abs(f) <= s.ftol * m.stress_scale(r.sigma, sp(r.q)));
    previous_error = err, previous_substeps = r.counters.substeps;
  }

  // with hardening, from a virgin state, in a general 3D direction
  vm::Constants c;
  c.E = 2.0e4, c.nu = 0.25, c.sigma_y = 100.0, c.H = 2.0e3;
  const vm::VonMisesModel m(c);
  Vec6 de;
  de << 4e-3, -1e-3, -2e-3, 5e-3, -2e-3, 1e-3;
  pl::Settings s = settings_for(pl::Scheme::modified_euler);
  s.ftol = 1e-10;
  const Run r = run(m, s, Vec6::Zero(), VecX::Zero(1), de, 1);
  REQUIRE(r.ok);
  CHECK(r.q[0] > 0.0);
  CHECK(std::abs(m.yield(0, r.sigma, sp(r.q))) <= 1e-10 * m.stress_scale(r.sigma, sp(r.q)));
  // agrees with a converged closest-point reference to about stol
  const Run ref = run(m, settings_for(pl::Scheme::closest_point), Vec6::Zero(), VecX::Zero(1), de, 20000);
  CHECK(tnorm(r.sigma - ref.sigma) / tnorm(ref.sigma) < 1e-5);
}

TEST_CASE("plasticity: a failed local iteration is an Outcome, not an exception", "[point]") {
  vm::Constants c;
  c.E = 2.0e4, c.nu = 0.3, c.sigma_y = 100.0;
  const VoceMises m(c, 300.0, 50.0);
  Vec6 de;
  de << 0.5, -0.2, -0.1, 0.3, 0.0, 0.1; // about 100 times the yield strain
  const Vec6 sigma_n = Vec6::Zero();
  for (pl::Scheme scheme : {pl::Scheme::closest_point, pl::Scheme::cutting_plane, pl::Scheme::trapezoidal}) {
    INFO(pl::to_string(scheme));
    pl::Settings s = settings_for(scheme);
    s.max_iterations = 1;
    Vec6 sigma = Vec6::Constant(7.0);
    double q[1] = {0.0};
    Mat6 T;
    pl::Result r;
    CHECK_NOTHROW(r = pl::integrate(m, s, sigma_n, de, sigma, q, T));
    CHECK_FALSE(r.outcome.ok());
    CHECK(r.outcome.status == stratum::Status::material_failure);
    CHECK_THAT(r.outcome.message, Catch::Contains(pl::to_string(scheme)));
    CHECK_THAT(r.outcome.message, Catch::Contains("1 iteration"));
    CHECK(sigma == sigma_n); // outputs are the committed state
    CHECK(q[0] == 0.0);
    CHECK(T.allFinite());
    // the same increment converges with the default iteration limit
    s.max_iterations = 50;
    if (scheme != pl::Scheme::trapezoidal) {
      r = pl::integrate(m, s, sigma_n, de, sigma, q, T);
      INFO(r.outcome.message);
      CHECK(r.outcome.ok());
      CHECK(std::abs(m.yield(0, sigma, q)) <= s.ftol * m.stress_scale(sigma, q));
    }
  }
  // NaN in the strain increment
  const vm::VonMisesModel vmm(c);
  Vec6 bad = de;
  bad[2] = std::numeric_limits<double>::quiet_NaN();
  Vec6 sigma;
  double q[1] = {0.0};
  Mat6 T;
  const pl::Result r = pl::integrate(vmm, settings_for(pl::Scheme::closest_point), sigma_n, bad, sigma, q, T);
  CHECK(r.outcome.status == stratum::Status::non_finite);
  CHECK(sigma.allFinite());
  // a wrong number of internal variables
  double none[2] = {0.0, 0.0};
  CHECK_FALSE(
      pl::integrate(vmm, settings_for(pl::Scheme::closest_point), sigma_n, de, sigma, none, T).outcome.ok());
}

TEST_CASE("plasticity: two surfaces, active set matches the exact projection", "[point]") {
  const double t = 10.0;
  struct Case {
    double nu;
    Vec6 de;
    std::vector<int> expected; ///< active surfaces of the exact projection
  };
  auto v = [](double a, double b, double c, double d) {
    Vec6 x;
    x << a, b, c, d, 0, 0;
    return x;
  };
  const std::vector<Case> cases = {
      {0.3, v(2e-3, 2e-3, 0, 1e-4), {0, 1}}, // both violated, corner return
      {0.3, v(3e-3, 0.35e-3, 0, 0), {0}},    // both violated at the trial, dlambda_1 < 0: drop surface 1
      {0.3, v(0, 1.5e-3, 0, 2e-4), {1}},     // one surface
      {-0.2,
       v(2e-3, 1.2e-3, 0, 0),
       {0, 1}}, // only surface 0 violated at the trial; the return violates 1: add
  };
  const Vec6 sigma_n = Vec6::Zero();
  for (const Case& cs : cases) {
    const TwoCutoffs m(1.0e4, cs.nu, t);
    const Vec6 trial = sigma_n + m.D() * cs.de;
    std::vector<int> active;
    const Vec6 exact = cutoff_projection(m, trial, t, active);
    INFO("nu " << cs.nu << " trial " << trial.transpose());
    REQUIRE(active == cs.expected);
    if (cs.nu < 0) REQUIRE(trial[1] < t); // the "add" case really starts with one violated surface
    for (pl::Scheme s : {pl::Scheme::closest_point, pl::Scheme::cutting_plane, pl::Scheme::trapezoidal,
                         pl::Scheme::midpoint}) {
      INFO(pl::to_string(s));
      Vec6 sigma;
      Mat6 T;
      const pl::Result r = pl::integrate(m, settings_for(s), sigma_n, cs.de, sigma, {}, T);
      INFO(r.outcome.message);
      REQUIRE(r.outcome.ok());
      CHECK(r.plastic);
      CHECK((sigma - exact).cwiseAbs().maxCoeff() <= 1e-8 * t);
    }
    // the explicit schemes stay admissible (f <= ftol t)
    for (pl::Scheme s : {pl::Scheme::forward_euler, pl::Scheme::modified_euler}) {
      INFO(pl::to_string(s));
      pl::Settings st = settings_for(s);
      st.substeps = 50;
      Vec6 sigma;
      Mat6 T;
      const pl::Result r = pl::integrate(m, st, sigma_n, cs.de, sigma, {}, T);
      REQUIRE(r.outcome.ok());
      CHECK(sigma[0] - t <= 1e-8 * t);
      CHECK(sigma[1] - t <= 1e-8 * t);
    }
    // consistent tangent of the corner/plane return = continuum tangent for planes, and both equal
    // central differences
    Vec6 sigma;
    Mat6 T;
    REQUIRE(
        pl::integrate(m, settings_for(pl::Scheme::closest_point), sigma_n, cs.de, sigma, {}, T).outcome.ok());
    const Mat6 Tc = pl::continuum_tangent(m, sigma, {}, active);
    CHECK((T - Tc).cwiseAbs().maxCoeff() <= 1e-10 * T.cwiseAbs().maxCoeff());
    Mat6 Tfd;
    for (int j = 0; j < 6; ++j) {
      const double h = 1e-7 * cs.de.cwiseAbs().maxCoeff();
      Vec6 sp, sm;
      Mat6 dummy;
      REQUIRE(pl::integrate(m, settings_for(pl::Scheme::closest_point), sigma_n, cs.de + h * Vec6::Unit(j),
                            sp, {}, dummy)
                  .outcome.ok());
      REQUIRE(pl::integrate(m, settings_for(pl::Scheme::closest_point), sigma_n, cs.de - h * Vec6::Unit(j),
                            sm, {}, dummy)
                  .outcome.ok());
      Tfd.col(j) = (sp - sm) / (2 * h);
    }
    CHECK((T - Tfd).cwiseAbs().maxCoeff() <= 1e-5 * T.cwiseAbs().maxCoeff());
    // at the corner the plastic response in xx and yy is rigid
    if (active.size() == 2) {
      CHECK(std::abs(T(0, 0)) < 1e-8 * m.D()(0, 0));
      CHECK(std::abs(T(1, 1)) < 1e-8 * m.D()(0, 0));
    }
  }
}

TEST_CASE("plasticity: continuum tangent of von Mises has the closed form", "[point]") {
  vm::Constants c;
  c.E = 3.0e4, c.nu = 0.2, c.sigma_y = 150.0, c.H = 1.0e3;
  const vm::VonMisesModel m(c);
  const Mat6 D = vm::isotropic_stiffness(c.E, c.nu);
  Vec6 dir;
  dir << 1.0, -0.4, -0.2, 0.5, -0.3, 0.2;
  const double q[1] = {0.01};
  const Vec6 sigma =
      -40.0 * pl::identity() + dir * (m.strength(q) / pl::q_mises(dir)); // on the surface, with a mean stress
  REQUIRE(std::abs(m.yield(0, sigma, q)) < 1e-10);
  const Vec6 n = m.yield_gradient(0, sigma, q);
  const Mat6 expected = D - (D * n) * (D * n).transpose() / (n.dot(D * n) + c.H);
  const int active[1] = {0};
  const Mat6 Cep = pl::continuum_tangent(m, sigma, q, active);
  CHECK((Cep - expected).cwiseAbs().maxCoeff() <= 1e-12 * D.cwiseAbs().maxCoeff());
  CHECK((Cep - Cep.transpose()).cwiseAbs().maxCoeff() <= 1e-10 * D.cwiseAbs().maxCoeff());
  CHECK((Cep * n).norm() < D.norm()); // softer along the normal
  CHECK((pl::continuum_tangent(m, sigma, q, {}) - D).norm() == 0.0);
  // the plastic response along n: n . Cep n = (n.D.n) H / (n.D.n + H)
  const double nDn = n.dot(D * n);
  CHECK(n.dot(Cep * n) == Approx(nDn * c.H / (nDn + c.H)).epsilon(1e-10));
}

TEST_CASE("plasticity: elastic steps, unloading from the surface and counters", "[point]") {
  vm::Constants c;
  c.E = 1.0e4, c.nu = 0.3, c.sigma_y = 50.0, c.H = 500.0;
  const vm::VonMisesModel m(c);
  const Mat6 D = vm::isotropic_stiffness(c.E, c.nu);
  Vec6 dir;
  dir << 0.0, 0.0, 0.0, 1.0, 0.0, 0.0;
  const double q0 = 0.002;
  const Vec6 on_surface = dir * ((c.sigma_y + c.H * q0) / std::sqrt(3.0));
  for (pl::Scheme s : all_schemes) {
    INFO(pl::to_string(s));
    double q[1] = {q0};
    Vec6 sigma;
    Mat6 T;
    pl::Counters counters;
    const Vec6 de = -1e-4 * pl::to_strain_like(dir); // unloading
    const pl::Result r = pl::integrate(m, settings_for(s), on_surface, de, sigma, q, T, &counters);
    REQUIRE(r.outcome.ok());
    CHECK_FALSE(r.plastic);
    CHECK(q[0] == q0);
    CHECK((sigma - (on_surface + D * de)).norm() < 1e-12);
    CHECK(T == D);
    CHECK(counters.yield_evaluations == 1);
    CHECK(counters.iterations == 0);
    // loading: counted work
    pl::Counters work;
    const pl::Result p = pl::integrate(m, settings_for(s), on_surface, -de, sigma, q, T, &work);
    REQUIRE(p.outcome.ok());
    CHECK(p.plastic);
    CHECK(q[0] > q0);
    CHECK(work.yield_evaluations > 1);
    CHECK(work.substeps >= 1);
  }
}

TEST_CASE("plasticity: integrator parameters are declared with ranges and read back", "[point]") {
  stratum::Schema schema;
  pl::add_integrator_parameters(schema, pl::Scheme::modified_euler);
  const auto* integrator = schema.find("integrator");
  REQUIRE(integrator);
  CHECK(integrator->choices.size() == 6);
  CHECK(std::get<std::string>(*integrator->fallback) == "modified_euler");
  REQUIRE(schema.find("substeps"));
  CHECK_FALSE(schema.find("substeps")->in_range(0));
  CHECK(schema.find("substeps")->in_range(1));
  CHECK_FALSE(schema.find("stol")->in_range(0.0));
  CHECK_FALSE(schema.find("stol")->in_range(1.0));
  CHECK(schema.find("stol")->in_range(1e-4));
  CHECK_FALSE(schema.find("ftol")->in_range(1e-2));
  CHECK(schema.find("ftol")->in_range(1e-12));
  CHECK(schema.find("alpha")->in_range(0.0));
  CHECK(schema.find("alpha")->in_range(1.0));
  CHECK_FALSE(schema.find("alpha")->in_range(1.01));
  CHECK_FALSE(schema.find("max_iterations")->in_range(0));

  stratum::Params p;
  for (const auto& spec : schema.specs()) p.set(spec.name, *spec.fallback);
  pl::Settings s = pl::read_integrator_parameters(p);
  const pl::Settings d;
  CHECK(s.scheme == pl::Scheme::modified_euler);
  CHECK(s.substeps == d.substeps);
  CHECK(s.stol == d.stol);
  CHECK(s.ftol == d.ftol);
  CHECK(s.alpha == d.alpha);
  CHECK(s.max_iterations == d.max_iterations);

  p.set("integrator", std::string("midpoint"));
  p.set("substeps", 7LL);
  p.set("alpha", 0.75);
  s = pl::read_integrator_parameters(p);
  CHECK(s.scheme == pl::Scheme::midpoint);
  CHECK(s.substeps == 7);
  CHECK(s.alpha == 0.75);
  for (pl::Scheme sc : all_schemes) {
    p.set("integrator", std::string(pl::to_string(sc)));
    CHECK(pl::read_integrator_parameters(p).scheme == sc);
  }
  p.set("integrator", std::string("runge_kutta"));
  CHECK_THROWS_AS(pl::read_integrator_parameters(p), stratum::Error);
}

} // namespace test_plasticity_integrators
