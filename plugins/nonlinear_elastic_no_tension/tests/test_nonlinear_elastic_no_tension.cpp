// Tests of the `nonlinear_elastic_no_tension` material, created through the plugin from TOML
// parameters, one regime at a time (README: K_t = A p_a (p/p_a)^n (2.18), G_t = B p_a (p/p_a)^m
// (2.19), principal stresses above T set to T after every substep; tension positive):
// - elastic, isotropic compression and back (loading and unloading of the hypoelastic law):
//   p^(1-n) = p0^(1-n) + (1-n) A p_a^(1-n) eps_v for n = 0, 1/4, 1/2 (1e-6 relative; n = 0 is
//   linear, 1e-12), and p0 again after the reverse strain;
// - elastic, simple shear at constant p: tau_xy = G(p0) gamma (1e-12), the mean stress unchanged;
// - the tangent at a zero increment is D(K_t(p0), G_t(p0)) = K 1x1 + 2G (I - 1x1/3) (1e-6), and
//   the tangent of finite increments matches central differences of the update (1e-5);
// - tension cut-off with constant moduli (n = m = 0): uniaxial and biaxial extension from
//   -p0 (isotropic): sigma_i = min(T, -p0 + sum_j D_ij eps_j) for T = 0 and T = 5 kPa (1e-10),
//   cut-off in 1, 2 and 3 directions with point_status 1, 2, 3, and the tangent rows of a cut
//   direction zero while the others are D's (1e-6);
// - a non-finite strain increment is a status (non_finite), not an exception.
#include "scene/toml_check.hpp"
#include "stratum/material.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace test_nonlinear_elastic_no_tension { // one namespace per test file: the test files build in batches
                                              // (unity)

using namespace stratum;

namespace {

struct Loaded {
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::unique_ptr<Material> m;
};
std::unique_ptr<Loaded> load(const std::string& params) {
  auto l = std::make_unique<Loaded>();
  l->catalog = std::make_unique<PluginCatalog>(std::vector<std::string>{STRATUM_PLUGIN_DIR});
  l->catalog->require(l->registry, PluginKind::material, "nonlinear_elastic_no_tension");
  const auto& f = l->registry.material("nonlinear_elastic_no_tension");
  l->m = f.create(io::check_table(toml::parse(params), f.schema, "[materials.rock]"));
  return l;
}

struct Result {
  Outcome o;
  Vec6 stress;
  Mat6 tangent;
};
Result update(const Material& m, const Vec6& s, const Vec6& de) {
  Result r;
  std::vector<double> h(static_cast<std::size_t>(m.history_size()));
  std::vector<double> hn(h.size());
  const Vec6 e = Vec6::Zero();
  MaterialOutput out{r.stress, hn, r.tangent};
  r.o = m.update(MaterialInput{s, e, h, de, {0, 0}}, out);
  return r;
}

Vec6 iso(double p) { return (Vec6() << -p, -p, -p, 0, 0, 0).finished(); }
Vec6 strain(double xx, double yy, double zz, double xy = 0, double yz = 0, double zx = 0) {
  return (Vec6() << xx, yy, zz, xy, yz, zx).finished();
}

/// The isotropic tangent written out: K 1x1 + 2G (I - 1x1/3), engineering shears.
Mat6 D_of(double K, double G) {
  Mat6 D = Mat6::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) D(i, j) = K + 2.0 * G * ((i == j ? 1.0 : 0.0) - 1.0 / 3.0);
  for (int i = 3; i < 6; ++i) D(i, i) = G;
  return D;
}

/// max |tangent - central differences (step 1e-6) of the update| / max |tangent|.
double fd_error(const Material& m, const Vec6& s, const Vec6& de) {
  const Result base = update(m, s, de);
  REQUIRE(base.o.ok());
  Mat6 fd;
  const double h = 1e-6;
  for (int j = 0; j < 6; ++j) {
    Vec6 dp = de, dm = de;
    dp[j] += h;
    dm[j] -= h;
    fd.col(j) = (update(m, s, dp).stress - update(m, s, dm).stress) / (2 * h);
  }
  return (base.tangent - fd).cwiseAbs().maxCoeff() / base.tangent.cwiseAbs().maxCoeff();
}

constexpr double A = 400.0, B = 200.0, pa = 100.0;

} // namespace

TEST_CASE("nonlinear_elastic_no_tension: isotropic compression and unloading follow (2.18)",
          "[plugins][nonlinear_elastic_no_tension]") {
  const double p0 = 50.0, ev = 0.01;
  for (const double n : {0.0, 0.25, 0.5}) {
    auto l = load("A = 400.0\nn = " + std::to_string(n) + "\nB = 200.0\nm = 0.5\nmax_substep_strain = 1e-6");
    const double p_exact =
        std::pow(std::pow(p0, 1 - n) + (1 - n) * A * std::pow(pa, 1 - n) * ev, 1.0 / (1 - n));
    const Result r = update(*l->m, iso(p0), strain(-ev / 3, -ev / 3, -ev / 3));
    REQUIRE(r.o.ok());
    INFO("n = " << n << ": p = " << -r.stress[0] << ", closed form " << p_exact);
    for (int i = 0; i < 3; ++i) CHECK(-r.stress[i] == Approx(p_exact).epsilon(n == 0.0 ? 1e-12 : 1e-6));
    for (int i = 3; i < 6; ++i) CHECK(r.stress[i] == 0.0);
    CHECK(l->m->point_status(r.stress, {}) == 0);
    // Unloading by the same strain: the hypoelastic law is reversible along the isotropic axis.
    const Result back = update(*l->m, r.stress, strain(ev / 3, ev / 3, ev / 3));
    REQUIRE(back.o.ok());
    CHECK(-back.stress[0] == Approx(p0).epsilon(n == 0.0 ? 1e-12 : 1e-6));
  }
  // The worked case of the plugin's README: n = 1/2 gives 732.843 kPa.
  CHECK(std::pow(std::sqrt(p0) + 0.5 * A * std::sqrt(pa) * ev, 2.0) == Approx(732.843).epsilon(1e-6));
}

TEST_CASE("nonlinear_elastic_no_tension: simple shear at constant mean stress, tau = G(p) gamma",
          "[plugins][nonlinear_elastic_no_tension]") {
  auto l = load("A = 400.0\nn = 0.5\nB = 200.0\nm = 0.4");
  const double p0 = 80.0, G = B * pa * std::pow(p0 / pa, 0.4);
  const double gamma = 0.5 * p0 / G; // tau = p0/2: the principal stresses -p0 -+ tau stay compressive
  const Result r = update(*l->m, iso(p0), strain(0, 0, 0, gamma));
  REQUIRE(r.o.ok());
  CHECK(r.stress[3] == Approx(G * gamma).epsilon(1e-12));
  for (int i = 0; i < 3; ++i) CHECK(r.stress[i] == Approx(-p0).epsilon(1e-12));
  CHECK(r.stress[4] == 0.0);
  CHECK(r.stress[5] == 0.0);
}

TEST_CASE("nonlinear_elastic_no_tension: the tangent", "[plugins][nonlinear_elastic_no_tension]") {
  auto l = load("A = 400.0\nn = 0.5\nB = 200.0\nm = 0.4");
  CHECK_FALSE(l->m->symmetric_tangent());
  // At a zero increment: the hypoelastic D of the start state (one Heun substep has the derivative
  // (D(s0) + D(s0))/2 at de = 0). p = 60 kPa from a non-isotropic stress.
  const Vec6 s = (Vec6() << -50.0, -80.0, -50.0, 10.0, 0.0, 0.0).finished();
  const double p = 60.0, K = A * pa * std::pow(p / pa, 0.5), G = B * pa * std::pow(p / pa, 0.4);
  const Result r0 = update(*l->m, s, Vec6::Zero());
  REQUIRE(r0.o.ok());
  const Mat6 D = D_of(K, G);
  CHECK((r0.tangent - D).cwiseAbs().maxCoeff() < 1e-6 * D.cwiseAbs().maxCoeff());
  // Finite increments (loading and unloading, a general direction): central differences. The
  // largest component, 5.3e-4, keeps its 6 substeps of at most 1e-4 under the +-1e-6 differences.
  const Vec6 g = strain(-2.3e-4, -5.3e-4, -1.1e-4, 1.3e-4, 5e-5, -3e-5);
  CHECK(fd_error(*l->m, s, g) < 1e-5);
  CHECK(fd_error(*l->m, s, Vec6(-g)) < 1e-5);
}

TEST_CASE("nonlinear_elastic_no_tension: tension cut-off in one, two and three directions",
          "[plugins][nonlinear_elastic_no_tension]") {
  // Constant moduli (n = m = 0): K = A p_a = 40 MPa, G = B p_a = 20 MPa, so before any cut
  // sigma = -p0 + D eps, and each cut direction stays at T while the others go on (the principal
  // axes are the coordinate axes throughout).
  const double p0 = 50.0, K = A * pa, G = B * pa;
  const Mat6 D = D_of(K, G);
  for (const double T : {0.0, 5.0}) {
    auto l = load("A = 400.0\nn = 0.0\nB = 200.0\nm = 0.0\ntensile_strength = " + std::to_string(T));
    CHECK(l->m->status_names() == std::vector<std::string>{"elastic", "cut off in one direction",
                                                           "cut off in two directions",
                                                           "cut off in all directions"});
    auto expect = [&](const Vec6& de) {
      Vec6 s = iso(p0) + D * de;
      for (int i = 0; i < 3; ++i) s[i] = std::min(s[i], T);
      return s;
    };
    struct Case {
      Vec6 de;
      int status;
    };
    // Uniaxial extension in y: sigma_yy reaches T at eps = (p0 + T)/(K + 4G/3) = 8.0e-4 (T = 0);
    // the lateral stresses at (p0 + T)/(K - 2G/3) = 1.9e-3.
    // Biaxial extension in x and y: sigma_xx = sigma_yy = -p0 + (2K + 2G/3) eps reach T first
    // (eps = 5.4e-4), sigma_zz = -p0 + 2 (K - 2G/3) eps at eps = 9.4e-4.
    const std::vector<Case> cases{{strain(0, 5e-4, 0), 0},    {strain(0, 1.5e-3, 0), 1},
                                  {strain(0, 4e-3, 0), 3},    {strain(7.5e-4, 7.5e-4, 0), 2},
                                  {strain(4e-3, 4e-3, 0), 3}, {strain(3e-3, 3e-3, 3e-3), 3}};
    for (const Case& c : cases) {
      const Result r = update(*l->m, iso(p0), c.de);
      REQUIRE(r.o.ok());
      const Vec6 e = expect(c.de);
      INFO("T = " << T << ", de = " << c.de.transpose() << ": stress " << r.stress.transpose()
                  << ", expected " << e.transpose());
      CHECK((r.stress - e).cwiseAbs().maxCoeff() < 1e-10 * p0);
      CHECK(l->m->point_status(r.stress, {}) == c.status);
      // Tangent: a direction strictly beyond the cut has a zero row in the normal block; the others
      // keep D's rows there.
      const Vec6 trial = iso(p0) + D * c.de;
      for (int i = 0; i < 3; ++i) {
        const bool cut = trial[i] > T + 1.0; // 1 kPa beyond: the central difference stays cut
        const bool near = std::abs(trial[i] - T) < 1.0;
        if (near) continue;
        for (int j = 0; j < 3; ++j) {
          INFO("row " << i << ", column " << j);
          CHECK(r.tangent(i, j) == Approx(cut ? 0.0 : D(i, j)).margin(1e-6 * D(0, 0)));
        }
      }
    }
  }
}

TEST_CASE("nonlinear_elastic_no_tension: a non-finite increment is a status",
          "[plugins][nonlinear_elastic_no_tension]") {
  auto l = load("A = 400.0\nn = 0.5\nB = 200.0\nm = 0.5");
  Result r;
  REQUIRE_NOTHROW(r = update(*l->m, iso(50.0), strain(std::numeric_limits<double>::quiet_NaN(), 0, 0)));
  CHECK(r.o.status == Status::non_finite);
  CHECK(r.o.message.find("nonlinear_elastic_no_tension") != std::string::npos);
}

} // namespace test_nonlinear_elastic_no_tension
