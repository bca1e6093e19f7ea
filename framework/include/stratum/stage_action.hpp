// Stage actions: what one [[stages.actions]] table does to the model when its stage starts
// (place or remove cells, set an initial stress, add or remove a load, prescribe a
// displacement, change a domain's material). The scene names an action by its `type`; the
// framework's own actions (geostatic, deactivate, activate, pressure, load, force, gravity,
// remove, displacement, reset_displacements, change_material, and the water's) and those of
// plugins are registered alike:
//
//   registry.add(stratum::Factory<stratum::StageAction>{"my_action", "one line", schema, create});
//
// The factory's schema checks the table (its `type` key belongs to the scene), so an unknown
// or misspelt key is a located error before anything runs.
#pragma once

#include "stratum/load.hpp"
#include "stratum/model.hpp"
#include "stratum/params.hpp"

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace stratum {

/// What an action sees when the scene is built (its text read and checked, its mesh made), stage
/// by stage in order, before anything runs.
struct StageCheck {
  const Mesh& mesh;
  std::string context;  ///< e.g. `[[stages]] #2 [[stages.actions]] #1 type = "pressure"`, for messages
  SourceLocation where; ///< the action's table
  std::set<std::string>& load_names; ///< names of the loads applied at this point of the scene
  std::string default_load_name;     ///< for a load the table does not name: "<type>@<stage>"
  bool reset_after = false;          ///< set it: the stage's displacements are zeroed at its end
  /// The model's domains as built (their names are their cell sets) and the scene's
  /// [materials.<name>] by name: for an action that changes a domain's material. Set by the
  /// framework; null in a StageCheck built elsewhere.
  const std::vector<Domain>* domains = nullptr;
  const std::map<std::string, const Material*>* materials = nullptr;

  /// Throws a located Error unless the text parameter `key` names a cell (node, edge) set.
  void require_cell_set(const Params& p, const std::string& key) const;
  void require_node_set(const Params& p, const std::string& key) const;
  void require_edge_set(const Params& p, const std::string& key) const;
  /// Records a load the action adds; throws a located Error when that name is already applied.
  void add_load_name(const std::string& name) const;
};

/// What an action may change when its stage starts; the stage then rebuilds the DOF map,
/// starts from equilibrium with the forces its active cells carry and moves to the loads.
struct StageState {
  Model& model; ///< active cells, constraints and prescribed values of the stage, displacements, stresses
  std::vector<LoadSpec>& loads; ///< the loads applied (kept in checkpoints)
  /// The pile head the stage's curves follow: a load with a total force, or the nodes pushed
  /// down by a prescribed head displacement (set by the `load` action).
  const LoadSpec* head_load = nullptr;
  std::vector<int> head_nodes;
  /// Loads that change as a jump at the stage's first step, not linearly over the stage: (before,
  /// after) of each (the `water_level` action: the buoyancy of the self-weight follows the level at
  /// once, as the excess pore pressure takes over the steady pressure's change at once).
  std::vector<std::pair<LoadSpec, LoadSpec>> load_jumps;
};

class StageAction {
public:
  virtual ~StageAction() = default;
  /// Called once when the scene is built: check the sets the action names, record the loads it
  /// adds or removes. Throw Error (located with Params::where) on bad input.
  virtual void check(StageCheck& scene) { (void)scene; }
  /// Applies the action at the start of its stage (actions run in the order written).
  virtual void apply(StageState& state) const = 0;
  /// A restart after this action's stage: re-applies what the action left in the model that a
  /// checkpoint does not keep (which material a domain has, and the layout of its states), before
  /// the checkpoint's values are restored. Called for the actions of every completed stage, in
  /// order. Most actions change only what a checkpoint keeps (displacements, states, loads,
  /// active cells) and need nothing here.
  virtual void resume(Model& model) const { (void)model; }
};

} // namespace stratum
