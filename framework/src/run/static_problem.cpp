#include "run/static_problem.hpp"

namespace stratum {

void StaticProblem::weigh_other_fields() {
  const int dim = m_.dim();
  if (static_cast<int>(m_.dofs.fields.size()) <= dim) return;
  is_other_.assign(static_cast<std::size_t>(size()), 0);
  for (std::size_t n = 0; n + 1 < m_.dofs.node_first.size(); ++n)
    for (int f = dim; f < static_cast<int>(m_.dofs.fields.size()); ++f)
      if (const int d = m_.dofs.dof(static_cast<int>(n), f); d >= 0)
        if (const int e = m_.dofs.eq[static_cast<std::size_t>(d)]; e >= 0) {
          other_rows_.push_back(e);
          is_other_[static_cast<std::size_t>(e)] = 1;
        }
  if (other_rows_.empty()) return;
  // The factor from the tangent at the stage's start (its states reverted after).
  SparseMatrix k = a_.make_matrix();
  Eigen::VectorXd f;
  const Outcome o = a_.assemble(m_, m_.u, f, &k);
  for (auto& dm : m_.domains) dm.states.revert();
  if (!o.ok()) return; // the stage's first evaluation reports the failure
  double diag = 0.0, coupling = 0.0;
  int nu = 0;
  std::vector<double> largest(static_cast<std::size_t>(size()), 0.0);
  for (int j = 0; j < k.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(k, j); it; ++it) {
      const bool row_other = is_other_[static_cast<std::size_t>(it.row())] != 0;
      const bool col_other = is_other_[static_cast<std::size_t>(j)] != 0;
      if (!row_other && !col_other && it.row() == j) diag += std::abs(it.value()), ++nu;
      if (!row_other && col_other)
        largest[static_cast<std::size_t>(j)] =
            std::max(largest[static_cast<std::size_t>(j)], std::abs(it.value()));
    }
  for (Eigen::Index e : other_rows_) coupling += largest[static_cast<std::size_t>(e)];
  coupling /= static_cast<double>(other_rows_.size());
  if (nu > 0 && coupling > 0.0 && std::isfinite(diag) && std::isfinite(coupling))
    weight_ = (diag / nu) / coupling;
}

void predict(NonlinearProblem& problem, LinearSolver& ls, double lambda_n, double lambda,
             Eigen::VectorXd& u) {
  SparseMatrix k = problem.make_tangent();
  Eigen::VectorXd r0, r1, du;
  constexpr double eps = 1e-6;
  if (!problem.evaluate(u, lambda_n, r0, &k).ok()) return;
  if (!problem.evaluate(u, lambda_n + eps * (lambda - lambda_n), r1, nullptr).ok()) return;
  if (!ls.factorize(k).ok() || !ls.solve((r1 - r0) / eps, du).ok() || !du.allFinite()) return;
  u += du;
}

} // namespace stratum
