// Tests of Lade's double-hardening model (plugins/lade): the consistent, unsymmetric tangent
// against finite differences in the cone-only, cap-only and both-active regimes, elastic
// unloading, the collapse-work closed form on isotropic compression, and a drained triaxial
// path (contraction, then dilation; the failure criterion reached at peak).
//
// Parameter set: see dense_sand() and README.md -- NOT a published set (none of the
// double-hardening sets of Lade 1977 could be retrieved); chosen to be physically defensible.
#include "lade/lade.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <optional>

namespace test_lade {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace ld = stratum::lade;

/// Our dense-sand set (README.md, "Parameter set"): not from a publication.
ld::Constants dense_sand() {
  ld::Constants c;
  c.pa = 100.0;
  c.Kur = 900.0;
  c.n = 0.4;
  c.nu = 0.2;
  c.eta1 = 80.0;
  c.m = 0.1;
  c.P = 0.05;
  c.l = 1.0;
  c.alpha = 1.5;
  c.beta = 0.0;
  c.S = 0.5;
  c.t = -5.0;
  c.R = 0.0;
  c.C = 0.0002;
  c.p = 0.8;
  return c;
}

Vec6 isotropic(double p) { // compression-positive p -> tension-positive stress
  Vec6 s = Vec6::Zero();
  s[0] = s[1] = s[2] = -p;
  return s;
}

struct Point {
  const ld::Lade& mat;
  Vec6 stress;
  Vec6 strain = Vec6::Zero();
  std::array<double, 4> history{};
  Mat6 tangent = Mat6::Zero();

  Point(const ld::Lade& m, const Vec6& s0) : mat(m), stress(s0) { mat.init_history(stress, history); }
  stratum::Outcome trial(const Vec6& de, Vec6& s, std::array<double, 4>& h, Mat6& T) const {
    const stratum::MaterialInput in{stress, strain, history, de, {}};
    stratum::MaterialOutput out{s, h, T};
    return mat.update(in, out);
  }
  stratum::Outcome step(const Vec6& de) {
    Vec6 s;
    std::array<double, 4> h{};
    Mat6 T;
    const stratum::Outcome o = trial(de, s, h, T);
    if (o.ok()) stress = s, strain += de, history = h, tangent = T;
    return o;
  }
  [[nodiscard]] int active() const { return static_cast<int>(history[2]); }
};

/// Central finite-difference tangent of one update from the committed state of p.
Mat6 fd_tangent(const Point& p, const Vec6& de, double h) {
  Mat6 J;
  for (int j = 0; j < 6; ++j) {
    Vec6 dp = de, dm = de, sp, sm;
    dp[j] += h, dm[j] -= h;
    std::array<double, 4> hh{};
    Mat6 T;
    REQUIRE(p.trial(dp, sp, hh, T).ok());
    REQUIRE(p.trial(dm, sm, hh, T).ok());
    J.col(j) = (sp - sm) / (2.0 * h);
  }
  return J;
}

double rel_diff(const Mat6& a, const Mat6& b) { return (a - b).norm() / b.norm(); }

/// Drained triaxial step: axial (yy) strain increment dea (tension positive), lateral stresses
/// (xx, zz) held at sigma3 (compression positive) by Newton on the lateral strains with the tangent.
stratum::Outcome triaxial_step(Point& p, double dea, Vec6& de_guess, double sigma3) {
  Vec6 de = de_guess;
  de[1] = dea;
  const double sx = -sigma3, sz = -sigma3;
  for (int it = 0; it < 30; ++it) {
    Vec6 s;
    std::array<double, 4> h{};
    Mat6 T;
    const stratum::Outcome o = p.trial(de, s, h, T);
    if (!o.ok()) return o;
    const Eigen::Vector2d r(s[0] - sx, s[2] - sz);
    if (r.norm() <= 1e-11 * std::abs(sx)) {
      de_guess = de;
      return p.step(de);
    }
    Eigen::Matrix2d J;
    J << T(0, 0), T(0, 2), T(2, 0), T(2, 2);
    const Eigen::Vector2d d = J.lu().solve(-r);
    de[0] += d[0], de[2] += d[1];
  }
  return stratum::Outcome::failure(stratum::Status::not_converged, "lateral stress not held");
}

} // namespace

TEST_CASE("lade: tangent against finite differences, cone only, cap only, both, elastic", "[lade]") {
  const ld::Lade mat(dense_sand());
  const double h = 1e-8;

  SECTION("cap only: isotropic compression from a normally consolidated state") {
    Point p(mat, isotropic(100.0));
    Vec6 de = Vec6::Zero();
    de[0] = de[1] = de[2] = -1e-3 / 3.0;
    de[3] = 1e-9; // break the exact isotropy only marginally
    Vec6 s;
    std::array<double, 4> hh{};
    Mat6 T;
    REQUIRE(p.trial(de, s, hh, T).ok());
    CHECK(static_cast<int>(hh[2]) == 2);
    const double err = rel_diff(T, fd_tangent(p, de, h));
    INFO("cap only: relative difference " << err);
    CHECK(err < 1e-5);
    CHECK((T - T.transpose()).norm() < 1e-8 * T.norm()); // associated cap, frozen moduli: symmetric
  }

  SECTION("cone only: shear after unloading inside the cap") {
    // Consolidate to 200 kPa, unload to 100 kPa: the cap stays at 200 kPa, the cone is virgin.
    Vec6 de;
    Point q(mat, isotropic(100.0));
    q.history[1] = mat.cap_work(-isotropic(200.0)); // cap at the 200 kPa isotropic state
    de << 2e-4, -6e-4, 1e-4, 3e-5, -2e-5, 1e-5;
    Vec6 s;
    std::array<double, 4> hh{};
    Mat6 T;
    REQUIRE(q.trial(de, s, hh, T).ok());
    CHECK(static_cast<int>(hh[2]) == 1);
    const double err = rel_diff(T, fd_tangent(q, de, h));
    INFO("cone only: relative difference " << err);
    CHECK(err < 1e-5);
    CHECK((T - T.transpose()).norm() > 1e-3 * T.norm()); // non-associated cone: unsymmetric
  }

  SECTION("both active: triaxial loading from a normally consolidated state, then a general increment") {
    Point p(mat, isotropic(100.0));
    Vec6 g = Vec6::Zero();
    for (int k = 0; k < 40; ++k) REQUIRE(triaxial_step(p, -1e-4, g, 100.0).ok());
    Vec6 de;
    de << 1e-5, -2e-4, 2e-5, 4e-5, -1e-5, 2e-5;
    Vec6 s;
    std::array<double, 4> hh{};
    Mat6 T;
    REQUIRE(p.trial(de, s, hh, T).ok());
    CHECK(static_cast<int>(hh[2]) == 3);
    const double err = rel_diff(T, fd_tangent(p, de, h));
    INFO("both active: relative difference " << err);
    CHECK(err < 1e-5);
    CHECK((T - T.transpose()).norm() > 1e-3 * T.norm());
  }

  SECTION("both active, a large increment split into 8 substeps (sensitivities chained)") {
    ld::Constants c8 = dense_sand();
    c8.substeps = 8;
    const ld::Lade mat8(c8);
    Point p(mat8, isotropic(100.0));
    Vec6 de;
    de << -1e-3, -3.2e-3, -1e-3, 4e-4, 0.0, 0.0;
    Vec6 s;
    std::array<double, 4> hh{};
    Mat6 T;
    REQUIRE(p.trial(de, s, hh, T).ok());
    CHECK(hh[3] == 8.0);
    CHECK(static_cast<int>(hh[2]) == 3);
    const double err = rel_diff(T, fd_tangent(p, de, 1e-7));
    INFO("large increment: relative difference " << err);
    CHECK(err < 1e-5);
  }
}

TEST_CASE("lade: elastic unloading follows E_ur = K_ur pa (sigma3/pa)^n", "[lade]") {
  const ld::Constants c = dense_sand();
  const ld::Lade mat(c);
  Point p(mat, isotropic(100.0));
  Vec6 g = Vec6::Zero();
  for (int k = 0; k < 40; ++k) REQUIRE(triaxial_step(p, -1e-4, g, 100.0).ok());
  const std::array<double, 4> h0 = p.history;
  // Axial unloading: a small axial extension increment, lateral strains free (stress held).
  Vec6 g2 = Vec6::Zero();
  const Vec6 s0 = p.stress;
  REQUIRE(triaxial_step(p, 1e-5, g2, 100.0).ok());
  CHECK(p.active() == 0);
  CHECK(p.history[0] == h0[0]);
  CHECK(p.history[1] == h0[1]);
  // sigma3 = 100 kPa: E_ur = 900 * 100 * 1 = 90 000 kPa; lateral stress held, so
  // d sigma_axial = E_ur d eps_axial exactly (constant moduli within the increment).
  const double E = c.Kur * c.pa * std::pow(100.0 / c.pa, c.n);
  CHECK((p.stress[1] - s0[1]) == Approx(E * 1e-5).epsilon(1e-9));
  CHECK(g2[0] == Approx(-c.nu * 1e-5).epsilon(1e-8));
  // The tangent is the elastic matrix: symmetric.
  CHECK((p.tangent - p.tangent.transpose()).norm() < 1e-12 * p.tangent.norm());
}

TEST_CASE("lade: isotropic compression obeys the collapse work law W_c = C pa (f_c/pa^2)^p", "[lade]") {
  const ld::Constants c = dense_sand();
  const ld::Lade mat(c);
  Point p(mat, isotropic(50.0));
  // Plastic work computed outside the model: sum of sigma_{n+1} . (d eps - D_n^-1 d sigma),
  // with D_n the (frozen) elastic matrix of each step; compared with Lade's closed form.
  double W = p.history[1];
  for (int k = 0; k < 200; ++k) {
    Vec6 de = Vec6::Zero();
    de[0] = de[1] = de[2] = -2e-5;
    const Vec6 s_n = p.stress;
    const Mat6 D = mat.frozen(-s_n).D;
    REQUIRE(p.step(de).ok());
    CHECK(p.active() == 2);
    const Vec6 dep = de - D.lu().solve(p.stress - s_n);
    W += p.stress.dot(dep);
  }
  const double pm = -p.stress[0];
  CHECK(-p.stress[1] == Approx(pm).epsilon(1e-12));
  const double closed = c.C * c.pa * std::pow(3.0 * pm * pm / (c.pa * c.pa), c.p);
  INFO("p = " << pm << " kPa, W external = " << W << ", closed form " << closed);
  CHECK(W == Approx(closed).epsilon(1e-6));
  CHECK(p.history[1] == Approx(closed).epsilon(1e-10));
  CHECK(p.history[0] < 1e-12 * closed); // the cone does no work on isotropic paths (round-off only)
}

TEST_CASE("lade: drained triaxial path, dense sand: contraction, then dilation, failure at peak", "[lade]") {
  const ld::Constants c = dense_sand();
  const ld::Lade mat(c);
  Point p(mat, isotropic(100.0));
  Vec6 g = Vec6::Zero();
  double ev_max = -1.0, ea_at_ev_max = 0.0, q_peak = 0.0, fp_at_peak = 0.0, ea_peak = 0.0, ev_end = 0.0;
  for (int k = 0; k < 500; ++k) {
    REQUIRE(triaxial_step(p, -1e-4, g, 100.0).ok());
    CHECK(-p.stress[0] == Approx(100.0).epsilon(1e-9));
    const double ea = -p.strain[1], ev = -(p.strain[0] + p.strain[1] + p.strain[2]);
    const double q = p.stress[0] - p.stress[1];
    if (ev > ev_max) ev_max = ev, ea_at_ev_max = ea;
    if (q > q_peak) q_peak = q, fp_at_peak = mat.fp(-p.stress), ea_peak = ea;
    ev_end = ev;
  }
  INFO("max contraction " << ev_max << " at eps_a " << ea_at_ev_max << "; peak q " << q_peak
                          << " kPa at eps_a " << ea_peak << " with f_p " << fp_at_peak
                          << "; eps_v at eps_a = 5 %: " << ev_end);
  CHECK(ev_max > 1e-3);       // contraction first
  CHECK(ea_at_ev_max < 0.02); // turns to dilation well before the end
  CHECK(ev_end < 0.0);        // net dilation at eps_a = 5 %
  CHECK(ea_peak < 0.049);     // a peak inside the path, then softening
  // Lade's failure criterion (I1^3/I3 - 27)(I1/pa)^m = eta1 at the peak (the hardening law's maximum).
  CHECK(fp_at_peak == Approx(c.eta1).epsilon(1e-3));
  CHECK(fp_at_peak <= c.eta1 * (1.0 + 1e-9));
}

TEST_CASE("lade: the peak of drained triaxial paths lies on the failure surface f_p = eta1", "[lade]") {
  // For sigma3 = 50, 100, 200 kPa: the peak deviator of the path (the maximum of q over the
  // axial strain, located by golden-section search on the last increment around the sampled
  // maximum) against q_f solved from (I1^3/I3 - 27)(I1/pa)^m = eta1 with s = (s3 + q, s3, s3).
  const ld::Constants c = dense_sand();
  const ld::Lade mat(c);
  for (double s3 : {50.0, 100.0, 200.0}) {
    INFO("sigma3 = " << s3);
    auto fp = [&](double q) {
      const double I1 = 3.0 * s3 + q, I3 = (s3 + q) * s3 * s3;
      return (I1 * I1 * I1 / I3 - 27.0) * std::pow(I1 / c.pa, c.m) - c.eta1;
    };
    double lo = 0.0, hi = 100.0 * s3;
    for (int it = 0; it < 200 && hi - lo > 1e-13 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      (fp(mid) < 0.0 ? lo : hi) = mid;
    }
    const double qf = 0.5 * (lo + hi);
    // The path, sampled every 1e-4 of axial strain; keep the state before the sampled maximum.
    const double dea = -1e-4;
    Point p(mat, isotropic(s3));
    Vec6 g = Vec6::Zero();
    std::optional<Point> before(p), before2(p);
    Vec6 g_before = g, g_before2 = g;
    double q_best = -1.0;
    for (int k = 0; k < 800; ++k) {
      const Point keep = p;
      const Vec6 gk = g;
      REQUIRE(triaxial_step(p, dea, g, s3).ok());
      const double q = p.stress[0] - p.stress[1];
      if (q > q_best) {
        q_best = q;
        before2.emplace(*before), g_before2 = g_before;
        before.emplace(keep), g_before = gk;
      } else if (k > 10) {
        break;
      }
    }
    // q after one increment x from the state two samples before the maximum, x in [0, 3 dea].
    auto q_at = [&](double x) {
      Point t = *before2;
      Vec6 gg = g_before2 * (x / dea);
      REQUIRE(triaxial_step(t, x, gg, s3).ok());
      return t.stress[0] - t.stress[1];
    };
    const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = 0.0, b = 3.0 * dea;
    double x1 = b - phi * (b - a), x2 = a + phi * (b - a), q1 = q_at(x1), q2 = q_at(x2);
    for (int it = 0; it < 60; ++it) {
      if (q1 > q2) {
        b = x2, x2 = x1, q2 = q1, x1 = b - phi * (b - a), q1 = q_at(x1);
      } else {
        a = x1, x1 = x2, q1 = q2, x2 = a + phi * (b - a), q2 = q_at(x2);
      }
    }
    const double q_peak = std::max(q1, q2);
    CHECK(q_peak >= q_best); // the search refines the sampled maximum
    CHECK(q_peak == Approx(qf).epsilon(1e-6));
  }
}

TEST_CASE("lade: point_status names the cap, the cone with the cap, the cone alone and the softening cone",
          "[lade][point_status]") {
  const ld::Constants c = dense_sand();
  const ld::Lade mat(c);
  REQUIRE(mat.status_names().size() == 5);
  // Isotropic compression: the cap alone (the cone does no work on isotropic paths).
  Point p(mat, isotropic(100.0));
  for (int k = 0; k < 3; ++k) {
    Vec6 de = Vec6::Zero();
    de[0] = de[1] = de[2] = -1e-4;
    REQUIRE(p.step(de).ok());
  }
  CHECK(mat.point_status(p.stress, p.history) == 2);
  INFO("isotropic compression to p = " << -p.stress[0] << " kPa");
  // Isotropic unloading to 100 kPa: elastic (the cap left behind).
  const double p_max = -p.stress[0];
  for (int k = 0; k < 200 && -p.stress[0] > 100.0; ++k) {
    Vec6 de = Vec6::Zero();
    de[0] = de[1] = de[2] = 1e-5;
    REQUIRE(p.step(de).ok());
  }
  CHECK(mat.point_status(p.stress, p.history) == 0);
  // Drained triaxial compression at sigma3 = 100 kPa, below the old cap (f_c = s:s < 3 p_max^2):
  // the cone alone; later, with s:s past the old cap, cone and cap; past the peak, softening.
  const double s3 = -p.stress[0];
  Vec6 g = Vec6::Zero();
  REQUIRE(triaxial_step(p, -1e-4, g, s3).ok());
  REQUIRE(ld::fc(-p.stress) < 3.0 * p_max * p_max);
  CHECK(mat.point_status(p.stress, p.history) == 1);
  bool both = false, soft = false;
  double q_peak = 0.0;
  for (int k = 0; k < 500; ++k) {
    REQUIRE(triaxial_step(p, -1e-4, g, s3).ok());
    const double q = p.stress[0] - p.stress[1];
    q_peak = std::max(q_peak, q);
    const int st = mat.point_status(p.stress, p.history);
    both = both || st == 3;
    // Past the peak of q: W_cone > W_peak (constant at constant sigma3, beta = 0), the
    // softening branch of H1.
    if (q < q_peak * (1.0 - 1e-9)) {
      CHECK(st == 4);
      soft = true;
    }
  }
  CHECK(both);
  CHECK(soft);
}

} // namespace test_lade
