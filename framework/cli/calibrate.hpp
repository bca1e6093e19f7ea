// `stratum calibrate`: back-analysis of a scene against measured curves, on one process or under
// mpirun/srun (framework/cli/calibrate.cpp).
#pragma once

#include <string>
#include <vector>

namespace stratum::cli {

/// The text of `stratum calibrate --help`: usage, options and exit codes.
const char* calibrate_help();

/// Runs `stratum calibrate STUDY.toml [--out DIR] [--print-scene]`; throws stratum::Error on bad
/// input (rank 0).
int calibrate(const std::vector<std::string>& args);

} // namespace stratum::cli
