// The linear solvers' failures come back as one line of ours, and the libraries print nothing
// (issue 22: a collapse printed nine raw "CHOLMOD warning: matrix not positive definite" lines).
#include "stratum/linear_solver.hpp"

#include <catch2/catch.hpp>

#include <Eigen/CholmodSupport>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

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
