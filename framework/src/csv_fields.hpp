// Splitting one line of a CSV data file (internal): the readers of laboratory curves
// (calibration/calibration_csv.cpp) and of measured curves (sweep/back_analysis.cpp) locate every
// cell of a bad file by line and column.
#pragma once

#include <string>
#include <vector>

namespace stratum::csv {

/// `s` without leading and trailing blanks, tabs and carriage returns.
[[nodiscard]] inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// The comma-separated fields of `raw`, trimmed, and the 1-based column where each starts (its
/// first non-blank character). No quoting: the data files hold numbers and names.
inline void split_fields(const std::string& raw, std::vector<std::string>& fields, std::vector<int>& starts) {
  fields.clear();
  starts.clear();
  std::size_t pos = 0;
  while (true) {
    const auto comma = raw.find(',', pos);
    const std::string f = raw.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    const auto lead = f.find_first_not_of(" \t");
    starts.push_back(static_cast<int>(pos + (lead == std::string::npos ? 0 : lead)) + 1);
    fields.push_back(trim(f));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
}

} // namespace stratum::csv
