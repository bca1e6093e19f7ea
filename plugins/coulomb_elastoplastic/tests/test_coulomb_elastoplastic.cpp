// Tests of the `coulomb_elastoplastic` contact law (thesis (3.56)-(3.60)), created through the
// plugin from TOML parameters (angles in degrees), one regime at a time, against closed forms of
// the law's definition (elastic jumps k_s, k_n; yield f = |tau| + sigma tan(phi) - c; flow along
// g = |tau| + sigma tan(psi); tension positive):
// - elastic: tau = k_s u, sigma = k_n v, tangent diag(k_s, k_n), state stick (exact);
// - loading, psi = 0 (catalogue C2 direct shear at constant normal stress p): tau = k_s u up to
//   c + p tan(phi), then the plateau, plastic slip u_p = u - tau/k_s (1e-12);
// - loading with dilation at a constant normal jump v0: on f = 0 with v_p = tan(psi) u_p,
//   u_p = (k_s u + k_n v0 tan(phi) - c)/(k_s + k_n tan(phi) tan(psi)) (1e-10), the same after
//   one increment and after 40 (the return of a linear yield function is exact);
// - unloading: elastic with slope k_s from the slip state (3.59), then reverse sliding at
//   tau = -(c + p tan(phi)) (1e-12);
// - the associated tangent (3.60): K_ss = k_s k_n tan^2(phi)/H, K_nn = k_s k_n/H,
//   |K_sn| = k_s k_n tan(phi)/H, H = k_s + k_n tan^2(phi) (1e-12);
// - tension cut-off: sigma_t = 0 opens at any tension (zero traction and tangent, state open),
//   sigma_t > 0 carries k_n v up to sigma_t, then fails for good; reclosing gives compression
//   k_n (v - v_p) and shear from zero (1e-12);
// - the tangent against central differences of the update in every regime (1e-6 relative).
#include "coulomb_elastoplastic/coulomb_elastoplastic.hpp"

#include "scene/toml_check.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace test_coulomb_elastoplastic {

using namespace stratum;

namespace {

constexpr double deg = std::numbers::pi / 180.0;

/// The law created by the plugin from the body of a [contact_laws.x] table.
struct Loaded {
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::unique_ptr<ContactLaw> law;
};
std::unique_ptr<Loaded> load(const std::string& params) {
  auto l = std::make_unique<Loaded>();
  l->catalog = std::make_unique<PluginCatalog>(std::vector<std::string>{STRATUM_PLUGIN_DIR});
  l->catalog->require(l->registry, PluginKind::contact_law, "coulomb_elastoplastic");
  const auto& f = l->registry.contact_law("coulomb_elastoplastic");
  l->law = f.create(io::check_table(toml::parse(params), f.schema, "[contact_laws.i]"));
  return l;
}

/// One interface point driven by total jumps; go() commits.
struct Point {
  const ContactLaw& law;
  Vec2 traction = Vec2::Zero(), jump = Vec2::Zero();
  std::vector<double> h;
  Mat2 tangent = Mat2::Zero();

  explicit Point(const ContactLaw& l) : law(l), h(static_cast<std::size_t>(l.history_size())) {
    law.init_history(h);
  }
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
  }
  [[nodiscard]] ContactState state() const { return law.state(traction, h); }
  /// max |D - D_fd| / max(|D_fd|, k_ref) at the trial jump j, central differences with step e.
  [[nodiscard]] double fd_error(const Vec2& j, double k_ref, double e = 1e-9) const {
    Mat2 D;
    trial(j, &D);
    Mat2 fd;
    for (int c = 0; c < 2; ++c) {
      Vec2 jp = j, jm = j;
      jp[c] += e, jm[c] -= e;
      fd.col(c) = (trial(jp) - trial(jm)) / (2 * e);
    }
    return (D - fd).cwiseAbs().maxCoeff() / std::max(fd.cwiseAbs().maxCoeff(), k_ref);
  }
};

constexpr double ks = 2e4, kn = 1e5, c = 5.0; // kPa/m, kPa/m, kPa

} // namespace

TEST_CASE("coulomb_elastoplastic: elastic regime", "[plugins][coulomb_elastoplastic]") {
  auto l = load("k_s = 2e4\nk_n = 1e5\nc = 5.0\nphi = 30.0\npsi = 10.0");
  REQUIRE(l->law->history_size() == 4);
  CHECK_FALSE(l->law->symmetric_tangent()); // psi != phi
  Point pt(*l->law);
  const double p = 50.0, v = -p / kn;
  pt.go(Vec2(0.0, v));
  CHECK(pt.traction[1] == Approx(-p).epsilon(1e-14));
  // Shear below c + p tan(30) = 33.868 kPa: tau = k_s u.
  const double u = 0.8 * (c + p * std::tan(30 * deg)) / ks;
  pt.go(Vec2(u, v));
  CHECK(pt.traction[0] == Approx(ks * u).epsilon(1e-14));
  CHECK(pt.traction[1] == Approx(-p).epsilon(1e-14));
  CHECK(pt.state() == ContactState::stick);
  CHECK(pt.tangent(0, 0) == ks);
  CHECK(pt.tangent(1, 1) == kn);
  CHECK(pt.tangent(0, 1) == 0.0);
  CHECK(pt.tangent(1, 0) == 0.0);
  CHECK(pt.h[0] == 0.0); // no plastic slip
  CHECK(pt.fd_error(Vec2(0.9 * u, 1.1 * v), ks) < 1e-6);
}

TEST_CASE("coulomb_elastoplastic: direct shear at constant normal stress (C2), psi = 0",
          "[plugins][coulomb_elastoplastic]") {
  auto l = load("k_s = 2e4\nk_n = 1e5\nc = 5.0\nphi = 30.0");
  CHECK_FALSE(l->law->symmetric_tangent()); // psi = 0 != phi: C^EP is not symmetric while sliding
  for (const double p : {25.0, 50.0, 75.0}) {
    Point pt(*l->law);
    const double v = -p / kn, tmax = c + p * std::tan(30 * deg);
    pt.go(Vec2(0.0, v));
    for (int i = 1; i <= 40; ++i) {
      const double u = i * 1e-4; // to 4 mm; yield at tmax/k_s = 0.97, 1.69, 2.41 mm
      pt.go(Vec2(u, v));
      INFO("p = " << p << ", u = " << u);
      CHECK(pt.traction[0] == Approx(std::min(ks * u, tmax)).epsilon(1e-12));
      CHECK(pt.traction[1] == Approx(-p).epsilon(1e-12)); // no dilation: sigma stays k_n v
      CHECK(pt.h[0] == Approx(std::max(0.0, u - tmax / ks)).margin(1e-15));
      CHECK(pt.h[1] == 0.0);
      CHECK(pt.state() == (ks * u > tmax ? ContactState::slip : ContactState::stick));
    }
  }
}

TEST_CASE("coulomb_elastoplastic: sliding with dilation at a constant normal jump",
          "[plugins][coulomb_elastoplastic]") {
  auto l = load("k_s = 2e4\nk_n = 1e5\nc = 5.0\nphi = 30.0\npsi = 10.0");
  const double tp = std::tan(30 * deg), ts = std::tan(10 * deg);
  const double v0 = -50.0 / kn;
  auto up_exact = [&](double u) { return (ks * u + kn * v0 * tp - c) / (ks + kn * tp * ts); };
  // 40 increments and one increment to the same total jump.
  Point many(*l->law), one(*l->law);
  many.go(Vec2(0.0, v0));
  one.go(Vec2(0.0, v0));
  const double u_end = 0.02;
  for (int i = 1; i <= 40; ++i) {
    const double u = u_end * i / 40.0;
    many.go(Vec2(u, v0));
    const double up = std::max(0.0, up_exact(u));
    INFO("u = " << u);
    CHECK(many.h[0] == Approx(up).margin(1e-14).epsilon(1e-10));
    CHECK(many.h[1] == Approx(ts * up).margin(1e-14).epsilon(1e-10));
    CHECK(many.traction[0] == Approx(ks * (u - up)).epsilon(1e-10));
    CHECK(many.traction[1] == Approx(kn * (v0 - ts * up)).epsilon(1e-10));
  }
  one.go(Vec2(u_end, v0));
  CHECK(one.traction[0] == Approx(many.traction[0]).epsilon(1e-10));
  CHECK(one.traction[1] == Approx(many.traction[1]).epsilon(1e-10));
  // On the yield surface, and the normal stress grew by dilation.
  CHECK(std::abs(many.traction[0]) + many.traction[1] * tp - c == Approx(0.0).margin(1e-9));
  CHECK(-many.traction[1] > 50.0);
  CHECK(many.state() == ContactState::slip);
  // Non-associated tangent (3.56)-(3.57) against central differences while sliding on.
  CHECK(many.fd_error(Vec2(u_end + 1e-4, v0), ks) < 1e-6);
  CHECK(many.fd_error(Vec2(u_end + 1e-4, v0 - 1e-5), ks) < 1e-6);
}

TEST_CASE("coulomb_elastoplastic: unloading is elastic, then reverse sliding",
          "[plugins][coulomb_elastoplastic]") {
  auto l = load("k_s = 2e4\nk_n = 1e5\nc = 5.0\nphi = 30.0");
  const double p = 50.0, v = -p / kn, tmax = c + p * std::tan(30 * deg);
  Point pt(*l->law);
  pt.go(Vec2(0.0, v));
  const double u_peak = 4e-3;
  pt.go(Vec2(u_peak, v));
  REQUIRE(pt.state() == ContactState::slip);
  const double up = u_peak - tmax / ks;
  // Unloading (3.59: dW < 0): tau = tmax - k_s (u_peak - u), elastic tangent, over the elastic
  // range 2 tmax / k_s = 3.39 mm (30 decrements of 0.1 mm).
  for (int i = 1; i <= 30; ++i) {
    const double u = u_peak - i * 1e-4;
    pt.go(Vec2(u, v));
    INFO("u = " << u);
    CHECK(pt.traction[0] == Approx(tmax - ks * (u_peak - u)).margin(1e-12));
    CHECK(pt.h[0] == Approx(up).epsilon(1e-12));
    CHECK(pt.state() == ContactState::stick);
    CHECK(pt.tangent(0, 0) == ks);
    CHECK(pt.tangent(0, 1) == 0.0);
  }
  // Beyond it, reverse sliding on the plateau -tmax: u_p = u + tmax / k_s.
  pt.go(Vec2(0.0, v));
  CHECK(pt.traction[0] == Approx(-tmax).epsilon(1e-12));
  CHECK(pt.h[0] == Approx(tmax / ks).epsilon(1e-12));
  CHECK(pt.state() == ContactState::slip);
  CHECK(pt.fd_error(Vec2(u_peak - 4.1e-3, v), ks) < 1e-6); // reverse sliding, s = -1
  CHECK(pt.fd_error(Vec2(u_peak - 3.9e-3, v), ks) < 1e-6); // unloading from it: elastic
}

TEST_CASE("coulomb_elastoplastic: associated flow gives the (3.60) matrix",
          "[plugins][coulomb_elastoplastic]") {
  auto l = load("k_s = 2e4\nk_n = 1e5\nc = 5.0\nphi = 30.0\npsi = 30.0");
  CHECK(l->law->symmetric_tangent());
  const double t = std::tan(30 * deg), H = ks + kn * t * t;
  for (const double sign : {1.0, -1.0}) {
    Point pt(*l->law);
    pt.go(Vec2(0.0, -50.0 / kn));
    pt.go(Vec2(sign * 0.01, -50.0 / kn));
    REQUIRE(pt.state() == ContactState::slip);
    CHECK(pt.tangent(0, 0) == Approx(ks * kn * t * t / H).epsilon(1e-12));
    CHECK(pt.tangent(1, 1) == Approx(ks * kn / H).epsilon(1e-12));
    CHECK(pt.tangent(0, 1) == Approx(-sign * ks * kn * t / H).epsilon(1e-12));
    CHECK(pt.tangent(1, 0) == Approx(pt.tangent(0, 1)).epsilon(1e-12));
    CHECK(pt.fd_error(Vec2(sign * 0.011, -50.0 / kn), ks) < 1e-6);
  }
}

TEST_CASE("coulomb_elastoplastic: tension cut-off, opening and reclosing",
          "[plugins][coulomb_elastoplastic]") {
  SECTION("sigma_t = 0: no tension at all") {
    auto l = load("k_s = 2e4\nk_n = 1e5\nc = 5.0\nphi = 30.0");
    Point pt(*l->law);
    pt.go(Vec2(1e-4, 1e-5)); // any opening
    CHECK(pt.traction.norm() == 0.0);
    CHECK(pt.tangent.norm() == 0.0);
    CHECK(pt.state() == ContactState::open);
    CHECK(pt.h[0] == 1e-4); // the faces slide freely: the whole slip is plastic
    CHECK(pt.fd_error(Vec2(2e-4, 2e-5), ks) < 1e-6);
    // Reclosing: compression k_n v, shear counted from the slip at which the faces touched.
    pt.go(Vec2(1.5e-4, -3e-4));
    CHECK(pt.traction[1] == Approx(-kn * 3e-4).epsilon(1e-12));
    CHECK(pt.traction[0] == Approx(ks * 0.5e-4).epsilon(1e-12));
    CHECK(pt.state() == ContactState::stick);
  }
  SECTION("sigma_t > 0: tension carried up to sigma_t, then lost for good") {
    auto l = load("k_s = 2e4\nk_n = 1e5\nc = 5.0\nphi = 30.0\nsigma_t = 10.0");
    Point pt(*l->law);
    pt.go(Vec2(0.0, 5.0 / kn));
    CHECK(pt.traction[1] == Approx(5.0).epsilon(1e-14)); // intact: k_n v in tension
    CHECK(pt.state() == ContactState::stick);
    CHECK(pt.h[2] == 0.0);
    // At 5 kPa tension the shear strength is c - 5 tan(30) = 2.113 kPa.
    pt.go(Vec2(1e-3, 5.0 / kn));
    CHECK(std::abs(pt.traction[0]) == Approx(c - 5.0 * std::tan(30 * deg)).epsilon(1e-12));
    pt.go(Vec2(1e-3, 10.5 / kn)); // beyond sigma_t
    CHECK(pt.traction.norm() == 0.0);
    CHECK(pt.state() == ContactState::open);
    CHECK(pt.h[2] == 1.0);
    // After the cut-off no tension: 5 kPa worth of opening is open now.
    pt.go(Vec2(1e-3, 5.0 / kn));
    CHECK(pt.traction.norm() == 0.0);
    CHECK(pt.state() == ContactState::open);
    // Reclosed: compression again.
    pt.go(Vec2(1e-3, -20.0 / kn));
    CHECK(pt.traction[1] == Approx(-20.0 - kn * pt.h[1]).epsilon(1e-12));
    CHECK(pt.state() == ContactState::stick);
  }
}

} // namespace test_coulomb_elastoplastic
