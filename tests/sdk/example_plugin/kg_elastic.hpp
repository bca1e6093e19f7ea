// The example_kg_elastic material: isotropic linear elasticity parameterised by
// the bulk modulus K and the shear modulus G. Header-only so that the test
// program (test_kg_elastic.cpp) checks the very code the plugin runs.
// Equations: README.md in this folder.
#pragma once

#include <stratum/elasticity.hpp>
#include <stratum/material.hpp>

#include <string>

namespace example_kg {

/// stress_{n+1} = stress_n + D dstrain with the constant isotropic D of the toolkit
/// (stratum/elasticity.hpp: K + 4G/3 and K - 2G/3 in the normal block, G on the shear diagonal).
/// No history.
class KGElastic final : public stratum::Material {
public:
  KGElastic(double K, double G) : D_(stratum::stiffness_kg(K, G)) {}

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
