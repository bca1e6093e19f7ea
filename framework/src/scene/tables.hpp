// Getting at the scene's tables, with file:line:col in every message.
#pragma once

#include "stratum/error.hpp"
#include "stratum/units.hpp"

#include <toml++/toml.h>

#include <string>
#include <string_view>
#include <vector>

namespace stratum::scene {

/// The required table [key] of `root`.
[[nodiscard]] const toml::table& table_at(const toml::table& root, std::string_view key,
                                          const std::string& ctx);
/// The table [key] of `root`, or an empty table when it is absent.
[[nodiscard]] const toml::table& optional_table(const toml::table& root, std::string_view key);
/// The [units] table of `root` (kN, m when absent), checked; located errors (scene/read_scene.cpp).
[[nodiscard]] Units read_units(const toml::table& root);
/// Checks a name the output uses as (part of) a file name: stages (checkpoints), recorders
/// (history/<name>.csv), interfaces (their curves). Letters, digits, '_', '-', '.' and '+', at most
/// 64 characters, not starting with '.'; otherwise a located Error "ctx key = "...": ...".
void require_file_name(const std::string& value, const SourceLocation& at, const std::string& ctx,
                       std::string_view key);
/// Array of tables [[key]] (absent = empty).
[[nodiscard]] std::vector<const toml::table*> table_list(const toml::table& root, std::string_view key);

} // namespace stratum::scene
