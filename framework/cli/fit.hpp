// `stratum fit`: the calibration subcommand (framework/cli/fit.cpp).
#pragma once

#include <string>
#include <vector>

namespace stratum::cli {

/// Runs `stratum fit TARGET FILES... [options]`; throws stratum::Error on bad input.
int fit(const std::vector<std::string>& args);

} // namespace stratum::cli
