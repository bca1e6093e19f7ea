// Parameter studies: TOML paths into the base scene and the study file's typed readers
// (sweep_toml.hpp).
#include "sweep_toml.hpp"

#include "scene/toml_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace stratum::sweep::detail {

using io::location;

namespace {

// ---------------------------------------------------------------- TOML paths of the base scene

struct Segment {
  std::string key;
  std::vector<std::size_t> index;
};

std::vector<Segment> parse_path(const std::string& path) {
  std::vector<Segment> segs;
  std::size_t i = 0;
  auto fail = [&](const std::string& what) {
    throw PathError{"'" + path + "' is not a path (" + what +
                    "); write keys joined by dots with optional [index], e.g. materials.soil.K[0]"};
  };
  while (true) {
    Segment s;
    while (i < path.size() &&
           (std::isalnum(static_cast<unsigned char>(path[i])) || path[i] == '_' || path[i] == '-'))
      s.key += path[i++];
    if (s.key.empty()) fail("an empty key at character " + std::to_string(i + 1));
    while (i < path.size() && path[i] == '[') {
      std::size_t j = ++i, n = 0;
      while (i < path.size() && std::isdigit(static_cast<unsigned char>(path[i])))
        n = 10 * n + static_cast<std::size_t>(path[i++] - '0');
      if (i == j || i >= path.size() || path[i] != ']')
        fail("a bad [index] at character " + std::to_string(j));
      ++i;
      s.index.push_back(n);
    }
    segs.push_back(std::move(s));
    if (i == path.size()) break;
    if (path[i] != '.') fail("'" + std::string(1, path[i]) + "' at character " + std::to_string(i + 1));
    ++i;
  }
  return segs;
}

std::string keys_of(const toml::table& t) {
  std::string k;
  for (auto&& [key, v] : t) k += (k.empty() ? "" : ", ") + std::string(key.str());
  return k.empty() ? "(none)" : k;
}

/// Follows one segment's key from `cur` (a table, or an array of tables addressed by `name`).
toml::node* step_key(toml::node& cur, const std::string& key, const std::string& done) {
  if (auto* t = cur.as_table()) {
    if (auto* n = t->get(key)) return n;
    throw PathError{"no key '" + key + "' in " + (done.empty() ? "the top level" : "[" + done + "]") +
                    "; keys: " + keys_of(*t)};
  }
  if (auto* a = cur.as_array(); a && a->is_array_of_tables()) {
    std::string names;
    for (auto& e : *a) {
      const auto* name = e.as_table()->get("name");
      if (name && name->is_string()) {
        if (name->as_string()->get() == key) return &e;
        names += (names.empty() ? "" : ", ") + name->as_string()->get();
      }
    }
    throw PathError{"no entry named '" + key + "' in [[" + done +
                    "]]; names: " + (names.empty() ? "(none: address entries by [index])" : names)};
  }
  throw PathError{"'" + done + "' is " + io::type_name(cur) + ", it has no key '" + key + "'"};
}

toml::node* step_index(toml::node& cur, std::size_t i, const std::string& done) {
  auto* a = cur.as_array();
  if (!a) throw PathError{"'" + done + "' is " + io::type_name(cur) + ", not an array"};
  if (i >= a->size())
    throw PathError{"index " + std::to_string(i) + " is beyond '" + done + "' (" + std::to_string(a->size()) +
                    " entries)"};
  return a->get(i);
}

/// The node a path names.
toml::node& walk(toml::table& root, const std::vector<Segment>& segs) {
  toml::node* cur = &root;
  std::string done;
  for (const auto& s : segs) {
    cur = step_key(*cur, s.key, done);
    done += (done.empty() ? "" : ".") + s.key;
    for (auto i : s.index) {
      cur = step_index(*cur, i, done);
      done += "[" + std::to_string(i) + "]";
    }
  }
  return *cur;
}

/// The numbers a parameter path names: one number, or every element of an array of numbers.

} // namespace

std::vector<toml::node*> number_leaves(toml::table& root, const std::string& path) {
  toml::node& n = walk(root, parse_path(path));
  if (n.is_number()) return {&n};
  if (auto* a = n.as_array(); a && !a->empty()) {
    std::vector<toml::node*> out;
    for (auto& e : *a) {
      if (!e.is_number()) break;
      out.push_back(&e);
    }
    if (out.size() == a->size()) return out;
  }
  throw PathError{"it is " + io::show(n) + " in the base file, not a number or an array of numbers"};
}

void set_number(toml::node& leaf, double v) {
  if (auto* i = leaf.as_integer())
    i->get() = std::llround(v);
  else
    leaf.as_floating_point()->get() = v;
}

double number_of(const toml::node& leaf) { return io::number(leaf); }

/// Sets a path to a copy of `value` (any TOML value); the last key may be new.
void assign(toml::table& root, const std::string& path, const toml::node& value) {
  auto segs = parse_path(path);
  Segment last = segs.back();
  segs.pop_back();
  toml::node* parent = segs.empty() ? static_cast<toml::node*>(&root) : &walk(root, segs);
  std::string done = path.substr(0, path.size() - last.key.size());
  if (!last.index.empty()) {
    parent = step_key(*parent, last.key, done);
    for (std::size_t k = 0; k + 1 < last.index.size(); ++k) parent = step_index(*parent, last.index[k], path);
    auto* a = parent->as_array();
    step_index(*parent, last.index.back(), path); // checks the range
    value.visit(
        [&](const auto& v) { a->replace(a->cbegin() + static_cast<std::ptrdiff_t>(last.index.back()), v); });
    return;
  }
  if (auto* a = parent->as_array(); a && a->is_array_of_tables()) { // a named entry replaced whole
    step_key(*parent, last.key, done);
    throw PathError{"'" + path + "' names a whole [[...]] entry; set its keys instead"};
  }
  auto* t = parent->as_table();
  if (!t) throw PathError{"'" + path + "': its parent is " + io::type_name(*parent) + ", not a table"};
  value.visit([&](const auto& v) { t->insert_or_assign(last.key, v); });
}

// ---------------------------------------------------------------- reading the study file

std::string context_of(const std::string& table, int index) {
  return index < 0 ? "[" + table + "]" : "[[" + table + "]] " + std::to_string(index + 1);
}

void only_keys(const toml::table& t, const std::vector<std::string>& allowed, const std::string& ctx) {
  for (auto&& [key, v] : t) {
    if (std::find(allowed.begin(), allowed.end(), std::string(key.str())) != allowed.end()) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw Error(location(key.source()),
                ctx + " unknown key '" + std::string(key.str()) + "'; allowed: " + list);
  }
}

const toml::table* table_of(const toml::table& root, const std::string& key) {
  const auto* n = root.get(key);
  if (!n) return nullptr;
  if (!n->is_table()) throw Error(location(*n), "'" + key + "' must be a table [" + key + "]");
  return n->as_table();
}

std::vector<const toml::table*> tables_of(const toml::table& root, const std::string& key) {
  std::vector<const toml::table*> out;
  const auto* n = root.get(key);
  if (!n) return out;
  const auto* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    throw Error(location(*n), "'" + key + "' must be an array of tables [[" + key + "]]");
  for (const auto& e : *a) out.push_back(e.as_table());
  return out;
}

std::optional<double> number(const toml::table& t, const std::string& key, const std::string& ctx) {
  const auto* n = t.get(key);
  if (!n) return std::nullopt;
  if (!n->is_number() || !std::isfinite(io::number(*n)))
    throw Error(location(*n), ctx + " " + key + " = " + io::show(*n) + " must be a finite number");
  return io::number(*n);
}

double need_number(const toml::table& t, const std::string& key, const std::string& ctx,
                   const std::string& why) {
  auto v = number(t, key, ctx);
  if (!v) throw Error(location(t), ctx + " needs " + key + " (" + why + ")");
  return *v;
}

std::vector<double> numbers(const toml::table& t, const std::string& key, const std::string& ctx) {
  const auto* n = t.get(key);
  if (!n) return {};
  if (n->is_number()) return {*number(t, key, ctx)};
  const auto* a = n->as_array();
  std::vector<double> out;
  if (a)
    for (const auto& e : *a)
      if (e.is_number() && std::isfinite(io::number(e))) out.push_back(io::number(e));
  if (!a || a->empty() || out.size() != a->size())
    throw Error(location(*n),
                ctx + " " + key + " = " + io::show(*n) + " must be a number or a non-empty array of numbers");
  return out;
}

std::string text(const toml::table& t, const std::string& key, const std::string& ctx,
                 const std::vector<std::string>& choices, std::string fallback) {
  const auto* n = t.get(key);
  if (!n) {
    if (fallback.empty()) throw Error(location(t), ctx + " needs " + key);
    return fallback;
  }
  if (!n->is_string())
    throw Error(location(*n), ctx + " " + key + " = " + io::show(*n) + " must be a string");
  std::string v = n->as_string()->get();
  if (!choices.empty() && std::find(choices.begin(), choices.end(), v) == choices.end()) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    throw Error(location(*n), ctx + " " + key + " = \"" + v + "\" is not allowed; allowed: " + list);
  }
  return v;
}

} // namespace stratum::sweep::detail
