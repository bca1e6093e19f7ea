// `stratum sweep`: parameter studies, on one process or under mpirun/srun (framework/cli/sweep.cpp).
#pragma once

#include <string>
#include <vector>

namespace stratum::cli {

/// The text of `stratum sweep --help`: usage, options and exit codes.
const char* sweep_help();

/// Runs `stratum sweep STUDY.toml [--out DIR]`; throws stratum::Error on bad input (rank 0).
int sweep(const std::vector<std::string>& args);

} // namespace stratum::cli
