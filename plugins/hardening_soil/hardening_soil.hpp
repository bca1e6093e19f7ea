// Hardening Soil (Schanz, Vermeer and Bonnier 1999) with the optional small-strain overlay of
// Benz (2007; Benz, Vermeer and Schwab 2009: the deviatoric strain history tensor and its
// reversal rules). Equations, the variant chosen and every difference: README.md in this folder.
//
// The model is isotropic, so the return is done in principal stress space (compression
// positive there) and rotated back; the consistent tangent is that of an isotropic tensor
// function (principal Jacobian plus the spin terms of the principal directions). The local
// problem (stresses, hardening variables, plastic multipliers of the active surfaces) is solved
// by Newton's method; its Jacobian is exact, from forward-mode automatic differentiation of the
// residual (Dual below), so the same Jacobian gives the consistent tangent.
//
// Surfaces (compression-positive principal stresses s, p = mean, q~ the rounded Mohr-Coulomb
// deviatoric measure, equal to s1 - s3 in triaxial compression):
//   0 S  shear hardening   q_a q~/E50 - (2 q~/E_ur + gamma_p)(q_a - q~)      (hardens gamma_p)
//   1 M  Mohr-Coulomb      q~ (3 - sin phi)/6 - p sin phi - c cos phi          (perfectly plastic)
//   2 C  cap               sqrt(q~^2/alpha^2 + <p>^2) - p_p, <p> = max(p, 0)    (hardens p_p)
//   3-5  tension cut-off   -s_i - T                                             (perfectly plastic)
//
// Header only, so the tests run exactly the plugin's code; hardening_soil.cpp adds the factory.
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
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>
#include <string>

namespace stratum::hardening_soil {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// ------------------------------------------------------------------------------------------
// Forward-mode dual numbers with a fixed maximum number of derivatives.

constexpr int max_active = 4;
constexpr int max_unknowns = 5 + max_active; // 3 stresses, gamma_p, p_p, the multipliers

struct Dual {
  double v = 0.0;
  std::array<double, max_unknowns> d{};
  Dual() = default;
  Dual(double x) : v(x) {} // NOLINT: implicit from double, like a literal
};

inline double value(double x) { return x; }
inline double sqrt(double x) { return std::sqrt(x); }
inline double pow(double a, double e) { return std::pow(a, e); }
inline double value(const Dual& x) { return x.v; }

inline Dual operator+(const Dual& a, const Dual& b) {
  Dual r(a.v + b.v);
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = a.d[i] + b.d[i];
  return r;
}
inline Dual operator-(const Dual& a, const Dual& b) {
  Dual r(a.v - b.v);
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = a.d[i] - b.d[i];
  return r;
}
inline Dual operator-(const Dual& a) {
  Dual r(-a.v);
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = -a.d[i];
  return r;
}
inline Dual operator*(const Dual& a, const Dual& b) {
  Dual r(a.v * b.v);
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
  return r;
}
inline Dual operator/(const Dual& a, const Dual& b) {
  Dual r(a.v / b.v);
  const double ib = 1.0 / b.v;
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = (a.d[i] - r.v * b.d[i]) * ib;
  return r;
}
inline Dual operator+(const Dual& a, double b) { return a + Dual(b); }
inline Dual operator+(double a, const Dual& b) { return Dual(a) + b; }
inline Dual operator-(const Dual& a, double b) { return a - Dual(b); }
inline Dual operator-(double a, const Dual& b) { return Dual(a) - b; }
inline Dual operator*(const Dual& a, double b) {
  Dual r(a.v * b);
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = a.d[i] * b;
  return r;
}
inline Dual operator*(double a, const Dual& b) { return b * a; }
inline Dual operator/(const Dual& a, double b) { return a * (1.0 / b); }
inline Dual operator/(double a, const Dual& b) { return Dual(a) / b; }
inline Dual sqrt(const Dual& a) {
  Dual r(std::sqrt(a.v));
  const double k = 0.5 / r.v;
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = a.d[i] * k;
  return r;
}
inline Dual pow(const Dual& a, double e) {
  Dual r(std::pow(a.v, e));
  const double k = e * std::pow(a.v, e - 1.0);
  for (int i = 0; i < max_unknowns; ++i) r.d[i] = a.d[i] * k;
  return r;
}
template <class T> T larger(const T& a, const T& b) { return value(a) >= value(b) ? a : b; }
template <class T> T smaller(const T& a, const T& b) { return value(a) <= value(b) ? a : b; }

// ------------------------------------------------------------------------------------------
// Parameters.

[[nodiscard]] inline double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

struct Parameters {
  double E50_ref = 0.0;   ///< secant stiffness at 50 % of q_f in triaxial compression at p_ref (kPa)
  double Eoed_ref = 0.0;  ///< tangent oedometer stiffness at sigma_1 = p_ref on the K0_nc path (kPa)
  double Eur_ref = 0.0;   ///< unloading-reloading stiffness at p_ref (kPa)
  double m = 0.5;         ///< stress exponent
  double p_ref = 100.0;   ///< reference stress (kPa)
  double nu_ur = 0.2;     ///< unloading-reloading Poisson's ratio
  double c = 0.0;         ///< cohesion (kPa)
  double phi = 30.0;      ///< friction angle (deg)
  double psi = 0.0;       ///< dilatancy angle (deg)
  double Rf = 0.9;        ///< failure ratio q_f / q_a
  double K0_nc = 0.5;     ///< K0 of normal consolidation
  double alpha = 0.0;     ///< cap shape (derived when <= 0)
  double H = 0.0;         ///< cap hardening modulus at p_p = p_ref (kPa; derived when <= 0)
  double tension = 0.0;   ///< tension cut-off T: largest principal stress <= T (kPa)
  double sigma_min = 1.0; ///< stiffness floor: sigma_3 in the stiffness laws is at least this (kPa)
  double OCR = 1.0;       ///< initial cap: p_p0 = OCR p_eq(initial stress)
  double p_p0 = 0.0;      ///< initial cap pressure lower bound (kPa)
  bool small_strain = false;
  double G0_ref = 0.0;   ///< small-strain shear modulus at p_ref (kPa)
  double gamma_07 = 0.0; ///< shear strain at which G_s = 0.722 G0
};

/// Constants derived once from the parameters.
struct Constants {
  double sphi = 0, cphi = 0, spsi = 0, sin_cv = 0, c_cot = 0;
  double a1 = 0, a2 = 0; ///< q~ = a1 sqrt(J2) - a2 J3 / J2 (compression-positive J3)
  double base_ref = 1, base_min = 1;
  double alpha = 1, H = 1;
};

inline constexpr double small_strain_a = 0.385; // Benz (2007): G_s = 0.722 G0 at gamma_07

enum Surface : int { S = 0, M = 1, C = 2, T0 = 3, T1 = 4, T2 = 5, n_surfaces = 6 };

/// One point's internal variables.
struct Internal {
  double gamma_p = 0.0;
  double p_p = 1.0;
};

// ------------------------------------------------------------------------------------------
// The model's functions (compression-positive principal stresses).

class Core {
public:
  Core(const Parameters& p, double alpha, double H) : p_(p) {
    k_.sphi = std::sin(radians(p.phi));
    k_.cphi = std::cos(radians(p.phi));
    k_.spsi = std::sin(radians(p.psi));
    k_.sin_cv = (k_.sphi - k_.spsi) / (1.0 - k_.sphi * k_.spsi);
    k_.c_cot = p.c * k_.cphi / k_.sphi;
    // Rounding: K = g(-30 deg), limited to 7/9 for convexity (README).
    const double K = std::max((3.0 - k_.sphi) / (3.0 + k_.sphi), 7.0 / 9.0);
    k_.a1 = std::sqrt(3.0) * (1.0 + K) / (2.0 * K);
    k_.a2 = 9.0 * (1.0 - K) / (4.0 * K);
    k_.base_ref = p.c * k_.cphi + p.p_ref * k_.sphi;
    k_.base_min = p.c * k_.cphi + p.sigma_min * k_.sphi;
    k_.alpha = alpha;
    k_.H = H;
  }

  [[nodiscard]] const Parameters& params() const { return p_; }
  [[nodiscard]] const Constants& constants() const { return k_; }

  /// Stress-level factor ((c cos phi + s3 sin phi) / (c cos phi + p_ref sin phi))^m, floored.
  template <class T> [[nodiscard]] T level(const T& s3) const {
    const T base = larger(T(k_.base_min), p_.c * k_.cphi + s3 * k_.sphi);
    return pow(base / k_.base_ref, p_.m);
  }
  [[nodiscard]] double level(double s3) const {
    const double base = std::max(k_.base_min, p_.c * k_.cphi + s3 * k_.sphi);
    return std::pow(base / k_.base_ref, p_.m);
  }
  [[nodiscard]] double Eur(double s3) const { return p_.Eur_ref * level(s3); }
  [[nodiscard]] double E50(double s3) const { return p_.E50_ref * level(s3); }
  [[nodiscard]] double G0(double s3) const { return p_.G0_ref * level(s3); }

  /// Asymptotic deviator q_a = q_f / Rf, q_f = 2 (c cos phi + s3 sin phi) / (1 - sin phi) (floored).
  template <class T> [[nodiscard]] T q_a(const T& s3) const {
    const T base = larger(T(k_.base_min), p_.c * k_.cphi + s3 * k_.sphi);
    return 2.0 * base / ((1.0 - k_.sphi) * p_.Rf);
  }

  /// p, q~ and grad q~ of principal stresses s.
  template <class T> void invariants(const T* s, T& p, T& q, T* g) const {
    p = (s[0] + s[1] + s[2]) / 3.0;
    const T d[3] = {s[0] - p, s[1] - p, s[2] - p};
    const T J2 = 0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double scale = std::abs(value(s[0])) + std::abs(value(s[1])) + std::abs(value(s[2])) + 1.0;
    if (value(J2) <= 1e-26 * scale * scale) {
      q = T(0.0);
      for (int i = 0; i < 3; ++i) g[i] = T(0.0);
      return;
    }
    const T J3 = d[0] * d[1] * d[2];
    const T sj = sqrt(J2);
    q = k_.a1 * sj - k_.a2 * J3 / J2;
    const T cof[3] = {d[1] * d[2], d[0] * d[2], d[0] * d[1]};
    const T cm = (cof[0] + cof[1] + cof[2]) / 3.0;
    for (int i = 0; i < 3; ++i)
      g[i] = k_.a1 * d[i] / (2.0 * sj) - k_.a2 * ((cof[i] - cm) / J2 - J3 * d[i] / (J2 * J2));
  }

  /// The hyperbola's plastic shear strain at q~ (the value of gamma_p on the shear surface).
  [[nodiscard]] double gamma_on_surface(const Vec3& s) const {
    double p, q, g[3];
    invariants(s.data(), p, q, g);
    const double s3 = p - q / 3.0, qa = q_a(s3), lev = level(s3);
    if (q >= qa) return 1e300;
    return qa / (p_.E50_ref * lev) * q / (qa - q) - 2.0 * q / (p_.Eur_ref * lev);
  }
  /// The cap's equivalent pressure sqrt(q~^2/alpha^2 + p^2).
  [[nodiscard]] double p_eq(const Vec3& s) const {
    double p, q, g[3];
    invariants(s.data(), p, q, g);
    const double pc = std::max(p, 0.0);
    return std::sqrt(q * q / (k_.alpha * k_.alpha) + pc * pc);
  }

  /// Yield value of surface k.
  /// p, q~ and grad q~ of one stress, computed once and shared by the surfaces.
  template <class T> struct Inv { T p, q, g[3]; };
  template <class T> [[nodiscard]] Inv<T> inv(const T* s) const {
    Inv<T> v;
    invariants(s, v.p, v.q, v.g);
    return v;
  }

  template <class T> [[nodiscard]] T yield(int k, const T* s, const T& gp, const T& pp) const {
    return yield(k, s, gp, pp, inv(s));
  }
  template <class T>
  [[nodiscard]] T yield(int k, const T* s, const T& gp, const T& pp, const Inv<T>& v) const {
    if (k >= T0) return -s[k - T0] - p_.tension;
    const T &p = v.p, &q = v.q;
    switch (k) {
    case S: {
      const T s3 = p - q / 3.0, lev = level(s3), qa = q_a(s3);
      return qa * q / (p_.E50_ref * lev) - (2.0 * q / (p_.Eur_ref * lev) + gp) * (qa - q);
    }
    case M:
      return q * ((3.0 - k_.sphi) / 6.0) - p * k_.sphi - p_.c * k_.cphi;
    default: {
      const T pc = larger(p, T(0.0)); // the cap closes the compression side only
      return sqrt(q * q / (k_.alpha * k_.alpha) + pc * pc) - pp;
    }
    }
  }

  /// Flow direction r_k (compression-positive plastic strain rate per unit multiplier) and the
  /// cap's hardening rate dp_p / dlambda.
  template <class T> void flow(int k, const T* s, const T& pp, T* r, T& dpp) const {
    flow(k, pp, r, dpp, inv(s));
  }
  template <class T> void flow(int k, const T& pp, T* r, T& dpp, const Inv<T>& v) const {
    dpp = T(0.0);
    if (k >= T0) {
      for (int i = 0; i < 3; ++i) r[i] = T(i == k - T0 ? -1.0 : 0.0);
      return;
    }
    const T &p = v.p, &q = v.q;
    const T* g = v.g;
    if (k == C) {
      const T pc = larger(p, T(0.0));
      const T A = sqrt(q * q / (k_.alpha * k_.alpha) + pc * pc);
      for (int i = 0; i < 3; ++i) r[i] = (q / (k_.alpha * k_.alpha) * g[i] + pc / 3.0) / A;
      dpp = k_.H * pow(pp / p_.p_ref, p_.m) * pc / A;
      return;
    }
    T spm = T(k_.spsi);
    if (k == S) {
      const T s3 = p - q / 3.0, den = 2.0 * (s3 + k_.c_cot) + q;
      const T sfm = value(den) > 0.0 ? smaller(q / den, T(k_.sphi)) : T(k_.sphi);
      spm = (sfm - k_.sin_cv) / (1.0 - sfm * k_.sin_cv);
      spm = larger(T(0.0), smaller(spm, T(k_.spsi)));
    }
    for (int i = 0; i < 3; ++i) r[i] = (3.0 - spm) / 6.0 * g[i] - spm / 3.0;
  }

private:
  Parameters p_;
  Constants k_;
};

// ------------------------------------------------------------------------------------------
// The principal-space return.

struct ReturnResult {
  bool ok = false;
  Vec3 s = Vec3::Zero();            ///< returned principal stresses (compression positive)
  Mat3 jacobian = Mat3::Identity(); ///< d s / d s_trial
  Internal q;
  unsigned active = 0; ///< bitmask of active surfaces
  int iterations = 0;
  bool converged = false;                  ///< Newton converged (ok also needs non-negative multipliers)
  int most_negative = -1;                  ///< surface with the most negative multiplier, if any
  std::array<double, max_active> lambda{}; ///< multipliers of the active surfaces (in surface order)
};

class PrincipalReturn {
public:
  explicit PrincipalReturn(const Core& core) : core_(core) {}

  /// Solves the local problem with the active set `mask`; nothing else is checked.
  [[nodiscard]] ReturnResult solve(unsigned mask, const Vec3& s_tr, const Internal& qn, const Mat3& Dp,
                                   double scale) const {
    ReturnResult out;
    int act[max_active], na = 0;
    for (int k = 0; k < n_surfaces; ++k)
      if (mask & (1u << k)) {
        if (na == max_active) return out;
        act[na++] = k;
      }
    const int n = 5 + na;
    using VecN = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, max_unknowns, 1>;
    using MatN = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, max_unknowns, max_unknowns>;
    VecN x(n), R(n);
    MatN J(n, n);
    x << s_tr[0], s_tr[1], s_tr[2], qn.gamma_p, qn.p_p, VecN::Zero(na);
    const double Eref = Dp(0, 0);
    auto eval = [&](const VecN& xv, VecN& Rv, MatN* Jv) {
      if (!Jv) { // residual only (line search): plain doubles
        double xd[max_unknowns], Rd[max_unknowns];
        for (int i = 0; i < n; ++i) xd[i] = xv[i];
        residual(xd, act, na, s_tr, qn, Dp, scale, Eref, Rd);
        for (int i = 0; i < n; ++i) Rv[i] = Rd[i];
        return;
      }
      Dual xs[max_unknowns];
      for (int i = 0; i < n; ++i) {
        xs[i] = Dual(xv[i]);
        if (Jv) xs[i].d[i] = 1.0;
      }
      Dual Rs[max_unknowns];
      residual(xs, act, na, s_tr, qn, Dp, scale, Eref, Rs);
      for (int i = 0; i < n; ++i) {
        Rv[i] = Rs[i].v;
        if (Jv)
          for (int j = 0; j < n; ++j) (*Jv)(i, j) = Rs[i].d[j];
      }
    };
    const double tol = 1e-11;
    for (int it = 0; it < 60; ++it) {
      eval(x, R, &J);
      if (!R.allFinite() || !J.allFinite()) return out;
      const double norm = R.cwiseAbs().maxCoeff();
      Eigen::FullPivLU<MatN> lu(J);
      lu.setThreshold(1e-13);
      if (!lu.isInvertible()) return out;
      if (norm < tol) {
        out.ok = true;
        out.converged = true;
        out.iterations = it;
        out.s = x.head<3>();
        out.q.gamma_p = x[3];
        out.q.p_p = x[4];
        double lmin = 0.0;
        for (int j = 0; j < na; ++j) out.lambda[static_cast<std::size_t>(j)] = x[5 + j];
        for (int j = 0; j < na; ++j)
          if (x[5 + j] < -1e-12 * (1.0 + std::abs(x[5 + j])) && x[5 + j] < lmin) {
            out.ok = false;
            lmin = x[5 + j];
            out.most_negative = act[j];
          }
        MatN rhs = MatN::Zero(n, 3);
        rhs.topRows(3) = Mat3::Identity() / scale;
        const MatN Z = lu.solve(rhs);
        out.jacobian = Z.topRows(3);
        out.active = mask;
        return out;
      }
      const VecN dx = lu.solve(-R);
      double t = 1.0;
      VecN xt(n), Rt(n);
      bool accepted = false;
      for (int ls = 0; ls < 30; ++ls, t *= 0.5) {
        xt = x + t * dx;
        if (xt[4] <= 0.0) continue;
        eval(xt, Rt, nullptr);
        if (Rt.allFinite() && Rt.cwiseAbs().maxCoeff() < (1.0 - 1e-4 * t) * norm) {
          accepted = true;
          break;
        }
      }
      if (!accepted) {
        if (!(xt[4] > 0.0) || !xt.allFinite()) return out;
        x = x + dx; // a full step out of a stagnating line search, left to Newton
        if (x[4] <= 0.0) return out;
      } else {
        x = xt;
      }
    }
    return out;
  }

  /// Trial evaluation of every surface.
  [[nodiscard]] std::array<double, n_surfaces> yields(const Vec3& s, const Internal& q) const {
    std::array<double, n_surfaces> f{};
    for (int k = 0; k < n_surfaces; ++k) f[k] = core_.yield<double>(k, s.data(), q.gamma_p, q.p_p);
    return f;
  }

  /// Whether (s, q) violates any surface (the shear surface is not checked when M is active:
  /// gamma_p is then set onto the hyperbola afterwards).
  [[nodiscard]] int most_violated(const Vec3& s, const Internal& q, unsigned active, double tol) const {
    const auto f = yields(s, q);
    int worst = -1;
    double fw = tol;
    for (int k = 0; k < n_surfaces; ++k) {
      if (active & (1u << k)) continue;
      if (k == S && (active & (1u << M))) continue;
      if (f[k] > fw) fw = f[k], worst = k;
    }
    return worst;
  }

  /// The full return: active-set iteration from the violated surfaces, then (if that fails)
  /// every admissible set of up to three surfaces.
  [[nodiscard]] ReturnResult operator()(const Vec3& s_tr, const Internal& qn, const Mat3& Dp) const {
    const double scale = std::max({s_tr.cwiseAbs().maxCoeff(), core_.params().c, core_.params().p_ref * 1e-3,
                                   std::abs(core_.params().tension)});
    const double tol = 1e-9 * scale;
    ReturnResult r;
    const auto f = yields(s_tr, qn);
    unsigned mask = 0;
    for (int k = 0; k < n_surfaces; ++k)
      if (f[k] > tol) mask |= 1u << k;
    if (mask == 0) {
      r.ok = true;
      r.s = s_tr;
      r.q = qn;
      return r;
    }
    // The hardening surface first: Mohr-Coulomb is active only when the shear hardening return
    // alone would cross it.
    if ((mask & (1u << S)) && (mask & (1u << M))) mask &= ~(1u << M);
    auto finish = [&](ReturnResult& res) {
      if (res.active & (1u << M))
        res.q.gamma_p = std::max(res.q.gamma_p, std::min(core_.gamma_on_surface(res.s), 1e300));
      return res;
    };
    auto valid = [&](const ReturnResult& res) {
      return res.ok && most_violated(res.s, res.q, res.active, tol) < 0;
    };
    while (std::popcount(mask) > max_active) { // keep the most violated
      int least = -1;
      for (int k = 0; k < n_surfaces; ++k)
        if ((mask & (1u << k)) && (least < 0 || f[k] < f[least])) least = k;
      mask &= ~(1u << least);
    }
    {
      unsigned cur = mask;
      for (int round = 0; round < 10 && cur != 0; ++round) {
        ReturnResult res = solve(cur, s_tr, qn, Dp, scale);
        if (!res.converged) break;
        if (!res.ok) { // drop the surface with the most negative multiplier
          cur &= ~(1u << res.most_negative);
          continue;
        }
        const int add = most_violated(res.s, res.q, res.active, tol);
        if (add < 0) return finish(res);
        unsigned next = cur | (1u << add);
        if (add == M) next &= ~(1u << S);
        if (add == S && (next & (1u << M))) break;
        if (std::popcount(next) > max_active || next == cur) break;
        cur = next;
      }
    }
    for (int size = 1; size <= max_active; ++size)
      for (unsigned m = 1; m < (1u << n_surfaces); ++m) {
        if (std::popcount(m) != size) continue;
        if ((m & (1u << S)) && (m & (1u << M))) continue;
        ReturnResult res = solve(m, s_tr, qn, Dp, scale);
        if (valid(res)) return finish(res);
      }
    r.ok = false;
    return r;
  }

  [[nodiscard]] const Core& core() const { return core_; }

private:
  template <class T>
  void residual(const T* x, const int* act, int na, const Vec3& s_tr, const Internal& qn, const Mat3& Dp,
                double scale, double Eref, T* R) const {
    const T* s = x;
    const T& gp = x[3];
    const T& pp = x[4];
    T dep[3] = {T(0.0), T(0.0), T(0.0)};
    T dgp = T(0.0), dpp_total = T(0.0);
    const auto v = core_.inv(s);
    for (int j = 0; j < na; ++j) {
      T r[3], dpp;
      core_.flow(act[j], pp, r, dpp, v);
      const T& lam = x[5 + j];
      for (int i = 0; i < 3; ++i) dep[i] = dep[i] + lam * r[i];
      if (act[j] == S) dgp = dgp + lam;
      if (act[j] == C) dpp_total = dpp_total + lam * dpp;
    }
    for (int i = 0; i < 3; ++i) {
      T Ri = s[i] - s_tr[i];
      for (int k = 0; k < 3; ++k) Ri = Ri + Dp(i, k) * dep[k];
      R[i] = Ri / scale;
    }
    R[3] = (gp - qn.gamma_p - dgp) * (Eref / scale);
    R[4] = (pp - qn.p_p - dpp_total) / scale;
    for (int j = 0; j < na; ++j) R[5 + j] = core_.yield(act[j], s, gp, pp, v) / scale;
  }

  const Core& core_;
};

// ------------------------------------------------------------------------------------------
// Spectral helpers.

/// The minor principal compression sigma_3 (compression positive) of a tension-positive stress.
[[nodiscard]] inline double sigma3(const Vec6& sigma) {
  const Eigen::SelfAdjointEigenSolver<Mat3> es(stress_tensor(sigma), Eigen::EigenvaluesOnly);
  return -es.eigenvalues()[2];
}

// ------------------------------------------------------------------------------------------
// Cap parameters from K0_nc and Eoed_ref.

/// The oedometric continuum response at sigma_1 = p_ref on the K0_nc line with the shear
/// surface and the cap both active: d sigma_3 / d sigma_1 and d sigma_1 / d eps_1.
struct Oedometer {
  bool ok = false;
  double K0 = 0.0, Eoed = 0.0;
};

[[nodiscard]] inline Oedometer oedometer_response(const Parameters& p, double alpha, double H) {
  Oedometer o;
  const Core core(p, alpha, H);
  const PrincipalReturn ret(core);
  const Vec3 s(p.p_ref, p.K0_nc * p.p_ref, p.K0_nc * p.p_ref);
  Internal q;
  q.gamma_p = core.gamma_on_surface(s);
  q.p_p = core.p_eq(s);
  if (!(q.gamma_p < 1e299)) return o;
  const Mat3 Dp = isotropic_stiffness(core.Eur(s[2]), p.nu_ur).topLeftCorner<3, 3>();
  // A vanishing increment's consistent tangent is the continuum tangent: solve at the state
  // itself (multipliers zero) and read the Jacobian.
  const ReturnResult r = ret.solve((1u << S) | (1u << C), s, q, Dp, p.p_ref);
  if (!r.ok) return o;
  const Mat3 Dep = r.jacobian * Dp;
  o.Eoed = Dep(0, 0);
  o.K0 = Dep(1, 0) / Dep(0, 0);
  o.ok = std::isfinite(o.Eoed) && std::isfinite(o.K0);
  return o;
}

/// alpha and H such that the K0_nc path is followed and the tangent oedometer modulus at
/// sigma_1 = p_ref is Eoed_ref. Empty when no such pair is found.
[[nodiscard]] inline std::optional<std::array<double, 2>> calibrate_cap(const Parameters& p) {
  std::array<double, 2> u = {std::log(3.0 * (1.0 - p.K0_nc) / (1.0 + 2.0 * p.K0_nc) + 0.1),
                             std::log(p.Eoed_ref)};
  auto res = [&](const std::array<double, 2>& v, bool& ok) {
    const Oedometer o = oedometer_response(p, std::exp(v[0]), std::exp(v[1]));
    ok = o.ok;
    return std::array<double, 2>{o.K0 - p.K0_nc, o.Eoed / p.Eoed_ref - 1.0};
  };
  for (int it = 0; it < 60; ++it) {
    bool ok = false;
    const auto r0 = res(u, ok);
    if (!ok) return std::nullopt;
    if (std::abs(r0[0]) < 1e-12 && std::abs(r0[1]) < 1e-12)
      return std::array<double, 2>{std::exp(u[0]), std::exp(u[1])};
    Eigen::Matrix2d J;
    for (int j = 0; j < 2; ++j) {
      auto v = u;
      v[j] += 1e-7;
      bool okj = false;
      const auto rj = res(v, okj);
      if (!okj) return std::nullopt;
      J(0, j) = (rj[0] - r0[0]) / 1e-7;
      J(1, j) = (rj[1] - r0[1]) / 1e-7;
    }
    Eigen::Vector2d du = J.fullPivLu().solve(-Eigen::Vector2d(r0[0], r0[1]));
    const double big = du.cwiseAbs().maxCoeff();
    if (!std::isfinite(big)) return std::nullopt;
    if (big > 1.0) du /= big; // at most a factor e per iteration
    u[0] += du[0];
    u[1] += du[1];
  }
  return std::nullopt;
}

// ------------------------------------------------------------------------------------------
// The material.

/// History layout.
namespace slot {
inline constexpr int gamma_p = 0, p_p = 1, status = 2;
/// Benz's deviatoric strain history H (small_strain only): 6 tensor components xx, yy, zz, xy,
/// yz, zx (not engineering shear).
inline constexpr int strain_history = 3;
inline constexpr int size_standard = 3, size_small_strain = 9;
} // namespace slot

/// The small-strain shear stress-strain curve of the overlay in terms of the history strain:
/// tau(gamma) = G0 gamma / (1 + a gamma / gamma_07) up to the cut-off strain where its tangent
/// G0 / (1 + a gamma / gamma_07)^2 has fallen to G_ur, beyond it a straight continuation with
/// slope G_ur. Returns tau and d tau / d gamma.
[[nodiscard]] inline std::array<double, 2> small_strain_tau(double G0, double Gur, double g07, double gamma) {
  const double a = small_strain_a;
  const double gc = G0 > Gur ? g07 / a * (std::sqrt(G0 / Gur) - 1.0) : 0.0;
  if (gamma <= gc) {
    const double den = 1.0 + a * gamma / g07;
    return {G0 * gamma / den, G0 / (den * den)};
  }
  const double tc = gc > 0.0 ? G0 * gc / (1.0 + a * gc / g07) : 0.0;
  return {tc + Gur * (gamma - gc), Gur};
}

/// The symmetric tensor of a tensor-component vector (xx yy zz xy yz zx) and back.
[[nodiscard]] inline Mat3 sym_tensor(const Vec6& v) {
  Mat3 t;
  t << v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2];
  return t;
}
[[nodiscard]] inline Vec6 sym_vector(const Mat3& t) {
  Vec6 v;
  v << t(0, 0), t(1, 1), t(2, 2), 0.5 * (t(0, 1) + t(1, 0)), 0.5 * (t(1, 2) + t(2, 1)),
      0.5 * (t(0, 2) + t(2, 0));
  return v;
}
/// The deviatoric strain tensor of an engineering-shear strain vector.
[[nodiscard]] inline Mat3 strain_deviator(const Vec6& e) {
  Mat3 t;
  t << e[0], 0.5 * e[3], 0.5 * e[5], 0.5 * e[3], e[1], 0.5 * e[4], 0.5 * e[5], 0.5 * e[4], e[2];
  t.diagonal().array() -= t.trace() / 3.0;
  return t;
}

/// Benz's strain history over one increment (README, "Small-strain stiffness"): the history
/// strain the increment starts from (gamma_1), the one it ends at (gamma_2), and the new history.
struct HistoryStep {
  Mat3 H; ///< after the increment
  double gamma1 = 0.0, gamma2 = 0.0;
  std::array<bool, 3> reset{}; ///< per principal direction of the increment (ascending)
};

/// One increment `de` (deviatoric strain tensor) from the history H. Each principal direction
/// of de along which H points the other way is reset (its diagonal entry in that basis set to
/// zero, the entries coupling it to the others scaled); `forced` (a finite-difference neighbour
/// of an increment) imposes the reset pattern instead of testing it. gamma = sqrt(3) |H n|,
/// n = de / |de|, before the increment is added (from the reset history) and after.
[[nodiscard]] inline HistoryStep history_step(const Mat3& H, const Mat3& de,
                                              const std::array<bool, 3>* forced = nullptr) {
  HistoryStep r;
  const double nde = de.norm();
  if (!(nde > 0.0)) { // no increment: along the history itself (continued loading)
    r.H = H;
    const double nh = H.norm();
    r.gamma1 = r.gamma2 = nh > 0.0 ? std::sqrt(3.0) * (H * H).norm() / nh : 0.0;
    return r;
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> es(de);
  const Mat3& Q = es.eigenvectors();
  const Vec3& d = es.eigenvalues();
  const Mat3 Hp = Q.transpose() * H * Q;
  Vec3 t = Vec3::Ones();
  for (int i = 0; i < 3; ++i) {
    r.reset[i] = forced ? (*forced)[i] : Hp(i, i) * d[i] < 0.0;
    if (r.reset[i]) t[i] = 1.0 / std::sqrt(std::max(1.0 + Hp(i, i), 1e-12));
  }
  const Mat3 reset =
      Q * (t.asDiagonal() * (Hp + Mat3::Identity()) * t.asDiagonal() - Mat3::Identity()) * Q.transpose();
  const Mat3 n = de / nde;
  r.gamma1 = std::sqrt(3.0) * (reset * n).norm();
  r.H = reset + de;
  r.gamma2 = std::sqrt(3.0) * (r.H * n).norm();
  return r;
}

class HardeningSoil final : public Material {
public:
  HardeningSoil(const Parameters& p, double alpha, double H) : core_(p, alpha, H), ret_(core_) {}
  HardeningSoil(const HardeningSoil&) = delete;
  HardeningSoil& operator=(const HardeningSoil&) = delete;

  [[nodiscard]] int history_size() const override {
    return core_.params().small_strain ? slot::size_small_strain : slot::size_standard;
  }
  /// The VTK names of the shear hardening parameter gamma_p, the cap pressure p_p and the
  /// regime code of point_status (the small-strain memory is not written).
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"gamma_p", "-"}, {"p_p", "kPa"}, {"status", "-"}});
  }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  void init_history(const Vec6& stress, std::span<double> h) const override {
    for (double& v : h) v = 0.0;
    const Eigen::SelfAdjointEigenSolver<Mat3> es(stress_tensor(stress), Eigen::EigenvaluesOnly);
    const Vec3 s = -es.eigenvalues();
    const double g = core_.gamma_on_surface(s);
    h[slot::gamma_p] = std::max(0.0, g < 1e299 ? g : 0.0);
    h[slot::p_p] =
        std::max({core_.params().OCR * core_.p_eq(s), core_.params().p_p0, 1e-6 * core_.params().p_ref});
    // small_strain: the history tensor H starts at zero (every point at G0)
  }

  [[nodiscard]] int point_status(const Vec6&, std::span<const double> h) const override {
    return h.size() > slot::status ? static_cast<int>(h[slot::status]) : -1;
  }
  /// The bitmask names, index = mask: bit 0 shear hardening, 1 Mohr-Coulomb failure, 2 cap,
  /// 3-5 the tension planes (1, 2, 3 of them active), joined by " + ".
  [[nodiscard]] std::vector<std::string> status_names() const override {
    std::vector<std::string> names{"elastic"};
    for (int mask = 1; mask < 64; ++mask) {
      std::string s;
      auto add = [&s](const char* part) { s += (s.empty() ? "" : " + ") + std::string(part); };
      if ((mask & 1) != 0) add("shear hardening");
      if ((mask & 2) != 0) add("Mohr-Coulomb failure");
      if ((mask & 4) != 0) add("cap");
      const int t = ((mask >> 3) & 1) + ((mask >> 4) & 1) + ((mask >> 5) & 1);
      if (t == 1) add("tension cut-off");
      if (t > 1) add(t == 3 ? "tension apex" : "tension cut-off (2 planes)");
      names.push_back(s);
    }
    return names;
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    if (Outcome o = material_checks::finite_input(in, "hardening_soil"); !o.ok()) return o;
    for (std::size_t i = 0; i < out.history.size(); ++i) out.history[i] = in.history_n[i];
    const Parameters& p = core_.params();
    Internal qn{in.history_n[slot::gamma_p], in.history_n[slot::p_p]};

    if (p.small_strain) {
      // Benz's overlay (README): the chord of the small-strain curve over the history strains
      // the increment starts from and ends at, G0 and G_ur at the stress at the start.
      const Mat3 H = sym_tensor(Eigen::Map<const Vec6>(&in.history_n[slot::strain_history]));
      const double s3 = sigma3(in.stress_n), Gur = core_.Eur(s3) / (2.0 * (1.0 + p.nu_ur));
      const double G0 = std::max(core_.G0(s3), Gur);
      const HistoryStep hstep = history_step(H, strain_deviator(in.dstrain));
      const Mat6 D = shear_stiffness(chord_modulus(G0, Gur, hstep));
      const Mat6 Dtr = in.want_tangent ? predictor_tangent(H, in.dstrain, G0, Gur, hstep) : D;
      const Vec6 hv = sym_vector(hstep.H);
      for (int i = 0; i < 6; ++i) out.history[slot::strain_history + i] = hv[i];
      return plastic_update(in, qn, in.stress_n + D * in.dstrain, Dtr, out);
    }
    const Mat6 D = isotropic_stiffness(core_.Eur(sigma3(in.stress_n)), p.nu_ur);
    return plastic_update(in, qn, in.stress_n + D * in.dstrain, D, out);
  }

  /// The chord modulus of the small-strain curve between the history strains of a step (its
  /// tangent where they coincide).
  [[nodiscard]] double chord_modulus(double G0, double Gur, const HistoryStep& h) const {
    const double g07 = core_.params().gamma_07;
    const auto [t1, d1] = small_strain_tau(G0, Gur, g07, h.gamma1);
    if (std::abs(h.gamma2 - h.gamma1) <= 1e-12 * std::max({h.gamma1, h.gamma2, g07})) return d1;
    return (small_strain_tau(G0, Gur, g07, h.gamma2)[0] - t1) / (h.gamma2 - h.gamma1);
  }
  /// The isotropic stiffness of shear modulus G at the constant nu_ur.
  [[nodiscard]] Mat6 shear_stiffness(double G) const {
    const double nu = core_.params().nu_ur;
    return isotropic_stiffness(2.0 * G * (1.0 + nu), nu);
  }
  /// d (D(G(de)) de) / d de by central differences with the step's reversal pattern held (step
  /// 1e-6 of the largest component: the chord law is smooth for a fixed pattern, so the error is
  /// about 1e-10 relative); at a zero increment D of the tangent modulus along the history.
  [[nodiscard]] Mat6 predictor_tangent(const Mat3& H, const Vec6& de, double G0, double Gur,
                                       const HistoryStep& at) const {
    const double scale = de.cwiseAbs().maxCoeff();
    if (!(scale > 0.0)) return shear_stiffness(chord_modulus(G0, Gur, at));
    const double dh = 1e-6 * scale;
    const auto predictor = [&](const Vec6& e) {
      const HistoryStep h = history_step(H, strain_deviator(e), &at.reset);
      return Vec6(shear_stiffness(chord_modulus(G0, Gur, h)) * e);
    };
    Mat6 D;
    for (int j = 0; j < 6; ++j) {
      Vec6 ep = de, em = de;
      ep[j] += dh;
      em[j] -= dh;
      D.col(j) = (predictor(ep) - predictor(em)) / (2.0 * dh);
    }
    return D;
  }

  [[nodiscard]] const Core& core() const { return core_; }

private:
  // Without want_tangent, out.tangent is the caller's (possibly uninitialised) storage, left as it
  // is: checking it failed residual-only evaluations at random (the sanitizer build, docs/testing.md).
  Outcome check(const MaterialInput& in, MaterialOutput& out) const {
    if (!out.stress.allFinite() || (in.want_tangent && !out.tangent.allFinite()))
      return Outcome::failure(Status::non_finite,
                              "hardening_soil: non-finite stress or tangent" + material_checks::where(in));
    return Outcome::success();
  }

  /// The return from `trial` (d trial / d strain = Dtr) with the corrector stiffness of E_ur.
  Outcome plastic_update(const MaterialInput& in, const Internal& qn, const Vec6& trial, const Mat6& Dtr,
                         MaterialOutput& out) const {
    const Parameters& p = core_.params();
    const Mat3 Dp = isotropic_stiffness(core_.Eur(sigma3(in.stress_n)), p.nu_ur).topLeftCorner<3, 3>();
    // One return from the whole trial; if no admissible active set exists (a trial far outside,
    // where the non-associated surfaces meet), the trial increment is split into 2, 4, ..., 64
    // sub-increments, each returned in turn. The tangent of a split step chains the
    // sub-increments' tangents (holding the internal variables fixed: approximate there).
    const Vec6 dtrial = trial - in.stress_n;
    for (int n = 1; n <= 64; n *= 2) {
      Vec6 s = in.stress_n;
      Internal q = qn;
      Mat6 T = Mat6::Zero();
      unsigned active = 0;
      bool ok = true;
      for (int k = 0; k < n && ok; ++k) {
        const Vec6 tr = s + dtrial / n;
        const Eigen::SelfAdjointEigenSolver<Mat3> es(stress_tensor(tr));
        const Vec3& lam = es.eigenvalues();
        const Mat3& V = es.eigenvectors();
        const ReturnResult r = ret_(-lam, q, Dp);
        if (!r.ok) {
          ok = false;
          break;
        }
        q = r.q;
        active |= r.active;
        if (r.active == 0) {
          s = tr;
          T += Dtr / n;
        } else {
          const Vec3 sig = -r.s;
          s = stress_voigt(V * sig.asDiagonal() * V.transpose());
          if (in.want_tangent)
            T = spectral_tangent(lam, V, sig, r.jacobian, 1e-9 * std::max(lam.cwiseAbs().maxCoeff(), 1e-12)) *
                (T + Dtr / n);
        }
        if (k + 1 == n) active = r.active;
      }
      if (!ok) continue;
      out.history[slot::gamma_p] = q.gamma_p;
      out.history[slot::p_p] = q.p_p;
      out.history[slot::status] = static_cast<double>(active);
      out.stress = s;
      if (in.want_tangent) out.tangent = T;
      return check(in, out);
    }
    return Outcome::failure(Status::material_failure,
                            "hardening_soil: no admissible return found (also in 64 sub-increments)" +
                                material_checks::where(in));
  }

  Core core_;
  PrincipalReturn ret_;
};

} // namespace stratum::hardening_soil
