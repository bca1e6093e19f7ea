// Helpers for the solver tests: a solver plugin created by name, and the softening
// bar of catalogue case S1 as a NonlinearProblem written here.
#pragma once

#include "scene/toml_check.hpp"
#include "stratum/linear_solver.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"
#include "stratum/solver.hpp"
#include "stratum/state_store.hpp"

#include <memory>
#include <string>

namespace stratum::testing {

/// A solver plugin with parameters from TOML text (the body of a [solver] table).
struct LoadedSolver {
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::unique_ptr<Solver> solver;
};

inline std::unique_ptr<LoadedSolver> load_solver(const std::string& name, const std::string& params = "") {
  auto l = std::make_unique<LoadedSolver>();
  l->catalog = std::make_unique<PluginCatalog>(std::vector<std::string>{STRATUM_PLUGIN_DIR});
  l->catalog->require(l->registry, PluginKind::solver, name);
  const auto& f = l->registry.solver(name);
  const toml::table t = toml::parse(params);
  l->solver = f.create(io::check_table(t, f.schema, "[solver]"));
  return l;
}

/// Catalogue S1: a bar of n equal elements (length L, unit area, node 0 fixed, force lambda at
/// node n). Element 0 (length l_s = L/n) softens after f_t with modulus H (H < 0; H > 0 hardens),
/// down to zero stress; unloading is secant (damage), so its history is the largest strain reached,
/// kept in a StateStore like the framework's. The other elements stay elastic.
class SofteningBar final : public NonlinearProblem {
public:
  SofteningBar(int n, double L, double E, double ft, double H)
      : n_(n), h_(L / n), E_(E), ft_(ft), H_(H), states_(1, 1), ref_(Eigen::VectorXd::Zero(n)) {
    ref_[n - 1] = 1.0;
    std::vector<Eigen::Triplet<double>> t;
    for (int e = 0; e < n; ++e) {
      const int a = e - 1, b = e; // free unknowns of its nodes (-1: fixed)
      for (int i : {a, b})
        for (int j : {a, b})
          if (i >= 0 && j >= 0) t.emplace_back(i, j, 0.0);
    }
    pattern_.resize(n, n);
    pattern_.setFromTriplets(t.begin(), t.end());
    ls_ = make_linear_solver("umfpack", false, n);
    (void)ls_->analyze(pattern_);
  }
  Eigen::Index size() const override { return n_; }
  Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r, SparseMatrix* k) override {
    r = lambda * ref_;
    if (k) *k = pattern_;
    for (int e = 0; e < n_; ++e) {
      const double ua = e > 0 ? u[e - 1] : 0.0, ub = u[e];
      const double eps = (ub - ua) / h_;
      double sig = E_ * eps, tan = E_;
      if (e == 0) {
        const double kappa_n = states_.committed(0).history()[0];
        const double kappa = std::max(kappa_n, eps);
        states_.trial(0).history()[0] = kappa;
        if (eps >= kappa_n) {
          sig = curve(eps);
          tan = slope(eps);
        } else if (kappa_n > 0) {
          sig = curve(kappa_n) / kappa_n * eps; // secant unloading
          tan = curve(kappa_n) / kappa_n;
        }
      }
      const double f = sig, kk = tan / h_; // unit area: axial force = stress
      if (e > 0) r[e - 1] += f;
      r[e] -= f;
      if (k) {
        if (e > 0) {
          k->coeffRef(e - 1, e - 1) += kk;
          k->coeffRef(e - 1, e) -= kk;
          k->coeffRef(e, e - 1) -= kk;
        }
        k->coeffRef(e, e) += kk;
      }
    }
    return {};
  }
  SparseMatrix make_tangent() const override { return pattern_; }
  const Eigen::VectorXd& reference_load() const override { return ref_; }
  LinearSolver& linear_solver() override { return *ls_; }
  double force_scale(double lambda) const override { return std::max(std::abs(lambda), ft_); }

  void commit() { states_.commit(); }
  void revert() { states_.revert(); }
  [[nodiscard]] double kappa() const { return states_.committed(0).history()[0]; }
  [[nodiscard]] const StateStore& states() const { return states_; }
  /// Analytic end displacement at stress sigma on the softening branch (S1).
  [[nodiscard]] double softening_u(double sigma) const {
    const double L = h_ * n_, ls = h_;
    return sigma * (L - ls) / E_ + ls * (ft_ / E_ + (sigma - ft_) / H_);
  }
  [[nodiscard]] double eps_t() const { return ft_ / E_; }

private:
  [[nodiscard]] double curve(double eps) const {
    if (eps <= ft_ / E_) return E_ * eps;
    return std::max(0.0, ft_ + H_ * (eps - ft_ / E_));
  }
  // Loading from the peak itself (eps = f_t/E) already follows the softening branch.
  [[nodiscard]] double slope(double eps) const {
    if (eps < ft_ / E_) return E_;
    return curve(eps) > 0 ? H_ : 0.0;
  }
  int n_;
  double h_, E_, ft_, H_;
  StateStore states_;
  Eigen::VectorXd ref_;
  SparseMatrix pattern_;
  std::unique_ptr<LinearSolver> ls_;
};

} // namespace stratum::testing
