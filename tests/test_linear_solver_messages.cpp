// The linear solvers' failures come back as one line of ours, and the libraries print nothing
// (issue 22: a collapse printed nine raw "CHOLMOD warning: matrix not positive definite" lines).
#include "solver_helpers.hpp"
#include "stratum/linear_solver.hpp"
#include "stratum/step_control.hpp"

#include <catch2/catch.hpp>

#include <Eigen/CholmodSupport>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>

namespace test_linear_solver_messages { // one namespace per test file: the test files build in batches
                                        // (unity)

namespace fs = std::filesystem;
using namespace stratum;

namespace {

/// What `f` writes to the process's stdout and stderr (file descriptors 1 and 2, so that C
/// libraries' printf output is caught as well as std::cout/std::cerr).
std::string captured_output(const std::function<void()>& f) {
  const fs::path path = fs::temp_directory_path() / ("stratum_ls_out_" + std::to_string(::getpid()) + ".txt");
  std::fflush(stdout);
  std::fflush(stderr);
  const int saved_out = ::dup(1), saved_err = ::dup(2);
  std::FILE* file = std::fopen(path.string().c_str(), "w");
  REQUIRE(file);
  ::dup2(::fileno(file), 1);
  ::dup2(::fileno(file), 2);
  f();
  std::fflush(stdout);
  std::fflush(stderr);
  ::dup2(saved_out, 1);
  ::dup2(saved_err, 2);
  ::close(saved_out);
  ::close(saved_err);
  std::fclose(file);
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  fs::remove(path);
  return s.str();
}

/// A dense symmetric n x n matrix, n I + 1 1^T (positive definite) with its last diagonal entry
/// made -n: indefinite (x = e_n gives x^T A x = -n + 1 < 0). Dense, so that CHOLMOD chooses its
/// supernodal LL^T, which stops at a non-positive pivot (its simplicial LDL^T, chosen for very
/// sparse matrices, factorizes indefinite matrices without complaint).
SparseMatrix indefinite(int n = 64) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Ones(n, n) + n * Eigen::MatrixXd::Identity(n, n);
  d(n - 1, n - 1) = -n;
  SparseMatrix a = d.sparseView();
  a.makeCompressed();
  return a;
}

} // namespace

TEST_CASE("cholmod: a matrix that is not positive definite gives one line of ours, no library output",
          "[linear_solver]") {
  const SparseMatrix a = indefinite();
  // The library on its own (Eigen's wrapper with CHOLMOD's default print level) does print: the
  // capture sees it, so the empty capture below means something.
  const std::string raw = captured_output([&] {
    Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower> plain;
    plain.compute(a);
    CHECK(plain.info() != Eigen::Success);
  });
  CHECK(raw.find("CHOLMOD") != std::string::npos);

  Outcome o;
  const std::string ours = captured_output([&] {
    auto ls = make_linear_solver("cholmod", true, a.rows());
    REQUIRE(ls->analyze(a).ok());
    o = ls->factorize(a);
  });
  CHECK(ours.empty());
  CHECK(o.status == Status::singular);
  INFO(o.message);
  CHECK(
      o.message.rfind("cholmod: the matrix is not positive definite (its Cholesky factorization stopped at a "
                      "non-positive pivot after ",
                      0) == 0);
  CHECK(o.message.find(" of 64 columns)") != std::string::npos);
  CHECK(o.message.find('\n') == std::string::npos);
  CHECK(o.message.find("check the constraints") == std::string::npos);

  // The same solver object factorizes a positive definite matrix of the same pattern afterwards.
  SparseMatrix b = a;
  b.coeffRef(63, 63) = 64.0;
  auto ls = make_linear_solver("cholmod", true, b.rows());
  REQUIRE(ls->factorize(a).status == Status::singular);
  REQUIRE(ls->factorize(b).ok());
  Eigen::VectorXd x, rhs = Eigen::VectorXd::Ones(64);
  REQUIRE(ls->solve(rhs, x).ok());
  CHECK((b * x - rhs).norm() < 1e-12);
}

TEST_CASE("the other solvers: a singular matrix is one line naming the solver", "[linear_solver]") {
  SparseMatrix z(2, 2); // rank 1: [[1, 1], [1, 1]]
  z.insert(0, 0) = 1.0, z.insert(0, 1) = 1.0, z.insert(1, 0) = 1.0, z.insert(1, 1) = 1.0;
  z.makeCompressed();
  for (const char* name : {"eigen_ldlt", "eigen_lu", "umfpack"}) {
    INFO(name);
    Outcome o;
    const std::string out = captured_output([&] {
      auto ls = make_linear_solver(name, std::string(name) == "eigen_ldlt", 2);
      o = ls->factorize(z);
    });
    CHECK(out.empty());
    CHECK(o.status == Status::singular);
    CHECK(o.message.rfind(std::string(name) + ": the matrix is singular", 0) == 0);
  }
}

namespace {

/// A structure that loses its stiffness: n unknowns coupled by A = n I + 1 1^T (dense, so that
/// CHOLMOD factorizes supernodally) and a softening spring on the last one, s(u) = -b u^2,
/// loaded at the last unknown by lambda F. Condensed on the last unknown the path is
/// lambda F = c u - b u^2 (c the condensed stiffness of A): a limit load c^2 / (4 b) at
/// u = c / (2 b), set to lambda = 0.6; past it the tangent A - 2 b u e e^T is indefinite.
class Softening final : public NonlinearProblem {
public:
  explicit Softening(int n) : n_(n), ls_(make_linear_solver("cholmod", true, n)) {
    const double m = n - 1.0;
    c_ = n + 1.0 - m / (n + m); // (n + 1) - 1^T (n I + 1 1^T)^-1 1 over the other n - 1 unknowns
    F_ = c_ * c_ / (4.0 * b_) / 0.6;
    ref_ = Eigen::VectorXd::Zero(n);
    ref_[n - 1] = F_;
  }
  Eigen::Index size() const override { return n_; }
  Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r, SparseMatrix* k) override {
    const double un = u[n_ - 1];
    r = lambda * ref_ - (n_ * u + Eigen::VectorXd::Constant(n_, u.sum()));
    r[n_ - 1] += b_ * un * un;
    if (k) {
      Eigen::MatrixXd d = Eigen::MatrixXd::Ones(n_, n_) + n_ * Eigen::MatrixXd::Identity(n_, n_);
      d(n_ - 1, n_ - 1) -= 2.0 * b_ * un;
      *k = d.sparseView(0.0, 0.0); // keep the full pattern
      k->makeCompressed();
    }
    return {};
  }
  SparseMatrix make_tangent() const override {
    SparseMatrix k = Eigen::MatrixXd::Ones(n_, n_).sparseView();
    k.makeCompressed();
    return k;
  }
  const Eigen::VectorXd& reference_load() const override { return ref_; }
  LinearSolver& linear_solver() override { return *ls_; }
  double force_scale(double lambda) const override { return std::max(1.0, std::abs(lambda) * F_); }
  double limit_u() const { return c_ / (2.0 * b_); }

private:
  int n_;
  double b_ = 1.0, c_ = 0.0, F_ = 0.0;
  Eigen::VectorXd ref_;
  std::unique_ptr<LinearSolver> ls_;
};

} // namespace

TEST_CASE("a load step past the limit: CHOLMOD's breakdown is one line in the step's record, nothing printed",
          "[linear_solver][solver]") {
  auto solver = stratum::testing::load_solver("newton");
  StepSettings s;
  s.steps = 4; // 0.25, 0.5, then 0.75 is past the limit load at 0.6
  s.max_cutbacks = 3;
  Softening p(64);
  StepCallbacks cb;
  cb.commit = [] {};
  cb.revert = [] {};
  Eigen::VectorXd u = Eigen::VectorXd::Zero(64);
  StageResult res;
  const std::string out = captured_output([&] { res = run_stage(p, *solver->solver, s, cb, u); });
  CHECK(out.empty());
  REQUIRE_FALSE(res.outcome.ok());
  CHECK(res.lambda >= 0.5);
  CHECK(res.lambda < 0.6);
  CHECK(u[63] < p.limit_u());
  // The failed attempts say why in one line of ours.
  int broke_down = 0;
  for (const auto& r : res.records)
    if (!r.accepted && r.message.find("cholmod: the matrix is not positive definite") != std::string::npos) {
      ++broke_down;
      CHECK(r.message.find('\n') == std::string::npos);
    }
  INFO(res.outcome.message);
  CHECK(broke_down > 0);
  CHECK(res.outcome.message.find("CHOLMOD warning") == std::string::npos);
}

} // namespace test_linear_solver_messages
