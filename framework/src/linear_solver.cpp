#include "stratum/linear_solver.hpp"
#include "stratum/suggest.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>

#include <cmath>
#include <type_traits>

namespace stratum {

namespace {

bool finite(const Eigen::VectorXd& v) { return v.allFinite(); }

/// Wraps any Eigen sparse solver with analyzePattern/factorize/solve/info.
template <class S> class EigenBacked final : public LinearSolver {
public:
  explicit EigenBacked(std::string name) : name_(std::move(name)) {
    if constexpr (std::is_same_v<S, Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower>>) {
      // AMD only: CHOLMOD's default also tries METIS when AMD's fill looks high, which at
      // 1e6 unknowns cost ~14 s and then kept AMD's ordering anyway (docs/benchmarks.md).
      solver_.cholmod().nmethods = 1;
      solver_.cholmod().method[0].ordering = CHOLMOD_AMD;
      solver_.cholmod().postorder = 1;
    }
  }
  std::string name() const override { return name_; }
  Outcome analyze(const SparseMatrix& a) override {
    solver_.analyzePattern(a);
    // Eigen's SparseLU sets info() only in factorize(): before that it is uninitialised.
    constexpr bool sets_info = !std::is_same_v<S, Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>>;
    if (sets_info && solver_.info() != Eigen::Success)
      return Outcome::failure(Status::singular, name_ + ": symbolic analysis failed");
    analyzed_ = true;
    return {};
  }
  Outcome factorize(const SparseMatrix& a) override {
    if (!analyzed_) {
      if (auto o = analyze(a); !o.ok()) return o;
    }
    solver_.factorize(a);
    if (solver_.info() != Eigen::Success)
      return Outcome::failure(Status::singular, name_ +
                                                    ": factorization failed (matrix singular or not positive "
                                                    "definite: check the constraints)");
    return {};
  }
  Outcome solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = solver_.solve(b);
    if (solver_.info() != Eigen::Success) return Outcome::failure(Status::singular, name_ + ": solve failed");
    if (!finite(x)) return Outcome::failure(Status::non_finite, name_ + ": solution contains NaN or Inf");
    return {};
  }

private:
  std::string name_;
  S solver_;
  bool analyzed_ = false;
};

} // namespace

const std::vector<std::string>& linear_solver_names() {
  static const std::vector<std::string> names{"auto", "cholmod", "umfpack", "eigen_ldlt", "eigen_lu"};
  return names;
}

std::unique_ptr<LinearSolver> make_linear_solver(const std::string& name, bool symmetric,
                                                 Eigen::Index unknowns) {
  std::string n = name;
  if (n == "auto") {
    // Below a few thousand unknowns the supernodal machinery costs more than it saves
    // (docs/design.md); Eigen's simplicial LDL^T is the faster choice there. For unsymmetric
    // tangents UMFPACK allocates its numeric workspace at every factorization, which at the
    // pile scene's ~2000 unknowns cost more than Eigen's SparseLU (docs/benchmarks.md, profile).
    constexpr Eigen::Index small = 3000;
    if (symmetric)
      n = unknowns < small ? "eigen_ldlt" : "cholmod";
    else
      n = unknowns < small ? "eigen_lu" : "umfpack";
  }
  if (n == "cholmod")
    return std::make_unique<EigenBacked<Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower>>>(n);
  if (n == "umfpack") return std::make_unique<EigenBacked<Eigen::UmfPackLU<SparseMatrix>>>(n);
  if (n == "eigen_ldlt")
    return std::make_unique<
        EigenBacked<Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>>>(n);
  if (n == "eigen_lu")
    return std::make_unique<EigenBacked<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>>>(n);
  std::string known;
  for (const auto& k : linear_solver_names()) known += (known.empty() ? "" : ", ") + k;
  throw Error("unknown linear solver '" + name + "'; known: " + known +
              did_you_mean(name, linear_solver_names()));
}

} // namespace stratum
