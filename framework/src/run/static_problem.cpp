#include "run/static_problem.hpp"

namespace stratum {

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
