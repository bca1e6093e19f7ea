// External loads that stay applied from the stage that adds them until a stage removes them
// (stage actions add and remove them; stratum/stage_action.hpp). Their nodal forces are
// recomputed from the active cells whenever a stage starts.
#pragma once

#include "stratum/model.hpp"

#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

namespace stratum {

struct LoadSpec {
  enum class Kind { pressure, force, gravity };
  std::string name;
  Kind kind = Kind::pressure;
  std::string set; ///< edge set (pressure), node set (force), cell set (gravity)
  // pressure: p(y) = p + gamma * min(max(surface - y, 0), critical_depth) (kPa, pushing into the body)
  double p = 0.0, gamma = 0.0, surface = 0.0;
  double critical_depth = std::numeric_limits<double>::infinity();
  /// When finite: the pressure is uniform and scaled so that its total vertical resultant is
  /// this force (kN, downward positive; axisymmetric: over the whole circle).
  double total_force = std::numeric_limits<double>::quiet_NaN();
  double fx = 0.0, fy = 0.0; ///< force per node (kN)
  bool top_of_cells = false; ///< pressure on the top faces of the cell set `set` (a pile head)
  /// gravity: cells whose centroid lies below this level y weigh gamma_below (the buoyant unit
  /// weight under a phreatic level) instead of gamma; -inf: none.
  double water_level = -std::numeric_limits<double>::infinity();
  double gamma_below = 0.0;

  /// Checkpoints keep the applied loads (framework/src/run/checkpoint.hpp).
  template <class Ar> void serialize(Ar& ar, unsigned version) {
    ar& name& kind& set& p& gamma& surface& critical_depth& total_force& fx& fy& top_of_cells;
    if (version >= 1) ar& water_level& gamma_below; // class version 1: framework/src/run/checkpoint.cpp
  }
};

/// The edges a pressure spec acts on (the top faces of its active cells for top_of_cells).
[[nodiscard]] std::vector<Edge> load_edges(const Model& model, const LoadSpec& spec);
/// The nodes of those edges (sorted, unique); a force spec's node set.
[[nodiscard]] std::vector<int> load_nodes(const Model& model, const LoadSpec& spec);

/// Adds the nodal forces of `spec` over the model's active cells to `f` (full size).
void add_load(const Model& model, const LoadSpec& spec, Eigen::VectorXd& f);

/// Axisymmetric area (2 pi r weighted) or plane length of the vertical projection of edges.
[[nodiscard]] double projected_area(const Model& model, const std::vector<Edge>& edges);

} // namespace stratum
