#include "stratum/plugin_loader.hpp"

#include "files.hpp"
#include "stratum/plugin.hpp"
#include "suggest.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

struct PluginCatalog::Library {
  std::string path;
  void* handle = nullptr;
  ~Library() {
    // RTLD_NODELETE keeps the code mapped: objects created by the plugin may outlive the catalog.
    if (handle) dlclose(handle);
  }
};

namespace {
bool parse_kind(const std::string& s, PluginKind& k) { return plugin_kind_from_string(s, k); }
} // namespace

PluginCatalog::PluginCatalog(std::vector<std::string> directories) : dirs_(std::move(directories)) {
  std::map<std::pair<PluginKind, std::string>, std::string> seen; // first directory wins
  for (const auto& dir : dirs_) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> manifests;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".plugin") manifests.push_back(e.path());
    std::sort(manifests.begin(), manifests.end());
    std::map<std::pair<PluginKind, std::string>, std::string> here;
    for (const auto& m : manifests) {
      fs::path lib = m;
      lib.replace_extension(".so");
      // A manifest is read through the guarded reader: a FIFO or a device named *.plugin in a
      // plugin folder is refused in one line instead of blocking or filling memory.
      std::istringstream in(
          read_text_file(m.string(), SourceLocation{}, "plugin manifest", file_limits::manifest));
      std::string line;
      int lineno = 0;
      while (std::getline(in, line)) {
        ++lineno;
        std::istringstream ls(line);
        std::string kind_s, name;
        if (!(ls >> kind_s)) continue;
        PluginKind kind{};
        if (!(ls >> name) || !parse_kind(kind_s, kind)) {
          std::string kinds;
          for (PluginKind k : all_plugin_kinds)
            kinds += (kinds.empty() ? "" : ", ") + std::string(to_string(k));
          throw Error(SourceLocation{m.string(), lineno, 1},
                      "bad plugin manifest line '" + line + "'; expected '<kind> <name>' with kind one of " +
                          kinds);
        }
        auto key = std::make_pair(kind, name);
        if (auto it = here.find(key); it != here.end()) {
          conflicts_.push_back(std::string("duplicate ") + kind_s + " '" + name + "': provided by " +
                               it->second + " and by " + lib.string());
          continue;
        }
        here[key] = lib.string();
        if (seen.count(key)) continue; // an earlier directory provides it
        seen[key] = lib.string();
        entries_.push_back({kind, name, lib.string()});
      }
    }
  }
}

PluginCatalog::~PluginCatalog() = default;

std::vector<std::string> PluginCatalog::default_directories() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("STRATUM_PLUGIN_PATH")) {
    std::string s = env;
    std::size_t start = 0;
    while (start <= s.size()) {
      auto end = s.find(':', start);
      if (end == std::string::npos) end = s.size();
      if (end > start) dirs.push_back(s.substr(start, end - start));
      start = end + 1;
    }
  }
  // The plugins that belong to the running libstratum: the library of a build tree uses that
  // tree's plugins folder, any other copy (an installed one) the folder beside it. Never both:
  // an installed program that fell back on the build tree would load plugins built from other
  // sources than its own, and a build tree that is rebuilt or deleted would change it.
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&PluginCatalog::default_directories), &info) && info.dli_fname) {
    std::error_code ec;
    fs::path here = fs::absolute(info.dli_fname).parent_path();
    if (fs::path c = fs::weakly_canonical(here, ec); !ec) here = c; // <prefix>/lib, not <prefix>/bin/../lib
    if (fs::equivalent(here, fs::path(STRATUM_BUILD_LIBRARY_DIR), ec))
      dirs.push_back(STRATUM_BUILD_PLUGIN_DIR);
    else
      dirs.push_back((here / "stratum" / "plugins").string());
  }
  return dirs;
}

std::vector<std::string> PluginCatalog::known(PluginKind kind) const {
  std::vector<std::string> v;
  for (const auto& e : entries_)
    if (e.kind == kind) v.push_back(e.name);
  std::sort(v.begin(), v.end());
  return v;
}

std::vector<std::string> PluginCatalog::opened() const {
  std::vector<std::string> v;
  for (const auto& l : libraries_) v.push_back(l->path);
  return v;
}

void PluginCatalog::require(Registry& registry, PluginKind kind, const std::string& name) {
  for (const auto& c : conflicts_)
    if (c.find(std::string(" '") + name + "'") != std::string::npos &&
        c.rfind(std::string("duplicate ") + to_string(kind), 0) == 0)
      throw Error(c);
  if (registry.has(kind, name)) return;
  for (const auto& e : entries_)
    if (e.kind == kind && e.name == name) {
      open(registry, e.library);
      if (!registry.has(kind, name))
        throw Error(e.library + ": its manifest lists " + to_string(kind) + " '" + name +
                    "' but the library did not register it");
      return;
    }
  std::string known_names;
  for (const auto& n : known(kind)) known_names += (known_names.empty() ? "" : ", ") + n;
  std::string dirs;
  for (const auto& d : dirs_) dirs += (dirs.empty() ? "" : ":") + d;
  throw Error(std::string("unknown ") + to_string(kind) + " '" + name +
              "'; known: " + (known_names.empty() ? "(none)" : known_names) + " (plugin path " + dirs + ")" +
              did_you_mean(name, known(kind)));
}

void PluginCatalog::require_all(Registry& registry) {
  if (!conflicts_.empty()) throw Error(conflicts_.front());
  for (const auto& e : entries_) open(registry, e.library);
}

void PluginCatalog::open(Registry& registry, const std::string& path) {
  for (const auto& l : libraries_)
    if (l->path == path) return;
  auto lib = std::make_unique<Library>();
  lib->path = path;
  lib->handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
  if (!lib->handle) {
    const char* why = dlerror();
    throw Error("cannot open plugin library " + path + ": " + (why ? why : "unknown reason"));
  }
  using AbiFn = int (*)();
  using RegisterFn = void (*)(Registry&);
  auto abi = reinterpret_cast<AbiFn>(dlsym(lib->handle, "stratum_plugin_abi_version"));
  auto reg = reinterpret_cast<RegisterFn>(dlsym(lib->handle, "stratum_register"));
  if (!abi || !reg)
    throw Error(
        "plugin library " + path +
        " does not export stratum_plugin_abi_version and stratum_register (use the STRATUM_PLUGIN macro)");
  const int version = abi();
  if (version != STRATUM_PLUGIN_ABI_VERSION)
    throw Error("plugin library " + path + " was built for plugin ABI version " + std::to_string(version) +
                ", this Stratum expects version " + std::to_string(STRATUM_PLUGIN_ABI_VERSION) +
                "; rebuild the plugin");
  registry.set_current_library(path);
  reg(registry);
  registry.set_current_library("(built in)");
  libraries_.push_back(std::move(lib));
}

} // namespace stratum
