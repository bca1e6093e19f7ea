// Sparse linear solvers behind one interface: CHOLMOD (SPD), UMFPACK (general)
// and Eigen's own solvers as the fallback.
//
// The pattern of a stage's matrix does not change, so analyze() (ordering and
// symbolic factorization) runs once per pattern and factorize() reuses it.
#pragma once

#include "stratum/error.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <string>
#include <vector>

namespace stratum {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

class LinearSolver {
public:
  virtual ~LinearSolver() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  /// Symbolic analysis of the pattern of A.
  [[nodiscard]] virtual Outcome analyze(const SparseMatrix& a) = 0;
  /// Numeric factorization of A (same pattern as the last analyze()).
  [[nodiscard]] virtual Outcome factorize(const SparseMatrix& a) = 0;
  /// x = A^-1 b with the last factorization.
  [[nodiscard]] virtual Outcome solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
};

/// Names accepted by make_linear_solver: "auto", "cholmod", "umfpack", "eigen_ldlt", "eigen_lu".
[[nodiscard]] const std::vector<std::string>& linear_solver_names();

/// "auto" picks by size and symmetry: symmetric -> CHOLMOD (Eigen LDLT below
/// `small` unknowns), unsymmetric -> UMFPACK. Throws Error for unknown names.
[[nodiscard]] std::unique_ptr<LinearSolver> make_linear_solver(const std::string& name, bool symmetric,
                                                               Eigen::Index unknowns);

} // namespace stratum
