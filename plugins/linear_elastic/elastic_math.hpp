// Linear elastic stiffness matrices (isotropic and cross-anisotropic) and the
// LinearElastic material. Header-only so the tests use the plugin's own code;
// linear_elastic.cpp only adds the factory. Equations: README.md in this folder.
//
// Voigt order and engineering shear as in stratum/voigt.hpp. Cross-anisotropy
// (transverse isotropy) has the vertical y axis as its axis of symmetry: x and z are
// the horizontal directions (in axisymmetry r and theta are horizontal, z vertical).
#pragma once

#include "stratum/elasticity.hpp"
#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/parameters.hpp"
#include "stratum/voigt.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace stratum::linear_elastic {

/// Isotropic stiffness: lambda = E nu / ((1 + nu)(1 - 2 nu)), G = E / (2 (1 + nu)).
[[nodiscard]] inline Mat6 isotropic_stiffness(double E, double nu) {
  return stratum::isotropic_stiffness(E, nu);
}

/// The five constants of a cross-anisotropic (transversely isotropic) solid whose axis of
/// symmetry is y (vertical).
struct CrossAnisotropic {
  double Eh = 0.0;    ///< Young's modulus in the horizontal directions x, z (kPa)
  double Ev = 0.0;    ///< Young's modulus in the vertical direction y (kPa)
  double nu_hh = 0.0; ///< horizontal strain from a horizontal stress in the other horizontal direction (-)
  double nu_vh = 0.0; ///< horizontal strain from a vertical stress: eps_h = -nu_vh sigma_v / Ev (-)
  double Gvh = 0.0;   ///< shear modulus of vertical planes (xy and yz) (kPa)

  /// Shear modulus of the horizontal plane (xz), fixed by isotropy in that plane.
  [[nodiscard]] double Ghh() const { return Eh / (2.0 * (1.0 + nu_hh)); }
};

/// Compliance (strain = S stress) of a cross-anisotropic solid. The symmetry
/// nu_hv / Eh = nu_vh / Ev is built in.
[[nodiscard]] inline Mat6 cross_anisotropic_compliance(const CrossAnisotropic& c) {
  Mat6 S = Mat6::Zero();
  const int x = voigt::xx, y = voigt::yy, z = voigt::zz;
  S(x, x) = S(z, z) = 1.0 / c.Eh;
  S(y, y) = 1.0 / c.Ev;
  S(x, z) = S(z, x) = -c.nu_hh / c.Eh;
  S(x, y) = S(y, x) = S(z, y) = S(y, z) = -c.nu_vh / c.Ev;
  S(voigt::xy, voigt::xy) = S(voigt::yz, voigt::yz) = 1.0 / c.Gvh;
  S(voigt::zx, voigt::zx) = 1.0 / c.Ghh();
  return S;
}

/// Checks that the cross-anisotropic stiffness is positive definite:
///   Eh > 0, Ev > 0, Gvh > 0, -1 < nu_hh < 1 and 1 - nu_hh - 2 nu_vh^2 Eh / Ev > 0.
[[nodiscard]] inline std::optional<Problem> check(const CrossAnisotropic& c) {
  if (!(c.Eh > 0.0)) return Problem{"E", "the horizontal modulus E = " + number(c.Eh) + " must be positive"};
  if (!(c.Ev > 0.0)) return Problem{"Ev", "the vertical modulus Ev = " + number(c.Ev) + " must be positive"};
  if (!(c.Gvh > 0.0)) return Problem{"Gvh", "the shear modulus Gvh = " + number(c.Gvh) + " must be positive"};
  if (!(c.nu_hh > -1.0 && c.nu_hh < 1.0))
    return Problem{"nu",
                   "nu (nu_hh) = " + number(c.nu_hh) + " must lie in (-1, 1) for a cross-anisotropic solid"};
  const double m = 1.0 - c.nu_hh - 2.0 * c.nu_vh * c.nu_vh * c.Eh / c.Ev;
  if (!(m > 0.0)) {
    const double limit = std::sqrt(std::max(0.0, (1.0 - c.nu_hh) * c.Ev / (2.0 * c.Eh)));
    return Problem{
        "nu_vh",
        "the cross-anisotropic stiffness is not positive definite: 1 - nu - 2 nu_vh^2 E/Ev = " + number(m) +
            " must be > 0, i.e. |nu_vh| < " + number(limit) + " (nu_vh = " + number(c.nu_vh) + ")"};
  }
  return std::nullopt;
}

/// Stiffness D = S^-1 of a cross-anisotropic solid (the parameters must pass check()).
[[nodiscard]] inline Mat6 cross_anisotropic_stiffness(const CrossAnisotropic& c) {
  const Mat6 S = cross_anisotropic_compliance(c);
  Mat6 D = Mat6::Zero();
  D.topLeftCorner<3, 3>() = S.topLeftCorner<3, 3>().inverse();
  for (int i = 3; i < 6; ++i) D(i, i) = 1.0 / S(i, i);
  return D;
}

/// The user's parameters as declared in the schema, before defaults are resolved.
struct Settings {
  bool cross_anisotropic = false;
  double E = 0.0;      ///< E (isotropic) or Eh (cross-anisotropic)
  double nu = 0.3;     ///< nu (isotropic) or nu_hh (cross-anisotropic)
  double Ev = 0.0;     ///< 0 means Ev = E
  double nu_vh = -1.0; ///< -1 means nu_vh = nu
  double Gvh = 0.0;    ///< 0 means Gvh = Ev / (2 (1 + nu_vh))
};

/// The cross-anisotropic constants of the settings with the "same as isotropic" defaults
/// filled in. With every optional parameter left at its default the result is isotropic.
[[nodiscard]] inline CrossAnisotropic resolve(const Settings& s) {
  CrossAnisotropic c;
  c.Eh = s.E;
  c.nu_hh = s.nu;
  c.Ev = s.Ev > 0.0 ? s.Ev : s.E;
  c.nu_vh = s.nu_vh > -1.0 ? s.nu_vh : s.nu;
  c.Gvh = s.Gvh > 0.0 ? s.Gvh : c.Ev / (2.0 * (1.0 + c.nu_vh));
  return c;
}

/// True when D is symmetric and positive definite (Cholesky succeeds).
[[nodiscard]] inline bool positive_definite(const Mat6& D) {
  if (!D.allFinite() || !D.isApprox(D.transpose(), 1e-12)) return false;
  const Eigen::LLT<Mat6> llt(D);
  return llt.info() == Eigen::Success;
}

/// stress = stress_n + D dstrain with a constant, symmetric, positive definite D.
class LinearElastic final : public Material {
public:
  /// Throws stratum::Error when D is not symmetric positive definite.
  explicit LinearElastic(const Mat6& D) : D_(D) {
    if (!positive_definite(D_))
      throw Error("linear_elastic: the elastic stiffness matrix is not positive definite");
  }

  [[nodiscard]] bool is_linear() const override { return true; }
  [[nodiscard]] bool symmetric_tangent() const override { return true; }
  [[nodiscard]] int history_size() const override { return 0; }
  /// Always 0: a linear elastic point has one regime.
  [[nodiscard]] int point_status(const Vec6& /*stress*/, std::span<const double> /*history*/) const override {
    return 0;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override { return {"elastic"}; }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    out.stress.noalias() = in.stress_n + D_ * in.dstrain;
    out.tangent = D_;
    return Outcome::success();
  }

  [[nodiscard]] const Mat6& stiffness() const { return D_; }

private:
  Mat6 D_;
};

} // namespace stratum::linear_elastic
