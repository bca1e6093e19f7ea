// [mesh]: generated blocks, a Gmsh file, or a registered mesh generator; read into a MeshSpec
// (scene.hpp), then built (the generator run, the file read, the mesh checked).
#include "analysis_impl.hpp"
#include "meshers/builtin_generators.hpp"
#include "scene/plugin_table.hpp"
#include "scene/scene.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "stratum/mesh_io.hpp"
#include "toml_check.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

using io::check_table;
using io::location;
using scene::optional_table;
using scene::table_at;
using scene::table_list;
using namespace scene;

// A Gmsh file's physical groups are names the user chose; one that no string of the scene names
// is likely a misspelling elsewhere (or a group left over). Generated meshes are not looked at:
// their generators define many sets a scene does not need (the pile mesher some forty).
void Analysis::Impl::unused_physical_groups(const std::set<std::string>& named, const SourceLocation& at,
                                            const std::string& file) {
  std::set<std::string> unused;
  for (const auto* sets : {&model.mesh.cell_sets, &model.mesh.node_sets})
    for (const auto& [name, v] : *sets)
      if (name != "all" && !named.count(name)) unused.insert(name);
  for (const auto& [name, v] : model.mesh.edge_sets)
    if (!named.count(name)) unused.insert(name);
  if (unused.empty()) return;
  std::string list;
  for (const auto& n : unused) list += (list.empty() ? "" : ", ") + n;
  std::ostringstream o;
  o << at.str() << " [mesh] file = \"" << file << "\": " << unused.size() << " physical group"
    << (unused.size() == 1 ? "" : "s") << " that the scene never names: " << list
    << " (harmless if left over; otherwise check the set names)";
  warnings.push_back(o.str());
}

scene::MeshSpec scene::read_mesh(const toml::table& root, const std::string& path, PluginCatalog& catalog,
                                 Registry& registry, const Units& units) {
  MeshSpec spec;
  const auto& mt = table_at(root, "mesh", "scene");
  spec.at = location(mt);
  std::string generator; // a generator's parameters are in [mesh.<its table>]
  if (const auto* g = mt.get("generator"); g && g->is_string()) generator = g->as_string()->get();
  const bool own_reader = generator == "blocks" || generator == "gmsh";
  const std::string sub = own_reader || generator.empty() ? "" : generator_table(generator);
  const TableKeys keys = mesh_keys();
  // keys.other: blocks, and the generator's table (whose name depends on the generator)
  std::vector<std::string_view> extra{keys.other.at(0).name};
  if (!sub.empty()) extra.push_back(sub);
  const auto mp = check_table(mt, keys.schema, "[mesh]", extra);
  spec.nodes_per_cell = static_cast<int>(mp.integer("nodes_per_cell"));
  if (mp.text("generator") == "blocks") {
    spec.source = MeshSpec::Source::blocks;
    const int npc = spec.nodes_per_cell;
    if (npc != 4 && npc != 8)
      throw Error(mp.where("nodes_per_cell"),
                  "[mesh] nodes_per_cell = " + std::to_string(npc) + " is not allowed; allowed: 4 or 8");
    const auto list = table_list(mt, "blocks");
    if (list.empty())
      throw Error(location(mt), "[mesh] generator = \"blocks\" needs at least one [[mesh.blocks]]");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string ctx = "[[mesh.blocks]] #" + std::to_string(i + 1);
      const auto bp = check_table(*list[i], block_schema(), ctx);
      Block b;
      b.name = bp.text("name");
      for (const char* xy : {"x", "y"}) {
        const auto& v = bp.real_list(xy);
        if (v.size() != 2 || !(v[1] > v[0]))
          throw Error(bp.where(xy), ctx + " " + xy + " must be [min, max] with max > min");
      }
      b.x0 = bp.real_list("x")[0], b.x1 = bp.real_list("x")[1];
      b.y0 = bp.real_list("y")[0], b.y1 = bp.real_list("y")[1];
      b.nx = static_cast<int>(bp.integer("nx")), b.ny = static_cast<int>(bp.integer("ny"));
      b.grade_x = bp.real("grade_x"), b.grade_y = bp.real("grade_y");
      spec.blocks.push_back(b);
      spec.block_at.push_back(location(*list[i]));
    }
    spec.polar = mp.text("transform") == "polar";
  } else if (generator != "gmsh") {
    spec.source = MeshSpec::Source::generator;
    if (mt.get("blocks"))
      throw Error(location(*mt.get("blocks")), "[mesh] blocks are only used with generator = \"blocks\"");
    const std::string what = "[mesh] generator = \"" + generator + "\"";
    if (!registry.has(PluginKind::mesh_generator, generator)) {
      auto known = catalog.known(PluginKind::mesh_generator);
      if (std::find(known.begin(), known.end(), generator) == known.end()) {
        for (const auto& n : registry.names(PluginKind::mesh_generator)) known.push_back(n);
        std::string list = "blocks, gmsh";
        for (const auto& n : known) list += ", " + n;
        known.insert(known.begin(), {"blocks", "gmsh"});
        throw Error(mp.where("generator"),
                    what + " is not allowed; allowed: one of: " + list + did_you_mean(generator, known));
      }
    }
    spec.generator = generator;
    spec.generator_at = mp.where("generator");
    const toml::node* t = mt.get(sub);
    spec.generator_table_at = t ? location(*t) : mp.where("generator");
    spec.mesher =
        scene::plugin_table<MeshGenerator>(catalog, registry, generator, mp.where("generator"), what,
                                           optional_table(mt, sub), "[mesh." + sub + "]", {}, units);
  } else {
    spec.source = MeshSpec::Source::gmsh;
    if (mt.get("blocks"))
      throw Error(location(*mt.get("blocks")), "[mesh] blocks are only used with generator = \"blocks\"");
    if (mp.text("file").empty())
      throw Error(location(mt), "[mesh] generator = \"gmsh\" needs file = \"...\"");
    spec.file = mp.text("file");
    spec.file_at = mp.where("file");
    fs::path f = spec.file;
    if (f.is_relative()) f = fs::path(path).parent_path() / f;
    spec.file_path = f.string();
  }
  return spec;
}

void Analysis::Impl::build_mesh(const scene::Scene& sc) {
  const scene::MeshSpec& spec = sc.mesh;
  switch (spec.source) {
  case scene::MeshSpec::Source::blocks:
    try {
      model.mesh = generate_blocks(spec.blocks, spec.nodes_per_cell);
    } catch (const Error& e) {
      if (e.where().known()) throw;
      // The generator names the block; locate the first block table that carries that name.
      SourceLocation at = spec.at;
      for (std::size_t i = 0; i < spec.blocks.size(); ++i)
        if (e.message().find("'" + spec.blocks[i].name + "'") != std::string::npos) {
          at = spec.block_at[i];
          if (e.message().find("used more than once") == std::string::npos) break;
        }
      throw Error(at, "[mesh] " + e.message());
    }
    if (spec.polar)
      for (auto& x : model.mesh.nodes) {
        const double r = x.x(), t = x.y() * std::numbers::pi / 180.0;
        x = Eigen::Vector2d(r * std::cos(t), r * std::sin(t));
      }
    break;
  case scene::MeshSpec::Source::generator: {
    const auto mesher = spec.mesher.create();
    try {
      model.mesh = mesher->generate(MeshRequest{model.formulation, spec.nodes_per_cell});
    } catch (const Error& e) {
      if (e.where().known()) throw;
      throw Error(spec.generator_table_at, e.message());
    }
    break;
  }
  case scene::MeshSpec::Source::gmsh: {
    const fs::path f = spec.file_path;
    std::error_code ec;
    if (!fs::is_regular_file(f, ec))
      throw Error(spec.file_at, "[mesh] file = \"" + spec.file + "\": " +
                                    (fs::exists(f, ec) ? "is not a regular file (a folder?)"
                                                       : "no such file ('" + f.string() + "')") +
                                    "; give a Gmsh .msh 4.1 ASCII file");
    model.mesh = read_gmsh(f.string());
    unused_physical_groups(sc.strings, spec.file_at, spec.file);
    break;
  }
  }
  model.mesh.check();
  if (!settings.pile_cells.empty() && !model.mesh.cell_sets.count(settings.pile_cells))
    throw Error(sc.settings.pile_cells_at,
                "[output] pile_cells = \"" + settings.pile_cells +
                    "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
  if (model.formulation == Formulation::axisymmetric)
    for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n)
      if (model.mesh.nodes[n].x() < -1e-12)
        throw Error(spec.at, "[mesh] node " + std::to_string(n) + " has a negative radius x = " +
                                 std::to_string(model.mesh.nodes[n].x()) + " in an axisymmetric scene");
}

} // namespace stratum
