// [mesh]: generated blocks, a Gmsh file, or a registered mesh generator; read into a MeshSpec
// (scene.hpp), then built (the generator run, the file read, the mesh checked).
#include "meshers/builtin_generators.hpp"
#include "scene/plugin_table.hpp"
#include "scene/scene.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "scene/toml_check.hpp"
#include "stratum/mesh_io.hpp"
#include "suggest.hpp"

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
      io::require_read(bp, block_schema(), ctx);
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
  io::require_read(mp, keys.schema, "[mesh]");
  return spec;
}

} // namespace stratum
