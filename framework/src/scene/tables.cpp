#include "scene/tables.hpp"

#include "scene/toml_check.hpp"

#include <algorithm>

namespace stratum::scene {

using io::location;

const toml::table& table_at(const toml::table& root, std::string_view key, const std::string& ctx) {
  const toml::node* n = root.get(key);
  if (!n) throw Error(location(root), ctx + " missing required table [" + std::string(key) + "]");
  if (!n->is_table())
    throw Error(location(*n), ctx + " " + std::string(key) + " must be a table, got " + io::type_name(*n));
  return *n->as_table();
}

namespace {
const toml::table empty_table;
} // namespace

const toml::table& optional_table(const toml::table& root, std::string_view key) {
  const toml::node* n = root.get(key);
  if (!n) return empty_table;
  if (!n->is_table())
    throw Error(location(*n), std::string(key) + " must be a table, got " + io::type_name(*n));
  return *n->as_table();
}
std::vector<const toml::table*> table_list(const toml::table& root, std::string_view key) {
  std::vector<const toml::table*> v;
  const toml::node* n = root.get(key);
  if (!n) return v;
  const auto* a = n->as_array();
  if (!a)
    throw Error(location(*n), std::string(key) + " must be an array of tables [[" + std::string(key) + "]]");
  for (const auto& e : *a) {
    if (!e.is_table())
      throw Error(location(e), std::string(key) + " entries must be tables [[" + std::string(key) + "]]");
    v.push_back(e.as_table());
  }
  return v;
}

void require_file_name(const std::string& value, const SourceLocation& at, const std::string& ctx,
                       std::string_view key) {
  constexpr std::size_t longest = 64;
  const auto plain = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.' || c == '+';
  };
  std::string why;
  if (value.empty())
    why = "is empty";
  else if (value.size() > longest)
    why = "is " + std::to_string(value.size()) + " characters long";
  else if (value.front() == '.')
    why = "starts with '.'";
  else if (const auto bad = std::find_if_not(value.begin(), value.end(), plain); bad != value.end())
    why = *bad == '/' || *bad == '\\'               ? "contains a path separator"
          : static_cast<unsigned char>(*bad) < 0x20 ? "contains a control character"
                                                    : std::string("contains '") + *bad + "'";
  if (why.empty()) return;
  std::string shown;
  for (char c : value.substr(0, longest)) shown += static_cast<unsigned char>(c) < 0x20 ? '?' : c;
  throw Error(at, ctx + " " + std::string(key) + " = \"" + shown + (value.size() > longest ? "..." : "") +
                      "\" " + why +
                      "; the output names files after it, so it may use letters, digits, '_', '-', '.' "
                      "and '+' (at most 64, not starting with '.')");
}

} // namespace stratum::scene
