// What a scene builds (framework/src/model/): the Model, the plugin objects it owns, the stages
// and what a checkpoint must match. The data path:
//
//   TOML --scene::read (scene/)--> scene::Scene --SceneModel::build (model/)--> SceneModel
//        --run/ steps its stages--> output/ observes each step through a RunView
//
// Building checks what needs the mesh (cell, node and edge sets, cell shapes) and creates the
// plugin objects; errors are located at the scene value that caused them. Internal to the
// framework.
#pragma once

#include "model/scene_interfaces.hpp"
#include "scene/scene.hpp"
#include "scene/scene_fingerprint.hpp"
#include "stages/stage.hpp"
#include "stratum/material.hpp"
#include "stratum/model.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"
#include "stratum/solver.hpp"
#include "stratum/units.hpp"

#include <Eigen/Dense>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace stratum {

struct SceneModel {
  /// The plugin libraries the scene names (opened while it is read; they outlive every object
  /// made from them) and the factories they registered with the framework's own.
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;

  std::string title;
  Units units; ///< [units]: the scene's force and length (stratum/units.hpp)
  /// [analysis], [convergence] and [output] as read (threads resolved: 0 = the machine's cores).
  scene::Settings settings;
  std::vector<std::unique_ptr<Material>> materials;
  /// The scene's [materials.<name>] by name (stage actions that change a domain's material).
  std::map<std::string, const Material*> material_by_name;
  std::vector<std::unique_ptr<Element>> elements;
  SceneInterfaces interfaces; ///< contact laws, interface elements, named interfaces
  /// The stage's solver factory and its checked parameters: each stage creates its own solver,
  /// so that nothing a solver keeps (a reference load, a factorization) outlives the stage.
  const Factory<Solver>* solver_factory = nullptr;
  Params solver_params;
  Model model;
  std::vector<stage::Stage> stages;
  Eigen::VectorXd initial_prescribed; ///< [[constraints]] values, applied over the first stage

  std::string fingerprint;
  std::vector<FingerprintPart> parts; ///< checked on restart (scene/scene_fingerprint.hpp)
  std::vector<std::string> warnings;  ///< Analysis::warnings()

  /// Builds everything from the scene as read, in this order: mesh, domains, interfaces,
  /// constraints (the DOF map), stages; then the fingerprint. The stage settings are moved out
  /// of `scene`.
  void build(scene::Scene& scene);
  /// Adds the plugin libraries' parts to `parts` (once): only a run that writes or reads a
  /// checkpoint reads the library files.
  void add_library_parts();

private:
  void build_mesh(const scene::Scene& scene);
  void unused_physical_groups(const std::set<std::string>& named, const SourceLocation& at,
                              const std::string& file);
  void build_domains(const scene::Scene& scene);
  void build_constraints(const scene::Scene& scene);
  void build_stages(scene::Scene& scene);
  /// The stages' actions on a copy of the model, nothing solved (model/rehearse_stages.cpp):
  /// located errors for what would fail when a stage starts, warnings for loads partly dropped.
  void rehearse_stages();
  bool library_parts_added_ = false;
};

} // namespace stratum
