// Checking TOML tables against schemas, with file:line:col in every message.
// Internal to the framework (plugins never see TOML).
#pragma once

#include "stratum/params.hpp"
#include "stratum/units.hpp"
#include "suggest.hpp"

#include <toml++/toml.h>

#include <string>
#include <string_view>
#include <vector>

namespace stratum::io {

/// Parses a scene (or study, or point) file: malformed TOML is a located error, and a top-level
/// `include = "file.toml"` or `include = ["a.toml", "b.toml"]` (paths relative to the including
/// file) merges those files' tables first, then this file's on top (toml_include.cpp):
/// - tables merge key by key, at any depth ([materials.soil] from one file, [materials.pile]
///   from another);
/// - a value this file sets replaces the included one (one parameter changed for one scene);
/// - the same value in two included files, or an array of tables ([[stages]]) written both in an
///   include and in the including file, is an error naming both places;
/// - includes nest; a cycle is an error. Every value keeps its own file:line:col for messages.
/// File names written as values (a Gmsh mesh, a UMAT library) stay relative to the file that is run.
[[nodiscard]] toml::table parse_with_includes(const std::string& text, const std::string& path);

[[nodiscard]] SourceLocation location(const toml::source_region& r);
[[nodiscard]] SourceLocation location(const toml::node& n);
/// The value as written, for messages: 0.7, "abc", [1, 2], true, {...}.
[[nodiscard]] std::string show(const toml::node& n);
[[nodiscard]] const char* type_name(const toml::node& n);
/// The value of a number node (is_number() must hold) as a double: integers by conversion, also
/// those beyond 2^53 (toml++'s value<double>() gives nothing for an integer it cannot hold exactly).
[[nodiscard]] double number(const toml::node& n);

/// Validates `table` against `schema`: unknown keys (other than `extra`), missing required
/// parameters, wrong types, values out of range or not among the choices. `context` is the
/// table's name as the user wrote it, e.g. "[materials.soil]". Throws Error on the first problem.
/// In a scene whose `units` are not kN, m, kPa, the defaults and the range bounds of dimensional
/// parameters are converted into them (their unit strings say how, stratum/units.hpp); a
/// default whose unit string cannot be read is refused unless it is zero; and the Params carry
/// the units (units_param) for plugins that must refuse them.
[[nodiscard]] Params check_table(const toml::table& table, const Schema& schema, const std::string& context,
                                 const std::vector<std::string_view>& extra = {}, const Units& units = {});

/// Throws a located Error for the first key of `schema` that the scene set in the table of `p`
/// but that the reader did not read (Params::read_names): such a key would be accepted by the
/// schema and then ignored. Call it where the reader is done with `p`.
void require_read(const Params& p, const Schema& schema, const std::string& context);

/// A required string key (for keys outside any schema, like `model = "..."`).
[[nodiscard]] std::string require_string(const toml::table& table, std::string_view key,
                                         const std::string& context);

} // namespace stratum::io
