// Nonlinear (pressure-dependent, hypoelastic) elasticity with a tension cut-off, the DIS material
// "nonlinear elastic with tension cut-off" (thesis §4.3; moduli of the Hertz type (2.18)-(2.19),
// digest §3.1). Header only so the tests run the plugin's code; see README.md.
//
//   K_t = A p_a (p/p_a)^n,  G_t = B p_a (p/p_a)^m,  p = max(-tr(sigma)/3, p_min)  (compression positive)
//   after every substep, principal stresses above the tensile strength T are set to T.
#pragma once

#include "stratum/elasticity.hpp"
#include "stratum/material.hpp"
#include "stratum/stress.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>

namespace stratum::nonlinear_elastic {

struct Constants {
  double A = 0, n = 0.5, B = 0, m = 0.5;
  double p_a = 100.0, p_min = 1.0;  ///< kPa
  double tensile_strength = 0.0;    ///< kPa, T >= 0
  double max_substep_strain = 1e-4; ///< largest strain component change per substep
};

class NoTension final : public Material {
public:
  explicit NoTension(Constants c) : c_(c) {}
  [[nodiscard]] const Constants& constants() const { return c_; }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

  /// How many principal stresses sit at the tensile strength T (within 1e-6 of
  /// max(|sigma|, p_a)): 0 none (elastic), 1, 2 or 3 directions cut off.
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> /*history*/) const override {
    const Eigen::Vector3d t = principal_tension(stress);
    const double tol = 1e-6 * std::max({std::abs(t[0]), std::abs(t[2]), c_.p_a});
    int n = 0;
    for (int i = 0; i < 3; ++i) n += t[i] >= c_.tensile_strength - tol ? 1 : 0;
    return n;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"elastic", "cut off in one direction", "cut off in two directions", "cut off in all directions"};
  }

  /// The tangent stiffness at a tension-positive stress.
  [[nodiscard]] Mat6 stiffness(const Vec6& s) const {
    const double p = std::max(-(s[0] + s[1] + s[2]) / 3.0, c_.p_min);
    const double K = c_.A * c_.p_a * std::pow(p / c_.p_a, c_.n);
    const double G = c_.B * c_.p_a * std::pow(p / c_.p_a, c_.m);
    return stiffness_kg(K, G);
  }

  /// Principal stresses above T are set to T (principal directions kept).
  [[nodiscard]] Vec6 cut(const Vec6& s) const {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(stress_tensor(s));
    if (es.eigenvalues()[2] <= c_.tensile_strength) return s;
    Eigen::Vector3d v = es.eigenvalues().cwiseMin(c_.tensile_strength);
    const Eigen::Matrix3d r = es.eigenvectors() * v.asDiagonal() * es.eigenvectors().transpose();
    return stress_voigt(r);
  }

  /// Heun substeps (explicit trapezoidal rule) with the cut-off after each; `substeps` <= 0: choose.
  [[nodiscard]] Vec6 integrate(const Vec6& s0, const Vec6& de, int& substeps) const {
    if (substeps <= 0)
      substeps = std::clamp(static_cast<int>(std::ceil(de.cwiseAbs().maxCoeff() / c_.max_substep_strain)), 1,
                            100000);
    const Vec6 dd = de / substeps;
    Vec6 s = s0;
    for (int k = 0; k < substeps; ++k) {
      const Vec6 d0 = stiffness(s) * dd;
      s = cut(s + 0.5 * (d0 + stiffness(s + d0) * dd));
    }
    return s;
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    const std::string where =
        " at element " + std::to_string(in.where.element) + ", point " + std::to_string(in.where.point);
    if (!in.dstrain.allFinite() || !in.stress_n.allFinite())
      return Outcome::failure(Status::non_finite, "nonlinear_elastic_no_tension: non-finite input" + where);
    int m = 0;
    out.stress = integrate(in.stress_n, in.dstrain, m);
    // The tangent of the update: central differences with the substep count frozen.
    const double h = 1e-7;
    for (int j = 0; j < 6; ++j) {
      Vec6 dp = in.dstrain, dm = in.dstrain;
      dp[j] += h;
      dm[j] -= h;
      out.tangent.col(j) = (integrate(in.stress_n, dp, m) - integrate(in.stress_n, dm, m)) / (2.0 * h);
    }
    if (!out.stress.allFinite() || !out.tangent.allFinite())
      return Outcome::failure(Status::non_finite, "nonlinear_elastic_no_tension: non-finite stress" + where);
    return Outcome::success();
  }

private:
  Constants c_;
};

} // namespace stratum::nonlinear_elastic
