// `stratum run` and `stratum check` (framework/cli/run_command.cpp).
#pragma once

#include <string>
#include <vector>

namespace stratum::cli {

[[nodiscard]] std::string run_help();
[[nodiscard]] std::string check_help();

/// `stratum run SCENE.toml [options]`, or `stratum check SCENE.toml [--quiet]` when check_only;
/// returns the exit status (README.md, "Exit codes").
int run(const std::vector<std::string>& args, bool check_only);

} // namespace stratum::cli
