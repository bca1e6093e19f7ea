// Reading a scene: the top level, the plugin path, [analysis], [convergence], [output] and the
// solver; the other sections in read_mesh.cpp, read_domains.cpp and read_stages.cpp.
#include "analysis_impl.hpp"
#include "scene/plugin_table.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "toml_check.hpp"
#include "worker_pool.hpp"

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

using io::check_table;
using io::location;
using scene::optional_table;
using namespace scene;

void Analysis::Impl::build(const toml::table& root) {
  // The framework's own stage actions and mesh generators are registered like a plugin's.
  register_builtin_factories(registry);

  // ---- top level
  // title and the sections (scene/schemas.cpp top_keys; `include` is merged away before this)
  const TableKeys top = scene::top_keys();
  std::vector<std::string_view> top_keys = key_names(top.schema);
  for (const auto& k : top.other)
    if (k.name != "include") top_keys.emplace_back(k.name);
  for (auto&& [key, value] : root) {
    const std::string k(key.str());
    if (std::find(top_keys.begin(), top_keys.end(), k) == top_keys.end()) {
      std::string allowed;
      for (auto t : top_keys) allowed += (allowed.empty() ? "" : ", ") + std::string(t);
      throw Error(location(key.source()), "unknown key '" + k + "' at the top level; allowed: " + allowed +
                                              did_you_mean(k, top_keys));
    }
  }
  if (const auto* t = root.get("title")) {
    if (!t->is_string()) throw Error(location(*t), "title must be a string");
    title = t->as_string()->get();
  }

  // ---- plugins: search path
  std::vector<std::string> dirs =
      options.plugin_dirs.empty() ? PluginCatalog::default_directories() : options.plugin_dirs;
  {
    const auto& pt = optional_table(root, "plugins");
    const TableKeys plugin_keys = plugins_keys(); // path only
    for (auto&& [key, value] : pt) {
      if (key.str() != plugin_keys.other.at(0).name)
        throw Error(location(key.source()),
                    "[plugins] unknown key '" + std::string(key.str()) + "'; allowed: path");
      const auto* a = value.as_array();
      if (!a) throw Error(location(value), "[plugins] path must be an array of directory strings");
      std::vector<std::string> extra;
      for (const auto& e : *a) {
        if (!e.is_string()) throw Error(location(e), "[plugins] path entries must be strings");
        fs::path d = e.as_string()->get();
        if (d.is_relative()) d = fs::path(path).parent_path() / d;
        extra.push_back(d.string());
      }
      dirs.insert(dirs.begin(), extra.begin(), extra.end());
    }
  }
  catalog = std::make_unique<PluginCatalog>(dirs);

  // ---- analysis, convergence, output
  const auto ap = check_table(optional_table(root, "analysis"), analysis_schema(), "[analysis]");
  model.formulation =
      ap.text("formulation") == "axisymmetric" ? Formulation::axisymmetric : Formulation::plane_strain;
  linear_solver = ap.text("linear_solver");
  reuse_linear_stiffness = ap.flag("reuse_linear_stiffness");
  reuse_symbolic = ap.flag("reuse_symbolic");
  threads = resolve_threads(ap.integer("threads"));
  stepping.steps = static_cast<int>(ap.integer("steps"));
  stepping.max_cutbacks = static_cast<int>(ap.integer("max_cutbacks"));
  stepping.increments = ap.real_list("increments");
  for (double v : stepping.increments)
    if (!(v > 0)) throw Error(ap.where("increments"), "[analysis] increments must all be > 0");
  stepping.automatic = ap.flag("automatic");
  stepping.fast_iterations = static_cast<int>(ap.integer("fast_iterations"));
  stepping.growth = ap.real("growth");
  stepping.max_increment = ap.real("max_increment");
  stepping.arc_length = ap.real("arc_length");
  stepping.max_arc_length = ap.real("max_arc_length");
  stepping.max_steps = static_cast<int>(ap.integer("max_steps"));
  stepping.error_tolerance = ap.real("error_tolerance");
  const auto cp = check_table(optional_table(root, "convergence"), convergence_schema(), "[convergence]");
  convergence.force_rtol = cp.real("force_rtol");
  convergence.force_atol = cp.real("force_atol");
  convergence.disp_rtol = cp.real("disp_rtol");
  convergence.disp_atol = cp.real("disp_atol");
  convergence.energy_rtol = cp.real("energy_rtol");
  convergence.energy_atol = cp.real("energy_atol");
  convergence.displacement_test = cp.flag("displacement_test");
  convergence.max_iterations = static_cast<int>(cp.integer("max_iterations"));
  const TableKeys output = output_keys();
  const auto op =
      check_table(optional_table(root, "output"), output.schema, "[output]", output.other_names());
  vtk = op.flag("vtk");
  ip_output = op.flag("integration_points");
  every = static_cast<int>(op.integer("every"));
  tables_every = op.real("tables_every");
  pile_cells = op.text("pile_cells");
  const SourceLocation pile_cells_at = op.where("pile_cells");

  // ---- solver plugin
  {
    const std::string name = ap.text("solver");
    const auto made = scene::plugin_table<Solver>(
        *catalog, registry, name, ap.where("solver").known() ? ap.where("solver") : location(root),
        "[analysis] solver = \"" + name + "\"", optional_table(root, "solver"), "[solver]");
    solver_factory = made.factory;
    solver_params = made.params;
    solver = made.create(); // checks the parameters now; each stage gets its own (run_stage)
  }

  read_mesh(root, pile_cells_at);
  read_domains(root);
  read_scene_interfaces(root, *catalog, registry, model, interfaces);
  read_constraints(root);
  read_stages(root);

  // Recorders and checks (recorders.hpp).
  {
    const auto list = table_list(optional_table(root, "output"), "history");
    for (std::size_t i = 0; i < list.size(); ++i) {
      recorders.emplace_back(*list[i], "[[output.history]] #" + std::to_string(i + 1), model);
      for (std::size_t j = 0; j + 1 < recorders.size(); ++j)
        if (recorders[j].name() == recorders.back().name())
          throw Error(location(*list[i]), "[[output.history]] #" + std::to_string(i + 1) + " name = \"" +
                                              recorders.back().name() +
                                              "\" is used twice; names must be unique");
    }
    const auto cl = table_list(root, "checks");
    for (std::size_t i = 0; i < cl.size(); ++i)
      checks.push_back(parse_check(*cl[i], "[[checks]] #" + std::to_string(i + 1), recorders));
  }

  // What a checkpoint must match: mesh size, domain layout, stage names.
  std::ostringstream fp;
  fp << "nodes " << model.mesh.nodes.size() << " cells " << model.mesh.cells.size();
  for (const auto& dm : model.domains)
    fp << " domain " << dm.name << ':' << dm.states.points() << 'x' << dm.states.stride();
  fp << " stages";
  for (const auto& st : stages) fp << ' ' << st.name;
  fingerprint = fp.str();
  parts = scene_parts(root, model.mesh, STRATUM_VERSION);
}

} // namespace stratum
