// Gmsh MSH 4.1 ASCII import.
//
// Quadrangles (4-, 8- and 9-node, the centre node of the 9-node one dropped) and triangles
// (3- and 6-node) become cells, turned counter-clockwise where needed. A triangle takes the
// slots of a quadrangle without corner 3: corners 0 1 2, midside 4 (edge 0-1), 5 (1-2), 6 (2-0),
// which is Gmsh's own order. Nodes no cell uses are dropped and the rest numbered 0, 1, ...
// in file order. Physical groups become sets: dimension 2 -> cell sets (a group holding both
// triangles and quadrangles also gets the sets "<name>.triangles" and "<name>.quadrangles",
// one per element kind), 1 -> edge sets (each edge oriented along the counter-clockwise
// boundary of the cell it belongs to; a line inside the body, between two cells, follows the
// one that comes first in the file), 0 -> node sets. Every error names file:line:column.
#include "stratum/mesh_io.hpp"

#include "edge_key.hpp"
#include "files.hpp"
#include "gmsh_sections.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string_view>
#include <unordered_map>

namespace stratum {
namespace {

using gmsh::corners;
using gmsh::GmshFile;
using gmsh::Lexer;
using gmsh::LineElement;
using gmsh::num;
using gmsh::PointElement;
using gmsh::QuadElement;
using gmsh::Token;

// Turns a clockwise triangle counter-clockwise and checks its area.
void orient_triangle(const Lexer& lx, QuadElement& q, const std::vector<Eigen::Vector2d>& x) {
  auto& c = q.cell.nodes;
  const Eigen::Vector2d a = x[c[1]] - x[c[0]], b = x[c[2]] - x[c[0]];
  const double area2 = a.x() * b.y() - a.y() * b.x();
  if (area2 < 0) {
    // Corners 0 2 1; the midside nodes follow their edges (0-2 was 2-0, 1-0 was 0-1).
    std::swap(c[1], c[2]);
    std::swap(c[4], c[6]);
  }
  if (!(std::abs(area2) > 0))
    lx.fail(q.at, "triangle " + std::to_string(q.tag) + " is degenerate (zero area) at (" + num(x[c[0]].x()) +
                      ", " + num(x[c[0]].y()) + ")");
}

// Turns a clockwise quadrangle counter-clockwise and checks that it is convex.
void orient(const Lexer& lx, QuadElement& q, const std::vector<Eigen::Vector2d>& x) {
  if (corners(q.cell) == 3) return orient_triangle(lx, q, x);
  auto& c = q.cell.nodes;
  double area2 = 0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = x[c[k]];
    const Eigen::Vector2d& r = x[c[(k + 1) % 4]];
    area2 += p.x() * r.y() - r.x() * p.y();
  }
  if (area2 < 0) {
    // Corners 0 3 2 1; the midside nodes follow their edges (0-3 was 3-0, ...).
    std::swap(c[1], c[3]);
    std::swap(c[4], c[7]);
    std::swap(c[5], c[6]);
  }
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = x[c[k]];
    const Eigen::Vector2d next = x[c[(k + 1) % 4]] - p;
    const Eigen::Vector2d prev = x[c[(k + 3) % 4]] - p;
    if (!(next.x() * prev.y() - next.y() * prev.x() > 0))
      lx.fail(q.at, "quadrangle " + std::to_string(q.tag) + " is degenerate or not convex at (" + num(p.x()) +
                        ", " + num(p.y()) + ")");
  }
}

std::string kind_of(const Cell& c) {
  return std::to_string(c.count()) + "-node " + (corners(c) == 3 ? "triangle" : "quadrangle");
}

std::string group_name(const GmshFile& f, int dim, int tag) {
  const auto it = f.names.find({dim, tag});
  return it != f.names.end() ? it->second.name : "physical_" + std::to_string(tag);
}

const std::vector<int>& groups_of(const GmshFile& f, int dim, int entity) {
  static const std::vector<int> none;
  const auto it = f.physical.find({dim, entity});
  return it == f.physical.end() ? none : it->second;
}

/// The cells' nodes (in file order) and the cells into the mesh; returns each file node's
/// number in the mesh (-1: not a node of a cell).
std::vector<int> nodes_and_cells(const GmshFile& f, Mesh& mesh) {
  // Keep the nodes of the cells, in file order.
  std::vector<int> index(f.nodes.size(), -1);
  for (const QuadElement& q : f.quads)
    for (int v : q.cell.nodes)
      if (v >= 0) index[v] = 0;
  for (std::size_t i = 0; i < f.nodes.size(); ++i)
    if (index[i] == 0) {
      index[i] = static_cast<int>(mesh.nodes.size());
      mesh.nodes.push_back(f.nodes[i]);
    }
  mesh.cells.reserve(f.quads.size());
  for (const QuadElement& q : f.quads) {
    Cell c = q.cell;
    for (int& v : c.nodes)
      if (v >= 0) v = index[v];
    mesh.cells.push_back(c);
  }

  return index;
}

/// Checks the physical names (the reserved one, point and curve groups of one name) and makes
/// the (possibly empty) cell and node sets of the named groups.
void check_names(const Lexer& lx, const GmshFile& f, Mesh& mesh) {
  // The reserved name and clashes between node sets of curve and point groups.
  for (const auto& [key, pn] : f.names) {
    if (key.first == 2 && pn.name == "all")
      lx.fail(pn.at, "physical name 'all' is reserved for the set of all cells");
    if (key.first == 0)
      for (const auto& [other, on] : f.names)
        if (other.first == 1 && on.name == pn.name)
          lx.fail(pn.at, "physical name '" + pn.name + "' is used by a point group and a curve group");
  }
  for (const auto& [key, pn] : f.names) {
    if (key.first == 2) mesh.cell_sets[pn.name];
    if (key.first == 0) mesh.node_sets[pn.name];
  }
}

/// The cell sets of the surface groups and "all", and the split of the mixed ones.
void make_cell_sets(const Lexer& lx, const GmshFile& f, Mesh& mesh, const Token& end) {
  // Cell sets.
  for (std::size_t c = 0; c < f.quads.size(); ++c)
    for (int tag : groups_of(f, 2, f.quads[c].entity)) {
      std::string name = group_name(f, 2, tag);
      if (name == "all") lx.fail(f.quads[c].at, "physical name 'all' is reserved for the set of all cells");
      mesh.cell_sets[name].push_back(static_cast<int>(c));
    }
  for (auto& [name, cells] : mesh.cell_sets) {
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  }
  mesh.add_all_set();
  // A set with both triangles and quadrangles is split by kind as well, so that each part can
  // be given its own element (a domain has one element kind).
  std::map<std::string, std::vector<int>> split;
  for (const auto& [name, cells] : mesh.cell_sets) {
    std::vector<int> tri, quad;
    for (int c : cells) (corners(mesh.cells[static_cast<std::size_t>(c)]) == 3 ? tri : quad).push_back(c);
    if (tri.empty() || quad.empty()) continue;
    split[name + ".triangles"] = std::move(tri);
    split[name + ".quadrangles"] = std::move(quad);
  }
  for (auto& [name, cells] : split) {
    if (mesh.cell_sets.count(name))
      throw Error(SourceLocation{lx.path(), end.line, end.column},
                  "the cell set '" + name +
                      "' made for a mixed physical group is also a physical group's name");
    mesh.cell_sets[name] = std::move(cells);
  }
}

/// The edge sets of the curve groups.
void make_edge_sets(const Lexer& lx, const GmshFile& f, Mesh& mesh, const std::vector<int>& index) {
  // Edge sets: orient every grouped line along the boundary of a quadrangle that has it.
  std::unordered_map<std::uint64_t, std::size_t> wanted;
  for (std::size_t l = 0; l < f.lines.size(); ++l)
    if (!groups_of(f, 1, f.lines[l].entity).empty())
      wanted.emplace(edge_key(f.lines[l].nodes[0], f.lines[l].nodes[1]), l);
  std::unordered_map<std::uint64_t, std::pair<int, int>> owner; // edge -> (cell, local edge)
  for (std::size_t c = 0; c < f.quads.size() && owner.size() < wanted.size(); ++c)
    for (int k = 0, nc = corners(f.quads[c].cell); k < nc; ++k) {
      const auto& n = f.quads[c].cell.nodes;
      const std::uint64_t key = edge_key(n[k], n[(k + 1) % nc]);
      if (wanted.count(key)) owner.emplace(key, std::pair{static_cast<int>(c), k});
    }
  std::map<std::string, std::vector<Edge>> edge_sets;
  for (const auto& [key, pn] : f.names)
    if (key.first == 1) edge_sets[pn.name];
  for (const LineElement& l : f.lines) {
    const std::vector<int>& groups = groups_of(f, 1, l.entity);
    if (groups.empty()) continue;
    const auto it = owner.find(edge_key(l.nodes[0], l.nodes[1]));
    if (it == owner.end())
      lx.fail(l.at, "line " + std::to_string(l.tag) + " of physical group '" + group_name(f, 1, groups[0]) +
                        "' is not a side of any cell");
    const auto [c, k] = it->second;
    const Cell& cell = f.quads[c].cell;
    Edge e{index[cell.nodes[k]], index[cell.nodes[(k + 1) % corners(cell)]], -1};
    const int cell_mid = cell.nodes[4 + k];
    if (l.nodes[2] >= 0) {
      if (cell_mid < 0)
        lx.fail(l.at, "3-node line " + std::to_string(l.tag) + " lies on " + kind_of(cell) + " " +
                          std::to_string(f.quads[c].tag) + ", which has no midside node");
      if (l.nodes[2] != cell_mid)
        lx.fail(l.at, "the midside node of line " + std::to_string(l.tag) + " is not the midside node of " +
                          kind_of(cell) + " " + std::to_string(f.quads[c].tag));
    }
    if (cell_mid >= 0) e.mid = index[cell_mid];
    for (int tag : groups) edge_sets[group_name(f, 1, tag)].push_back(e);
  }
  for (auto& [name, edges] : edge_sets) mesh.add_edge_set(name, std::move(edges));
}

/// The node sets of the point groups.
void make_point_sets(const Lexer& lx, const GmshFile& f, Mesh& mesh, const std::vector<int>& index) {
  // Node sets of point groups.
  for (const PointElement& p : f.points)
    for (int tag : groups_of(f, 0, p.entity)) {
      const std::string name = group_name(f, 0, tag);
      if (index[p.node] < 0)
        lx.fail(p.at, "point " + std::to_string(p.tag) + " of physical group '" + name +
                          "' is not a node of any cell");
      if (mesh.edge_sets.count(name))
        lx.fail(p.at, "physical name '" + name + "' is used by a point group and a curve group");
      mesh.node_sets[name].push_back(index[p.node]);
    }
  for (auto& [name, ids] : mesh.node_sets) {
    if (mesh.edge_sets.count(name)) continue;
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  }
}

Mesh build(const Lexer& lx, GmshFile& f, const Token& end) {
  if (f.quads.empty())
    lx.fail(end, "no quadrangles (4-, 8- or 9-node) or triangles (3- or 6-node) in the mesh");
  for (QuadElement& q : f.quads) orient(lx, q, f.nodes);
  Mesh mesh;
  const std::vector<int> index = nodes_and_cells(f, mesh);
  check_names(lx, f, mesh);
  make_cell_sets(lx, f, mesh, end);
  make_edge_sets(lx, f, mesh, index);
  make_point_sets(lx, f, mesh, index);
  return mesh;
}

} // namespace

Mesh read_gmsh(const std::string& path) {
  Lexer lx(path, read_text_file(path, SourceLocation{}, "mesh file", file_limits::mesh));
  GmshFile f;
  using namespace gmsh;
  read_format(lx);
  for (Token t = lx.next();; t = lx.next()) {
    if (t.text.empty()) return build(lx, f, t);
    if (t.text == "$PhysicalNames")
      read_physical_names(lx, f);
    else if (t.text == "$Entities")
      read_entities(lx, f);
    else if (t.text == "$Nodes")
      read_nodes(lx, f, t);
    else if (t.text == "$Elements")
      read_elements(lx, f, t);
    else if (t.text.front() == '$')
      lx.skip_section(t.text.substr(1), t);
    else
      lx.fail(t, "expected a section such as $Nodes, found '" + std::string(t.text) + "'");
  }
}

} // namespace stratum
