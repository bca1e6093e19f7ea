// Tests of the DiMaggio-Sandler cap model (plugins/cap_sandler): the hydrostatic closed form
// of docs/verification.md M7, point tests of the tension, envelope, corner and cap regimes
// against closed forms or hand-derived conditions, agreement of the Sandler-Rubin and
// closest-point integrators, analytic derivatives and the consistent tangent against finite
// differences, and the thesis' loess set (README.md: F_CUT is the envelope's apex).
#include "cap_sandler/cap_sandler.hpp"

#include "stratum/error.hpp"
#include "stratum/point_driver.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

namespace test_cap_sandler {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace cs = stratum::cap_sandler;
namespace pl = stratum::plasticity;

/// The thesis' loess set (digest §9.4) with theta = 0 and the initial cap Z.
cs::Constants loess(double Z = 0.0) {
  cs::Constants c; // defaults are the loess values
  c.Z = Z;
  return c;
}

Vec6 isotropic(double p) { // compression-positive p
  Vec6 s = Vec6::Zero();
  s[0] = s[1] = s[2] = -p;
  return s;
}
Vec6 volumetric(double ev) { // tension-positive volumetric strain
  Vec6 e = Vec6::Zero();
  e[0] = e[1] = e[2] = ev / 3.0;
  return e;
}

/// One material point with its committed state.
struct Point {
  const cs::CapSandler& mat;
  Vec6 stress;
  Vec6 strain = Vec6::Zero();
  std::array<double, 3> history{};
  Mat6 tangent = Mat6::Zero();

  Point(const cs::CapSandler& m, const Vec6& s0) : mat(m), stress(s0) { mat.init_history(stress, history); }
  stratum::Outcome trial(const Vec6& de, Vec6& s, std::array<double, 3>& h, Mat6& T) const {
    const stratum::MaterialInput in{stress, strain, history, de, {}};
    stratum::MaterialOutput out{s, h, T};
    return mat.update(in, out);
  }
  stratum::Outcome step(const Vec6& de) {
    Vec6 s;
    std::array<double, 3> h{};
    Mat6 T;
    const stratum::Outcome o = trial(de, s, h, T);
    if (o.ok()) stress = s, strain += de, history = h, tangent = T;
    return o;
  }
  [[nodiscard]] double kappa() const { return history[0]; }
  [[nodiscard]] cs::Regime regime() const { return static_cast<cs::Regime>(static_cast<int>(history[2])); }
};

double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

/// Central finite-difference tangent of one update from the committed state of p.
Mat6 fd_tangent(const Point& p, const Vec6& de, double h) {
  Mat6 J;
  for (int j = 0; j < 6; ++j) {
    Vec6 dp = de, dm = de, sp, sm;
    dp[j] += h, dm[j] -= h;
    std::array<double, 3> hh{};
    Mat6 T;
    REQUIRE(p.trial(dp, sp, hh, T).ok());
    REQUIRE(p.trial(dm, sm, hh, T).ok());
    J.col(j) = (sp - sm) / (2 * h);
  }
  return J;
}

/// The plastic strain increment de - D^-1 dsigma (tension positive, engineering shear).
Vec6 plastic_increment(const cs::Constants& c, const Vec6& s0, const Vec6& s1, const Vec6& de) {
  const Mat6 D = stratum::stiffness_kg(c.K(), c.G());
  return de - D.inverse() * (s1 - s0);
}

/// Both materials of one constant set.
struct Pair {
  cs::CapSandler sr, cp;
  explicit Pair(const cs::Constants& c)
      : sr(c, cs::Integration::sandler_rubin), cp(c, cs::Integration::closest_point) {}
};

} // namespace

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: M7 hydrostatic compression from X0 = 0 follows the closed form", "[cap]") {
  // verification.md M7: eps_v = I1/(3K) + W (1 - exp(-D I1)), Z = X0 = 0 (the cap is active
  // from the first increment). Loess constants, compression to eps_v = 4 % in 40 steps.
  const cs::Constants c = loess(0.0);
  const Pair pair(c);
  for (const cs::CapSandler* m : {&pair.sr, &pair.cp}) {
    INFO((m == &pair.sr ? "sandler_rubin" : "closest_point"));
    Point p(*m, Vec6::Zero());
    CHECK(c.X(p.kappa()) == Approx(0.0).margin(1e-9)); // the cap tip sits at the origin
    double worst = 0.0;
    for (int i = 0; i < 40; ++i) {
      REQUIRE(p.step(volumetric(-0.001)).ok());
      CHECK(p.regime() == cs::Regime::cap);
      const double I1 = cs::J1c(p.stress);
      const double ev = -(p.strain[0] + p.strain[1] + p.strain[2]);
      const double closed = I1 / (3 * c.K()) + c.W * (1 - std::exp(-c.D * I1));
      worst = std::max(worst, std::abs(ev - closed) / ev);
      CHECK(cs::rootJ2(p.stress) < 1e-9);
      CHECK(c.X(p.kappa()) == Approx(I1).epsilon(1e-10)); // the cap passes through the stress
      CHECK(p.history[1] == Approx(c.W * (1 - std::exp(-c.D * I1))).epsilon(1e-9));
    }
    INFO("worst relative error in eps_v " << worst);
    CHECK(worst < 1e-6);
    // unloading is elastic: K unchanged
    const double I1 = cs::J1c(p.stress);
    REQUIRE(p.step(volumetric(0.001)).ok());
    CHECK(p.regime() == cs::Regime::elastic);
    CHECK(I1 - cs::J1c(p.stress) == Approx(3 * c.K() * 0.001).epsilon(1e-12));
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: tension cut-off regime", "[cap]") {
  const cs::Constants c = loess(0.0);
  const Pair pair(c);
  // From J1 = 30 kPa (isotropic p = 10) a hydrostatic extension of 2e-3 gives the trial
  // J1E = 30 - 3 K 2e-3 = -60 < -T = -30: the stress stops at J1 = -T, the rest is plastic.
  const Vec6 s0 = isotropic(10.0);
  const double J1E = 30.0 - 3 * c.K() * 2e-3;
  for (const cs::CapSandler* m : {&pair.sr, &pair.cp}) {
    INFO((m == &pair.sr ? "sandler_rubin" : "closest_point"));
    Point p(*m, s0);
    const double e0 = c.eps_of_kappa(p.kappa());
    REQUIRE(p.step(volumetric(2e-3)).ok());
    CHECK(p.regime() == cs::Regime::tension);
    for (int i = 0; i < 3; ++i) CHECK(p.stress[i] == Approx(c.T / 3).epsilon(1e-12));
    for (int i = 3; i < 6; ++i) CHECK(p.stress[i] == Approx(0.0).margin(1e-12));
    // (4.53): d eps_v^p = (J1E - J1)/(3K) < 0 retracts the cap through the hardening law
    const double dev = (J1E + c.T) / (3 * c.K());
    CHECK(p.history[1] == Approx(dev).epsilon(1e-10));
    const double X = c.Z - std::log(1 - (e0 + dev) / c.W) / c.D;
    CHECK(c.X(p.kappa()) == Approx(X).epsilon(1e-10));
  }
  // With a deviator the thesis' rule (S_ij = 0) and the closest point differ: the closest
  // point keeps the trial deviator when it lies below the envelope at J1 = -T.
  Vec6 de = volumetric(2e-3);
  de[3] = 1e-3; // gamma_xy: trial s_xy = G 1e-3 = 6.92 kPa < F_e(-30) = 74.9 kPa
  Point a(pair.sr, s0), b(pair.cp, s0);
  REQUIRE(a.step(de).ok());
  REQUIRE(b.step(de).ok());
  CHECK(a.stress[3] == Approx(0.0).margin(1e-12));
  CHECK(b.stress[3] == Approx(c.G() * 1e-3).epsilon(1e-10));
  CHECK(cs::J1c(b.stress) == Approx(-c.T).epsilon(1e-10));
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: retraction = above_initial stops the cap at X0 = Z, free lets it retract", "[cap]") {
  // The tension case above: from J1 = 30 kPa (the initial cap widened to X = 30, eps_v^p =
  // W (1 - exp(-30 D)) = 4.13e-4) the return to J1 = -T adds d eps_v^p = (J1E + T)/(3K) =
  // -6.67e-4. free: X = Z - ln(1 - (e0 + dev)/W)/D < Z; above_initial: X = Z exactly. A
  // hydrostatic recompression then hardens from X = Z by the M7 closed form
  // eps_v^p = W (1 - exp(-D (I1 - Z))): the dilation below the virgin state is not remembered.
  cs::Constants free_c = loess(0.0), held = loess(0.0);
  held.free_retraction = false;
  const Vec6 s0 = isotropic(10.0);
  const double J1E = 30.0 - 3 * free_c.K() * 2e-3;
  const double e0 = free_c.eps_of_X(30.0), dev = (J1E + free_c.T) / (3 * free_c.K());
  REQUIRE(e0 + dev < 0.0);
  for (auto integ : {cs::Integration::sandler_rubin, cs::Integration::closest_point}) {
    INFO((integ == cs::Integration::sandler_rubin ? "sandler_rubin" : "closest_point"));
    const cs::CapSandler mf(free_c, integ), mh(held, integ);
    Point a(mf, s0), b(mh, s0);
    REQUIRE(a.step(volumetric(2e-3)).ok());
    REQUIRE(b.step(volumetric(2e-3)).ok());
    CHECK(a.regime() == cs::Regime::tension);
    CHECK(b.regime() == cs::Regime::tension);
    CHECK(cs::J1c(b.stress) == Approx(-held.T).epsilon(1e-12));
    CHECK(free_c.X(a.kappa()) ==
          Approx(free_c.Z - std::log1p(-(e0 + dev) / free_c.W) / free_c.D).epsilon(1e-10));
    CHECK(free_c.X(a.kappa()) < held.Z - 1.0);               // retracted by more than 1 kPa
    CHECK(held.X(b.kappa()) == Approx(held.Z).margin(1e-9)); // held at X0 = Z
    REQUIRE(b.step(volumetric(2e-3)).ok());                  // more tension: still held
    CHECK(held.X(b.kappa()) == Approx(held.Z).margin(1e-9));
    // recompress hydrostatically: elastic to J1 = Z, then the cap moves by M7 from Z
    const double I1_start = cs::J1c(b.stress);
    double total = 0.0;
    for (int i = 0; i < 20; ++i) {
      REQUIRE(b.step(volumetric(-2e-4)).ok());
      total += 2e-4;
    }
    const double I1 = cs::J1c(b.stress);
    REQUIRE(I1 > held.Z + 50.0);
    const double ep_closed = held.W * (1 - std::exp(-held.D * (I1 - held.Z)));
    CHECK(held.eps_of_kappa(b.kappa()) == Approx(ep_closed).epsilon(1e-8));
    CHECK(total == Approx((I1 - I1_start) / (3 * held.K()) + ep_closed).epsilon(1e-6));
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: closest point at a near-triple corner (envelope, cap, tension)", "[cap]") {
  // A state of the loess pile scene beside the pile toe: the stress sits on the corner of
  // envelope and cap at J1 = kappa = -29.59 kPa, 0.41 kPa from the tension cut-off J1 = -30.
  // The active-set strategy cycles between {envelope, cap, tension} and two-surface sets; the
  // exhaustive fallback must return an admissible stress (every f <= tol) whose plastic strain
  // is a non-negative combination of the normals of the surfaces active there (normal flow),
  // with the hardening law satisfied.
  cs::Constants c = loess(0.0);
  c.free_retraction = false;
  const cs::CapSandler m(c, cs::Integration::closest_point);
  Vec6 s0;
  s0 << -33.913756890810596, 39.7665869336168, 23.734395641883463, 64.223836518869078, 0, 0;
  Point p(m, s0);
  p.history[0] = -29.587225684683457;
  const std::array<double, 1> q0{c.eps_of_kappa(p.history[0])};
  const auto& model = m.model();
  for (int k = 0; k < 3; ++k) REQUIRE(model.yield(k, s0, q0) < 1e-6); // admissible start
  Vec6 de;
  de << -1.3287895913653105e-05, 3.3118548934543929e-05, -5.9408440229013675e-07, 8.0490359803870871e-05, 0,
      0;
  const double k0 = p.kappa();
  REQUIRE(p.step(de).ok());
  const std::array<double, 1> q{c.eps_of_kappa(p.kappa())};
  const double tol = 1e-8 * model.stress_scale(p.stress, q);
  Eigen::Matrix<double, 6, Eigen::Dynamic> N(6, 0);
  for (int k = 0; k < 3; ++k) {
    const double f = model.yield(k, p.stress, q);
    INFO("surface " << k << ": f = " << f);
    CHECK(f <= tol * c.R);
    if (std::abs(f) <= tol * c.R) {
      N.conservativeResize(6, N.cols() + 1);
      N.col(N.cols() - 1) = model.yield_gradient(k, p.stress, q);
    }
  }
  REQUIRE(N.cols() >= 1);
  const Vec6 ep = plastic_increment(c, s0, p.stress, de);
  const Eigen::VectorXd l = N.colPivHouseholderQr().solve(ep);
  INFO("multipliers " << l.transpose());
  CHECK(l.minCoeff() >= -1e-12);
  CHECK((N * l - ep).norm() < 1e-7 * ep.norm());
  // hardening: the cap moves with the plastic volume change (held at Z when it dilates below)
  const double e_new = c.moving(c.eps_of_kappa(k0) - (ep[0] + ep[1] + ep[2]));
  CHECK(c.eps_of_kappa(p.kappa()) == Approx(e_new).margin(1e-12));
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: envelope regime, straight envelope against the Drucker-Prager closed form", "[cap]") {
  // C -> 0 leaves the straight envelope sqrt(J2) = A + theta J1. A simple-shear increment
  // from an isotropic state far inside the cap: trial J1E = 3 p, sqrt(J2E) = G gamma, and the
  // return (4.59)-(4.60) is exact: dl = fE / (9 K theta^2 + G), J1 = J1E + 9 K dl theta,
  // sqrt(J2) = sqrt(J2E) - G dl.
  cs::Constants c = loess(3000.0);
  c.C = 0.0;
  c.theta = 0.2;
  const Pair pair(c);
  const double p0 = 50.0, gamma = 0.04;
  const double J1E = 3 * p0, rE = c.G() * gamma, fE = rE - (c.A + c.theta * J1E);
  REQUIRE(fE > 0);
  const double dl = fE / (9 * c.K() * c.theta * c.theta + c.G());
  const double J1 = J1E + 9 * c.K() * dl * c.theta, r = rE - c.G() * dl;
  Vec6 de = Vec6::Zero();
  de[3] = gamma;
  for (const cs::CapSandler* m : {&pair.sr, &pair.cp}) {
    INFO((m == &pair.sr ? "sandler_rubin" : "closest_point"));
    Point p(*m, isotropic(p0));
    REQUIRE(p.kappa() > J1); // the cap is far away
    REQUIRE(p.step(de).ok());
    CHECK(p.regime() == cs::Regime::envelope);
    CHECK(cs::J1c(p.stress) == Approx(J1).epsilon(1e-10));
    CHECK(cs::rootJ2(p.stress) == Approx(r).epsilon(1e-10));
    CHECK(p.stress[3] == Approx(r).epsilon(1e-10));
    CHECK(p.history[1] == Approx(-3 * dl * c.theta).epsilon(1e-9)); // dilation
  }
}

TEST_CASE("cap_sandler: envelope regime, loess envelope: on the surface with normal flow", "[cap]") {
  // The curved envelope has no closed form; the return must satisfy its defining equations:
  // sqrt(J2) = F_e(J1) and d eps^p parallel to n = s/(2 sqrt J2) + F_e'(J1) 1 at the end.
  const cs::Constants c = loess(3000.0);
  const Pair pair(c);
  Vec6 de;
  de << 6e-3, -27e-3, 3e-3, 18e-3, -6e-3, 9e-3;
  const Vec6 s0 = isotropic(60.0);
  Vec6 out[2];
  int i = 0;
  for (const cs::CapSandler* m : {&pair.sr, &pair.cp}) {
    INFO((m == &pair.sr ? "sandler_rubin" : "closest_point"));
    Point p(*m, s0);
    REQUIRE(p.step(de).ok());
    CHECK(p.regime() == cs::Regime::envelope);
    const double J1 = cs::J1c(p.stress);
    CHECK(cs::rootJ2(p.stress) == Approx(c.Fe(J1)).epsilon(1e-10));
    const std::array<double, 1> q{0.0};
    const Vec6 n = pair.cp.model().yield_gradient(cs::Model::envelope, p.stress, q);
    const Vec6 ep = plastic_increment(c, s0, p.stress, de);
    const double lambda = ep.dot(n) / n.dot(n);
    CHECK(lambda > 0);
    CHECK((ep - lambda * n).norm() < 1e-9 * ep.norm());
    out[i++] = p.stress;
  }
  CHECK(rel_diff(out[0], out[1]) < 1e-9); // both integrators
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: cap regime with shear: on the cap, normal flow, hardening law", "[cap]") {
  // Normally consolidated isotropic state p = 100 kPa (the cap passes through it), then a
  // compressive increment with shear. Conditions: f_c = 0 at the end, d eps^p parallel to the
  // cap normal, and d eps_v^p = eps_v^p(kappa) - eps_v^p(kappa_n) (2.148).
  const cs::Constants c = loess(0.0);
  const Pair pair(c);
  Vec6 de;
  de << -1e-3, -4e-3, -1e-3, 2e-3, 0.5e-3, -1e-3;
  const Vec6 s0 = isotropic(100.0);
  Vec6 out[2];
  double kap[2];
  int i = 0;
  for (const cs::CapSandler* m : {&pair.sr, &pair.cp}) {
    INFO((m == &pair.sr ? "sandler_rubin" : "closest_point"));
    Point p(*m, s0);
    CHECK(c.X(p.kappa()) == Approx(300.0).epsilon(1e-12)); // widened to the initial stress
    const double k0 = p.kappa();
    REQUIRE(p.step(de).ok());
    CHECK(p.regime() == cs::Regime::cap);
    const std::array<double, 1> q{c.eps_of_kappa(p.kappa())};
    CHECK(pair.cp.model().yield(cs::Model::cap, p.stress, q) == Approx(0.0).margin(1e-9));
    CHECK(cs::J1c(p.stress) > p.kappa());
    const Vec6 n = pair.cp.model().yield_gradient(cs::Model::cap, p.stress, q);
    const Vec6 ep = plastic_increment(c, s0, p.stress, de);
    const double lambda = ep.dot(n) / n.dot(n);
    CHECK(lambda > 0);
    CHECK((ep - lambda * n).norm() < 1e-9 * ep.norm());
    const double dev = -(ep[0] + ep[1] + ep[2]);
    CHECK(dev == Approx(c.eps_of_kappa(p.kappa()) - c.eps_of_kappa(k0)).epsilon(1e-9));
    CHECK(p.history[1] == Approx(dev).epsilon(1e-9));
    out[i] = p.stress, kap[i] = p.kappa();
    ++i;
  }
  CHECK(rel_diff(out[0], out[1]) < 1e-9);
  CHECK(kap[0] == Approx(kap[1]).epsilon(1e-9));
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: corner regime (envelope meets cap)", "[cap]") {
  // Isotropic p = 100 kPa (J1 = 300) with the initial cap Z = X(310), so kappa = 310 kPa lies
  // just beyond the stress, then a large shear: the dilatant envelope return raises J1 past
  // kappa, into the corner.
  const cs::Constants c0 = loess(0.0);
  const double kappa_target = 310.0;
  const cs::Constants c = loess(c0.X(kappa_target));
  const Pair pair(c);
  Vec6 de = Vec6::Zero();
  de[3] = 0.06; // gamma_xy
  const Vec6 s0 = isotropic(100.0);

  // Sandler-Rubin (4.61) (option corner = "thesis"): J1 = L(kappa_n) = kappa_n, kappa
  // unchanged, sqrt(J2) = F_e(kappa_n), deviator along the trial deviator (4.63).
  const cs::CapSandler thesis(c, cs::Integration::sandler_rubin, cs::Corner::thesis);
  Point a(thesis, s0);
  REQUIRE(a.kappa() == Approx(kappa_target).epsilon(1e-12));
  REQUIRE(a.step(de).ok());
  CHECK(a.regime() == cs::Regime::corner);
  CHECK(cs::J1c(a.stress) == Approx(kappa_target).epsilon(1e-12));
  CHECK(a.kappa() == Approx(kappa_target).epsilon(1e-14));
  CHECK(a.stress[3] == Approx(c.Fe(kappa_target)).epsilon(1e-12));

  // Closest point (and the default Sandler-Rubin corner = "two_surface"): on both surfaces
  // (J1 = kappa, sqrt(J2) = F_e(kappa)), the plastic strain in the normal cone,
  // d eps^p = l_e n_e + l_c n_c with l_e, l_c >= 0, and the hardening law.
  for (const cs::CapSandler* m : {&pair.sr, &pair.cp}) {
    INFO((m == &pair.sr ? "sandler_rubin" : "closest_point"));
    Point b(*m, s0);
    const double k0 = b.kappa();
    REQUIRE(b.step(de).ok());
    const double k1 = b.kappa();
    INFO("closest point: kappa " << k0 << " -> " << k1 << ", J1 " << cs::J1c(b.stress));
    CHECK(b.regime() == cs::Regime::corner);
    CHECK(cs::J1c(b.stress) == Approx(k1).epsilon(1e-9));
    CHECK(cs::rootJ2(b.stress) == Approx(c.Fe(k1)).epsilon(1e-9));
    const std::array<double, 1> q{c.eps_of_kappa(k1)};
    Eigen::Matrix<double, 6, 2> N;
    N.col(0) = pair.cp.model().yield_gradient(cs::Model::envelope, b.stress, q);
    N.col(1) = pair.cp.model().yield_gradient(cs::Model::cap, b.stress, q);
    const Vec6 ep = plastic_increment(c, s0, b.stress, de);
    const Eigen::Vector2d l = N.colPivHouseholderQr().solve(ep);
    CHECK(l[0] >= -1e-12);
    CHECK(l[1] >= -1e-12);
    CHECK((N * l - ep).norm() < 1e-8 * ep.norm());
    CHECK(-(ep[0] + ep[1] + ep[2]) == Approx(c.eps_of_kappa(k1) - c.eps_of_kappa(k0)).epsilon(1e-8));
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: analytic derivatives of the model match finite differences", "[cap]") {
  const cs::Model m(loess(0.0));
  Vec6 s;
  s << -120, -260, -150, 30, -20, 15; // J1 = 530
  for (double eps : {0.002, 0.012}) { // kappa below and above J1... both with J1 > kappa
    const std::array<double, 1> q{eps};
    for (int k = 0; k < 3; ++k) {
      INFO("surface " << k << " eps_v^p " << eps);
      const double h = 1e-4;
      Vec6 g, r;
      Mat6 H;
      for (int j = 0; j < 6; ++j) {
        Vec6 sp = s, sm = s;
        sp[j] += h, sm[j] -= h;
        g[j] = (m.yield(k, sp, q) - m.yield(k, sm, q)) / (2 * h);
        H.col(j) = (m.flow(k, sp, q) - m.flow(k, sm, q)) / (2 * h);
      }
      CHECK(rel_diff(m.yield_gradient(k, s, q), g) < 1e-7);
      if (k != cs::Model::tension) CHECK(rel_diff(m.flow_gradient(k, s, q), H) < 1e-6);
      const double hq = 1e-7;
      const std::array<double, 1> qp{eps + hq}, qm{eps - hq};
      const double dfdq = (m.yield(k, s, qp) - m.yield(k, s, qm)) / (2 * hq);
      CHECK(m.yield_gradient_q(k, s, q)[0] == Approx(dfdq).epsilon(1e-6).margin(1e-6));
      const Vec6 drdq = (m.flow(k, s, qp) - m.flow(k, s, qm)) / (2 * hq);
      CHECK((m.flow_gradient_q(k, s, q).col(0) - drdq).norm() < 1e-6 * (1 + drdq.norm()));
    }
  }
}

TEST_CASE("cap_sandler: without want_tangent the same stress and history, the tangent untouched", "[cap]") {
  // A residual-only evaluation (MaterialInput::want_tangent = false) skips the consistent
  // tangent of the closest point; stress and history must be those of the full evaluation.
  const Pair m(loess(0.0));
  const Vec6 s0 = isotropic(100.0);
  Vec6 cap_step = volumetric(-0.01), shear_step = Vec6::Zero(), elastic_step = volumetric(1e-6);
  cap_step[3] = 0.002;
  shear_step[3] = 0.02;
  for (const Vec6& de : {cap_step, shear_step, elastic_step}) {
    Point p(m.cp, s0);
    Vec6 s1, s2, strain = Vec6::Zero();
    std::array<double, 3> h1{}, h2{};
    Mat6 T1 = Mat6::Zero(), T2 = Mat6::Constant(7.0);
    const stratum::MaterialInput full{p.stress, strain, p.history, de, {}, true};
    const stratum::MaterialInput residual{p.stress, strain, p.history, de, {}, false};
    stratum::MaterialOutput o1{s1, h1, T1}, o2{s2, h2, T2};
    REQUIRE(m.cp.update(full, o1).ok());
    REQUIRE(m.cp.update(residual, o2).ok());
    INFO("regime " << h1[2]);
    CHECK(s1 == s2);
    CHECK(h1 == h2);
    if (h1[2] != 0.0) CHECK(T2 == Mat6::Constant(7.0)); // a plastic step leaves it as it was
  }
}

TEST_CASE("cap_sandler: Model::surface gives the numbers of the single functions", "[cap]") {
  // The closest-point return takes every function of a surface from one surface() call; the
  // cap's override inverts kappa once and must reproduce the single functions bit for bit.
  const cs::Model m(loess(0.0));
  Vec6 s1, s2, s3;
  s1 << -120, -260, -150, 30, -20, 15; // J1 = 530: J1 > kappa, on the elliptic part
  s2 << -10, -12, -8, 3, -2, 1;        // J1 = 30: below kappa, the flat continuation
  s3 << -200, -200, -200, 0, 0, 0;     // hydrostatic, sqrt(J2) = 0
  for (const Vec6& s : {s1, s2, s3})
    for (double eps : {0.0, 0.002, 0.012})
      for (int k = 0; k < 3; ++k)
        for (bool jac : {false, true}) {
          INFO("surface " << k << " eps_v^p " << eps << " jacobian " << jac << " stress " << s.transpose());
          const std::array<double, 1> q{eps};
          pl::SurfaceDerivatives d;
          m.surface(k, s, q, d, jac);
          CHECK(d.f == m.yield(k, s, q));
          CHECK(d.r == m.flow(k, s, q));
          CHECK(d.h == m.hardening(k, s, q));
          if (!jac) continue;
          CHECK(d.n == m.yield_gradient(k, s, q));
          CHECK(d.xi == m.yield_gradient_q(k, s, q));
          CHECK(d.dr_ds == m.flow_gradient(k, s, q));
          CHECK(d.dr_dq == m.flow_gradient_q(k, s, q));
          CHECK(d.dh_ds == m.hardening_gradient(k, s, q));
          CHECK(d.dh_dq == m.hardening_gradient_q(k, s, q));
        }
}

TEST_CASE("cap_sandler: the closed-form cap inverse kappa(X) equals the root by bisection", "[cap]") {
  // kappa_of_X starts Newton at the Lambert-W closed form; the reference here is 200 bisections
  // of X(kappa) = Xv (X is increasing), independent of both. Tolerance: 1e-13 (1 + |kappa|),
  // the round-off of X's terms (R A = 475 kPa) divided by dX/dkappa >= 1. Includes kappa near
  // 0, where the old stopping rule alone cycled at round-off, and a linear envelope term theta.
  for (double theta : {0.0, 0.05}) {
    cs::Constants c = loess(0.0);
    c.theta = theta;
    const double apex = c.envelope_apex();
    for (double kappa :
         {apex + 1e-3, -300.0, -137.0, -1.0, -1e-9, 0.0, 1e-9, 0.5, 37.0, 250.0, 1.0e3, 2.5e4, 3.0e6}) {
      const double Xv = c.X(kappa);
      double lo = apex - 1.0, hi = Xv + 1.0;
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (c.X(mid) < Xv ? lo : hi) = mid;
      }
      const double k = c.kappa_of_X(Xv);
      INFO("theta " << theta << " kappa " << kappa << " X " << Xv << " got " << k << " bisection " << lo);
      CHECK(std::abs(k - 0.5 * (lo + hi)) <= 1e-13 * (1.0 + std::abs(k)));
      CHECK(std::abs(k - kappa) <= 1e-12 * (1.0 + std::abs(kappa)));
      // and through the hardening law: eps -> kappa -> eps
      if (kappa > -300.0 && kappa < 3.0e3) {
        const double e = c.eps_of_kappa(kappa);
        CHECK(c.eps_of_kappa(c.kappa_of_eps(e)) == Approx(e).epsilon(1e-12).margin(1e-18));
      }
    }
  }
}

TEST_CASE("cap_sandler: closest-point consistent tangent matches finite differences", "[cap]") {
  const cs::Constants c = loess(0.0);
  const cs::CapSandler m(c, cs::Integration::closest_point);
  struct Case {
    const char* name;
    double Z;
    Vec6 s0, de;
    cs::Regime regime;
  };
  Vec6 cap_de, env_de, el_de, corner_de = Vec6::Zero();
  cap_de << -1e-3, -4e-3, -1e-3, 2e-3, 0.5e-3, -1e-3;
  env_de << 6e-3, -27e-3, 3e-3, 18e-3, -6e-3, 9e-3;
  el_de << 1e-5, -2e-5, 0.5e-5, 1e-5, 0, 0;
  corner_de[3] = 0.06;
  const Case cases[] = {
      {"cap", 0.0, isotropic(100.0), cap_de, cs::Regime::cap},
      {"envelope", 3000.0, isotropic(60.0), env_de, cs::Regime::envelope},
      {"elastic", 3000.0, isotropic(60.0), el_de, cs::Regime::elastic},
      {"corner", c.X(310.0), isotropic(100.0), corner_de, cs::Regime::corner},
  };
  for (const Case& k : cases) {
    INFO(k.name);
    cs::Constants ck = c;
    ck.Z = k.Z;
    const cs::CapSandler mk(ck, cs::Integration::closest_point);
    Point p(mk, k.s0);
    Vec6 s;
    std::array<double, 3> h{};
    Mat6 T;
    REQUIRE(p.trial(k.de, s, h, T).ok());
    CHECK(static_cast<int>(h[2]) == static_cast<int>(k.regime));
    const Mat6 fd = fd_tangent(p, k.de, 1e-8);
    INFO("relative difference " << rel_diff(T, fd));
    CHECK(rel_diff(T, fd) < 1e-5);
  }
  (void)m;
}

TEST_CASE("cap_sandler: Sandler-Rubin continuum tangent is the limit of small increments", "[cap]") {
  // The Sandler-Rubin option returns the continuum tangent (2.73); from a state on the cap
  // it is the derivative of the update as the increment goes to zero.
  const cs::Constants c = loess(0.0);
  const cs::CapSandler m(c, cs::Integration::sandler_rubin);
  Point p(m, isotropic(100.0));
  Vec6 de;
  de << -1e-3, -4e-3, -1e-3, 2e-3, 0.5e-3, -1e-3;
  REQUIRE(p.step(de).ok()); // now on the cap with shear
  const Vec6 dir = de / de.norm();
  Vec6 s;
  std::array<double, 3> h{};
  Mat6 T;
  const double t = 1e-9;
  REQUIRE(p.trial(t * dir, s, h, T).ok());
  CHECK(static_cast<int>(h[2]) == static_cast<int>(cs::Regime::cap));
  const Vec6 secant = (s - p.stress) / t;
  CHECK((secant - p.tangent * dir).norm() < 1e-5 * secant.norm());
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: drained triaxial path, both integrators agree", "[cap]") {
  // sigma_3 = 80 kPa, normally consolidated start; 1 % axial strain in 200 steps under mixed
  // control (radial stress held by Newton on the radial strains with the material's tangent).
  const cs::Constants c = loess(0.0);
  const Pair pair(c);
  double q_end[2], ev_end[2];
  int i = 0;
  for (const cs::CapSandler* m : {&pair.sr, &pair.cp}) {
    INFO((m == &pair.sr ? "sandler_rubin" : "closest_point"));
    Point p(*m, isotropic(80.0));
    for (int n = 0; n < 200; ++n) {
      // radial strain increment d so that the radial stress stays at -80
      double d = 0.0;
      for (int it = 0; it < 30; ++it) {
        Vec6 de = Vec6::Zero(), s;
        de[1] = -5e-5, de[0] = de[2] = d;
        std::array<double, 3> h{};
        Mat6 T;
        REQUIRE(p.trial(de, s, h, T).ok());
        const double r = s[0] + 80.0;
        if (std::abs(r) < 1e-10) break;
        d -= r / (T(0, 0) + T(0, 2));
      }
      Vec6 de = Vec6::Zero();
      de[1] = -5e-5, de[0] = de[2] = d;
      REQUIRE(p.step(de).ok());
      CHECK(p.stress[0] == Approx(-80.0).epsilon(1e-9));
    }
    q_end[i] = p.stress[0] - p.stress[1];
    ev_end[i] = -(p.strain[0] + p.strain[1] + p.strain[2]);
    ++i;
  }
  INFO("q: SR " << q_end[0] << ", CP " << q_end[1] << "; eps_v: SR " << ev_end[0] << ", CP " << ev_end[1]);
  CHECK(q_end[0] == Approx(q_end[1]).epsilon(1e-6));
  CHECK(ev_end[0] == Approx(ev_end[1]).epsilon(1e-6));
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cap_sandler: the loess set, F_CUT is the envelope's apex", "[cap]") {
  const cs::Constants c = loess(0.0);
  CHECK(c.K() == Approx(15000.0).epsilon(1e-14));
  CHECK(c.G() == Approx(18000.0 / 2.6).epsilon(1e-14));
  // ln(A/C)/B = ln(190/110)/0.0015 = 364.36 kPa; the thesis prints F_CUT = 364.34 (6e-5 off)
  CHECK(-c.envelope_apex() == Approx(364.34).epsilon(1e-4));
  CHECK(c.Fe(c.envelope_apex()) == Approx(0.0).margin(1e-12));
  CHECK(!cs::check(c).has_value());
}

TEST_CASE("cap_sandler: the loess point file runs and reaches the envelope", "[cap]") {
  for (const char* f : {"loess_cap_s3_025.toml", "loess_cap_s3_400.toml"}) {
    INFO(f);
    const auto d = stratum::PointDriver::from_file(std::string(STRATUM_SOURCE_DIR) + "/inputs/point/" + f,
                                                   {STRATUM_PLUGIN_DIR});
    const stratum::PointRun run = d->run();
    REQUIRE(run.outcome.ok());
    const Vec6& s = run.rows.back().stress;
    const cs::Constants c = loess(0.0);
    // at the end of the path the stress is on the failure envelope (or its corner with the cap)
    CHECK(cs::rootJ2(s) == Approx(c.Fe(cs::J1c(s))).epsilon(2e-3));
  }
}

TEST_CASE("cap_sandler: the stress integrator's key is integrator, the old key points to it", "[cap]") {
  // Issue 39: every plugin names its stress integration `integrator` (`integration` is the Gauss
  // order of a domain); the old key is refused with one located line that names the new one.
  const std::string path = std::string(STRATUM_SOURCE_DIR) + "/inputs/point/loess_cap_s3_040.toml";
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const auto at = text.find("retraction = \"free\"");
  REQUIRE(at != std::string::npos);
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  text.replace(at, std::string("retraction = \"free\"").size(), "integration = \"closest_point\"");
  try {
    (void)stratum::PointDriver::from_string(text, path, {STRATUM_PLUGIN_DIR});
    FAIL("the old key was accepted");
  } catch (const stratum::Error& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Catch::Contains("loess_cap_s3_040.toml:" + std::to_string(line) + ":1") &&
                         Catch::Contains("unknown key 'integration'") &&
                         Catch::Contains("did you mean 'integrator'?"));
  }
  text.replace(text.find("integration = "), 11, "integrator");
  CHECK(stratum::PointDriver::from_string(text, path, {STRATUM_PLUGIN_DIR})->run().outcome.ok());
}

} // namespace test_cap_sandler
