// The stress integrators of the shared plasticity library (stratum/plasticity/integrate.hpp).
//
// Notation (thesis §2.4.1 and §4.2, tension positive, Voigt order of voigt.hpp):
//   n_k = df_k/dsigma, xi_k = df_k/dq, r_k = flow direction, h_k = hardening direction,
//   D = model.elastic(sigma, q), d eps_p = sum_k dlambda_k r_k, dq = sum_k dlambda_k h_k.
// Consistency of surface k after an increment de with the surfaces j active:
//   n_k . D (de - sum_j dlambda_j r_j) + xi_k . sum_j dlambda_j h_j = 0
// so the plastic multipliers solve L dlambda = F^T D de with
//   L_kj = n_k . D r_j - xi_k . h_j                                            (thesis (2.69))
// The thesis writes L = F^T D Q - diag(xi_k . h_k), i.e. it assumes that surface k is not
// affected by the hardening of surface j != k; here the full matrix is used, which reduces to the
// thesis form in that case. Sign: hardening makes -xi_k . h_k > 0 (e.g. von Mises with linear
// hardening H: xi = -H, h = 1, so L = n.D.n + H); softening makes it negative.
//
// Every scheme starts with the same elastic trial. A plastic increment is then handled by
//   forward_euler   equal sub-increments, each with an explicit continuum step (no drift correction)
//   modified_euler  error-controlled modified Euler substeps with drift correction (Sloan et al. 2001)
//   trapezoidal     generalized trapezoidal rule, Newton on (sigma, q, dlambda)
//   midpoint        generalized midpoint rule, Newton on (sigma, q, dlambda)
//   cutting_plane   Ortiz & Simo (1986) cutting-plane iterations from the trial stress
//   closest_point   Simo & Taylor backward-Euler return with active-set strategy and consistent tangent
// forward_euler, modified_euler, trapezoidal and midpoint first find the elastic part of the
// increment (Pegasus on the fraction where the elastic path meets the surface, including elastic
// unloading from the surface followed by reloading) and apply the rule to the plastic rest;
// cutting_plane and closest_point return from the elastic trial of the whole increment.
//
// Tangents: closest_point linearizes its converged residual system R(x; de) = 0,
//   d sigma / d de = first six rows of J^-1 [T_e; 0; 0],  T_e = elastic_update_tangent,
// which for constant elasticity is the classical algorithmic modulus. The others return the
// continuum tangent C_ep = D - D Q L^-1 F^T D (thesis (2.73)) with the surfaces active at the end
// (F = [n_k], Q = [r_k]); a singular L (perfect plasticity at dependent corners) uses the
// minimum-norm least-squares solve.
//
// Tolerances: yield values within ftol * stress_scale count as on the surface; internal
// variables are compared relative to max(|q_i|, stress_scale / max_k |xi_k,i|), i.e. never
// tighter than their effect on the yield functions (see Context::q_scale).
//
// Counters: yield_evaluations counts every f_k evaluation; substeps counts the (attempted)
// substeps of forward_euler and modified_euler and 1 for the other schemes (plastic increments); iterations
// counts Newton solves, cutting-plane iterations and drift-correction iterations.
#include "stratum/plasticity/integrate.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace stratum::plasticity {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::span<const double> cs(const VecX& v) { return {v.data(), static_cast<std::size_t>(v.size())}; }

/// Tensor norm of a stress-like Voigt vector (shear entries counted twice).
double stress_norm(const Vec6& s) {
  return std::sqrt(s.head<3>().squaredNorm() + 2.0 * s.tail<3>().squaredNorm());
}

/// The gradients of one surface at one state.
struct Gradients {
  Vec6 n, r;
  VecX xi, h;
};

/// Solves the small symmetric-or-not system A x = b of the plastic multipliers. A singular or
/// rank-deficient A (dependent gradients, perfect plasticity at an apex) gets the minimum-norm
/// least-squares solution.
VecX solve_small(const MatX& A, const VecX& b) {
  const Eigen::FullPivLU<MatX> lu(A);
  if (lu.isInvertible()) return lu.solve(b);
  return A.completeOrthogonalDecomposition().solve(b);
}

/// LU of a row- and column-equilibrated matrix (the local Newton systems mix kPa and strains).
class ScaledLU {
public:
  bool factor(const MatX& J) {
    const Eigen::Index n = J.rows();
    row_ = VecX::Ones(n), col_ = VecX::Ones(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double m = J.row(i).cwiseAbs().maxCoeff();
      if (!(m > 0.0) || !std::isfinite(m)) return false;
      row_[i] = 1.0 / m;
    }
    MatX S = row_.asDiagonal() * J;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double m = S.col(j).cwiseAbs().maxCoeff();
      if (!(m > 0.0)) return false;
      col_[j] = 1.0 / m;
    }
    S = S * col_.asDiagonal();
    lu_.compute(S);
    return lu_.isInvertible() && lu_.rcond() > 1e-14;
  }
  [[nodiscard]] MatX solve(const MatX& B) const {
    return col_.asDiagonal() * lu_.solve(row_.asDiagonal() * B);
  }

private:
  Eigen::FullPivLU<MatX> lu_;
  VecX row_, col_;
};

/// One call's view of the model, with the work counters.
struct Context {
  const Model& model;
  const Settings& settings;
  Counters* counters;
  int m = 1;  ///< surfaces
  int nq = 0; ///< internal variables

  Context(const Model& mo, const Settings& se, Counters* c)
      : model(mo), settings(se), counters(c), m(mo.surfaces()), nq(mo.internal_size()) {}

  [[nodiscard]] const char* name() const { return to_string(settings.scheme); }

  double f(int k, const Vec6& s, const VecX& q) const {
    if (counters) ++counters->yield_evaluations;
    return model.yield(k, s, cs(q));
  }
  /// Largest yield value over all surfaces.
  double fmax(const Vec6& s, const VecX& q) const {
    double v = -inf;
    for (int k = 0; k < m; ++k) {
      const double fk = f(k, s, q);
      if (std::isnan(fk)) return fk;
      v = std::max(v, fk);
    }
    return v;
  }
  VecX fall(const Vec6& s, const VecX& q) const {
    VecX v(m);
    for (int k = 0; k < m; ++k) v[k] = f(k, s, q);
    return v;
  }
  /// model.stress_scale, or |sigma| (at least 1) if the model returns no positive number.
  double scale(const Vec6& s, const VecX& q) const {
    const double sc = model.stress_scale(s, cs(q));
    return sc > 0.0 && std::isfinite(sc) ? sc : std::max(stress_norm(s), 1.0);
  }
  /// The yield tolerance ftol * stress_scale (a positive stress).
  double tol(const Vec6& s, const VecX& q) const { return settings.ftol * scale(s, q); }
  Gradients grad(int k, const Vec6& s, const VecX& q) const {
    return {model.yield_gradient(k, s, cs(q)), model.flow(k, s, cs(q)), model.yield_gradient_q(k, s, cs(q)),
            model.hardening(k, s, cs(q))};
  }
  Vec6 elastic_update(const Vec6& s, const VecX& q, const Vec6& de) const {
    return model.elastic_update(s, cs(q), de);
  }
  /// Per-component scale of the internal variables for relative tolerances: |q_i|, but never
  /// smaller than the change of q_i that moves a yield function by one stress scale (so that
  /// q_i = 0 at the start of hardening is not measured relative to zero). A variable that no yield
  /// function depends on gets `unused` (infinity: ignore it in error estimates) or, when `unused`
  /// is 0, max(|q_i|, |q_ref_i|) (1 if both are 0).
  VecX q_scale(const Vec6& s, const VecX& q, const VecX& q_ref, double unused) const {
    VecX out(nq);
    if (nq == 0) return out;
    const double sc = scale(s, q);
    VecX g = VecX::Zero(nq);
    for (int k = 0; k < m; ++k) g = g.cwiseMax(model.yield_gradient_q(k, s, cs(q)).cwiseAbs());
    for (int i = 0; i < nq; ++i) {
      double v = std::max(std::abs(q[i]), std::abs(q_ref[i]));
      if (g[i] > 0.0)
        v = std::max(v, sc / g[i]);
      else if (unused > 0.0)
        v = unused;
      out[i] = v > 0.0 ? v : 1.0;
    }
    return out;
  }
};

/// The multiplier matrix L_kj = n_k . D r_j - xi_k . h_j of the surfaces in `set`.
MatX multiplier_matrix(const std::vector<Gradients>& g, const Mat6& D) {
  const int a = static_cast<int>(g.size());
  MatX L(a, a);
  for (int i = 0; i < a; ++i)
    for (int j = 0; j < a; ++j) L(i, j) = g[i].n.dot(D * g[j].r) - g[i].xi.dot(g[j].h);
  return L;
}

Mat6 continuum(const Context& c, const Vec6& s, const VecX& q, const std::vector<int>& active) {
  const Mat6 D = c.model.elastic(s, cs(q));
  if (active.empty()) return D;
  std::vector<Gradients> g;
  for (int k : active) g.push_back(c.grad(k, s, q));
  const int a = static_cast<int>(active.size());
  const MatX L = multiplier_matrix(g, D);
  MatX DQ(6, a), FD(a, 6); // D r_j and n_k^T D
  for (int j = 0; j < a; ++j) {
    DQ.col(j) = D * g[j].r;
    FD.row(j) = (D.transpose() * g[j].n).transpose();
  }
  MatX Linv_FD;
  const Eigen::FullPivLU<MatX> lu(L);
  if (lu.isInvertible())
    Linv_FD = lu.solve(FD);
  else
    Linv_FD = L.completeOrthogonalDecomposition().solve(FD);
  return D - DQ * Linv_FD; // C_ep = D - D Q L^-1 F^T D   (thesis (2.73))
}

/// The result of one explicit (continuum) plastic step.
struct Explicit {
  Vec6 dsigma;
  VecX dq;
  std::vector<int> active;
};

/// Explicit plastic step from (s, q) over the strain increment de with the continuum operator at
/// (s, q): dlambda = L^-1 F^T D de, dsigma = D (de - Q dlambda), dq = H dlambda (thesis (4.29)-(4.30)).
/// Candidate surfaces with a negative multiplier are dropped one at a time (elastic unloading from
/// that surface); without candidates the step is elastic.
Explicit explicit_step(const Context& c, const Vec6& s, const VecX& q, const Vec6& de,
                       std::vector<int> cand) {
  const Mat6 D = c.model.elastic(s, cs(q));
  const Vec6 Dde = D * de;
  std::vector<Gradients> all;
  for (int k : cand) all.push_back(c.grad(k, s, q));
  while (!cand.empty()) {
    const int a = static_cast<int>(cand.size());
    const MatX L = multiplier_matrix(all, D);
    VecX rhs(a);
    for (int i = 0; i < a; ++i) rhs[i] = all[i].n.dot(Dde);
    const VecX dl = solve_small(L, rhs);
    int worst = -1;
    for (int i = 0; i < a; ++i)
      if (dl[i] < 0.0 && (worst < 0 || dl[i] < dl[worst])) worst = i;
    if (worst < 0) {
      Explicit e{Dde, VecX::Zero(c.nq), cand};
      for (int i = 0; i < a; ++i) {
        e.dsigma -= dl[i] * (D * all[i].r);
        e.dq += dl[i] * all[i].h;
      }
      return e;
    }
    cand.erase(cand.begin() + worst);
    all.erase(all.begin() + worst);
  }
  return {Dde, VecX::Zero(c.nq), {}};
}

/// g(a) = max_k f_k(elastic_update(s0, q0, a de), q0).
double crossing_value(const Context& c, const Vec6& s0, const VecX& q0, const Vec6& de, double a) {
  return c.fmax(c.elastic_update(s0, q0, a * de), q0);
}

/// Pegasus (modified regula falsi) root of g on [a0, a1] with g(a0) < 0 < g(a1); stops at |g| <= tol.
template <class G> double pegasus(const G& g, double a0, double g0, double a1, double g1, double tol) {
  double best = a0, gbest = std::abs(g0);
  for (int it = 0; it < 200; ++it) {
    if (!(g1 != g0)) break;
    const double a = a1 - g1 * (a1 - a0) / (g1 - g0);
    const double ga = g(a);
    if (std::isnan(ga)) break;
    if (std::abs(ga) < gbest) best = a, gbest = std::abs(ga);
    if (std::abs(ga) <= tol) return a;
    if (ga * g1 < 0.0) {
      a0 = a1, g0 = g1; // the root lies between a and a1
    } else {
      g0 *= g1 / (g1 + ga); // Pegasus scaling of the retained end
    }
    a1 = a, g1 = ga;
    if (std::abs(a1 - a0) <= 1e-16) break;
  }
  return best;
}

double pegasus(const Context& c, const Vec6& s0, const VecX& q0, const Vec6& de, double a0, double g0,
               double a1, double g1, double tol) {
  return pegasus([&](double a) { return crossing_value(c, s0, q0, de, a); }, a0, g0, a1, g1, tol);
}

/// The elastic fraction a in [0, 1] of the increment de from (s0, q0) whose elastic trial violates
/// a surface: the state elastic_update(s0, q0, a de) lies on the yield surface. From inside the
/// surface this is one Pegasus search. From a point on the surface, a loading increment
/// (n . dsigma_e >= -LTOL |n| |dsigma_e| for a surface at yield) gives a = 0; otherwise the path
/// first unloads elastically and may reach the surface again later: the increment is scanned in
/// ten parts (refined where needed) to bracket the crossing (Sloan, Abbo & Sheng 2001).
double elastic_fraction(const Context& c, const Vec6& s0, const VecX& q0, const Vec6& de, double tol) {
  const double g0 = crossing_value(c, s0, q0, de, 0.0);
  const double g1 = crossing_value(c, s0, q0, de, 1.0);
  if (g0 < -tol) return pegasus(c, s0, q0, de, 0.0, g0, 1.0, g1, tol);

  // On (or outside) the surface: loading or unloading?
  constexpr double ltol = 1e-6;
  const Vec6 dse = c.elastic_update(s0, q0, de) - s0;
  bool loading = false;
  for (int k = 0; k < c.m && !loading; ++k) {
    if (c.f(k, s0, q0) < -tol) continue;
    const Vec6 n = c.model.yield_gradient(k, s0, cs(q0));
    loading = n.dot(dse) >= -ltol * n.norm() * dse.norm();
  }
  if (loading) return 0.0;

  double lo = 0.0, hi = 1.0;
  for (int level = 0; level < 8; ++level) {
    constexpr int parts = 10;
    double a_prev = lo, g_prev = crossing_value(c, s0, q0, de, lo);
    bool refined = false;
    for (int j = 1; j <= parts; ++j) {
      const double a = lo + (hi - lo) * j / parts;
      const double ga = j == parts && hi == 1.0 ? g1 : crossing_value(c, s0, q0, de, a);
      if (ga > tol) {
        if (g_prev < -tol) return pegasus(c, s0, q0, de, a_prev, g_prev, a, ga, tol);
        lo = a_prev, hi = a, refined = true;
        break;
      }
      a_prev = a, g_prev = ga;
    }
    if (!refined) return lo; // no crossing found at this resolution: plastic from lo
  }
  return lo;
}

/// Surfaces at yield (f_k >= -tol) at (s, q).
std::vector<int> at_yield(const Context& c, const Vec6& s, const VecX& q, double tol) {
  std::vector<int> v;
  for (int k = 0; k < c.m; ++k)
    if (c.f(k, s, q) >= -tol) v.push_back(k);
  return v;
}

/// The working state of one integration.
struct State {
  Vec6 sigma;
  VecX q;
  std::vector<int> active; ///< surfaces active at the end (for the tangent)
  Mat6 tangent;
  bool has_tangent = false; ///< set by closest_point (consistent tangent)
};

Outcome fail(const Context& c, Status s, const std::string& what) {
  return Outcome::failure(s, std::string(c.name()) + ": " + what);
}

// ---------------------------------------------------------------------------------------------
// Drift correction (Sloan, Abbo & Sheng 2001): consistent correction
//   dlambda = L^-1 f,  sigma -= D Q dlambda,  q += H dlambda
// on the violated (and active) surfaces, or the normal correction dlambda = (N^T N)^-1 f,
// sigma -= N dlambda when the consistent one does not reduce |f|.

Outcome drift_correction(const Context& c, State& st, const std::vector<int>& active) {
  for (int it = 0; it <= c.settings.max_iterations; ++it) {
    const double tol = c.tol(st.sigma, st.q);
    const VecX f = c.fall(st.sigma, st.q);
    if (!f.allFinite())
      return fail(c, Status::non_finite, "NaN in the yield function during drift correction");
    std::vector<int> set;
    for (int k = 0; k < c.m; ++k) {
      const bool is_active = std::find(active.begin(), active.end(), k) != active.end();
      if (f[k] > tol || (is_active && std::abs(f[k]) > tol)) set.push_back(k);
    }
    if (set.empty()) return Outcome::success();
    if (it == c.settings.max_iterations) break;
    if (c.counters) ++c.counters->iterations;

    const int a = static_cast<int>(set.size());
    std::vector<Gradients> g;
    VecX fa(a);
    for (int i = 0; i < a; ++i) g.push_back(c.grad(set[i], st.sigma, st.q)), fa[i] = f[set[i]];
    const Mat6 D = c.model.elastic(st.sigma, cs(st.q));
    const VecX dl = solve_small(multiplier_matrix(g, D), fa);
    Vec6 s1 = st.sigma;
    VecX q1 = st.q;
    for (int i = 0; i < a; ++i) s1 -= dl[i] * (D * g[i].r), q1 += dl[i] * g[i].h;
    double before = 0.0, after = 0.0;
    for (int i = 0; i < a; ++i) before = std::max(before, std::abs(fa[i]));
    for (int k : set) after = std::max(after, std::abs(c.f(k, s1, q1)));
    if (!(after < before)) { // normal correction
      MatX N(6, a);
      for (int i = 0; i < a; ++i) N.col(i) = g[i].n;
      const VecX dn = solve_small(N.transpose() * N, fa);
      s1 = st.sigma - N * dn;
      q1 = st.q;
    }
    st.sigma = s1, st.q = q1;
  }
  return fail(c, Status::material_failure,
              "yield surface drift correction did not converge in " +
                  std::to_string(c.settings.max_iterations) + " iterations, max f = " +
                  num(c.fmax(st.sigma, st.q)) + " (tolerance " + num(c.tol(st.sigma, st.q)) + ")");
}

// ---------------------------------------------------------------------------------------------
// forward_euler

/// An explicit plastic step over de that stops where it first violates another surface (a corner
/// or an edge is reached inside the step: Pegasus on the fraction of the step), adds that surface
/// to the candidates and continues with the rest; at most one restart per surface.
void explicit_with_corners(const Context& c, State& st, Vec6 de, std::vector<int> cand, double tol) {
  for (int pass = 0; pass <= c.m; ++pass) {
    const Explicit e = explicit_step(c, st.sigma, st.q, de, cand);
    auto outside = [&](double b) {
      double g = -inf;
      for (int k = 0; k < c.m; ++k)
        if (std::find(e.active.begin(), e.active.end(), k) == e.active.end())
          g = std::max(g, c.f(k, st.sigma + b * e.dsigma, st.q + b * e.dq));
      return g;
    };
    const double g1 = pass < c.m && static_cast<int>(e.active.size()) < c.m ? outside(1.0) : -inf;
    const double g0 = g1 > tol ? outside(0.0) : 0.0;
    if (!(g1 > tol) || !(g0 < -tol)) { // no new surface crossed inside the step
      st.sigma += e.dsigma, st.q += e.dq, st.active = e.active;
      return;
    }
    const double b = pegasus(outside, 0.0, g0, 1.0, g1, tol);
    st.sigma += b * e.dsigma, st.q += b * e.dq;
    de *= 1.0 - b;
    cand = e.active;
    for (int k = 0; k < c.m; ++k)
      if (std::find(cand.begin(), cand.end(), k) == cand.end() && c.f(k, st.sigma, st.q) >= -tol)
        cand.push_back(k);
  }
}

Outcome forward_euler(const Context& c, const Vec6& sigma_n, const VecX& q_n, const Vec6& de, State& st) {
  const int substeps = std::max(1, c.settings.substeps);
  const Vec6 d = de / substeps;
  st.sigma = sigma_n, st.q = q_n, st.active.clear();
  for (int i = 0; i < substeps; ++i) {
    if (c.counters) ++c.counters->substeps;
    const Vec6 trial = c.elastic_update(st.sigma, st.q, d);
    const double tol = c.tol(st.sigma, st.q);
    const double ftrial = c.fmax(trial, st.q);
    if (std::isnan(ftrial)) return fail(c, Status::non_finite, "NaN in the yield function");
    if (ftrial <= tol) {
      st.sigma = trial, st.active.clear();
      continue;
    }
    const double a = elastic_fraction(c, st.sigma, st.q, d, tol);
    st.sigma = c.elastic_update(st.sigma, st.q, a * d);
    const Vec6 rest = (1.0 - a) * d;
    std::vector<int> cand = at_yield(c, st.sigma, st.q, tol);
    if (cand.empty()) cand = at_yield(c, c.elastic_update(st.sigma, st.q, rest), st.q, tol);
    explicit_with_corners(c, st, rest, cand, tol);
  }
  return Outcome::success();
}

// ---------------------------------------------------------------------------------------------
// modified_euler

Outcome modified_euler(const Context& c, const Vec6& sigma_n, const VecX& q_n, const Vec6& de, State& st) {
  const double tol0 = c.tol(sigma_n, q_n);
  const double a = elastic_fraction(c, sigma_n, q_n, de, tol0);
  st.sigma = c.elastic_update(sigma_n, q_n, a * de), st.q = q_n, st.active.clear();
  const Vec6 rest = (1.0 - a) * de;

  constexpr double dt_min = 1e-6, eps = 1e-16;
  const double stol = c.settings.stol;
  double t = 0.0, dt = 1.0;
  bool failed_before = false;
  while (t < 1.0) {
    const bool last = dt >= 1.0 - t;
    if (last) dt = 1.0 - t;
    if (c.counters) ++c.counters->substeps;
    const Vec6 d = dt * rest;
    const double tol = c.tol(st.sigma, st.q);
    std::vector<int> cand = at_yield(c, st.sigma, st.q, tol);
    if (cand.empty()) cand = at_yield(c, c.elastic_update(st.sigma, st.q, d), st.q, tol);
    const Explicit e1 = explicit_step(c, st.sigma, st.q, d, cand);
    const Explicit e2 = explicit_step(c, st.sigma + e1.dsigma, st.q + e1.dq, d, e1.active);
    const Vec6 s_new = st.sigma + 0.5 * (e1.dsigma + e2.dsigma);
    const VecX q_new = st.q + 0.5 * (e1.dq + e2.dq);

    // Relative local error of the pair: stresses relative to |sigma|, each internal variable
    // relative to its scale (see Context::q_scale).
    const double snorm = std::max(stress_norm(s_new), 1e-3 * c.scale(s_new, q_new)); // guard |sigma| = 0
    double R = stress_norm(e2.dsigma - e1.dsigma) / (2.0 * snorm);
    if (c.nq > 0) {
      const VecX qs = c.q_scale(s_new, q_new, st.q, inf);
      R = std::max(R, ((e2.dq - e1.dq).cwiseAbs().cwiseQuotient(2.0 * qs)).maxCoeff());
    }
    if (std::isnan(R) || !s_new.allFinite() || !q_new.allFinite())
      return fail(c, Status::non_finite, "NaN in a substep");
    R = std::max(R, eps);

    if (R > stol) {
      if (dt <= dt_min * (1.0 + 1e-12))
        return fail(c, Status::material_failure,
                    "substep size fell below the minimum " + num(dt_min) +
                        " of the increment (relative error " + num(R) + " > stol " + num(stol) + ")");
      dt = std::max(dt_min, dt * std::clamp(0.9 * std::sqrt(stol / R), 0.1, 1.0));
      failed_before = true;
      continue;
    }
    st.sigma = s_new, st.q = q_new, st.active = e2.active;
    if (const Outcome o = drift_correction(c, st, st.active); !o.ok()) return o;
    t = last ? 1.0 : t + dt;
    double factor = std::min(0.9 * std::sqrt(stol / R), 1.1);
    if (failed_before) factor = std::min(factor, 1.0);
    failed_before = false;
    dt = std::max(dt_min, factor * dt);
  }
  return Outcome::success();
}

// ---------------------------------------------------------------------------------------------
// cutting_plane (Ortiz & Simo 1986; thesis (4.41)-(4.45))

Outcome cutting_plane(const Context& c, const Vec6& trial, const VecX& q_n, State& st) {
  st.sigma = trial, st.q = q_n;
  VecX total = VecX::Zero(c.m);
  const int max_it = c.settings.max_iterations;
  for (int it = 0;; ++it) {
    const double tol = c.tol(st.sigma, st.q);
    const VecX f = c.fall(st.sigma, st.q);
    if (!f.allFinite() || !st.sigma.allFinite())
      return fail(c, Status::non_finite, "NaN after " + std::to_string(it) + " iterations");
    std::vector<int> set;
    for (int k = 0; k < c.m; ++k)
      if (f[k] > tol) set.push_back(k);
    if (set.empty()) break;
    if (it >= max_it)
      return fail(c, Status::material_failure,
                  "no convergence after " + std::to_string(max_it) +
                      " iterations, |f| = " + num(f.maxCoeff()) + " (tolerance " + num(tol) + ")");
    if (c.counters) ++c.counters->iterations;
    // Violated surfaces are relaxed jointly: L dlambda = f with L_kj = n_k . D r_j - xi_k . h_j
    // (thesis (4.44) for one surface); a surface with a negative multiplier is dropped.
    const Mat6 D = c.model.elastic(st.sigma, cs(st.q));
    std::vector<Gradients> g;
    for (int k : set) g.push_back(c.grad(k, st.sigma, st.q));
    VecX dl;
    while (true) {
      VecX fa(static_cast<Eigen::Index>(set.size()));
      for (std::size_t i = 0; i < set.size(); ++i) fa[static_cast<Eigen::Index>(i)] = f[set[i]];
      dl = solve_small(multiplier_matrix(g, D), fa);
      Eigen::Index worst;
      if (set.size() == 1 || dl.minCoeff(&worst) >= 0.0) break;
      set.erase(set.begin() + worst);
      g.erase(g.begin() + worst);
    }
    for (std::size_t i = 0; i < set.size(); ++i) {
      const double d = dl[static_cast<Eigen::Index>(i)];
      st.sigma -= d * (D * g[i].r);
      st.q += d * g[i].h;
      total[set[i]] += d;
    }
  }
  st.active.clear();
  for (int k = 0; k < c.m; ++k)
    if (total[k] > 0.0) st.active.push_back(k);
  return Outcome::success();
}

// ---------------------------------------------------------------------------------------------
// Implicit rules: generalized trapezoidal, generalized midpoint, closest point (= either with alpha = 1).
// Unknowns x = [sigma (6), q (nq), dlambda (active surfaces)], residuals
//   R_sigma = sigma - elastic_update(sigma0, q0, de - sum_j dlambda_j rbar_j)
//   R_q     = q - q0 - sum_j dlambda_j hbar_j
//   R_f,j   = f_j(sigma, q)
// trapezoidal: rbar = (1 - alpha) r(sigma0, q0) + alpha r(sigma, q)       (thesis (4.31)-(4.32))
// midpoint:    rbar = r((1 - alpha) sigma0 + alpha sigma, (1 - alpha) q0 + alpha q)  ((4.33)-(4.34))
// and the same for hbar.

enum class Rule { trapezoidal, midpoint };

class ImplicitSystem {
public:
  ImplicitSystem(const Context& c, Rule rule, double alpha, const Vec6& sigma0, const VecX& q0,
                 const Vec6& de)
      : c_(c), rule_(rule), alpha_(alpha), sigma0_(sigma0), q0_(q0), de_(de) {
    if (rule_ == Rule::trapezoidal && alpha_ < 1.0)
      for (int k = 0; k < c_.m; ++k) start_.push_back(c_.grad(k, sigma0_, q0_));
  }

  [[nodiscard]] int size(int na) const { return 6 + c_.nq + na; }

  /// Residual and (when J is given) Jacobian at x for the active surfaces; also the elastic
  /// tangent d elastic_update / d de at the converged elastic strain (for the consistent tangent).
  void evaluate(const VecX& x, const std::vector<int>& active, VecX& R, MatX* J, Mat6* Te = nullptr) const {
    const int nq = c_.nq, na = static_cast<int>(active.size()), n = size(na);
    const Vec6 sigma = x.head<6>();
    const VecX q = x.segment(6, nq);
    const VecX dl = x.tail(na);
    const double a = alpha_;

    Vec6 eps_p = Vec6::Zero();
    VecX dq = VecX::Zero(nq);
    Mat6 deps_dsigma = Mat6::Zero();
    MatX deps_dq = MatX::Zero(6, nq), ddq_dsigma = MatX::Zero(nq, 6), ddq_dq = MatX::Zero(nq, nq);
    std::vector<Vec6> rbar(na);
    std::vector<VecX> hbar(na);

    // where r and h of the end point are evaluated, and the chain factor d(point)/d(sigma, q)
    Vec6 sp = sigma;
    VecX qp = q;
    if (rule_ == Rule::midpoint) sp = (1.0 - a) * sigma0_ + a * sigma, qp = (1.0 - a) * q0_ + a * q;
    const double w_end = rule_ == Rule::trapezoidal ? a : 1.0; // weight of the end-point direction
    const double chain = rule_ == Rule::midpoint ? a : 1.0;    // d(point)/d(unknown)

    for (int j = 0; j < na; ++j) {
      const int k = active[j];
      const bool need_end = w_end > 0.0;
      Vec6 r = Vec6::Zero();
      VecX h = VecX::Zero(nq);
      if (need_end) r = w_end * c_.model.flow(k, sp, cs(qp)), h = w_end * c_.model.hardening(k, sp, cs(qp));
      if (rule_ == Rule::trapezoidal && a < 1.0) r += (1.0 - a) * start_[k].r, h += (1.0 - a) * start_[k].h;
      rbar[j] = r, hbar[j] = h;
      eps_p += dl[j] * r;
      dq += dl[j] * h;
      if (J && need_end && chain > 0.0) {
        const double w = dl[j] * w_end * chain;
        deps_dsigma += w * c_.model.flow_gradient(k, sp, cs(qp));
        if (nq > 0) {
          deps_dq += w * c_.model.flow_gradient_q(k, sp, cs(qp));
          ddq_dsigma += w * c_.model.hardening_gradient(k, sp, cs(qp));
          ddq_dq += w * c_.model.hardening_gradient_q(k, sp, cs(qp));
        }
      }
    }
    const Vec6 e_el = de_ - eps_p;
    R.resize(n);
    R.head<6>() = sigma - c_.elastic_update(sigma0_, q0_, e_el);
    R.segment(6, nq) = q - q0_ - dq;
    for (int j = 0; j < na; ++j) R[6 + nq + j] = c_.f(active[j], sigma, q);

    if (!J && !Te) return;
    const Mat6 T = c_.model.elastic_update_tangent(sigma0_, cs(q0_), e_el);
    if (Te) *Te = T;
    if (!J) return;
    J->setZero(n, n);
    J->block<6, 6>(0, 0) = Mat6::Identity() + T * deps_dsigma;
    if (nq > 0) {
      J->block(0, 6, 6, nq) = T * deps_dq;
      J->block(6, 0, nq, 6) = -ddq_dsigma;
      J->block(6, 6, nq, nq) = MatX::Identity(nq, nq) - ddq_dq;
    }
    for (int j = 0; j < na; ++j) {
      const int k = active[j];
      J->block(0, 6 + nq + j, 6, 1) = T * rbar[j];
      if (nq > 0) J->block(6, 6 + nq + j, nq, 1) = -hbar[j];
      J->block(6 + nq + j, 0, 1, 6) = c_.model.yield_gradient(k, sigma, cs(q)).transpose();
      if (nq > 0) J->block(6 + nq + j, 6, 1, nq) = c_.model.yield_gradient_q(k, sigma, cs(q)).transpose();
    }
  }

  /// Per-residual tolerances at x.
  [[nodiscard]] VecX tolerances(const VecX& x, int na) const {
    const Vec6 sigma = x.head<6>();
    const VecX q = x.segment(6, c_.nq);
    const double tol = c_.tol(sigma, q);
    VecX t(size(na));
    t.head<6>().setConstant(tol);
    if (c_.nq > 0) t.segment(6, c_.nq) = c_.settings.ftol * c_.q_scale(sigma, q, q0_, 0.0);
    t.tail(na).setConstant(tol);
    return t;
  }

  [[nodiscard]] VecX start(int na) const {
    VecX x = VecX::Zero(size(na));
    x.head<6>() = c_.elastic_update(sigma0_, q0_, de_);
    x.segment(6, c_.nq) = q0_;
    return x;
  }

private:
  const Context& c_;
  Rule rule_;
  double alpha_;
  Vec6 sigma0_;
  VecX q0_;
  Vec6 de_;
  std::vector<Gradients> start_;
};

enum class NewtonStatus { converged, not_converged, singular, non_finite };

struct NewtonResult {
  NewtonStatus status = NewtonStatus::not_converged;
  int iterations = 0;
  double fmax = 0.0, tol = 0.0; ///< largest |f| of the active surfaces and its tolerance, at the end
};

/// Newton with backtracking on the tolerance-weighted residual norm.
NewtonResult newton(const Context& c, const ImplicitSystem& sys, const std::vector<int>& active, VecX& x) {
  const int na = static_cast<int>(active.size());
  NewtonResult out;
  auto merit = [](const VecX& r, const VecX& t) { return r.cwiseQuotient(t).squaredNorm(); };
  VecX R;
  MatX J;
  sys.evaluate(x, active, R, &J);
  VecX tol = sys.tolerances(x, na);
  for (int it = 0;; ++it) {
    if (!R.allFinite() || !J.allFinite()) {
      out.status = NewtonStatus::non_finite;
      return out;
    }
    out.fmax = na > 0 ? R.tail(na).cwiseAbs().maxCoeff() : 0.0;
    out.tol = tol[0];
    if ((R.cwiseAbs().array() <= tol.array()).all()) {
      out.status = NewtonStatus::converged;
      return out;
    }
    if (it >= c.settings.max_iterations) return out;
    ScaledLU lu;
    if (!lu.factor(J)) {
      out.status = NewtonStatus::singular;
      return out;
    }
    ++out.iterations;
    if (c.counters) ++c.counters->iterations;
    const VecX dx = lu.solve(-R);
    // Full step unless it increases the weighted residual; then halve (at most 6 times).
    const double m0 = merit(R, tol);
    VecX xt = x + dx, Rt;
    sys.evaluate(xt, active, Rt, nullptr);
    if (!(Rt.allFinite() && merit(Rt, sys.tolerances(xt, na)) < m0)) {
      double step = 1.0;
      for (int ls = 0; ls < 6; ++ls) {
        step *= 0.5;
        const VecX xs = x + step * dx;
        sys.evaluate(xs, active, Rt, nullptr);
        if (Rt.allFinite() && merit(Rt, sys.tolerances(xs, na)) < m0) {
          xt = xs;
          break;
        }
      } // no decrease found: keep the full Newton step
    }
    x = xt;
    sys.evaluate(x, active, R, &J);
    tol = sys.tolerances(x, na);
  }
}

std::string set_str(const std::vector<int>& s) {
  std::string o = "{";
  for (std::size_t i = 0; i < s.size(); ++i) o += (i ? ", " : "") + std::to_string(s[i]);
  return o + "}";
}

/// Converged state of the implicit system on one fixed active set, if admissible: non-negative
/// multipliers and no inactive surface violated.
bool admissible_on(const Context& c, const ImplicitSystem& sys, const std::vector<int>& active, VecX& x) {
  const int na = static_cast<int>(active.size());
  x = sys.start(na);
  if (newton(c, sys, active, x).status != NewtonStatus::converged) return false;
  if (na > 0 && x.tail(na).minCoeff() < 0.0) return false;
  const Vec6 sigma = x.head<6>();
  const VecX q = x.segment(6, c.nq);
  const double tol = c.tol(sigma, q);
  for (int k = 0; k < c.m; ++k)
    if (std::find(active.begin(), active.end(), k) == active.end() && c.f(k, sigma, q) > tol) return false;
  return true;
}

/// Implicit integration with the active-set strategy: start with the surfaces violated by the
/// elastic trial, drop the surface with the most negative multiplier, add the most violated
/// inactive surface, until neither applies. When that strategy cycles or its Newton iteration
/// fails on a set of several surfaces (near-degenerate corners, e.g. three surfaces meeting
/// almost in one point), every set of surfaces is tried, smallest first, and the first
/// admissible solution is taken (for a convex elastic domain and associated flow it is the
/// closest point). Returns the converged state; with `consistent` the algorithmic tangent
/// d sigma / d de from the linearized residual system.
Outcome implicit(const Context& c, Rule rule, double alpha, const Vec6& sigma0, const VecX& q0,
                 const Vec6& de, bool consistent, State& st) {
  const ImplicitSystem sys(c, rule, alpha, sigma0, q0, de);
  const Vec6 trial = c.elastic_update(sigma0, q0, de);
  const double tol_trial = c.tol(trial, q0);
  const VecX f_trial = c.fall(trial, q0);
  if (!f_trial.allFinite())
    return fail(c, Status::non_finite, "NaN in the yield function at the trial stress");
  std::vector<int> active;
  for (int k = 0; k < c.m; ++k)
    if (f_trial[k] > tol_trial) active.push_back(k);
  if (active.empty()) { // elastic (the caller checks the whole increment first; this is a plastic remainder)
    st.sigma = trial, st.q = q0, st.active.clear();
    return Outcome::success();
  }

  // Every non-empty set of surfaces, smallest first; the first admissible solution.
  auto exhaustive = [&](const std::string& why, VecX& x) -> Outcome {
    if (c.m > 12) return fail(c, Status::material_failure, why);
    std::vector<std::vector<int>> sets;
    for (unsigned mask = 1; mask < (1u << c.m); ++mask) {
      std::vector<int> set;
      for (int k = 0; k < c.m; ++k)
        if (mask & (1u << k)) set.push_back(k);
      sets.push_back(std::move(set));
    }
    std::stable_sort(sets.begin(), sets.end(),
                     [](const auto& a, const auto& b) { return a.size() < b.size(); });
    for (const auto& set : sets)
      if (admissible_on(c, sys, set, x)) {
        active = set;
        return Outcome::success();
      }
    return fail(c, Status::material_failure, why + "; no set of surfaces gives an admissible return");
  };

  std::set<std::vector<int>> seen;
  const int max_changes = 4 * c.m + 4;
  int total_iterations = 0;
  VecX x;
  for (int change = 0;; ++change) {
    std::vector<int> key = active;
    std::sort(key.begin(), key.end());
    if (change > max_changes || !seen.insert(key).second) {
      const Outcome o = exhaustive("the active set of surfaces did not settle (" + std::to_string(change) +
                                       " changes, last " + set_str(active) + ")",
                                   x);
      if (!o.ok()) return o;
      break;
    }
    const int na = static_cast<int>(active.size());
    x = sys.start(na);
    const NewtonResult nr = newton(c, sys, active, x);
    total_iterations += nr.iterations;
    if (nr.status == NewtonStatus::non_finite)
      return fail(c, Status::non_finite,
                  "NaN in the local Newton iteration (active surfaces " + set_str(active) + ")");
    if (nr.status == NewtonStatus::singular) {
      if (na > 1) { // dependent gradients (corner or apex): drop the least violated surface
        int least = 0;
        for (int j = 1; j < na; ++j)
          if (f_trial[active[j]] < f_trial[active[least]]) least = j;
        active.erase(active.begin() + least);
        continue;
      }
      return fail(c, Status::material_failure,
                  "singular local Jacobian after " + std::to_string(total_iterations) + " iterations");
    }
    if (nr.status == NewtonStatus::not_converged) {
      const std::string why = "no convergence after " + std::to_string(nr.iterations) +
                              " iterations (max_iterations = " + std::to_string(c.settings.max_iterations) +
                              "), |f| = " + num(nr.fmax) + " (tolerance " + num(nr.tol) +
                              "), active surfaces " + set_str(active);
      if (na < 2) return fail(c, Status::material_failure, why);
      const Outcome o = exhaustive(why, x);
      if (!o.ok()) return o;
      break;
    }

    const VecX dl = x.tail(na);
    Eigen::Index worst = 0;
    if (dl.minCoeff(&worst) < 0.0 && na > 0) {
      active.erase(active.begin() + worst);
      if (active.empty())
        return fail(c, Status::material_failure, "all plastic multipliers negative (no admissible return)");
      continue;
    }
    const Vec6 sigma = x.head<6>();
    const VecX q = x.segment(6, c.nq);
    const double tol = c.tol(sigma, q);
    int add = -1;
    double fadd = tol;
    for (int k = 0; k < c.m; ++k) {
      if (std::find(active.begin(), active.end(), k) != active.end()) continue;
      const double fk = c.f(k, sigma, q);
      if (fk > fadd) add = k, fadd = fk;
    }
    if (add < 0) break;
    active.push_back(add);
  }

  st.sigma = x.head<6>(), st.q = x.segment(6, c.nq), st.active = active;
  if (consistent) {
    // sigma(de) from R(x(de); de) = 0: dx/dde = -J^-1 dR/dde, dR/dde = [-T_e; 0; 0].
    VecX R;
    MatX J;
    Mat6 Te;
    sys.evaluate(x, active, R, &J, &Te);
    ScaledLU lu;
    if (!lu.factor(J))
      return fail(c, Status::material_failure, "singular local Jacobian for the consistent tangent");
    MatX B = MatX::Zero(J.rows(), 6);
    B.topRows(6) = Te;
    st.tangent = lu.solve(B).topRows(6);
    st.has_tangent = true;
  }
  return Outcome::success();
}

} // namespace

// ---------------------------------------------------------------------------------------------

const char* to_string(Scheme s) {
  switch (s) {
  case Scheme::forward_euler:
    return "forward_euler";
  case Scheme::modified_euler:
    return "modified_euler";
  case Scheme::trapezoidal:
    return "trapezoidal";
  case Scheme::midpoint:
    return "midpoint";
  case Scheme::cutting_plane:
    return "cutting_plane";
  case Scheme::closest_point:
    return "closest_point";
  }
  return "unknown";
}

void add_integrator_parameters(Schema& schema, Scheme default_scheme) {
  std::vector<std::string> names;
  for (Scheme s : {Scheme::forward_euler, Scheme::modified_euler, Scheme::trapezoidal, Scheme::midpoint,
                   Scheme::cutting_plane, Scheme::closest_point})
    names.emplace_back(to_string(s));
  const Settings d;
  schema.text("integrator", names, "stress integration algorithm")
      .defaults_to(std::string(to_string(default_scheme)));
  schema.integer("substeps", "-", "forward_euler: number of equal sub-increments")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.substeps));
  schema.real("stol", "-", "modified_euler: tolerance of the relative stress error per substep")
      .greater_than(0.0)
      .less_than(1.0)
      .defaults_to(d.stol);
  schema.real("ftol", "-", "yield tolerance, relative to the model's stress scale")
      .greater_than(0.0)
      .less_than(1e-2)
      .defaults_to(d.ftol);
  schema.real("alpha", "-", "trapezoidal / midpoint: integration parameter (0 explicit, 1 fully implicit)")
      .at_least(0.0)
      .at_most(1.0)
      .defaults_to(d.alpha);
  schema.integer("max_iterations", "-", "limit of local iterations (implicit schemes, drift correction)")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.max_iterations));
}

Settings read_integrator_parameters(const Params& params) {
  Settings s;
  const std::string& name = params.text("integrator");
  bool found = false;
  for (Scheme k : {Scheme::forward_euler, Scheme::modified_euler, Scheme::trapezoidal, Scheme::midpoint,
                   Scheme::cutting_plane, Scheme::closest_point})
    if (name == to_string(k)) s.scheme = k, found = true;
  if (!found) throw Error(params.where("integrator"), params.context + " unknown integrator '" + name + "'");
  s.substeps = static_cast<int>(params.integer("substeps"));
  s.stol = params.real("stol");
  s.ftol = params.real("ftol");
  s.alpha = params.real("alpha");
  s.max_iterations = static_cast<int>(params.integer("max_iterations"));
  return s;
}

Mat6 continuum_tangent(const Model& model, const Vec6& sigma, std::span<const double> q,
                       std::span<const int> active) {
  const Settings settings;
  const Context c(model, settings, nullptr);
  VecX qv(static_cast<Eigen::Index>(q.size()));
  for (std::size_t i = 0; i < q.size(); ++i) qv[static_cast<Eigen::Index>(i)] = q[i];
  return continuum(c, sigma, qv, std::vector<int>(active.begin(), active.end()));
}

Result integrate(const Model& model, const Settings& settings, const Vec6& sigma_n, const Vec6& de,
                 Vec6& sigma, std::span<double> q, Mat6& tangent, Counters* counters) {
  const Context c(model, settings, counters);
  Result result;
  VecX q_n(c.nq);
  for (int i = 0; i < c.nq; ++i) q_n[i] = q[static_cast<std::size_t>(i)];
  auto failed = [&](Outcome o) {
    sigma = sigma_n; // q keeps q_n
    tangent = model.elastic(sigma_n, cs(q_n));
    if (!tangent.allFinite()) tangent = Mat6::Identity();
    result.outcome = std::move(o);
    result.plastic = false;
    return result;
  };
  if (static_cast<int>(q.size()) != c.nq)
    return failed(
        fail(c, Status::material_failure,
             "expected " + std::to_string(c.nq) + " internal variables, got " + std::to_string(q.size())));
  if (!sigma_n.allFinite() || !de.allFinite() || !q_n.allFinite())
    return failed(fail(c, Status::non_finite, "NaN or Inf in the committed state or the strain increment"));

  // Elastic trial for the whole increment.
  const Vec6 trial = c.elastic_update(sigma_n, q_n, de);
  if (!trial.allFinite()) return failed(fail(c, Status::non_finite, "NaN in the elastic trial stress"));
  const double ftrial = c.fmax(trial, q_n);
  if (std::isnan(ftrial)) return failed(fail(c, Status::non_finite, "NaN in the yield function"));
  if (ftrial <= c.tol(trial, q_n)) {
    sigma = trial;
    tangent = model.elastic_update_tangent(sigma_n, cs(q_n), de);
    if (!tangent.allFinite()) return failed(fail(c, Status::non_finite, "NaN in the elastic tangent"));
    if (!model.admissible(sigma, cs(q_n)))
      return failed(fail(c, Status::material_failure, "inadmissible state after an elastic step"));
    return result; // q unchanged
  }

  State st;
  Outcome o;
  switch (settings.scheme) {
  case Scheme::forward_euler:
    o = forward_euler(c, sigma_n, q_n, de, st);
    break;
  case Scheme::modified_euler:
    o = modified_euler(c, sigma_n, q_n, de, st);
    break;
  case Scheme::cutting_plane:
    o = cutting_plane(c, trial, q_n, st);
    break;
  case Scheme::closest_point:
    o = implicit(c, Rule::trapezoidal, 1.0, sigma_n, q_n, de, true, st);
    break;
  case Scheme::trapezoidal:
  case Scheme::midpoint: {
    // The plastic part of the increment starts where the elastic path meets the yield surface.
    const double a = elastic_fraction(c, sigma_n, q_n, de, c.tol(sigma_n, q_n));
    const Vec6 s0 = c.elastic_update(sigma_n, q_n, a * de);
    const Rule rule = settings.scheme == Scheme::trapezoidal ? Rule::trapezoidal : Rule::midpoint;
    o = implicit(c, rule, settings.alpha, s0, q_n, (1.0 - a) * de, false, st);
    break;
  }
  }
  if (counters && settings.scheme != Scheme::forward_euler && settings.scheme != Scheme::modified_euler)
    ++counters->substeps; // the implicit schemes and the cutting plane take the increment in one step
  if (!o.ok()) return failed(o);

  if (!st.sigma.allFinite() || !st.q.allFinite())
    return failed(fail(c, Status::non_finite, "NaN or Inf in the integrated state"));
  if (!st.has_tangent) st.tangent = continuum(c, st.sigma, st.q, st.active);
  if (!st.tangent.allFinite()) return failed(fail(c, Status::non_finite, "NaN or Inf in the tangent"));
  if (!model.admissible(st.sigma, cs(st.q)))
    return failed(
        fail(c, Status::material_failure, "inadmissible state (internal variables) at the end of the step"));

  sigma = st.sigma;
  for (int i = 0; i < c.nq; ++i) q[static_cast<std::size_t>(i)] = st.q[i];
  tangent = st.tangent;
  result.plastic = true;
  return result;
}

} // namespace stratum::plasticity
