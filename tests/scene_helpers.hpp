// Helpers for tests that run whole scenes in-process.
#pragma once

#include "stratum/analysis.hpp"

#include <cmath>
#include <memory>
#include <string>

namespace stratum::testing {

/// Builds a scene from TOML text with the build tree's plugins; no files are written.
inline std::unique_ptr<Analysis> scene(const std::string& toml, const std::string& name = "test.toml") {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  return Analysis::from_string(toml, name, std::move(o));
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
