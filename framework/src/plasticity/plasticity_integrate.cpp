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
#include "stratum/enum_names.hpp"
#include "stratum/plasticity/integrate.hpp"

#include "plasticity_detail.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace stratum::plasticity {

namespace detail {

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

} // namespace detail

using namespace detail;

// ---------------------------------------------------------------------------------------------

const char* to_string(Scheme s) {
  static constexpr std::array<const char*, 6> names{"forward_euler", "modified_euler", "trapezoidal",
                                                    "midpoint",      "cutting_plane",  "closest_point"};
  return enum_name(s, names, "unknown");
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
                 Vec6& sigma, std::span<double> q, Mat6& tangent, Counters* counters, bool want_tangent) {
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
    o = implicit(c, Rule::trapezoidal, 1.0, sigma_n, q_n, de, want_tangent, st);
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
  if (want_tangent) {
    if (!st.has_tangent) st.tangent = continuum(c, st.sigma, st.q, st.active);
    if (!st.tangent.allFinite()) return failed(fail(c, Status::non_finite, "NaN or Inf in the tangent"));
  }
  if (!model.admissible(st.sigma, cs(st.q)))
    return failed(
        fail(c, Status::material_failure, "inadmissible state (internal variables) at the end of the step"));

  sigma = st.sigma;
  for (int i = 0; i < c.nq; ++i) q[static_cast<std::size_t>(i)] = st.q[i];
  if (want_tangent) tangent = st.tangent;
  result.plastic = true;
  return result;
}

} // namespace stratum::plasticity
