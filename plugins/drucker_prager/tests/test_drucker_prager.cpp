// Tests of the Drucker-Prager material (plugins/drucker_prager): the four Mohr-Coulomb matchings,
// the elastic, cone and apex regimes, consistent tangents against central differences, the
// triaxial plastic modulus of verification.md M2 and a proportional path in 1 and 1000 steps.
#include "drucker_prager/drucker_prager.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace test_drucker_prager {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace dp = stratum::drucker_prager;
namespace pl = stratum::plasticity;

constexpr std::array<pl::Scheme, 6> all_schemes{pl::Scheme::forward_euler, pl::Scheme::modified_euler,
                                                pl::Scheme::trapezoidal,   pl::Scheme::midpoint,
                                                pl::Scheme::cutting_plane, pl::Scheme::closest_point};

dp::Parameters base_parameters() {
  dp::Parameters p;
  p.E = 2.0e4;
  p.nu = 0.3;
  p.c = 10.0;
  p.phi = 30.0;
  p.psi = 10.0;
  p.H_c = 0.0;
  p.cone = dp::Cone::compression;
  return p;
}

pl::Settings settings(pl::Scheme scheme = pl::Scheme::closest_point) {
  pl::Settings s;
  s.scheme = scheme;
  s.ftol = 1e-12;
  s.substeps = 50;
  return s;
}

struct Response {
  Vec6 stress = Vec6::Zero();
  double q = 0.0;
  Mat6 tangent = Mat6::Zero();
  stratum::Outcome outcome;
};

Response respond(const dp::DruckerPrager& m, const Vec6& stress_n, double q_n, const Vec6& de) {
  Response r;
  const Vec6 strain_n = Vec6::Zero();
  const std::array<double, 1> h_n{q_n};
  std::array<double, 1> h{-1.0};
  stratum::MaterialOutput out{r.stress, h, r.tangent};
  r.outcome = m.update(stratum::MaterialInput{stress_n, strain_n, h_n, de, {}}, out);
  r.q = h[0];
  return r;
}

/// Central-difference tangent d stress / d strain.
Mat6 fd_tangent(const dp::DruckerPrager& m, const Vec6& stress_n, double q_n, const Vec6& de,
                double h = 1e-7) {
  Mat6 fd;
  for (int j = 0; j < 6; ++j) {
    Vec6 dp_ = de, dm = de;
    dp_[j] += h;
    dm[j] -= h;
    fd.col(j) = (respond(m, stress_n, q_n, dp_).stress - respond(m, stress_n, q_n, dm).stress) / (2.0 * h);
  }
  return fd;
}

Mat6 compliance(double E, double nu) { return dp::elastic_stiffness(E, nu).inverse(); }

double yield(const dp::DruckerPrager& m, const Vec6& s, double q) {
  const std::array<double, 1> qq{q};
  return m.model().yield(0, s, qq);
}

Vec6 hydrostatic(double p) { return p * pl::identity(); }

/// Mixed control: the strain increment whose components `strain_ctl` are given in de and whose
/// other components make the stress equal to `target` there. Newton with the material tangent.
Response mixed(const dp::DruckerPrager& m, const Vec6& stress_n, double q_n, Vec6& de,
               const std::array<bool, 6>& stress_ctl, const Vec6& target) {
  std::vector<int> u;
  for (int i = 0; i < 6; ++i)
    if (stress_ctl[static_cast<std::size_t>(i)]) u.push_back(i);
  const int n = static_cast<int>(u.size());
  Response r = respond(m, stress_n, q_n, de);
  for (int it = 0; it < 50; ++it) {
    Eigen::VectorXd res(n);
    Eigen::MatrixXd J(n, n);
    for (int a = 0; a < n; ++a) {
      res[a] = r.stress[u[a]] - target[u[a]];
      for (int b = 0; b < n; ++b) J(a, b) = r.tangent(u[a], u[b]);
    }
    if (res.cwiseAbs().maxCoeff() < 1e-11 * std::max(1.0, target.cwiseAbs().maxCoeff())) break;
    const Eigen::VectorXd dx = J.fullPivLu().solve(-res);
    for (int a = 0; a < n; ++a) de[u[a]] += dx[a];
    r = respond(m, stress_n, q_n, de);
  }
  return r;
}

} // namespace

TEST_CASE("drucker_prager: the four cones for phi = 30, c = 10", "[point]") {
  const double phi = dp::radians(30.0), c = 10.0, r3 = std::sqrt(3.0);
  struct Case {
    dp::Cone cone;
    double alpha, K;
  };
  // Hand values: sin 30 = 1/2, cos 30 = sqrt(3)/2, tan^2 30 = 1/3.
  //   compression: alpha = 1 / (2.5 sqrt 3), K = 30 / 2.5 = 12
  //   extension:   alpha = 1 / (3.5 sqrt 3), K = 30 / 3.5
  //   plane strain and inscribed (the same cone): alpha = 1 / sqrt(39), K = 30 / sqrt(13)
  const std::vector<Case> cases{{dp::Cone::compression, 1.0 / (2.5 * r3), 12.0},
                                {dp::Cone::extension, 1.0 / (3.5 * r3), 30.0 / 3.5},
                                {dp::Cone::plane_strain, 1.0 / std::sqrt(39.0), 30.0 / std::sqrt(13.0)},
                                {dp::Cone::inscribed, 1.0 / std::sqrt(39.0), 30.0 / std::sqrt(13.0)}};
  for (const Case& k : cases) {
    const dp::ConeConstants cc = dp::cone_constants(k.cone, phi);
    CHECK(cc.alpha == Approx(k.alpha).epsilon(1e-14));
    CHECK(cc.k * c == Approx(k.K).epsilon(1e-14));
    // Every cone has its apex at the Mohr-Coulomb apex c cot(phi).
    CHECK(cc.k * c / (3.0 * cc.alpha) == Approx(c / std::tan(phi)).epsilon(1e-14));
  }
  CHECK(dp::cone_constants(dp::Cone::compression, phi).alpha == Approx(0.23094010767585030).epsilon(1e-15));
  CHECK(dp::cone_constants(dp::Cone::extension, phi).alpha == Approx(0.16495721976846450).epsilon(1e-14));
  CHECK(dp::cone_constants(dp::Cone::plane_strain, phi).alpha == Approx(0.16012815380508713).epsilon(1e-14));

  // Geometric meaning, with Mohr-Coulomb written for sigma_1 >= sigma_3 (tension positive):
  //   (sigma_1 - sigma_3) + (sigma_1 + sigma_3) sin(phi) = 2 c cos(phi).
  const double s = std::sin(phi), co = std::cos(phi);
  auto dp_f = [&](dp::Cone cone, const Vec6& sig) {
    const dp::ConeConstants cc = dp::cone_constants(cone, phi);
    return cc.alpha * 3.0 * pl::mean(sig) + std::sqrt(pl::j2(sig)) - cc.k * c;
  };
  for (double confining : {0.0, 50.0, 400.0}) {
    // Triaxial compression corner: sigma_1 = sigma_2 = -confining, sigma_3 from Mohr-Coulomb.
    const double s1 = -confining, s3 = (s1 * (1 + s) - 2 * c * co) / (1 - s);
    Vec6 tc;
    tc << s1, s3, s1, 0, 0, 0;
    CHECK(std::abs(dp_f(dp::Cone::compression, tc)) < 1e-12 * (confining + c));
    // Triaxial extension corner: sigma_2 = sigma_3 = -confining, sigma_1 from Mohr-Coulomb.
    const double e3 = -confining, e1 = (2 * c * co + e3 * (1 - s)) / (1 + s);
    Vec6 te;
    te << e3, e1, e3, 0, 0, 0;
    CHECK(std::abs(dp_f(dp::Cone::extension, te)) < 1e-12 * (confining + c));
  }
  // Inscribed cone: touches the Mohr-Coulomb faces. In invariants (thesis (2.78)),
  // F = sigma_m sin(phi) + (cos(theta) - sin(theta) sin(phi) / sqrt 3) sqrt(J2) - c cos(phi) is largest
  // over theta where tan(theta) = -sin(phi) / sqrt 3; on the cone that maximum is zero.
  {
    const dp::ConeConstants cc = dp::cone_constants(dp::Cone::inscribed, phi);
    for (double sm : {-300.0, -20.0, 5.0}) {
      const double sj = cc.k * c - 3.0 * cc.alpha * sm;
      const double th = std::atan(-s / r3);
      const double F = sm * s + (std::cos(th) - std::sin(th) * s / r3) * sj - c * co;
      CHECK(std::abs(F) < 1e-12 * (std::abs(sm) + c));
      double worst = -1e300;
      for (int i = 0; i <= 600; ++i) {
        const double t = -std::numbers::pi / 6 + std::numbers::pi / 3 * i / 600.0;
        worst = std::max(worst, sm * s + (std::cos(t) - std::sin(t) * s / r3) * sj - c * co);
      }
      CHECK(worst <= 1e-12 * (std::abs(sm) + c));
    }
  }
  // Plane-strain cone: a stress on the cone whose associated flow has d eps_zz^p = 0 satisfies
  // Mohr-Coulomb exactly with its in-plane principal stresses.
  {
    const dp::ConeConstants cc = dp::cone_constants(dp::Cone::plane_strain, phi);
    const double sx = -120.0, sy = -40.0, txy = 25.0;
    auto rzz = [&](double sz) {
      Vec6 sg;
      sg << sx, sy, sz, txy, 0, 0;
      return pl::deviator(sg)[2] / (2.0 * std::sqrt(pl::j2(sg))) + cc.alpha;
    };
    double lo = -1e3, hi = 1e3; // r_zz increases with sigma_zz
    for (int i = 0; i < 200; ++i) (rzz(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
    Vec6 sg;
    sg << sx, sy, 0.5 * (lo + hi), txy, 0, 0;
    const double f = dp_f(dp::Cone::plane_strain, sg);
    sg.head<3>().array() -= f / (3.0 * cc.alpha); // shift the mean stress onto the cone
    REQUIRE(std::abs(dp_f(dp::Cone::plane_strain, sg)) < 1e-10);
    const double cm = 0.5 * (sg[0] + sg[1]), rad = std::hypot(0.5 * (sg[0] - sg[1]), sg[3]);
    const double p1 = cm + rad, p3 = cm - rad;
    CHECK(p3 <= sg[2]);
    CHECK(sg[2] <= p1);
    CHECK(std::abs((p1 - p3) + (p1 + p3) * s - 2 * c * co) < 1e-10 * (std::abs(p3) + c));
  }
}

TEST_CASE("drucker_prager: elastic regime", "[point]") {
  const dp::Parameters p = base_parameters();
  const dp::DruckerPrager m(p, settings());
  Vec6 s_n, de;
  s_n << -100, -120, -90, 5, -3, 2;
  de << 1e-5, -2e-5, 5e-6, 1e-5, 0, -4e-6;
  REQUIRE(yield(m, s_n + m.stiffness() * de, 0.3) < 0.0);
  const Response r = respond(m, s_n, 0.3, de);
  REQUIRE(r.outcome.ok());
  CHECK((r.stress - (s_n + m.stiffness() * de)).norm() < 1e-12 * s_n.norm());
  CHECK((r.tangent - m.stiffness()).norm() < 1e-12 * m.stiffness().norm());
  CHECK(r.q == 0.3);
}

TEST_CASE("drucker_prager: smooth cone regime", "[point]") {
  for (double H : {0.0, 800.0})
    for (double psi : {0.0, 10.0, 30.0}) {
      dp::Parameters p = base_parameters();
      p.H_c = H;
      p.psi = psi;
      const double G = p.E / (2 * (1 + p.nu)), K = p.E / (3 * (1 - 2 * p.nu));
      Vec6 s_n, de;
      s_n << -100, -120, -90, 5, -3, 2;
      de << 6e-3, -1.2e-2, 3e-3, 9e-3, 0, -3e-3;
      const double q_n = 0.01;
      const dp::DruckerPrager m(p, settings());
      const Vec6 trial = s_n + m.stiffness() * de;
      REQUIRE(yield(m, trial, q_n) > 0.0);
      REQUIRE_FALSE(dp::apex_regime(m.model(), G, K, trial, q_n));

      // Closed-form backward-Euler return: the deviator shrinks radially by G dlambda, the mean
      // stress drops by 3 K alpha_psi dlambda, q grows by h_q dlambda.
      const double dl = dp::cone_multiplier(m.model(), G, K, trial, q_n);
      const double sj = std::sqrt(pl::j2(trial));
      const Vec6 expect = pl::deviator(trial) * (1.0 - G * dl / sj) +
                          hydrostatic(pl::mean(trial) - 3.0 * K * m.model().potential_cone().alpha * dl);

      for (pl::Scheme scheme : all_schemes) {
        INFO("H_c " << H << " psi " << psi << " scheme " << pl::to_string(scheme));
        const dp::DruckerPrager ms(p, settings(scheme));
        const Response r = respond(ms, s_n, q_n, de);
        REQUIRE(r.outcome.ok());
        const double scale = ms.model().stress_scale(r.stress, std::array<double, 1>{r.q});
        if (scheme == pl::Scheme::forward_euler) {
          CHECK(std::abs(yield(ms, r.stress, r.q)) < 1e-2 * scale); // no drift correction
        } else {
          CHECK(std::abs(yield(ms, r.stress, r.q)) < 1e-9 * scale);
        }
        if (scheme == pl::Scheme::closest_point || scheme == pl::Scheme::cutting_plane) {
          // The cutting plane converges to the same backward-Euler point on a straight meridian.
          CHECK((r.stress - expect).norm() < 1e-9 * expect.norm());
          CHECK(r.q == Approx(q_n + m.model().h_q() * dl).epsilon(1e-9));
        }
        // Hardening law (thesis (2.49)): q grows by sqrt(2/3) |d eps_p|, since the flow direction r
        // has |r|^2 = 1/2 + 3 alpha_psi^2 whatever the stress. Exact for the schemes that take the
        // increment with one flow direction (closest point, midpoint); the others sum several.
        const Vec6 dep = de - compliance(p.E, p.nu) * (r.stress - s_n);
        const double eq =
            std::sqrt(2.0 / 3.0 * (dep.head<3>().squaredNorm() + 0.5 * dep.tail<3>().squaredNorm()));
        if (scheme == pl::Scheme::closest_point || scheme == pl::Scheme::midpoint) {
          CHECK(r.q - q_n == Approx(eq).epsilon(1e-8));
        } else {
          CHECK(r.q - q_n >= eq * (1.0 - 1e-8));
          CHECK(r.q - q_n == Approx(eq).epsilon(1e-2));
        }
      }
    }
}

TEST_CASE("drucker_prager: apex regime", "[point]") {
  for (double H : {0.0, 800.0})
    for (double psi : {0.0, 10.0, 30.0}) {
      INFO("H_c " << H << " psi " << psi);
      dp::Parameters p = base_parameters();
      p.H_c = H;
      p.psi = psi;
      const double G = p.E / (2 * (1 + p.nu)), K = p.E / (3 * (1 - 2 * p.nu));
      Vec6 s_n, de;
      s_n << -10, -12, -9, 1, 0, 2;
      de << 2e-3, 1.5e-3, 2.2e-3, 2e-4, -1e-4, 0; // mostly volumetric extension
      const double q_n = 0.002;
      for (pl::Scheme scheme : all_schemes) {
        const dp::DruckerPrager m(p, settings(scheme));
        const Vec6 trial = s_n + m.stiffness() * de;
        REQUIRE(dp::apex_regime(m.model(), G, K, trial, q_n));
        const Response r = respond(m, s_n, q_n, de);
        REQUIRE(r.outcome.ok());
        // Hydrostatic, on the (hardened) apex: f = 0 at sqrt(J2) = 0.
        CHECK(pl::deviator(r.stress).norm() < 1e-12 * r.stress.norm());
        CHECK(pl::mean(r.stress) == Approx(m.model().apex(r.q)).epsilon(1e-12));
        CHECK(std::abs(yield(m, r.stress, r.q)) < 1e-11 * m.model().strength(r.q));
        // q grows by sqrt(2/3) |d eps_p| (thesis (2.49)), d eps_p = de - C^-1 d sigma.
        const Vec6 dep = de - compliance(p.E, p.nu) * (r.stress - s_n);
        const double eq =
            std::sqrt(2.0 / 3.0 * (dep.head<3>().squaredNorm() + 0.5 * dep.tail<3>().squaredNorm()));
        CHECK(r.q - q_n == Approx(eq).epsilon(1e-10));
        if (H == 0.0) {
          CHECK(pl::mean(r.stress) == Approx(p.c / std::tan(dp::radians(p.phi))).epsilon(1e-14));
          CHECK(r.tangent.norm() == 0.0);
        }
      }
    }
}

TEST_CASE("drucker_prager: cone and apex returns meet at the regime boundary", "[point]") {
  // Scale the volumetric part of a strain increment until the trial crosses into the apex region;
  // just below and just above the crossing the two returns must give the same stress and q.
  for (double H : {0.0, 800.0})
    for (double psi : {0.0, 20.0}) {
      INFO("H_c " << H << " psi " << psi);
      dp::Parameters p = base_parameters();
      p.H_c = H;
      p.psi = psi;
      const double G = p.E / (2 * (1 + p.nu)), K = p.E / (3 * (1 - 2 * p.nu));
      pl::Settings st = settings();
      st.ftol = 1e-9; // the default; the tighter 1e-12 cannot resolve a deviator this small
      const dp::DruckerPrager m(p, st);
      Vec6 s_n, dev, vol;
      s_n << -20, -25, -22, 3, 0, 1;
      dev << 1e-3, -2e-3, 1e-3, 2e-3, 0, 0;
      vol << 1, 1, 1, 0, 0, 0;
      auto de = [&](double t) -> Vec6 { return dev + t * vol; };
      auto in_apex = [&](double t) {
        return dp::apex_regime(m.model(), G, K, s_n + m.stiffness() * de(t), 0.0);
      };
      double lo = 0.0, hi = 0.05;
      REQUIRE_FALSE(in_apex(lo));
      REQUIRE(in_apex(hi));
      for (int i = 0; i < 200; ++i) (in_apex(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
      const Response a = respond(m, s_n, 0.0, de(lo - 1e-9)), b = respond(m, s_n, 0.0, de(hi + 1e-9));
      INFO(a.outcome.message);
      REQUIRE(a.outcome.ok());
      REQUIRE(b.outcome.ok());
      CHECK((a.stress - b.stress).norm() < 1e-5 * b.stress.norm());
      CHECK(a.q == Approx(b.q).epsilon(1e-5));
    }
}

TEST_CASE("drucker_prager: consistent tangent against central differences", "[point]") {
  struct Case {
    double H, psi;
    bool apex;
  };
  for (const Case& k :
       {Case{0.0, 30.0, false}, Case{800.0, 10.0, false}, Case{0.0, 0.0, false}, Case{800.0, 30.0, true},
        Case{800.0, 10.0, true}, Case{800.0, 0.0, true}, Case{0.0, 10.0, true}}) {
    INFO("H_c " << k.H << " psi " << k.psi << " apex " << k.apex);
    dp::Parameters p = base_parameters();
    p.H_c = k.H;
    p.psi = k.psi;
    const dp::DruckerPrager m(p, settings());
    Vec6 s_n, de;
    if (k.apex) {
      s_n << -10, -12, -9, 1, 0, 2;
      de << 2e-3, 1.5e-3, 2.2e-3, 2e-4, -1e-4, 3e-5;
    } else {
      s_n << -100, -120, -90, 5, -3, 2;
      de << 2e-3, -4e-3, 1e-3, 3e-3, 5e-4, -1e-3;
    }
    const Response r = respond(m, s_n, 0.004, de);
    REQUIRE(r.outcome.ok());
    const Mat6 fd = fd_tangent(m, s_n, 0.004, de);
    if (k.apex && k.H == 0.0) {
      CHECK(r.tangent.norm() == 0.0);
      CHECK(fd.norm() < 1e-8 * m.stiffness().norm());
    } else {
      CHECK((fd - r.tangent).norm() < 1e-5 * r.tangent.norm());
    }
    if (m.symmetric_tangent()) CHECK((r.tangent - r.tangent.transpose()).norm() < 1e-9 * r.tangent.norm());
  }
}

TEST_CASE("drucker_prager: model derivatives against central differences", "[point]") {
  dp::Parameters p = base_parameters();
  p.H_c = 500.0;
  const dp::Model model(p);
  Vec6 s;
  s << -100, -40, -70, 20, -10, 15;
  const std::array<double, 1> q{0.01};
  const double h = 1e-5;
  Vec6 grad_fd;
  Mat6 hess_fd;
  for (int j = 0; j < 6; ++j) {
    Vec6 a = s, b = s;
    a[j] += h;
    b[j] -= h;
    grad_fd[j] = (model.yield(0, a, q) - model.yield(0, b, q)) / (2 * h);
    hess_fd.col(j) = (model.flow(0, a, q) - model.flow(0, b, q)) / (2 * h);
  }
  CHECK((grad_fd - model.yield_gradient(0, s, q)).norm() < 1e-8);
  CHECK((hess_fd - model.flow_gradient(0, s, q)).norm() < 1e-7 * model.flow_gradient(0, s, q).norm());
  const std::array<double, 1> q2{0.01 + 1e-6};
  CHECK((model.yield(0, s, q2) - model.yield(0, s, q)) / 1e-6 == Approx(model.yield_gradient_q(0, s, q)[0]));
}

TEST_CASE("drucker_prager: triaxial compression plastic modulus (verification M2)", "[point]") {
  // Verification M2 writes the cone as F = q + b p - a (p = sigma_m, tension positive) with
  // potential G = q + b_dil p, a = a0 + h kappa, d kappa = d Lambda, and finds for triaxial
  // compression at constant radial stress 1/E_p = 1/E + (b_dil - 3)(b - 3) / (9 h).
  // (From consistency: dq = -d sigma_a, dp = d sigma_a / 3, so d Lambda = (b - 3) d sigma_a / (3 h);
  //  d eps_a^p = d Lambda dG/d sigma_a = d Lambda (b_dil - 3) / 3.)
  // Here f = sqrt(J2) + 3 alpha sigma_m - K with q = sqrt(3 J2), so F = sqrt(3) f:
  //   b = 3 sqrt(3) alpha,  b_dil = 3 sqrt(3) alpha_psi,  a = sqrt(3) K.
  // The plugin's multiplier dlambda belongs to g = sqrt(J2) + 3 alpha_psi sigma_m = G / sqrt(3), so
  // the same plastic strain needs dlambda = sqrt(3) d Lambda. With K = k (c0 + H_c eps_bar_p) and
  // d eps_bar_p = h_q dlambda:  da = sqrt(3) k H_c h_q sqrt(3) d Lambda, i.e.  h = 3 k H_c h_q.
  for (dp::Cone cone : {dp::Cone::compression, dp::Cone::extension, dp::Cone::plane_strain})
    for (double psi : {0.0, 10.0, 30.0}) {
      INFO("cone " << static_cast<int>(cone) << " psi " << psi);
      dp::Parameters p = base_parameters();
      p.cone = cone;
      p.psi = psi;
      p.H_c = 2000.0;
      const dp::DruckerPrager m(p, settings());
      const double b = 3.0 * std::sqrt(3.0) * m.model().yield_cone().alpha;
      const double b_dil = 3.0 * std::sqrt(3.0) * m.model().potential_cone().alpha;
      const double h = 3.0 * m.model().yield_cone().k * p.H_c * m.model().h_q();
      const double Ep = 1.0 / (1.0 / p.E + (b_dil - 3.0) * (b - 3.0) / (9.0 * h));

      const std::array<bool, 6> ctl{true, false, true, true, true, true}; // axial = yy strain-controlled
      Vec6 s = hydrostatic(-100.0), target = hydrostatic(-100.0);
      double q = 0.0;
      std::vector<double> sa, ea;
      double eps_a = 0.0;
      for (int step = 0; step < 60; ++step) {
        Vec6 de = Vec6::Zero();
        de[1] = -4e-4;
        const Response r = mixed(m, s, q, de, ctl, target);
        REQUIRE(r.outcome.ok());
        s = r.stress, q = r.q, eps_a += de[1];
        sa.push_back(s[1]), ea.push_back(eps_a);
      }
      REQUIRE(q > 0.0); // yielded
      // Radial stress held, last steps plastic: secant modulus of the last two steps.
      CHECK(s[0] == Approx(-100.0).epsilon(1e-10));
      const std::size_t n = sa.size();
      const double Ep_num = (sa[n - 1] - sa[n - 2]) / (ea[n - 1] - ea[n - 2]);
      CHECK(Ep_num == Approx(Ep).epsilon(1e-8));
      CHECK((sa[n - 2] - sa[n - 3]) / (ea[n - 2] - ea[n - 3]) == Approx(Ep).epsilon(1e-8));
    }
}

TEST_CASE("drucker_prager: proportional path in 1 and 1000 steps", "[point]") {
  // From sigma_0 on the cone (q = 0), the stress path sigma(t) = (1 + t) sigma_0 stays on the
  // hardening cone when c(q) = (1 + t) c0, i.e. q = t c0 / H_c and dlambda = q / h_q. Its strain
  // increment is linear in t:  d eps = t C^-1 sigma_0 + t c0 / (H_c h_q) r_0, r_0 = flow at sigma_0.
  for (pl::Scheme scheme : all_schemes) {
    INFO("scheme " << pl::to_string(scheme));
    dp::Parameters p = base_parameters();
    p.H_c = 1000.0;
    p.psi = 10.0;
    const dp::DruckerPrager m(p, settings(scheme));
    Vec6 s0;
    s0 << -100, -160, -80, 20, -10, 5;
    // Put s0 on the cone by scaling its deviator.
    const double alpha = m.model().yield_cone().alpha;
    const double sj = m.model().strength(0.0) - 3.0 * alpha * pl::mean(s0);
    s0 = hydrostatic(pl::mean(s0)) + pl::deviator(s0) * (sj / std::sqrt(pl::j2(s0)));
    REQUIRE(std::abs(yield(m, s0, 0.0)) < 1e-12 * sj);
    const std::array<double, 1> q0{0.0};
    const Vec6 r0 = m.model().flow(0, s0, q0);
    const double T = 0.5;
    const Vec6 de = T * compliance(p.E, p.nu) * s0 + T * p.c / (p.H_c * m.model().h_q()) * r0;

    const Response one = respond(m, s0, 0.0, de);
    REQUIRE(one.outcome.ok());
    Vec6 s = s0;
    double q = 0.0;
    for (int i = 0; i < 1000; ++i) {
      const Response r = respond(m, s, q, de / 1000.0);
      REQUIRE(r.outcome.ok());
      s = r.stress, q = r.q;
    }
    CHECK((one.stress - s).norm() < 1e-10 * s.norm());
    CHECK(one.q == Approx(q).epsilon(1e-10));
    CHECK((one.stress - (1.0 + T) * s0).norm() < 1e-10 * s.norm());
    CHECK(one.q == Approx(T * p.c / p.H_c).epsilon(1e-10));
  }
}

} // namespace test_drucker_prager
