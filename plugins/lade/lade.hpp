// Lade's (1977) double-hardening model ("lade"), thesis §2.4.6 (2.152)-(2.168).
//
// Header only, so that the tests use the plugin's own code; lade.cpp only adds the factory.
// Equations, parameters, the integration scheme and the corrections to the OCR'd thesis
// formulas: README.md in this folder.
//
// Inside the model stresses and strains are compression positive (Lade's convention); the
// framework's are tension positive. The update negates both at the boundary; the tangent
// d sigma / d eps is unchanged by negating both.
//
//   invariants  I1 = tr s, I3 = det s, f_c = I1^2 + 2 I2 = s : s (Lade's I2 = -(s1 s2 + s2 s3 + s3 s1))
//   cone        f_p(s) = (I1^3 / I3 - 27)(I1 / p_a)^m  =  H1(W1) = a exp(-b W1) (W1 / p_a)^(1/q)   (2.152)
//               potential g_1 = I1^3 - [27 + eta2 (p_a / I1)^m] I3                             (2.154)
//   cap         f_c(s) / p_a^2 = H2(W2) = (W2 / (C p_a))^(1/p), associated                   (2.155), (2.157)
//   hardening   dW_k = s : d eps^p_k (plastic work of each mechanism)
//               W_peak = P p_a (s3 / p_a)^l, q = alpha + beta s3 / p_a,
//               b = 1 / (q W_peak), a = eta1 (e p_a / W_peak)^(1/q)  (so max H1 = eta1 at W_peak)
//               eta2 = t + R sqrt(s3 / p_a) + S f_p
//   elasticity  E_ur = K_ur p_a (s3 / p_a)^n, constant nu (s3: minor principal stress)
//
// The stress-dependent quantities (E_ur, q, W_peak, a, b, eta2) are evaluated once per update
// from the committed stress s_n and held for the increment ("frozen"); the return itself is a
// fully implicit (backward-Euler) two-surface return with both multipliers solved at once by
// Newton on the 10 unknowns (s, v1, W2, lambda1, lambda2), v1 = (W1 / p_a)^(1/q). If Newton
// fails, the increment is split into 2, 4, ... (up to 64 x the `substeps` minimum) equal
// substeps. The tangent is the exact derivative of this algorithm (sensitivities carried
// through the substeps): unsymmetric.
//
// History (framework owned): [0] W1 cone plastic work (kPa), [1] W2 cap plastic work (kPa),
// [2] active set of the last increment (0 elastic, 1 cone, 2 cap, 3 both), [3] substeps used.
#pragma once

#include "common/material_checks.hpp"
#include "stratum/elasticity.hpp"
#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/parameters.hpp"
#include "stratum/stress.hpp"
#include "stratum/voigt.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>

namespace stratum::lade {

/// Material constants, Lade's names. p_a and all stresses in kPa.
struct Constants {
  double pa = 100.0;   ///< atmospheric pressure (kPa)
  double Kur = 1000.0; ///< unload-reload modulus number (-)
  double n = 0.4;      ///< unload-reload modulus exponent (-)
  double nu = 0.2;     ///< Poisson's ratio (-)
  double eta1 = 80.0;  ///< cone: value of f_p at failure (-)
  double m = 0.1;      ///< cone: meridian curvature (-)
  double P = 0.05;     ///< cone hardening: W_peak = P p_a (s3/p_a)^l (-)
  double l = 1.0;      ///< cone hardening exponent (-)
  double alpha = 1.5;  ///< cone hardening: q = alpha + beta s3/p_a (-)
  double beta = 0.0;   ///< (-)
  double t = 40.0;     ///< potential: eta2 = t + R sqrt(s3/p_a) + S f_p (-)
  double R = 0.0;      ///< (-)
  double S = 0.0;      ///< (-)
  double C = 0.0002;   ///< cap: W2 = C p_a (f_c/p_a^2)^p (-)
  double p = 0.8;      ///< cap hardening exponent (-)
  double s3_min = 1.0; ///< floor on s3 in the stress-dependent quantities (kPa)
  int substeps = 1;    ///< minimum number of equal substeps per update (doubled while Newton fails)
};

/// Checks what the schema ranges cannot.
[[nodiscard]] inline std::optional<Problem> check(const Constants& c) {
  if (!(c.alpha + c.beta * c.s3_min / c.pa > 0.0))
    return Problem{"beta", "alpha + beta s3/p_a must stay positive (q > 0), got alpha = " + number(c.alpha) +
                               ", beta = " + number(c.beta)};
  return std::nullopt;
}

using Vec10 = Eigen::Matrix<double, 10, 1>;
using Mat10 = Eigen::Matrix<double, 10, 10>;
using Mat10x6 = Eigen::Matrix<double, 10, 6>;

[[nodiscard]] inline Vec6 delta() {
  Vec6 d = Vec6::Zero();
  d[0] = d[1] = d[2] = 1.0;
  return d;
}
[[nodiscard]] inline double I1(const Vec6& s) { return s[0] + s[1] + s[2]; }
/// det of the symmetric tensor; Voigt xx, yy, zz, xy, yz, zx.
[[nodiscard]] inline double I3(const Vec6& s) {
  return s[0] * s[1] * s[2] + 2.0 * s[3] * s[4] * s[5] - s[0] * s[4] * s[4] - s[1] * s[5] * s[5] -
         s[2] * s[3] * s[3];
}
/// d I3 / d s (Voigt derivative: shear entries are engineering-strain-like).
[[nodiscard]] inline Vec6 dI3(const Vec6& s) {
  Vec6 g;
  g << s[1] * s[2] - s[4] * s[4], s[0] * s[2] - s[5] * s[5], s[0] * s[1] - s[3] * s[3],
      2.0 * (s[4] * s[5] - s[2] * s[3]), 2.0 * (s[3] * s[5] - s[0] * s[4]), 2.0 * (s[3] * s[4] - s[1] * s[5]);
  return g;
}
[[nodiscard]] inline Mat6 d2I3(const Vec6& s) {
  Mat6 H = Mat6::Zero();
  H(0, 1) = H(1, 0) = s[2];
  H(0, 2) = H(2, 0) = s[1];
  H(1, 2) = H(2, 1) = s[0];
  H(0, 4) = H(4, 0) = -2.0 * s[4];
  H(1, 5) = H(5, 1) = -2.0 * s[5];
  H(2, 3) = H(3, 2) = -2.0 * s[3];
  H(3, 3) = -2.0 * s[2];
  H(4, 4) = -2.0 * s[0];
  H(5, 5) = -2.0 * s[1];
  H(3, 4) = H(4, 3) = 2.0 * s[5];
  H(3, 5) = H(5, 3) = 2.0 * s[4];
  H(4, 5) = H(5, 4) = 2.0 * s[3];
  return H;
}
/// f_c = s : s = I1^2 + 2 I2 and its Voigt gradient and Hessian.
[[nodiscard]] inline double fc(const Vec6& s) {
  return s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
}
[[nodiscard]] inline Vec6 dfc(const Vec6& s) {
  Vec6 g;
  g << 2.0 * s[0], 2.0 * s[1], 2.0 * s[2], 4.0 * s[3], 4.0 * s[4], 4.0 * s[5];
  return g;
}
[[nodiscard]] inline Mat6 d2fc() {
  Mat6 H = Mat6::Zero();
  for (int i = 0; i < 3; ++i) H(i, i) = 2.0;
  for (int i = 3; i < 6; ++i) H(i, i) = 4.0;
  return H;
}
/// Minor principal stress (compression positive: the smallest eigenvalue).
[[nodiscard]] inline double sigma3(const Vec6& s) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(stress_tensor(s), Eigen::EigenvaluesOnly)
      .eigenvalues()[0];
}

/// A scalar function of (I1, I3) with its partial derivatives up to second order.
struct Fn {
  double v = 0, d1 = 0, d3 = 0, d11 = 0, d13 = 0, d33 = 0;
  [[nodiscard]] Vec6 grad(const Vec6& s) const { return d1 * delta() + d3 * dI3(s); }
  [[nodiscard]] Mat6 hess(const Vec6& s) const {
    const Vec6 d = delta(), g3 = dI3(s);
    return d11 * d * d.transpose() + d13 * (d * g3.transpose() + g3 * d.transpose()) +
           d33 * g3 * g3.transpose() + d3 * d2I3(s);
  }
};

/// f_p = (I1^3/I3 - 27)(I1/p_a)^m.
[[nodiscard]] inline Fn cone_f(double i1, double i3, double m, double pa) {
  const double A = i1 * i1 * i1 / i3 - 27.0, A1 = 3.0 * i1 * i1 / i3, A3 = -i1 * i1 * i1 / (i3 * i3);
  const double A11 = 6.0 * i1 / i3, A13 = -3.0 * i1 * i1 / (i3 * i3),
               A33 = 2.0 * i1 * i1 * i1 / (i3 * i3 * i3);
  const double B = std::pow(i1 / pa, m), B1 = m * B / i1, B11 = m * (m - 1.0) * B / (i1 * i1);
  return {A * B, A1 * B + A * B1, A3 * B, A11 * B + 2.0 * A1 * B1 + A * B11, A13 * B + A3 * B1, A33 * B};
}

/// g_1 / p_a^3 = (I1^3 - [27 + eta2 (p_a/I1)^m] I3) / p_a^3.
[[nodiscard]] inline Fn cone_g(double i1, double i3, double m, double eta2, double pa) {
  const double r = eta2 * std::pow(pa / i1, m);
  const double E = 27.0 + r, E1 = -m * r / i1, E11 = m * (m + 1.0) * r / (i1 * i1);
  const double k = 1.0 / (pa * pa * pa);
  return {k * (i1 * i1 * i1 - E * i3),
          k * (3.0 * i1 * i1 - E1 * i3),
          -k * E,
          k * (6.0 * i1 - E11 * i3),
          -k * E1,
          0.0};
}

/// The quantities held for one update (evaluated from the committed stress).
struct Frozen {
  Mat6 D;
  double q = 1, Wpeak = 1, a = 1, b = 1, eta2 = 0;
};

class Lade final : public Material {
public:
  explicit Lade(const Constants& c) : c_(c) {}
  [[nodiscard]] const Constants& constants() const { return c_; }

  [[nodiscard]] int history_size() const override { return 4; }
  /// The VTK names of the plastic work of the cone (W1) and of the cap (W2).
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"W_cone", "kPa"}, {"W_cap", "kPa"}});
  }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  /// The active set of the committed increment (history[2]): 0 elastic, 1 cone (shear
  /// hardening), 2 cap (collapse), 3 cone and cap; 4 cone past its peak (W_cone above W_peak at
  /// the committed stress: softening), with or without the cap.
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> h) const override {
    if (h.size() < 3) return -1;
    const int set = static_cast<int>(h[2]);
    if ((set & 1) != 0 && h[0] > frozen(-stress).Wpeak) return 4;
    return set;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"elastic", "cone (shear hardening)", "cap (collapse)", "cone and cap",
            "cone past peak (softening)"};
  }

  /// Elastic stiffness, q, W_peak, a, b and eta2 at the compression-positive stress s.
  [[nodiscard]] Frozen frozen(const Vec6& s) const {
    Frozen z;
    const double s3 = std::max(sigma3(s), c_.s3_min), r = s3 / c_.pa;
    const double E = c_.Kur * c_.pa * std::pow(r, c_.n);
    const double K = E / (3.0 * (1.0 - 2.0 * c_.nu)), G = E / (2.0 * (1.0 + c_.nu));
    z.D = stiffness_kg(K, G);
    z.q = c_.alpha + c_.beta * r;
    z.Wpeak = c_.P * c_.pa * std::pow(r, c_.l);
    z.b = 1.0 / (z.q * z.Wpeak);
    z.a = c_.eta1 * std::pow(std::exp(1.0) * c_.pa / z.Wpeak, 1.0 / z.q);
    const double i1 = I1(s), i3 = I3(s);
    const double fp = (i1 > 0.0 && i3 > 0.0) ? cone_f(i1, i3, c_.m, c_.pa).v : 0.0;
    z.eta2 = c_.t + c_.R * std::sqrt(r) + c_.S * fp;
    return z;
  }

  /// H1 as a function of the plastic work, with the constants of `z`.
  [[nodiscard]] static double H1(const Frozen& z, double W, double pa) {
    return z.a * std::exp(-z.b * W) * std::pow(std::max(W, 0.0) / pa, 1.0 / z.q);
  }
  [[nodiscard]] double H2(double W2) const {
    return std::pow(std::max(W2, 0.0) / (c_.C * c_.pa), 1.0 / c_.p);
  }
  /// Cap plastic work for which the cap passes through s (Lade's collapse work law).
  [[nodiscard]] double cap_work(const Vec6& s) const {
    return c_.C * c_.pa * std::pow(fc(s) / (c_.pa * c_.pa), c_.p);
  }
  [[nodiscard]] double fp(const Vec6& s) const { return cone_f(I1(s), I3(s), c_.m, c_.pa).v; }

  /// Virgin point: both surfaces pass through the initial stress (cone on its rising branch).
  void init_history(const Vec6& stress, std::span<double> h) const override {
    std::fill(h.begin(), h.end(), 0.0);
    const Vec6 s = -stress;
    const double i1 = I1(s), i3 = I3(s);
    if (!(i1 > 0.0 && i3 > 0.0)) return;
    h[1] = cap_work(s);
    const Frozen z = frozen(s);
    const double f = fp(s);
    if (f <= 0.0) return;
    if (f >= c_.eta1) {
      h[0] = z.Wpeak;
      return;
    }
    double lo = 0.0, hi = z.Wpeak;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (H1(z, mid, c_.pa) < f ? lo : hi) = mid;
    }
    h[0] = 0.5 * (lo + hi);
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    if (Outcome o = material_checks::finite_input(in, "lade"); !o.ok()) return o;
    const Vec6 sn = -in.stress_n, de = -in.dstrain;
    if (!(I1(sn) > 0.0 && I3(sn) > 0.0))
      return Outcome::failure(Status::material_failure,
                              "lade: committed stress outside the cone (I1 = " + number(I1(sn)) +
                                  ", I3 = " + number(I3(sn)) + " kPa^3; the model has no tensile strength)" +
                                  material_checks::where(in));
    const Frozen z = frozen(sn);
    for (int nsub = std::max(c_.substeps, 1); nsub <= 64 * std::max(c_.substeps, 1); nsub *= 2) {
      State st{sn, in.history_n[0], in.history_n[1]};
      Sens sens;
      int set = 0;
      bool ok = true;
      for (int k = 0; k < nsub && ok; ++k) ok = substep(z, de / nsub, 1.0 / nsub, st, sens, set);
      if (!ok) continue;
      out.stress = -st.s;
      out.tangent = sens.s;
      out.history[0] = st.W1;
      out.history[1] = st.W2;
      out.history[2] = set;
      out.history[3] = nsub;
      for (std::size_t i = 4; i < out.history.size(); ++i) out.history[i] = 0.0;
      return Outcome::success();
    }
    return Outcome::failure(Status::not_converged, "lade: two-surface return did not converge with " +
                                                       std::to_string(64 * std::max(c_.substeps, 1)) +
                                                       " substeps" + material_checks::where(in));
  }

private:
  struct State {
    Vec6 s;
    double W1, W2;
  };
  /// Derivatives of the state with respect to the (compression-positive) strain increment.
  struct Sens {
    Mat6 s = Mat6::Zero();
    Eigen::Matrix<double, 1, 6> W1 = Eigen::Matrix<double, 1, 6>::Zero(),
                                W2 = Eigen::Matrix<double, 1, 6>::Zero();
  };

  [[nodiscard]] static bool admissible(const Vec6& s) { return s.allFinite() && I1(s) > 0.0 && I3(s) > 0.0; }

  /// Residual and Jacobian of the return with active set (a1, a2); x = (s, v1, W2, l1, l2).
  bool residual(const Frozen& z, const Vec6& str, const State& st0, bool a1, bool a2, const Vec10& x,
                Vec10& R, Mat10* J) const {
    const Vec6 s = x.head<6>();
    const double v = x[6], W2 = x[7], l1 = x[8], l2 = x[9], pa = c_.pa;
    if (!admissible(s) || !(v >= 0.0) || !(W2 >= 0.0)) return false;
    const double i1 = I1(s), i3 = I3(s);
    const Fn f = cone_f(i1, i3, c_.m, pa), g = cone_g(i1, i3, c_.m, z.eta2, pa);
    const Vec6 g1 = g.grad(s), g2 = dfc(s) / (pa * pa);
    const double w1 = s.dot(g1), w2 = s.dot(g2);
    const double W1 = pa * std::pow(v, z.q);
    const double e = std::exp(-z.b * W1);
    R.head<6>() = s - str + l1 * (z.D * g1) + l2 * (z.D * g2);
    const double v0 = std::pow(std::max(st0.W1, 0.0) / pa, 1.0 / z.q);
    R[6] = a1 ? (W1 - st0.W1 - l1 * w1) / pa : v - v0;
    R[7] = (W2 - st0.W2 - l2 * w2) / pa;
    R[8] = a1 ? (f.v - z.a * v * e) / c_.eta1 : l1;
    R[9] = a2 ? fc(s) / (pa * pa) - H2(W2) : l2;
    if (!R.allFinite()) return false;
    if (!J) return true;
    const Mat6 G1 = g.hess(s), G2 = d2fc() / (pa * pa);
    const double dW1dv =
        v > 0.0 ? pa * z.q * std::pow(v, z.q - 1.0) : (z.q < 1.0 ? 1e300 : (z.q == 1.0 ? pa : 0.0));
    J->setZero();
    J->topLeftCorner<6, 6>() = Mat6::Identity() + l1 * z.D * G1 + l2 * z.D * G2;
    J->block<6, 1>(0, 8) = z.D * g1;
    J->block<6, 1>(0, 9) = z.D * g2;
    if (a1) {
      J->block<1, 6>(6, 0) = -l1 * (g1 + G1 * s).transpose() / pa;
      (*J)(6, 6) = dW1dv / pa;
      (*J)(6, 8) = -w1 / pa;
    } else {
      (*J)(6, 6) = 1.0;
    }
    J->block<1, 6>(7, 0) = -l2 * (g2 + G2 * s).transpose() / pa;
    (*J)(7, 7) = 1.0 / pa;
    (*J)(7, 9) = -w2 / pa;
    if (a1) {
      J->block<1, 6>(8, 0) = f.grad(s).transpose() / c_.eta1;
      (*J)(8, 6) = -z.a * e * (1.0 - z.b * dW1dv * v) / c_.eta1;
    } else {
      (*J)(8, 8) = 1.0;
    }
    if (a2) {
      J->block<1, 6>(9, 0) = g2.transpose();
      (*J)(9, 7) = W2 > 0.0 ? -H2(W2) / (c_.p * W2) : 0.0;
    } else {
      (*J)(9, 9) = 1.0;
    }
    return J->allFinite();
  }

  /// Newton with backtracking; returns the converged x and the Jacobian there.
  bool solve(const Frozen& z, const Vec6& str, const State& st0, bool a1, bool a2, Vec10& x, Mat10& J) const {
    Vec10 R;
    if (!residual(z, str, st0, a1, a2, x, R, &J)) return false;
    const double scale = str.norm() + c_.pa;
    for (int it = 0; it < 60; ++it) {
      const Eigen::PartialPivLU<Mat10> lu(J);
      const Vec10 dx = -lu.solve(R);
      if (!dx.allFinite()) return false;
      double t = 1.0;
      Vec10 xn, Rn;
      Mat10 Jn;
      bool accepted = false;
      for (int bt = 0; bt < 30; ++bt, t *= 0.5) {
        xn = x + t * dx;
        if (residual(z, str, st0, a1, a2, xn, Rn, &Jn) &&
            (bt == 29 || Rn.norm() < (1.0 - 1e-4 * t) * R.norm() || Rn.norm() < 1e-13)) {
          accepted = true;
          break;
        }
      }
      if (!accepted) return false;
      x = xn, R = Rn, J = Jn;
      const bool small_step = (t * dx.head<6>()).norm() <= 1e-12 * scale;
      if (R.head<6>().norm() <= 1e-11 * scale && R.tail<4>().lpNorm<Eigen::Infinity>() <= 1e-12) return true;
      if (small_step && R.norm() <= 1e-9) return true;
    }
    return false;
  }

  /// One backward-Euler substep from st with increment de; updates st, the sensitivities and
  /// the active-set code.
  bool substep(const Frozen& z, const Vec6& de, double share, State& st, Sens& sens, int& set) const {
    const double pa = c_.pa;
    const Vec6 str = st.s + z.D * de;
    const double v0 = std::pow(std::max(st.W1, 0.0) / pa, 1.0 / z.q);
    bool a1, a2;
    if (admissible(str)) {
      a1 = cone_f(I1(str), I3(str), c_.m, pa).v - z.a * v0 * std::exp(-z.b * st.W1) > 1e-12 * c_.eta1;
      a2 = fc(str) / (pa * pa) - H2(st.W2) > 1e-12 * std::max(1.0, H2(st.W2));
    } else {
      a1 = true;
      a2 = fc(str) / (pa * pa) - H2(st.W2) > 0.0;
    }
    // de = de_total / nsub, so d(de)/d(de_total) = share I with share = 1 / nsub.
    if (!a1 && !a2) {
      sens.s += share * z.D;
      st.s = str;
      set = 0;
      return true;
    }
    Vec10 x;
    Mat10 J;
    for (int pass = 0; pass < 6; ++pass) {
      x.head<6>() = admissible(str) ? str : st.s;
      x[6] = v0;
      x[7] = st.W2;
      x[8] = x[9] = 0.0;
      if (a1 && x[6] == 0.0) x[6] = 1e-8;
      if (!solve(z, str, st, a1, a2, x, J)) return false;
      bool changed = false;
      if (a1 && x[8] < 0.0) a1 = false, changed = true;
      if (a2 && x[9] < 0.0) a2 = false, changed = true;
      if (!changed) {
        const Vec6 s = x.head<6>();
        const double W1 = pa * std::pow(x[6], z.q);
        if (!a1 && cone_f(I1(s), I3(s), c_.m, pa).v - H1(z, W1, pa) > 1e-9 * c_.eta1)
          a1 = true, changed = true;
        if (!a2 && fc(s) / (pa * pa) - H2(x[7]) > 1e-9 * std::max(1.0, H2(x[7]))) a2 = true, changed = true;
      }
      if (!changed) break;
      if (pass == 5) return false;
    }
    if (!a1 && !a2) {
      sens.s += share * z.D;
      st.s = str;
      set = 0;
      return true;
    }
    // Sensitivities: J dx = [d s_k + D d de; d W1_k / pa; d W2_k / pa; 0; 0] (the rows of an
    // inactive cone: v = v_k, whose sensitivity is not needed because W1 is differentiated below).
    Mat10x6 rhs = Mat10x6::Zero();
    rhs.topRows<6>() = sens.s + share * z.D;
    rhs.row(6) = sens.W1 / pa;
    rhs.row(7) = sens.W2 / pa;
    const Mat10x6 dx = Eigen::PartialPivLU<Mat10>(J).solve(rhs);
    const Vec6 s = x.head<6>();
    const Fn g = cone_g(I1(s), I3(s), c_.m, z.eta2, pa);
    const Vec6 g1 = g.grad(s);
    const double w1 = s.dot(g1);
    const Vec6 dw1 = g1 + g.hess(s) * s;
    // W1 = W1_k + l1 w1(s): differentiate directly (avoids v^(q-1) at v = 0).
    sens.W1 = sens.W1 + w1 * dx.row(8) + x[8] * dw1.transpose() * dx.topRows<6>();
    sens.W2 = dx.row(7);
    sens.s = dx.topRows<6>();
    st.W1 = st.W1 + x[8] * w1;
    st.W2 = x[7];
    st.s = s;
    set = (a1 ? 1 : 0) + (a2 ? 2 : 0);
    return true;
  }

  Constants c_;
};

} // namespace stratum::lade
