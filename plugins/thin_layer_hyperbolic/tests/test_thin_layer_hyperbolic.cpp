// Tests of the thin-layer interface material (plugins/thin_layer_hyperbolic, thesis (3.63)-(3.67)):
// - simple shear at constant sigma_n follows the hyperbola whose tangent is (3.65), caps at tau_f;
// - unloading and reloading with G_i below the remembered stress level;
// - finite-difference check of the (non-symmetric) tangent in every regime;
// - C1 rigid pile with a hyperbolic thin layer on the shaft: shaft capacity 2 pi r_mid L tau_f.
#include "contact_scenes.hpp"
#include "scene_helpers.hpp"
#include "thin_layer_hyperbolic/thin_layer_hyperbolic.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace test_thin_layer_hyperbolic {

using namespace stratum;
using namespace stratum::testing;
namespace tl = stratum::thin_layer_hyperbolic;

namespace {

tl::Constants loess() {
  tl::Constants c;
  c.E = 2e4, c.nu = 0.3, c.K_I = 2000.0, c.n = 0.89, c.R_f = 0.9, c.c_a = 10.0, c.delta = 29.0;
  return c;
}

/// One material point: committed stress and history; step() applies a strain increment.
struct Point {
  const tl::ThinLayerHyperbolic& m;
  Vec6 stress = Vec6::Zero(), strain = Vec6::Zero();
  std::vector<double> h = std::vector<double>(2, 0.0);
  Mat6 D = Mat6::Zero();

  Outcome trial(const Vec6& de, Vec6& s, std::vector<double>& hn, Mat6& Dt) const {
    hn.assign(h.size(), 0.0);
    MaterialInput in{stress, strain, h, de, {}};
    MaterialOutput out{s, hn, Dt};
    return m.update(in, out);
  }
  void step(const Vec6& de) {
    Vec6 s;
    std::vector<double> hn;
    REQUIRE(trial(de, s, hn, D).ok());
    stress = s, h = hn, strain += de;
  }
};

/// Largest |D_fd - D|_ij / (|D_ij| + 1e-6 max |D|), D_fd by central differences of the update.
double fd_error(const Point& p, const Vec6& de, bool skip_shear_shear = false) {
  Vec6 s;
  std::vector<double> hn;
  Mat6 D;
  REQUIRE(p.trial(de, s, hn, D).ok());
  const double eps = 1e-7;
  double err = 0.0;
  for (int j = 0; j < 6; ++j) {
    Vec6 dp = de, dm = de;
    dp[j] += eps, dm[j] -= eps;
    Vec6 sp, sm;
    Mat6 Dd;
    REQUIRE(p.trial(dp, sp, hn, Dd).ok());
    REQUIRE(p.trial(dm, sm, hn, Dd).ok());
    const Vec6 col = (sp - sm) / (2 * eps);
    for (int i = 0; i < 6; ++i) {
      if (skip_shear_shear && i == voigt::xy && j == voigt::xy) continue;
      // Entry-wise, so that the small shear entries of a soft layer are checked as well.
      err = std::max(err, std::abs(col[i] - D(i, j)) / (std::abs(D(i, j)) + 1e-6 * D.cwiseAbs().maxCoeff()));
    }
  }
  return err;
}

Vec6 shear(double g) {
  Vec6 d = Vec6::Zero();
  d[voigt::xy] = g;
  return d;
}

} // namespace

TEST_CASE("thin_layer_hyperbolic: simple shear at constant sigma_n follows the hyperbola (3.65)",
          "[thin_layer]") {
  for (const bool vertical : {true, false})
    for (const double t : {0.0, 0.005})
      for (const double sn : {25.0, 50.0, 75.0})
        for (const int steps : {2000, 7}) {
          CAPTURE(vertical, t, sn, steps);
          tl::Constants c = loess();
          c.vertical = vertical, c.thickness = t;
          const tl::ThinLayerHyperbolic m(c);
          const double Gi = (t > 0 ? t : 1.0) * c.K_I * c.gamma_w * std::pow(sn / c.p_a, c.n);
          const double tf = c.c_a + sn * std::tan(c.delta * std::numbers::pi / 180);
          const double gf = tf / (Gi * (1 - c.R_f)); // strain at which the hyperbola reaches tau_f
          Point p{m};
          p.stress[vertical ? voigt::xx : voigt::yy] = -sn;
          p.stress[vertical ? voigt::yy : voigt::xx] = -2 * sn; // the tangential stress plays no role
          double worst = 0.0;
          const double gmax = 0.95 * gf;
          for (int i = 1; i <= steps; ++i) {
            p.step(shear(gmax / steps));
            const double g = gmax * i / steps;
            const double expected = g / (1 / Gi + c.R_f * g / tf);
            worst = std::max(worst, std::abs(p.stress[voigt::xy] - expected) / tf);
          }
          CHECK(worst < 1e-4);
          // The tangent at the end is (3.65) itself.
          const double tau = p.stress[voigt::xy];
          CHECK(std::abs(p.D(voigt::xy, voigt::xy) - Gi * std::pow(1 - c.R_f * tau / tf, 2)) < 1e-8 * Gi);
          // The normal stress is untouched.
          CHECK(std::abs(p.stress[vertical ? voigt::xx : voigt::yy] + sn) < 1e-12);
          // Beyond gamma_f the stress sits at tau_f; the tangent keeps the residual modulus.
          p.step(shear(0.2 * gf));
          CHECK(std::abs(p.stress[voigt::xy] - tf) < 1e-12 * tf);
          CHECK(p.h[1] == 1.0);
          CHECK(std::abs(p.D(voigt::xy, voigt::xy) - c.residual * Gi) < 1e-12 * Gi);
          // Negative shear mirrors: unload all the way and fail on the other side.
          p.step(shear(-2.6 * gf));
          CHECK(std::abs(p.stress[voigt::xy] + tf) < 1e-12 * tf);
        }
}

TEST_CASE("thin_layer_hyperbolic: unloading and reloading use G_i below the memory", "[thin_layer]") {
  const tl::Constants c = loess();
  const tl::ThinLayerHyperbolic m(c);
  const double sn = 50.0;
  const double Gi = c.K_I * c.gamma_w * std::pow(sn / c.p_a, c.n);
  const double tf = c.c_a + sn * std::tan(c.delta * std::numbers::pi / 180);
  auto hyper = [&](double g) { return g / (1 / Gi + c.R_f * g / tf); };
  const double g1 = 1.0 * tf / Gi; // about 0.5 tau_f
  Point p{m};
  p.stress[voigt::xx] = -sn;
  p.step(shear(g1));
  const double tau1 = hyper(g1);
  CHECK(std::abs(p.stress[voigt::xy] - tau1) < 1e-12 * tf);
  CHECK(std::abs(p.h[0] - tau1 / tf) < 1e-14);
  // Unload by du: linear with G_i.
  const double back = 0.3 * g1;
  p.step(shear(-back));
  CHECK(std::abs(p.stress[voigt::xy] - (tau1 - Gi * back)) < 1e-10 * tf);
  CHECK(std::abs(p.D(voigt::xy, voigt::xy) - Gi) < 1e-10 * Gi);
  // Reload past the memory in one step: G_i back to tau1, then the hyperbola from g1 onwards.
  const double more = 0.4 * g1;
  p.step(shear(back + more));
  CHECK(std::abs(p.stress[voigt::xy] - hyper(g1 + more)) < 1e-10 * tf);
}

TEST_CASE("thin_layer_hyperbolic: finite-difference check of the tangent", "[thin_layer]") {
  for (const bool vertical : {true, false})
    for (const double t : {0.0, 0.004}) {
      CAPTURE(vertical, t);
      tl::Constants c = loess();
      c.vertical = vertical, c.thickness = t;
      const tl::ThinLayerHyperbolic m(c);
      const int nrm = vertical ? voigt::xx : voigt::yy, tng = vertical ? voigt::yy : voigt::xx;
      const double sn = 40.0;
      const double Gi = (t > 0 ? t : 1.0) * c.K_I * c.gamma_w * std::pow(sn / c.p_a, c.n);
      const double tf = c.c_a + sn * std::tan(c.delta * std::numbers::pi / 180);
      const double g = tf / Gi; // strain scale
      // A mixed increment: shear plus normal strains that change sigma_n by a few kPa.
      Vec6 mixed = Vec6::Zero();
      mixed[voigt::xy] = 0.3 * g;
      mixed[nrm] = -3.0 / c.C1();
      mixed[tng] = 1.0 / c.C1();
      mixed[voigt::zz] = 0.5 / c.C1();
      mixed[voigt::yz] = 1e-4, mixed[voigt::zx] = -1e-4;
      Point p{m};
      p.stress[nrm] = -sn;
      CHECK(fd_error(p, mixed) < 1e-5); // virgin loading
      p.step(shear(1.5 * g));
      CHECK(fd_error(p, mixed) < 1e-5); // on the hyperbola
      Vec6 unload = mixed;
      unload[voigt::xy] = -0.3 * g;
      CHECK(fd_error(p, unload) < 1e-5); // unloading below the memory
      Vec6 reload = mixed;
      p.step(shear(-0.5 * g));
      reload[voigt::xy] = 0.8 * g; // through the memory into the hyperbola
      CHECK(fd_error(p, reload) < 1e-5);
      // At failure every entry but the shear-shear one is exact (d tau / d sigma_n = tan delta).
      p.step(shear(20 * g));
      REQUIRE(p.h[1] == 1.0);
      CHECK(fd_error(p, mixed, true) < 1e-5);
      CHECK(std::abs(p.D(voigt::xy, nrm) + c.tan_delta() * c.C1()) < 1e-9 * c.C1());
    }
}

TEST_CASE("thin_layer_hyperbolic: C1 rigid pile with a hyperbolic thin layer, shaft capacity",
          "[thin_layer]") {
  PileSpec s;
  s.kind = "thin_layer";
  const double K_I = 1e5, n = 0.5, R_f = 0.9, c_a = 20.0, delta = 20.0, floor = 0.01, p_a = 100.0;
  // No initial stress: sigma_n across the layer stays near zero, so the floor sigma_n = 0.01 p_a
  // sets G_i and tau_f (README).
  const double tf = c_a + floor * p_a * std::tan(delta * std::numbers::pi / 180);
  const double ks = K_I * 9.81 * std::pow(floor, n); // kPa/m; G_i = t k_s
  const double capacity = 2 * std::numbers::pi * (s.r0 + 0.5 * s.layer) * s.L * tf;
  // Before slip: soil (concentric cylinders from r_s = r0 + t) in series with the layer:
  // w = tau r_s ln(rm / r_s) / G + t gamma(tau), gamma = tau / (G_i (1 - R_f tau / tau_f)).
  const double rs = s.r0 + s.layer;
  auto w_of_tau = [&](double tau) {
    return tau * rs * std::log(s.rm / rs) / s.G() + tau / (ks * (1 - R_f * tau / tf));
  };
  // 8-node cells: the first Newton iterate of a step puts opposite shear signs at the two Gauss
  // columns of the layer (quadratic u across it), which the loading/unloading rule and the cap can
  // lock; a line search gets through (README). 4-node cells need none.
  for (const int npc : {4, 8}) {
    CAPTURE(npc);
    std::string text = pile_scene(s);
    auto replace = [&](const std::string& a, const std::string& b) {
      const auto pos = text.find(a);
      REQUIRE(pos != std::string::npos);
      text.replace(pos, a.size(), b);
    };
    const auto a0 = text.find("[materials.layer]");
    const auto a1 = text.find("[[domains]]", a0);
    REQUIRE(a0 != std::string::npos);
    REQUIRE(a1 != std::string::npos);
    std::ostringstream mat;
    mat.precision(17);
    mat << "[materials.layer]\nmodel = \"thin_layer_hyperbolic\"\nE = " << s.E << "\nnu = " << s.nu
        << "\nK_I = " << K_I << "\nn = " << n << "\nR_f = " << R_f << "\nc_a = " << c_a
        << "\ndelta = " << delta << "\nthickness = " << s.layer << "\norientation = \"vertical\"\n";
    text.replace(a0, a1 - a0, mat.str());
    if (npc == 4)
      replace("nodes_per_cell = 8", "nodes_per_cell = 4");
    else
      replace("[mesh]", "[solver]\nline_search = 8\n[mesh]");
    std::vector<std::pair<double, double>> curve;
    RunOptions o;
    o.plugin_dirs = {STRATUM_PLUGIN_DIR};
    o.write_output = false;
    Analysis* self = nullptr;
    o.on_step = [&](int, int, double lambda, const StepReport&) {
      curve.emplace_back(lambda * s.w_max(), pile_load(self->model(), s));
    };
    auto a = Analysis::from_string(text, "pile_hyperbolic.toml", o);
    self = a.get();
    const auto run = a->run();
    CAPTURE(run.outcome.message);
    REQUIRE(run.outcome.ok());
    REQUIRE(curve.size() == static_cast<std::size_t>(s.steps));
    for (std::size_t i = 1; i < curve.size(); ++i) CHECK(curve[i].second >= curve[i - 1].second - 1e-9);
    // First step (below slip): tau from w by bisection, P = 2 pi r_s L tau, within 10 %.
    const double w1 = curve.front().first;
    double lo = 0.0, hi = tf / R_f * (1 - 1e-12);
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (std::min(w_of_tau(mid), 1e300) < w1 ? lo : hi) = mid;
    }
    const double P1 = 2 * std::numbers::pi * rs * s.L * lo;
    CAPTURE(w1, curve.front().second, P1);
    CHECK(lo < 0.9 * tf);
    CHECK(std::abs(curve.front().second - P1) <= 0.10 * P1);
    CAPTURE(curve.back().second, capacity);
    CHECK(std::abs(curve.back().second - capacity) <= 0.01 * capacity);
  }
}

} // namespace test_thin_layer_hyperbolic
