// The names of an enumeration's values, as one array in the order of the enumeration: one line
// per enumeration instead of a switch per enumeration.
//
//   constexpr std::array<const char*, 3> names{"red", "green", "blue"};
//   const char* name = enum_name(Colour::green, names); // "green"
#pragma once

#include <array>
#include <cstddef>

namespace stratum {

/// The name of `value` in `names` (indexed by the value's number), `otherwise` past the end.
template <class Enum, std::size_t N>
[[nodiscard]] constexpr const char* enum_name(Enum value, const std::array<const char*, N>& names,
                                              const char* otherwise = "?") {
  const auto i = static_cast<std::size_t>(value);
  return i < N ? names[i] : otherwise;
}

} // namespace stratum
