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

#include "gmsh_lexer.hpp"

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

using gmsh::Lexer;
using gmsh::Token;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// What we know about a Gmsh element type.
struct ElementType {
  int dim = -1;  ///< -1: unknown type
  int nodes = 0; ///< nodes per element
  const char* name = "";
  bool supported = false;
};

ElementType element_type(long long type) {
  switch (type) {
  case 1:
    return {1, 2, "2-node line", true};
  case 8:
    return {1, 3, "3-node line", true};
  case 15:
    return {0, 1, "point", true};
  case 3:
    return {2, 4, "4-node quadrangle", true};
  case 16:
    return {2, 8, "8-node quadrangle", true};
  case 10:
    return {2, 9, "9-node quadrangle", true};
  case 2:
    return {2, 3, "triangle", true};
  case 9:
    return {2, 6, "6-node triangle", true};
  case 20:
    return {2, 9, "9-node triangle", false};
  case 21:
    return {2, 10, "10-node triangle", false};
  case 36:
    return {2, 16, "16-node quadrangle", false};
  case 37:
    return {2, 25, "25-node quadrangle", false};
  case 26:
    return {1, 4, "4-node line", false};
  case 27:
    return {1, 5, "5-node line", false};
  case 28:
    return {1, 6, "6-node line", false};
  case 4:
    return {3, 4, "tetrahedron", false};
  case 5:
    return {3, 8, "hexahedron", false};
  case 6:
    return {3, 6, "prism", false};
  case 7:
    return {3, 5, "pyramid", false};
  case 11:
    return {3, 10, "10-node tetrahedron", false};
  case 12:
    return {3, 27, "27-node hexahedron", false};
  case 17:
    return {3, 20, "20-node hexahedron", false};
  default:
    return {};
  }
}

// Maps Gmsh node tags to indices in file order.
class NodeTags {
public:
  void reserve(std::size_t max_tag, std::size_t count) {
    if (max_tag <= 4 * count + 1024) dense_.assign(max_tag + 1, -1);
  }
  bool add(std::size_t tag, int index) {
    if (tag < dense_.size()) {
      if (dense_[tag] >= 0) return false;
      dense_[tag] = index;
      return true;
    }
    return sparse_.emplace(tag, index).second;
  }
  [[nodiscard]] int find(std::size_t tag) const {
    if (tag < dense_.size()) return dense_[tag];
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? -1 : it->second;
  }

private:
  std::vector<int> dense_;
  std::unordered_map<std::size_t, int> sparse_;
};

struct QuadElement {
  Cell cell;
  int entity;
  long long tag;
  Token at;
};

struct LineElement {
  std::array<int, 3> nodes{-1, -1, -1};
  int entity;
  long long tag;
  Token at;
};

struct PointElement {
  int node;
  int entity;
  long long tag;
  Token at;
};

struct PhysicalName {
  std::string name;
  Token at;
};

using DimTag = std::pair<int, int>;

struct GmshFile {
  std::map<DimTag, PhysicalName> names;        ///< (dim, physical tag) -> name
  std::map<DimTag, std::vector<int>> physical; ///< (dim, entity tag) -> physical tags
  std::vector<Eigen::Vector2d> nodes;
  NodeTags tags;
  bool have_nodes = false, have_elements = false;
  std::vector<QuadElement> quads;
  std::vector<LineElement> lines;
  std::vector<PointElement> points;
};

void read_format(Lexer& lx) {
  const Token first = lx.next();
  if (first.text != "$MeshFormat")
    lx.fail(first,
            "not a Gmsh mesh file: expected $MeshFormat, found " +
                (first.text.empty() ? std::string("end of file") : "'" + std::string(first.text) + "'"));
  const Token version = lx.need("the format version");
  Token type_at;
  const long long file_type = lx.integer("the file type", &type_at);
  if (version.text != "4.1")
    lx.fail(version, "Gmsh format version " + std::string(version.text) +
                         " is not supported; save the mesh as version 4.1 ASCII");
  if (file_type == 1) lx.fail(type_at, "binary .msh is not supported; save as ASCII 4.1");
  if (file_type != 0) lx.fail(type_at, "file type " + std::to_string(file_type) + " is not 0 (ASCII)");
  lx.integer("the data size");
  lx.expect("$EndMeshFormat");
}

void read_physical_names(Lexer& lx, GmshFile& f) {
  const int n = lx.count("the number of physical names");
  for (int i = 0; i < n; ++i) {
    Token at;
    const int dim = lx.count("a physical dimension", &at);
    const int tag = static_cast<int>(lx.integer("a physical tag"));
    const Token name = lx.need("a physical name");
    if (name.text.size() < 2 || name.text.front() != '"' || name.text.back() != '"')
      lx.fail(name, "expected a quoted physical name, found '" + std::string(name.text) + "'");
    std::string text(name.text.substr(1, name.text.size() - 2));
    if (text.empty()) text = "physical_" + std::to_string(tag);
    f.names[{dim, tag}] = {std::move(text), at};
  }
  lx.expect("$EndPhysicalNames");
}

void read_entities(Lexer& lx, GmshFile& f) {
  int counts[4];
  for (int& c : counts) c = lx.count("the number of entities");
  for (int dim = 0; dim < 4; ++dim)
    for (int i = 0; i < counts[dim]; ++i) {
      const int tag = static_cast<int>(lx.integer("an entity tag"));
      const int coordinates = dim == 0 ? 3 : 6;
      for (int k = 0; k < coordinates; ++k) lx.real("an entity coordinate");
      const int n = lx.count("the number of physical tags");
      std::vector<int>& phys = f.physical[{dim, tag}];
      for (int k = 0; k < n; ++k) phys.push_back(static_cast<int>(lx.integer("a physical tag")));
      if (dim > 0) {
        const int nb = lx.count("the number of bounding entities");
        for (int k = 0; k < nb; ++k) lx.integer("a bounding entity tag");
      }
    }
  lx.expect("$EndEntities");
}

void read_nodes(Lexer& lx, GmshFile& f, const Token& section) {
  if (f.have_nodes) lx.fail(section, "a second $Nodes section");
  f.have_nodes = true;
  const int blocks = lx.count("the number of node blocks");
  const int total = lx.count("the number of nodes");
  lx.integer("the smallest node tag");
  Token max_at;
  const long long max_tag = lx.integer("the largest node tag", &max_at);
  if (max_tag < 0) lx.fail(max_at, "negative node tag");
  f.tags.reserve(static_cast<std::size_t>(max_tag), static_cast<std::size_t>(total));
  f.nodes.reserve(static_cast<std::size_t>(total));
  std::vector<std::pair<long long, Token>> tags;
  for (int b = 0; b < blocks; ++b) {
    const int dim = lx.count("an entity dimension");
    lx.integer("an entity tag");
    Token par_at;
    const long long parametric = lx.integer("the parametric flag", &par_at);
    if (parametric != 0 && parametric != 1) lx.fail(par_at, "the parametric flag must be 0 or 1");
    const int n = lx.count("the number of nodes in the block");
    tags.clear();
    for (int i = 0; i < n; ++i) {
      Token at;
      const long long tag = lx.integer("a node tag", &at);
      if (tag < 0) lx.fail(at, "negative node tag " + std::to_string(tag));
      tags.emplace_back(tag, at);
    }
    const int extra = parametric ? std::min(dim, 3) : 0;
    for (int i = 0; i < n; ++i) {
      Token at;
      const double x = lx.real("a node coordinate", &at);
      const double y = lx.real("a node coordinate");
      Token z_at;
      const double z = lx.real("a node coordinate", &z_at);
      for (int k = 0; k < extra; ++k) lx.real("a parametric coordinate");
      if (z != 0.0)
        lx.fail(z_at, "node " + std::to_string(tags[i].first) + " has z = " + num(z) +
                          "; only 2D meshes in the x-y plane (z = 0) are supported");
      if (!f.tags.add(static_cast<std::size_t>(tags[i].first), static_cast<int>(f.nodes.size())))
        lx.fail(tags[i].second, "node tag " + std::to_string(tags[i].first) + " is used twice");
      f.nodes.emplace_back(x, y);
    }
  }
  lx.expect("$EndNodes");
}

void read_elements(Lexer& lx, GmshFile& f, const Token& section) {
  if (!f.have_nodes) lx.fail(section, "$Elements before $Nodes");
  if (f.have_elements) lx.fail(section, "a second $Elements section");
  f.have_elements = true;
  const int blocks = lx.count("the number of element blocks");
  lx.count("the number of elements");
  lx.integer("the smallest element tag");
  lx.integer("the largest element tag");
  for (int b = 0; b < blocks; ++b) {
    Token header;
    lx.count("an entity dimension", &header);
    const int entity = static_cast<int>(lx.integer("an entity tag"));
    Token type_at;
    const long long type = lx.integer("an element type", &type_at);
    const ElementType et = element_type(type);
    if (et.dim < 0) lx.fail(type_at, "unknown element type " + std::to_string(type));
    if (!et.supported) {
      const std::string what =
          "element type " + std::to_string(type) + " (" + et.name + ") is not supported; ";
      if (et.dim == 1) lx.fail(type_at, what + "allowed lines: 2- and 3-node");
      if (et.dim == 3)
        lx.fail(type_at,
                what + "meshes are 2D; allowed: 3- and 6-node triangles, 4-, 8- and 9-node quadrangles");
      lx.fail(type_at,
              what + "allowed: 3- and 6-node triangles (gmsh -order 1 or 2), 4-, 8- and 9-node quadrangles");
    }
    const int n = lx.count("the number of elements in the block");
    int nodes[9];
    for (int e = 0; e < n; ++e) {
      Token at;
      const long long tag = lx.integer("an element tag", &at);
      for (int k = 0; k < et.nodes; ++k) {
        Token node_at;
        const long long t = lx.integer("a node tag", &node_at);
        nodes[k] = t < 0 ? -1 : f.tags.find(static_cast<std::size_t>(t));
        if (nodes[k] < 0)
          lx.fail(node_at, "element " + std::to_string(tag) + " refers to node " + std::to_string(t) +
                               ", which is not in $Nodes");
      }
      if (et.dim == 2 && (type == 2 || type == 9)) {
        // Triangle: corners to slots 0-2, midside nodes (Gmsh order 0-1, 1-2, 2-0) to slots 4-6.
        QuadElement q{Cell{}, entity, tag, at};
        for (int k = 0; k < et.nodes; ++k) q.cell.nodes[k < 3 ? k : k + 1] = nodes[k];
        f.quads.push_back(q);
      } else if (et.dim == 2) {
        QuadElement q{Cell{}, entity, tag, at};
        for (int k = 0; k < std::min(et.nodes, 8); ++k) q.cell.nodes[k] = nodes[k];
        f.quads.push_back(q);
      } else if (et.dim == 1) {
        LineElement l{{-1, -1, -1}, entity, tag, at};
        for (int k = 0; k < et.nodes; ++k) l.nodes[k] = nodes[k];
        f.lines.push_back(l);
      } else {
        f.points.push_back({nodes[0], entity, tag, at});
      }
    }
  }
  lx.expect("$EndElements");
}

// Number of corners of a cell read from the file: 3 for a triangle (slot 3 empty), else 4.
int corners(const Cell& c) { return c.nodes[3] < 0 ? 3 : 4; }

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

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (hi << 32) | lo;
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

Mesh build(const Lexer& lx, GmshFile& f, const Token& end) {
  if (f.quads.empty())
    lx.fail(end, "no quadrangles (4-, 8- or 9-node) or triangles (3- or 6-node) in the mesh");
  for (QuadElement& q : f.quads) orient(lx, q, f.nodes);

  // Keep the nodes of the cells, in file order.
  std::vector<int> index(f.nodes.size(), -1);
  for (const QuadElement& q : f.quads)
    for (int v : q.cell.nodes)
      if (v >= 0) index[v] = 0;
  Mesh mesh;
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
  return mesh;
}

} // namespace

Mesh read_gmsh(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open mesh file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error("cannot read mesh file '" + path + "'");

  Lexer lx(path, std::move(text).str());
  GmshFile f;
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
