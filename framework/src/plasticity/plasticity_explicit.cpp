// The explicit stress integrators: forward Euler with equal substeps and error-controlled
// modified Euler with drift correction, both after the elastic part of the increment
// (notation: plasticity_integrate.cpp).
#include "plasticity_detail.hpp"

#include <set>

namespace stratum::plasticity::detail {

namespace {

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

} // namespace

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

namespace {

/// Surfaces at yield (f_k >= -tol) at (s, q).
std::vector<int> at_yield(const Context& c, const Vec6& s, const VecX& q, double tol) {
  std::vector<int> v;
  for (int k = 0; k < c.m; ++k)
    if (c.f(k, s, q) >= -tol) v.push_back(k);
  return v;
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

} // namespace

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

} // namespace stratum::plasticity::detail
