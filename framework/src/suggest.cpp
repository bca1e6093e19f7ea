#include "suggest.hpp"

#include <algorithm>
#include <cctype>

namespace stratum {

namespace {

char lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

} // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  // d[i][j]: distance between the first i letters of a and the first j of b (rows i-2, i-1, i).
  std::vector<std::size_t> prev2(m + 1), prev(m + 1), cur(m + 1);
  for (std::size_t j = 0; j <= m; ++j) prev[j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1]))
        cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[m];
}

std::string closest_name(std::string_view name, const std::vector<std::string_view>& candidates) {
  if (std::find(candidates.begin(), candidates.end(), name) != candidates.end()) return {};
  std::string_view best;
  std::size_t best_d = 0;
  for (auto c : candidates) {
    const std::size_t d = edit_distance(name, c);
    const std::size_t limit =
        std::max<std::size_t>(1, std::min<std::size_t>(2, std::max(name.size(), c.size()) / 3));
    if (d <= limit && (best.empty() || d < best_d)) {
      best = c;
      best_d = d;
    }
  }
  return std::string(best);
}

std::string did_you_mean(std::string_view name, const std::vector<std::string_view>& candidates) {
  const std::string c = closest_name(name, candidates);
  return c.empty() ? std::string() : "; did you mean '" + c + "'?";
}

} // namespace stratum
