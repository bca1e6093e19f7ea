// `stratum plugins` and `stratum describe`: what is installed and what a scene may say
// (framework/cli/info.cpp).
#pragma once

#include <string>
#include <vector>

namespace stratum::cli {

[[nodiscard]] std::string plugins_help();
[[nodiscard]] std::string describe_help();

/// `stratum plugins [--describe [NAME] | --all | --paths] [--scene FILE]`.
int plugins(std::vector<std::string> args);

/// `stratum describe [SECTION | --markdown]`: the scene format's sections and keys.
int describe_scene(const std::vector<std::string>& args);

} // namespace stratum::cli
