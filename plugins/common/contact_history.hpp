// How the contact laws of this project (coulomb_elastoplastic, goodman_nonlinear,
// hyperbolic_interface) keep their history: plain numbers in the slots the framework owns, the
// point's ContactState among them as a number.
#pragma once

#include "stratum/contact_law.hpp"

#include <algorithm>
#include <initializer_list>
#include <span>

namespace stratum::contact_history {

/// Writes `values` into the history slots 0, 1, ... in order.
inline void store(std::span<double> history, std::initializer_list<double> values) {
  std::copy(values.begin(), values.end(), history.begin());
}

/// The ContactState stored as a number in a history slot (rounded to the nearest state).
[[nodiscard]] inline ContactState state(double stored) {
  return static_cast<ContactState>(static_cast<int>(stored + 0.5));
}

} // namespace stratum::contact_history
