// Parsing TOML input files with `include` (toml_check.hpp, parse_with_includes).
//
// Values are moved, never copied, from the included tables into the result: toml++ keeps a
// node's source position on a move and drops it on a copy, and every later message needs it.
#include "files.hpp"
#include "scene/toml_check.hpp"

#include "stratum/error.hpp"

#include <filesystem>

namespace fs = std::filesystem;

namespace stratum::io {

namespace {

toml::table parse_text(const std::string& text, const std::string& path) {
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw Error(location(e.source()), "malformed TOML: " + std::string(e.description()));
  }
}

std::string where(const toml::node& n) {
  const SourceLocation l = location(n);
  return l.file + ":" + std::to_string(l.line) + ":" + std::to_string(l.column);
}

/// Moves every value of `src` into `dst`. `src_wins`: a value in both is taken from `src` (the
/// including file over its includes); otherwise it is an error (two includes).
void merge(toml::table& dst, toml::table&& src, bool src_wins, const std::string& context) {
  for (auto&& [src_key, value] : src) {
    const toml::key key = src_key; // with its source position; a lambda cannot capture a binding (clang 14)
    const std::string name =
        context.empty() ? std::string(key.str()) : context + "." + std::string(key.str());
    toml::node* old = dst.get(key.str());
    if (!old) {
      value.visit([&](auto&& v) { dst.insert(key, std::move(v)); });
      continue;
    }
    if (old->is_table() && value.is_table()) {
      merge(*old->as_table(), std::move(*value.as_table()), src_wins, name);
      continue;
    }
    const bool tables_array = (old->is_array_of_tables() || value.is_array_of_tables());
    if (!src_wins || tables_array)
      throw Error(location(value),
                  "'" + name + "' is set here and at " + where(*old) +
                      (tables_array ? " (an array of tables, [[" + name + "]], is written in one file only)"
                                    : " (two included files may not set the same value)"));
    value.visit([&](auto&& v) { dst.insert_or_assign(key, std::move(v)); });
  }
}

/// The name that tells two paths of one file apart from two files (a cycle of includes).
std::string canonical_name(const fs::path& p) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal().string() : c.string();
}

/// How deep includes may nest (the scene is depth 0), and how many included files one scene may
/// read in all: a chain of thousands of includes would overflow the stack, and a file included
/// twice at every level would be read 2^depth times.
constexpr std::size_t max_include_depth = 32, max_included_files = 1024;

/// The includes read so far: the chain from the scene to the file being read (canonical paths,
/// for cycles and the depth) and how many files were read in all.
struct IncludeState {
  std::vector<std::string> chain;
  std::size_t files_read = 0;
};

toml::table resolve(toml::table root, const std::string& path, IncludeState& state) {
  std::vector<std::string>& chain = state.chain;
  const toml::node* inc = root.get("include");
  if (!inc) return root;
  std::vector<const toml::node*> files;
  if (inc->is_string()) {
    files.push_back(inc);
  } else if (const auto* a = inc->as_array(); a && !a->empty()) {
    for (const auto& e : *a) {
      if (!e.is_string())
        throw Error(location(e), "include entries must be file names (strings), found " + show(e));
      files.push_back(&e);
    }
  } else {
    throw Error(location(*inc), "include = " + show(*inc) +
                                    "; allowed: a file name or a non-empty array of file names, e.g. "
                                    "include = \"../materials/loess.toml\"");
  }
  toml::table merged;
  const fs::path base = fs::path(path).parent_path();
  for (const toml::node* f : files) {
    const std::string name = f->as_string()->get();
    const fs::path file = fs::path(name).is_absolute() ? fs::path(name) : base / name;
    const std::string key = canonical_name(file);
    for (const auto& c : chain)
      if (c == key) throw Error(location(*f), "include '" + name + "' includes itself (a cycle of includes)");
    if (chain.size() > max_include_depth)
      throw Error(location(*f), "include '" + name + "' would be at depth " + std::to_string(chain.size()) +
                                    " of a chain of includes (the scene is depth 0); includes nest at most " +
                                    std::to_string(max_include_depth) + " deep");
    if (++state.files_read > max_included_files)
      throw Error(location(*f), "include '" + name + "': more than " + std::to_string(max_included_files) +
                                    " included files in one scene (counting a file as often as it is "
                                    "included); at most " +
                                    std::to_string(max_included_files) + " are read");
    const std::string text = read_text_file(file.string(), location(*f), "included file", file_limits::scene);
    chain.push_back(key);
    toml::table child = resolve(parse_text(text, file.string()), file.string(), state);
    chain.pop_back();
    merge(merged, std::move(child), false, "");
  }
  root.erase("include");
  merge(merged, std::move(root), true, "");
  return merged;
}

} // namespace

toml::table parse_with_includes(const std::string& text, const std::string& path) {
  IncludeState state;
  state.chain.push_back(canonical_name(fs::path(path)));
  return resolve(parse_text(text, path), path, state);
}

} // namespace stratum::io
