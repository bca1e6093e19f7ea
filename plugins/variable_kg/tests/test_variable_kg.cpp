// Tests of the `variable_kg` material (the K_t/G_t form of the Duncan-Chang hyperbola), created
// through the plugin from TOML parameters (the loess set (a) of the thesis with nu = 0.3), one
// regime at a time against closed forms of the README (compression positive inside):
//   E_i = K p_a (sigma_3/p_a)^n,  q_f = 2 (c cos phi + sigma_3 sin phi)/(1 - sin phi),  S = q/q_f,
//   loading K_t = E_i/(3(1 - 2 nu)), G_t = E_i (1 - R_f S)^2/(2(1 + nu)); unloading both from
//   E_ur = K_ur p_a (sigma_3/p_a)^n; failed (S >= 1): G from residual E_i; tension cut-off.
// - loading, drained triaxial at constant sigma_3: fed the closed-form strain path
//   eps_v = q/(3 K_t), eps_a = q/(9 K_t) + 2 (1 + nu) q/(3 E_i (1 - R_f q/q_f)), the update returns
//   sigma_3 constant and the deviator q (1e-4 relative), up to 0.9 q_f;
// - loading, isotropic compression and extension (S = 0 stays the maximum, so the loading K from
//   E_i applies both ways): p^(1-n) = p0^(1-n) + (1-n) K p_a^(1-n) eps_v/(3(1-2nu)), reached at
//   second order in the substep (error ratio 4 +- 0.5 on halving, below 2e-5 relative), the floor
//   sigma_3 = 0.01 p_a (then linear, 1e-5 p0), the tension cut-off at p = 0 (exact zero);
// - unloading: a uniaxial-stress increment (lateral strain -nu times the axial) from S = 0.5
//   changes only the axial stress, by E_ur d eps (1e-9);
// - tangents at a zero increment in closed form: D(K_t, G_t) loading, D(E_ur, nu) unloading,
//   G = residual E_i / (2(1 + nu)) failed (1e-6); finite increments against central differences of
//   the update, loading and unloading (1e-5);
// - point_status: 0 below failure, 1 failed (S >= 0.99), 2 tension cut-off.
#include "scene/toml_check.hpp"
#include "stratum/material.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace test_variable_kg {

using namespace stratum;

namespace {

const std::string loess_a = "K = 500.0\nn = 0.82\nR_f = 0.8\nphi = 26.0\nc = 10.0\nK_ur = 800.0\nnu = 0.3\n";
constexpr double Kn = 500.0, n = 0.82, Rf = 0.8, phi_deg = 26.0, coh = 10.0, Kur = 800.0, nu = 0.3,
                 pa = 100.0;

struct Loaded {
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::unique_ptr<Material> m;
};
std::unique_ptr<Loaded> load(const std::string& extra = "") {
  auto l = std::make_unique<Loaded>();
  l->catalog = std::make_unique<PluginCatalog>(std::vector<std::string>{STRATUM_PLUGIN_DIR});
  l->catalog->require(l->registry, PluginKind::material, "variable_kg");
  const auto& f = l->registry.material("variable_kg");
  l->m = f.create(io::check_table(toml::parse(loess_a + extra), f.schema, "[materials.loess]"));
  return l;
}

// Closed forms (compression positive).
double E_i(double s3) { return Kn * pa * std::pow(s3 / pa, n); }
double E_ur(double s3) { return Kur * pa * std::pow(s3 / pa, n); }
double q_f(double s3) {
  const double phi = phi_deg * std::numbers::pi / 180.0;
  return 2.0 * (coh * std::cos(phi) + s3 * std::sin(phi)) / (1.0 - std::sin(phi));
}
Mat6 D_of(double K, double G) {
  Mat6 D = Mat6::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) D(i, j) = K + 2.0 * G * ((i == j ? 1.0 : 0.0) - 1.0 / 3.0);
  for (int i = 3; i < 6; ++i) D(i, i) = G;
  return D;
}

struct Result {
  Outcome o;
  Vec6 stress;
  Mat6 tangent;
  std::vector<double> h;
};
Result update(const Material& m, const Vec6& s, const std::vector<double>& h, const Vec6& de) {
  Result r;
  r.h.assign(h.size(), 0.0);
  const Vec6 e = Vec6::Zero();
  MaterialOutput out{r.stress, r.h, r.tangent};
  r.o = m.update(MaterialInput{s, e, h, de, {0, 0}}, out);
  return r;
}
std::vector<double> virgin(const Material& m, const Vec6& s) {
  std::vector<double> h(static_cast<std::size_t>(m.history_size()));
  m.init_history(s, h);
  return h;
}
/// History of a point that has reached stress level S_max at deviator q_max (F_sr memory).
std::vector<double> memory(const Material& m, double S_max, double q_max) {
  std::vector<double> h(static_cast<std::size_t>(m.history_size()), 0.0);
  h[0] = S_max;
  h[1] = q_max;
  return h;
}
/// Tension-positive stress: lateral -s3 (x, z), axial -(s3 + q) (y), and sigma_zz moved by dz.
Vec6 triaxial(double s3, double q, double dz = 0.0) {
  return (Vec6() << -s3, -(s3 + q), -s3 - dz, 0, 0, 0).finished();
}
double fd_error(const Material& m, const Vec6& s, const std::vector<double>& h, const Vec6& de) {
  const Result base = update(m, s, h, de);
  REQUIRE(base.o.ok());
  Mat6 fd;
  const double step = 1e-6;
  for (int j = 0; j < 6; ++j) {
    Vec6 dp = de, dm = de;
    dp[j] += step;
    dm[j] -= step;
    fd.col(j) = (update(m, s, h, dp).stress - update(m, s, h, dm).stress) / (2 * step);
  }
  return (base.tangent - fd).cwiseAbs().maxCoeff() / base.tangent.cwiseAbs().maxCoeff();
}

} // namespace

TEST_CASE("variable_kg: loading on a drained triaxial path (closed-form strain path in, stresses out)",
          "[plugins][variable_kg]") {
  auto l = load("max_substep_strain = 1e-5\n");
  const double s3 = 100.0, Ei = E_i(s3), Kt = Ei / (3.0 * (1.0 - 2.0 * nu)), qf = q_f(s3);
  // Guard on the closed form: q_f = 188.1 kPa, E_i = 50 MPa at sigma_3 = p_a.
  CHECK(qf == Approx(2.0 * (10.0 * 0.898794 + 100.0 * 0.438371) / (1.0 - 0.438371)).epsilon(1e-6));
  CHECK(Ei == 50000.0);
  auto strains = [&](double q) { // tension positive: (lateral, axial, lateral)
    const double ev = q / (3.0 * Kt);
    const double ea = q / (9.0 * Kt) + 2.0 * (1.0 + nu) * q / (3.0 * Ei * (1.0 - Rf * q / qf));
    const double er = 0.5 * (ev - ea);
    return (Vec6() << -er, -ea, -er, 0, 0, 0).finished();
  };
  Vec6 s = triaxial(s3, 0.0);
  std::vector<double> h = virgin(*l->m, s);
  const int N = 400;
  double worst_q = 0.0, worst_s3 = 0.0;
  for (int k = 1; k <= N; ++k) {
    const double q0 = 0.9 * qf * (k - 1) / N, q1 = 0.9 * qf * k / N;
    const Result r = update(*l->m, s, h, strains(q1) - strains(q0));
    REQUIRE(r.o.ok());
    s = r.stress, h = r.h;
    worst_q = std::max(worst_q, std::abs((-s[1] - s3) - q1) / q1);
    worst_s3 = std::max({worst_s3, std::abs(-s[0] - s3) / s3, std::abs(-s[2] - s3) / s3});
  }
  INFO("worst relative deviator error " << worst_q << ", lateral stress error " << worst_s3);
  CHECK(worst_q < 1e-4);
  CHECK(worst_s3 < 1e-4);
  CHECK(h[0] == Approx(0.9).epsilon(1e-4)); // S_max remembered
  CHECK(l->m->point_status(s, h) == 0);
}

TEST_CASE("variable_kg: isotropic compression and extension, sigma_3 floor and tension cut-off",
          "[plugins][variable_kg]") {
  const double A = Kn / (3.0 * (1.0 - 2.0 * nu)); // K_t = A p_a (p/p_a)^n on the isotropic axis
  auto p_of = [&](double p0, double ev) {         // ev compression positive, above the floor
    return std::pow(std::pow(p0, 1 - n) + (1 - n) * A * std::pow(pa, 1 - n) * ev, 1.0 / (1 - n));
  };
  auto run = [&](const Material& m, double p0, double ev) {
    const Vec6 s = triaxial(p0, 0.0);
    const Result r = update(m, s, virgin(m, s), (Vec6() << -ev / 3, -ev / 3, -ev / 3, 0, 0, 0).finished());
    REQUIRE(r.o.ok());
    CHECK(r.stress[0] == Approx(r.stress[1]).epsilon(1e-14));
    CHECK(r.stress[1] == Approx(r.stress[2]).epsilon(1e-14));
    return r;
  };
  // Compression from 100 kPa by 0.2 % (p = 217.375 kPa) and extension from 20 kPa by 0.2 %
  // (p = 5.773 kPa): Heun's substeps converge to the closed form at second order, the error falls
  // by 4 (3.5-4.5) when the substep is halved, and is below 2e-5 at substeps of 5e-6.
  auto fine = load("max_substep_strain = 5e-6\n"), coarse = load("max_substep_strain = 1e-5\n");
  for (const auto& [p0, ev] : {std::pair{100.0, 0.002}, std::pair{20.0, -0.002}}) {
    const double exact = p_of(p0, ev);
    const double err_fine = std::abs(-run(*fine->m, p0, ev).stress[0] - exact) / exact;
    const double err_coarse = std::abs(-run(*coarse->m, p0, ev).stress[0] - exact) / exact;
    INFO("p0 = " << p0 << ", eps_v = " << ev << ": p = " << exact << ", errors " << err_coarse << ", "
                 << err_fine);
    CHECK(err_fine < 2e-5);
    CHECK(err_coarse / err_fine == Approx(4.0).margin(0.5));
  }
  CHECK(p_of(100.0, 0.002) == Approx(217.375).epsilon(1e-5));
  // Extension from 20 kPa down the power law to the floor p = 0.01 p_a = 1 kPa at
  // ev_floor = (1 - 20^(1-n)) / ((1-n) A p_a^(1-n)) = -4.157e-3, then linear with K at the floor
  // (to 1e-5 p0: the error of the power-law part carried along), then cut off at p = 0 (exact).
  const double p0 = 20.0, floor = 0.01 * pa;
  const double ev_floor =
      (std::pow(floor, 1 - n) - std::pow(p0, 1 - n)) / ((1 - n) * A * std::pow(pa, 1 - n));
  const double K_floor = A * pa * std::pow(floor / pa, n);
  CHECK(ev_floor == Approx(-4.157e-3).epsilon(1e-3));
  const Result e1 = run(*fine->m, p0, -0.002);
  CHECK(fine->m->point_status(e1.stress, e1.h) == 0);
  const Result e2 = run(*fine->m, p0, ev_floor - 0.5 / K_floor); // halfway from the floor to zero stress
  CHECK(-e2.stress[0] == Approx(0.5).margin(1e-5 * p0));
  const Result e3 = run(*fine->m, p0, ev_floor - 2.0 / K_floor); // beyond zero stress: cut off
  for (int i = 0; i < 6; ++i) CHECK(e3.stress[i] == Approx(0.0).margin(1e-12));
  CHECK(fine->m->point_status(e3.stress, e3.h) == 2);
}

TEST_CASE("variable_kg: unloading with E_ur (uniaxial stress increment at constant sigma_3)",
          "[plugins][variable_kg]") {
  auto l = load();
  const double s3 = 100.0, q = 0.5 * q_f(s3), d = 5e-4; // axial unloading strain (extension)
  const Vec6 s = triaxial(s3, q);
  const Vec6 de = (Vec6() << -nu * d, d, -nu * d, 0, 0, 0).finished();
  const Result r = update(*l->m, s, memory(*l->m, 0.5, q), de);
  REQUIRE(r.o.ok());
  INFO("stress change " << (r.stress - s).transpose());
  CHECK(r.stress[1] - s[1] == Approx(E_ur(s3) * d).epsilon(1e-9)); // 40 kPa less deviator
  CHECK(r.stress[0] == Approx(s[0]).epsilon(1e-12));
  CHECK(r.stress[2] == Approx(s[2]).epsilon(1e-12));
  CHECK(r.h[0] == Approx(0.5).epsilon(1e-12)); // the memory keeps the maximum
}

TEST_CASE("variable_kg: tangents in closed form and against central differences", "[plugins][variable_kg]") {
  auto l = load();
  CHECK_FALSE(l->m->symmetric_tangent());
  const double s3 = 100.0, qf = q_f(s3), Ei = E_i(s3);
  // sigma_2 between sigma_3 and sigma_1 (at sigma_2 = sigma_3 the minor principal stress has a kink).
  const double q = 0.5 * qf, S = 0.5;
  const Vec6 s = triaxial(s3, q, 0.3 * q);
  SECTION("loading: K from E_i, G from E_t") {
    const Result r = update(*l->m, s, memory(*l->m, S, q), Vec6::Zero());
    REQUIRE(r.o.ok());
    const double Et = Ei * (1.0 - Rf * S) * (1.0 - Rf * S);
    const Mat6 D = D_of(Ei / (3.0 * (1.0 - 2.0 * nu)), Et / (2.0 * (1.0 + nu)));
    CHECK((r.tangent - D).cwiseAbs().maxCoeff() < 1e-6 * D.cwiseAbs().maxCoeff());
    const Vec6 de = (Vec6() << 2.3e-5, -7.7e-5, 1.3e-5, 1e-5, -5e-6, 3e-6).finished();
    CHECK(fd_error(*l->m, s, memory(*l->m, S, q), de) < 1e-5);
    CHECK(l->m->point_status(s, {}) == 0);
  }
  SECTION("unloading: both moduli from E_ur") {
    const Result r = update(*l->m, s, memory(*l->m, 0.7, 1.4 * q), Vec6::Zero());
    REQUIRE(r.o.ok());
    const double Eu = E_ur(s3);
    const Mat6 D = D_of(Eu / (3.0 * (1.0 - 2.0 * nu)), Eu / (2.0 * (1.0 + nu)));
    CHECK((r.tangent - D).cwiseAbs().maxCoeff() < 1e-6 * D.cwiseAbs().maxCoeff());
    const Vec6 de = (Vec6() << -2.3e-5, 7.7e-5, -1.3e-5, 1e-5, -5e-6, 3e-6).finished();
    CHECK(fd_error(*l->m, s, memory(*l->m, 0.7, 1.4 * q), de) < 1e-5);
  }
  SECTION("failed: G from the residual modulus 1e-3 E_i") {
    const Vec6 sf = triaxial(s3, 1.02 * qf, 0.3 * qf);
    const Result r = update(*l->m, sf, memory(*l->m, 1.02, 1.02 * qf), Vec6::Zero());
    REQUIRE(r.o.ok());
    const Mat6 D = D_of(Ei / (3.0 * (1.0 - 2.0 * nu)), 1e-3 * Ei / (2.0 * (1.0 + nu)));
    CHECK((r.tangent - D).cwiseAbs().maxCoeff() < 1e-6 * D.cwiseAbs().maxCoeff());
    CHECK(l->m->point_status(sf, {}) == 1);
    CHECK(l->m->point_status(triaxial(s3, 0.995 * qf), {}) == 1); // S >= 0.99 counts as failed
    CHECK(l->m->point_status(triaxial(s3, 0.985 * qf), {}) == 0);
  }
}

TEST_CASE("variable_kg: axial extension ends at the tension cut-off", "[plugins][variable_kg]") {
  auto l = load();
  Vec6 s = triaxial(20.0, 0.0);
  std::vector<double> h = virgin(*l->m, s);
  const Vec6 de = (Vec6() << -0.0005, 0.003, -0.0005, 0, 0, 0).finished();
  for (int k = 0; k < 5; ++k) {
    const Result r = update(*l->m, s, h, de);
    REQUIRE(r.o.ok());
    s = r.stress, h = r.h;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(
        (Eigen::Matrix3d() << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2]).finished());
    CHECK(es.eigenvalues()[2] <= 1e-12); // never tensile
  }
  CHECK(s[1] == Approx(0.0).margin(1e-12)); // the axial stress pulled to zero, not beyond
  CHECK(s[0] < 0.0);
  CHECK(l->m->point_status(s, h) == 2);
  CHECK(l->m->status_names() ==
        std::vector<std::string>{"below failure", "failed (S >= 0.99)", "tension cut-off"});
}

} // namespace test_variable_kg
