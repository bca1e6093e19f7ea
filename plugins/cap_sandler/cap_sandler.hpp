// DiMaggio-Sandler cap model ("cap_sandler"), thesis §2.4.5 (2.145)-(2.151), integrated by the
// Sandler-Rubin algorithm of §4.2.8 (4.51)-(4.69) or by the closest-point return of the shared
// plasticity library (stratum/plasticity/integrate.hpp) with its consistent tangent.
//
// Header only, so that the tests use the plugin's own code; cap_sandler.cpp only adds the
// factory. Equations, parameters, the reading of the thesis' loess set and the corrections:
// README.md in this folder.
//
// Inside the model J1 = -tr(sigma) is compression positive, sqrt(J2) is the root of the second
// deviatoric invariant; the framework's stresses and strains are tension positive.
//
//   envelope   f_e = sqrt(J2) - F_e(J1),  F_e(J1) = A - C exp(-B J1) + theta J1        (2.145)
//   cap        f_c = sqrt(R^2 J2 + <J1 - kappa>^2) - R F_e(kappa)                      (2.147)
//              (the ellipse R^2 J2 + (J1 - L)^2 = (X - L)^2 with L = kappa, X = kappa + R F_e(kappa),
//               for J1 >= kappa; for J1 < kappa its flat continuation sqrt(J2) = F_e(kappa), which
//               never cuts into the envelope's domain)
//   tension    f_t = -J1 - T <= 0                                                      (2.151)
//   hardening  X = Z - ln(1 - eps_v^p / W) / D, i.e. eps_v^p = W (1 - exp(-D (X - Z)))    (2.148)
//   elasticity constant K = E / (3 (1 - 2 nu)), G = E / (2 (1 + nu))
//   flow       associated on every surface
//
// History (framework owned): [0] kappa (kPa, the J1 where the cap meets the envelope),
// [1] accumulated plastic volumetric strain (compression positive, output only),
// [2] the regime of the last increment (0 elastic, 1 tension, 2 envelope, 3 corner, 4 cap).
// The internal variable of the plasticity::Model (closest point) is the hardening measure
// eps_v^p(kappa) = W (1 - exp(-D (X(kappa) - Z))); kappa follows from it by inverting X(kappa).
#pragma once

#include "stratum/elasticity.hpp"
#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/parameters.hpp"
#include "stratum/plasticity/integrate.hpp"
#include "stratum/plasticity/invariants.hpp"
#include "stratum/plasticity/model.hpp"
#include "stratum/voigt.hpp"

#include <Eigen/Core>
#include <boost/math/special_functions/lambert_w.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace stratum::cap_sandler {

enum class Integration { sandler_rubin, closest_point };
enum class Regime { elastic = 0, tension = 1, envelope = 2, corner = 3, cap = 4 };
/// Sandler-Rubin corner treatment: the thesis' rule (4.61) (stress held at the corner of the
/// old cap, kappa kept) or the two-surface backward-Euler return of the closest point.
enum class Corner { thesis, two_surface };

/// Material constants; the thesis' names (§9.4 of the digest), kPa and 1/kPa.
struct Constants {
  double E = 18000.0; ///< Young's modulus (kPa)
  double nu = 0.30;   ///< Poisson's ratio
  double A = 190.0;   ///< envelope: limit of sqrt(J2) at large J1 (kPa)           (alpha)
  double B = 0.0015;  ///< envelope: exponential rate (1/kPa)                       (beta)
  double C = 110.0;   ///< envelope: A - C = sqrt(J2) strength at J1 = 0 (kPa)      (gamma)
  double theta = 0.0; ///< envelope: linear term (-)
  double D = 0.00023; ///< hardening rate (1/kPa)
  double W = 0.06;    ///< maximum plastic volumetric compaction (-)
  double R = 2.5;     ///< cap ellipse axis ratio (J1 axis / sqrt(J2) axis)
  double T = 30.0;    ///< tension cut-off: J1 >= -T (kPa)
  double Z = 0.0;     ///< initial cap position X0 in J1 (kPa)
  /// retraction = "free" (true): (2.148) extended to dilatant eps_v^p < 0, the cap retracts
  /// without bound; "above_initial" (false): the tip X never moves below X0 = Z (dilation
  /// below the virgin state is not remembered), so the elastic domain cannot vanish.
  bool free_retraction = true;

  [[nodiscard]] double K() const { return E / (3.0 * (1.0 - 2.0 * nu)); }
  [[nodiscard]] double G() const { return E / (2.0 * (1.0 + nu)); }

  [[nodiscard]] double Fe(double J1) const { return A - C * std::exp(-B * J1) + theta * J1; }
  [[nodiscard]] double Fe1(double J1) const { return C * B * std::exp(-B * J1) + theta; }
  [[nodiscard]] double Fe2(double J1) const { return -C * B * B * std::exp(-B * J1); }

  /// Cap tip X(kappa) = kappa + R F_e(kappa) and its slope.
  [[nodiscard]] double X(double kappa) const { return kappa + R * Fe(kappa); }
  [[nodiscard]] double dX(double kappa) const { return 1.0 + R * Fe1(kappa); }
  /// The hardening law (2.148) and its inverse.
  [[nodiscard]] double eps_of_X(double X) const { return -W * std::expm1(-D * (X - Z)); }
  [[nodiscard]] double X_of_eps(double e) const { return Z - std::log1p(-e / W) / D; }
  [[nodiscard]] double eps_of_kappa(double kappa) const { return eps_of_X(X(kappa)); }

  /// J1 where the envelope meets the hydrostatic axis in tension (F_e = 0); for theta = 0
  /// J1 = -ln(A / C) / B. The cap needs F_e(kappa) > 0, i.e. kappa above it.
  [[nodiscard]] double envelope_apex() const {
    if (theta == 0.0) return -std::log(A / C) / B;
    double lo = -1e7, hi = 0.0; // F_e is increasing; F_e(0) = A - C > 0
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (Fe(mid) > 0.0 ? hi : lo) = mid;
    }
    return hi;
  }

  /// kappa with X(kappa) = Xv. X(kappa) = s kappa + R A - R C exp(-B kappa) with s = 1 + R theta,
  /// so with b = Xv - R A and kappa = b / s + v: (B v) exp(B v) = z = (B R C / s) exp(-B b / s),
  /// i.e. kappa = b / s + W0(z) / B with Lambert's W0 (z > 0). That closed form starts Newton on
  /// X(kappa) = Xv, which takes it to round-off in one step (one exponential per step). Where z
  /// overflows (kappa far beyond the envelope's apex, never admissible) Newton starts at
  /// min(Xv, 0): X is increasing and concave, so Newton from the left of the root converges
  /// monotonically (every Newton step from the right lands on the left). Newton stops when the
  /// step is below 1e-14 (1 + |kappa|) or the residual is at the round-off of its terms (near
  /// kappa = 0 the step cannot get below the first bound).
  [[nodiscard]] double kappa_of_X(double Xv) const {
    const double s = 1.0 + R * theta, b = Xv - R * A;
    const double z = (B * R * C / s) * std::exp(-B * b / s);
    double k = std::min(Xv, 0.0);
    if (std::isfinite(z) && z < 1e300) k = b / s + boost::math::lambert_w0(z) / B;
    for (int it = 0; it < 200; ++it) {
      const double e = std::exp(-B * k);
      const double g = k + R * (A - C * e + theta * k) - Xv; // X(k) - Xv
      const double dk = g / (1.0 + R * (C * B * e + theta)); // / dX(k)
      k -= dk;
      const double terms = std::abs(k) + R * (A + C * e + theta * std::abs(k)) + std::abs(Xv);
      if (std::abs(dk) <= 1e-14 * (1.0 + std::abs(k)) || std::abs(g) <= 8.0 * 2.2e-16 * terms) break;
    }
    return k;
  }
  /// The hardening strain that moves the cap: eps_v^p, or max(eps_v^p, 0) when the cap stops at Z.
  [[nodiscard]] double moving(double e) const { return free_retraction ? e : std::max(e, 0.0); }
  [[nodiscard]] double kappa_of_eps(double e) const { return kappa_of_X(X_of_eps(moving(e))); }
  /// d kappa / d eps_v^p.
  [[nodiscard]] double dkappa_deps(double e, double kappa) const {
    if (!free_retraction && e < 0.0) return 0.0;
    return 1.0 / (dX(kappa) * D * (W - e));
  }
};

/// Checks what the schema ranges cannot.
[[nodiscard]] inline std::optional<Problem> check(const Constants& c) {
  if (!(c.A > c.C))
    return Problem{"C", "C = " + number(c.C) + " must be smaller than A = " + number(c.A) +
                            " (the envelope must have positive strength A - C at J1 = 0)"};
  if (!(c.T < -c.envelope_apex()))
    return Problem{"T_CUT", "T_CUT = " + number(c.T) + " must lie inside the envelope, below ln(A/C)/B = " +
                                number(-c.envelope_apex())};
  if (!(c.Z > c.envelope_apex()))
    return Problem{"Z", "Z = " + number(c.Z) +
                            " must lie above the envelope's apex J1 = " + number(c.envelope_apex()) + " kPa"};
  return std::nullopt;
}

// -------------------------------------------------------------------------------------------
// Small helpers on tension-positive Voigt vectors

/// Compression-positive first invariant.
[[nodiscard]] inline double J1c(const Vec6& s) { return -(s[0] + s[1] + s[2]); }
[[nodiscard]] inline double rootJ2(const Vec6& s) { return std::sqrt(plasticity::j2(s)); }

/// Stress with compression-positive J1 and the deviator of `dev` scaled to root J2 = r.
[[nodiscard]] inline Vec6 compose(double J1, const Vec6& dev, double rj2_dev, double r) {
  Vec6 s = rj2_dev > 0.0 ? Vec6((r / rj2_dev) * dev) : Vec6(Vec6::Zero());
  for (int i = 0; i < 3; ++i) s[i] -= J1 / 3.0;
  return s;
}

// -------------------------------------------------------------------------------------------
/// The model in the form of the shared integration library. Surfaces: 0 envelope, 1 cap,
/// 2 tension cut-off. Internal variable q[0] = eps_v^p (compression positive).
class Model final : public plasticity::Model {
public:
  static constexpr int envelope = 0, cap = 1, tension = 2;

  explicit Model(const Constants& c)
      : c_(c), D_(stiffness_kg(c.K(), c.G())), P_(plasticity::deviatoric_projector_strain_like()) {}
  [[nodiscard]] const Constants& constants() const { return c_; }

  [[nodiscard]] int internal_size() const override { return 1; }
  [[nodiscard]] int surfaces() const override { return 3; }
  [[nodiscard]] Mat6 elastic(const Vec6&, std::span<const double>) const override { return D_; }

  [[nodiscard]] double yield(int k, const Vec6& s, std::span<const double> q) const override {
    const double J1 = J1c(s);
    if (k == envelope) return rootJ2(s) - c_.Fe(J1);
    if (k == tension) return -J1 - c_.T;
    const double kap = c_.kappa_of_eps(q[0]);
    const double a = std::max(J1 - kap, 0.0);
    return std::sqrt(c_.R * c_.R * plasticity::j2(s) + a * a) - c_.R * c_.Fe(kap);
  }

  [[nodiscard]] Vec6 yield_gradient(int k, const Vec6& s, std::span<const double> q) const override {
    const Vec6 I = plasticity::identity();
    const double J1 = J1c(s);
    if (k == tension) return I;
    const Vec6 shat = plasticity::to_strain_like(plasticity::deviator(s));
    if (k == envelope) {
      const double r = rootJ2(s);
      Vec6 n = c_.Fe1(J1) * I;
      if (r > tiny()) n += shat / (2.0 * r);
      return n;
    }
    const double kap = c_.kappa_of_eps(q[0]);
    const double a = std::max(J1 - kap, 0.0);
    const double Q = std::sqrt(c_.R * c_.R * plasticity::j2(s) + a * a);
    if (Q <= tiny()) return Vec6::Zero();
    return (c_.R * c_.R * shat - 2.0 * a * I) / (2.0 * Q);
  }

  [[nodiscard]] plasticity::VecX yield_gradient_q(int k, const Vec6& s,
                                                  std::span<const double> q) const override {
    plasticity::VecX g = plasticity::VecX::Zero(1);
    if (k != cap) return g;
    const double kap = c_.kappa_of_eps(q[0]);
    const double a = std::max(J1c(s) - kap, 0.0);
    const double Q = std::sqrt(c_.R * c_.R * plasticity::j2(s) + a * a);
    const double dfdk = (Q > tiny() ? -a / Q : 0.0) - c_.R * c_.Fe1(kap);
    g[0] = dfdk * c_.dkappa_deps(q[0], kap);
    return g;
  }

  [[nodiscard]] Vec6 flow(int k, const Vec6& s, std::span<const double> q) const override {
    return yield_gradient(k, s, q);
  }

  /// d eps_v^p = dlambda (-tr r): compression-positive plastic volume change.
  [[nodiscard]] plasticity::VecX hardening(int k, const Vec6& s, std::span<const double> q) const override {
    plasticity::VecX h(1);
    h[0] = -plasticity::identity().dot(flow(k, s, q));
    return h;
  }

  [[nodiscard]] Mat6 flow_gradient(int k, const Vec6& s, std::span<const double> q) const override {
    const Vec6 I = plasticity::identity();
    const Mat6 II = I * I.transpose();
    if (k == tension) return Mat6::Zero();
    const Vec6 shat = plasticity::to_strain_like(plasticity::deviator(s));
    const double J1 = J1c(s);
    if (k == envelope) {
      Mat6 H = -c_.Fe2(J1) * II;
      const double r = rootJ2(s);
      if (r > tiny()) H += P_ / (2.0 * r) - shat * shat.transpose() / (4.0 * r * r * r);
      return H;
    }
    const double kap = c_.kappa_of_eps(q[0]);
    const double a = std::max(J1 - kap, 0.0);
    const double Q = std::sqrt(c_.R * c_.R * plasticity::j2(s) + a * a);
    if (Q <= tiny()) return Mat6::Zero();
    const Vec6 n = (c_.R * c_.R * shat - 2.0 * a * I) / (2.0 * Q);
    Mat6 N = c_.R * c_.R * P_;
    if (a > 0.0) N += 2.0 * II;
    return N / (2.0 * Q) - n * n.transpose() / Q;
  }

  [[nodiscard]] plasticity::MatX flow_gradient_q(int k, const Vec6& s,
                                                 std::span<const double> q) const override {
    plasticity::MatX G = plasticity::MatX::Zero(6, 1);
    if (k != cap) return G;
    const Vec6 I = plasticity::identity();
    const double kap = c_.kappa_of_eps(q[0]);
    const double a = std::max(J1c(s) - kap, 0.0);
    const double Q = std::sqrt(c_.R * c_.R * plasticity::j2(s) + a * a);
    if (Q <= tiny() || a <= 0.0) return G;
    const Vec6 shat = plasticity::to_strain_like(plasticity::deviator(s));
    const Vec6 n = (c_.R * c_.R * shat - 2.0 * a * I) / (2.0 * Q);
    G.col(0) = (I / Q + n * (a / (Q * Q))) * c_.dkappa_deps(q[0], kap);
    return G;
  }

  [[nodiscard]] plasticity::MatX hardening_gradient(int k, const Vec6& s,
                                                    std::span<const double> q) const override {
    plasticity::MatX H(1, 6);
    H.row(0) = -plasticity::identity().transpose() * flow_gradient(k, s, q);
    return H;
  }

  [[nodiscard]] plasticity::MatX hardening_gradient_q(int k, const Vec6& s,
                                                      std::span<const double> q) const override {
    return -plasticity::identity().transpose() * flow_gradient_q(k, s, q);
  }

  /// The cap surface's functions all at once, with kappa inverted once (the expressions of the
  /// single functions above, so the same numbers); the envelope and the tension cut-off do not
  /// need kappa and take the default.
  void surface(int k, const Vec6& s, std::span<const double> q, plasticity::SurfaceDerivatives& d,
               bool jacobian) const override {
    if (k != cap) return plasticity::Model::surface(k, s, q, d, jacobian);
    const Vec6 I = plasticity::identity();
    const double J1 = J1c(s);
    const double kap = c_.kappa_of_eps(q[0]);
    const double a = std::max(J1 - kap, 0.0);
    const double Q = std::sqrt(c_.R * c_.R * plasticity::j2(s) + a * a);
    const bool flat = Q <= tiny();
    d.f = Q - c_.R * c_.Fe(kap);
    const Vec6 shat = plasticity::to_strain_like(plasticity::deviator(s));
    const Vec6 n = flat ? Vec6(Vec6::Zero()) : Vec6((c_.R * c_.R * shat - 2.0 * a * I) / (2.0 * Q));
    d.r = n;
    d.h.resize(1);
    d.h[0] = -I.dot(n);
    if (!jacobian) return;
    d.n = n;
    d.xi.resize(1);
    const double dkde = c_.dkappa_deps(q[0], kap);
    d.xi[0] = ((Q > tiny() ? -a / Q : 0.0) - c_.R * c_.Fe1(kap)) * dkde;
    if (flat) {
      d.dr_ds.setZero();
    } else {
      Mat6 N = c_.R * c_.R * P_;
      if (a > 0.0) N += 2.0 * (I * I.transpose());
      d.dr_ds = N / (2.0 * Q) - n * n.transpose() / Q;
    }
    d.dr_dq = plasticity::MatX::Zero(6, 1);
    if (!flat && a > 0.0) d.dr_dq.col(0) = (I / Q + n * (a / (Q * Q))) * dkde;
    d.dh_ds.resize(1, 6);
    d.dh_ds.row(0) = -I.transpose() * d.dr_ds;
    d.dh_dq = -I.transpose() * d.dr_dq;
  }

  /// eps_v^p below W (the cap at finite X) and kappa above the envelope's apex (F_e(kappa) > 0).
  [[nodiscard]] bool admissible(const Vec6& s, std::span<const double> q) const override {
    if (!s.allFinite() || !std::isfinite(q[0]) || !(q[0] < c_.W)) return false;
    return c_.Fe(c_.kappa_of_eps(q[0])) > 0.0;
  }

  [[nodiscard]] double stress_scale(const Vec6& s, std::span<const double> /*q*/) const override {
    return std::max({c_.A, c_.T, std::abs(J1c(s)) / 3.0});
  }

private:
  [[nodiscard]] double tiny() const { return 1e-12 * c_.A; }

  Constants c_;
  Mat6 D_, P_;
};

// -------------------------------------------------------------------------------------------
/// Result of one Sandler-Rubin update (compression-positive kappa).
struct SRResult {
  Outcome outcome;
  Vec6 stress = Vec6::Zero();
  double kappa = 0.0;
  Regime regime = Regime::elastic;
  std::vector<int> active; ///< surfaces of Model active at the end (for the continuum tangent)
};

/// The Sandler-Rubin algorithm (4.51)-(4.69), compression-positive reading (README.md):
/// elastic predictor, then the tests in order tension, envelope, cap. The envelope and cap
/// returns solve their equations to round-off (the thesis' one-shot (4.59) is the first iterate).
[[nodiscard]] inline SRResult sandler_rubin(const Constants& c, const Vec6& sigma_n, double kappa_n,
                                            const Vec6& de) {
  SRResult r;
  const double K = c.K(), G = c.G();
  const Vec6 trial = sigma_n + stiffness_kg(K, G) * de; // (4.51)-(4.52), constant K and G
  const double J1E = J1c(trial);
  const Vec6 sE = plasticity::deviator(trial);
  const double rE = rootJ2(trial);
  const double tol = 1e-12 * std::max({c.A, c.T, std::abs(J1E) / 3.0});
  const double e_n = c.eps_of_kappa(kappa_n);
  r.kappa = kappa_n;
  r.stress = trial;

  // (i) tension (4.53): J1 = -T, deviator removed, the excess volume change is plastic.
  if (J1E < -c.T) {
    const double J1 = -c.T;
    const double dev = (J1E - J1) / (3.0 * K); // compression-positive eps_v^p increment (< 0)
    r.kappa = c.kappa_of_eps(e_n + dev);
    r.stress = compose(J1, sE, rE, 0.0);
    r.regime = Regime::tension;
    r.active = {Model::tension};
    return r;
  }

  // (ii) envelope side of the cap (4.54)-(4.63)
  if (J1E <= kappa_n) {
    const double fE = rE - c.Fe(J1E);
    if (fE <= tol) return r; // elastic
    // Backward-Euler return on the envelope, unknowns (dlambda, J1):
    //   J1 = J1E + 9 K dlambda F_e'(J1)           ((4.60) with (4.59): dilatant flow raises J1)
    //   sqrt(J2) = sqrt(J2E) - G dlambda = F_e(J1)
    // The start (4.59) is the exact answer for a straight envelope.
    double dl = fE / (9.0 * K * c.Fe1(J1E) * c.Fe1(J1E) + G);
    double J1 = J1E + 9.0 * K * dl * c.Fe1(J1E);
    bool converged = false;
    for (int it = 0; it < 60; ++it) {
      const double r1 = J1 - J1E - 9.0 * K * dl * c.Fe1(J1);
      const double r2 = rE - G * dl - c.Fe(J1);
      if (std::abs(r1) <= tol && std::abs(r2) <= tol) {
        converged = true;
        break;
      }
      // d(r1, r2)/d(dl, J1)
      const double a11 = -9.0 * K * c.Fe1(J1), a12 = 1.0 - 9.0 * K * dl * c.Fe2(J1);
      const double a21 = -G, a22 = -c.Fe1(J1);
      const double det = a11 * a22 - a12 * a21;
      if (!(std::abs(det) > 0.0)) break;
      dl -= (a22 * r1 - a12 * r2) / det;
      J1 -= (-a21 * r1 + a11 * r2) / det;
    }
    if (!converged || !(dl >= 0.0))
      return {Outcome::failure(Status::not_converged,
                               "cap_sandler: the envelope return did not converge (trial J1 = " +
                                   number(J1E) + " kPa, sqrt(J2) = " + number(rE) + " kPa)"),
              sigma_n,
              kappa_n,
              Regime::elastic,
              {}};
    const double dev = -3.0 * dl * c.Fe1(J1); // dilatant: compression-positive eps_v^p decreases
    if (J1 > kappa_n) {
      // (4.61) corner: the stress stops at the intersection of envelope and cap, kappa kept.
      r.kappa = kappa_n;
      r.stress = compose(kappa_n, sE, rE, std::min(c.Fe(kappa_n), rE)); // (4.63) at J1 = L
      r.regime = Regime::corner;
      r.active = {Model::envelope, Model::cap};
      return r;
    }
    // (4.62): the cap retracts with the dilation, but never past the stress point.
    r.kappa = std::max(J1, c.kappa_of_eps(e_n + dev));
    r.stress = compose(J1, sE, rE, c.Fe(J1)); // (4.63)
    r.regime = Regime::envelope;
    r.active = {Model::envelope};
    return r;
  }

  // (iii) cap side (4.64)-(4.69)
  const double aE = J1E - kappa_n;
  const double fE = std::sqrt(c.R * c.R * rE * rE + aE * aE) - c.R * c.Fe(kappa_n);
  if (fE <= tol) return r; // elastic
  // For a trial kappa: dev = eps(kappa) - eps_n, J1 = J1E - 3 K dev (4.64); the flow
  // d eps^p = dmu (R^2 s / 2 - (J1 - kappa) 1) gives dev = 3 dmu (J1 - kappa) and
  // s = s^E / (1 + G R^2 dmu), the same relation as (4.65)-(4.68); residual: the distance of
  // (J1, sqrt(J2)) from the cap of kappa. It is positive at kappa_n and negative where
  // J1 reaches kappa (kappa_top below).
  auto J1_of = [&](double k) { return J1E - 3.0 * K * (c.eps_of_kappa(k) - e_n); };
  auto residual = [&](double k, double* rj2) {
    const double dev = c.eps_of_kappa(k) - e_n;
    const double J1 = J1E - 3.0 * K * dev;
    const double a = J1 - k;
    if (a <= 0.0) {
      if (rj2) *rj2 = 0.0;
      return -c.R * c.Fe(k);
    }
    const double dmu = dev / (3.0 * a);
    const double rj = rE / (1.0 + G * c.R * c.R * dmu);
    if (rj2) *rj2 = rj;
    return std::sqrt(c.R * c.R * rj * rj + a * a) - c.R * c.Fe(k);
  };
  // kappa_top: J1_of(k) = k, between kappa_n (J1 - k > 0) and J1E (J1 - k < 0); bisection.
  double lo = kappa_n, hi = J1E;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++it) {
    const double mid = 0.5 * (lo + hi);
    (J1_of(mid) - mid > 0.0 ? lo : hi) = mid;
  }
  // Root of the residual in [kappa_n, kappa_top]: Illinois regula falsi.
  double a = kappa_n, b = hi;
  double ga = fE, gb = residual(b, nullptr);
  double k = a;
  bool converged = false;
  int side = 0;
  for (int it = 0; it < 300; ++it) {
    k = (a * gb - b * ga) / (gb - ga);
    if (!(k > a && k < b)) k = 0.5 * (a + b);
    const double g = residual(k, nullptr);
    if (g == 0.0 || std::abs(g) <= 1e-6 * tol || b - a <= 1e-15 * (1.0 + std::abs(k))) {
      converged = true;
      break;
    }
    if ((g > 0.0) == (ga > 0.0)) {
      a = k, ga = g;
      if (side == -1) gb *= 0.5;
      side = -1;
    } else {
      b = k, gb = g;
      if (side == 1) ga *= 0.5;
      side = 1;
    }
  }
  if (!converged)
    return {Outcome::failure(Status::not_converged,
                             "cap_sandler: the cap iteration on kappa did not converge (trial J1 = " +
                                 number(J1E) + " kPa)"),
            sigma_n,
            kappa_n,
            Regime::elastic,
            {}};
  double rj = 0.0;
  residual(k, &rj);
  r.kappa = k;
  r.stress = compose(J1_of(k), sE, rE, rj); // (4.69)
  r.regime = Regime::cap;
  r.active = {Model::cap};
  return r;
}

// -------------------------------------------------------------------------------------------
/// The Material. History: [kappa, accumulated eps_v^p, regime].
class CapSandler final : public Material {
public:
  CapSandler(const Constants& c, Integration integration, Corner corner = Corner::two_surface)
      : model_(c), integration_(integration), corner_(corner) {
    settings_.scheme = plasticity::Scheme::closest_point;
    settings_.ftol = 1e-11;
    settings_.max_iterations = 60;
  }

  [[nodiscard]] const Model& model() const { return model_; }
  [[nodiscard]] Integration integration() const { return integration_; }
  [[nodiscard]] int history_size() const override { return 3; }
  /// The VTK names of the history: the cap parameter kappa, the accumulated plastic volumetric
  /// strain (compression positive) and the regime code of point_status.
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"kappa", "kPa"}, {"eps_v_p", "-"}, {"regime", "-"}});
  }
  [[nodiscard]] bool symmetric_tangent() const override { return true; } // associated flow
  /// The regime of the last increment (history[2]): 0 elastic, 1 tension, 2 envelope, 3 corner,
  /// 4 cap.
  [[nodiscard]] int point_status(const Vec6& /*stress*/, std::span<const double> h) const override {
    return static_cast<int>(h[2]);
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"elastic", "tension cut-off", "shear envelope", "corner (envelope and cap)", "cap"};
  }

  /// kappa of the initial cap X0 = Z, widened (normally consolidated) until the cap passes
  /// through the initial stress when that stress lies outside it.
  void init_history(const Vec6& stress, std::span<double> h) const override {
    const Constants& c = model_.constants();
    double kappa = c.kappa_of_X(c.Z);
    auto f = [&](double k) {
      const std::array<double, 1> q{c.eps_of_kappa(k)};
      return model_.yield(Model::cap, stress, q);
    };
    if (f(kappa) > 0.0) {
      double lo = kappa, hi = std::max(kappa, 0.0) + 1.0;
      while (f(hi) > 0.0 && hi < 1e9) hi = 2.0 * hi + 1.0;
      for (int it = 0; it < 200 && hi - lo > 1e-14 * (1.0 + std::abs(hi)); ++it) {
        const double mid = 0.5 * (lo + hi);
        (f(mid) > 0.0 ? lo : hi) = mid;
      }
      kappa = hi;
    }
    h[0] = kappa;
    h[1] = 0.0;
    h[2] = 0.0;
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    const Constants& c = model_.constants();
    auto where = [&] {
      return "cap_sandler at element " + std::to_string(in.where.element) + ", point " +
             std::to_string(in.where.point) + ": ";
    };
    const double kappa_n = in.history_n[0];
    if (!std::isfinite(kappa_n) || !(c.Fe(kappa_n) > 0.0))
      return Outcome::failure(Status::material_failure,
                              where() + "cap parameter kappa = " + number(kappa_n) +
                                  " kPa lies beyond the envelope's apex (F_e(kappa) <= 0)");
    Regime regime = Regime::elastic;
    double kappa = kappa_n;
    bool closest = integration_ == Integration::closest_point;
    SRResult r;
    if (!closest) {
      r = sandler_rubin(c, in.stress_n, kappa_n, in.dstrain);
      if (!r.outcome.ok()) return Outcome::failure(r.outcome.status, where() + r.outcome.message);
      closest = r.regime == Regime::corner && corner_ == Corner::two_surface;
    }
    if (!closest) {
      out.stress = r.stress;
      kappa = r.kappa;
      regime = r.regime;
      if (regime == Regime::elastic) {
        out.tangent = model_.elastic(out.stress, {});
      } else if (in.want_tangent) {
        const std::array<double, 1> q{c.eps_of_kappa(kappa)};
        out.tangent = plasticity::continuum_tangent(model_, out.stress, q, r.active);
      }
    } else {
      std::array<double, 1> q{c.eps_of_kappa(kappa_n)};
      const plasticity::Result r = plasticity::integrate(
          model_, settings_, in.stress_n, in.dstrain, out.stress, q, out.tangent, nullptr, in.want_tangent);
      if (!r.outcome.ok()) return Outcome::failure(r.outcome.status, where() + r.outcome.message);
      if (r.plastic) {
        kappa = c.kappa_of_eps(q[0]);
        regime = classify(out.stress, q);
      }
    }
    if (!out.stress.allFinite() || (in.want_tangent && !out.tangent.allFinite()) || !std::isfinite(kappa))
      return Outcome::failure(Status::non_finite, where() + "the stress update produced NaN or Inf");
    if (!(c.eps_of_kappa(kappa) < c.W))
      return Outcome::failure(Status::material_failure,
                              where() + "plastic compaction reached W = " + number(c.W) + "; step too large");
    const double dev_total = -(in.dstrain[0] + in.dstrain[1] + in.dstrain[2]);
    const double dev_plastic = dev_total - (J1c(out.stress) - J1c(in.stress_n)) / (3.0 * c.K());
    out.history[0] = kappa;
    out.history[1] = in.history_n[1] + (regime == Regime::elastic ? 0.0 : dev_plastic);
    out.history[2] = static_cast<double>(regime);
    return Outcome::success();
  }

  /// Which surfaces the closest-point result lies on.
  [[nodiscard]] Regime classify(const Vec6& s, std::span<const double> q) const {
    const double tol = 1e-8 * model_.stress_scale(s, q);
    const bool t = std::abs(model_.yield(Model::tension, s, q)) <= tol;
    const bool e = std::abs(model_.yield(Model::envelope, s, q)) <= tol;
    const bool k = std::abs(model_.yield(Model::cap, s, q)) <= tol * model_.constants().R;
    if (t) return Regime::tension;
    if (e && k) return Regime::corner;
    if (e) return Regime::envelope;
    if (k) return Regime::cap;
    return Regime::elastic;
  }

private:
  Model model_;
  Integration integration_;
  Corner corner_;
  plasticity::Settings settings_;
};

} // namespace stratum::cap_sandler
