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
#include <cstdio>

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
[[maybe_unused]] Mat6 fd_tangent(const Point& p, const Vec6& de, double h) {
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

[[maybe_unused]] double rel_diff(const Mat6& a, const Mat6& b) { return (a - b).norm() / b.norm(); }

/// Drained triaxial step: axial (yy) strain increment dea (tension positive), lateral stresses
/// (xx, zz) held at their current values by Newton on the lateral strains with the tangent.
stratum::Outcome triaxial_step(Point& p, double dea, Vec6& de_guess) {
  Vec6 de = de_guess;
  de[1] = dea;
  const double sx = p.stress[0], sz = p.stress[2];
  for (int it = 0; it < 30; ++it) {
    Vec6 s;
    std::array<double, 4> h{};
    Mat6 T;
    const stratum::Outcome o = p.trial(de, s, h, T);
    if (!o.ok()) return o;
    const Eigen::Vector2d r(s[0] - sx, s[2] - sz);
    if (r.norm() <= 1e-10 * std::abs(sx)) {
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

TEST_CASE("lade: explore triaxial", "[.lade-explore]") {
  const ld::Lade mat(dense_sand());
  Point p(mat, isotropic(100.0));
  Vec6 g = Vec6::Zero();
  for (int k = 0; k < 300; ++k) {
    const auto o = triaxial_step(p, -5e-5, g);
    if (!o.ok()) {
      std::printf("fail %s\n", o.message.c_str());
      break;
    }
    if (k % 10 == 0)
      std::printf("%4d ea=%.5f ev=%.6f q=%.2f fp=%.3f W1=%.4g W2=%.4g set=%d sub=%g\n", k, -p.strain[1],
                  -(p.strain[0] + p.strain[1] + p.strain[2]), -(p.stress[1] - p.stress[0]), mat.fp(-p.stress),
                  p.history[0], p.history[1], p.active(), p.history[3]);
  }
}
