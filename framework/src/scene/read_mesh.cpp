// Reading [mesh]: generated blocks, a Gmsh file, or a registered mesh generator.
#include "run/analysis_impl.hpp"
#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "stratum/mesh_io.hpp"
#include "toml_check.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>

namespace fs = std::filesystem;

namespace stratum {

using io::check_table;
using io::location;
using scene::optional_table;
using scene::table_at;
using scene::table_list;
using namespace scene;

void Analysis::Impl::read_mesh(const toml::table& root, const SourceLocation& pile_cells_at) {
  {
    const auto& mt = table_at(root, "mesh", "scene");
    const auto mp = check_table(mt, mesh_schema(), "[mesh]", {"blocks", "pile"});
    if (mp.text("generator") == "axisymmetric_pile") {
      if (model.formulation != Formulation::axisymmetric)
        throw Error(
            mp.where("generator"),
            "[mesh] generator = \"axisymmetric_pile\" needs [analysis] formulation = \"axisymmetric\"");
      const PileMesh d;
      Schema ps;
      ps.real("radius", "m", "pile radius").greater_than(0).defaults_to(d.radius);
      ps.real("length", "m", "pile length below the ground surface y = 0")
          .greater_than(0)
          .defaults_to(d.length);
      ps.real("near_radius", "m", "outer radius of the near (nonlinear) zone")
          .greater_than(0)
          .defaults_to(d.near_radius);
      ps.real("near_depth", "m", "depth of the near zone").greater_than(0).defaults_to(d.near_depth);
      ps.real("domain_radius", "m", "radius of the model").greater_than(0).defaults_to(d.domain_radius);
      ps.real("domain_depth", "m", "depth of the model").greater_than(0).defaults_to(d.domain_depth);
      ps.integer("n_pile", "-", "cells across the pile radius")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_pile));
      ps.integer("n_shaft", "-", "cells along the pile")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_shaft));
      ps.integer("n_near", "-", "cells across the near zone")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_near));
      ps.integer("n_far", "-", "cells across the far zone")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_far));
      ps.integer("n_below", "-", "cells from the pile base to near_depth")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_below));
      ps.integer("n_deep", "-", "cells from near_depth to domain_depth")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_deep));
      ps.real("grade_near", "-", "outer/inner cell width in the near zone")
          .greater_than(0)
          .defaults_to(d.grade_near);
      ps.real("grade_far", "-", "outer/inner cell width in the far zone")
          .greater_than(0)
          .defaults_to(d.grade_far);
      ps.real("grade_below", "-", "lower/upper cell height below the base")
          .greater_than(0)
          .defaults_to(d.grade_below);
      ps.real("grade_deep", "-", "lower/upper cell height in the deep zone")
          .greater_than(0)
          .defaults_to(d.grade_deep);
      const auto pp = check_table(optional_table(mt, "pile"), ps, "[mesh.pile]");
      PileMesh spec;
      spec.radius = pp.real("radius"), spec.length = pp.real("length");
      spec.near_radius = pp.real("near_radius"), spec.near_depth = pp.real("near_depth");
      spec.domain_radius = pp.real("domain_radius"), spec.domain_depth = pp.real("domain_depth");
      spec.nodes_per_cell = static_cast<int>(mp.integer("nodes_per_cell"));
      spec.n_pile = static_cast<int>(pp.integer("n_pile")),
      spec.n_shaft = static_cast<int>(pp.integer("n_shaft"));
      spec.n_near = static_cast<int>(pp.integer("n_near")),
      spec.n_far = static_cast<int>(pp.integer("n_far"));
      spec.n_below = static_cast<int>(pp.integer("n_below")),
      spec.n_deep = static_cast<int>(pp.integer("n_deep"));
      spec.grade_near = pp.real("grade_near"), spec.grade_far = pp.real("grade_far");
      spec.grade_below = pp.real("grade_below"), spec.grade_deep = pp.real("grade_deep");
      try {
        model.mesh = generate_pile(spec);
      } catch (const Error& e) {
        throw Error(location(optional_table(mt, "pile")), e.message());
      }
    } else if (mp.text("generator") == "blocks") {
      const int npc = static_cast<int>(mp.integer("nodes_per_cell"));
      if (npc != 4 && npc != 8)
        throw Error(mp.where("nodes_per_cell"),
                    "[mesh] nodes_per_cell = " + std::to_string(npc) + " is not allowed; allowed: 4 or 8");
      std::vector<Block> blocks;
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
        blocks.push_back(b);
      }
      try {
        model.mesh = generate_blocks(blocks, npc);
      } catch (const Error& e) {
        if (e.where().known()) throw;
        // The generator names the block; locate the first block table that carries that name.
        SourceLocation at = location(mt);
        for (std::size_t i = 0; i < list.size(); ++i)
          if (e.message().find("'" + blocks[i].name + "'") != std::string::npos) {
            at = location(*list[i]);
            if (e.message().find("used more than once") == std::string::npos) break;
          }
        throw Error(at, "[mesh] " + e.message());
      }
      if (mp.text("transform") == "polar")
        for (auto& x : model.mesh.nodes) {
          const double r = x.x(), t = x.y() * std::numbers::pi / 180.0;
          x = Eigen::Vector2d(r * std::cos(t), r * std::sin(t));
        }
    } else {
      if (mt.get("blocks"))
        throw Error(location(*mt.get("blocks")), "[mesh] blocks are only used with generator = \"blocks\"");
      if (mp.text("file").empty())
        throw Error(location(mt), "[mesh] generator = \"gmsh\" needs file = \"...\"");
      fs::path f = mp.text("file");
      if (f.is_relative()) f = fs::path(path).parent_path() / f;
      std::error_code ec;
      if (!fs::is_regular_file(f, ec))
        throw Error(mp.where("file"), "[mesh] file = \"" + mp.text("file") + "\": " +
                                          (fs::exists(f, ec) ? "is not a regular file (a folder?)"
                                                             : "no such file ('" + f.string() + "')") +
                                          "; give a Gmsh .msh 4.1 ASCII file");
      model.mesh = read_gmsh(f.string());
    }
    model.mesh.check();
    if (!pile_cells.empty() && !model.mesh.cell_sets.count(pile_cells))
      throw Error(pile_cells_at,
                  "[output] pile_cells = \"" + pile_cells +
                      "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
    if (model.formulation == Formulation::axisymmetric)
      for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n)
        if (model.mesh.nodes[n].x() < -1e-12)
          throw Error(location(mt), "[mesh] node " + std::to_string(n) + " has a negative radius x = " +
                                        std::to_string(model.mesh.nodes[n].x()) +
                                        " in an axisymmetric scene");
  }
}

} // namespace stratum
