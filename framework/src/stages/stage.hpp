// Staged analysis: the load specifications that persist between stages, the stage
// actions (geostatic, deactivate, activate, pressure, load, ...) and what they do to
// the model. Parsed from [[stages]] in analysis.cpp; executed by Analysis::run().
#pragma once

#include "stratum/error.hpp"
#include "stratum/model.hpp"

#include <limits>
#include <string>
#include <vector>

namespace stratum::stage {

/// An external load that stays applied until a stage removes it. Its nodal forces are
/// recomputed from the active cells whenever a stage starts.
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

  template <class Ar> void serialize(Ar& ar, unsigned /*version*/) {
    ar& name& kind& set& p& gamma& surface& critical_depth& total_force& fx& fy& top_of_cells;
  }
};

/// The edges a pressure spec acts on (the top faces of its active cells for top_of_cells).
std::vector<Edge> load_edges(const Model& model, const LoadSpec& spec);
/// The nodes of those edges (sorted, unique).
std::vector<int> load_nodes(const Model& model, const LoadSpec& spec);

/// Adds the nodal forces of `spec` over the model's active cells to `f` (full size).
void add_load(const Model& model, const LoadSpec& spec, Eigen::VectorXd& f);

/// Axisymmetric area (2 pi r weighted) or plane length of the vertical projection of edges.
double projected_area(const Model& model, const std::vector<Edge>& edges);

struct Action {
  enum class Kind {
    geostatic,
    deactivate,
    activate,
    add_load, ///< pressure, force, gravity, or the head `load` with a total force
    remove_load,
    displacement, ///< prescribed displacement increment over the stage's steps
    reset_displacements
  };
  Kind kind = Kind::geostatic;
  SourceLocation where;
  std::string cells; ///< geostatic, deactivate, activate; displacement: the pile whose head is pushed
  std::string nodes; ///< displacement
  double gamma = 0.0, K0 = 0.5, surface = 0.0; ///< geostatic; activate with hydrostatic stress
  bool hydrostatic = false;                    ///< activate: fresh-concrete (fluid) initial stress
  double ux = std::numeric_limits<double>::quiet_NaN(), uy = std::numeric_limits<double>::quiet_NaN();
  LoadSpec load;    ///< add_load
  std::string name; ///< remove_load
};

struct Stage {
  std::string name;
  SourceLocation where;
  int steps = 1;
  std::vector<double> increments; ///< load-factor increments (sum 1); empty: `steps` equal ones
  int max_cutbacks = 4;
  double error_tolerance = 0.0; ///< error-controlled load steps (step_control.hpp); 0: off
  std::vector<Action> actions;
  bool reset_after = false;   ///< zero the displacements at the end (geostatic stages)
  bool until_failure = false; ///< a step that fails after its cut-backs ends the run normally
  double collapse_stiffness =
      0.1;                      ///< until_failure: current-stiffness ratio below which a stop is a collapse
  double stop_settlement = 0.0; ///< > 0: stop once the monitored settlement exceeds it (m)
  std::string monitor;          ///< edge or node set whose mean vertical displacement is monitored
  bool vtk = true;
  int every = 1;
  bool checkpoint = true;
};

/// Sets the geostatic stress sigma_v = -gamma (surface - y), sigma_h = K0 sigma_v at every
/// integration point of the active cells in `cells` (history initialised for that stress).
void set_geostatic(Model& model, const std::vector<int>& cells, double gamma, double K0, double surface);

/// Initial stress of freshly placed cells: zero, or the fluid's hydrostatic -gamma (surface - y) I.
void set_placed_stress(Model& model, const std::vector<int>& cells, bool hydrostatic, double gamma,
                       double surface);

} // namespace stratum::stage
