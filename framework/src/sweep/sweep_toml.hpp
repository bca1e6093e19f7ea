// Parameter studies, internal: the TOML paths that address a value of the base scene
// ("materials.soil.K[0]") and the typed readers of the study file's tables, with located errors.
#pragma once

#include "stratum/error.hpp"

#include <toml++/toml.h>

#include <optional>
#include <string>
#include <vector>

namespace stratum::sweep::detail {

/// A path that does not name a value of the scene; the message says what is wrong.
struct PathError {
  std::string message;
};

/// The numbers a path names (one, or every element of an array); throws PathError.
std::vector<toml::node*> number_leaves(toml::table& root, const std::string& path);
void set_number(toml::node& leaf, double v);
double number_of(const toml::node& leaf);
/// Replaces (or inserts) the value at `path`; throws PathError.
void assign(toml::table& root, const std::string& path, const toml::node& value);

std::string context_of(const std::string& table, int index = -1);
void only_keys(const toml::table& t, const std::vector<std::string>& allowed, const std::string& ctx);
const toml::table* table_of(const toml::table& root, const std::string& key);
std::vector<const toml::table*> tables_of(const toml::table& root, const std::string& key);
std::optional<double> number(const toml::table& t, const std::string& key, const std::string& ctx);
double need_number(const toml::table& t, const std::string& key, const std::string& ctx,
                   const std::string& why);
std::vector<double> numbers(const toml::table& t, const std::string& key, const std::string& ctx);
std::string text(const toml::table& t, const std::string& key, const std::string& ctx,
                 const std::vector<std::string>& choices = {}, std::string fallback = {});

} // namespace stratum::sweep::detail
