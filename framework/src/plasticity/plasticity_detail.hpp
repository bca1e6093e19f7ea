// The stress integrators, internal: what the explicit schemes (plasticity_explicit.cpp), the
// implicit ones (plasticity_implicit.cpp) and the dispatcher (plasticity_integrate.cpp) share.
// The notation is written once, at the top of plasticity_integrate.cpp.
#pragma once

#include "stratum/plasticity/integrate.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace stratum::plasticity::detail {

inline constexpr double inf = std::numeric_limits<double>::infinity();

inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

template <class Derived> std::span<const double> cs(const Eigen::PlainObjectBase<Derived>& v) {
  return {v.data(), static_cast<std::size_t>(v.size())};
}

/// Tensor norm of a stress-like Voigt vector (shear entries counted twice).
inline double stress_norm(const Vec6& s) {
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
inline VecX solve_small(const MatX& A, const VecX& b) {
  const Eigen::FullPivLU<MatX> lu(A);
  if (lu.isInvertible()) return lu.solve(b);
  return A.completeOrthogonalDecomposition().solve(b);
}

/// Dense vectors and matrices of at most MaxN rows and columns, stored in place (no heap
/// allocation) for a fixed MaxN; Eigen::Dynamic gives the heap-allocated VecX and MatX.
template <int MaxN> using VecN = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MaxN, 1>;
template <int MaxN> using MatN = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, MaxN, MaxN>;

/// LU of a row- and column-equilibrated matrix (the local Newton systems mix kPa and strains).
template <int MaxN = Eigen::Dynamic> class ScaledLU {
public:
  using Vec = VecN<MaxN>;
  using Mat = MatN<MaxN>;
  bool factor(const Mat& J) {
    const Eigen::Index n = J.rows();
    row_ = Vec::Ones(n), col_ = Vec::Ones(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double m = J.row(i).cwiseAbs().maxCoeff();
      if (!(m > 0.0) || !std::isfinite(m)) return false;
      row_[i] = 1.0 / m;
    }
    Mat S = row_.asDiagonal() * J;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double m = S.col(j).cwiseAbs().maxCoeff();
      if (!(m > 0.0)) return false;
      col_[j] = 1.0 / m;
    }
    S = S * col_.asDiagonal();
    lu_.compute(S);
    // Partial pivoting on the equilibrated matrix; singular (dependent gradients at a corner or
    // an apex) when a pivot is negligible against the largest (the rank test of a full-pivot LU)
    // or the estimated reciprocal condition number is below 1e-14. The estimate (several
    // triangular solves, as costly as the factorization) runs only when the pivots spread over
    // more than 1e6: with pivots within 1e6 of each other an rcond below 1e-14 would need an
    // element growth of the order 1e8 in the factors of a 7-16 unknown equilibrated system,
    // which partial pivoting does not produce outside constructed examples.
    const auto d = lu_.matrixLU().diagonal().cwiseAbs();
    const double dmax = d.maxCoeff(), dmin = d.minCoeff();
    if (!(dmax > 0.0) || !std::isfinite(dmax)) return false;
    if (!(dmin > static_cast<double>(n) * std::numeric_limits<double>::epsilon() * dmax)) return false;
    return dmin > 1e-6 * dmax || lu_.rcond() > 1e-14;
  }
  template <class B> [[nodiscard]] auto solve(const B& b) const {
    using Out = Eigen::Matrix<double, Eigen::Dynamic, B::ColsAtCompileTime, 0, MaxN, B::MaxColsAtCompileTime>;
    Out r = row_.asDiagonal() * b;
    Out x = lu_.solve(r);
    return Out(col_.asDiagonal() * x);
  }

private:
  Eigen::PartialPivLU<Mat> lu_;
  Vec row_, col_;
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

  template <class Q> double f(int k, const Vec6& s, const Q& q) const {
    if (counters) ++counters->yield_evaluations;
    return model.yield(k, s, cs(q.eval()));
  }
  /// Largest yield value over all surfaces.
  template <class Q> double fmax(const Vec6& s, const Q& q) const {
    double v = -inf;
    for (int k = 0; k < m; ++k) {
      const double fk = f(k, s, q);
      if (std::isnan(fk)) return fk;
      v = std::max(v, fk);
    }
    return v;
  }
  template <class Q> VecX fall(const Vec6& s, const Q& q) const {
    VecX v(m);
    for (int k = 0; k < m; ++k) v[k] = f(k, s, q);
    return v;
  }
  /// model.stress_scale, or |sigma| (at least 1) if the model returns no positive number.
  template <class Q> double scale(const Vec6& s, const Q& q) const {
    const double sc = model.stress_scale(s, cs(q.eval()));
    return sc > 0.0 && std::isfinite(sc) ? sc : std::max(stress_norm(s), 1.0);
  }
  /// The yield tolerance ftol * stress_scale (a positive stress).
  template <class Q> double tol(const Vec6& s, const Q& q) const { return settings.ftol * scale(s, q); }
  template <class Q> Gradients grad(int k, const Vec6& s, const Q& q) const {
    return {model.yield_gradient(k, s, cs(q.eval())), model.flow(k, s, cs(q.eval())),
            model.yield_gradient_q(k, s, cs(q.eval())), model.hardening(k, s, cs(q.eval()))};
  }
  template <class Q> Vec6 elastic_update(const Vec6& s, const Q& q, const Vec6& de) const {
    return model.elastic_update(s, cs(q.eval()), de);
  }
  /// Per-component scale of the internal variables for relative tolerances: |q_i|, but never
  /// smaller than the change of q_i that moves a yield function by one stress scale (so that
  /// q_i = 0 at the start of hardening is not measured relative to zero). A variable that no yield
  /// function depends on gets `unused` (infinity: ignore it in error estimates) or, when `unused`
  /// is 0, max(|q_i|, |q_ref_i|) (1 if both are 0).
  template <class Q, class Qr> VecX q_scale(const Vec6& s, const Q& q, const Qr& q_ref, double unused) const {
    VecX out(nq);
    if (nq == 0) return out;
    const double sc = scale(s, q);
    VecX g = VecX::Zero(nq);
    for (int k = 0; k < m; ++k) g = g.cwiseMax(model.yield_gradient_q(k, s, cs(q.eval())).cwiseAbs());
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
inline MatX multiplier_matrix(const std::vector<Gradients>& g, const Mat6& D) {
  const int a = static_cast<int>(g.size());
  MatX L(a, a);
  for (int i = 0; i < a; ++i)
    for (int j = 0; j < a; ++j) L(i, j) = g[i].n.dot(D * g[j].r) - g[i].xi.dot(g[j].h);
  return L;
}

/// The working state of one integration.
struct State {
  Vec6 sigma;
  VecX q;
  std::vector<int> active; ///< surfaces active at the end (for the tangent)
  Mat6 tangent;
  bool has_tangent = false; ///< set by closest_point (consistent tangent)
};

inline Outcome fail(const Context& c, Status s, const std::string& what) {
  return Outcome::failure(s, std::string(c.name()) + ": " + what);
}

/// The continuum tangent C_ep = D - D Q L^-1 F^T D with the surfaces `active` (thesis (2.73)).
Mat6 continuum(const Context& c, const Vec6& s, const VecX& q, const std::vector<int>& active);

/// The fraction of `de` that is elastic from (s0, q0) (Pegasus on the yield crossing, elastic
/// unloading from the surface followed by reloading included) (plasticity_explicit.cpp).
double elastic_fraction(const Context& c, const Vec6& s0, const VecX& q0, const Vec6& de, double tol);

/// Equal sub-increments with explicit continuum steps, no drift correction.
Outcome forward_euler(const Context& c, const Vec6& sigma_n, const VecX& q_n, const Vec6& de, State& st);
/// Error-controlled modified Euler substeps with drift correction (Sloan et al. 2001).
Outcome modified_euler(const Context& c, const Vec6& sigma_n, const VecX& q_n, const Vec6& de, State& st);

/// Ortiz & Simo cutting-plane iterations from the elastic trial (plasticity_implicit.cpp).
Outcome cutting_plane(const Context& c, const Vec6& trial, const VecX& q_n, State& st);

enum class Rule { trapezoidal, midpoint };
/// The generalized trapezoidal or midpoint rule (closest point: alpha = 1) with the active-set
/// strategy; with `consistent` the algorithmic tangent.
Outcome implicit(const Context& c, Rule rule, double alpha, const Vec6& sigma0, const VecX& q0,
                 const Vec6& de, bool consistent, State& st);

} // namespace stratum::plasticity::detail
