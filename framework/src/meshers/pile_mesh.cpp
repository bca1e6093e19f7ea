#include "stratum/mesh_io.hpp"

#include <algorithm>
#include <string>

namespace stratum {

Mesh generate_pile(const PileMesh& s) {
  auto fail = [](const std::string& what) { throw Error("[mesh.pile] " + what); };
  if (!(s.radius > 0 && s.length > 0)) fail("radius and length must be > 0");
  if (!(s.near_radius > s.radius)) fail("near_radius must exceed the pile radius");
  if (!(s.domain_radius > s.near_radius)) fail("domain_radius must exceed near_radius");
  if (!(s.near_depth > s.length)) fail("near_depth must exceed the pile length");
  if (!(s.domain_depth > s.near_depth)) fail("domain_depth must exceed near_depth");
  const double a = s.radius, rn = s.near_radius, R = s.domain_radius;
  const double L = s.length, dn = s.near_depth, D = s.domain_depth;
  // Columns: pile, near, far. Rows (top down): shaft, below the base, deep.
  struct Col {
    const char* name;
    double x0, x1;
    int n;
    double g;
  };
  struct Row {
    const char* name;
    double y0, y1;
    int n;
    double g;
  };
  const Col cols[3] = {{"pile", 0.0, a, s.n_pile, 1.0},
                       {"near", a, rn, s.n_near, s.grade_near},
                       {"far", rn, R, s.n_far, s.grade_far}};
  // Grading along y runs from y0 up to y1: below the base and deep rows get finer upwards.
  const Row rows[3] = {{"shaft", -L, 0.0, s.n_shaft, 1.0},
                       {"below", -dn, -L, s.n_below, 1.0 / s.grade_below},
                       {"deep", -D, -dn, s.n_deep, 1.0 / s.grade_deep}};
  std::vector<Block> blocks;
  for (const auto& r : rows)
    for (const auto& c : cols) {
      Block b;
      b.name = std::string(c.name) + "_" + r.name;
      b.x0 = c.x0, b.x1 = c.x1, b.y0 = r.y0, b.y1 = r.y1;
      b.nx = c.n, b.ny = r.n, b.grade_x = c.g, b.grade_y = r.g;
      blocks.push_back(b);
    }
  Mesh m = generate_blocks(blocks, s.nodes_per_cell);
  auto cells_of = [&](std::initializer_list<const char*> names) {
    std::vector<int> v;
    for (const char* n : names) {
      const auto& c = m.cell_sets.at(n);
      v.insert(v.end(), c.begin(), c.end());
    }
    std::sort(v.begin(), v.end());
    return v;
  };
  m.cell_sets["bore"] = m.cell_sets.at("pile_shaft");
  m.cell_sets["near"] = cells_of({"near_shaft", "pile_below", "near_below"});
  m.cell_sets["far"] = cells_of({"far_shaft", "far_below", "pile_deep", "near_deep", "far_deep"});
  m.cell_sets["soil"] = cells_of({"pile_shaft", "near_shaft", "pile_below", "near_below", "far_shaft",
                                  "far_below", "pile_deep", "near_deep", "far_deep"});
  // The pile: copies of the bore cells on the same nodes (an interface split gives it its own).
  std::vector<int> pile;
  for (int c : m.cell_sets.at("bore")) {
    pile.push_back(static_cast<int>(m.cells.size()));
    m.cells.push_back(m.cells[static_cast<std::size_t>(c)]);
  }
  m.cell_sets["pile"] = pile;
  m.cell_sets["all"].insert(m.cell_sets["all"].end(), pile.begin(), pile.end());
  // The borehole seen from the soil: down the shaft wall, then along the base towards the axis.
  std::vector<Edge> shaft = m.edge_sets.at("near_shaft.left"), base = m.edge_sets.at("pile_below.top");
  auto by = [](const Mesh& mesh, bool down) {
    return [&mesh, down](const Edge& e1, const Edge& e2) {
      const double y1 = mesh.nodes[e1.a].y(), y2 = mesh.nodes[e2.a].y();
      const double x1 = mesh.nodes[e1.a].x(), x2 = mesh.nodes[e2.a].x();
      return down ? y1 > y2 : x1 > x2;
    };
  };
  std::sort(shaft.begin(), shaft.end(), by(m, true));
  std::sort(base.begin(), base.end(), by(m, false));
  std::vector<Edge> hole = shaft;
  hole.insert(hole.end(), base.begin(), base.end());
  m.add_edge_set("shaft", shaft);
  m.add_edge_set("base", base);
  m.add_edge_set("hole", hole);
  m.add_edge_set("axis", m.edge_sets.at("left"));
  m.add_edge_set("surface", m.edge_sets.at("top"));
  m.add_edge_set("far_side", m.edge_sets.at("right"));
  return m;
}

} // namespace stratum
