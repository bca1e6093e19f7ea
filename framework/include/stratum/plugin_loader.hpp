// Finding and opening plugin libraries.
//
// Each plugin library `X.so` has a manifest `X.plugin` beside it that lists the
// factories it provides ("<kind> <name>" per line; written by the CMake helper
// stratum_add_plugin). The catalog reads manifests only; a library is opened
// when a scene names one of its factories (or when all are listed).
//
// Search path: the directories in $STRATUM_PLUGIN_PATH (':'-separated), then
// the plugin directory of the libstratum that runs: <libdir>/stratum/plugins for
// an installed library, the build tree's plugins folder for the library of a
// build tree (told apart by where the running libstratum is; an installed
// library never searches a build tree). Like PATH, the first directory providing a name wins; two libraries
// in the same directory providing the same name are an error naming both.
#pragma once

#include "stratum/registry.hpp"

#include <memory>
#include <string>
#include <vector>

namespace stratum {

class PluginCatalog {
public:
  /// Reads the manifests in `directories` (missing directories are skipped).
  explicit PluginCatalog(std::vector<std::string> directories);
  ~PluginCatalog();
  PluginCatalog(const PluginCatalog&) = delete;
  PluginCatalog& operator=(const PluginCatalog&) = delete;

  /// The default search path (see the file comment).
  [[nodiscard]] static std::vector<std::string> default_directories();

  /// Opens the library providing kind/name (once) and registers its factories.
  /// Throws Error: unknown name (listing the known ones), ABI mismatch (both numbers
  /// and the path), duplicate name (both libraries), missing entry symbols.
  void require(Registry& registry, PluginKind kind, const std::string& name);
  /// Opens every library of the catalog.
  void require_all(Registry& registry);

  [[nodiscard]] std::vector<std::string> known(PluginKind kind) const;
  [[nodiscard]] const std::vector<std::string>& directories() const { return dirs_; }
  /// Paths of the libraries opened so far, in the order they were opened.
  [[nodiscard]] std::vector<std::string> opened() const;

private:
  struct Entry {
    PluginKind kind;
    std::string name;
    std::string library;
  };
  struct Library;
  void open(Registry& registry, const std::string& path);

  std::vector<std::string> dirs_;
  std::vector<Entry> entries_;
  std::vector<std::string> conflicts_; // messages for names provided twice in one directory
  std::vector<std::unique_ptr<Library>> libraries_;
};

} // namespace stratum
