// `stratum fit`: the calibration subcommand (framework/cli/fit.cpp).
#pragma once

#include <string>
#include <vector>

namespace stratum::cli {

/// The text of `stratum fit --help`: usage, the targets on the plugin path with their options
/// (their libraries are opened), the common options and exit codes.
std::string fit_help();

/// Runs `stratum fit TARGET FILES... [options]`; throws stratum::Error on bad input.
int fit(const std::vector<std::string>& args);

} // namespace stratum::cli
