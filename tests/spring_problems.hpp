// Small nonlinear spring systems with closed-form equilibrium paths, written as NonlinearProblems
// for the solver plugins' tests (plugins/{newton,modified_newton,arc_length,displacement_control,
// kinsol}/tests). Every law comes with its exact derivative, so a solver's iterates are those of
// the textbook method, and with its inverse or its limit points in closed form:
//
//   sinh spring    f(e) = F0 sinh(e/e0)          e(f) = e0 asinh(f/F0)          (hardening)
//   tanh spring    f(e) = F1 tanh(e/e1)          e(f) = e1 atanh(f/F1), f < F1  (softening, asymptote F1)
//   atan spring    f(e) = F1 (2/pi) atan(e/e1)   e(f) = e1 tan(pi f/(2 F1))     (softening, asymptote F1)
//   Mises truss    two bars of axial stiffness k = EA/L0, half-span a, rise h, apex deflection w:
//                  F(w) = 2 k (L0 - L) (h - w)/L,  L = sqrt(a^2 + (h - w)^2),
//                  F'(w) = 2 k [(h - w)^2/L^2 + (L - L0) a^2/L^3];
//                  limit points (F' = 0) where L^3 = a^2 L0, at w = h -+ sqrt(L*^2 - a^2).
#pragma once

#include "stratum/linear_solver.hpp"
#include "stratum/solver.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace stratum::testing {

/// A scalar spring law with its first and second derivatives.
struct SpringLaw {
  std::function<double(double)> f, df, d2f;
};

inline SpringLaw sinh_spring(double F0, double e0) {
  return {[=](double e) { return F0 * std::sinh(e / e0); },
          [=](double e) { return F0 / e0 * std::cosh(e / e0); },
          [=](double e) { return F0 / (e0 * e0) * std::sinh(e / e0); }};
}
inline SpringLaw tanh_spring(double F1, double e1) {
  return {[=](double e) { return F1 * std::tanh(e / e1); },
          [=](double e) {
            const double c = std::cosh(e / e1);
            return F1 / (e1 * c * c);
          },
          [=](double e) {
            const double c = std::cosh(e / e1);
            return -2.0 * F1 / (e1 * e1) * std::tanh(e / e1) / (c * c);
          }};
}
inline SpringLaw atan_spring(double F1, double e1) {
  const double g = 2.0 / std::numbers::pi;
  return {[=](double e) { return F1 * g * std::atan(e / e1); },
          [=](double e) { return F1 * g * e1 / (e1 * e1 + e * e); },
          [=](double e) { return -F1 * g * 2.0 * e * e1 / ((e1 * e1 + e * e) * (e1 * e1 + e * e)); }};
}

/// The shallow two-bar (von Mises) truss: apex force F(w) and stiffness F'(w) in closed form.
struct MisesTruss {
  double k = 1000.0, a = 1.0, h = 0.5;
  [[nodiscard]] double L0() const { return std::hypot(a, h); }
  [[nodiscard]] double L(double w) const { return std::hypot(a, h - w); }
  [[nodiscard]] double F(double w) const { return 2.0 * k * (L0() - L(w)) * (h - w) / L(w); }
  [[nodiscard]] double dF(double w) const {
    const double l = L(w), g = h - w;
    return 2.0 * k * (g * g / (l * l) + (l - L0()) * a * a / (l * l * l));
  }
  /// Apex deflections of the two limit points (F' = 0): L^3 = a^2 L0.
  [[nodiscard]] double L_star() const { return std::cbrt(a * a * L0()); }
  [[nodiscard]] double w_max() const { return h - std::sqrt(L_star() * L_star() - a * a); }
  [[nodiscard]] double w_min() const { return h + std::sqrt(L_star() * L_star() - a * a); }
  [[nodiscard]] SpringLaw law() const {
    return {[t = *this](double w) { return t.F(w); }, [t = *this](double w) { return t.dF(w); },
            [t = *this](double w) { // central difference of the closed-form F' (only used for bounds)
              const double d = 1e-6;
              return (t.dF(w + d) - t.dF(w - d)) / (2 * d);
            }};
  }
};

/// A chain of springs: spring 0 from the ground to unknown 0, spring i from unknown i-1 to
/// unknown i; the reference load acts on the last unknown (times `P`). All springs carry the
/// same force in equilibrium (statically determinate), so the unknowns are sums of the inverse laws.
/// Counts evaluations; `fail_when` lets a test make an evaluation fail as a material would.
class SpringChain final : public NonlinearProblem {
public:
  SpringChain(std::vector<SpringLaw> springs, double P, const std::string& linear_solver = "eigen_lu")
      : springs_(std::move(springs)), ref_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(springs_.size()))),
        P_(P) {
    const auto n = size();
    ref_[n - 1] = P;
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = std::max<Eigen::Index>(0, i - 1); j <= std::min(n - 1, i + 1); ++j)
        t.emplace_back(static_cast<int>(i), static_cast<int>(j), 0.0);
    pattern_.resize(n, n);
    pattern_.setFromTriplets(t.begin(), t.end());
    ls_ = make_linear_solver(linear_solver, false, n);
    (void)ls_->analyze(pattern_);
  }
  [[nodiscard]] Eigen::Index size() const override { return static_cast<Eigen::Index>(springs_.size()); }

  /// Internal forces of the chain at u.
  [[nodiscard]] Eigen::VectorXd internal(const Eigen::VectorXd& u) const {
    const auto n = size();
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double e = u[i] - (i > 0 ? u[i - 1] : 0.0);
      const double s = springs_[static_cast<std::size_t>(i)].f(e);
      f[i] += s;
      if (i > 0) f[i - 1] -= s;
    }
    return f;
  }

  Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r, SparseMatrix* k) override {
    ++evaluations;
    points.push_back(u);
    if (fail_when)
      if (Outcome o = fail_when(u); !o.ok()) return o;
    r = lambda * ref_ - internal(u);
    if (k) {
      ++tangents;
      *k = pattern_;
      const auto n = size();
      for (Eigen::Index i = 0; i < n; ++i) {
        const double e = u[i] - (i > 0 ? u[i - 1] : 0.0);
        const double kk = springs_[static_cast<std::size_t>(i)].df(e);
        k->coeffRef(i, i) += kk;
        if (i > 0) {
          k->coeffRef(i - 1, i - 1) += kk;
          k->coeffRef(i - 1, i) -= kk;
          k->coeffRef(i, i - 1) -= kk;
        }
      }
    }
    return {};
  }
  [[nodiscard]] SparseMatrix make_tangent() const override { return pattern_; }
  [[nodiscard]] const Eigen::VectorXd& reference_load() const override { return ref_; }
  [[nodiscard]] LinearSolver& linear_solver() override { return *ls_; }
  [[nodiscard]] double force_scale(double lambda) const override { return std::abs(lambda * P_) + 1.0; }
  [[nodiscard]] std::vector<Eigen::Index> node_set_dofs(const std::string& set,
                                                        int component) const override {
    if (component != 1) return {};
    const auto it = sets.find(set);
    return it == sets.end() ? std::vector<Eigen::Index>{} : it->second;
  }

  /// Named "node sets" (y component) of free unknowns, for displacement control by `nodes`.
  std::map<std::string, std::vector<Eigen::Index>> sets;
  std::function<Outcome(const Eigen::VectorXd&)> fail_when;
  int evaluations = 0, tangents = 0;
  std::vector<Eigen::VectorXd> points; ///< every evaluated u, in order

private:
  std::vector<SpringLaw> springs_;
  Eigen::VectorXd ref_;
  double P_;
  SparseMatrix pattern_;
  std::unique_ptr<LinearSolver> ls_;
};

/// The largest relative deviation |r_(k+1) - C r_k^2| / (C r_k^2) over the residual pairs with
/// r_k <= upper and r_(k+1) >= lower (the asymptotic range of quadratic convergence, above
/// round-off); -1 when there is no such pair.
inline double quadratic_constant_deviation(const std::vector<double>& r, double C, double upper,
                                           double lower) {
  double worst = -1.0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k)
    if (r[k] <= upper && r[k + 1] >= lower)
      worst = std::max(worst, std::abs(r[k + 1] - C * r[k] * r[k]) / (C * r[k] * r[k]));
  return worst;
}

} // namespace stratum::testing
