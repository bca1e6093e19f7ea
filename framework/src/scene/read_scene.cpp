// Reading a scene (scene.hpp): the top level, the plugin path, [analysis], [convergence], [output]
// and the solver here; the other sections in read_mesh.cpp, read_domains.cpp, read_interfaces.cpp
// and read_stages.cpp. Building the model from the Scene: model/scene_model.hpp.
#include "files.hpp"
#include "scene/plugin_table.hpp"
#include "scene/scene.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "scene/toml_check.hpp"
#include "suggest.hpp"
#include "worker_pool.hpp"

#include <algorithm>
#include <filesystem>
#include <set>

namespace fs = std::filesystem;

namespace stratum {

using io::check_table;
using io::location;
using scene::optional_table;
using namespace scene;

Units scene::read_units(const toml::table& root) {
  const auto& t = optional_table(root, "units");
  // A misspelt unit gets "did you mean" (check_table would list the allowed ones only).
  for (const auto& [key, allowed] :
       {std::pair{"force", &Units::force_units()}, std::pair{"length", &Units::length_units()},
        std::pair{"time", &Units::time_units()}}) {
    const auto* v = t.get(key);
    if (!v || !v->is_string()) continue;
    const std::string x = v->as_string()->get();
    if (std::find(allowed->begin(), allowed->end(), x) != allowed->end()) continue;
    std::string list;
    for (auto a : *allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    throw Error(location(*v), std::string("[units] ") + key + " = " + io::show(*v) +
                                  " is not allowed; allowed: one of: " + list + did_you_mean(x, *allowed));
  }
  const auto p = check_table(t, units_schema(), "[units]");
  Units u(p.text("force"), p.text("length"), p.text("time"));
  u.declared_at = p.where("force").known() ? p.where("force") : location(t);
  if (const auto* sv = t.get("stress")) {
    const std::string want = p.text("stress");
    const std::string spelt = u.force() + "/" + u.length() + "2";
    if (want != u.stress() && want != spelt)
      throw Error(location(*sv), "[units] stress = \"" + want + "\" does not follow from force = \"" +
                                     u.force() + "\", length = \"" + u.length() + "\" (" + spelt +
                                     "); allowed: " + u.stress() + (spelt == u.stress() ? "" : ", " + spelt) +
                                     " (or leave stress out)");
  }
  io::require_read(p, units_schema(), "[units]");
  return u;
}

Units scene_units(const std::string& scene_path) {
  const std::string text =
      read_text_file(scene_path, SourceLocation{scene_path, 0, 0}, "scene file", file_limits::scene);
  return read_units(io::parse_with_includes(text, scene_path));
}

namespace {

/// Every string value of a table, at any depth.
void strings_of(const toml::node& n, std::set<std::string>& out) {
  if (const auto* s = n.as_string()) out.insert(s->get());
  if (const auto* t = n.as_table())
    for (auto&& [k, v] : *t) strings_of(v, out);
  if (const auto* a = n.as_array())
    for (const auto& v : *a) strings_of(v, out);
}

} // namespace

std::vector<std::string> scene::plugin_directories(const toml::table& root, const std::string& path,
                                                   const RunOptions& options) {
  std::vector<std::string> dirs =
      options.plugin_dirs.empty() ? PluginCatalog::default_directories() : options.plugin_dirs;
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
  return dirs;
}

scene::Scene scene::read(const toml::table& root, const std::string& path, PluginCatalog& catalog,
                         Registry& registry) {
  Scene sc;
  sc.path = path;
  sc.at = location(root);

  // ---- top level: title and the sections (scene/schemas.cpp top_keys; `include` is merged
  // away before this)
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
    sc.title = t->as_string()->get();
  }

  // ---- units (stratum/units.hpp): before anything whose defaults they convert
  sc.units = read_units(root);
  const Units& units = sc.units;

  // ---- analysis, convergence, output
  Settings& s = sc.settings;
  const auto ap = check_table(optional_table(root, "analysis"), analysis_schema(), "[analysis]");
  s.formulation =
      ap.text("formulation") == "axisymmetric" ? Formulation::axisymmetric : Formulation::plane_strain;
  s.linear_solver = ap.text("linear_solver");
  s.reuse_linear_stiffness = ap.flag("reuse_linear_stiffness");
  s.reuse_symbolic = ap.flag("reuse_symbolic");
  s.threads = resolve_threads(ap.integer("threads"));
  StepSettings& stepping = s.stepping;
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
  const auto cp =
      check_table(optional_table(root, "convergence"), convergence_schema(), "[convergence]", {}, units);
  Convergence& convergence = s.convergence;
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
  s.vtk = op.flag("vtk");
  s.ip_output = op.flag("integration_points");
  s.every = static_cast<int>(op.integer("every"));
  s.tables_every = op.real("tables_every");
  s.pile_cells = op.text("pile_cells");
  s.pile_cells_at = op.where("pile_cells");
  io::require_read(cp, convergence_schema(), "[convergence]");
  io::require_read(op, output.schema, "[output]");

  // ---- solver plugin: its table checked now, the solver created per stage (run_stage)
  {
    const std::string name = ap.text("solver");
    sc.solver = scene::plugin_table<Solver>(
        catalog, registry, name, ap.where("solver").known() ? ap.where("solver") : location(root),
        "[analysis] solver = \"" + name + "\"", optional_table(root, "solver"), "[solver]", {}, units);
  }
  io::require_read(ap, analysis_schema(), "[analysis]");

  sc.mesh = read_mesh(root, path, catalog, registry, units);
  read_domains(root, catalog, registry, sc);
  read_interfaces(root, catalog, registry, sc);
  read_constraints(root, sc);
  read_stages(root, catalog, registry, sc);

  // ---- recorders and checks (recorders.hpp)
  {
    const auto list = table_list(optional_table(root, "output"), "history");
    for (std::size_t i = 0; i < list.size(); ++i) {
      sc.history.push_back(read_recorder(*list[i], "[[output.history]] #" + std::to_string(i + 1), units));
      for (std::size_t j = 0; j + 1 < sc.history.size(); ++j)
        if (sc.history[j].name == sc.history.back().name)
          throw Error(location(*list[i]), "[[output.history]] #" + std::to_string(i + 1) + " name = \"" +
                                              sc.history.back().name +
                                              "\" is used twice; names must be unique");
    }
    const auto cl = table_list(root, "checks");
    for (std::size_t i = 0; i < cl.size(); ++i)
      sc.checks.push_back(parse_check(*cl[i], "[[checks]] #" + std::to_string(i + 1), sc.history));
  }

  strings_of(root, sc.strings);
  sc.parts = scene_parts(root, STRATUM_VERSION);
  return sc;
}

} // namespace stratum
