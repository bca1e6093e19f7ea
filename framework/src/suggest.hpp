// "Did you mean": the closest of a list of allowed names to a misspelt one, for the one-line
// error messages of the scene reader, the plugin catalog and the command line.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace stratum {

/// Optimal-string-alignment (restricted Damerau-Levenshtein) distance: insertions, deletions,
/// substitutions and transpositions of neighbours cost 1 each; letters compare case-insensitively.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate nearest to `name`, if it is near enough to be a likely misspelling: at most 2
/// edits and at most a third of the longer name's length (at least 1 edit allowed); ties go to the
/// first candidate. Empty when none qualifies or `name` itself is a candidate.
std::string closest_name(std::string_view name, const std::vector<std::string_view>& candidates);

/// "; did you mean 'x'?" for the closest candidate, or "" when none is close: appended to an
/// "unknown ...; allowed: ..." message.
std::string did_you_mean(std::string_view name, const std::vector<std::string_view>& candidates);

/// The same for any range of names: strings, string views, or a map keyed by name.
template <class Range>
requires(!std::is_convertible_v<const Range&, const std::vector<std::string_view>&>) std::string
    did_you_mean(std::string_view name, const Range& names) {
  std::vector<std::string_view> v;
  for (const auto& n : names) {
    if constexpr (requires { n.first; })
      v.emplace_back(n.first);
    else
      v.emplace_back(n);
  }
  return did_you_mean(name, v);
}

/// The keys of a map keyed by name, comma-separated ("(none)" when empty), for "known: ..." in
/// messages; with `name`, followed by did_you_mean(name, ...).
template <class Map> std::string key_list(const Map& m, std::string_view name = {}) {
  std::string s;
  for (const auto& [k, v] : m) s += (s.empty() ? "" : ", ") + k;
  return (s.empty() ? "(none)" : s) + (name.empty() ? "" : did_you_mean(name, m));
}

/// A number for a message: up to ten significant digits, no trailing zeros ("%.10g").
[[nodiscard]] inline std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

/// Names, comma-separated, for "allowed: ..." in messages.
[[nodiscard]] inline std::string name_list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

} // namespace stratum
