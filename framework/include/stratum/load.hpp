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
  enum class Kind { pressure, force, gravity, inflow };
  std::string name;
  Kind kind = Kind::pressure;
  std::string set; ///< edge set (pressure, inflow), node set (force), cell set (gravity)
  // pressure: p(y) = p + gamma * min(max(surface - y, 0), critical_depth) (kPa, pushing into the body)
  double p = 0.0, gamma = 0.0, surface = 0.0;
  double critical_depth = std::numeric_limits<double>::infinity();
  /// When finite: the pressure is uniform and scaled so that its total vertical resultant is
  /// this force (kN, downward positive; axisymmetric: over the whole circle).
  double total_force = std::numeric_limits<double>::quiet_NaN();
  double fx = 0.0, fy = 0.0; ///< force per node (kN)
  bool top_of_cells = false; ///< pressure on the top faces of the cell set `set` (a pile head)
  /// gravity: cells whose centroid lies below this phreatic level weigh gamma_below (the buoyant
  /// unit weight) instead of gamma, and under a sloped level carry the horizontal seepage force
  /// -gamma_w dlevel/dx (kN/m3) of the steady flow; none: dry.
  PhreaticLevel water;
  double gamma_below = 0.0;
  double gamma_w = 9.81;
  /// inflow: the volume entering through the edges per unit area and unit time (m/s in the scene's
  /// units; negative: outflow), into the pore-pressure unknowns (Model::inflow).
  double q = 0.0;

  /// Checkpoints keep the applied loads (framework/src/run/checkpoint.cpp: class version 2; a
  /// version-1 archive holds a horizontal level as one number).
  template <class Ar> void serialize(Ar& ar, unsigned version) {
    ar& name& kind& set& p& gamma& surface& critical_depth& total_force& fx& fy& top_of_cells;
    if (version == 1) {
      double level = -std::numeric_limits<double>::infinity();
      ar& level& gamma_below;
      if (level > -std::numeric_limits<double>::infinity()) water = PhreaticLevel::horizontal(level);
    }
    if (version >= 2) ar& water& gamma_below& gamma_w& q;
  }
};

/// The edges a pressure spec acts on (the top faces of its active cells for top_of_cells).
[[nodiscard]] std::vector<Edge> load_edges(const Model& model, const LoadSpec& spec);
/// The nodes of those edges (sorted, unique); a force spec's node set.
[[nodiscard]] std::vector<int> load_nodes(const Model& model, const LoadSpec& spec);

/// Adds the nodal forces of `spec` over the model's active cells to `f` (full size); an inflow
/// adds nothing (add_inflow).
void add_load(const Model& model, const LoadSpec& spec, Eigen::VectorXd& f);

/// Adds the volume rate of an inflow spec (m3 per time unit, consistent over its edges with the
/// pore pressure's interpolation along them) at the pore-pressure DOFs to `rate` (full size);
/// nothing for other kinds. Throws Error when no node of its edges carries a pore pressure.
void add_inflow(const Model& model, const LoadSpec& spec, Eigen::VectorXd& rate);

/// Axisymmetric area (2 pi r weighted) or plane length of the vertical projection of edges.
[[nodiscard]] double projected_area(const Model& model, const std::vector<Edge>& edges);

} // namespace stratum
