// `stratum point` (framework/cli/point_command.cpp).
#pragma once

#include <string>
#include <vector>

namespace stratum::cli {

[[nodiscard]] std::string point_help();

/// `stratum point POINT.toml [--out FILE.csv]`: one material point along the file's paths.
int point(const std::vector<std::string>& args);

} // namespace stratum::cli
