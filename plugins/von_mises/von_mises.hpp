// Von Mises plasticity with linear isotropic hardening: the plasticity::Model and the Material
// that wraps the shared integrators. Header-only so the tests use the plugin's own code;
// von_mises.cpp only registers the factory. Equations and sources: README.md in this folder.
//
// Voigt order and engineering shear strains of stratum/voigt.hpp, tension positive.
//   f(sigma, q) = sqrt(3 J2(sigma)) - (sigma_y + H eps_bar_p),  q = [eps_bar_p]
//   associated flow r = n = df/dsigma, h = 1 (so d eps_bar_p = dlambda = sqrt(2/3 deps_p:deps_p))
#pragma once

#include "stratum/elasticity.hpp"
#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/parameters.hpp"
#include "stratum/params.hpp"
#include "stratum/plasticity/integrate.hpp"
#include "stratum/plasticity/invariants.hpp"
#include "stratum/plasticity/model.hpp"
#include "stratum/voigt.hpp"

#include <cmath>
#include <memory>
#include <string>

namespace stratum::von_mises {

using plasticity::MatX;
using plasticity::VecX;

/// Material constants.
struct Constants {
  double E = 0.0;       ///< Young's modulus (kPa)
  double nu = 0.3;      ///< Poisson's ratio (-)
  double sigma_y = 0.0; ///< initial uniaxial yield stress (kPa)
  double H = 0.0;       ///< linear isotropic hardening modulus d sigma_y / d eps_bar_p (kPa)

  [[nodiscard]] double G() const { return E / (2.0 * (1.0 + nu)); }
  [[nodiscard]] double K() const { return E / (3.0 * (1.0 - 2.0 * nu)); }
};

/// Isotropic elastic stiffness in Voigt form with engineering shear strains.
[[nodiscard]] inline Mat6 isotropic_stiffness(double E, double nu) {
  return stratum::isotropic_stiffness(E, nu);
}

/// The von Mises model for the shared integrators.
class VonMisesModel final : public plasticity::Model {
public:
  explicit VonMisesModel(const Constants& c) : c_(c), D_(isotropic_stiffness(c.E, c.nu)) {}

  [[nodiscard]] const Constants& constants() const { return c_; }

  [[nodiscard]] int internal_size() const override { return 1; }

  [[nodiscard]] Mat6 elastic(const Vec6& /*sigma*/, std::span<const double> /*q*/) const override {
    return D_;
  }

  [[nodiscard]] double yield(int /*k*/, const Vec6& sigma, std::span<const double> q) const override {
    return plasticity::q_mises(sigma) - strength(q);
  }

  /// n = (3 / (2 q_eq)) M s with s the deviator and M = diag(1, 1, 1, 2, 2, 2) (Voigt gradient:
  /// shear entries are twice the tensor derivative). Zero on the hydrostatic axis.
  [[nodiscard]] Vec6 yield_gradient(int /*k*/, const Vec6& sigma,
                                    std::span<const double> /*q*/) const override {
    const double qe = plasticity::q_mises(sigma);
    if (!(qe > 0.0)) return Vec6::Zero();
    return plasticity::to_strain_like(plasticity::deviator(sigma)) * (1.5 / qe);
  }

  [[nodiscard]] VecX yield_gradient_q(int /*k*/, const Vec6& /*sigma*/,
                                      std::span<const double> /*q*/) const override {
    return VecX::Constant(1, -c_.H);
  }

  [[nodiscard]] Vec6 flow(int k, const Vec6& sigma, std::span<const double> q) const override {
    return yield_gradient(k, sigma, q);
  }

  [[nodiscard]] VecX hardening(int /*k*/, const Vec6& /*sigma*/,
                               std::span<const double> /*q*/) const override {
    return VecX::Ones(1);
  }

  /// d n / d sigma = (3 / (2 q_eq)) M P - n n^T / q_eq, P the deviatoric projector on Voigt
  /// stresses (symmetric: M P is). Zero on the hydrostatic axis.
  [[nodiscard]] Mat6 flow_gradient(int /*k*/, const Vec6& sigma,
                                   std::span<const double> /*q*/) const override {
    const double qe = plasticity::q_mises(sigma);
    if (!(qe > 0.0)) return Mat6::Zero();
    const Vec6 n = plasticity::to_strain_like(plasticity::deviator(sigma)) * (1.5 / qe);
    return (1.5 / qe) * plasticity::deviatoric_projector_strain_like() - (n * n.transpose()) / qe;
  }

  [[nodiscard]] MatX flow_gradient_q(int, const Vec6&, std::span<const double>) const override {
    return MatX::Zero(6, 1);
  }
  [[nodiscard]] MatX hardening_gradient(int, const Vec6&, std::span<const double>) const override {
    return MatX::Zero(1, 6);
  }
  [[nodiscard]] MatX hardening_gradient_q(int, const Vec6&, std::span<const double>) const override {
    return MatX::Zero(1, 1);
  }

  [[nodiscard]] bool admissible(const Vec6& sigma, std::span<const double> q) const override {
    return sigma.allFinite() && std::isfinite(q[0]) && q[0] >= 0.0;
  }

  /// The current yield stress sigma_y + H eps_bar_p.
  [[nodiscard]] double stress_scale(const Vec6& /*sigma*/, std::span<const double> q) const override {
    return strength(q);
  }

  [[nodiscard]] double strength(std::span<const double> q) const { return c_.sigma_y + c_.H * q[0]; }

private:
  Constants c_;
  Mat6 D_;
};

/// The material: history = [eps_bar_p].
class VonMisesMaterial final : public Material {
public:
  VonMisesMaterial(const Constants& c, const plasticity::Settings& s) : model_(c), settings_(s) {}

  [[nodiscard]] int history_size() const override { return 1; }
  [[nodiscard]] std::vector<std::string> history_names() const override {
    return stratum::history_names({{"eps_bar_p", "-"}});
  }
  [[nodiscard]] bool symmetric_tangent() const override { return true; } // associated flow
  /// 0 elastic (inside the yield surface), 1 on the yield surface: q = sigma_y + H eps_bar_p
  /// within a relative 1e-6 (the closest-point return lands on it; the explicit schemes to
  /// their ftol/stol drift).
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> h) const override {
    const double q[1] = {h.empty() ? 0.0 : h[0]};
    return model_.yield(0, stress, q) >= -1e-6 * model_.strength(q) ? 1 : 0;
  }
  [[nodiscard]] std::vector<std::string> status_names() const override {
    return {"elastic", "on the yield surface"};
  }
  [[nodiscard]] const VonMisesModel& model() const { return model_; }
  [[nodiscard]] const plasticity::Settings& settings() const { return settings_; }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    double q[1] = {in.history_n.empty() ? 0.0 : in.history_n[0]};
    const plasticity::Result r = plasticity::integrate(model_, settings_, in.stress_n, in.dstrain, out.stress,
                                                       q, out.tangent, nullptr, in.want_tangent);
    if (!out.history.empty()) out.history[0] = q[0];
    if (r.outcome.ok()) return r.outcome;
    return Outcome::failure(r.outcome.status, "von_mises (element " + std::to_string(in.where.element) +
                                                  ", point " + std::to_string(in.where.point) +
                                                  "): " + r.outcome.message);
  }

private:
  VonMisesModel model_;
  plasticity::Settings settings_;
};

/// The parameters of the "von_mises" material, each declared once and bound to its member of
/// Constants: TOML -> schema check -> Constants -> strength().
[[nodiscard]] inline Declared<Constants> declaration() {
  Declared<Constants> d;
  declare_isotropic_elastic(d, &Constants::E, &Constants::nu);
  d.real(&Constants::sigma_y, "sigma_y", "kPa",
         "initial uniaxial yield stress (sqrt(3) times the shear strength)")
      .greater_than(0.0);
  d.real(&Constants::H, "H", "kPa",
         "linear isotropic hardening modulus d sigma_y / d eps_bar_p (0: perfectly plastic)")
      .at_least(0.0)
      .defaults_to(0.0);
  plasticity::add_integrator_parameters(d.schema(), plasticity::Scheme::closest_point);
  return d;
}

/// The parameter schema of the "von_mises" material.
[[nodiscard]] inline Schema schema() { return declaration().schema(); }

/// The material from validated parameters.
[[nodiscard]] inline std::unique_ptr<Material> create(const Params& p) {
  return std::make_unique<VonMisesMaterial>(declaration().read(p), plasticity::read_integrator_parameters(p));
}

} // namespace stratum::von_mises
