// The Duncan-Chang hypoelastic model (thesis §2.3, (2.22)-(2.41); digest §3.2-3.3) and its
// variable K_t/G_t variant (digest §3.2, "K_t, G_t model"), header only so the tests run the
// plugins' code. See plugins/duncan_chang/README.md for the equations and the choices made.
//
// Inside: compression positive (sigma_c = -sigma), principal stresses s1 >= s2 >= s3, q = s1 - s3.
// At the Material boundary: tension positive, Voigt xx, yy, zz, xy, yz, zx, engineering shear.
#pragma once

#include "stratum/elasticity.hpp"
#include "stratum/material.hpp"
#include "stratum/parameters.hpp"
#include "stratum/stress.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace stratum::duncan_chang {

enum class Form { E_nu, E_B, K_G };
enum class Update { recovery, incremental, explicit_step };
enum class Unloading { F_sr, max_deviator };
/// How the explicit update picks the E_ur or the E_t branch (`branch`).
enum class Branch { increment, step_start };
enum class BulkStress { sigma_m, sigma_3 };

/// One parameter set of the hyperbolic model (angles in degrees, stresses in kPa).
struct Set {
  double K = 0, n = 0, R_f = 0, phi = 0, c = 0, K_ur = 0, G = 0, F = 0, d = 0, K_b = 0, m = 0, delta_phi = 0,
         nu = 0;
};

/// Which forms use a level-dependent parameter.
enum class Needs { all, E_nu, E_B, K_G };
/// The default of a level-dependent parameter: required, none (an empty list: unused) or 0.
enum class Fallback { required, none, zero };

/// One level-dependent parameter, declared once: the TOML key, the member of Set it fills, unit,
/// meaning (thesis equations), the form that needs it, its range and default. The schema, the
/// reading and the interpolation all walk this table (duncan_chang_schema.hpp).
struct SetParameter {
  const char* name;
  double Set::*member;
  const char* unit;
  const char* meaning;
  Needs needs;
  double lower, upper;         ///< range; -inf / inf: unbounded
  bool lower_open, upper_open; ///< (lower, ...) rather than [lower, ...
  Fallback fallback;
};

inline constexpr double unbounded = std::numeric_limits<double>::infinity();

/// In the order of the schema; the parameters every form needs come first.
inline constexpr std::array<SetParameter, 13> set_parameters{{
    {"K", &Set::K, "-", "modulus number of E_i = K p_a (sigma_3/p_a)^n (2.27)", Needs::all, 0.0, unbounded,
     true, false, Fallback::required},
    {"n", &Set::n, "-", "modulus exponent of (2.27) and (2.40)", Needs::all, 0.0, 2.0, false, true,
     Fallback::required},
    {"R_f", &Set::R_f, "-", "failure ratio q_f/q_ult (2.25)", Needs::all, 0.0, 1.0, true, false,
     Fallback::required},
    {"phi", &Set::phi, "deg", "friction angle phi_i at sigma_3 = p_a (2.28), (2.41)", Needs::all, 0.0, 90.0,
     false, true, Fallback::required},
    {"c", &Set::c, "kPa", "cohesion (2.28)", Needs::all, 0.0, unbounded, false, false, Fallback::required},
    {"K_ur", &Set::K_ur, "-", "unloading-reloading modulus number, E_ur = K_ur p_a (sigma_3/p_a)^n (2.40)",
     Needs::all, 0.0, unbounded, true, false, Fallback::required},
    {"G", &Set::G, "-",
     "initial Poisson ratio at sigma_3 = p_a, nu_i = G - F log10(sigma_3/p_a) (2.33); E_nu form", Needs::E_nu,
     -unbounded, unbounded, false, false, Fallback::none},
    {"F", &Set::F, "-", "decrease of nu_i per tenfold sigma_3 (2.33); E_nu form", Needs::E_nu, -unbounded,
     unbounded, false, false, Fallback::none},
    {"d", &Set::d, "-", "lateral-strain parameter of (2.32), (2.35); E_nu form", Needs::E_nu, 0.0, unbounded,
     false, false, Fallback::none},
    {"K_b", &Set::K_b, "-", "bulk modulus number, B_t = K_b p_a (sigma/p_a)^m (2.36); E_B form", Needs::E_B,
     0.0, unbounded, true, false, Fallback::none},
    {"m", &Set::m, "-", "bulk modulus exponent of (2.36); E_B form", Needs::E_B, 0.0, 2.0, false, true,
     Fallback::none},
    {"nu", &Set::nu, "-", "constant Poisson ratio: K_t = E_i/(3(1 - 2 nu)), G_t = E_t/(2(1 + nu))",
     Needs::K_G, -1.0, 0.5, true, true, Fallback::required},
    {"delta_phi", &Set::delta_phi, "deg", "decrease of phi per tenfold sigma_3 (2.41)", Needs::all,
     -unbounded, unbounded, false, false, Fallback::zero},
}};

struct Constants {
  Form form = Form::E_nu;
  Update update = Update::incremental;
  Unloading unloading = Unloading::F_sr;
  Branch branch = Branch::increment; ///< explicit update only
  BulkStress bulk_stress = BulkStress::sigma_m;
  double p_a = 100.0;
  double nu_min = 0.0, nu_max = 0.49;
  double sigma3_floor = 0.01;         ///< smallest sigma_3 used in the moduli, as a fraction of p_a
  double residual = 1e-3;             ///< E_t / E_i at and beyond failure (stress level >= 1)
  double tangent_stabilization = 0.0; ///< kPa: isotropic modulus added to the tangent only (nu = 0.3)
  double max_substep_strain = 1e-4;   ///< incremental update: largest strain component per substep
  int max_substeps = 1000;            ///< incremental update: more substeps than this fail the update
  double recovery_min_strain = 1e-6;  ///< recovery needs a major compressive strain above this
  bool tension_cutoff = true;
  /// Explicit update: keep the branch decision of each point within a load step (decided at the
  /// step's first evaluation, re-checked at convergence by the solver; `branch_iteration`).
  bool keep_decisions = false;
  bool origin_at_initial_stress = true; ///< recovery: strains count from the CID state of the initial stress
  std::vector<double> levels;           ///< sigma_3 of the sets, increasing (empty: one set)
  std::vector<Set> sets;                ///< one per level (one when levels is empty)

  /// The parameter set at sigma_3 (kPa): the first set below levels[0], the last above the last
  /// level, linear interpolation of every parameter in sigma_3 in between.
  [[nodiscard]] Set at(double s3) const {
    if (sets.size() == 1 || s3 <= levels.front()) return sets.front();
    if (s3 >= levels.back()) return sets.back();
    std::size_t i = 0;
    while (s3 >= levels[i + 1]) ++i;
    const double t = (s3 - levels[i]) / (levels[i + 1] - levels[i]);
    Set s;
    for (const auto& sp : set_parameters)
      s.*sp.member = (1.0 - t) * sets[i].*sp.member + t * sets[i + 1].*sp.member;
    return s;
  }
};

/// Everything the moduli need at one stress.
struct Point {
  double s1 = 0, s3 = 0, s3eff = 0, sm = 0, q = 0;
  Set P;
  double phi = 0;  ///< radians, (2.41)
  double q_f = 0;  ///< (2.28)
  double S = 0;    ///< stress level F_sr (4.50)
  double E_i = 0;  ///< (2.27)
  double E_ur = 0; ///< (2.40)
  double f = 0;    ///< nu_i = G - F log10(sigma_3/p_a) (2.33), bounded
};

/// Bulk and shear tangent moduli.
struct Moduli {
  double K = 0, G = 0, E = 0, nu = 0;
};

class DuncanChang final : public Material {
public:
  explicit DuncanChang(Constants c) : c_(std::move(c)) {}

  [[nodiscard]] const Constants& constants() const { return c_; }
  /// 8, and 10 with keep_decisions: history[8] the branch decision of the step (0 decide afresh,
  /// 1 E_ur, 2 split at the maximum, 3 E_t), history[9] the local error estimate of the update.
  [[nodiscard]] int history_size() const override { return c_.keep_decisions ? 10 : 8; }
  /// The VTK names of history[0] and [1]: the largest stress level and deviator reached (the
  /// memory of the unloading criterion); the strain origin and the decision slots are not written.
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"S_max", "-"}, {"q_max", "kPa"}});
  }
  [[nodiscard]] int decision_slot() const override { return c_.keep_decisions ? 8 : -1; }
  [[nodiscard]] double step_error(std::span<const double> h) const override {
    return c_.keep_decisions && h.size() > 9 ? h[9] : 0.0;
  }
  /// history[0]: largest stress level F_sr reached; history[1]: largest deviator q reached;
  /// history[2..7]: the strain origin of the recovery (Voigt, tension positive): the strain of a
  /// CID path from an isotropic state to the initial stress (recovery_origin = "initial_stress"),
  /// or zero.
  void init_history(const Vec6& stress, std::span<double> h) const override {
    const Point pt = point(stress);
    h[0] = pt.S;
    h[1] = pt.q;
    const Vec6 e0 = c_.update == Update::recovery && c_.origin_at_initial_stress ? cid_strain(stress)
                                                                                 : Vec6::Zero().eval();
    for (int i = 0; i < 6; ++i) h[static_cast<std::size_t>(2 + i)] = e0[i];
    for (std::size_t i = 8; i < h.size(); ++i) h[i] = 0.0;
  }

  /// The strain (tension positive) that a CID path from an isotropic state at sigma_3 reaches at
  /// the given stress: eps_1 from the hyperbola (2.26) inverted, eps_1 = q / (E_i (1 - R_f S)) with
  /// S at most 0.99, the lateral strain from (2.32), directions of the principal stresses.
  [[nodiscard]] Vec6 cid_strain(const Vec6& stress) const {
    const Point pt = point(stress);
    if (!(pt.q > 0.0)) return Vec6::Zero();
    const double S = std::min(pt.S, 0.99), q = S * pt.q_f;
    const double e1 = q / (pt.E_i * (1.0 - pt.P.R_f * S));
    const double el = lateral(e1, pt);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(stress_tensor(stress));
    const Eigen::Vector3d n1 = es.eigenvectors().col(0); // the major compression
    const Eigen::Matrix3d e =
        -e1 * n1 * n1.transpose() + el * (Eigen::Matrix3d::Identity() - n1 * n1.transpose());
    Vec6 v = stress_voigt(e);
    v.tail<3>() *= 2.0; // engineering shear
    return v;
  }
  [[nodiscard]] static Vec6 origin(std::span<const double> h) {
    Vec6 e;
    for (int i = 0; i < 6; ++i) e[i] = h[static_cast<std::size_t>(2 + i)];
    return e;
  }
  /// 0 below failure; 1 at failure (stress level S = q / q_f >= 0.99); 2 tension cut off (the
  /// minor principal stress is not compressive).
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> /*history*/) const override {
    if (principal_compression(stress).s3 <= 0.0) return 2;
    return point(stress).S >= 0.99 ? 1 : 0;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"below failure", "failed (S >= 0.99)", "tension cut-off"};
  }

  /// The tangent of a finite step is not symmetric in general (stress-dependent moduli, recovery).
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  /// The state quantities of the model at a tension-positive stress.
  [[nodiscard]] Point point(const Vec6& sigma) const {
    const Principal pr = principal_compression(sigma);
    return point_of(pr.s1, pr.s3, (pr.s1 + pr.s2 + pr.s3) / 3.0);
  }
  [[nodiscard]] Point point_of(double s1, double s3, double sm) const {
    Point pt;
    pt.s1 = s1;
    pt.s3 = s3;
    pt.sm = sm;
    pt.q = std::max(s1 - s3, 0.0);
    pt.s3eff = std::max(s3, c_.sigma3_floor * c_.p_a);
    pt.P = c_.at(pt.s3eff);
    const double lg = std::log10(pt.s3eff / c_.p_a);
    const double phi_deg = std::clamp(pt.P.phi - pt.P.delta_phi * lg, 0.0, 89.0);
    pt.phi = phi_deg * std::numbers::pi / 180.0;
    const double sp = std::sin(pt.phi);
    pt.q_f = 2.0 * (pt.P.c * std::cos(pt.phi) + pt.s3eff * sp) / (1.0 - sp);
    pt.S = pt.q_f > 0.0 ? pt.q / pt.q_f : (pt.q > 0.0 ? 1e30 : 0.0);
    const double pw = std::pow(pt.s3eff / c_.p_a, pt.P.n);
    pt.E_i = pt.P.K * c_.p_a * pw;
    pt.E_ur = pt.P.K_ur * c_.p_a * pw;
    pt.f = std::clamp(pt.P.G - pt.P.F * lg, c_.nu_min, c_.nu_max);
    return pt;
  }

  /// Tangent moduli at a point, on the loading (virgin) or the unloading-reloading branch.
  [[nodiscard]] Moduli moduli(const Point& pt, bool unloading) const {
    Moduli mo;
    const double nu_kg = pt.P.nu;
    if (unloading) {
      mo.E = pt.E_ur;
      if (c_.form == Form::E_nu)
        mo.nu = pt.f;
      else if (c_.form == Form::E_B)
        mo.nu = std::clamp(0.5 - mo.E / (6.0 * bulk(pt)), c_.nu_min, c_.nu_max);
      else {
        mo.nu = nu_kg;
        mo.K = mo.E / (3.0 * (1.0 - 2.0 * nu_kg));
        mo.G = mo.E / (2.0 * (1.0 + nu_kg));
        return mo;
      }
    } else {
      const double one = 1.0 - pt.P.R_f * pt.S;
      const bool failed = pt.S >= 1.0 || one <= 0.0;
      mo.E = std::max(failed ? 0.0 : pt.E_i * one * one, c_.residual * pt.E_i); // (2.31)
      if (c_.form == Form::E_nu) {
        const double A = failed ? 1.0 : pt.P.d * pt.q / (pt.E_i * one); // (2.35)
        mo.nu = A < 1.0 ? std::min(pt.f / ((1.0 - A) * (1.0 - A)), c_.nu_max) : c_.nu_max;
      } else if (c_.form == Form::E_B) {
        mo.nu = std::clamp(0.5 - mo.E / (6.0 * bulk(pt)), c_.nu_min, c_.nu_max); // (2.39)
      } else {
        mo.nu = nu_kg; // K from E_i, G from E_t
        mo.K = pt.E_i / (3.0 * (1.0 - 2.0 * nu_kg));
        mo.G = mo.E / (2.0 * (1.0 + nu_kg));
        return mo;
      }
    }
    mo.K = mo.E / (3.0 * (1.0 - 2.0 * mo.nu));
    mo.G = mo.E / (2.0 * (1.0 + mo.nu));
    return mo;
  }
  [[nodiscard]] Mat6 stiffness(const Vec6& sigma, bool unloading) const {
    const Moduli mo = moduli(point(sigma), unloading);
    return stiffness_kg(mo.K, mo.G);
  }

  /// B_t = K_b p_a (sigma/p_a)^m (2.36) with sigma = sigma_m (thesis) or sigma_3 (Duncan et al. 1980).
  [[nodiscard]] double bulk(const Point& pt) const {
    const double s =
        std::max(c_.bulk_stress == BulkStress::sigma_m ? pt.sm : pt.s3, c_.sigma3_floor * c_.p_a);
    return pt.P.K_b * c_.p_a * std::pow(s / c_.p_a, pt.P.m);
  }

  /// The loading criterion value: F_sr (4.50) or q.
  [[nodiscard]] double criterion(const Point& pt) const {
    return c_.unloading == Unloading::F_sr ? pt.S : pt.q;
  }
  [[nodiscard]] double criterion_max(std::span<const double> h) const {
    return c_.unloading == Unloading::F_sr ? h[0] : h[1];
  }
  /// True when a stress with criterion value v is below the historical maximum (unloading).
  [[nodiscard]] static bool below(double v, double vmax) {
    return v < vmax - 1e-12 * std::max(1.0, std::abs(vmax));
  }

  /// How one update went; replayed when the tangent is differenced.
  struct Record {
    bool recovery = false;
    int substeps = 0;
    double too_large = 0.0;    ///< the strain increment when it needs more than max_substeps (else 0)
    bool cut = false;          ///< the tension cut-off changed the stress in some substep
    std::vector<double> alpha; ///< per substep: the fraction integrated on the E_ur branch
    /// Explicit update, branch = increment: 1 E_ur, 2 split at the maximum, 3 E_t (0: not decided).
    int code = 0;
    /// The code is given (kept from earlier in the step, or frozen for the tangent's differences):
    /// alpha of a split is still computed from the increment.
    bool forced = false;
    double error = 0.0; ///< explicit update: |Heun - Euler| / max(|stress|, p_a)
    /// A replayed recovery found no stress (the perturbed strain left the recovery's domain, e.g.
    /// below recovery_min_strain): the difference on that side must not be used.
    bool replay_failed = false;
  };

  /// The explicit update's stiffness for a branch split alpha (the fraction on the E_ur branch):
  /// alpha D_ur + (1 - alpha) D_t, both at the step's start stress (point p0).
  [[nodiscard]] Mat6 explicit_stiffness(const Point& p0, double alpha) const {
    Mat6 D = Mat6::Zero();
    if (alpha > 0.0) {
      const Moduli mo = moduli(p0, true);
      D += alpha * stiffness_kg(mo.K, mo.G);
    }
    if (alpha < 1.0) {
      const Moduli mo = moduli(p0, false);
      D += (1.0 - alpha) * stiffness_kg(mo.K, mo.G);
    }
    return D;
  }

  /// One Heun step (explicit trapezoidal rule) of the hypoelastic law on one branch.
  [[nodiscard]] Vec6 heun(const Vec6& s, const Vec6& de, bool unloading) const {
    const Moduli m0 = moduli(point(s), unloading);
    const Vec6 ds0 = stiffness_kg(m0.K, m0.G) * de;
    const Moduli m1 = moduli(point(s + ds0), unloading);
    return s + 0.5 * (ds0 + stiffness_kg(m1.K, m1.G) * de);
  }

  /// Incremental update: substeps of Heun's method. Per substep an E_ur trial decides the branch:
  /// below the historical maximum of the criterion it is unloading-reloading (E_ur); a substep that
  /// crosses the maximum is split where the trial reaches it (linear in the criterion), the rest on
  /// the loading branch (E_t). Tension cut-off after each substep.
  [[nodiscard]] Vec6 incremental(const Vec6& stress_n, const Vec6& de, std::span<double> h, Record& rec,
                                 bool replay) const {
    if (!replay) {
      rec.recovery = false;
      rec.cut = false;
      const double big = de.cwiseAbs().maxCoeff();
      if (c_.update != Update::explicit_step && !(big <= c_.max_substep_strain * c_.max_substeps)) {
        // Thousands of substeps per point and evaluation would stall the run for minutes (a
        // wild iterate of a large load step): fail, and let the step driver cut the step back.
        rec.too_large = big;
        return stress_n;
      }
      rec.substeps =
          c_.update == Update::explicit_step
              ? 1
              : std::clamp(static_cast<int>(std::ceil(big / c_.max_substep_strain)), 1, c_.max_substeps);
      rec.alpha.assign(static_cast<std::size_t>(rec.substeps), 0.0);
    }
    const Vec6 dd = de / rec.substeps;
    Vec6 s = stress_n;
    for (int k = 0; k < rec.substeps; ++k) {
      double alpha;
      if (replay && !rec.forced)
        alpha = rec.alpha[static_cast<std::size_t>(k)];
      else {
        const Point p0 = point(s);
        const double cmax = criterion_max(h), c0 = criterion(p0);
        if (c_.branch == Branch::step_start) {
          // The classical load-step rule: the branch of the state at the step's start, whatever
          // the increment; the update is then linear in the increment over all iterations.
          alpha = below(c0, cmax) ? 1.0 : 0.0;
        } else {
          const Moduli mu = moduli(p0, true);
          const double ct = criterion(point(s + stiffness_kg(mu.K, mu.G) * dd));
          // The increment rule: E_ur while the E_ur trial stays below the maximum (1), split
          // where it crosses it from below (2), else E_t (3). A kept (forced) code only fixes
          // which of the three; the split fraction follows the increment.
          int code = rec.forced ? rec.code : 0;
          if (code < 1 || code > 3) code = below(ct, cmax) ? 1 : (below(c0, cmax) && ct > c0 ? 2 : 3);
          if (code == 1)
            alpha = 1.0;
          else if (code == 2)
            alpha = ct > c0 ? std::clamp((cmax - c0) / (ct - c0), 0.0, 1.0) : 1.0;
          else
            alpha = 0.0;
          if (!replay) rec.code = code;
        }
        if (!replay) rec.alpha[static_cast<std::size_t>(k)] = alpha;
      }
      if (c_.update == Update::explicit_step) {
        // The moduli of the step's start on both parts: the stress is linear in the increment
        // for a given branch split, so global Newton sees a piecewise-linear material.
        const Point p0 = point(s);
        const Vec6 sn = s;
        if (alpha > 0.0) s += explicit_stiffness(p0, 1.0) * (alpha * dd);
        if (alpha < 1.0) s += explicit_stiffness(p0, 0.0) * ((1.0 - alpha) * dd);
        if (c_.keep_decisions && !replay) {
          // Heun's corrector over the same step with the same split (moduli averaged between the
          // start and the Euler end): its difference from the Euler stress estimates the local
          // error of the step (Sloan's substepping, lifted to the load step). Only the estimate:
          // the stress stays Euler's (a second-order stress converges to another limit on the
          // pile, README).
          const Point p1 = point(s);
          Vec6 sh = sn;
          if (alpha > 0.0)
            sh += 0.5 * (explicit_stiffness(p0, 1.0) + explicit_stiffness(p1, 1.0)) * (alpha * dd);
          if (alpha < 1.0)
            sh += 0.5 * (explicit_stiffness(p0, 0.0) + explicit_stiffness(p1, 0.0)) * ((1.0 - alpha) * dd);
          rec.error = (sh - s).norm() / std::max(sh.norm(), c_.p_a);
        }
      } else {
        if (alpha > 0.0) s = heun(s, alpha * dd, true);
        if (alpha < 1.0) s = heun(s, (1.0 - alpha) * dd, false);
      }
      if (c_.tension_cutoff) {
        const Vec6 cut = cut_tension(s);
        if (!replay && cut != s) rec.cut = true;
        s = cut;
      }
      const Point pe = point(s);
      h[0] = std::max(h[0], pe.S);
      h[1] = std::max(h[1], pe.q);
    }
    return s;
  }

  /// Lateral strain (expansion positive) of a CID path at major compressive strain e1 and the
  /// sigma_3 of `pt`: the integral of nu_t = f/(1 - d e)^2 (2.32)-(2.34), with nu_t = nu_max from
  /// where it reaches nu_max or from failure (e1 = q_f/(E_i (1 - R_f))) on, as the incremental
  /// update does.
  [[nodiscard]] double lateral(double e1, const Point& pt) const {
    const double f = pt.f, d = pt.P.d;
    if (f <= 0.0) return 0.0;
    double es = 1e300; // strain where nu_t reaches nu_max
    if (f >= c_.nu_max)
      es = 0.0;
    else if (d > 0.0)
      es = (1.0 - std::sqrt(f / c_.nu_max)) / d;
    if (pt.P.R_f < 1.0) es = std::min(es, pt.q_f / (pt.E_i * (1.0 - pt.P.R_f)));
    if (e1 <= es) return f * e1 / (1.0 - d * e1);
    return f * es / (1.0 - d * es) + c_.nu_max * (e1 - es);
  }

  /// The deviator of the hyperbola (2.26) at major compressive strain e1 and sigma_3,
  /// continued with the residual modulus beyond failure.
  [[nodiscard]] double hyperbola(const Point& pt, double e1) const {
    const double R = pt.P.R_f;
    if (R < 1.0) {
      const double ef = pt.q_f / (pt.E_i * (1.0 - R)); // strain where q = q_f
      if (e1 > ef) return pt.q_f + c_.residual * pt.E_i * (e1 - ef);
    }
    return e1 / (1.0 / pt.E_i + R * e1 / pt.q_f);
  }

  /// The author's stress recovery (4.46)-(4.49): sigma_3 from the ratio of the lateral to the
  /// major principal strain, sigma_1 - sigma_3 from the hyperbola, sigma_2 = sigma_3, principal
  /// directions of the strain. Returns false when the strain has no major compression or its
  /// lateral-to-major ratio corresponds to no sigma_3 in (sigma3_floor p_a, 10^4 p_a).
  [[nodiscard]] bool recover(const Vec6& strain, Vec6& stress) const {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(strain_tensor(strain));
    const auto& ev = es.eigenvalues(); // ascending, tension positive
    const double e1 = -ev[0];
    if (!(e1 > c_.recovery_min_strain)) return false;
    const double elat = 0.5 * (ev[1] + ev[2]);
    // g(sigma_3) = lateral(e1, f(sigma_3), d(sigma_3)) decreases with sigma_3: bisection in ln sigma_3.
    auto g = [&](double s3) { return lateral(e1, point_of(s3, s3, s3)); };
    double lo = std::log(c_.sigma3_floor * c_.p_a), hi = std::log(1e4 * c_.p_a);
    // Outside (g(hi), g(lo)) the ratio belongs to no sigma_3 of the law (e.g. a lateral
    // contraction, or an expansion beyond nu_max): no recovery, the caller integrates instead.
    if (!(elat < g(std::exp(lo)) && elat > g(std::exp(hi)))) return false;
    for (int it = 0; it < 200 && hi - lo > 1e-14; ++it) {
      const double mid = 0.5 * (lo + hi);
      (g(std::exp(mid)) > elat ? lo : hi) = mid;
    }
    const double s3 = std::exp(0.5 * (lo + hi));
    const Point pt = point_of(s3, s3, s3);
    const double q = hyperbola(pt, e1);
    const Eigen::Vector3d n1 = es.eigenvectors().col(0);
    const Eigen::Matrix3d sc = s3 * Eigen::Matrix3d::Identity() + q * n1 * n1.transpose();
    // The thesis takes sigma_2 = sigma_3. To keep a shear stiffness in the lateral plane (without
    // it the stress would not depend on the lateral shear strains), the lateral strain deviator
    // adds 2 G_t times itself, G_t = E_t/(2(1 + nu_t)) at the recovered state; it vanishes for
    // the axisymmetric states of a triaxial test, so sigma_2 = sigma_3 there.
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n1 * n1.transpose();
    const Eigen::Matrix3d lat = P * strain_tensor(strain) * P;
    const Moduli mo = moduli(point_of(s3 + q, s3, s3 + q / 3.0), false);
    stress = -stress_voigt(sc) + stress_voigt(2.0 * mo.G * (lat - 0.5 * lat.trace() * P));
    return true;
  }

  /// Sets tensile principal stresses to zero (principal directions kept).
  [[nodiscard]] static Vec6 cut_tension(const Vec6& s) {
    if (is_2d(s)) {
      const auto [m, h, r] = in_plane(s);
      if (std::max(m + r, s[2]) <= 0.0) return s;
      const double l1 = std::min(m + r, 0.0), l2 = std::min(m - r, 0.0);
      // Direction of the larger in-plane principal stress: (cos t, sin t), t = atan2(s_xy, h) / 2.
      const double t = 0.5 * std::atan2(s[3], h), c = std::cos(t), sn = std::sin(t);
      Vec6 out = Vec6::Zero();
      out[0] = l1 * c * c + l2 * sn * sn;
      out[1] = l1 * sn * sn + l2 * c * c;
      out[2] = std::min(s[2], 0.0);
      out[3] = (l1 - l2) * sn * c;
      return out;
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(stress_tensor(s));
    if (es.eigenvalues()[2] <= 0.0) return s;
    Eigen::Vector3d v = es.eigenvalues();
    for (int i = 0; i < 3; ++i) v[i] = std::min(v[i], 0.0);
    return stress_voigt(es.eigenvectors() * v.asDiagonal() * es.eigenvectors().transpose());
  }

  /// The whole update for a strain increment: stress and history; `rec` says what was done.
  [[nodiscard]] Vec6 evaluate(const MaterialInput& in, const Vec6& de, std::span<double> h, Record& rec,
                              bool replay) const {
    for (std::size_t i = 0; i < h.size(); ++i) h[i] = in.history_n[i];
    if (!replay && c_.update == Update::recovery) {
      // Loading or unloading: an E_ur trial of the whole increment against the historical maximum.
      Vec6 trial = in.stress_n;
      {
        const Moduli mu = moduli(point(in.stress_n), true);
        trial += stiffness_kg(mu.K, mu.G) * de;
      }
      rec.recovery = !below(criterion(point(trial)), criterion_max(in.history_n));
      if (rec.recovery) {
        Vec6 s;
        if (recover(in.strain_n + de + origin(in.history_n), s)) {
          const Point pe = point(s);
          h[0] = std::max(h[0], pe.S);
          h[1] = std::max(h[1], pe.q);
          return s;
        }
        rec.recovery = false; // no major compression yet: incremental for this step
      }
    } else if (replay && rec.recovery) {
      Vec6 s;
      if (!recover(in.strain_n + de + origin(in.history_n), s)) {
        // The perturbed strain is outside the recovery's domain (the base point lies within the
        // difference step of its edge): say so; the caller differences on the other side.
        rec.replay_failed = true;
        return in.stress_n;
      }
      const Point pe = point(s);
      h[0] = std::max(h[0], pe.S);
      h[1] = std::max(h[1], pe.q);
      return s;
    }
    return incremental(in.stress_n, de, h, rec, replay);
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    auto where = [&] {
      return " at element " + std::to_string(in.where.element) + ", point " + std::to_string(in.where.point);
    };
    if (!in.dstrain.allFinite() || !in.strain_n.allFinite() || !in.stress_n.allFinite())
      return Outcome::failure(Status::non_finite, "duncan_chang: non-finite strain or stress" + where());
    Record rec;
    if (c_.keep_decisions) {
      // The decision kept from earlier in this step (read before the history is written).
      const double kept = out.history.size() > 8 ? out.history[8] : 0.0;
      rec.code = static_cast<int>(kept);
      rec.forced = rec.code >= 1 && rec.code <= 3;
    }
    out.stress = evaluate(in, in.dstrain, out.history, rec, false);
    if (c_.keep_decisions) {
      out.history[8] = rec.code;
      out.history[9] = rec.error;
    }
    if (rec.too_large > 0.0) {
      std::ostringstream m;
      m << "duncan_chang: strain increment " << rec.too_large
        << " needs more than max_substeps = " << c_.max_substeps << " substeps of " << c_.max_substep_strain
        << where();
      return Outcome::failure(Status::material_failure, m.str());
    }
    if (!in.want_tangent) {
      if (!out.stress.allFinite())
        return Outcome::failure(Status::non_finite, "duncan_chang: the stress is not finite" + where());
      return Outcome::success();
    }
    if (c_.keep_decisions) rec.forced = true; // differences keep the decision, not the split
    if (c_.update == Update::explicit_step && !rec.cut && !(c_.keep_decisions && rec.code == 2)) {
      // The explicit update is linear in the increment for its branch split (moduli of the
      // step's start), so its tangent is that stiffness exactly: no differences needed. Where
      // the tension cut-off acted, the differences below include the cut-off's derivative.
      out.tangent = explicit_stiffness(point(in.stress_n), rec.alpha.front());
    } else if (!difference_tangent(in, rec, out))
      return Outcome::failure(Status::material_failure,
                              "duncan_chang: the tangent's differences left the stress recovery's domain on "
                              "both sides of the strain" +
                                  where());
    if (c_.tangent_stabilization > 0.0) {
      // Only the iteration matrix changes (never the stress): keeps it regular where the soil has
      // failed or its tension is cut off.
      const double E = c_.tangent_stabilization, nu = 0.3;
      const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) out.tangent(a, b) += lam;
        out.tangent(a, a) += 2 * G;
        out.tangent(a + 3, a + 3) += G;
      }
    }
    if (!out.stress.allFinite() || !out.tangent.allFinite())
      return Outcome::failure(Status::non_finite,
                              "duncan_chang: the stress or tangent is not finite" + where());
    return Outcome::success();
  }

  /// The tangent of what the update did: central differences of the update with the branch
  /// decisions (recovery or incremental, substep count, E_t or E_ur per substep) frozen.
  /// Where a recovery replay fails on one side (the strain lies within the difference step of the
  /// recovery's edge), that column is a one-sided difference from the other; false when both fail.
  [[nodiscard]] bool difference_tangent(const MaterialInput& in, Record& rec, MaterialOutput& out) const {
    std::vector<double> hp(out.history.size());
    const double step = 1e-7;
    // A plane state (no out-of-plane shear in the stress, the strain or its increment) stays
    // plane: by the reflection z -> -z of an isotropic law the out-of-plane shears (4, 5) do not
    // couple with the in-plane components, so only columns 0-3 are differenced (each 3D
    // perturbation would also need a 3x3 eigensolver). Their diagonal, which the plane-strain
    // and axisymmetric elements never use, is taken as the in-plane shear stiffness.
    const auto plane = [](const Vec6& v) { return v[4] == 0.0 && v[5] == 0.0; };
    // Not where the tension cut-off acted: it treats the shears of the cut direction (xy, yz)
    // differently from zx, so those columns are differenced too (rare states).
    const bool plane_state = !rec.cut && plane(in.stress_n) && plane(in.strain_n) && plane(in.dstrain);
    const int columns = plane_state ? 4 : 6;
    for (int j = 0; j < columns; ++j) {
      Vec6 dp = in.dstrain, dm = in.dstrain;
      dp[j] += step;
      dm[j] -= step;
      rec.replay_failed = false;
      const Vec6 sp = evaluate(in, dp, hp, rec, true);
      const bool ok_p = !rec.replay_failed;
      rec.replay_failed = false;
      const Vec6 sm = evaluate(in, dm, hp, rec, true);
      const bool ok_m = !rec.replay_failed;
      if (ok_p && ok_m)
        out.tangent.col(j) = (sp - sm) / (2.0 * step);
      else if (ok_p)
        out.tangent.col(j) = (sp - out.stress) / step;
      else if (ok_m)
        out.tangent.col(j) = (out.stress - sm) / step;
      else
        return false;
    }
    if (plane_state) {
      out.tangent.leftCols<4>().bottomRows<2>().setZero();
      out.tangent.rightCols<2>().setZero();
      out.tangent(4, 4) = out.tangent(5, 5) = out.tangent(3, 3);
    }
    return true;
  }

private:
  Constants c_;
};

} // namespace stratum::duncan_chang
