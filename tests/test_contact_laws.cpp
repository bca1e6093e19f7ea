// Contact laws at one interface point (verification.md section 4, C2 direct shear; opening,
// reclosing and tension cut-off; finite-difference checks of the tangents).
#include "coulomb_elastoplastic/coulomb_elastoplastic.hpp"
#include "goodman_nonlinear/goodman_nonlinear.hpp"
#include "hyperbolic_interface/hyperbolic_interface.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

namespace test_contact_laws {

using namespace stratum;

namespace {

constexpr double deg = std::numbers::pi / 180.0;

/// One interface point driven by total jumps; commits after every call.
struct Point {
  const ContactLaw& law;
  Vec2 traction = Vec2::Zero(), jump = Vec2::Zero();
  std::vector<double> h;
  Mat2 tangent = Mat2::Zero();
  ContactState state = ContactState::stick;

  explicit Point(const ContactLaw& l) : law(l), h(static_cast<std::size_t>(l.history_size())) {
    law.init_history(h);
  }
  /// Trial update to the total jump j; returns the traction without committing.
  Vec2 trial(const Vec2& j, Mat2* D = nullptr, std::vector<double>* hist = nullptr) const {
    Vec2 t;
    Mat2 k;
    std::vector<double> hn(h.size());
    const Vec2 dj = j - jump;
    ContactInput in{traction, jump, h, dj, {}};
    ContactOutput out{t, hn, k};
    REQUIRE(law.update(in, out).ok());
    if (D) *D = k;
    if (hist) *hist = hn;
    return t;
  }
  void go(const Vec2& j) {
    std::vector<double> hn;
    traction = trial(j, &tangent, &hn);
    h = hn;
    jump = j;
    state = law.state(traction, h);
  }
  /// Largest relative deviation of the tangent from central differences at the trial jump j.
  double fd_error(const Vec2& j) const {
    Mat2 D;
    trial(j, &D);
    Mat2 fd;
    for (int c = 0; c < 2; ++c) {
      const double e = 1e-9;
      Vec2 jp = j, jm = j;
      jp[c] += e, jm[c] -= e;
      fd.col(c) = (trial(jp) - trial(jm)) / (2 * e);
    }
    return (D - fd).norm() / std::max(1.0, fd.norm());
  }
};

goodman::Constants loess() {
  goodman::Constants c;
  c.k_s0 = 5000, c.alpha = 20000, c.m = 0.8, c.p_a = 100;
  c.c_peak = 10, c.tan_peak = std::tan(30 * deg);
  c.c_res = 2, c.tan_res = std::tan(22 * deg);
  c.c_A = 7, c.tan_A = 0.7 * std::tan(30 * deg);
  c.r2 = 0.4, c.r3 = 1.0, c.r4 = 1.5;
  c.k_n = 1e6;
  return c;
}

} // namespace

TEST_CASE("goodman_nonlinear: direct shear at 25, 50 and 75 kPa", "[contact]") {
  const auto c = loess();
  const goodman::GoodmanNonlinear law(c);
  for (double sn : {25.0, 50.0, 75.0}) {
    CAPTURE(sn);
    Point pt(law);
    const double v = -sn / c.k_n; // constant normal stress: the normal law is decoupled
    pt.go(Vec2(0.0, v));
    REQUIRE(pt.traction[1] == Approx(-sn).epsilon(1e-12));
    const double k1 = c.k_s0 + c.alpha * std::pow(sn / c.p_a, c.m);
    const double tA = c.c_A + sn * c.tan_A, tP = c.c_peak + sn * c.tan_peak;
    const double tR = c.c_res + sn * c.tan_res;
    // Initial stiffness (3.53).
    const double du0 = 0.1 * tA / k1;
    pt.go(Vec2(du0, v));
    CHECK(pt.traction[0] / du0 == Approx(k1).epsilon(1e-8));
    CHECK(pt.tangent(0, 0) == Approx(k1).epsilon(1e-8));
    // Monotonic shear in small steps: peak, then residual.
    const double uA = tA / k1, uP = uA + (tP - tA) / (c.r2 * k1);
    double peak = 0.0;
    bool saw_drop = false;
    for (int i = 1; i <= 400; ++i) {
      const double u = du0 + i * (2.0 * uP) / 400;
      pt.go(Vec2(u, v));
      peak = std::max(peak, pt.traction[0]);
      if (u < uA) CHECK(pt.traction[0] == Approx(k1 * u).epsilon(1e-8));
      if (u > uA && u < uP) CHECK(pt.traction[0] == Approx(tA + c.r2 * k1 * (u - uA)).epsilon(1e-8));
      if (u > uP) {
        saw_drop = true;
        CHECK(pt.traction[0] == Approx(tR).epsilon(1e-8));
        CHECK(pt.state == ContactState::slip);
      }
    }
    CHECK(saw_drop);
    CHECK(peak <= tP * (1 + 1e-12));
    // The peak is reached exactly at u = uP.
    Point exact(law);
    exact.go(Vec2(0.0, v));
    exact.go(Vec2(uP * (1 - 1e-12), v));
    CHECK(exact.traction[0] == Approx(tP).epsilon(1e-8));
    // The peak is never recovered: unload and reload stay at the residual strength.
    pt.go(Vec2(pt.jump[0] - 0.5 * tR / k1, v));
    CHECK(pt.traction[0] == Approx(0.5 * tR).epsilon(1e-8));
    pt.go(Vec2(pt.jump[0] + 2 * uP, v));
    CHECK(pt.traction[0] == Approx(tR).epsilon(1e-8));
  }
}

TEST_CASE("goodman_nonlinear: unloading and reloading follow the Q_max memory (3.55)", "[contact]") {
  const auto c = loess();
  const goodman::GoodmanNonlinear law(c);
  const double sn = 50.0, v = -sn / c.k_n;
  const double k1 = c.k_s0 + c.alpha * std::pow(sn / c.p_a, c.m), k2 = c.r2 * k1, k4 = c.r4 * k1;
  const double tA = c.c_A + sn * c.tan_A, tP = c.c_peak + sn * c.tan_peak;
  const double uA = tA / k1;
  const double t1 = 0.5 * (tA + tP), u1 = uA + (t1 - tA) / k2; // a virgin point between A and B
  Point pt(law);
  pt.go(Vec2(0.0, v));
  for (int i = 1; i <= 10; ++i) pt.go(Vec2(u1 * i / 10, v));
  REQUIRE(pt.traction[0] == Approx(t1).epsilon(1e-8));
  CHECK(pt.h[0] == Approx(t1 - tA).epsilon(1e-8)); // Q_max = |tau| - tau_A
  // Unloading with K_s4 to tau = 0 ...
  const double u0 = u1 - t1 / k4;
  pt.go(Vec2(u1 - 0.5 * t1 / k4, v));
  CHECK(pt.traction[0] == Approx(0.5 * t1).epsilon(1e-8));
  CHECK(pt.tangent(0, 0) == Approx(k4).epsilon(1e-8));
  pt.go(Vec2(u0, v));
  CHECK(std::abs(pt.traction[0]) < 1e-8 * t1);
  // ... reloading with K_s4 while Q < Q_max ...
  pt.go(Vec2(u0 + 0.8 * t1 / k4, v));
  CHECK(pt.traction[0] == Approx(0.8 * t1).epsilon(1e-8));
  CHECK(pt.tangent(0, 0) == Approx(k4).epsilon(1e-8));
  // ... and on the virgin branch K_s2 again beyond Q_max, in one increment across the kink.
  const double u2 = u0 + t1 / k4 + 0.5 * (tP - t1) / k2;
  pt.go(Vec2(u2, v));
  CHECK(pt.traction[0] == Approx(t1 + 0.5 * (tP - t1)).epsilon(1e-8));
  CHECK(pt.tangent(0, 0) == Approx(k2).epsilon(1e-8));
  // Reverse shear: the memory acts on |tau| (Q uses |tau|): K_s4 down to -(tau_A + Q_max).
  const double q = pt.h[0];
  const double u3 = pt.jump[0] - (pt.traction[0] + 0.5 * (tA + q)) / k4;
  pt.go(Vec2(u3, v));
  CHECK(pt.traction[0] == Approx(-0.5 * (tA + q)).epsilon(1e-8));
}

TEST_CASE("goodman_nonlinear: tension cut-off, opening, gap and reclosing under cyclic normal load",
          "[contact]") {
  auto c = loess();
  c.sigma_t = 30.0;
  const goodman::GoodmanNonlinear law(c);
  Point pt(law);
  const double vt = c.sigma_t / c.k_n;
  for (int cycle = 0; cycle < 2; ++cycle) {
    pt.go(Vec2(0.0, 0.5 * vt));
    if (cycle == 0) { // intact: tension up to sigma_T
      CHECK(pt.traction[1] == Approx(0.5 * c.sigma_t).epsilon(1e-12));
      CHECK(pt.state == ContactState::stick);
    } else { // after the cut-off no tension is ever carried again
      CHECK(pt.traction[1] == 0.0);
      CHECK(pt.state == ContactState::open);
    }
    pt.go(Vec2(0.0, 2.0 * vt)); // beyond sigma_T: cut-off to zero
    CHECK(pt.traction[1] == 0.0);
    CHECK(pt.state == ContactState::open);
    pt.go(Vec2(1e-3, 5.0 * vt)); // open: free slip, no shear
    CHECK(pt.traction[0] == 0.0);
    pt.go(Vec2(1e-3, -2.0 * vt)); // reclosed: compression with k_n
    CHECK(pt.traction[1] == Approx(-2.0 * c.sigma_t).epsilon(1e-12));
    CHECK(pt.state == ContactState::stick);
  }
  // Initial gap: no stress until the gap is closed, then k_n.
  c.sigma_t = 0.0;
  c.gap = 2e-4;
  const goodman::GoodmanNonlinear gapped(c);
  Point g(gapped);
  g.go(Vec2(0.0, -1e-4));
  CHECK(g.traction[1] == 0.0);
  CHECK(g.state == ContactState::open);
  g.go(Vec2(0.0, -3e-4));
  CHECK(g.traction[1] == Approx(-c.k_n * 1e-4).epsilon(1e-12));
}

TEST_CASE("goodman_nonlinear: tangent against finite differences", "[contact]") {
  const goodman::GoodmanNonlinear law(loess());
  const double v = -50.0 / 1e6;
  Point pt(law);
  pt.go(Vec2(0.0, v));
  CHECK(pt.fd_error(Vec2(1e-4, v)) < 1e-5); // O-A
  pt.go(Vec2(8e-4, v));                     // virgin A-B
  CHECK(pt.fd_error(Vec2(9e-4, v * 1.1)) < 1e-5);
  pt.go(Vec2(5e-3, v)); // residual, sliding
  CHECK(pt.state == ContactState::slip);
  CHECK(pt.fd_error(Vec2(6e-3, v * 1.2)) < 1e-5);
}

TEST_CASE("coulomb_elastoplastic: sliding, dilation, plastic-work loading and tangent", "[contact]") {
  coulomb_interface::Constants c;
  c.k_s = 2e4, c.k_n = 1e5, c.c = 5.0, c.phi = 30 * deg, c.psi = 10 * deg;
  const coulomb_interface::CoulombInterface law(c);
  REQUIRE_FALSE(law.symmetric_tangent());
  Point pt(law);
  const double v0 = -50.0 / c.k_n;
  pt.go(Vec2(0.0, v0));
  // Elastic until |tau| = c + p tan(phi).
  const double tmax = c.c + 50.0 * std::tan(c.phi);
  pt.go(Vec2(0.5 * tmax / c.k_s, v0));
  CHECK(pt.traction[0] == Approx(0.5 * tmax).epsilon(1e-12));
  CHECK(pt.state == ContactState::stick);
  // Shearing at constant normal jump: plastic slip dilates, the normal stress grows, and the
  // traction stays on f = 0 with v_p = tan(psi) u_p.
  for (int i = 1; i <= 20; ++i) pt.go(Vec2(i * 2e-3, v0));
  const double p = -pt.traction[1];
  CHECK(std::abs(pt.traction[0]) == Approx(c.c + p * std::tan(c.phi)).epsilon(1e-10));
  CHECK(pt.h[1] == Approx(std::tan(c.psi) * pt.h[0]).epsilon(1e-10));
  CHECK(p > 50.0);
  CHECK(pt.state == ContactState::slip);
  CHECK(pt.fd_error(Vec2(pt.jump[0] + 1e-4, v0)) < 1e-6);
  // Unloading: dW < 0 (3.59) gives the elastic matrix.
  pt.go(Vec2(pt.jump[0] - 1e-5, v0));
  CHECK(pt.state == ContactState::stick);
  CHECK(pt.tangent(0, 0) == Approx(c.k_s));
  CHECK(pt.tangent(0, 1) == 0.0);
  // Associated (psi = phi): the thesis' (3.60) matrix.
  c.psi = c.phi;
  const coulomb_interface::CoulombInterface assoc(c);
  Point a(assoc);
  a.go(Vec2(0.0, v0));
  a.go(Vec2(0.01, v0));
  const double t = std::tan(c.phi), H = c.k_s + c.k_n * t * t;
  CHECK(a.tangent(0, 0) == Approx(c.k_s * c.k_n * t * t / H).epsilon(1e-12));
  CHECK(a.tangent(1, 1) == Approx(c.k_s * c.k_n / H).epsilon(1e-12));
  CHECK(std::abs(a.tangent(0, 1)) == Approx(c.k_s * c.k_n * t / H).epsilon(1e-12));
  CHECK(a.tangent(0, 1) == Approx(a.tangent(1, 0)).epsilon(1e-12));
}

TEST_CASE("coulomb_elastoplastic: opening and reclosing, tension cut-off", "[contact]") {
  coulomb_interface::Constants c;
  c.k_s = 2e4, c.k_n = 1e5, c.c = 5.0, c.phi = 30 * deg, c.sigma_t = 10.0;
  const coulomb_interface::CoulombInterface law(c);
  Point pt(law);
  pt.go(Vec2(0.0, 5.0 / c.k_n));
  CHECK(pt.traction[1] == Approx(5.0));
  pt.go(Vec2(0.0, 20.0 / c.k_n));
  CHECK(pt.traction.norm() == 0.0);
  CHECK(pt.state == ContactState::open);
  for (int cycle = 0; cycle < 3; ++cycle) {
    pt.go(Vec2(1e-3 * cycle, 5.0 / c.k_n)); // no tension after the cut-off
    CHECK(pt.traction.norm() == 0.0);
    CHECK(pt.state == ContactState::open);
    pt.go(Vec2(1e-3 * cycle, -30.0 / c.k_n)); // closed again: compression, shear from zero
    CHECK(pt.traction[1] == Approx(-30.0).epsilon(1e-12));
    CHECK(pt.traction[0] == Approx(0.0).margin(1e-12));
    CHECK(pt.state == ContactState::stick);
  }
}

TEST_CASE("hyperbolic_interface: Clough-Duncan curve, tangent (3.65) and sliding", "[contact]") {
  hyperbolic_interface::Constants c;
  c.K_I = 5e4, c.n = 0.6, c.R_f = 0.85, c.c_a = 3.0, c.tan_delta = std::tan(25 * deg), c.k_n = 1e6;
  const hyperbolic_interface::HyperbolicInterface law(c);
  for (double sn : {25.0, 50.0, 75.0}) {
    CAPTURE(sn);
    Point pt(law);
    const double v = -sn / c.k_n;
    pt.go(Vec2(0.0, v));
    const double Ki = c.K_I * c.gamma_w * std::pow(sn / c.p_a, c.n), tf = c.c_a + sn * c.tan_delta;
    const double uf = tf / (Ki * (1 - c.R_f));
    for (double u : {0.01 * uf, 0.3 * uf, 0.9 * uf}) {
      pt.go(Vec2(u, v));
      const double tau = u / (1 / Ki + c.R_f * u / tf);
      CHECK(pt.traction[0] == Approx(tau).epsilon(1e-12));
      CHECK(pt.tangent(0, 0) == Approx(Ki * std::pow(1 - c.R_f * tau / tf, 2)).epsilon(1e-12));
      CHECK(pt.fd_error(Vec2(u * 1.01, v * 1.05)) < 1e-5);
    }
    pt.go(Vec2(3 * uf, v));
    CHECK(pt.traction[0] == Approx(tf).epsilon(1e-12));
    CHECK(pt.state == ContactState::slip);
    CHECK(pt.fd_error(Vec2(3.1 * uf, v * 1.05)) < 1e-5);
    pt.go(Vec2(3 * uf, 1e-4)); // open
    CHECK(pt.traction.norm() == 0.0);
    CHECK(pt.state == ContactState::open);
  }
}

} // namespace test_contact_laws
