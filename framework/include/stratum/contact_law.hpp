// The ContactLaw interface: the traction-relative displacement law of one
// interface point. Same shape as Material: parameters only, const update,
// history owned by the framework, failures returned as values.
//
// Components: 0 = shear (tangential slip), 1 = normal (opening positive).
// Tractions in kPa, relative displacements in m; normal traction tension positive.
#pragma once

#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/voigt.hpp"

#include <span>

namespace stratum {

struct ContactInput {
  const Vec2& traction_n;
  const Vec2& jump_n; ///< relative displacement at t_n
  std::span<const double> history_n;
  const Vec2& djump; ///< relative displacement increment
  PointContext where;
};

struct ContactOutput {
  Vec2& traction;
  std::span<double> history;
  Mat2& tangent;
};

/// Point status reported for output.
enum class ContactState { stick = 0, slip = 1, open = 2 };

class ContactLaw {
public:
  virtual ~ContactLaw() = default;
  [[nodiscard]] virtual int history_size() const { return 0; }
  virtual void init_history(std::span<double> history) const {
    for (double& h : history) h = 0.0;
  }
  [[nodiscard]] virtual bool symmetric_tangent() const { return true; }
  [[nodiscard]] virtual Outcome update(const ContactInput& in, ContactOutput& out) const = 0;
  /// The state of a point from its (trial or committed) history and traction.
  [[nodiscard]] virtual ContactState state(const Vec2& /*traction*/,
                                           std::span<const double> /*history*/) const {
    return ContactState::stick;
  }
};

} // namespace stratum
