// Tests of the hyperbolic hypoelastic materials (plugins/duncan_chang, plugins/variable_kg) and the
// nonlinear elastic no-tension material (plugins/nonlinear_elastic_no_tension):
// - M6 of docs/verification.md: the drained triaxial path reproduces Kondner's hyperbola (2.26);
// - the author's stress recovery (4.46)-(4.49) against fine-step incremental integration;
// - unloading with E_ur (2.40) and the F_sr criterion (4.50), including a case where the
//   maximum-deviator criterion decides the other way;
// - the rule between the loess parameter sets (digest §9.4) and its TOML form;
// - tension and failure regimes; finite-difference checks of every tangent.
#include "duncan_chang/duncan_chang_schema.hpp"
#include "nonlinear_elastic_no_tension/nonlinear_elastic_no_tension.hpp"

#include "scene/toml_check.hpp"
#include "stratum/elasticity.hpp"
#include "stratum/point_driver.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#ifdef STRATUM_DUNCAN_CHANG_VERBOSE
#define REPORT(msg) WARN(msg)
#else
#define REPORT(msg) INFO(msg)
#endif

namespace test_duncan_chang {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace dc = stratum::duncan_chang;
namespace ne = stratum::nonlinear_elastic;

// The loess sets of the thesis (digest §9.4): (a) sigma_3 <= 100 kPa, (b) sigma_3 >= 200 kPa.
dc::Set loess_a() {
  dc::Set s;
  s.K = 500, s.n = 0.82, s.R_f = 0.80, s.phi = 26, s.c = 10, s.K_ur = 800, s.G = 0.18, s.F = 0.22, s.d = 20;
  return s;
}
dc::Set loess_b() {
  dc::Set s;
  s.K = 70, s.n = 0.82, s.R_f = 0.80, s.phi = 20, s.c = 40, s.K_ur = 350, s.G = 0.18, s.F = 0.22, s.d = 14;
  return s;
}

dc::Constants constants(dc::Update u = dc::Update::incremental, dc::Form f = dc::Form::E_nu) {
  dc::Constants c;
  c.form = f;
  c.update = u;
  c.sets = {loess_a()};
  return c;
}

// Closed forms of M6 at constant sigma_3 (compression positive).
double q_f(const dc::Set& s, double s3) {
  const double phi = s.phi * std::numbers::pi / 180.0;
  return 2.0 * (s.c * std::cos(phi) + s3 * std::sin(phi)) / (1.0 - std::sin(phi));
}
double E_i(const dc::Set& s, double s3) { return s.K * 100.0 * std::pow(s3 / 100.0, s.n); }
double hyperbola(const dc::Set& s, double s3, double eps) {
  return eps / (1.0 / E_i(s, s3) + s.R_f * eps / q_f(s, s3));
}

// A point file for one drained triaxial path of the duncan_chang material.
std::string point_file(const std::string& material, double s3, double axial, int steps) {
  std::ostringstream o;
  o << "[material]\nmodel = \"duncan_chang\"\n"
    << material << "\n[initial]\np = " << s3
    << "\n[[paths]]\ntype = \"triaxial_drained\"\naxial_strain = " << -axial << "\nsteps = " << steps << "\n";
  return o.str();
}
const std::string loess_a_toml = "K = 500\nn = 0.82\nR_f = 0.8\nphi = 26\nc = 10\nK_ur = 800\nG = 0.18\n"
                                 "F = 0.22\nd = 20\n";

stratum::PointRun run_point(const std::string& text) {
  auto d = stratum::PointDriver::from_string(text, "dc.toml", {STRATUM_PLUGIN_DIR});
  return d->run();
}
// Compression-positive axial strain, radial stress, deviator and lateral expansion of a row.
double eps_a(const stratum::PointRow& r) { return -r.strain[1]; }
double eps_r(const stratum::PointRow& r) { return r.strain[0]; }
double q_of(const stratum::PointRow& r) { return r.stress[0] - r.stress[1]; }

// One material update from a given state.
struct Result {
  stratum::Outcome o;
  Vec6 stress;
  Mat6 tangent;
  std::vector<double> h;
};
Result update(const stratum::Material& m, const Vec6& s, const Vec6& e, const std::vector<double>& h,
              const Vec6& de) {
  Result r;
  r.h.assign(h.size(), 0.0);
  stratum::MaterialOutput out{r.stress, r.h, r.tangent};
  r.o = m.update(stratum::MaterialInput{s, e, h, de, {0, 0}}, out);
  return r;
}

// Central differences (step 1e-6) of the update's stress in all six strain directions.
Mat6 fd_tangent(const stratum::Material& m, const Vec6& s, const Vec6& e, const std::vector<double>& h,
                const Vec6& de) {
  Mat6 fd;
  const double step = 1e-6;
  for (int j = 0; j < 6; ++j) {
    Vec6 dp = de, dm = de;
    dp[j] += step;
    dm[j] -= step;
    fd.col(j) = (update(m, s, e, h, dp).stress - update(m, s, e, h, dm).stress) / (2.0 * step);
  }
  return fd;
}

// Largest |tangent - central difference of the update| relative to the largest tangent entry.
double tangent_error(const stratum::Material& m, const Vec6& s, const Vec6& e, const std::vector<double>& h,
                     const Vec6& de) {
  const Result base = update(m, s, e, h, de);
  REQUIRE(base.o.ok());
  const Mat6 fd = fd_tangent(m, s, e, h, de);
  return (base.tangent - fd).cwiseAbs().maxCoeff() / base.tangent.cwiseAbs().maxCoeff();
}

// History of a duncan_chang point: F_sr max, q max, and a zero recovery origin.
std::vector<double> hist(double S, double q) { return {S, q, 0, 0, 0, 0, 0, 0}; }

Vec6 triaxial_stress(double s3, double q) { return (Vec6() << -s3, -s3 - q, -s3, 0, 0, 0).finished(); }

} // namespace

TEST_CASE("duncan_chang M6: a drained triaxial path follows the hyperbola (2.26)", "[duncan_chang]") {
  for (const auto& [s3, toml, set] :
       {std::tuple{100.0, loess_a_toml, loess_a()},
        std::tuple{300.0,
                   std::string("K = 70\nn = 0.82\nR_f = 0.8\nphi = 20\nc = 40\nK_ur = 350\nG = 0.18\nF = "
                               "0.22\nd = 14\n"),
                   loess_b()}}) {
    // Up to a stress level of 0.9: eps = 0.9 q_f / (E_i (1 - 0.9 R_f)).
    const double emax = 0.9 * q_f(set, s3) / (E_i(set, s3) * (1.0 - 0.9 * set.R_f));
    for (const char* form : {"E_nu", "E_B"}) {
      const std::string extra = std::string("form = \"") + form + "\"\n" +
                                (std::string(form) == "E_B" ? "K_b = 300\nm = 0.5\n" : "") +
                                "max_substep_strain = 1e-5\n";
      std::string mat = toml;
      if (std::string(form) == "E_B") // the E_B form has no G, F, d
        mat = mat.substr(0, mat.find("G = "));
      const auto run = run_point(point_file(mat + extra, s3, emax, 1000));
      REQUIRE(run.outcome.ok());
      double worst = 0.0, worst_lat = 0.0;
      const double f = set.G - set.F * std::log10(s3 / 100.0);
      for (const auto& r : run.rows) {
        worst = std::max(worst, std::abs(q_of(r) - hyperbola(set, s3, eps_a(r))) / q_f(set, s3));
        const double lat = f * eps_a(r) / (1.0 - set.d * eps_a(r)); // (2.32), while nu_t < 0.49
        if (std::string(form) == "E_nu" && f / std::pow(1.0 - set.d * eps_a(r), 2) < 0.49)
          worst_lat = std::max(worst_lat, std::abs(eps_r(r) - lat) / std::max(lat, 1e-6));
      }
      REPORT("sigma_3 = " << s3 << " form " << form << ": max |q - hyperbola|/q_f = " << worst
                          << ", max relative lateral-strain error (2.32) = " << worst_lat);
      CHECK(worst < 1e-4);
      CHECK(worst_lat < 1e-4);
      CHECK(std::abs(q_of(run.rows.back()) / q_f(set, s3) - 0.9) < 1e-4);
    }
  }
}

TEST_CASE("duncan_chang: stress recovery (4.46)-(4.49) matches fine-step incremental integration",
          "[duncan_chang]") {
  // Triaxial at sigma_3 = 100 kPa (set a) to 3% axial strain: past the nu_t cap (eps = 1.97%) and
  // past failure (eps_f = 1.88%), so every branch of the recovery is crossed.
  const double s3 = 100.0, emax = 0.03;
  const auto inc = run_point(point_file(loess_a_toml + "max_substep_strain = 1e-6\n", s3, emax, 300));
  const auto rec = run_point(point_file(loess_a_toml + "update = \"recovery\"\n", s3, emax, 300));
  REQUIRE(inc.outcome.ok());
  REQUIRE(rec.outcome.ok());
  REQUIRE(inc.rows.size() == rec.rows.size());
  double worst_s = 0.0, worst_e = 0.0;
  for (std::size_t i = 1; i < inc.rows.size(); ++i) {
    const double scale = inc.rows[i].stress.cwiseAbs().maxCoeff();
    worst_s = std::max(worst_s, (inc.rows[i].stress - rec.rows[i].stress).cwiseAbs().maxCoeff() / scale);
    worst_e = std::max(worst_e, std::abs(eps_r(inc.rows[i]) - eps_r(rec.rows[i])) /
                                    std::max(std::abs(eps_r(inc.rows[i])), 1e-5));
  }
  REPORT("recovery vs incremental: max stress difference / |stress| = " << worst_s
                                                                        << ", lateral strain: " << worst_e);
  CHECK(worst_s < 1e-3);
  CHECK(worst_e < 1e-3);
  // Strain control: the recovered stress of every strain state of the incremental run (no mixed
  // control involved, so sigma_3 comes from the strain ratio alone).
  const dc::DuncanChang m(constants(dc::Update::recovery));
  double worst_direct = 0.0;
  for (std::size_t i = 1; i < inc.rows.size(); ++i) {
    Vec6 sr;
    REQUIRE(m.recover(inc.rows[i].strain, sr));
    worst_direct = std::max(worst_direct, (sr - inc.rows[i].stress).cwiseAbs().maxCoeff() /
                                              inc.rows[i].stress.cwiseAbs().maxCoeff());
  }
  REPORT("recovered stress of the incremental strains: max difference / |stress| = " << worst_direct);
  CHECK(worst_direct < 1e-3);
  // And the recovery alone: the stress of a CID strain state (2.32) at sigma_3 = 60 kPa.
  const double s = 60.0, e1 = 0.004, f = 0.18 - 0.22 * std::log10(0.6);
  const double lat = f * e1 / (1.0 - 20.0 * e1);
  Vec6 sig;
  REQUIRE(m.recover((Vec6() << lat, -e1, lat, 0, 0, 0).finished(), sig));
  CHECK(sig[0] == Approx(-s).epsilon(1e-10));
  CHECK(sig[2] == Approx(-s).epsilon(1e-10));
  CHECK(sig[0] - sig[1] == Approx(hyperbola(loess_a(), s, e1)).epsilon(1e-10));
}

TEST_CASE("duncan_chang: recovery from an anisotropic initial stress (recovery_origin)", "[duncan_chang]") {
  // K0 = 0.5: sigma_v = 100 kPa (axial, y), sigma_h = 50 kPa. With recovery_origin =
  // "initial_stress" the strains count from the CID state of the initial stress, eps_1,0 =
  // q0/(E_i (1 - R_f S0)); a drained triaxial path then follows q = hyperbola(eps_1,0 + eps_a),
  // as the incremental update does from the same stress. With "zero" (the thesis as printed) the
  // initial deviator is lost at the first recovered step.
  const dc::Set a = loess_a();
  const double s3 = 50.0, q0 = 50.0, S0 = q0 / q_f(a, s3);
  const double e10 = q0 / (E_i(a, s3) * (1.0 - a.R_f * S0));
  auto file = [&](const std::string& extra) {
    return "[material]\nmodel = \"duncan_chang\"\n" + loess_a_toml + extra +
           "[initial]\nstress = [-50.0, -100.0, -50.0, 0.0, 0.0, 0.0]\n[[paths]]\ntype = "
           "\"triaxial_drained\"\naxial_strain = -0.01\nsteps = 100\n";
  };
  for (const char* upd : {"recovery", "incremental"}) {
    const auto run = run_point(file(std::string("update = \"") + upd + "\"\nmax_substep_strain = 1e-5\n"));
    REQUIRE(run.outcome.ok());
    double worst = 0.0;
    for (const auto& r : run.rows)
      worst = std::max(worst, std::abs(q_of(r) - hyperbola(a, s3, e10 + eps_a(r))) / q_f(a, s3));
    REPORT(upd << " from K0 = 0.5: max |q - hyperbola(eps_1,0 + eps_a)| / q_f = " << worst);
    CHECK(worst < 1e-5);
  }
  // The zero increment returns the initial stress.
  auto c = constants(dc::Update::recovery);
  const dc::DuncanChang m(c);
  const Vec6 s0 = (Vec6() << -50.0, -100.0, -50.0, 0, 0, 0).finished();
  std::vector<double> h(8);
  m.init_history(s0, h);
  CHECK(-h[3] == Approx(e10).epsilon(1e-14));
  const Result r0 = update(m, s0, Vec6::Zero(), h, Vec6::Zero());
  CHECK((r0.stress - s0).cwiseAbs().maxCoeff() < 1e-9 * 100.0);
  // recovery_origin = "zero": after the first step q is the hyperbola of eps_a alone.
  const auto z = run_point(file("update = \"recovery\"\nrecovery_origin = \"zero\"\n"));
  REQUIRE(z.outcome.ok());
  CHECK(q_of(z.rows[1]) == Approx(hyperbola(a, s3, eps_a(z.rows[1]))).epsilon(1e-6));
  CHECK(q_of(z.rows[1]) < 0.2 * q0);
}

TEST_CASE("duncan_chang: unloading and reloading follow E_ur (2.40)", "[duncan_chang]") {
  // Load to 1% axial strain at sigma_3 = 100, unload by 0.1% (q from 160 to 80 kPa), reload to 1.5%.
  const double s3 = 100.0;
  for (const char* upd : {"incremental", "recovery"}) {
    std::string text = point_file(loess_a_toml + "update = \"" + upd + "\"\n", s3, 0.01, 100);
    text += "[[paths]]\ntype = \"triaxial_drained\"\naxial_strain = 0.001\nsteps = 20\n";
    text += "[[paths]]\ntype = \"triaxial_drained\"\naxial_strain = -0.006\nsteps = 60\n";
    const auto run = run_point(text);
    REQUIRE(run.outcome.ok());
    const auto& top = run.rows[100];
    const auto& bottom = run.rows[120];
    const double E_ur = 800.0 * 100.0;
    // sigma_3 is constant, so the unloading is linear with slope E_ur.
    const double slope = (q_of(top) - q_of(bottom)) / (eps_a(top) - eps_a(bottom));
    REPORT(upd << ": unloading slope " << slope << " against E_ur = " << E_ur);
    CHECK(slope == Approx(E_ur).epsilon(1e-6));
    CHECK(q_of(top) == Approx(hyperbola(loess_a(), s3, 0.01)).epsilon(1e-4));
    // Reloading returns along E_ur to the virgin curve and continues on the hyperbola.
    CHECK(q_of(run.rows[130]) == Approx(q_of(top)).epsilon(1e-6)); // back at 1% axial strain
    CHECK(q_of(run.rows.back()) == Approx(hyperbola(loess_a(), s3, 0.015)).epsilon(1e-4));
  }
}

TEST_CASE("duncan_chang: F_sr (4.50) and the maximum-deviator criterion", "[duncan_chang]") {
  // A point loaded to stress level 0.6 at sigma_3 = 100 kPa, then compressed almost isotropically:
  // q grows a little (maximum-deviator: loading, E_t) while sigma_3 grows more, so F_sr drops
  // (F_sr: unloading, E_ur).
  const dc::Set a = loess_a();
  const double s3 = 100.0, q = 0.6 * q_f(a, s3);
  const Vec6 s = triaxial_stress(s3, q);
  const std::vector<double> h = hist(0.6, q);
  const Vec6 de = (Vec6() << -1e-6, -1.1e-6, -1e-6, 0, 0, 0).finished();
  const double E_t = E_i(a, s3) * std::pow(1.0 - a.R_f * 0.6, 2), E_ur = 800.0 * 100.0;
  const double nu_i = 0.18, A = a.d * q / (E_i(a, s3) * (1.0 - a.R_f * 0.6));
  const double nu_t = std::min(nu_i / ((1 - A) * (1 - A)), 0.49);
  for (const auto crit : {dc::Unloading::F_sr, dc::Unloading::max_deviator}) {
    auto c = constants();
    c.unloading = crit;
    const dc::DuncanChang m(c);
    const Result r = update(m, s, Vec6::Zero(), h, de);
    REQUIRE(r.o.ok());
    const bool fsr = crit == dc::Unloading::F_sr;
    const Mat6 D = fsr ? stratum::isotropic_stiffness(E_ur, nu_i) : stratum::isotropic_stiffness(E_t, nu_t);
    const Vec6 expect = s + D * de;
    REPORT((fsr ? "F_sr" : "max_deviator")
           << ": stress " << r.stress.transpose() << ", expected " << expect.transpose());
    CHECK((r.stress - expect).cwiseAbs().maxCoeff() < 1e-3 * (D * de).cwiseAbs().maxCoeff());
    // Both criteria agree on their own measures: q rose, F_sr fell.
    const dc::Point pe = m.point(r.stress);
    CHECK(pe.q > q);
    CHECK(pe.S < 0.6);
    CHECK(r.h[1] == Approx(pe.q).epsilon(1e-14));
    CHECK(r.h[0] == 0.6);
  }
  // A plain axial unloading: both criteria say E_ur.
  for (const auto crit : {dc::Unloading::F_sr, dc::Unloading::max_deviator}) {
    auto c = constants();
    c.unloading = crit;
    const dc::DuncanChang m(c);
    const Vec6 d2 = (Vec6() << 0, 1e-6, 0, 0, 0, 0).finished();
    const Result r = update(m, s, Vec6::Zero(), h, d2);
    const Vec6 expect = s + stratum::isotropic_stiffness(E_ur, nu_i) * d2;
    CHECK((r.stress - expect).cwiseAbs().maxCoeff() < 1e-3 * 0.1);
  }
}

TEST_CASE("duncan_chang: F_sr and max-deviator disagree on a point path where sigma_3 grows",
          "[duncan_chang]") {
  // Triaxial loading at 100 kPa to 1% axial strain (S = 0.85), then all stresses controlled:
  // sigma_3 + 50 kPa and q + 1 kPa. q passes its maximum (max-deviator: loading, E_t, nu_t),
  // F_sr falls (F_sr: unloading, E_ur and nu_i). The stress increment is isotropic up to 1 kPa,
  // so the volumetric strain is the integral of dp/K along the path.
  const std::string path2 =
      "[[paths]]\ntype = \"mixed\"\ncontrol = [\"stress\", \"stress\", \"stress\", \"stress\", "
      "\"stress\", \"stress\"]\nincrement = [-50.0, -51.0, -50.0, 0.0, 0.0, 0.0]\nsteps = 100\n";
  double ev[2];
  for (int k = 0; k < 2; ++k) {
    const std::string crit = k == 0 ? "F_sr" : "max_deviator";
    const auto run =
        run_point(point_file(loess_a_toml + "unloading = \"" + crit + "\"\n", 100.0, 0.01, 100) + path2);
    REQUIRE(run.outcome.ok());
    const auto &a = run.rows[100], &b = run.rows.back();
    ev[k] = -(b.strain - a.strain).head<3>().sum();
    CHECK(q_of(b) == Approx(q_of(a) + 1.0).epsilon(1e-9));
  }
  // F_sr: the integral of dp/K_ur(sigma_3), K_ur = E_ur/(3 (1 - 2 nu_i)), by Simpson's rule; the
  // deviator change of 1 kPa adds 1/3 kPa to p.
  const int N = 2000;
  double integral = 0.0;
  for (int j = 0; j <= N; ++j) {
    const double s3 = 100.0 + 50.0 * j / N;
    const double nu = 0.18 - 0.22 * std::log10(s3 / 100.0);
    const double K = 800.0 * 100.0 * std::pow(s3 / 100.0, 0.82) / (3.0 * (1.0 - 2.0 * nu));
    integral += (j == 0 || j == N ? 1.0 : (j % 2 ? 4.0 : 2.0)) / K;
  }
  integral *= (50.0 / N / 3.0) * (50.0 + 1.0 / 3.0) / 50.0;
  REPORT("volumetric strain of the sigma_3 increase: F_sr " << ev[0] << " (E_ur closed form " << integral
                                                            << "), max-deviator " << ev[1]);
  CHECK(ev[0] == Approx(integral).epsilon(1e-4));
  CHECK(ev[1] > 2.0 * ev[0]); // on the loading branch the soil is far softer
}

TEST_CASE("duncan_chang: the rule between the loess sets (a) and (b)", "[duncan_chang]") {
  auto c = constants();
  c.levels = {100.0, 200.0};
  c.sets = {loess_a(), loess_b()};
  const dc::DuncanChang m(c);
  // Below 100 kPa set (a), above 200 kPa set (b), in between each parameter linear in sigma_3.
  for (const double s3 : {25.0, 40.0, 80.0, 100.0}) {
    const dc::Point p = m.point(triaxial_stress(s3, 0.0));
    CHECK(p.E_i == Approx(E_i(loess_a(), s3)).epsilon(1e-14));
    CHECK(p.q_f == Approx(q_f(loess_a(), s3)).epsilon(1e-14));
  }
  for (const double s3 : {200.0, 300.0, 400.0}) {
    const dc::Point p = m.point(triaxial_stress(s3, 0.0));
    CHECK(p.E_i == Approx(E_i(loess_b(), s3)).epsilon(1e-14));
    CHECK(p.E_ur == Approx(350.0 * 100.0 * std::pow(s3 / 100.0, 0.82)).epsilon(1e-14));
  }
  const dc::Point mid = m.point(triaxial_stress(150.0, 0.0));
  CHECK(mid.P.K == Approx(285.0).epsilon(1e-14));
  CHECK(mid.P.phi == Approx(23.0).epsilon(1e-14));
  CHECK(mid.P.c == Approx(25.0).epsilon(1e-14));
  CHECK(mid.P.d == Approx(17.0).epsilon(1e-14));
  CHECK(mid.E_i == Approx(285.0 * 100.0 * std::pow(1.5, 0.82)).epsilon(1e-14));
  // E_i falls monotonically from set (a) at 100 kPa to set (b) at 200 kPa.
  double prev = m.point(triaxial_stress(100.0, 0.0)).E_i;
  for (double s3 = 105.0; s3 <= 200.0; s3 += 5.0) {
    const double e = m.point(triaxial_stress(s3, 0.0)).E_i;
    CHECK(e < prev);
    prev = e;
  }

  // The TOML form: every set parameter a number or a list matching sigma3_levels.
  stratum::Schema schema;
  dc::declare(schema, dc::Family::duncan_chang);
  auto read = [&](const std::string& text) {
    const toml::table t = toml::parse(text, std::string("m.toml"));
    return dc::read(stratum::io::check_table(t, schema, "[material]"), dc::Family::duncan_chang);
  };
  auto message = [&](const std::string& text) {
    try {
      (void)read(text);
    } catch (const stratum::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string loess = "sigma3_levels = [100, 200]\nK = [500, 70]\nn = 0.82\nR_f = 0.8\nphi = [26, 20]\n"
                            "c = [10, 40]\nK_ur = [800, 350]\nG = 0.18\nF = 0.22\nd = [20, 14]\n";
  const dc::Constants got = read(loess);
  REQUIRE(got.sets.size() == 2);
  CHECK(got.sets[1].K == 70.0);
  CHECK(got.sets[1].n == 0.82);
  CHECK(got.sets[0].d == 20.0);
  CHECK(message("K = [500, 70]\nn = 0.82\nR_f = 0.8\nphi = 26\nc = 10\nK_ur = 800\nG = 0.18\nF = 0.22\nd = "
                "20\n") == "m.toml:1:5 [material] K has 2 values, so sigma3_levels must list 2 increasing "
                           "sigma_3 values (kPa), one per set");
  CHECK(message("sigma3_levels = [100, 200, 300]\n" + loess.substr(loess.find('\n') + 1)) ==
        "m.toml:1:17 [material] K has 2 values, so sigma3_levels must list 2 increasing sigma_3 values "
        "(kPa), one per set");
  CHECK(message(loess + "form = \"E_B\"\n") == "m.toml:11:8 [material] K_b is required for form = \"E_B\"");
  // A list of one value is a list, not a number for every level (README; found on 997ba04:
  // K = [500.0] beside two levels was broadcast silently). A plain number is broadcast.
  std::string k1 = loess;
  k1.replace(k1.find("K = [500, 70]"), 13, "K = [500.0]");
  CHECK(message(k1) ==
        "m.toml:2:5 [material] K is a list of 1 value but phi has 2; give one value per "
        "sigma3_levels entry, or write it as a plain number (no brackets) to use it for every level");
  std::string kn = loess;
  kn.replace(kn.find("K = [500, 70]"), 13, "K = 500.0");
  const dc::Constants broadcast = read(kn);
  REQUIRE(broadcast.sets.size() == 2);
  CHECK(broadcast.sets[0].K == 500.0);
  CHECK(broadcast.sets[1].K == 500.0);
  std::string f0 = loess;
  f0.replace(f0.find("F = 0.22"), 8, "F = 0");
  CHECK(message(f0 + "update = \"recovery\"\n") ==
        "m.toml:9:5 [material] update = \"recovery\" needs F > 0: sigma_3 is recovered from nu_i = G - F "
        "log10(sigma_3/p_a)");
  std::string rf = loess;
  rf.replace(rf.find("R_f = 0.8"), 9, "R_f = [0.8, 1.2]");
  CHECK(message(rf) == "m.toml:4:13 [material] R_f contains 1.2, outside (0, 1]");
  std::string rf1 = loess;
  rf1.replace(rf1.find("R_f = 0.8"), 9, "R_f = 1.2");
  CHECK(message(rf1) == "m.toml:4:7 [material] R_f = 1.2 is outside (0, 1]");
}

TEST_CASE("duncan_chang: tension and failure regimes", "[duncan_chang]") {
  const dc::Set a = loess_a();
  // Failure: beyond q_f the modulus is residual * E_i (default 1e-3).
  const double s3 = 100.0, ef = q_f(a, s3) / (E_i(a, s3) * (1.0 - a.R_f));
  const auto run = run_point(point_file(loess_a_toml + "max_substep_strain = 1e-6\n", s3, 0.04, 400));
  REQUIRE(run.outcome.ok());
  const double expect = q_f(a, s3) + 1e-3 * E_i(a, s3) * (0.04 - ef);
  REPORT("q at 4% axial strain: " << q_of(run.rows.back()) << ", expected " << expect);
  CHECK(q_of(run.rows.back()) == Approx(expect).epsilon(1e-3));
  // Tension: axial extension of a point at 20 kPa. Principal stresses never become tensile; the
  // moduli use sigma_3 >= 0.01 p_a.
  const dc::DuncanChang m(constants());
  Vec6 s = triaxial_stress(20.0, 0.0), e = Vec6::Zero();
  std::vector<double> h = hist(0.0, 0.0);
  const Vec6 de = (Vec6() << -0.0005, 0.003, -0.0005, 0, 0, 0).finished();
  for (int k = 0; k < 5; ++k) {
    const Result r = update(m, s, e, h, de);
    REQUIRE(r.o.ok());
    s = r.stress, e += de, h = r.h;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(stratum::stress_tensor(s));
    CHECK(es.eigenvalues()[2] <= 1e-12);
  }
  // The cut-off is active: the axial stress has been pulled to zero, not beyond.
  CHECK(s[1] == Approx(0.0).margin(1e-12));
  // The stiffness of a tensile state is that at the floor sigma_3 = 1 kPa.
  const dc::Point pt = m.point((Vec6() << 5.0, 5.0, 5.0, 0, 0, 0).finished());
  CHECK(pt.E_i == Approx(500.0 * 100.0 * std::pow(0.01, 0.82)).epsilon(1e-14));
}

TEST_CASE("duncan_chang: finite-difference check of the tangent", "[duncan_chang]") {
  // A loaded state (S = 0.5 at 100 kPa) and an increment that keeps loading in a general direction.
  const dc::Set a = loess_a();
  const double q = 0.5 * q_f(a, 100.0);
  const Vec6 s = triaxial_stress(100.0, q);
  const Vec6 de = (Vec6() << 2e-4, -7.5e-4, 1.5e-4, 1e-4, -5e-5, 3e-5).finished();
  const std::vector<double> h = hist(0.5, q);
  for (const auto form : {dc::Form::E_nu, dc::Form::E_B, dc::Form::K_G}) {
    auto c = constants(dc::Update::incremental, form);
    c.sets[0].K_b = 300, c.sets[0].m = 0.5, c.sets[0].nu = 0.3;
    const dc::DuncanChang m(c);
    for (const Vec6& d : {de, Vec6(-de)}) { // loading and unloading increments
      const double err = tangent_error(m, s, Vec6::Zero(), h, d);
      REPORT("form " << static_cast<int>(form) << ": tangent error " << err);
      CHECK(err < 1e-5);
    }
    // At a zero increment the update has a kink (E_t one way, E_ur the other); its tangent is
    // the loading one, the hypoelastic D(E_t, nu_t) of the current stress.
    // (Checked at sigma_2 != sigma_3: at sigma_2 = sigma_3 the minor principal stress, and with it
    // the moduli, has a kink, and any difference quotient there carries an O(step) error.)
    Vec6 s2 = s;
    s2[2] -= 0.3 * q;
    const dc::Moduli mo = m.moduli(m.point(s2), false);
    const Result r0 = update(m, s2, Vec6::Zero(), h, Vec6::Zero());
    CHECK((r0.tangent - stratum::stiffness_kg(mo.K, mo.G)).cwiseAbs().maxCoeff() <
          1e-6 * r0.tangent.cwiseAbs().maxCoeff());
    // Strictly inside the unloading region the map is smooth at a zero increment too.
    CHECK(tangent_error(m, s2, Vec6::Zero(), hist(0.7, 2.0 * q), Vec6::Zero()) < 1e-5);
  }
  {
    // E_nu loading moduli in closed form: E_t (2.31) and nu_t (2.35) at S = 0.5, sigma_3 = 100.
    const dc::DuncanChang m(constants());
    const dc::Moduli mo = m.moduli(m.point(s), false);
    const double A = a.d * q / (E_i(a, 100.0) * (1.0 - 0.5 * a.R_f));
    CHECK(mo.E == Approx(E_i(a, 100.0) * std::pow(1.0 - 0.5 * a.R_f, 2)).epsilon(1e-14));
    CHECK(mo.nu == Approx(0.18 / ((1.0 - A) * (1.0 - A))).epsilon(1e-14));
  }
  // Recovery: a CID strain state at sigma_3 = 100 kPa (eps_1 = 0.5%) and a general increment.
  const dc::DuncanChang m(constants(dc::Update::recovery));
  const double e1 = 0.005, lat = 0.18 * e1 / (1.0 - 20.0 * e1);
  const Vec6 e = (Vec6() << lat, -e1, lat, 0, 0, 0).finished();
  Vec6 s0;
  REQUIRE(m.recover(e, s0));
  const std::vector<double> h0 = hist(m.point(s0).S, m.point(s0).q);
  const double err = tangent_error(m, s0, e, h0, 0.1 * de);
  REPORT("recovery: tangent error " << err);
  CHECK(err < 1e-5);
}

TEST_CASE("duncan_chang: plane states: the out-of-plane shears do not couple (the 4-column tangent)",
          "[duncan_chang]") {
  // For a plane state (no out-of-plane shear in stress, strain or increment) the update
  // differences only the four in-plane columns and fills the out-of-plane block by the
  // reflection symmetry z -> -z of an isotropic law. Check that claim against central
  // differences of the full update in all six directions (perturbing components 4 and 5 makes
  // the state three-dimensional): the in-plane block agrees, and the differenced couplings
  // between in-plane and out-of-plane components vanish.
  const dc::Set a = loess_a();
  const double q = 0.5 * q_f(a, 100.0);
  Vec6 s = triaxial_stress(100.0, q);
  s[2] -= 0.2 * q; // sigma_2 != sigma_3: away from the kink of the minor principal stress
  s[3] = 0.1 * q;  // in-plane shear
  const Vec6 de = (Vec6() << 2e-4, -7.5e-4, 1.5e-4, 1e-4, 0, 0).finished();
  for (const auto u : {dc::Update::incremental, dc::Update::explicit_step, dc::Update::recovery}) {
    INFO("update " << static_cast<int>(u));
    const dc::DuncanChang m(constants(u));
    Vec6 s0 = s, e0 = Vec6::Zero();
    if (u == dc::Update::recovery) { // a strain state the recovery maps to a stress
      const double e1 = 0.005, lat = 0.18 * e1 / (1.0 - 20.0 * e1);
      e0 << lat, -e1, 0.8 * lat, 2e-4, 0, 0;
      REQUIRE(m.recover(e0, s0));
    }
    const std::vector<double> h = hist(m.point(s0).S, m.point(s0).q);
    const Result base = update(m, s0, e0, h, de);
    REQUIRE(base.o.ok());
    const Mat6 fd = fd_tangent(m, s0, e0, h, de);
    const double scale = fd.cwiseAbs().maxCoeff();
    CHECK((base.tangent.topLeftCorner<4, 4>() - fd.topLeftCorner<4, 4>()).cwiseAbs().maxCoeff() <
          1e-5 * scale);
    CHECK(fd.topRightCorner<4, 2>().cwiseAbs().maxCoeff() < 1e-6 * scale);
    CHECK(fd.bottomLeftCorner<2, 4>().cwiseAbs().maxCoeff() < 1e-6 * scale);
    CHECK(base.tangent.topRightCorner<4, 2>().cwiseAbs().maxCoeff() == 0.0);
    CHECK(base.tangent.bottomLeftCorner<2, 4>().cwiseAbs().maxCoeff() == 0.0);
  }
}

TEST_CASE("duncan_chang: the explicit update is one forward-Euler step of the hyperbola", "[duncan_chang]") {
  // update = "explicit": sigma = sigma_n + D(sigma_n) d eps on the branch of the E_ur trial; its
  // tangent is D(sigma_n) itself, so global Newton sees a piecewise-linear law.
  const dc::Set a = loess_a();
  const double q = 0.5 * q_f(a, 100.0);
  const Vec6 s = triaxial_stress(100.0, q);
  const Vec6 de = (Vec6() << 2e-4, -7.5e-4, 1.5e-4, 1e-4, -5e-5, 3e-5).finished();
  const dc::DuncanChang m(constants(dc::Update::explicit_step));
  const dc::Moduli mo = m.moduli(m.point(s), false);
  const Mat6 D = stratum::stiffness_kg(mo.K, mo.G);
  const Result r = update(m, s, Vec6::Zero(), hist(0.5, q), de);
  CHECK((r.stress - (s + D * de)).cwiseAbs().maxCoeff() < 1e-9 * s.cwiseAbs().maxCoeff());
  CHECK((r.tangent - D).cwiseAbs().maxCoeff() < 1e-6 * D.cwiseAbs().maxCoeff());
  // Unloading: the E_ur moduli of the start (E_ur (2.40), nu = f).
  const dc::Moduli mu = m.moduli(m.point(s), true);
  const Result ru = update(m, s, Vec6::Zero(), hist(0.5, q), Vec6(-de));
  CHECK((ru.stress - (s - stratum::stiffness_kg(mu.K, mu.G) * de)).cwiseAbs().maxCoeff() <
        1e-9 * s.cwiseAbs().maxCoeff());
  // Along a drained triaxial path to S = 0.9 the error against the hyperbola (2.26) is first order
  // in the step: halving the step halves it (ratio 2 within 15 %).
  auto error = [&](int steps) {
    const double emax = 0.9 * q_f(a, 100.0) / (E_i(a, 100.0) * (1.0 - 0.9 * a.R_f));
    const auto run = run_point(point_file(loess_a_toml + "update = \"explicit\"\n", 100.0, emax, steps));
    REQUIRE(run.outcome.ok());
    double worst = 0.0;
    for (const auto& rr : run.rows)
      worst = std::max(worst, std::abs(q_of(rr) - hyperbola(a, 100.0, eps_a(rr))) / q_f(a, 100.0));
    return worst;
  };
  const double e100 = error(100), e200 = error(200), e400 = error(400);
  REPORT("explicit: max |q - hyperbola|/q_f with 100, 200, 400 steps: " << e100 << ", " << e200 << ", "
                                                                        << e400);
  CHECK(e100 / e200 == Approx(2.0).epsilon(0.15));
  CHECK(e200 / e400 == Approx(2.0).epsilon(0.15));
  CHECK(e400 < 1e-2);
}

TEST_CASE("duncan_chang: the explicit update's closed-form tangent in every regime", "[duncan_chang]") {
  // update = "explicit" returns alpha D_ur + (1 - alpha) D_t of the start stress instead of
  // differencing the update. Against central differences of the whole update (all six
  // directions, branch decided afresh at every perturbed increment) where the branch is one:
  // loading (3D and plane), unloading, beyond failure (residual modulus); against the replayed
  // differences (branch split frozen, as Newton's tangent has always been) where an increment
  // crosses the historical maximum; and where the tension cut-off acts the update falls back to
  // differences, which must include the cut-off's derivative.
  const dc::Set a = loess_a();
  const dc::DuncanChang m(constants(dc::Update::explicit_step));
  const double q = 0.5 * q_f(a, 100.0);
  Vec6 s = triaxial_stress(100.0, q);
  s[2] -= 0.2 * q; // sigma_2 != sigma_3: away from the kink of the minor principal stress
  const Vec6 de3 = (Vec6() << 2e-4, -7.5e-4, 1.5e-4, 1e-4, -5e-5, 3e-5).finished();
  const Vec6 de2 = (Vec6() << 2e-4, -7.5e-4, 1.5e-4, 1e-4, 0, 0).finished();
  const std::vector<double> h = hist(m.point(s).S, m.point(s).q);
  auto closed = [&](const Vec6& s0, double alpha) { return m.explicit_stiffness(m.point(s0), alpha); };
  // Loading, a 3D and a plane increment: the tangent is D_t of the start.
  for (const Vec6& de : {de3, de2}) {
    const Result r = update(m, s, Vec6::Zero(), h, de);
    REQUIRE(r.o.ok());
    const Mat6 D = closed(s, 0.0);
    CHECK((r.tangent - D).cwiseAbs().maxCoeff() == 0.0);
    CHECK(tangent_error(m, s, Vec6::Zero(), h, de) < 1e-6);
  }
  // Unloading: D_ur.
  {
    const Result r = update(m, s, Vec6::Zero(), h, Vec6(-de3));
    REQUIRE(r.o.ok());
    CHECK((r.tangent - closed(s, 1.0)).cwiseAbs().maxCoeff() == 0.0);
    CHECK(tangent_error(m, s, Vec6::Zero(), h, Vec6(-de3)) < 1e-6);
  }
  // Beyond failure (S = 1.05): E_t = 1e-3 E_i with nu_t = 0.49.
  {
    Vec6 sf = triaxial_stress(100.0, 1.05 * q_f(a, 100.0));
    sf[2] -= 0.01 * q;
    const std::vector<double> hf = hist(m.point(sf).S, m.point(sf).q);
    const Result r = update(m, sf, Vec6::Zero(), hf, 0.01 * de3);
    REQUIRE(r.o.ok());
    const dc::Moduli mo = m.moduli(m.point(sf), false);
    CHECK(mo.E == Approx(1e-3 * m.point(sf).E_i).epsilon(1e-12));
    CHECK((r.tangent - stratum::stiffness_kg(mo.K, mo.G)).cwiseAbs().maxCoeff() == 0.0);
    CHECK(tangent_error(m, sf, Vec6::Zero(), hf, 0.01 * de3) < 1e-6);
  }
  // Crossing: the historical maximum just above the start, so the E_ur trial crosses it within
  // the increment (0 < alpha < 1). The closed form equals the frozen-split differences.
  {
    const std::vector<double> hc = hist(m.point(s).S * 1.002, m.point(s).q * 1.002);
    const Result r = update(m, s, Vec6::Zero(), hc, de2);
    REQUIRE(r.o.ok());
    Vec6 stress;
    Mat6 tangent;
    std::vector<double> hh(hc.size());
    stratum::MaterialOutput fd_out{stress, hh, tangent};
    const stratum::MaterialInput in{s, Vec6::Zero(), hc, de2, {0, 0}};
    dc::DuncanChang::Record rec;
    fd_out.stress = m.evaluate(in, de2, fd_out.history, rec, false);
    REQUIRE(rec.alpha.size() == 1);
    CAPTURE(rec.alpha[0]);
    CHECK(rec.alpha[0] > 0.0);
    CHECK(rec.alpha[0] < 1.0);
    REQUIRE(m.difference_tangent(in, rec, fd_out));
    const Mat6 D = closed(s, rec.alpha[0]);
    CHECK((r.tangent - D).cwiseAbs().maxCoeff() == 0.0);
    CHECK((tangent - D).cwiseAbs().maxCoeff() < 1e-6 * D.cwiseAbs().maxCoeff());
  }
  // Tension cut-off: an axial extension from a low confinement pulls the axial stress past
  // zero; the update differences, and the differences see the cut-off (the axial row vanishes).
  {
    const Vec6 sl = triaxial_stress(20.0, 0.0);
    const Vec6 ext = (Vec6() << -0.0005, 0.003, -0.0005, 0, 0, 0).finished();
    const std::vector<double> hl = hist(0.0, 0.0);
    const Result r = update(m, sl, Vec6::Zero(), hl, ext);
    REQUIRE(r.o.ok());
    CHECK(r.stress[1] == Approx(0.0).margin(1e-12));
    CHECK((r.tangent - closed(sl, 0.0)).cwiseAbs().maxCoeff() > 0.1 * closed(sl, 0.0).cwiseAbs().maxCoeff());
    CHECK(tangent_error(m, sl, Vec6::Zero(), hl, ext) < 1e-5);
  }
}

TEST_CASE("duncan_chang: branch = step_start decides E_ur or E_t by the step's start state",
          "[duncan_chang]") {
  // The classical load-step rule (digest 3.3: E_ur "whenever F_sr is below the values reached there
  // before", read at the state the step starts from): the branch ignores the increment, so the update
  // is linear in it and every iterate of a step uses the same moduli.
  const dc::Set a = loess_a();
  dc::Constants c = constants(dc::Update::explicit_step);
  c.branch = dc::Branch::step_start;
  const dc::DuncanChang m(c);
  const dc::DuncanChang by_increment(constants(dc::Update::explicit_step));
  const double q = 0.5 * q_f(a, 100.0);
  Vec6 s = triaxial_stress(100.0, q);
  s[2] -= 0.2 * q; // sigma_2 != sigma_3: away from the kink of the minor principal stress
  const Vec6 de = (Vec6() << 2e-4, -7.5e-4, 1.5e-4, 1e-4, -5e-5, 3e-5).finished();
  const Mat6 D_t = m.explicit_stiffness(m.point(s), 0.0), D_ur = m.explicit_stiffness(m.point(s), 1.0);
  const double tol = 1e-12 * s.cwiseAbs().maxCoeff();

  // At its maximum: E_t for an unloading increment too (the increment rule takes E_ur there).
  const std::vector<double> at_max = hist(m.point(s).S, m.point(s).q);
  {
    const Result r = update(m, s, Vec6::Zero(), at_max, Vec6(-de));
    REQUIRE(r.o.ok());
    CHECK((r.stress - (s - D_t * de)).cwiseAbs().maxCoeff() < tol);
    CHECK((r.tangent - D_t).cwiseAbs().maxCoeff() == 0.0);
    CHECK(tangent_error(m, s, Vec6::Zero(), at_max, Vec6(-de)) < 1e-6);
    const Result ri = update(by_increment, s, Vec6::Zero(), at_max, Vec6(-de));
    CHECK((ri.stress - (s - D_ur * de)).cwiseAbs().maxCoeff() < tol);
  }
  // Below its maximum: E_ur for the whole of a loading increment that crosses the maximum (the
  // increment rule splits it and ends on E_t).
  const std::vector<double> below = hist(m.point(s).S * 1.002, m.point(s).q * 1.002);
  {
    const Result r = update(m, s, Vec6::Zero(), below, de);
    REQUIRE(r.o.ok());
    CHECK((r.stress - (s + D_ur * de)).cwiseAbs().maxCoeff() < tol);
    CHECK((r.tangent - D_ur).cwiseAbs().maxCoeff() == 0.0);
    CHECK(m.point(r.stress).S > below[0]); // it did cross the maximum
    CHECK(tangent_error(m, s, Vec6::Zero(), below, de) < 1e-6);
    const Result ri = update(by_increment, s, Vec6::Zero(), below, de);
    CHECK((ri.stress - (s + D_ur * de)).cwiseAbs().maxCoeff() > 1e-3 * (D_ur * de).cwiseAbs().maxCoeff());
    // The history records the new maximum either way.
    CHECK(r.h[0] == Approx(m.point(r.stress).S).epsilon(1e-12));
  }
  // Linear in the increment (no cut-off acting): doubling and reversing it scale the change.
  for (const auto& h : {at_max, below}) {
    const Vec6 d1 = update(m, s, Vec6::Zero(), h, de).stress - s;
    const Vec6 d2 = update(m, s, Vec6::Zero(), h, Vec6(2.0 * de)).stress - s;
    const Vec6 dm = update(m, s, Vec6::Zero(), h, Vec6(-de)).stress - s;
    CHECK((d2 - 2.0 * d1).cwiseAbs().maxCoeff() < tol);
    CHECK((dm + d1).cwiseAbs().maxCoeff() < tol);
  }

  // On a monotonic drained triaxial path every point loads at its maximum: the two readings agree.
  {
    const double emax = 0.9 * q_f(a, 100.0) / (E_i(a, 100.0) * (1.0 - 0.9 * a.R_f));
    const auto inc = run_point(point_file(loess_a_toml + "update = \"explicit\"\n", 100.0, emax, 50));
    const auto st = run_point(
        point_file(loess_a_toml + "update = \"explicit\"\nbranch = \"step_start\"\n", 100.0, emax, 50));
    REQUIRE(inc.outcome.ok());
    REQUIRE(st.outcome.ok());
    REQUIRE(inc.rows.size() == st.rows.size());
    for (std::size_t i = 0; i < inc.rows.size(); ++i) CHECK(q_of(st.rows[i]) == q_of(inc.rows[i]));
  }

  // TOML: the rule belongs to the explicit update.
  stratum::Schema schema;
  dc::declare(schema, dc::Family::duncan_chang);
  const std::string base =
      "K = 500\nn = 0.82\nR_f = 0.8\nphi = 26\nc = 10\nK_ur = 800\nG = 0.18\nF = 0.22\nd = 20\n";
  auto read = [&](const std::string& text) {
    const toml::table t = toml::parse(text, std::string("m.toml"));
    return dc::read(stratum::io::check_table(t, schema, "[material]"), dc::Family::duncan_chang);
  };
  CHECK(read(base).branch == dc::Branch::increment);
  CHECK(read(base + "update = \"explicit\"\nbranch = \"step_start\"\n").branch == dc::Branch::step_start);
  std::string msg = "(no error)";
  try {
    (void)read(base + "branch = \"step_start\"\n");
  } catch (const stratum::Error& e) {
    msg = e.what();
  }
  CHECK(msg ==
        "m.toml:10:10 [material] branch = \"step_start\" belongs to update = \"explicit\" (one step per "
        "increment); the substepped updates decide the branch per substep");
}

TEST_CASE("variable_kg: K from E_i, G from E_t on a drained triaxial path", "[variable_kg]") {
  // At constant sigma_3: p = sigma_3 + q/3 with K = E_i/(3(1 - 2 nu)) constant, so eps_v = q/(3K);
  // d eps_s = dq/(3 G_t), G_t = E_i (1 - R_f q/q_f)^2 / (2(1 + nu)), so
  // eps_s = 2(1 + nu) q / (3 E_i (1 - R_f q/q_f)); eps_a = eps_v/3 + eps_s.
  const dc::Set a = loess_a();
  const double s3 = 100.0, nu = 0.3, Ei = E_i(a, s3), Kb = Ei / (3.0 * (1.0 - 2.0 * nu)), qf = q_f(a, s3);
  std::string text = point_file("K = 500\nn = 0.82\nR_f = 0.8\nphi = 26\nc = 10\nK_ur = 800\nnu = 0.3\n"
                                "max_substep_strain = 1e-5\n",
                                s3, 0.012, 200);
  text.replace(text.find("duncan_chang"), 12, "variable_kg");
  const auto run = run_point(text);
  REQUIRE(run.outcome.ok());
  double worst = 0.0;
  for (const auto& r : run.rows) {
    const double q = q_of(r);
    const double ea = q / (9.0 * Kb) + 2.0 * (1.0 + nu) * q / (3.0 * Ei * (1.0 - a.R_f * q / qf));
    worst = std::max(worst, std::abs(eps_a(r) - ea) / std::max(ea, 1e-6));
    const double ev = -(r.strain[0] + r.strain[1] + r.strain[2]);
    CHECK(ev == Approx(q / (3.0 * Kb)).epsilon(1e-4).margin(1e-12));
  }
  REPORT("variable_kg: max relative axial-strain error " << worst);
  CHECK(worst < 1e-4);
  // Unloading: both moduli from E_ur.
  auto c = constants(dc::Update::incremental, dc::Form::K_G);
  c.sets[0].nu = nu;
  const dc::DuncanChang m(c);
  const Vec6 s = triaxial_stress(s3, 0.5 * qf);
  const Vec6 de = (Vec6() << 0, 1e-6, 0, 0, 0, 0).finished();
  const Result r = update(m, s, Vec6::Zero(), hist(0.5, 0.5 * qf), de);
  const Vec6 expect = s + stratum::isotropic_stiffness(80000.0, nu) * de;
  CHECK((r.stress - expect).cwiseAbs().maxCoeff() < 1e-4);
}

TEST_CASE("nonlinear_elastic_no_tension: isotropic compression, tension cut-off, tangent",
          "[nonlinear_elastic]") {
  ne::Constants c;
  c.A = 400, c.n = 0.5, c.B = 200, c.m = 0.5, c.max_substep_strain = 1e-6;
  const ne::NoTension m(c);
  // Isotropic compression from p0 = 50 kPa: dp/deps_v = A p_a (p/p_a)^n, so
  // p^(1-n) = p0^(1-n) + (1-n) A p_a^(1-n) eps_v.
  const double p0 = 50.0, ev = 0.01;
  const Result r = update(m, triaxial_stress(p0, 0.0), Vec6::Zero(), {},
                          (Vec6() << -ev / 3, -ev / 3, -ev / 3, 0, 0, 0).finished());
  REQUIRE(r.o.ok());
  const double p = std::pow(std::pow(p0, 0.5) + 0.5 * 400.0 * std::pow(100.0, 0.5) * ev, 2.0);
  REPORT("isotropic: p = " << -r.stress[0] << ", closed form " << p);
  CHECK(-r.stress[0] == Approx(p).epsilon(1e-6));
  // Axial extension: the axial stress stops at the tensile strength 0; the others stay compressive.
  const Vec6 de = (Vec6() << -0.005, 0.01, -0.005, 0, 0, 0).finished();
  const Result t = update(m, triaxial_stress(p0, 0.0), Vec6::Zero(), {}, de);
  REQUIRE(t.o.ok());
  CHECK(t.stress[1] == Approx(0.0).margin(1e-12));
  CHECK(t.stress[0] < 0.0);
  // Tangent, in compression and while the cut-off is active.
  const Vec6 g = (Vec6() << -2e-4, -5e-4, -1e-4, 1e-4, 5e-5, -3e-5).finished();
  CHECK(tangent_error(m, triaxial_stress(p0, 20.0), Vec6::Zero(), {}, g) < 1e-5);
  CHECK(tangent_error(m, triaxial_stress(p0, 0.0), Vec6::Zero(), {}, de + g) < 1e-5);
}

TEST_CASE("duncan_chang: the loess triaxial inputs through `stratum point` follow the M6 closed form",
          "[duncan_chang][cli]") {
  // inputs/point/loess_duncan_chang_s*.toml: 300 steps to 15% axial strain with the sets (a)/(b).
  const std::string dir = std::string(STRATUM_BINARY_DIR) + "/tests/duncan_chang_cli";
  std::filesystem::create_directories(dir);
  for (const int s3 : {25, 40, 80, 200, 300, 400}) {
    char name[64];
    std::snprintf(name, sizeof name, "loess_duncan_chang_s%03d", s3);
    const std::string in = std::string(STRATUM_SOURCE_DIR) + "/inputs/point/" + name + ".toml";
    const std::string csv = dir + "/" + name + ".csv";
    const std::string cmd =
        std::string(STRATUM_EXE) + " point " + in + " --out " + csv + " > " + csv + ".log 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    std::ifstream f(csv);
    std::string line;
    std::getline(f, line); // header; eps_axial, eps_vol, p, q are the last four columns
    const dc::Set set = s3 <= 100 ? loess_a() : loess_b();
    const double qf = q_f(set, s3), ef = qf / (E_i(set, s3) * (1.0 - set.R_f));
    double worst = 0.0, last_e = 0.0, last_q = 0.0;
    int rows = 0;
    while (std::getline(f, line)) {
      std::vector<double> v;
      std::stringstream ss(line);
      for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
      REQUIRE(v.size() == 18);
      last_e = v[14], last_q = v[17];
      const double expect =
          last_e <= ef ? hyperbola(set, s3, last_e) : qf + 1e-3 * E_i(set, s3) * (last_e - ef);
      worst = std::max(worst, std::abs(last_q - expect) / qf);
      ++rows;
    }
    REPORT("sigma_3 = " << s3 << " kPa: q_f = " << qf << " kPa at eps_a = " << ef << ", q(15%) = " << last_q
                        << ", max |q - closed form| / q_f = " << worst);
    CHECK(rows == 301);
    CHECK(last_e == Approx(0.15).epsilon(1e-12));
    CHECK(worst < 1e-6);
  }
}

// Regression (bench_stability): a wild Newton iterate of a one-step load asked the incremental
// update for 100000 substeps per point and evaluation, and a 72-point sample ran for minutes.
// More than max_substeps now fails the update, so the step driver cuts the step back.
TEST_CASE("duncan_chang: a strain increment beyond max_substeps fails the update cleanly",
          "[duncan_chang][stability]") {
  dc::Constants c = constants(dc::Update::incremental);
  c.max_substeps = 1000;
  const dc::DuncanChang m(c);
  const Vec6 s = triaxial_stress(50, 0);
  const Vec6 e = Vec6::Zero();
  Vec6 de = Vec6::Zero();
  de[1] = -0.5; // 5000 substeps of 1e-4
  const Result big = update(m, s, e, hist(0, 0), de);
  CHECK(big.o.status == stratum::Status::material_failure);
  CHECK(big.o.message.find("max_substeps") != std::string::npos);
  de[1] = -0.05; // 500 substeps: still integrated
  const Result ok = update(m, s, e, hist(0, 0), de);
  CHECK(ok.o.ok());
  CHECK(ok.stress.allFinite());
  // The explicit update takes one step whatever the increment.
  c.update = dc::Update::explicit_step;
  de[1] = -0.5;
  CHECK(update(dc::DuncanChang(c), s, e, hist(0, 0), de).o.ok());
}

TEST_CASE("duncan_chang: point_status marks failed and tension-cut points for the output", "[duncan_chang]") {
  const dc::DuncanChang m(constants(dc::Update::explicit_step));
  const std::vector<double> h(8, 0.0);
  const double s3 = 50.0, qf = q_f(loess_a(), s3);
  auto triaxial = [&](double q) { // compression positive s1 = s3 + q (vertical), tension-positive Voigt
    stratum::Vec6 s = stratum::Vec6::Zero();
    s[0] = s[2] = -s3;
    s[1] = -(s3 + q);
    return s;
  };
  CHECK(m.point_status(triaxial(0.5 * qf), h) == 0);
  CHECK(m.point_status(triaxial(0.98 * qf), h) == 0);
  CHECK(m.point_status(triaxial(1.0 * qf), h) == 1);
  stratum::Vec6 cut = triaxial(20.0);
  cut[0] = 0.0; // a principal stress at zero: cut off in tension
  CHECK(m.point_status(cut, h) == 2);
}

TEST_CASE("duncan_chang: a recovery within the difference step of its domain's edge differences one-sided",
          "[duncan_chang]") {
  // The recovery needs a major compressive strain above recovery_min_strain. At e1 = min + 3e-8
  // the tangent's central difference (step 1e-7) of the axial column leaves the domain on the
  // minus side. Found on 997ba04: the replay then took the start stress as the perturbed stress,
  // which made that column (sigma(e + h) - sigma_n) / 2h, a wrong number of order sigma / 2e-7.
  // Now the column is the one-sided difference from the plus side: compare it with a forward
  // difference of the update itself (step 1e-6, inside the domain).
  auto c = constants(dc::Update::recovery);
  c.recovery_min_strain = 1e-3; // the edge at a strain where the law is smooth on the scale 1e-6
  const dc::DuncanChang m(c);
  const double e1 = c.recovery_min_strain + 3e-8, lat = 0.18 * e1 / (1.0 - 20.0 * e1);
  const Vec6 de = (Vec6() << lat, -e1, lat, 0, 0, 0).finished();
  const std::vector<double> h0 = hist(0, 0);
  const Result base = update(m, Vec6::Zero(), Vec6::Zero(), h0, de);
  REQUIRE(base.o.ok());
  REQUIRE(base.stress.cwiseAbs().maxCoeff() > 0.0);
  Vec6 dp = de;
  dp[1] -= 1e-6; // more compression: deeper inside the domain
  const Vec6 forward = (update(m, Vec6::Zero(), Vec6::Zero(), h0, dp).stress - base.stress) / -1e-6;
  const double err = (base.tangent.col(1) - forward).cwiseAbs().maxCoeff() / forward.cwiseAbs().maxCoeff();
  REPORT("axial column at the recovery's edge: relative difference from a forward difference " << err);
  CHECK(err < 1e-2);
}

} // namespace test_duncan_chang
