// Tests of the Mohr-Coulomb material (plugins/mohr_coulomb): the meridians of both forms
// (verification.md M8), the regimes of the exact principal-space return (face, edges, apex,
// tension cut-off) with trial stresses built from a known answer, normality, the spectral
// consistent tangent and the rounded form's library tangent against central differences, and
// the triaxial strength q_f.
#include "mohr_coulomb/mohr_coulomb.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace test_mohr_coulomb {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace mc = stratum::mohr_coulomb;
namespace pl = stratum::plasticity;
using mc::Mat3;
using mc::Vec3;

constexpr std::array<pl::Scheme, 6> all_schemes{pl::Scheme::forward_euler, pl::Scheme::modified_euler,
                                                pl::Scheme::trapezoidal,   pl::Scheme::midpoint,
                                                pl::Scheme::cutting_plane, pl::Scheme::closest_point};

mc::Parameters base_parameters(mc::Form form, double psi = 30.0, double tension = -1.0) {
  mc::Parameters p;
  p.E = 2.0e4;
  p.nu = 0.3;
  p.c = 10.0;
  p.phi = 30.0;
  p.psi = psi;
  p.tension = tension;
  p.form = form;
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
  Mat6 tangent = Mat6::Zero();
  double eps_p = 0.0;
  stratum::Outcome outcome;
};

Response respond(const mc::MohrCoulomb& m, const Vec6& stress_n, const Vec6& de) {
  Response r;
  const Vec6 strain_n = Vec6::Zero();
  const std::array<double, 1> h_n{0.0};
  std::array<double, 1> h{-1.0};
  stratum::MaterialOutput out{r.stress, h, r.tangent};
  r.outcome = m.update(stratum::MaterialInput{stress_n, strain_n, h_n, de, {}}, out);
  r.eps_p = h[0];
  return r;
}

Mat6 fd_tangent(const mc::MohrCoulomb& m, const Vec6& stress_n, const Vec6& de, double h = 1e-7) {
  Mat6 fd;
  for (int j = 0; j < 6; ++j) {
    Vec6 a = de, b = de;
    a[j] += h;
    b[j] -= h;
    fd.col(j) = (respond(m, stress_n, a).stress - respond(m, stress_n, b).stress) / (2.0 * h);
  }
  return fd;
}

/// A rotation from three angles.
Mat3 rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Vec3::UnitZ()) * Eigen::AngleAxisd(b, Vec3::UnitY()) *
          Eigen::AngleAxisd(c, Vec3::UnitX()))
      .toRotationMatrix();
}

Vec6 rotated(const Vec3& principal, const Mat3& Q) {
  return stratum::stress_voigt(Q * principal.asDiagonal() * Q.transpose());
}

Vec3 principal_sorted(const Vec6& s) {
  Vec3 v = Eigen::SelfAdjointEigenSolver<Mat3>(stratum::stress_tensor(s)).eigenvalues();
  return v; // ascending
}

/// Index of the Mohr-Coulomb plane whose largest stress is i and smallest j (ExactReturn order).
int mc_plane(int i, int j) { return i * 2 + (j > i ? j - 1 : j); }
int tension_plane(int i) { return 6 + i; }

/// Exact Mohr-Coulomb function for sorted principal stresses, tension positive (thesis (2.75)):
/// (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi), s1 the largest.
double mc_exact(const Vec3& s, double c, double phi) {
  const double s1 = s.maxCoeff(), s3 = s.minCoeff();
  return (s1 - s3) + (s1 + s3) * std::sin(phi) - 2.0 * c * std::cos(phi);
}

/// Mixed control with Newton on the stress-controlled components (see test_drucker_prager.cpp).
Response mixed(const mc::MohrCoulomb& m, const Vec6& stress_n, Vec6& de,
               const std::array<bool, 6>& stress_ctl, const Vec6& target) {
  std::vector<int> u;
  for (int i = 0; i < 6; ++i)
    if (stress_ctl[static_cast<std::size_t>(i)]) u.push_back(i);
  const int n = static_cast<int>(u.size());
  Response r = respond(m, stress_n, de);
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
    r = respond(m, stress_n, de);
  }
  return r;
}

/// q where the yield function vanishes at mean pressure p (compression positive) and Lode angle
/// theta. Along such a ray the function is linear in sqrt(J2) (the deviatoric terms are
/// positively homogeneous of degree one), so two evaluations give the root.
template <class F> double q_at(const F& f, double p, double theta) {
  const Vec6 m = -p * pl::identity();
  const Vec6 u = mc::unit_deviator(theta);
  const double f0 = f(m), f1 = f(Vec6(m + u));
  return std::sqrt(3.0) * (-f0 / (f1 - f0));
}

} // namespace

TEST_CASE("mohr_coulomb: both forms recover M_c and M_e on the meridians (verification M8)", "[point]") {
  for (double phi_deg : {10.0, 20.0, 30.0, 40.0}) {
    INFO("phi " << phi_deg);
    const double phi = mc::radians(phi_deg), s = std::sin(phi), c = 10.0;
    const double Mc = 6 * s / (3 - s), Me = 6 * s / (3 + s);
    mc::Parameters p = base_parameters(mc::Form::rounded);
    p.phi = phi_deg;
    p.psi = phi_deg;
    const mc::RoundedModel rounded(p);
    const mc::ExactReturn exact(p);
    auto f_r = [&](const Vec6& sg) { return rounded.yield(0, sg, {}); };
    auto f_e = [&](const Vec6& sg) { // the six Mohr-Coulomb planes (0-5), without the tension planes
      double f = -1e300;
      for (int k = 0; k < 6; ++k) f = std::max(f, exact.yield(k, principal_sorted(sg)));
      return f;
    };
    const double pi6 = std::numbers::pi / 6;
    // Slopes of the compression (theta = +30 deg) and extension (-30 deg) meridians.
    CHECK((q_at(f_r, 300, pi6) - q_at(f_r, 100, pi6)) / 200 == Approx(Mc).epsilon(1e-12));
    CHECK((q_at(f_r, 300, -pi6) - q_at(f_r, 100, -pi6)) / 200 == Approx(Me).epsilon(1e-12));
    CHECK((q_at(f_e, 300, pi6) - q_at(f_e, 100, pi6)) / 200 == Approx(Mc).epsilon(1e-12));
    CHECK((q_at(f_e, 300, -pi6) - q_at(f_e, 100, -pi6)) / 200 == Approx(Me).epsilon(1e-12));
    // Intercepts q(p = 0) = 6 c cos(phi) / (3 -+ sin(phi)), and the common apex c cot(phi).
    CHECK(q_at(f_r, 0, pi6) == Approx(6 * c * std::cos(phi) / (3 - s)).epsilon(1e-12));
    CHECK(q_at(f_r, 0, -pi6) == Approx(6 * c * std::cos(phi) / (3 + s)).epsilon(1e-12));
    CHECK(q_at(f_e, 0, -pi6) == Approx(6 * c * std::cos(phi) / (3 + s)).epsilon(1e-12));
    CHECK(rounded.apex() == Approx(c / std::tan(phi)).epsilon(1e-14));
    // Gudehus g (thesis (2.83)-(2.85)): g(30 deg) = 1, g(-30 deg) = K = (3 - sin phi) / (3 + sin phi).
    const double K = (3 - s) / (3 + s);
    CHECK(mc::gudehus_g(pi6, K) == Approx(1.0).epsilon(1e-15));
    CHECK(mc::gudehus_g(-pi6, K) == Approx(K).epsilon(1e-15));
    // On both meridians the rounded function equals the exact invariant form (thesis (2.78)).
    for (double th : {pi6, -pi6}) {
      const Vec6 sg = -150.0 * pl::identity() + 40.0 * mc::unit_deviator(th);
      const double F =
          pl::mean(sg) * s + (std::cos(th) - std::sin(th) * s / std::sqrt(3.0)) * 40.0 - c * std::cos(phi);
      CHECK(f_r(sg) == Approx(F).epsilon(1e-12));
      CHECK(mc_exact(principal_sorted(sg), c, phi) / 2.0 == Approx(F).epsilon(1e-12));
    }
  }
}

TEST_CASE("mohr_coulomb: the Gudehus rounding is convex only for phi up to about 22 deg", "[point]") {
  // Polar pi-plane curve rho(theta) = 1 / (1/g): convex where rho^2 + 2 rho'^2 - rho rho'' >= 0.
  // The Gudehus curve is convex for K >= 7/9, i.e. sin(phi) <= 3/8 (phi <= 22.02 deg); the README
  // documents this limitation of (2.83).
  auto convex = [](double phi_deg) {
    const double s = std::sin(mc::radians(phi_deg)), K = (3 - s) / (3 + s);
    for (int i = 0; i <= 2000; ++i) {
      const double t = -std::numbers::pi / 6 + std::numbers::pi / 3 * i / 2000.0, h = 1e-4;
      const double r = mc::gudehus_g(t, K),
                   rp = (mc::gudehus_g(t + h, K) - mc::gudehus_g(t - h, K)) / (2 * h);
      const double rpp = (mc::gudehus_g(t + h, K) - 2 * r + mc::gudehus_g(t - h, K)) / (h * h);
      if (r * r + 2 * rp * rp - r * rpp < -1e-9) return false;
    }
    return true;
  };
  CHECK(convex(10.0));
  CHECK(convex(21.9));
  CHECK_FALSE(convex(22.2));
  CHECK_FALSE(convex(30.0));
  CHECK(std::asin(3.0 / 8.0) * 180 / std::numbers::pi == Approx(22.024).epsilon(1e-4));
}

TEST_CASE("mohr_coulomb: rounded model derivatives against central differences", "[point]") {
  mc::Parameters p = base_parameters(mc::Form::rounded, 10.0);
  const mc::RoundedModel model(p);
  Vec6 s;
  s << -100, -40, -70, 20, -10, 15;
  const double h = 1e-5;
  Vec6 grad_fd;
  Mat6 hess_fd;
  for (int j = 0; j < 6; ++j) {
    Vec6 a = s, b = s;
    a[j] += h;
    b[j] -= h;
    grad_fd[j] = (model.yield(0, a, {}) - model.yield(0, b, {})) / (2 * h);
    hess_fd.col(j) = (model.flow(0, a, {}) - model.flow(0, b, {})) / (2 * h);
  }
  CHECK((grad_fd - model.yield_gradient(0, s, {})).norm() < 1e-8);
  CHECK((hess_fd - model.flow_gradient(0, s, {})).norm() < 1e-7 * model.flow_gradient(0, s, {}).norm());
  // The Lode angle of the rounded term: f restricted to a pi-plane circle follows 1 / g(theta).
  for (double th : {-0.4, -0.1, 0.2, 0.5}) {
    const Vec6 sg = -100.0 * pl::identity() + 30.0 * mc::unit_deviator(th);
    CHECK(pl::lode(sg) == Approx(th).epsilon(1e-12));
    const mc::Rounding& r = model.yield_rounding();
    CHECK(model.yield(0, sg, {}) == Approx(-100.0 * r.sin_angle + r.b * 30.0 / mc::gudehus_g(th, r.kbar) -
                                           p.c * std::cos(mc::radians(p.phi)))
                                        .epsilon(1e-12));
  }
}

TEST_CASE("mohr_coulomb: elastic regime", "[point]") {
  for (mc::Form form : {mc::Form::exact, mc::Form::rounded}) {
    const mc::MohrCoulomb m(base_parameters(form, 10.0), settings());
    Vec6 s_n, de;
    s_n << -100, -120, -90, 5, -3, 2;
    de << 1e-5, -2e-5, 5e-6, 1e-5, 0, -4e-6;
    const Response r = respond(m, s_n, de);
    REQUIRE(r.outcome.ok());
    CHECK((r.stress - (s_n + m.stiffness() * de)).norm() < 1e-12 * s_n.norm());
    CHECK((r.tangent - m.stiffness()).norm() < 1e-12 * m.stiffness().norm());
    CHECK(r.eps_p < 1e-15);
  }
}

TEST_CASE("mohr_coulomb: exact form, every regime from a trial with a known answer", "[point]") {
  // Each case is a target stress on a face, edge or vertex of the surface and positive multipliers
  // of the planes meeting there: the trial sigma_tr = target + D_p sum lambda_k b_k must return
  // to the target. Principal stresses in the order given; c = 10, phi = 30 deg (2 c cos phi = 17.32).
  const double s30 = 0.5, k = 2 * 10.0 * std::cos(mc::radians(30.0));
  const double on_face = (k - (1 - s30) * 300.0) / (1 + s30); // sigma_1 on the face with sigma_3 = -300
  const double T = 5.0;
  const double with_T = ((1 + s30) * T - k) / (1 - s30); // sigma_3 on the face with sigma_1 = T
  struct Case {
    std::string name;
    Vec3 target;
    std::vector<int> planes;
    double tension;
  };
  const double apex = 10.0 / std::tan(mc::radians(30.0));
  const std::vector<Case> cases{
      {"face", {on_face, -150, -300}, {mc_plane(0, 2)}, -1},
      {"compression edge (sigma_1 = sigma_2)",
       {on_face, on_face, -300},
       {mc_plane(0, 2), mc_plane(1, 2)},
       -1},
      {"extension edge (sigma_2 = sigma_3)", {on_face, -300, -300}, {mc_plane(0, 1), mc_plane(0, 2)}, -1},
      {"apex", {apex, apex, apex}, {mc_plane(0, 2), mc_plane(1, 2), mc_plane(0, 1)}, -1},
      {"apex, volumetric", {apex, apex, apex}, {tension_plane(0), tension_plane(1), tension_plane(2)}, -1},
      {"tension face", {T, -5, -6}, {tension_plane(0)}, T},
      {"tension edge", {T, T, -10}, {tension_plane(0), tension_plane(1)}, T},
      {"tension vertex", {T, T, T}, {tension_plane(0), tension_plane(1), tension_plane(2)}, T},
      {"face and tension edge", {T, -10, with_T}, {mc_plane(0, 2), tension_plane(0)}, T},
      {"compression corner with tension",
       {T, T, with_T},
       {mc_plane(0, 2), mc_plane(1, 2), tension_plane(0), tension_plane(1)},
       T},
      {"extension corner with tension",
       {T, with_T, with_T},
       {mc_plane(0, 1), mc_plane(0, 2), tension_plane(0)},
       T},
  };
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (double psi : {30.0, 10.0, 0.0})
    for (const Case& cs : cases) {
      INFO(cs.name << ", psi " << psi);
      const mc::Parameters p = base_parameters(mc::Form::exact, psi, cs.tension);
      const mc::ExactReturn ret(p);
      const double scale = ret.scale(cs.target);
      REQUIRE(ret.max_yield(cs.target) <= 1e-12 * scale);
      Vec3 trial = cs.target;
      for (std::size_t i = 0; i < cs.planes.size(); ++i)
        trial += ret.stiffness() * ret.plane(cs.planes[i]).b * (1e-3 * (1.0 + 0.37 * static_cast<double>(i)));
      const mc::PrincipalReturn pr = ret(trial);
      REQUIRE(pr.ok);
      CHECK((pr.sigma - cs.target).norm() < 1e-10 * scale);
      CHECK(ret.max_yield(pr.sigma) <= 1e-10 * scale);
      for (int pl_idx : cs.planes) CHECK(std::abs(ret.yield(pl_idx, pr.sigma)) < 1e-10 * scale);
      CHECK(mc_exact(pr.sigma, p.c, mc::radians(p.phi)) <= 1e-10 * scale);
      if (cs.tension >= 0) CHECK(pr.sigma.maxCoeff() <= T * (1 + 1e-12));

      // The same through the spectral return of the material, in rotated axes.
      const Mat3 Q = rotation(0.3, -0.7, 1.1);
      const mc::MohrCoulomb m(p, settings());
      const Vec6 de = stratum::isotropic_compliance(p.E, p.nu) * rotated(trial, Q);
      const Response r = respond(m, Vec6::Zero(), de);
      REQUIRE(r.outcome.ok());
      CHECK((r.stress - rotated(cs.target, Q)).norm() < 1e-10 * scale);

      // Associated flow: the plastic strain lies in the normal cone, i.e. the return is the
      // closest point in the energy norm: (sigma* - sigma) : d eps_p <= 0 for every admissible sigma*.
      if (psi == p.phi) {
        const Vec6 dep = de - stratum::isotropic_compliance(p.E, p.nu) * r.stress;
        CHECK(r.eps_p == Approx(mc::equivalent_plastic_strain(dep)).epsilon(1e-12));
        int tried = 0;
        while (tried < 300) {
          const Vec3 sp(-400 + 420 * U(gen), -400 + 420 * U(gen), -400 + 420 * U(gen));
          if (ret.max_yield(sp) > 0) continue;
          ++tried;
          const Vec6 star = rotated(sp, rotation(6 * U(gen), 6 * U(gen), 6 * U(gen)));
          const Vec6 diff = star - r.stress;
          const double work = diff.head<3>().dot(dep.head<3>()) + diff.tail<3>().dot(dep.tail<3>());
          CHECK(work <= 1e-12 * scale * dep.norm());
        }
      }
    }
}

TEST_CASE("mohr_coulomb: exact form, consistent tangent against central differences", "[point]") {
  const double s30 = 0.5, k = 2 * 10.0 * std::cos(mc::radians(30.0));
  const double on_face = (k - (1 - s30) * 300.0) / (1 + s30);
  const double T = 5.0, with_T = ((1 + s30) * T - k) / (1 - s30);
  struct Case {
    std::string name;
    Vec3 target;
    std::vector<int> planes;
    double tension;
  };
  const std::vector<Case> cases{
      {"face", {on_face, -150, -300}, {mc_plane(0, 2)}, -1},
      {"compression edge", {on_face, on_face, -300}, {mc_plane(0, 2), mc_plane(1, 2)}, -1},
      {"extension edge", {on_face, -300, -300}, {mc_plane(0, 1), mc_plane(0, 2)}, -1},
      {"tension face", {T, -5, -6}, {tension_plane(0)}, T},
      {"tension edge", {T, T, -10}, {tension_plane(0), tension_plane(1)}, T},
      {"face and tension edge", {T, -10, with_T}, {mc_plane(0, 2), tension_plane(0)}, T},
      {"apex",
       {17.320508075688775, 17.320508075688775, 17.320508075688775},
       {mc_plane(0, 2), mc_plane(1, 2), mc_plane(0, 1)},
       -1},
      {"tension vertex", {T, T, T}, {tension_plane(0), tension_plane(1), tension_plane(2)}, T},
  };
  for (double psi : {30.0, 10.0})
    for (const Case& cs : cases) {
      INFO(cs.name << ", psi " << psi);
      const mc::Parameters p = base_parameters(mc::Form::exact, psi, cs.tension);
      const mc::MohrCoulomb m(p, settings());
      const mc::ExactReturn& ret = m.exact();
      Vec3 trial = cs.target;
      for (std::size_t i = 0; i < cs.planes.size(); ++i)
        trial += ret.stiffness() * ret.plane(cs.planes[i]).b * (1e-3 * (1.0 + 0.37 * static_cast<double>(i)));
      const bool vertex = cs.name == "apex" || cs.name == "tension vertex";
      if (!vertex) trial += Vec3(3.0, 0.0, -2.0); // keep the trial eigenvalues apart
      const Mat3 Q = rotation(0.3, -0.7, 1.1);
      Vec6 s_n;
      s_n << -20, -30, -10, 4, -2, 3;
      const Vec6 de = stratum::isotropic_compliance(p.E, p.nu) * (rotated(trial, Q) - s_n);
      const Response r = respond(m, s_n, de);
      REQUIRE(r.outcome.ok());
      const Mat6 fd = fd_tangent(m, s_n, de);
      if (vertex) {
        CHECK(r.tangent.norm() < 1e-10 * m.stiffness().norm());
        CHECK(fd.norm() < 1e-6 * m.stiffness().norm());
      } else {
        CHECK((fd - r.tangent).norm() < 1e-5 * r.tangent.norm());
      }
      if (psi == p.phi) CHECK((r.tangent - r.tangent.transpose()).norm() < 1e-10 * m.stiffness().norm());
    }
}

TEST_CASE("mohr_coulomb: rounded form through every integrator", "[point]") {
  for (double phi : {20.0, 30.0})
    for (double psi : {0.0, 10.0, 20.0}) {
      mc::Parameters p = base_parameters(mc::Form::rounded, psi);
      p.phi = phi;
      Vec6 s_n, de;
      s_n << -100, -120, -90, 5, -3, 2;
      de << 6e-3, -1.2e-2, 2e-3, 8e-3, 2e-3, -4e-3;
      for (pl::Scheme scheme : all_schemes) {
        INFO("phi " << phi << " psi " << psi << " scheme " << pl::to_string(scheme));
        const mc::MohrCoulomb m(p, settings(scheme));
        REQUIRE(m.rounded_model().yield(0, s_n + m.stiffness() * de, {}) > 0.0);
        const Response r = respond(m, s_n, de);
        REQUIRE(r.outcome.ok());
        const double f = m.rounded_model().yield(0, r.stress, {});
        const double scale = m.rounded_model().stress_scale(r.stress, {});
        if (scheme == pl::Scheme::forward_euler) {
          CHECK(std::abs(f) < 1e-2 * scale); // no drift correction
        } else {
          CHECK(std::abs(f) < 1e-9 * scale);
        }
        CHECK(r.eps_p > 1e-9);
      }
    }
}

TEST_CASE("mohr_coulomb: rounded form, closest-point tangent against central differences", "[point]") {
  for (double phi : {20.0, 30.0})
    for (double psi : {0.0, 10.0, 20.0}) {
      INFO("phi " << phi << " psi " << psi);
      mc::Parameters p = base_parameters(mc::Form::rounded, psi);
      p.phi = phi;
      const mc::MohrCoulomb m(p, settings());
      Vec6 s_n, de;
      s_n << -100, -120, -90, 5, -3, 2;
      de << 6e-3, -1.2e-2, 2e-3, 8e-3, 2e-3, -4e-3;
      const Response r = respond(m, s_n, de);
      REQUIRE(r.outcome.ok());
      const Mat6 fd = fd_tangent(m, s_n, de);
      CHECK((fd - r.tangent).norm() < 1e-5 * r.tangent.norm());
      if (psi == phi) CHECK((r.tangent - r.tangent.transpose()).norm() < 1e-9 * r.tangent.norm());
    }
}

TEST_CASE("mohr_coulomb: rounded form, apex regime", "[point]") {
  for (double psi : {0.0, 10.0, 30.0}) {
    INFO("psi " << psi);
    const mc::MohrCoulomb m(base_parameters(mc::Form::rounded, psi), settings());
    const double G = 2.0e4 / 2.6, K = 2.0e4 / (3 * 0.4);
    const Vec6 trial = rotated(Vec3(30, 25, 20), rotation(0.2, 0.4, -0.3));
    REQUIRE(mc::rounded_apex_regime(m.rounded_model(), G, K, trial));
    const Vec6 de = stratum::isotropic_compliance(2.0e4, 0.3) * trial;
    const Response r = respond(m, Vec6::Zero(), de);
    REQUIRE(r.outcome.ok());
    CHECK((r.stress - m.rounded_model().apex() * pl::identity()).norm() < 1e-12 * r.stress.norm());
    CHECK(std::abs(m.rounded_model().yield(0, r.stress, {})) < 1e-12 * 10.0);
    CHECK(r.tangent.norm() == 0.0);
  }
  // The apex region and the library return meet continuously: move the mean part of a trial
  // across the boundary found by bisection. The return map is Lipschitz, so trials delta
  // (kPa) either side of the boundary give stresses a few delta apart. (Convex potentials only:
  // psi <= 22 deg, see the README.)
  struct Angles {
    double phi, psi;
  };
  for (const Angles an : {Angles{20.0, 20.0}, Angles{30.0, 10.0}, Angles{30.0, 0.0}}) {
    INFO("phi " << an.phi << " psi " << an.psi);
    pl::Settings st = settings();
    st.ftol = 1e-9;
    mc::Parameters p = base_parameters(mc::Form::rounded, an.psi);
    p.phi = an.phi;
    const mc::MohrCoulomb m(p, st);
    const double G = 2.0e4 / 2.6, K = 2.0e4 / (3 * 0.4);
    const Vec6 dev = rotated(Vec3(8, -3, -5), rotation(0.2, 0.4, -0.3));
    auto trial = [&](double t) -> Vec6 { return dev + t * pl::identity(); };
    double lo = 0.0, hi = 200.0;
    REQUIRE_FALSE(mc::rounded_apex_regime(m.rounded_model(), G, K, trial(lo)));
    REQUIRE(mc::rounded_apex_regime(m.rounded_model(), G, K, trial(hi)));
    for (int i = 0; i < 200; ++i)
      (mc::rounded_apex_regime(m.rounded_model(), G, K, trial(0.5 * (lo + hi))) ? hi : lo) = 0.5 * (lo + hi);
    const Mat6 S = stratum::isotropic_compliance(2.0e4, 0.3);
    for (double delta : {1e-1, 1e-2, 1e-3}) {
      const Response a = respond(m, Vec6::Zero(), S * trial(lo - delta));
      const Response b = respond(m, Vec6::Zero(), S * trial(hi + delta));
      INFO("delta " << delta << ": " << a.outcome.message);
      REQUIRE(a.outcome.ok());
      REQUIRE(b.outcome.ok());
      CHECK((a.stress - b.stress).norm() < 20.0 * delta);
    }
  }
}

TEST_CASE("mohr_coulomb: triaxial compression reaches q_f", "[point]") {
  // Compression positive: q_f = 2 (c cos phi + sigma_3 sin phi) / (1 - sin phi) at confining
  // pressure sigma_3. Axial (yy) strain prescribed, radial and shear stresses held.
  for (mc::Form form : {mc::Form::exact, mc::Form::rounded})
    for (double psi : {30.0, 5.0})
      for (double confining : {50.0, 200.0}) {
        INFO("form " << (form == mc::Form::exact ? "exact" : "rounded") << " psi " << psi << " sigma_3 "
                     << confining);
        const mc::Parameters p = base_parameters(form, psi);
        const mc::MohrCoulomb m(p, settings());
        const double phi = mc::radians(p.phi);
        const double qf = 2 * (p.c * std::cos(phi) + confining * std::sin(phi)) / (1 - std::sin(phi));
        const std::array<bool, 6> ctl{true, false, true, true, true, true};
        const Vec6 target = -confining * pl::identity();
        Vec6 s = target;
        double q_prev = 0.0;
        bool yielded = false;
        for (int step = 0; step < 200; ++step) {
          Vec6 de = Vec6::Zero();
          de[1] = -2e-4;
          const Response r = mixed(m, s, de, ctl, target);
          REQUIRE(r.outcome.ok());
          s = r.stress;
          const double q = s[0] - s[1];
          CHECK(q <= qf * (1 + 1e-10));
          if (r.eps_p > 1e-9) yielded = true;
          q_prev = q;
        }
        REQUIRE(yielded);
        CHECK(q_prev == Approx(qf).epsilon(1e-8));
        CHECK(s[0] == Approx(-confining).epsilon(1e-10));
      }
}

TEST_CASE("mohr_coulomb: exact form, no stiffness for the modes that split an edge", "[point]") {
  // A trial on the compression meridian (sigma_xx = sigma_zz > sigma_yy) beyond the surface
  // returns to the edge. Splitting the two radial trial values, by eps_xx - eps_zz or by
  // gamma_zx, leaves the returned stress unchanged: the tangent is zero in those modes (perfectly
  // plastic corner), and finite differences agree.
  for (double psi : {30.0, 5.0}) {
    INFO("psi " << psi);
    const mc::MohrCoulomb m(base_parameters(mc::Form::exact, psi), settings());
    const Vec6 s_n = -100.0 * pl::identity();
    Vec6 trial;
    trial << -100, -600, -100, 0, 0, 0;
    const Vec6 de = stratum::isotropic_compliance(2.0e4, 0.3) * (trial - s_n);
    const Response r = respond(m, s_n, de);
    REQUIRE(r.outcome.ok());
    REQUIRE(r.eps_p > 1e-6);
    REQUIRE(m.exact()(principal_sorted(trial)).active != 0);
    CHECK(r.stress[0] == Approx(r.stress[2]).epsilon(1e-14));
    Vec6 split = Vec6::Zero(), shear = Vec6::Zero();
    split[0] = 1.0, split[2] = -1.0;
    shear[5] = 1.0;
    const double scale = m.stiffness().norm();
    CHECK((r.tangent * split).norm() < 1e-10 * scale);
    CHECK((r.tangent * shear).norm() < 1e-10 * scale);
    const Mat6 fd = fd_tangent(m, s_n, de);
    CHECK((fd * split).norm() < 1e-6 * scale);
    CHECK((fd * shear).norm() < 1e-6 * scale);
    CHECK((fd - r.tangent).norm() < 1e-5 * r.tangent.norm());
  }
}

// ------------------------------------------------------------------------------------------
// Tresca: phi = 0 (then psi = 0). The exact form is the hexagonal prism (sigma_1 - sigma_3) = 2c
// with no apex; the rounded form is the von Mises cylinder through its corners,
// (sqrt 3 / 2) sqrt(J2) = c.

TEST_CASE("mohr_coulomb: Tresca (phi = 0) against closed forms", "[point][tresca]") {
  const double c = 10.0;
  for (mc::Form form : {mc::Form::exact, mc::Form::rounded}) {
    mc::Parameters p = base_parameters(form, 0.0);
    p.phi = 0.0;
    p.c = c;
    const mc::MohrCoulomb m(p, settings());
    const double G = p.E / (2 * (1 + p.nu)), K = p.E / (3 * (1 - 2 * p.nu));
    INFO((form == mc::Form::exact ? "exact" : "rounded"));
    CHECK(std::isinf(mc::apex(p)));
    if (form == mc::Form::exact) CHECK(m.exact().planes() == 6); // no tension planes: no apex

    // Triaxial compression in one increment from zero stress, axial strain -eps (10 x the yield
    // strain): a corner of the hexagon, reached by both forms. The return is purely deviatoric
    // (psi = 0), so sigma_m = -K eps is kept and the deviator is the one of q = 2c:
    // sigma_xx = -K eps - 4c/3, sigma_yy = sigma_zz = -K eps + 2c/3.
    {
      const double eps = 10 * c / G;
      Vec6 de = Vec6::Zero();
      de[0] = -eps;
      const Response r = respond(m, Vec6::Zero(), de);
      REQUIRE(r.outcome.ok());
      CHECK(r.stress[0] == Approx(-K * eps - 4 * c / 3).epsilon(1e-10));
      CHECK(r.stress[1] == Approx(-K * eps + 2 * c / 3).epsilon(1e-10));
      CHECK(r.stress[2] == Approx(-K * eps + 2 * c / 3).epsilon(1e-10));
      CHECK(r.stress[1] - r.stress[0] == Approx(2 * c).epsilon(1e-10));
      CHECK(r.stress.tail<3>().norm() <= 1e-10 * c);
      CHECK(r.eps_p > 0.0);
    }
    // Simple shear (plane strain, gamma_xy only) from zero: sigma_1,3 = +-tau, sigma_2 = 0. Tresca
    // yields at tau = c (mid-face of the hexagon); the circumscribed cylinder at tau = 2c/sqrt(3).
    // Below that the response is elastic (tau = G gamma).
    {
      Vec6 de = Vec6::Zero();
      de[3] = 0.9 * c / G;
      const Response e = respond(m, Vec6::Zero(), de);
      REQUIRE(e.outcome.ok());
      CHECK(e.stress[3] == Approx(0.9 * c).epsilon(1e-12));
      CHECK(e.eps_p == 0.0);
      de[3] = 5 * c / G;
      const Response r = respond(m, Vec6::Zero(), de);
      REQUIRE(r.outcome.ok());
      const double tau = form == mc::Form::exact ? c : 2 * c / std::sqrt(3.0);
      CHECK(r.stress[3] == Approx(tau).epsilon(1e-9));
      CHECK(r.stress.head<3>().norm() <= 1e-9 * c);
      CHECK(r.stress.tail<2>().norm() <= 1e-9 * c);
    }
    // The strength does not depend on the mean stress: the same q = 2c at 1000 kPa of confinement
    // and under 1000 kPa of all-round tension (no apex, no tension limit).
    for (double mean : {-1000.0, 1000.0}) {
      const Vec6 s0 = mean * pl::identity();
      Vec6 de = Vec6::Zero();
      de[1] = -10 * c / G;
      const Response r = respond(m, s0, de);
      REQUIRE(r.outcome.ok());
      const Vec3 s = principal_sorted(r.stress);
      CHECK(s[2] - s[0] == Approx(2 * c).epsilon(1e-10));
    }
  }
}

TEST_CASE("mohr_coulomb: Tresca (phi = 0), consistent tangent against central differences",
          "[point][tresca]") {
  const double c = 10.0;
  struct Case {
    std::string name;
    Vec3 target;
    std::vector<int> planes;
  };
  // On the prism sigma_i - sigma_j = 2c: a face (distinct principal stresses) and both edges.
  const std::vector<Case> cases{
      {"face", {-50, -65, -50 - 2 * c}, {mc_plane(0, 2)}},
      {"compression edge", {-50, -50, -50 - 2 * c}, {mc_plane(0, 2), mc_plane(1, 2)}},
      {"extension edge", {-50, -50 - 2 * c, -50 - 2 * c}, {mc_plane(0, 1), mc_plane(0, 2)}},
  };
  for (const Case& cs : cases) {
    INFO(cs.name);
    mc::Parameters p = base_parameters(mc::Form::exact, 0.0);
    p.phi = 0.0;
    p.c = c;
    const mc::MohrCoulomb m(p, settings());
    const mc::ExactReturn& ret = m.exact();
    Vec3 trial = cs.target;
    for (std::size_t i = 0; i < cs.planes.size(); ++i)
      trial += ret.stiffness() * ret.plane(cs.planes[i]).b * (1e-3 * (1.0 + 0.37 * static_cast<double>(i)));
    const Mat3 Q = rotation(0.3, -0.7, 1.1);
    Vec6 s_n;
    s_n << -20, -30, -10, 4, -2, 3;
    const Vec6 de = stratum::isotropic_compliance(p.E, p.nu) * (rotated(trial, Q) - s_n);
    const Response r = respond(m, s_n, de);
    REQUIRE(r.outcome.ok());
    const Vec3 s = principal_sorted(r.stress);
    CHECK(s[2] - s[0] == Approx(2 * c).epsilon(1e-10));                              // on the prism
    CHECK(pl::mean(r.stress) == Approx(pl::mean(rotated(trial, Q))).epsilon(1e-10)); // deviatoric return
    const Mat6 fd = fd_tangent(m, s_n, de);
    CHECK((fd - r.tangent).norm() < 1e-5 * r.tangent.norm());
    CHECK((r.tangent - r.tangent.transpose()).norm() < 1e-10 * m.stiffness().norm()); // associated
  }
  // The rounded form at phi = 0 through the library's closest-point return, off the corners.
  mc::Parameters p = base_parameters(mc::Form::rounded, 0.0);
  p.phi = 0.0;
  p.c = c;
  const mc::MohrCoulomb m(p, settings());
  Vec6 s_n;
  s_n << -20, -30, -10, 4, -2, 3;
  Vec6 de;
  de << -2e-3, 1e-3, 0.5e-3, 1.5e-3, -0.4e-3, 0.7e-3;
  const Response r = respond(m, s_n, de);
  REQUIRE(r.outcome.ok());
  REQUIRE(r.eps_p > 0.0);
  const Mat6 fd = fd_tangent(m, s_n, de);
  CHECK((fd - r.tangent).norm() < 1e-5 * r.tangent.norm());
}

} // namespace test_mohr_coulomb
