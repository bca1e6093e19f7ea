// Checking TOML tables against schemas, with file:line:col in every message.
// Internal to the framework (plugins never see TOML).
#pragma once

#include "stratum/params.hpp"
#include "stratum/suggest.hpp"

#include <toml++/toml.h>

#include <string>
#include <string_view>
#include <vector>

namespace stratum::io {

[[nodiscard]] SourceLocation location(const toml::source_region& r);
[[nodiscard]] SourceLocation location(const toml::node& n);
/// The value as written, for messages: 0.7, "abc", [1, 2], true, {...}.
[[nodiscard]] std::string show(const toml::node& n);
[[nodiscard]] const char* type_name(const toml::node& n);

/// Validates `table` against `schema`: unknown keys (other than `extra`), missing required
/// parameters, wrong types, values out of range or not among the choices. `context` is the
/// table's name as the user wrote it, e.g. "[materials.soil]". Throws Error on the first problem.
[[nodiscard]] Params check_table(const toml::table& table, const Schema& schema, const std::string& context,
                                 const std::vector<std::string_view>& extra = {});

/// A required string key (for keys outside any schema, like `model = "..."`).
[[nodiscard]] std::string require_string(const toml::table& table, std::string_view key,
                                         const std::string& context);

} // namespace stratum::io
