// Helpers for tests that run whole scenes in-process.
#pragma once

#include "stratum/analysis.hpp"
#include "stratum/error.hpp"

#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

namespace stratum::testing {

/// Builds a scene from TOML text with the build tree's plugins; no files are written.
inline std::unique_ptr<Analysis> scene(const std::string& toml, const std::string& name = "test.toml") {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  return Analysis::from_string(toml, name, std::move(o));
}

/// The message of the error that building `toml` (as file `name`) throws; "" when it builds.
inline std::string build_error(const std::string& toml, const std::string& name = "test.toml") {
  try {
    (void)scene(toml, name);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

/// The path of a file of the source tree, e.g. source_path("plugins/tri/tests/scenes/patch.toml").
inline std::string source_path(const std::string& relative) {
  return std::string(STRATUM_SOURCE_DIR) + "/" + relative;
}

/// The path of a test scene file: tests/scenes/<relative>, e.g. scene_path("stages/column.toml").
inline std::string scene_path(const std::string& relative) { return source_path("tests/scenes/" + relative); }

/// The text of a file (a scene to vary by a small edit before it is built); throws if unreadable.
inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read test file '" + path + "'");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// `text` with the one occurrence of `from` replaced by `to`; throws unless `from` occurs exactly once.
inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos || text.find(from, at + 1) != std::string::npos)
    throw std::runtime_error("test scene edit: '" + from + "' must occur exactly once");
  return text.replace(at, from.size(), to);
}

/// Builds the scene file at `path` (its includes resolved beside it) with the build tree's plugins.
inline std::unique_ptr<Analysis> scene_file(const std::string& path) {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  return Analysis::from_file(path, std::move(o));
}

/// Builds the test scene tests/scenes/<relative>.
inline std::unique_ptr<Analysis> test_scene(const std::string& relative) {
  return scene_file(scene_path(relative));
}

/// Index of the mesh node nearest to (x, y).
inline int node_at(const Model& m, double x, double y) {
  int best = -1;
  double d = 1e300;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
    const double e = std::hypot(m.mesh.nodes[n].x() - x, m.mesh.nodes[n].y() - y);
    if (e < d) d = e, best = static_cast<int>(n);
  }
  return best;
}

inline double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

} // namespace stratum::testing
