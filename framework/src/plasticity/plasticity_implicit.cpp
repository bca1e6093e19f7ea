// The implicit stress integrators: cutting plane, the generalized trapezoidal and midpoint rules
// and the closest-point return with the active-set strategy and the consistent tangent
// (notation: plasticity_integrate.cpp).
#include "plasticity_detail.hpp"

#include <set>

namespace stratum::plasticity::detail {

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

namespace {

// ---------------------------------------------------------------------------------------------
// Implicit rules: generalized trapezoidal, generalized midpoint, closest point (= either with alpha = 1).
// Unknowns x = [sigma (6), q (nq), dlambda (active surfaces)], residuals
//   R_sigma = sigma - elastic_update(sigma0, q0, de - sum_j dlambda_j rbar_j)
//   R_q     = q - q0 - sum_j dlambda_j hbar_j
//   R_f,j   = f_j(sigma, q)
// trapezoidal: rbar = (1 - alpha) r(sigma0, q0) + alpha r(sigma, q)       (thesis (4.31)-(4.32))
// midpoint:    rbar = r((1 - alpha) sigma0 + alpha sigma, (1 - alpha) q0 + alpha q)  ((4.33)-(4.34))
// and the same for hbar.

template <int MaxN> class ImplicitSystem {
public:
  using Vec = VecN<MaxN>;
  using Mat = MatN<MaxN>;

  ImplicitSystem(const Context& c, Rule rule, double alpha, const Vec6& sigma0, const VecX& q0,
                 const Vec6& de)
      : c_(c), rule_(rule), alpha_(alpha), sigma0_(sigma0), q0_(q0), de_(de) {
    if (rule_ == Rule::trapezoidal && alpha_ < 1.0)
      for (int k = 0; k < c_.m; ++k) start_.push_back(c_.grad(k, sigma0_, q0_));
  }

  [[nodiscard]] int size(int na) const { return 6 + c_.nq + na; }

  /// Residual and (when J is given) Jacobian at x for the active surfaces; also the elastic
  /// tangent d elastic_update / d de at the converged elastic strain (for the consistent tangent).
  void evaluate(const Vec& x, const std::vector<int>& active, Vec& R, Mat* J, Mat6* Te = nullptr) const {
    const int nq = c_.nq, na = static_cast<int>(active.size()), n = size(na);
    const Vec6 sigma = x.template head<6>();
    const Vec q = x.segment(6, nq);
    const Vec dl = x.tail(na);
    const double a = alpha_;

    Vec6 eps_p = Vec6::Zero();
    Vec dq = Vec::Zero(nq);
    Mat6 deps_dsigma = Mat6::Zero();
    Mat deps_dq = Mat::Zero(6, nq), ddq_dsigma = Mat::Zero(nq, 6), ddq_dq = Mat::Zero(nq, nq);
    Mat rbar(6, na), hbar(nq, na); // the directions of the active surfaces, by column

    // where r and h of the end point are evaluated, and the chain factor d(point)/d(sigma, q)
    Vec6 sp = sigma;
    Vec qp = q;
    if (rule_ == Rule::midpoint) sp = (1.0 - a) * sigma0_ + a * sigma, qp = (1.0 - a) * q0_ + a * q;
    const double w_end = rule_ == Rule::trapezoidal ? a : 1.0; // weight of the end-point direction
    const double chain = rule_ == Rule::midpoint ? a : 1.0;    // d(point)/d(unknown)

    // The closest point (trapezoidal, alpha = 1) needs every function at the end point (sigma, q):
    // one Model::surface call per surface gives them (the same numbers as the single calls).
    const bool closest = rule_ == Rule::trapezoidal && a == 1.0;
    VecN<MaxN> fval(na);
    Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, MaxN> nbar(6, na);
    Mat xibar(nq, na);
    for (int j = 0; j < na && closest; ++j) {
      const int k = active[j];
      c_.model.surface(k, sigma, cs(q), sd_, J != nullptr);
      if (c_.counters) ++c_.counters->yield_evaluations;
      fval[j] = sd_.f;
      const Vec6 r = w_end * sd_.r;
      const Vec h = w_end * sd_.h;
      rbar.col(j) = r, hbar.col(j) = h;
      eps_p += dl[j] * r;
      dq += dl[j] * h;
      if (J) {
        const double w = dl[j] * w_end * chain;
        deps_dsigma += w * sd_.dr_ds;
        nbar.col(j) = sd_.n;
        if (nq > 0) {
          deps_dq += w * sd_.dr_dq;
          ddq_dsigma += w * sd_.dh_ds;
          ddq_dq += w * sd_.dh_dq;
          xibar.col(j) = sd_.xi;
        }
      }
    }
    for (int j = 0; j < na && !closest; ++j) {
      const int k = active[j];
      const bool need_end = w_end > 0.0;
      Vec6 r = Vec6::Zero();
      Vec h = Vec::Zero(nq);
      if (need_end) r = w_end * c_.model.flow(k, sp, cs(qp)), h = w_end * c_.model.hardening(k, sp, cs(qp));
      if (rule_ == Rule::trapezoidal && a < 1.0) r += (1.0 - a) * start_[k].r, h += (1.0 - a) * start_[k].h;
      rbar.col(j) = r, hbar.col(j) = h;
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
    R.template head<6>() = sigma - c_.elastic_update(sigma0_, q0_, e_el);
    R.segment(6, nq) = q - q0_ - dq;
    for (int j = 0; j < na; ++j) R[6 + nq + j] = closest ? fval[j] : c_.f(active[j], sigma, q);

    if (!J && !Te) return;
    const Mat6 T = c_.model.elastic_update_tangent(sigma0_, cs(q0_), e_el);
    if (Te) *Te = T;
    if (!J) return;
    J->setZero(n, n);
    J->template block<6, 6>(0, 0) = Mat6::Identity() + T * deps_dsigma;
    if (nq > 0) {
      J->block(0, 6, 6, nq) = T * deps_dq;
      J->block(6, 0, nq, 6) = -ddq_dsigma;
      J->block(6, 6, nq, nq) = Mat::Identity(nq, nq) - ddq_dq;
    }
    for (int j = 0; j < na; ++j) {
      const int k = active[j];
      J->block(0, 6 + nq + j, 6, 1) = T * rbar.col(j);
      if (nq > 0) J->block(6, 6 + nq + j, nq, 1) = -hbar.col(j);
      if (closest) {
        J->block(6 + nq + j, 0, 1, 6) = nbar.col(j).transpose();
        if (nq > 0) J->block(6 + nq + j, 6, 1, nq) = xibar.col(j).transpose();
        continue;
      }
      J->block(6 + nq + j, 0, 1, 6) = c_.model.yield_gradient(k, sigma, cs(q)).transpose();
      if (nq > 0) J->block(6 + nq + j, 6, 1, nq) = c_.model.yield_gradient_q(k, sigma, cs(q)).transpose();
    }
  }

  /// Per-residual tolerances at x.
  [[nodiscard]] Vec tolerances(const Vec& x, int na) const {
    const Vec6 sigma = x.template head<6>();
    const Vec q = x.segment(6, c_.nq);
    const double tol = c_.tol(sigma, q);
    Vec t(size(na));
    t.template head<6>().setConstant(tol);
    if (c_.nq > 0) t.segment(6, c_.nq) = c_.settings.ftol * c_.q_scale(sigma, q, q0_, 0.0);
    t.tail(na).setConstant(tol);
    return t;
  }

  [[nodiscard]] Vec start(int na) const {
    Vec x = Vec::Zero(size(na));
    x.template head<6>() = c_.elastic_update(sigma0_, q0_, de_);
    x.segment(6, c_.nq) = q0_;
    return x;
  }

private:
  const Context& c_;
  Rule rule_;
  double alpha_;
  Vec6 sigma0_;
  Vec q0_;
  Vec6 de_;
  std::vector<Gradients> start_;
  mutable SurfaceDerivatives sd_; ///< work space of evaluate (its vectors keep their storage)
};

enum class NewtonStatus { converged, not_converged, singular, non_finite };

struct NewtonResult {
  NewtonStatus status = NewtonStatus::not_converged;
  int iterations = 0;
  double fmax = 0.0, tol = 0.0; ///< largest |f| of the active surfaces and its tolerance, at the end
  /// The residual furthest outside its tolerance at the end: what it is, its value, its tolerance.
  std::string worst_what;
  double worst = 0.0, worst_tol = 0.0;
};

/// Newton with backtracking on the tolerance-weighted residual norm.
template <int MaxN>
NewtonResult newton(const Context& c, const ImplicitSystem<MaxN>& sys, const std::vector<int>& active,
                    VecN<MaxN>& x) {
  using Vec = VecN<MaxN>;
  using Mat = MatN<MaxN>;
  const int na = static_cast<int>(active.size());
  NewtonResult out;
  auto merit = [](const Vec& r, const Vec& t) { return r.cwiseQuotient(t).squaredNorm(); };
  Vec R;
  Mat J;
  sys.evaluate(x, active, R, &J);
  Vec tol = sys.tolerances(x, na);
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
    if (it >= c.settings.max_iterations) {
      Eigen::Index w = 0;
      (R.cwiseAbs().cwiseQuotient(tol)).maxCoeff(&w);
      out.worst = std::abs(R[w]), out.worst_tol = tol[w];
      const auto wi = static_cast<int>(w);
      out.worst_what = wi < 6          ? "stress residual " + std::to_string(wi)
                       : wi < 6 + c.nq ? "internal-variable residual " + std::to_string(wi - 6)
                                       : "yield function of surface " + std::to_string(active[wi - 6 - c.nq]);
      return out;
    }
    ScaledLU<MaxN> lu;
    if (!lu.factor(J)) {
      out.status = NewtonStatus::singular;
      return out;
    }
    ++out.iterations;
    if (c.counters) ++c.counters->iterations;
    const Vec dx = lu.solve(-R);
    // Full step unless it increases the weighted residual; then halve (at most 6 times). The
    // full step is evaluated with its Jacobian, which the next iteration uses when it is taken.
    const double m0 = merit(R, tol);
    Vec xt = x + dx, Rt;
    Mat Jt;
    sys.evaluate(xt, active, Rt, &Jt);
    Vec tolt = sys.tolerances(xt, na);
    if (Rt.allFinite() && merit(Rt, tolt) < m0) {
      x = xt, R = Rt, J = Jt, tol = tolt;
      continue;
    }
    double step = 1.0;
    for (int ls = 0; ls < 6; ++ls) {
      step *= 0.5;
      const Vec xs = x + step * dx;
      sys.evaluate(xs, active, Rt, nullptr);
      if (Rt.allFinite() && merit(Rt, sys.tolerances(xs, na)) < m0) {
        xt = xs;
        break;
      }
    } // no decrease found: keep the full Newton step
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
template <int MaxN>
bool admissible_on(const Context& c, const ImplicitSystem<MaxN>& sys, const std::vector<int>& active,
                   VecN<MaxN>& x) {
  using Vec = VecN<MaxN>;
  const int na = static_cast<int>(active.size());
  x = sys.start(na);
  if (newton(c, sys, active, x).status != NewtonStatus::converged) return false;
  if (na > 0 && x.tail(na).minCoeff() < 0.0) return false;
  const Vec6 sigma = x.template head<6>();
  const Vec q = x.segment(6, c.nq);
  const double tol = c.tol(sigma, q);
  for (int k = 0; k < c.m; ++k)
    if (std::find(active.begin(), active.end(), k) == active.end() && c.f(k, sigma, q) > tol) return false;
  return true;
}

/// Every non-empty set of surfaces, smallest first; the first admissible solution (x, and its
/// set in `active`). `why`: what made the active-set strategy give up, for the failure message.
template <int MaxN>
Outcome exhaustive(const Context& c, const ImplicitSystem<MaxN>& sys, const std::string& why,
                   std::vector<int>& active, VecN<MaxN>& x) {
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
}

/// The algorithmic tangent d sigma / d de at the converged state x into st.tangent.
template <int MaxN>
Outcome consistent_tangent(const Context& c, const ImplicitSystem<MaxN>& sys, const VecN<MaxN>& x,
                           const std::vector<int>& active, State& st) {
  using Vec = VecN<MaxN>;
  using Mat = MatN<MaxN>;
  // sigma(de) from R(x(de); de) = 0: dx/dde = -J^-1 dR/dde, dR/dde = [-T_e; 0; 0].
  Vec R;
  Mat J;
  Mat6 Te;
  sys.evaluate(x, active, R, &J, &Te);
  ScaledLU<MaxN> lu;
  if (!lu.factor(J))
    return fail(c, Status::material_failure, "singular local Jacobian for the consistent tangent");
  Eigen::Matrix<double, Eigen::Dynamic, 6, 0, MaxN, 6> B =
      Eigen::Matrix<double, Eigen::Dynamic, 6, 0, MaxN, 6>::Zero(J.rows(), 6);
  B.topRows(6) = Te;
  st.tangent = lu.solve(B).topRows(6);
  st.has_tangent = true;
  return Outcome::success();
}

/// Implicit integration with the active-set strategy: start with the surfaces violated by the
/// elastic trial, drop the surface with the most negative multiplier, add the most violated
/// inactive surface, until neither applies. When that strategy cycles or its Newton iteration
/// fails on a set of several surfaces (near-degenerate corners, e.g. three surfaces meeting
/// almost in one point), every set of surfaces is tried, smallest first, and the first
/// admissible solution is taken (for a convex elastic domain and associated flow it is the
/// closest point). Returns the converged state; with `consistent` the algorithmic tangent
/// d sigma / d de from the linearized residual system.
template <int MaxN>
Outcome implicit_n(const Context& c, Rule rule, double alpha, const Vec6& sigma0, const VecX& q0,
                   const Vec6& de, bool consistent, State& st) {
  using Vec = VecN<MaxN>;
  const ImplicitSystem<MaxN> sys(c, rule, alpha, sigma0, q0, de);
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

  std::set<std::vector<int>> seen;
  const int max_changes = 4 * c.m + 4;
  int total_iterations = 0;
  Vec x;
  for (int change = 0;; ++change) {
    std::vector<int> key = active;
    std::sort(key.begin(), key.end());
    if (change > max_changes || !seen.insert(key).second) {
      const Outcome o = exhaustive(c, sys,
                                   "the active set of surfaces did not settle (" + std::to_string(change) +
                                       " changes, last " + set_str(active) + ")",
                                   active, x);
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
                              "); furthest from " + "convergence: " + nr.worst_what + " = " + num(nr.worst) +
                              " (tolerance " + num(nr.worst_tol) + "), active surfaces " + set_str(active);
      if (na < 2) return fail(c, Status::material_failure, why);
      const Outcome o = exhaustive(c, sys, why, active, x);
      if (!o.ok()) return o;
      break;
    }

    const Vec dl = x.tail(na);
    Eigen::Index worst = 0;
    if (dl.minCoeff(&worst) < 0.0 && na > 0) {
      active.erase(active.begin() + worst);
      if (active.empty())
        return fail(c, Status::material_failure, "all plastic multipliers negative (no admissible return)");
      continue;
    }
    const Vec6 sigma = x.template head<6>();
    const Vec q = x.segment(6, c.nq);
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

  st.sigma = x.template head<6>(), st.q = x.segment(6, c.nq), st.active = active;
  if (consistent) return consistent_tangent(c, sys, x, active, st);
  return Outcome::success();
}

/// Systems of up to this size (6 stresses, internal variables and multipliers; the models of
/// the repository need at most 13) are solved with matrices stored in place, larger ones on the heap.
constexpr int max_fixed_size = 16;

} // namespace

Outcome implicit(const Context& c, Rule rule, double alpha, const Vec6& sigma0, const VecX& q0,
                 const Vec6& de, bool consistent, State& st) {
  if (6 + c.nq + c.m <= max_fixed_size)
    return implicit_n<max_fixed_size>(c, rule, alpha, sigma0, q0, de, consistent, st);
  return implicit_n<Eigen::Dynamic>(c, rule, alpha, sigma0, q0, de, consistent, st);
}

} // namespace stratum::plasticity::detail
