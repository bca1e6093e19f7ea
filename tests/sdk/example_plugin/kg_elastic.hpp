// The example_kg_elastic material: isotropic linear elasticity parameterised by
// the bulk modulus K and the shear modulus G. Header-only so that the test
// program (test_kg_elastic.cpp) checks the very code the plugin runs.
// Equations: README.md in this folder.
#pragma once

#include <stratum/material.hpp>

#include <string>

namespace example_kg {

/// Isotropic stiffness in Voigt form (xx, yy, zz, xy, yz, zx; engineering shear):
///   normal block  K + 4G/3 on the diagonal, K - 2G/3 off it;  shear diagonal G.
[[nodiscard]] inline stratum::Mat6 stiffness(double K, double G) {
  stratum::Mat6 D = stratum::Mat6::Zero();
  D.topLeftCorner<3, 3>().setConstant(K - 2.0 * G / 3.0);
  for (int i = 0; i < 3; ++i) D(i, i) = K + 4.0 * G / 3.0;
  for (int i = 3; i < 6; ++i) D(i, i) = G;
  return D;
}

/// stress_{n+1} = stress_n + D dstrain with the constant D above. No history.
class KGElastic final : public stratum::Material {
public:
  KGElastic(double K, double G) : D_(stiffness(K, G)) {}

  [[nodiscard]] bool is_linear() const override { return true; }         // D never changes
  [[nodiscard]] bool symmetric_tangent() const override { return true; } // D = D^T
  [[nodiscard]] int history_size() const override { return 0; }          // nothing to remember

  // Pure and const: reads only `in`, writes only `out`. Trouble is returned, never thrown or printed.
  [[nodiscard]] stratum::Outcome update(const stratum::MaterialInput& in,
                                        stratum::MaterialOutput& out) const override {
    if (!in.dstrain.allFinite())
      return stratum::Outcome::failure(stratum::Status::non_finite,
                                       "example_kg_elastic: non-finite strain increment at element " +
                                           std::to_string(in.where.element) + ", point " +
                                           std::to_string(in.where.point));
    out.stress.noalias() = in.stress_n + D_ * in.dstrain;
    out.tangent = D_;
    return stratum::Outcome::success();
  }

private:
  stratum::Mat6 D_;
};

} // namespace example_kg
