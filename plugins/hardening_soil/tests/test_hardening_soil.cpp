// Tests of the Hardening Soil plugin (plugins/hardening_soil): the closed forms of the drained
// triaxial hyperbola, Mohr-Coulomb failure, the oedometer modulus, unloading-reloading with
// E_ur, the small-strain overlay (G/G0 curve, tangent floor, history tensor and reversals), and the
// consistent tangent against central finite differences in every regime.
#include "hardening_soil/hardening_soil.hpp"

#include "stratum/error.hpp"
#include "stratum/point_driver.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace test_hardening_soil {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace hs = stratum::hardening_soil;

/// The test set (a loess-like silt): E50_ref 20 MPa, Eur_ref 60 MPa, m 0.5, c 10 kPa, phi 30 deg.
hs::Parameters base_set() {
  hs::Parameters p;
  p.E50_ref = 20000.0;
  p.Eoed_ref = 20000.0;
  p.Eur_ref = 60000.0;
  p.m = 0.5;
  p.p_ref = 100.0;
  p.nu_ur = 0.2;
  p.c = 10.0;
  p.phi = 30.0;
  p.psi = 0.0;
  p.Rf = 0.9;
  p.K0_nc = 0.5;
  return p;
}

const char* base_toml = R"(
[material]
model = "hardening_soil"
E50_ref = 20000.0
Eoed_ref = 20000.0
Eur_ref = 60000.0
m = 0.5
p_ref = 100.0
nu_ur = 0.2
c = 10.0
phi = 30.0
psi = 0.0
Rf = 0.9
K0_nc = 0.5
)";

double deg(double d) { return d * std::acos(-1.0) / 180.0; }

struct Point {
  Vec6 stress = Vec6::Zero();
  std::vector<double> h;
};

/// One update from a point; returns the outcome, fills stress, history and tangent.
stratum::Outcome step(const hs::HardeningSoil& m, const Point& pt, const Vec6& de, Vec6& s,
                      std::vector<double>& h, Mat6& T) {
  h.assign(pt.h.size(), 0.0);
  const Vec6 e0 = Vec6::Zero();
  stratum::MaterialOutput out{s, h, T};
  return m.update(stratum::MaterialInput{pt.stress, e0, pt.h, de, {0, 0}}, out);
}

/// Relative difference between the tangent and a central finite difference of the stress, with
/// the step `rel` times the largest increment component (at least 1e-5).
double fd_error(const hs::HardeningSoil& m, const Point& pt, const Vec6& de, int& status, double rel = 1e-7) {
  Vec6 s;
  std::vector<double> h;
  Mat6 T;
  REQUIRE(step(m, pt, de, s, h, T).ok());
  status = static_cast<int>(h[hs::slot::status]);
  Mat6 F;
  const double dh = rel * std::max(de.cwiseAbs().maxCoeff(), 1e-5);
  for (int j = 0; j < 6; ++j) {
    Vec6 dp = de, dm = de, sp, sm;
    dp[j] += dh;
    dm[j] -= dh;
    Mat6 Tp;
    std::vector<double> hp;
    REQUIRE(step(m, pt, dp, sp, hp, Tp).ok());
    REQUIRE(step(m, pt, dm, sm, hp, Tp).ok());
    F.col(j) = (sp - sm) / (2.0 * dh);
  }
  return (F - T).norm() / std::max(T.norm(), 1.0);
}

std::unique_ptr<hs::HardeningSoil> make(const hs::Parameters& p) {
  const auto cap = hs::calibrate_cap(p);
  REQUIRE(cap.has_value());
  return std::make_unique<hs::HardeningSoil>(p, (*cap)[0], (*cap)[1]);
}

Point at(const hs::HardeningSoil& m, const Vec6& stress) {
  Point pt;
  pt.stress = stress;
  pt.h.assign(static_cast<std::size_t>(m.history_size()), 0.0);
  m.init_history(stress, pt.h);
  return pt;
}

Vec6 diag(double xx, double yy, double zz) {
  Vec6 s = Vec6::Zero();
  s << xx, yy, zz, 0, 0, 0;
  return s;
}

} // namespace

TEST_CASE("hardening_soil: drained triaxial hyperbola and Mohr-Coulomb failure", "[hardening_soil]") {
  const hs::Parameters P = base_set();
  const double sp = std::sin(deg(P.phi)), cp = std::cos(deg(P.phi));
  for (double s3 : {50.0, 100.0, 200.0}) {
    INFO("sigma_3 = " << s3);
    const std::string text = std::string(base_toml) +
                             "p_p0 = 100000.0\n[initial]\np = " + std::to_string(s3) +
                             "\n[[paths]]\ntype = \"triaxial_drained\"\naxial_strain = -0.2\nsteps = 400\n";
    auto d = stratum::PointDriver::from_string(text, "hs_triaxial.toml", {STRATUM_PLUGIN_DIR});
    const auto run = d->run();
    REQUIRE(run.outcome.ok());
    const double E50 = P.E50_ref * std::pow((P.c * cp + s3 * sp) / (P.c * cp + P.p_ref * sp), P.m);
    const double qf = 2.0 * (P.c * cp + s3 * sp) / (1.0 - sp), qa = qf / P.Rf;
    int checked = 0;
    for (std::size_t i = 1; i < run.rows.size(); ++i) {
      const auto& r = run.rows[i];
      const double q = r.stress[0] - r.stress[1], eps1 = -r.strain[1];
      REQUIRE(r.stress[0] == Approx(-s3).epsilon(1e-9));
      if (q < 0.995 * qf) {
        CHECK(eps1 == Approx(qa * q / (2.0 * E50 * (qa - q))).epsilon(1e-4));
        ++checked;
      }
    }
    CHECK(checked > 50);
    const auto& last = run.rows.back();
    CHECK((last.stress[0] - last.stress[1]) == Approx(qf).epsilon(1e-8));
  }
}

TEST_CASE("hardening_soil: oedometer tangent modulus at sigma_1 = p_ref is Eoed_ref", "[hardening_soil]") {
  // K0_nc start at sigma_1 = 40 kPa on both the shear surface and the cap (OCR = 1); the
  // tangent modulus d sigma_1 / d eps_1 where sigma_1 passes p_ref, by central differences of
  // the driver's rows (steps of 2e-5 strain).
  for (double c : {0.0, 10.0}) {
    INFO("c = " << c);
    const std::string text = std::string(base_toml) + "c = " + std::to_string(c) +
                             "\n[initial]\nstress = [-20.0, -40.0, -20.0, 0.0, 0.0, 0.0]\n"
                             "[[paths]]\ntype = \"oedometer\"\naxial_strain = -0.02\nsteps = 1000\n";
    std::string t = text;
    t.replace(t.find("c = 10.0\n"), 9, ""); // the set's c replaced by the loop's
    auto d = stratum::PointDriver::from_string(t, "hs_oedometer.toml", {STRATUM_PLUGIN_DIR});
    const auto run = d->run();
    REQUIRE(run.outcome.ok());
    bool found = false;
    for (std::size_t i = 1; i + 1 < run.rows.size(); ++i) {
      const double s1 = -run.rows[i].stress[1], s1n = -run.rows[i + 1].stress[1];
      if (s1 <= 100.0 && s1n > 100.0) {
        const auto &a = run.rows[i - 1], &b = run.rows[i + 1];
        const double Eoed = (b.stress[1] - a.stress[1]) / (b.strain[1] - a.strain[1]);
        CHECK(Eoed == Approx(20000.0).epsilon(0.02));
        CHECK(run.rows[i].stress[0] / run.rows[i].stress[1] == Approx(0.5).epsilon(0.02));
        found = true;
      }
    }
    CHECK(found);
  }
}

TEST_CASE("hardening_soil: unloading and reloading inside the surfaces with E_ur(sigma_3)",
          "[hardening_soil]") {
  hs::Parameters P = base_set();
  P.p_p0 = 1e5; // the cap out of the way
  auto m = make(P);
  const double sp = std::sin(deg(P.phi)), cp = std::cos(deg(P.phi));
  // Shear from isotropic 100 kPa (plastic), then unload and reload the axial stress elastically.
  Point pt = at(*m, diag(-100, -100, -100));
  Vec6 s;
  std::vector<double> h;
  Mat6 T;
  REQUIRE(step(*m, pt, diag(2e-4, -2e-3, 2e-4), s, h, T).ok());
  REQUIRE(h[hs::slot::status] == 1.0);
  pt.stress = s;
  pt.h = h;
  const double s3 = -s[0]; // minor principal compression (the lateral stress)
  const double Eur = P.Eur_ref * std::pow((P.c * cp + s3 * sp) / (P.c * cp + P.p_ref * sp), P.m);
  const Mat6 D = stratum::isotropic_stiffness(Eur, P.nu_ur);
  const Vec6 unload = diag(-P.nu_ur * 1e-4, 1e-4, -P.nu_ur * 1e-4); // uniaxial-stress unloading
  Vec6 s1;
  REQUIRE(step(*m, pt, unload, s1, h, T).ok());
  CHECK(h[hs::slot::status] == 0.0);
  CHECK((T - D).norm() / D.norm() < 1e-12);
  const Vec6 ds = s1 - pt.stress;
  CHECK(ds[1] / unload[1] == Approx(Eur).epsilon(1e-10));
  CHECK(std::abs(ds[0]) < 1e-10 * std::abs(ds[1]));
  // Reloading to the point of unloading: elastic all the way (E_ur at the unloaded sigma_3, which
  // is unchanged), and the stress comes back to the one before unloading.
  Point back{s1, h};
  Vec6 s2;
  std::vector<double> h2;
  REQUIRE(step(*m, back, -unload, s2, h2, T).ok());
  CHECK(h2[hs::slot::status] == 0.0);
  CHECK((s2 - pt.stress).norm() < 1e-10 * pt.stress.norm());
  CHECK(h2[hs::slot::gamma_p] == pt.h[hs::slot::gamma_p]);
}

TEST_CASE("hardening_soil: consistent tangent against finite differences in every regime",
          "[hardening_soil]") {
  hs::Parameters P = base_set();
  P.p_p0 = 1e5;
  auto m = make(P);
  int st = -1;
  SECTION("elastic") {
    Point pt = at(*m, diag(-100, -150, -100));
    pt.h[hs::slot::gamma_p] = 1.0;
    CHECK(fd_error(*m, pt, (Vec6() << 1e-4, -2e-4, 5e-5, 3e-5, -1e-5, 2e-5).finished(), st) < 1e-6);
    CHECK(st == 0);
  }
  SECTION("shear hardening, psi = 0 and psi = 10 deg") {
    for (double psi : {0.0, 10.0}) {
      hs::Parameters Q = P;
      Q.psi = psi;
      auto mq = make(Q);
      const Point pt = at(*mq, diag(-100, -150, -100));
      CHECK(fd_error(*mq, pt, (Vec6() << 3e-4, -1e-3, 2e-4, 1e-4, -5e-5, 3e-5).finished(), st) < 1e-6);
      CHECK(st == (1 << hs::S));
    }
  }
  SECTION("shear hardening with dilatancy (Rowe: mobilised friction above phi_cv)") {
    // From isotropic 100 kPa the "psi = 10 deg" case above mobilises sin phi_m < sin phi_cv, so its
    // dilatancy is zero. Here q = 0.8 q_f at sigma_3 = 100 kPa: sin phi_m = q / (2 (sigma_3 + c cot
    // phi) + q) = 0.444 > sin phi_cv = (sin phi - sin psi) / (1 - sin phi sin psi) = 0.357, so
    // sin psi_m = 0.104 > 0 (below sin psi = 0.174, not capped).
    hs::Parameters Q = P;
    Q.psi = 10.0;
    auto mq = make(Q);
    const double sp = std::sin(deg(Q.phi)), cp = std::cos(deg(Q.phi)), spsi = std::sin(deg(Q.psi));
    const double qf = 2.0 * (Q.c * cp + 100.0 * sp) / (1.0 - sp), q = 0.8 * qf;
    const double sfm = q / (2.0 * (100.0 + Q.c * cp / sp) + q), scv = (sp - spsi) / (1.0 - sp * spsi);
    const double spm = (sfm - scv) / (1.0 - sfm * scv);
    REQUIRE(spm > 0.05);
    REQUIRE(spm < spsi);
    const Point pt = at(*mq, diag(-100, -100 - q, -100));
    CHECK(fd_error(*mq, pt, (Vec6() << 3e-5, -1e-4, 2e-5, 1e-5, -5e-6, 3e-6).finished(), st) < 1e-6);
    CHECK(st == (1 << hs::S));
  }
  SECTION("Mohr-Coulomb failure") {
    const double sp = std::sin(deg(P.phi)), cp = std::cos(deg(P.phi));
    const double qf = 2.0 * (P.c * cp + 100.0 * sp) / (1.0 - sp);
    const Point pt = at(*m, diag(-100, -100 - 0.99 * qf, -100));
    CHECK(fd_error(*m, pt, (Vec6() << 1.5e-2, -3e-2, 1.5e-2, 1e-4, 0.0, 3e-5).finished(), st) < 1e-6);
    CHECK(st == (1 << hs::M));
  }
  SECTION("cap") {
    hs::Parameters Q = base_set();
    auto mq = make(Q);
    Point pt = at(*mq, diag(-100, -110, -100));
    pt.h[hs::slot::gamma_p] = 1.0; // shear surface far away
    CHECK(fd_error(*mq, pt, (Vec6() << -5e-4, -6e-4, -4e-4, 1e-5, -2e-5, 1e-5).finished(), st) < 1e-6);
    CHECK(st == (1 << hs::C));
  }
  SECTION("shear hardening and cap (oedometer from K0_nc)") {
    hs::Parameters Q = base_set();
    auto mq = make(Q);
    const Point pt = at(*mq, diag(-50, -100, -50));
    CHECK(fd_error(*mq, pt, (Vec6() << 1e-5, -1e-3, -1e-5, 1e-5, 0.0, -1e-5).finished(), st) < 1e-6);
    CHECK(st == ((1 << hs::S) | (1 << hs::C)));
  }
  SECTION("tension cut-off: one plane and the apex") {
    hs::Parameters Q = base_set();
    Q.tension = 5.0;
    auto mq = make(Q);
    const Point pt = at(*mq, diag(-20, -20, -20));
    CHECK(fd_error(*mq, pt, (Vec6() << 3e-3, -1e-4, -1e-4, 0.0, 0.0, 0.0).finished(), st) < 1e-6);
    CHECK((st & (7 << hs::T0)) != 0); // one of the three tension planes
    Vec6 s;
    std::vector<double> h;
    Mat6 T;
    REQUIRE(step(*mq, pt, diag(5e-3, 5e-3, 5e-3), s, h, T).ok());
    CHECK(s[0] == Approx(5.0).epsilon(1e-10));
    CHECK(s[1] == Approx(5.0).epsilon(1e-10));
    CHECK(s[2] == Approx(5.0).epsilon(1e-10));
    CHECK(fd_error(*mq, pt, diag(5e-3, 5.1e-3, 4.9e-3), st) < 1e-6);
  }
}

TEST_CASE("hardening_soil: consistent tangent and return at every corner of the surfaces",
          "[hardening_soil][corner]") {
  // Each corner where two or more surfaces are active together (S shear hardening, M Mohr-Coulomb,
  // C cap, T the tension planes): one normally consolidated start on S and C (OCR = 1) and one
  // strain increment that ends there. Checked: the expected active set, the returned stress on
  // every active surface (|f_k| <= 1e-9 max(|s|, p_ref)), the consistent tangent against central
  // differences (relative 1e-6; at the apex, where the stress is fixed, the tangent and the
  // differences are zero to 1e-5 kPa per unit strain). The increments are small enough that the
  // whole increment is returned at once (no sub-increments).
  hs::Parameters P = base_set();
  P.tension = 5.0;
  auto m = make(P);
  struct Corner {
    unsigned status;
    double start[3];
    double dir[4];
    double size;
  };
  const unsigned S = 1u << hs::S, M = 1u << hs::M, C = 1u << hs::C;
  const unsigned T2 = 1u << hs::T2, T12 = (1u << hs::T1) | (1u << hs::T2), T012 = (1u << hs::T0) | T12;
  const Corner corners[] = {
      {S | C, {-20, -40, -20}, {-1.0, -1.6, 0.8, -1.4}, 5.1e-4},
      {M | C, {-100, -100, -100}, {-1.9, -0.9, 1.8, -0.9}, 9.38e-3},
      {M | C, {-20, -40, -20}, {0.5, -1.6, 1.8, 0.5}, 7.48e-4},
      {S | T2, {-100, -100, -100}, {-1.3, 2.0, 0.8, 1.0}, 2.14e-3},
      {M | T2, {-20, -40, -20}, {0.9, -0.4, 0.4, -1.9}, 6.07e-3},
      {S | C | T2, {-5, -10, -5}, {1.3, -0.2, 0.0, -0.8}, 8.35e-4},
      {M | C | T2, {-5, -10, -5}, {-0.4, 1.8, -1.5, 0.6}, 2.6e-3},
      {T12, {-20, -40, -20}, {0.4, 1.9, 1.0, 1.1}, 5.55e-4},
      {S | T12, {-5, -10, -5}, {0.0, 1.7, 1.1, 1.9}, 4.1e-4},
      {M | T12, {-20, -40, -20}, {1.2, -0.6, 1.1, 1.6}, 5.81e-3},
      {S | C | T12, {-5, -10, -5}, {1.8, -0.9, 1.4, 0.0}, 1.94e-3},
      {M | C | T12, {-5, -10, -5}, {0.6, 0.6, -1.2, 0.1}, 8.2e-3},
      {T012, {-50, -100, -50}, {1.0, 1.3, 1.4, -1.7}, 6.91e-3},
      {S | T012, {-100, -100, -100}, {1.5, 1.2, 1.4, -0.4}, 4.39e-3},
  };
  for (const Corner& c : corners) {
    INFO("expected active set " << c.status);
    const Point pt = at(*m, diag(c.start[0], c.start[1], c.start[2]));
    const Vec6 de = c.size * (Vec6() << c.dir[0], c.dir[1], c.dir[2], c.dir[3], 0.0, 0.0).finished();
    Vec6 s;
    std::vector<double> h;
    Mat6 T;
    REQUIRE(step(*m, pt, de, s, h, T).ok());
    REQUIRE(static_cast<unsigned>(h[hs::slot::status]) == c.status);
    const Eigen::Vector3d sp = -stratum::principal_tension(s); // compression positive, s1 >= s2 >= s3
    const double bound = 1e-9 * std::max(sp.cwiseAbs().maxCoeff(), P.p_ref);
    for (int k = 0; k < hs::n_surfaces; ++k)
      if (c.status & (1u << k)) {
        INFO("surface " << k);
        CHECK(std::abs(m->core().yield<double>(k, sp.data(), h[hs::slot::gamma_p], h[hs::slot::p_p])) <=
              bound);
      }
    int st = -1;
    const double err = fd_error(*m, pt, de, st);
    if ((c.status & T012) == T012) {
      CHECK(T.norm() == 0.0); // the apex: the stress is (T, T, T) whatever the strain
      CHECK(err < 1e-5);
    } else {
      CHECK(err < 1e-6);
    }
  }
}

TEST_CASE("hardening_soil: a failing local return is an outcome, not an exception", "[hardening_soil]") {
  // Non-finite input and increments far beyond anything a load step gives (the trial far outside
  // every surface) come back as an Outcome; nothing throws.
  hs::Parameters P = base_set();
  P.tension = 5.0;
  auto m = make(P);
  const Point pt = at(*m, diag(-20, -40, -20));
  Vec6 s;
  std::vector<double> h;
  Mat6 T;
  Vec6 bad = diag(1e-4, 0.0, 0.0);
  bad[2] = std::numeric_limits<double>::quiet_NaN();
  stratum::Outcome o = stratum::Outcome::success();
  CHECK_NOTHROW(o = step(*m, pt, bad, s, h, T));
  CHECK(!o.ok());
  for (double size : {0.5, 5.0, 50.0}) {
    INFO("increment " << size);
    const Vec6 huge = size * (Vec6() << 1.0, -3.0, 2.0, 1.5, -0.5, 0.7).finished();
    CHECK_NOTHROW(o = step(*m, pt, huge, s, h, T));
    if (o.ok()) {
      CHECK(s.allFinite());
      CHECK(T.allFinite());
    }
  }
}

TEST_CASE("hardening_soil: small-strain overlay, G/G0 curve, tangent floor and reversal",
          "[hardening_soil]") {
  hs::Parameters P = base_set();
  P.p_p0 = 1e5;
  P.small_strain = true;
  P.G0_ref = 100000.0;
  P.gamma_07 = 2e-4;
  auto m = make(P);
  const double sp = std::sin(deg(P.phi)), cp = std::cos(deg(P.phi)), a = 0.385;
  auto G0_at = [&](double s3) {
    return P.G0_ref * std::pow((P.c * cp + s3 * sp) / (P.c * cp + P.p_ref * sp), P.m);
  };
  auto Gur_at = [&](double s3) {
    return P.Eur_ref * std::pow((P.c * cp + s3 * sp) / (P.c * cp + P.p_ref * sp), P.m) /
           (2.0 * (1.0 + P.nu_ur));
  };
  // Primary shearing (plastic) from isotropic 100 kPa.
  Point pt = at(*m, diag(-100, -100, -100));
  Vec6 s;
  std::vector<double> h;
  Mat6 T;
  for (int i = 0; i < 5; ++i) {
    REQUIRE(step(*m, pt, diag(2e-4, -1e-3, 2e-4), s, h, T).ok());
    REQUIRE(h[hs::slot::status] == 1.0);
    pt = Point{s, h};
  }
  // The history is the accumulated deviatoric strain (plastic steps do not reset it).
  CHECK(h[hs::slot::strain_history + 1] == Approx(-4e-3).epsilon(1e-12)); // 5 x -8e-4
  // Continued primary loading: plastic, with the small-strain predictor (FD check of its tangent).
  {
    int st0 = -1;
    CHECK(fd_error(*m, pt, (Vec6() << 2e-4, -1e-3, 2e-4, 1e-5, 0.0, -1e-5).finished(), st0) < 1e-6);
    CHECK(st0 == 1);
  }
  // Unloading along the isochoric triaxial direction d = (-1/2, 1, -1/2) t, against the loading:
  // every principal direction reverses, the history starts again from zero, gamma_hist = 1.5 t and
  // the change of sigma_yy - sigma_xx is 2 G_sec gamma_hist.
  const Vec6 dir = diag(-0.5, 1.0, -0.5);
  auto secant = [&](const Point& from, double gamma, Mat6& tangent) {
    const double t = gamma / 1.5;
    Vec6 s1;
    std::vector<double> h1;
    REQUIRE(step(*m, from, t * dir, s1, h1, tangent).ok());
    CHECK(h1[hs::slot::status] == 0.0);
    return ((s1[1] - s1[0]) - (from.stress[1] - from.stress[0])) / (2.0 * gamma);
  };
  const double s3r = -pt.stress[0], G0 = G0_at(s3r), Gur = Gur_at(s3r), g07 = P.gamma_07;
  for (double g : {1e-5, 1e-4, g07}) {
    INFO("gamma_hist = " << g);
    // One step from the reversal: the chord from 0 is the secant, exactly.
    CHECK(secant(pt, g, T) == Approx(G0 / (1.0 + a * g / g07)).epsilon(1e-12));
    // The tangent along the path: d tau / d gamma = G0 / (1 + a gamma / gamma_07)^2 (the
    // predictor's derivative by central differences: 1e-8).
    const double tangent_shear = (T.row(1) - T.row(0)).dot(dir) / 3.0;
    CHECK(tangent_shear == Approx(G0 / std::pow(1.0 + a * g / g07, 2)).epsilon(1e-8));
  }
  // Beyond the cut-off strain the tangent is G_ur.
  const double gc = g07 / a * (std::sqrt(G0 / Gur) - 1.0);
  (void)secant(pt, 1.2 * gc, T);
  CHECK((T.row(1) - T.row(0)).dot(dir) / 3.0 == Approx(Gur).epsilon(1e-8));
  (void)secant(pt, 0.9 * gc, T);
  CHECK((T.row(1) - T.row(0)).dot(dir) / 3.0 > Gur);
  // FD check of the whole update's tangent (unloading) at gamma = 1e-4, and beyond the cut-off.
  // The increments carry a little shear: where the increment's principal axes are those of a
  // fully reset history, gamma_1 grows with the absolute value of a shear perturbation (a kink
  // of the projection, README), so no derivative exists exactly there. The difference step is
  // 1e-5 of the increment: the eigenbasis of the increment enters the projection, and its
  // rounding (1e-16) over a step of 1e-7 of the increment already costs about 4e-7.
  int st = -1;
  const Vec6 off = (Vec6() << 1e-6, 0.0, -2e-6, 3e-6, 0.0, -1e-6).finished();
  CHECK(fd_error(*m, pt, (1e-4 / 1.5) * dir + off, st, 1e-5) < 1e-6);
  CHECK(st == 0);
  CHECK(fd_error(*m, pt, (1.5 * gc / 1.5) * dir + off, st, 1e-5) < 1e-6);
  // A partial reset: after the triaxial loading H = diag(h, -2h, h) (h > 0), a plane increment
  // (+d, 0, -d) reverses direction 3 only (H_zz d < 0), which is set to zero before the increment
  // is added; direction 1 keeps its memory and accumulates; direction 2 (no strain) is kept.
  {
    Vec6 s1;
    std::vector<double> h1;
    const double d = 1e-6;
    REQUIRE(step(*m, pt, diag(d, 0.0, -d), s1, h1, T).ok());
    const double hx = pt.h[hs::slot::strain_history], hy = pt.h[hs::slot::strain_history + 1];
    CHECK(h1[hs::slot::strain_history] == Approx(hx + d).epsilon(1e-12));
    CHECK(h1[hs::slot::strain_history + 1] == Approx(hy).epsilon(1e-12));
    CHECK(h1[hs::slot::strain_history + 2] == Approx(-d).epsilon(1e-9));
    CHECK(fd_error(*m, pt, diag(d, 0.0, -d) + 1e-7 * off, st, 1e-5) < 1e-6);
  }
}

TEST_CASE("hardening_soil: small-strain overlay in closed form: G/G0 = 0.722 at gamma_07, simple shear, a "
          "strain cycle, overshooting",
          "[hardening_soil]") {
  // Constant G0 (m = 0) and a point far inside the shear hardening surface (gamma_p = 1) and the
  // cap, so that every step is elastic and the overlay alone acts; isotropic 100 kPa.
  hs::Parameters P = base_set();
  P.m = 0.0;
  P.p_p0 = 1e5;
  P.small_strain = true;
  P.G0_ref = 100000.0;
  P.gamma_07 = 2e-4;
  auto m = make(P);
  const double a = 0.385, G0 = P.G0_ref, g07 = P.gamma_07;
  auto fresh = [&] {
    Point pt = at(*m, diag(-100, -100, -100));
    pt.h[hs::slot::gamma_p] = 1.0;
    return pt;
  };
  auto walk = [&](Point pt, const Vec6& increment, int steps) {
    Vec6 s;
    std::vector<double> h;
    Mat6 T;
    for (int i = 0; i < steps; ++i) {
      REQUIRE(step(*m, pt, increment, s, h, T).ok());
      REQUIRE(h[hs::slot::status] == 0.0);
      pt = Point{s, h};
    }
    return pt;
  };
  SECTION("isochoric triaxial to gamma_07 = eps_1 - eps_3 in 50 steps: G_sec = G0 / 1.385 = 0.722 G0") {
    const Point e = walk(fresh(), (g07 / 1.5 / 50.0) * diag(-0.5, 1.0, -0.5), 50);
    const double Gsec = (e.stress[1] - e.stress[0]) / (2.0 * g07);
    CHECK(Gsec / G0 == Approx(1.0 / 1.385).epsilon(1e-9));
    CHECK(Gsec / G0 == Approx(0.722).margin(2.2e-5));
  }
  // Simple shear: gamma_hist = (sqrt(3)/2) gamma_xy, so tau_xy = F(gamma_xy) with
  // F(x) = G0 x / (1 + a k x / gamma_07), k = sqrt(3)/2.
  const double k = std::sqrt(3.0) / 2.0;
  auto F = [&](double x) { return G0 * x / (1.0 + a * k * x / g07); };
  auto shear = [](double g) {
    Vec6 e = Vec6::Zero();
    e[3] = g;
    return e;
  };
  SECTION("simple shear: tau_xy = F(gamma_xy), G/G0 = 1/(1 + a sqrt(3)/2) = 0.750 at gamma_07") {
    const Point e = walk(fresh(), shear(g07 / 40.0), 40);
    CHECK(e.stress[3] == Approx(F(g07)).epsilon(1e-9));
    CHECK(e.stress[3] / (G0 * g07) == Approx(1.0 / (1.0 + a * k)).epsilon(1e-9));
  }
  SECTION("a strain cycle +-gamma_a: every reversal restarts the curve (no Masing doubling)") {
    const double ga = g07;
    const Point up = walk(fresh(), shear(ga / 20.0), 20);
    const Point down = walk(up, shear(-ga / 20.0), 40); // to -gamma_a
    CHECK(down.stress[3] == Approx(F(ga) - F(2.0 * ga)).epsilon(1e-9));
    const Point again = walk(down, shear(ga / 20.0), 40); // back to +gamma_a: the loop closes
    CHECK(again.stress[3] == Approx(F(ga)).epsilon(1e-9));
    // Frame invariance: the same cycle in axes rotated by 30 degrees about z gives the rotated
    // stresses (the history tensor is kept in the global axes).
    const double c = std::cos(deg(30.0)), sn = std::sin(deg(30.0));
    Eigen::Matrix3d R;
    R << c, -sn, 0, sn, c, 0, 0, 0, 1;
    auto rotated = [&](double g) {
      Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
      e(0, 1) = e(1, 0) = 0.5 * g;
      const Eigen::Matrix3d r = R * e * R.transpose();
      Vec6 v;
      v << r(0, 0), r(1, 1), r(2, 2), 2.0 * r(0, 1), 2.0 * r(1, 2), 2.0 * r(0, 2);
      return v;
    };
    const Point rup = walk(fresh(), rotated(ga / 20.0), 20);
    const Point rdown = walk(rup, rotated(-ga / 20.0), 40);
    const Eigen::Matrix3d back = R.transpose() * stratum::stress_tensor(rdown.stress) * R;
    CHECK(back(0, 1) == Approx(down.stress[3]).epsilon(1e-9));
    CHECK(back(0, 0) == Approx(down.stress[0]).epsilon(1e-9));
  }
  SECTION(
      "overshooting: a tiny unloading resets the memory; the reloading is stiffer than the virgin curve") {
    const double g1 = g07, d = 1e-3 * g07;
    const Point up = walk(fresh(), shear(g1 / 20.0), 20);
    const Point back = walk(up, shear(-d), 1);
    const Point on = walk(back, shear((g1 + d) / 20.0), 20); // to 2 g1
    CHECK(on.stress[3] == Approx(F(g1) - F(d) + F(g1 + d)).epsilon(1e-9));
    CHECK(on.stress[3] > F(2.0 * g1) * 1.2);
  }
}

TEST_CASE("hardening_soil: bad parameters are located errors", "[hardening_soil]") {
  const std::string text = std::string(base_toml) + "[initial]\np = 100.0\n[[paths]]\ntype = \"oedometer\"\n"
                                                    "axial_strain = -0.01\nsteps = 2\n";
  std::string bad = text;
  bad.replace(bad.find("Eur_ref = 60000.0"), 17, "Eur_ref = 30000.0");
  try {
    (void)stratum::PointDriver::from_string(bad, "bad.toml", {STRATUM_PLUGIN_DIR});
    FAIL("no error");
  } catch (const stratum::Error& e) {
    CHECK(std::string(e.what()).find("bad.toml:6:") != std::string::npos);
    CHECK(std::string(e.what()).find("2 E50_ref") != std::string::npos);
  }
  std::string ss = text + "";
  ss.replace(ss.find("K0_nc = 0.5"), 11, "K0_nc = 0.5\nsmall_strain = true");
  CHECK_THROWS_AS(stratum::PointDriver::from_string(ss, "bad.toml", {STRATUM_PLUGIN_DIR}), stratum::Error);
}

TEST_CASE("hardening_soil: the loess point inputs", "[hardening_soil]") {
  const double sp = std::sin(deg(26.0)), cp = std::cos(deg(26.0)), c = 10.0;
  auto run = [](const std::string& name) {
    auto d = stratum::PointDriver::from_file(
        std::string(STRATUM_SOURCE_DIR) + "/inputs/point/" + name + ".toml", {STRATUM_PLUGIN_DIR});
    auto r = d->run();
    REQUIRE(r.outcome.ok());
    return r;
  };
  // CID at 25, 40, 80 kPa: the end of the path is on the Mohr-Coulomb surface.
  for (double s3 : {25.0, 40.0, 80.0}) {
    INFO("sigma_3 = " << s3);
    char name[32];
    std::snprintf(name, sizeof name, "loess_hs_s%03d", static_cast<int>(s3));
    const auto r = run(name);
    const auto& last = r.rows.back();
    CHECK(last.stress[0] - last.stress[1] == Approx(2.0 * (c * cp + s3 * sp) / (1.0 - sp)).epsilon(1e-8));
  }
  // Oedometer: tangent modulus at sigma_1 = 100 kPa is Eoed_ref = 8160 kPa (2 %).
  {
    const auto r = run("loess_hs_oedometer");
    bool found = false;
    for (std::size_t i = 1; i + 1 < r.rows.size(); ++i)
      if (-r.rows[i].stress[1] <= 100.0 && -r.rows[i + 1].stress[1] > 100.0) {
        const auto &a = r.rows[i - 1], &b = r.rows[i + 1];
        CHECK((b.stress[1] - a.stress[1]) / (b.strain[1] - a.strain[1]) == Approx(8160.0).epsilon(0.02));
        found = true;
      }
    CHECK(found);
  }
  // Small strain: load, unload 0.03 %, reload: back at the turning point the stress is the one
  // before unloading (the branch is elastic and path independent).
  {
    const auto r = run("loess_hs_small_strain");
    REQUIRE(r.rows.size() == 1 + 40 + 30 + 100);
    const auto &turn = r.rows[40], &back = r.rows[85]; // 15 reloading steps of 2e-5
    CHECK(back.strain[1] == Approx(turn.strain[1]).epsilon(1e-9));
    CHECK((back.stress - turn.stress).norm() < 1e-8 * turn.stress.norm());
  }
}

TEST_CASE("hardening_soil: a residual-only update does not read the caller's tangent storage",
          "[hardening_soil]") {
  // With want_tangent = false the material leaves out.tangent as it is; it used to check it for
  // NaN anyway, so uninitialised caller storage failed the update at random (found by the
  // sanitizer build: the pile scene's first assembly stopped with "non-finite stress or tangent").
  const auto m = make(base_set());
  const Point pt = at(*m, diag(-100.0, -100.0, -100.0));
  const Vec6 e0 = Vec6::Zero();
  const Vec6 de = diag(-1e-4, 0.0, 0.0);
  Vec6 s;
  std::vector<double> h(pt.h.size(), 0.0);
  Mat6 T = Mat6::Constant(std::numeric_limits<double>::quiet_NaN());
  stratum::MaterialOutput out{s, h, T};
  stratum::MaterialInput in{pt.stress, e0, pt.h, de, {0, 0}};
  in.want_tangent = false;
  REQUIRE(m->update(in, out).ok());
  CHECK(s.allFinite());
  CHECK(std::isnan(T(0, 0))); // left as it was
}

TEST_CASE("hardening_soil: every status bitmask has a name for the VTK legend",
          "[hardening_soil][point_status]") {
  const auto m = make(base_set());
  const auto names = m->status_names();
  REQUIRE(names.size() == 64); // bits 0-5: S, M, C and the three tension planes
  CHECK(names[0] == "elastic");
  CHECK(names[1] == "shear hardening");
  CHECK(names[1 | 4] == "shear hardening + cap");
  CHECK(names[2 | 8] == "Mohr-Coulomb failure + tension cut-off");
  CHECK(names[8 | 16 | 32] == "tension apex");
}

} // namespace test_hardening_soil
