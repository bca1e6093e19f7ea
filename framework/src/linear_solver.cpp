#include "stratum/linear_solver.hpp"
#include "suggest.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>

#include <cmath>
#include <string>
#include <type_traits>

namespace stratum {

namespace {

bool finite(const Eigen::VectorXd& v) { return v.allFinite(); }

/// Eigen's CHOLMOD wrapper, silenced, with the column where a factorization broke down.
///
/// CHOLMOD reports trouble (e.g. "CHOLMOD warning: matrix not positive definite") through
/// cholmod_error(): it prints the text when the cholmod_common's `print` level is above 0
/// (1 for errors, 2 for warnings; the default is 3), using SuiteSparse's process-wide printf
/// function, and then calls the common's `error_handler`, a plain function pointer without any
/// user data, so a handler could only pass the text on through global state. We need neither:
/// `print = 0` in our own cholmod_common (one per solver object) stops the printing, nothing
/// process-wide is changed, and after a failed factorization CHOLMOD's `status` (why) and the
/// factor's `minor` (the column at which it stopped) are all that our one-line message needs.
class QuietCholmod final : public Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower> {
public:
  QuietCholmod() {
    cholmod().print = 0; // nothing on stdout or stderr; the Outcome carries the message
    // AMD only: CHOLMOD's default also tries METIS when AMD's fill looks high, which at
    // 1e6 unknowns cost ~14 s and then kept AMD's ordering anyway (docs/benchmarks.md).
    cholmod().nmethods = 1;
    cholmod().method[0].ordering = CHOLMOD_AMD;
    cholmod().postorder = 1;
  }
  /// Why the last factorization failed, in one line (without the solver's name).
  [[nodiscard]] std::string failure() {
    const auto n = m_cholmodFactor ? static_cast<long long>(m_cholmodFactor->n) : -1;
    const auto k = m_cholmodFactor ? static_cast<long long>(m_cholmodFactor->minor) : -1;
    switch (cholmod().status) {
    case CHOLMOD_NOT_POSDEF:
      // minor counts the columns factorized in CHOLMOD's fill-reducing order: how far it got.
      return "the matrix is not positive definite (its Cholesky factorization stopped at a non-positive "
             "pivot after " +
             std::to_string(k) + " of " + std::to_string(n) + " columns)";
    case CHOLMOD_OUT_OF_MEMORY:
      return "out of memory in the factorization";
    case CHOLMOD_TOO_LARGE:
      return "the factor is too large (integer overflow in CHOLMOD)";
    default:
      return "the factorization failed (CHOLMOD status " + std::to_string(cholmod().status) + ", after " +
             std::to_string(k) + " of " + std::to_string(n) + " columns)";
    }
  }
};

/// Wraps any Eigen sparse solver with analyzePattern/factorize/solve/info.
template <class S> class EigenBacked final : public LinearSolver {
public:
  explicit EigenBacked(std::string name) : name_(std::move(name)) {}
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
    if (solver_.info() == Eigen::Success) return {};
    // One line, what the factorization found; the caller says what it means (a collapse, a
    // rigid-body motion before any step converged).
    if constexpr (std::is_same_v<S, QuietCholmod>)
      return Outcome::failure(Status::singular, name_ + ": " + solver_.failure());
    else if constexpr (std::is_same_v<
                           S, Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>>)
      return Outcome::failure(Status::singular,
                              name_ + ": the matrix is singular (a zero pivot in its LDL^T)");
    else
      return Outcome::failure(Status::singular,
                              name_ + ": the matrix is singular (its LU factorization failed)");
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
  if (n == "cholmod") return std::make_unique<EigenBacked<QuietCholmod>>(n);
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
