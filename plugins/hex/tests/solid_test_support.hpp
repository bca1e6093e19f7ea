// Test helpers shared by the solid elements' tests (test_hex_element.cpp, test_solid_elements.cpp):
// a linear elastic and a nonlinear, unsymmetric test material with exact tangents, a direct solve
// with prescribed unknowns, and a fixed pseudo-random distortion of a mesh's nodes.
#pragma once

#include "linear_elastic/elastic_math.hpp"
#include "stratum/material.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <cmath>
#include <vector>

namespace stratum::hex::testing {

/// Linear isotropic elasticity with its exact (constant) tangent.
class Elastic final : public stratum::Material {
public:
  Elastic(double E, double nu) : D_(stratum::linear_elastic::isotropic_stiffness(E, nu)) {}
  [[nodiscard]] stratum::Outcome update(const stratum::MaterialInput& in,
                                        stratum::MaterialOutput& out) const override {
    out.stress = in.stress_n + D_ * in.dstrain;
    out.tangent = D_;
    return stratum::Outcome::success();
  }
  [[nodiscard]] bool is_linear() const override { return true; }
  [[nodiscard]] const stratum::Mat6& D() const { return D_; }

private:
  stratum::Mat6 D_;
};

/// A small nonlinear, non-symmetric material with an exact tangent (for the difference check).
class Nonlinear final : public stratum::Material {
public:
  [[nodiscard]] stratum::Outcome update(const stratum::MaterialInput& in,
                                        stratum::MaterialOutput& out) const override {
    const stratum::Vec6 e = in.strain_n + in.dstrain;
    out.stress = in.stress_n + sigma(e) - sigma(in.strain_n);
    const double tr = e.head<3>().sum();
    out.tangent = D_;
    out.tangent.topLeftCorner<3, 3>().array() += 2.0 * 3e4 * tr;
    out.tangent(0, 4) += 500.0;
    return stratum::Outcome::success();
  }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

private:
  [[nodiscard]] stratum::Vec6 sigma(const stratum::Vec6& e) const {
    stratum::Vec6 s = D_ * e;
    const double tr = e.head<3>().sum();
    s.head<3>().array() += 3e4 * tr * tr;
    s(0) += 500.0 * e(4);
    return s;
  }
  stratum::Mat6 D_ = stratum::linear_elastic::isotropic_stiffness(2e4, 0.3);
};

/// Solves K u = f with u prescribed where `fixed` (values in u on entry).
inline Eigen::VectorXd solve(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& f,
                             const std::vector<char>& fixed, Eigen::VectorXd u) {
  std::vector<int> map(fixed.size(), -1);
  int n = 0;
  for (std::size_t d = 0; d < fixed.size(); ++d)
    if (!fixed[d]) map[d] = n++;
  std::vector<Eigen::Triplet<double>> t;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  for (int j = 0; j < K.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, j); it; ++it) {
      const auto i = static_cast<std::size_t>(it.row());
      if (map[i] < 0) continue;
      if (map[static_cast<std::size_t>(j)] >= 0)
        t.emplace_back(map[i], map[static_cast<std::size_t>(j)], it.value());
      else
        rhs(map[i]) -= it.value() * u(j);
    }
  for (std::size_t d = 0; d < fixed.size(); ++d)
    if (map[d] >= 0) rhs(map[d]) += f(static_cast<Eigen::Index>(d));
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(A);
  REQUIRE(lu.info() == Eigen::Success);
  const Eigen::VectorXd x = lu.solve(rhs);
  for (std::size_t d = 0; d < fixed.size(); ++d)
    if (map[d] >= 0) u(static_cast<Eigen::Index>(d)) = x(map[d]);
  return u;
}

/// Every node moved by up to `amount` in each direction (a fixed pseudo-random field).
inline void distort(std::vector<Eigen::Vector3d>& x, double amount) {
  for (std::size_t n = 0; n < x.size(); ++n)
    for (int k = 0; k < 3; ++k)
      x[n](k) += amount * std::sin(12.9898 * static_cast<double>(n) + 78.233 * k + 1.0);
}

} // namespace stratum::hex::testing
