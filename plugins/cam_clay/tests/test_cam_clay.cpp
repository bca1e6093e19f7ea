// Tests of the Cam-Clay and Modified Cam-Clay materials (plugins/cam_clay): analytic
// derivatives against finite differences, the closed-form triaxial paths of
// docs/verification.md M1 (undrained and drained), the original Cam-Clay undrained
// closed form, the consistent tangent of the closest-point return, every other
// integrator on the undrained path, and the no-tension failure.
#include "cam_clay/cam_clay.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <string>
#include <vector>

// The measured figures go to INFO (shown when a check fails); build with
// -DSTRATUM_CAM_CLAY_VERBOSE to print them always.
#ifdef STRATUM_CAM_CLAY_VERBOSE
#define REPORT(msg) WARN(msg)
#else
#define REPORT(msg) INFO(msg)
#endif

namespace test_cam_clay {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace cc = stratum::cam_clay;
namespace pl = stratum::plasticity;

// The worked case of verification.md M1.
constexpr double M_ = 1.2, lambda_ = 0.077, kappa_ = 0.0066, p0_ = 200.0;
constexpr double Lambda_ = (lambda_ - kappa_) / lambda_;

cc::Constants constants(cc::Variant v = cc::Variant::modified, double G = 0.0) {
  cc::Constants c;
  c.variant = v;
  c.M = M_;
  c.lambda = lambda_;
  c.kappa = kappa_;
  c.e0 = 1.0;
  c.nu = 0.3;
  c.G = G;
  c.p_min = 1.0;
  return c;
}

pl::Settings closest_point() {
  pl::Settings s;
  s.scheme = pl::Scheme::closest_point;
  s.ftol = 1e-12;
  s.max_iterations = 50;
  return s;
}

Vec6 isotropic(double p) {
  Vec6 s = Vec6::Zero();
  s[0] = s[1] = s[2] = -p;
  return s;
}

/// Isochoric triaxial compression increment, axial = y (tension positive).
Vec6 undrained(double d) {
  Vec6 e = Vec6::Zero();
  e[1] = -d;
  e[0] = e[2] = d / 2;
  return e;
}

double p_of(const Vec6& s) { return pl::p_comp(s); }
double q_of(const Vec6& s) { return pl::q_mises(s); }

/// One material point with its committed state.
struct Point {
  const cc::CamClay& mat;
  Vec6 stress;
  Vec6 strain = Vec6::Zero();
  std::array<double, 1> history{};
  Mat6 tangent = Mat6::Zero();

  Point(const cc::CamClay& m, const Vec6& s0) : mat(m), stress(s0) { mat.init_history(stress, history); }

  /// Trial update (nothing committed).
  stratum::Outcome trial(const Vec6& de, Vec6& s, std::array<double, 1>& h, Mat6& T) const {
    const stratum::MaterialInput in{stress, strain, history, de, {}};
    stratum::MaterialOutput out{s, h, T};
    return mat.update(in, out);
  }
  /// Update and commit.
  stratum::Outcome step(const Vec6& de) {
    Vec6 s;
    std::array<double, 1> h{};
    Mat6 T;
    const stratum::Outcome o = trial(de, s, h, T);
    if (o.ok()) stress = s, strain += de, history = h, tangent = T;
    return o;
  }
};

/// Undrained closed form of MCC: q/p = M sqrt(OCR (p0/p)^(1/Lambda) - 1) on the yield surface.
double mcc_undrained_ratio(double p, double ocr) {
  return M_ * std::sqrt(ocr * std::pow(p0_ / p, 1 / Lambda_) - 1);
}

/// Central finite-difference Jacobian of a vector function of a Vec6.
template <class F> Eigen::MatrixXd fd_jacobian(F f, const Vec6& x, double h) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), 6);
  for (int j = 0; j < 6; ++j) {
    Vec6 xp = x, xm = x;
    xp[j] += h, xm[j] -= h;
    J.col(j) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

/// A general stress state (tension positive, all shear components non-zero).
Vec6 general_stress(double p, double scale) {
  Vec6 s;
  s << -p + 0.6 * scale, -p - 0.9 * scale, -p + 0.3 * scale, 0.25 * scale, -0.15 * scale, 0.1 * scale;
  return s;
}

} // namespace

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: M1 worked numbers follow from the closed forms", "[point]") {
  const double pf = p0_ * std::pow(0.5, Lambda_);
  CHECK(Lambda_ == Approx(0.0704 / 0.077).epsilon(1e-15));
  CHECK(pf == Approx(106.121).epsilon(1e-5));
  CHECK(M_ * pf == Approx(127.346).epsilon(1e-5));
  CHECK(M_ * pf / 2 == Approx(63.673).epsilon(1e-5));
  // the same point from the path formula: q/p = M at p = p_f
  CHECK(mcc_undrained_ratio(pf, 1.0) == Approx(M_).epsilon(1e-12));
  // drained constant sigma_3 from the normally consolidated state
  CHECK(3 * p0_ / (3 - M_) == Approx(333.333333).epsilon(1e-8));
  CHECK(M_ * 3 * p0_ / (3 - M_) == Approx(400.0).epsilon(1e-12));
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: analytic derivatives match finite differences", "[point]") {
  for (auto variant : {cc::Variant::modified, cc::Variant::original}) {
    for (double G : {0.0, 5000.0}) {
      const cc::Model m(constants(variant, G));
      INFO((variant == cc::Variant::modified ? "modified" : "original") << " G " << G);
      for (double p : {40.0, 150.0, 320.0}) {
        for (double scale : {20.0, 90.0}) {
          INFO("p " << p << " scale " << scale);
          const Vec6 s = general_stress(p, scale);
          const std::array<double, 1> q{std::log(260.0)};
          const double hs = 1e-4; // stress perturbation (kPa)
          // n = df/dsigma
          auto f = [&](const Vec6& x) {
            Eigen::VectorXd v(1);
            v[0] = m.yield(0, x, q);
            return v;
          };
          CHECK(rel_diff(m.yield_gradient(0, s, q).transpose(), fd_jacobian(f, s, hs)) < 1e-7);
          // dr/dsigma, and symmetry of the associated flow gradient
          auto r = [&](const Vec6& x) { return Eigen::VectorXd(m.flow(0, x, q)); };
          const Mat6 H = m.flow_gradient(0, s, q);
          CHECK(rel_diff(H, fd_jacobian(r, s, hs)) < 1e-7);
          CHECK((H - H.transpose()).cwiseAbs().maxCoeff() < 1e-14 * H.cwiseAbs().maxCoeff());
          // dh/dsigma
          auto h = [&](const Vec6& x) { return Eigen::VectorXd(m.hardening(0, x, q)); };
          CHECK(rel_diff(m.hardening_gradient(0, s, q), fd_jacobian(h, s, hs)) < 1e-7);
          // derivatives with respect to xi = ln p_c
          const double hq = 1e-6;
          const std::array<double, 1> qp{q[0] + hq}, qm{q[0] - hq};
          const double dfdq = (m.yield(0, s, qp) - m.yield(0, s, qm)) / (2 * hq);
          CHECK(m.yield_gradient_q(0, s, q)[0] == Approx(dfdq).epsilon(1e-7));
          const Vec6 drdq = (m.flow(0, s, qp) - m.flow(0, s, qm)) / (2 * hq);
          CHECK(rel_diff(m.flow_gradient_q(0, s, q), drdq) < 1e-7);
          const double dhdq = (m.hardening(0, s, qp)[0] - m.hardening(0, s, qm)[0]) / (2 * hq);
          CHECK(m.hardening_gradient_q(0, s, q)(0, 0) == Approx(dhdq).epsilon(1e-7));
          // hardening = v0/(lambda - kappa) * d eps_v^p / dlambda = -v0/(lambda - kappa) tr(r)
          const Vec6 n = m.flow(0, s, q);
          CHECK(m.hardening(0, s, q)[0] ==
                Approx(-(n[0] + n[1] + n[2]) * 2.0 / (lambda_ - kappa_)).epsilon(1e-12));
          // elastic update: tangent vs FD, and the rate form at de = 0
          Vec6 de;
          de << 2e-4, -7e-4, 3e-4, 4e-4, -1e-4, 2e-4;
          auto eu = [&](const Vec6& x) { return Eigen::VectorXd(m.elastic_update(s, q, x)); };
          CHECK(rel_diff(m.elastic_update_tangent(s, q, de), fd_jacobian(eu, de, 1e-8)) < 1e-6);
          CHECK(rel_diff(m.elastic_update_tangent(s, q, Vec6::Zero()), m.elastic(s, q)) < 1e-14);
          // the volumetric law is the swelling line: p = p_n exp(v0 de_v / kappa)
          const double dev = -(de[0] + de[1] + de[2]);
          CHECK(p_of(m.elastic_update(s, q, de)) == Approx(p * std::exp(2.0 * dev / kappa_)).epsilon(1e-13));
        }
      }
    }
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: initial preconsolidation pressure from ocr, pc0 and p_min", "[point]") {
  const pl::Settings s = closest_point();
  std::array<double, 1> h{};
  {
    const cc::CamClay m(constants(), {2.5, 0.0}, s);
    m.init_history(isotropic(p0_), h);
    CHECK(h[0] == Approx(500.0).epsilon(1e-14));
    // anisotropic (K0-like) stress: ocr scales the surface through the stress
    Vec6 k0 = isotropic(100.0);
    k0[1] = -200.0; // p = 133.33, q = 100
    m.init_history(k0, h);
    const double p = 400.0 / 3, q = 100.0;
    CHECK(h[0] == Approx(2.5 * (p + q * q / (M_ * M_ * p))).epsilon(1e-14));
    // no compression: p_min stands in for p
    m.init_history(Vec6::Zero(), h);
    CHECK(h[0] == Approx(2.5).epsilon(1e-14));
  }
  {
    const cc::CamClay m(constants(cc::Variant::original), {1.0, 0.0}, s);
    Vec6 k0 = isotropic(100.0);
    k0[1] = -200.0;
    m.init_history(k0, h);
    const double p = 400.0 / 3, q = 100.0;
    CHECK(h[0] == Approx(p * std::exp(q / (M_ * p))).epsilon(1e-14));
    CHECK(m.model().yield(0, k0, std::array<double, 1>{std::log(h[0])}) == Approx(0.0).margin(1e-10));
  }
  {
    const cc::CamClay m(constants(), {1.0, 350.0}, s);
    m.init_history(isotropic(p0_), h);
    CHECK(h[0] == 350.0);
    m.init_history(isotropic(400.0), h); // outside the given surface: widened through the stress
    CHECK(h[0] == Approx(400.0).epsilon(1e-14));
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: M1 undrained triaxial of normally consolidated MCC (closest point)", "[point]") {
  const cc::CamClay mat(constants(), {1.0, 0.0}, closest_point());
  Point pt(mat, isotropic(p0_));
  // 200 steps along the path up to 1 % axial strain; every step on the closed form.
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    REQUIRE(pt.step(undrained(5e-5)).ok());
    const double p = p_of(pt.stress), q = q_of(pt.stress);
    CHECK(pt.strain.head<3>().sum() == Approx(0.0).margin(1e-18));
    const double err = std::abs(q / p / mcc_undrained_ratio(p, 1.0) - 1);
    worst = std::max(worst, err);
    // p_c follows p: p_c = p0 (p0/p)^(kappa/(lambda - kappa))
    CHECK(pt.history[0] == Approx(p0_ * std::pow(p0_ / p, kappa_ / (lambda_ - kappa_))).epsilon(1e-9));
  }
  REPORT("undrained MCC: worst relative error of q/p along 200 steps = " << worst);
  CHECK(worst < 1e-4);
  // Onwards to the critical state with growing steps until q stops changing.
  double dq = 1.0, d = 1e-4;
  int steps = 0;
  while (dq > 1e-10 && steps < 2000) {
    const double q_before = q_of(pt.stress);
    REQUIRE(pt.step(undrained(d)).ok());
    dq = std::abs(q_of(pt.stress) - q_before);
    d = std::min(d * 1.05, 5e-3);
    ++steps;
  }
  REQUIRE(dq <= 1e-10);
  const double pf = p0_ * std::pow(0.5, Lambda_);
  const double p = p_of(pt.stress), q = q_of(pt.stress);
  REPORT("undrained MCC failure after " << steps << " more steps, axial strain " << -pt.strain[1]
                                        << ": p = " << p << " q = " << q << " (closed form " << pf << ", "
                                        << M_ * pf << ")");
  CHECK(p == Approx(pf).epsilon(1e-6));
  CHECK(q == Approx(M_ * pf).epsilon(1e-6));
  CHECK(p == Approx(106.121).epsilon(1e-5));
  CHECK(q == Approx(127.346).epsilon(1e-5));
  CHECK(q / 2 == Approx(63.673).epsilon(1e-5)); // s_u
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: M1 undrained failure of overconsolidated MCC, wet and dry side", "[point]") {
  for (double ocr : {1.5, 4.0}) {
    for (double G : {0.0, 8000.0}) {
      INFO("OCR " << ocr << " G " << G);
      const cc::CamClay mat(constants(cc::Variant::modified, G), {ocr, 0.0}, closest_point());
      Point pt(mat, isotropic(p0_));
      double worst = 0.0, dq = 1.0, d = 5e-5;
      int steps = 0, plastic_steps = 0;
      while (dq > 1e-10 && steps < 3000) {
        const double q_before = q_of(pt.stress), pc_before = pt.history[0];
        REQUIRE(pt.step(undrained(d)).ok());
        const double p = p_of(pt.stress), q = q_of(pt.stress);
        dq = std::abs(q - q_before);
        if (pt.history[0] != pc_before) { // plastic: on the closed-form path
          worst = std::max(worst, std::abs(q / p / mcc_undrained_ratio(p, ocr) - 1));
          ++plastic_steps;
        } else {
          CHECK(p == Approx(p0_).epsilon(1e-12)); // elastic and isochoric: p constant
        }
        if (plastic_steps >= 200) d = std::min(d * 1.05, 5e-3);
        ++steps;
      }
      REQUIRE(dq <= 1e-10);
      CHECK(plastic_steps > 200);
      const double pf = p0_ * std::pow(ocr / 2, Lambda_);
      REPORT("undrained MCC OCR " << ocr << " G " << G << ": p_f = " << p_of(pt.stress) << " (closed form "
                                  << pf << "), q_f = " << q_of(pt.stress) << ", worst path error " << worst);
      CHECK(worst < 1e-4);
      CHECK(p_of(pt.stress) == Approx(pf).epsilon(1e-6));
      CHECK(q_of(pt.stress) == Approx(M_ * pf).epsilon(1e-6));
    }
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: M1 drained triaxial at constant sigma_3 (mixed control)", "[point]") {
  const cc::CamClay mat(constants(), {1.0, 0.0}, closest_point());
  Point pt(mat, isotropic(p0_));
  const double sigma3 = -p0_; // tension positive, held on x and z
  double dq = 1.0, d = 5e-5;
  int steps = 0, newton_total = 0;
  double worst_path = 0.0, ratio = 0.0;
  while (dq > 1e-10 && steps < 4000) {
    // axial strain increment -d prescribed; radial strains solved so that sigma_xx = sigma_zz = sigma3
    // (first guess: the radial/axial strain ratio of the previous step)
    Vec6 de = Vec6::Zero();
    de[1] = -d;
    de[0] = de[2] = -ratio * d;
    Vec6 s;
    std::array<double, 1> h{};
    Mat6 T;
    int it = 0;
    for (;; ++it) {
      REQUIRE(pt.trial(de, s, h, T).ok());
      const Eigen::Vector2d r(s[0] - sigma3, s[2] - sigma3);
      if (r.cwiseAbs().maxCoeff() < 1e-9) break;
      REQUIRE(it < 25);
      Eigen::Matrix2d J;
      J << T(0, 0), T(0, 2), T(2, 0), T(2, 2);
      const Eigen::Vector2d dx = J.partialPivLu().solve(-r);
      de[0] += dx[0], de[2] += dx[1];
    }
    newton_total += it;
    const double q_before = q_of(pt.stress);
    REQUIRE(pt.step(de).ok());
    ratio = de[0] / de[1];
    dq = std::abs(q_of(pt.stress) - q_before);
    // stress path: q = 3 (p - p0)
    worst_path = std::max(worst_path, std::abs(q_of(pt.stress) - 3 * (p_of(pt.stress) - p0_)));
    if (steps >= 200) d = std::min(d * 1.05, 1e-2);
    ++steps;
  }
  REQUIRE(dq <= 1e-10);
  const double pf = 3 * p0_ / (3 - M_);
  REPORT("drained MCC: " << steps << " steps, " << newton_total << " Newton iterations, axial strain "
                         << -pt.strain[1] << ": p = " << p_of(pt.stress) << " q = " << q_of(pt.stress)
                         << " (closed form " << pf << ", " << M_ * pf << ")");
  CHECK(worst_path < 1e-7);
  CHECK(newton_total <= 3 * steps); // the consistent tangent: few iterations per step
  CHECK(p_of(pt.stress) == Approx(pf).epsilon(1e-6));
  CHECK(q_of(pt.stress) == Approx(M_ * pf).epsilon(1e-6));
  CHECK(pt.history[0] == Approx(2 * pf).epsilon(1e-6)); // on the CSL: p_c = 2 p
}

// ------------------------------------------------------------------------------------------
// Original Cam-Clay, undrained. With p_c = p_c0 exp(v0 eps_v^p/(lambda - kappa)) and
// p = p0 exp(v0 eps_v^e/kappa) (before any yield eps_v^e = eps_v^p = 0), an isochoric path
// (eps_v^e = -eps_v^p) gives
//   ln(p_c/p_c0) = -(kappa/(lambda - kappa)) ln(p/p0).
// The yield condition (thesis (2.131)) eta = M ln(p_c/p) then reads
//   eta/M = ln(p_c0/p0) + ln(p0/p) (1 + kappa/(lambda - kappa)) = ln OCR + ln(p0/p)/Lambda,
// so for OCR = 1:  p/p0 = exp(-Lambda eta/M), and at the critical state (eta = M)
//   p_f = p0 (OCR/e)^Lambda, q_f = M p_f.
TEST_CASE("cam_clay: original Cam-Clay undrained closed form p/p0 = exp(-Lambda eta/M)", "[point]") {
  for (double ocr : {1.0, 1.8}) {
    INFO("OCR " << ocr);
    const cc::CamClay mat(constants(cc::Variant::original), {ocr, 0.0}, closest_point());
    Point pt(mat, isotropic(p0_));
    double worst = 0.0, dq = 1.0, d = 5e-5;
    int steps = 0, plastic_steps = 0;
    while (dq > 1e-10 && steps < 3000) {
      const double q_before = q_of(pt.stress), pc_before = pt.history[0];
      REQUIRE(pt.step(undrained(d)).ok());
      const double p = p_of(pt.stress), q = q_of(pt.stress);
      dq = std::abs(q - q_before);
      if (pt.history[0] != pc_before) {
        const double eta = q / p;
        const double expected = std::exp(-Lambda_ * (eta / M_ - std::log(ocr)));
        worst = std::max(worst, std::abs(p / p0_ / expected - 1));
        ++plastic_steps;
      }
      if (plastic_steps >= 200) d = std::min(d * 1.05, 5e-3);
      ++steps;
    }
    REQUIRE(dq <= 1e-10);
    CHECK(plastic_steps > 200);
    const double pf = p0_ * std::pow(ocr / std::exp(1.0), Lambda_);
    REPORT("undrained OCC OCR " << ocr << ": p_f = " << p_of(pt.stress) << " (closed form " << pf
                                << "), q_f = " << q_of(pt.stress) << ", worst path error " << worst);
    CHECK(worst < 1e-4);
    CHECK(p_of(pt.stress) == Approx(pf).epsilon(1e-6));
    CHECK(q_of(pt.stress) == Approx(M_ * pf).epsilon(1e-6));
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: consistent tangent of the closest-point return vs finite differences", "[point]") {
  struct Case {
    const char* name;
    cc::Variant variant;
    double ocr;
    Vec6 de;
    int expect; // 0 elastic, 1 hardening, -1 softening
  };
  Vec6 shear_comp, small, dry;
  shear_comp << 1e-3, -2.5e-3, 6e-4, 8e-4, -3e-4, 5e-4; // compression and shear, NC: hardening
  small << 1e-5, -3e-5, 1e-5, 1e-5, 0, 0;               // OCR 4: inside the surface
  dry << 2e-3, -4e-3, 2e-3, 1.5e-3, 5e-4, -7e-4;        // OCR 4, heavy shear: dry side, softening
  const std::vector<Case> cases = {
      {"MCC elastic", cc::Variant::modified, 4.0, small, 0},
      {"MCC hardening", cc::Variant::modified, 1.0, shear_comp, 1},
      {"MCC softening", cc::Variant::modified, 4.0, dry, -1},
      {"OCC elastic", cc::Variant::original, 4.0, small, 0},
      {"OCC hardening", cc::Variant::original, 1.0, shear_comp, 1},
      {"OCC softening", cc::Variant::original, 4.0, dry, -1},
  };
  for (double G : {0.0, 6000.0}) {
    for (const Case& c : cases) {
      INFO(c.name << " G " << G);
      const cc::CamClay mat(constants(c.variant, G), {c.ocr, 0.0}, closest_point());
      // start from a sheared state: inside the surface (elastic case), or just yielded
      Point pt(mat, isotropic(p0_));
      if (c.expect == 0) {
        REQUIRE(pt.step(undrained(2e-4)).ok());
      } else {
        for (double pc = pt.history[0]; pt.history[0] == pc;) REQUIRE(pt.step(undrained(2e-4)).ok());
      }
      Vec6 s;
      std::array<double, 1> h{};
      Mat6 T;
      REQUIRE(pt.trial(c.de, s, h, T).ok());
      const double dpc = h[0] - pt.history[0];
      if (c.expect == 0) CHECK(dpc == 0.0);
      if (c.expect == 1) CHECK(dpc > 0.0);
      if (c.expect == -1) CHECK(dpc < 0.0);
      auto update = [&](const Vec6& de) {
        Vec6 sx;
        std::array<double, 1> hx{};
        Mat6 Tx;
        const auto o = pt.trial(de, sx, hx, Tx);
        REQUIRE(o.ok());
        return Eigen::VectorXd(sx);
      };
      const double err = rel_diff(T, fd_jacobian(update, c.de, 1e-7));
      REPORT("consistent tangent " << c.name << " G " << G << ": relative difference to FD " << err);
      CHECK(err < 1e-5);
    }
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: every integrator reaches the MCC undrained failure point", "[point]") {
  const double pf = p0_ * std::pow(0.5, Lambda_);
  struct Scheme {
    const char* name;
    pl::Settings settings;
  };
  std::vector<Scheme> schemes;
  auto add = [&](const char* name, pl::Scheme sc, auto tweak) {
    pl::Settings s;
    s.scheme = sc;
    tweak(s);
    schemes.push_back({name, s});
  };
  add("forward_euler", pl::Scheme::forward_euler, [](pl::Settings& s) { s.substeps = 100; });
  add("modified_euler", pl::Scheme::modified_euler, [](pl::Settings& s) { s.stol = 1e-6; });
  add("midpoint", pl::Scheme::midpoint, [](pl::Settings& s) { s.alpha = 0.5; });
  add("trapezoidal", pl::Scheme::trapezoidal, [](pl::Settings& s) { s.alpha = 0.5; });
  add("cutting_plane", pl::Scheme::cutting_plane, [](pl::Settings&) {});
  add("closest_point", pl::Scheme::closest_point, [](pl::Settings&) {});
  for (const Scheme& sc : schemes) {
    INFO(sc.name);
    const cc::CamClay mat(constants(), {1.0, 0.0}, sc.settings);
    Point pt(mat, isotropic(p0_));
    // 200 steps of 5e-5, then 200 steps of 1e-3 (20 % axial strain): well past failure
    for (int i = 0; i < 400; ++i) {
      const auto o = pt.step(undrained(i < 200 ? 5e-5 : 1e-3));
      INFO("step " << i << ": " << o.message);
      REQUIRE(o.ok());
    }
    const double p = p_of(pt.stress), q = q_of(pt.stress);
    REPORT(sc.name << ": undrained MCC end point p = " << p << " q = " << q << " relative errors "
                   << std::abs(p / pf - 1) << ", " << std::abs(q / (M_ * pf) - 1));
    CHECK(p == Approx(pf).epsilon(1e-3));
    CHECK(q == Approx(M_ * pf).epsilon(1e-3));
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: tension is refused with a message, never NaN", "[point]") {
  for (auto variant : {cc::Variant::modified, cc::Variant::original}) {
    INFO((variant == cc::Variant::modified ? "modified" : "original"));
    const cc::CamClay mat(constants(variant), {1.0, 0.0}, closest_point());
    {
      // a big tensile (expansive) increment from p0 = 200
      Point pt(mat, isotropic(p0_));
      Vec6 de = Vec6::Zero();
      de[0] = de[1] = de[2] = 0.02;
      Vec6 s = Vec6::Constant(-7.0);
      std::array<double, 1> h{};
      Mat6 T;
      const stratum::Outcome o = pt.trial(de, s, h, T);
      CHECK_FALSE(o.ok());
      CHECK(o.status == stratum::Status::material_failure);
      CHECK(o.message.find("p_min") != std::string::npos);
      CHECK(o.message.find("tension") != std::string::npos);
      // with shear as well, plastic dilation may keep p positive: either an admissible
      // state, or a failure with a message; never NaN
      for (double gamma : {0.01, 0.05, 0.2}) {
        de[3] = gamma;
        const stratum::Outcome o2 = pt.trial(de, s, h, T);
        INFO("gamma " << gamma << ": " << o2.message);
        if (o2.ok()) {
          CHECK(s.allFinite());
          CHECK(T.allFinite());
          CHECK(p_of(s) >= 1.0);
          CHECK(std::isfinite(h[0]));
        } else {
          CHECK_FALSE(o2.message.empty());
        }
      }
    }
    {
      // a point already in tension
      Point pt(mat, isotropic(-10.0));
      CHECK(pt.history[0] == Approx(1.0)); // p_min stands in for p
      const stratum::Outcome o = pt.step(Vec6::Zero());
      CHECK_FALSE(o.ok());
      CHECK(o.message.find("p = -10") != std::string::npos);
    }
    {
      // from zero stress a compression is accepted (the analysis may start unstressed)
      Point pt(mat, Vec6::Zero());
      Vec6 de = Vec6::Zero();
      de[0] = de[1] = de[2] = -1e-4;
      const stratum::Outcome o = pt.step(de);
      INFO(o.message);
      CHECK(o.ok());
      CHECK(p_of(pt.stress) > 0.0);
      CHECK(pt.stress.allFinite());
    }
  }
}

// ------------------------------------------------------------------------------------------
TEST_CASE("cam_clay: isotropic loading follows the normal compression and swelling lines", "[point]") {
  // NCL: eps_v = (lambda/v0) ln(p/p0); swelling line: eps_v - eps_v,max = (kappa/v0) ln(p/p_max)
  for (auto variant : {cc::Variant::modified, cc::Variant::original}) {
    INFO((variant == cc::Variant::modified ? "modified" : "original"));
    const cc::CamClay mat(constants(variant), {1.0, 0.0}, closest_point());
    Point pt(mat, isotropic(p0_));
    Vec6 de = Vec6::Zero();
    de[0] = de[1] = de[2] = -1e-3; // eps_v = 3e-3 per step
    for (int i = 0; i < 10; ++i) REQUIRE(pt.step(de).ok());
    const double ev = -pt.strain.head<3>().sum();
    const double p_max = p0_ * std::exp(2.0 * ev / lambda_);
    CHECK(p_of(pt.stress) == Approx(p_max).epsilon(1e-10));
    CHECK(q_of(pt.stress) < 1e-9);
    CHECK(pt.history[0] == Approx(p_max).epsilon(1e-10));
    for (int i = 0; i < 5; ++i) REQUIRE(pt.step(-de).ok());
    CHECK(p_of(pt.stress) == Approx(p_max * std::exp(-2.0 * 15e-3 / kappa_)).epsilon(1e-10));
    CHECK(pt.history[0] == Approx(p_max).epsilon(1e-12));
  }
}

TEST_CASE("cam_clay: one large undrained step of the closest point lands on the closed form", "[point]") {
  for (double d : {2e-3, 1e-2, 5e-2}) {
    INFO("axial strain " << d);
    const cc::CamClay mat(constants(), {1.0, 0.0}, closest_point());
    Point pt(mat, isotropic(p0_));
    const auto o = pt.step(undrained(d));
    INFO(o.message);
    REQUIRE(o.ok());
    const double p = p_of(pt.stress), q = q_of(pt.stress);
    CHECK(q / p == Approx(mcc_undrained_ratio(p, 1.0)).epsilon(1e-9));
  }
}

} // namespace test_cam_clay
