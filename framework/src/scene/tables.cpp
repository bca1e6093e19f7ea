#include "scene/tables.hpp"

#include "scene/toml_check.hpp"

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

} // namespace stratum::scene
