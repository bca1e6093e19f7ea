// The material of a displacement-only domain with drainage = "undrained" (docs/groundwater.md,
// "Drainage of displacement domains"): any soil model for the effective stress, plus a pore fluid
// that no water leaves. The excess pore pressure of a point grows with its volumetric compression,
//   p = p_n - K_f (eps_v - eps_v,n),   K_f = K_w / n (the fluid's bulk modulus over the porosity),
// and the point carries the total stress sigma = sigma' - p m (m = (1, 1, 1, 0, 0, 0)); the tangent
// is the skeleton's plus K_f m m^T. PLAXIS calls this "Undrained (A)": effective-stress
// parameters, the fluid's stiffness added. The point's stress (what the framework stores and
// writes) is the total stress; its history is [p, the skeleton's history], so that the output
// shows p as the point field "p_excess [kPa]".
#pragma once

#include "stratum/material.hpp"

#include <span>
#include <string>
#include <vector>

namespace stratum {

class UndrainedMaterial final : public Material {
public:
  UndrainedMaterial(const Material& skeleton, double fluid_stiffness) : s_(skeleton), kf_(fluid_stiffness) {}

  [[nodiscard]] int history_size() const override { return 1 + s_.history_size(); }
  /// The initial stress is effective (geostatic stresses are): no excess pressure yet.
  void init_history(const Vec6& stress, std::span<double> history) const override {
    history[0] = 0.0;
    s_.init_history(stress, history.subspan(1));
  }
  [[nodiscard]] bool is_linear() const override { return s_.is_linear(); }
  [[nodiscard]] bool symmetric_tangent() const override { return s_.symmetric_tangent(); }
  [[nodiscard]] int point_status(const Vec6& stress, std::span<const double> history) const override {
    return s_.point_status(effective(stress, history[0]), history.subspan(1));
  }
  [[nodiscard]] std::vector<std::string> status_names() const override { return s_.status_names(); }
  [[nodiscard]] int decision_slot() const override {
    const int slot = s_.decision_slot();
    return slot < 0 ? slot : slot + 1;
  }
  [[nodiscard]] double step_error(std::span<const double> trial_history) const override {
    return s_.step_error(trial_history.subspan(1));
  }
  [[nodiscard]] std::vector<std::string> history_names() const override {
    std::vector<std::string> names{"p_excess [kPa]"};
    for (auto& n : s_.history_names()) names.push_back(std::move(n));
    return names;
  }

  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    const double p_n = in.history_n[0];
    const Vec6 stress_n = effective(in.stress_n, p_n);
    const MaterialInput skeleton_in{stress_n,   in.strain_n, in.history_n.subspan(1),
                                    in.dstrain, in.where,    in.want_tangent};
    MaterialOutput skeleton_out{out.stress, out.history.subspan(1), out.tangent};
    if (Outcome o = s_.update(skeleton_in, skeleton_out); !o.ok()) return o;
    const double p = p_n - kf_ * (in.dstrain[0] + in.dstrain[1] + in.dstrain[2]);
    out.history[0] = p;
    for (int i = 0; i < 3; ++i) out.stress[i] -= p;
    if (in.want_tangent) out.tangent.topLeftCorner<3, 3>().array() += kf_;
    return Outcome::success();
  }

private:
  /// The effective stress of a point that carries the total stress `total` and the pressure p.
  [[nodiscard]] static Vec6 effective(const Vec6& total, double p) {
    Vec6 s = total;
    for (int i = 0; i < 3; ++i) s[i] += p;
    return s;
  }

  const Material& s_;
  double kf_;
};

} // namespace stratum
