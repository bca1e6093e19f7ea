// The shared stress-integration library: what a plasticity model provides.
//
// A material plugin describes its elastoplastic model once through this
// interface (yield surfaces, flow directions, hardening, elasticity) and
// chooses, per material in the TOML, which integrator of integrate.hpp
// updates its stress. All functions are const and pure.
//
// Conventions: Voigt order and engineering shear of voigt.hpp, tension
// positive (models that think in compression-positive p, q convert through
// invariants.hpp). Internal variables q are the model's hardening variables
// (e.g. the preconsolidation pressure, the accumulated plastic strain); they
// are stored in the material's history. lambda_k >= 0 is the plastic
// multiplier of surface k:
//   d eps_p = sum_k dlambda_k r_k(sigma, q),   dq = sum_k dlambda_k h_k(sigma, q)
//   f_k(sigma, q) <= 0, consistency f_k = 0 on active surfaces.
//
// Gradients with respect to sigma are derivatives with respect to the six
// Voigt entries, so a shear entry is twice the tensor derivative df/dsigma_xy.
// Then r_k is directly an engineering plastic strain rate and n_k . dsigma the
// exact first-order change of f_k (invariants.hpp: to_strain_like converts).
#pragma once

#include "stratum/voigt.hpp"

#include <Eigen/Core>

#include <span>

namespace stratum::plasticity {

using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

/// What the closest-point return needs of one surface at one state (Model::surface).
struct SurfaceDerivatives {
  double f = 0.0; ///< yield
  Vec6 r;         ///< flow direction
  VecX h;         ///< hardening direction
  // with `jacobian` only:
  Vec6 n;                   ///< yield gradient
  VecX xi;                  ///< d f / d q
  Mat6 dr_ds;               ///< d r / d sigma
  MatX dr_dq, dh_ds, dh_dq; ///< d r / d q, d h / d sigma, d h / d q (left empty when internal_size() = 0)
};

class Model {
public:
  virtual ~Model() = default;

  /// Number of internal (hardening) variables.
  [[nodiscard]] virtual int internal_size() const = 0;
  /// Number of yield surfaces (Mohr-Coulomb: 6 planes + tension cut-off, ...).
  [[nodiscard]] virtual int surfaces() const { return 1; }

  // ---- elasticity
  /// Elastic tangent stiffness at (sigma, q).
  [[nodiscard]] virtual Mat6 elastic(const Vec6& sigma, std::span<const double> q) const = 0;
  /// Stress after an elastic strain increment de from sigma_n. The default integrates with the
  /// stiffness at sigma_n (exact for constant elasticity); pressure-dependent models override it.
  [[nodiscard]] virtual Vec6 elastic_update(const Vec6& sigma_n, std::span<const double> q,
                                            const Vec6& de) const {
    return sigma_n + elastic(sigma_n, q) * de;
  }
  /// d elastic_update / d de (used by the closest-point return).
  [[nodiscard]] virtual Mat6 elastic_update_tangent(const Vec6& sigma_n, std::span<const double> q,
                                                    const Vec6& /*de*/) const {
    return elastic(sigma_n, q);
  }

  // ---- surfaces
  /// Yield function of surface k (kPa-scaled; negative inside the elastic domain).
  [[nodiscard]] virtual double yield(int k, const Vec6& sigma, std::span<const double> q) const = 0;
  /// n_k = d f_k / d sigma.
  [[nodiscard]] virtual Vec6 yield_gradient(int k, const Vec6& sigma, std::span<const double> q) const = 0;
  /// d f_k / d q (size internal_size).
  [[nodiscard]] virtual VecX yield_gradient_q(int k, const Vec6& sigma, std::span<const double> q) const = 0;

  // ---- flow and hardening
  /// r_k = d g_k / d sigma (equals yield_gradient for associated flow).
  [[nodiscard]] virtual Vec6 flow(int k, const Vec6& sigma, std::span<const double> q) const = 0;
  /// h_k: dq = dlambda_k h_k (size internal_size).
  [[nodiscard]] virtual VecX hardening(int k, const Vec6& sigma, std::span<const double> q) const = 0;

  // ---- second derivatives, for the closest-point return and its consistent tangent
  /// d r_k / d sigma (6 x 6).
  [[nodiscard]] virtual Mat6 flow_gradient(int k, const Vec6& sigma, std::span<const double> q) const = 0;
  /// d r_k / d q (6 x internal_size).
  [[nodiscard]] virtual MatX flow_gradient_q(int k, const Vec6& sigma, std::span<const double> q) const = 0;
  /// d h_k / d sigma (internal_size x 6).
  [[nodiscard]] virtual MatX hardening_gradient(int k, const Vec6& sigma,
                                                std::span<const double> q) const = 0;
  /// d h_k / d q (internal_size x internal_size).
  [[nodiscard]] virtual MatX hardening_gradient_q(int k, const Vec6& sigma,
                                                  std::span<const double> q) const = 0;

  /// All of surface k at once: f, r and h, and with `jacobian` also n, xi and the four second
  /// derivatives; the values equal those of the single functions above. The default calls them
  /// one by one; a model whose functions share costly work (an inverted hardening law, say)
  /// overrides it to do that work once.
  virtual void surface(int k, const Vec6& sigma, std::span<const double> q, SurfaceDerivatives& d,
                       bool jacobian) const {
    d.f = yield(k, sigma, q);
    d.r = flow(k, sigma, q);
    d.h = hardening(k, sigma, q);
    if (!jacobian) return;
    d.n = yield_gradient(k, sigma, q);
    d.dr_ds = flow_gradient(k, sigma, q);
    if (internal_size() == 0) return;
    d.xi = yield_gradient_q(k, sigma, q);
    d.dr_dq = flow_gradient_q(k, sigma, q);
    d.dh_ds = hardening_gradient(k, sigma, q);
    d.dh_dq = hardening_gradient_q(k, sigma, q);
  }

  /// Whether internal variables are admissible (e.g. p_c > 0); integrators fail cleanly otherwise.
  [[nodiscard]] virtual bool admissible(const Vec6& /*sigma*/, std::span<const double> /*q*/) const {
    return true;
  }
  /// A stress scale for relative tolerances of yield values (kPa), e.g. the current strength.
  [[nodiscard]] virtual double stress_scale(const Vec6& sigma, std::span<const double> q) const = 0;
};

} // namespace stratum::plasticity
