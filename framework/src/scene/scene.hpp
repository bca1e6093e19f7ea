// The scene as read: every section of a scene file checked and typed, with the source location
// of every value, before anything is built (internal to the framework).
//
//   TOML text --parse_with_includes--> toml::table --scene::read--> Scene --SceneModel::build-->
//   mesh, materials, elements, interfaces, constraints, stages, recorders (the run's state)
//
// Reading checks what the text alone decides: the keys of every table against its schema (a
// plugin's table against the schema the plugin declares, so the plugin's library is opened but
// nothing is created), the types, ranges and choices of values, the references between sections
// (a domain's material, an interface's contact law, a check's recorder), and the stage rules
// (what a stage inherits, which stage may end the run). Building checks what needs the mesh (cell,
// node and edge sets, cell shapes) and creates the plugins. Both report errors at the value's
// file:line:col, kept here as SourceLocation next to each value.
#pragma once

#include "scene/plugin_table.hpp"
#include "scene/recorder_spec.hpp"
#include "scene/scene_fingerprint.hpp"
#include "stages/stage.hpp"
#include "stratum/analysis.hpp"
#include "stratum/contact_law.hpp"
#include "stratum/element.hpp"
#include "stratum/material.hpp"
#include "stratum/mesh_generator.hpp"
#include "stratum/mesh_io.hpp"
#include "stratum/solver.hpp"
#include "stratum/stage_action.hpp"
#include "stratum/step_control.hpp"
#include "stratum/units.hpp"

#include <array>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace stratum::scene {

/// [analysis], [convergence] and [output]: how the run solves and what it writes.
struct Settings {
  Formulation formulation = Formulation::plane_strain;
  std::string linear_solver = "auto";
  bool reuse_linear_stiffness = true, reuse_symbolic = true;
  int threads = 1; ///< resolved ([analysis] threads, 0 = the machine's)
  StepSettings stepping;
  Convergence convergence;
  bool vtk = true, ip_output = true;
  int every = 1;
  double tables_every = 5.0;
  std::string pile_cells;
  SourceLocation pile_cells_at;
  /// A stage loads a pile head (a `load` action): the VTK steps carry the head's load and
  /// settlement as field data (NaN before the head is loaded); other scenes have no such values.
  bool pile_head = false;
};

/// [mesh]: blocks, a Gmsh file or a registered generator with its checked table.
struct MeshSpec {
  enum class Source { blocks, gmsh, generator };
  Source source = Source::blocks;
  SourceLocation at; ///< the [mesh] table
  int nodes_per_cell = 8;
  // blocks
  std::vector<Block> blocks;
  std::vector<SourceLocation> block_at;
  bool polar = false;
  // gmsh
  std::string file, file_path; ///< as written, and resolved against the scene's folder
  SourceLocation file_at;
  // generator
  std::string generator;
  SourceLocation generator_at, generator_table_at; ///< the generator's name, its [mesh.<table>]
  PluginTable<MeshGenerator> mesher;
};

struct MaterialSpec {
  std::string name; ///< [materials.<name>]
  PluginTable<Material> plugin;
};

struct DomainSpec {
  std::string context; ///< "[[domains]] #k"
  std::string cells, material, element;
  SourceLocation cells_at, material_at, element_at;
  std::size_t material_index = 0; ///< into Scene::materials
  PluginTable<Element> plugin;
  std::string drainage = "drained"; ///< drained, undrained, undrained_total, non_porous
  double fluid_stiffness = 0.0;     ///< K_w / n of an undrained domain (kPa)
  SourceLocation drainage_at;
};

struct ContactLawSpec {
  std::string name; ///< [contact_laws.<name>]
  PluginTable<ContactLaw> plugin;
};

struct InterfaceSpec {
  std::string context; ///< "[[interfaces]] #k"
  std::string name, edges, cells, element;
  bool csv = true;
  SourceLocation at, edges_at, cells_at, element_at;
  std::size_t law_index = 0; ///< into Scene::contact_laws
  PluginTable<Element> plugin;
};

struct ConstraintSpec {
  std::string nodes;
  SourceLocation at, nodes_at;
  std::array<std::optional<double>, 2> value; ///< ux, uy
  std::array<SourceLocation, 2> value_at;
  std::string field; ///< another field by name (`field` and `value`), empty when none
  double field_value = 0.0;
  SourceLocation field_at, field_value_at;
};

/// One [[stages.actions]] (or [[loads]]) table: its action's factory and checked parameters.
struct ActionSpec {
  std::string context, default_load_name;
  SourceLocation at;
  PluginTable<StageAction> plugin;
};

struct StageSpec {
  stage::Stage settings; ///< everything but the actions (created when the scene is built)
  SourceLocation monitor_at;
  std::vector<ActionSpec> actions;
};

/// A scene file, read and checked: what SceneModel::build (model/) makes the model from.
struct Scene {
  std::string path, title;
  SourceLocation at; ///< the file's top level
  Units units;
  Settings settings;
  PluginTable<Solver> solver;
  MeshSpec mesh;
  std::vector<MaterialSpec> materials;
  std::vector<DomainSpec> domains;
  SourceLocation domains_at;
  std::vector<ContactLawSpec> contact_laws;
  std::vector<InterfaceSpec> interfaces;
  std::vector<ConstraintSpec> constraints;
  bool staged = false; ///< [[stages]] given (else one stage "load" from [[loads]])
  std::vector<StageSpec> stages;
  std::vector<RecorderSpec> history; ///< [[output.history]]
  std::vector<Check> checks;         ///< [[checks]]
  std::set<std::string> strings;     ///< every string value of the file (unused physical groups)
  /// What a checkpoint must match (scene_fingerprint.hpp); the mesh part's digest is filled in
  /// when the mesh is built.
  std::vector<FingerprintPart> parts;
};

/// The plugin search path: the run options' directories (or the defaults) after the scene's
/// [plugins] path, relative entries resolved against the scene's folder.
[[nodiscard]] std::vector<std::string> plugin_directories(const toml::table& root, const std::string& path,
                                                          const RunOptions& options);

/// Reads and checks the whole scene. Plugins the scene names are looked up (their libraries
/// opened) through `catalog` into `registry`, whose factories the Scene points to: both must
/// outlive it. Throws Error at the offending value's location.
[[nodiscard]] Scene read(const toml::table& root, const std::string& path, PluginCatalog& catalog,
                         Registry& registry);

// The sections, in the order read() reads them (read_mesh.cpp, read_domains.cpp,
// body_interfaces.cpp, read_stages.cpp).
[[nodiscard]] MeshSpec read_mesh(const toml::table& root, const std::string& path, PluginCatalog& catalog,
                                 Registry& registry, const Units& units);
void read_domains(const toml::table& root, PluginCatalog& catalog, Registry& registry, Scene& scene);
void read_interfaces(const toml::table& root, PluginCatalog& catalog, Registry& registry, Scene& scene);
void read_constraints(const toml::table& root, Scene& scene);
void read_stages(const toml::table& root, PluginCatalog& catalog, Registry& registry, Scene& scene);

} // namespace stratum::scene
