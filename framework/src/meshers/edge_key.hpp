// The key of an undirected mesh edge for hash maps (internal to the meshers): the two node
// numbers, the larger in the upper half, so (a, b) and (b, a) meet.
#pragma once

#include <algorithm>
#include <cstdint>

namespace stratum {

[[nodiscard]] inline std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (hi << 32) | lo;
}

} // namespace stratum
