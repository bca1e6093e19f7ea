// Gmsh MSH 4.1 ASCII: reading the sections of a file (gmsh_sections.hpp); every error names
// file:line:column. What the sections become: gmsh_reader.cpp.
#include "gmsh_sections.hpp"

#include "stratum/error.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string_view>

namespace stratum::gmsh {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

namespace {

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

} // namespace

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
    if (f.names.count({dim, tag}))
      lx.fail(at, "physical group " + std::to_string(tag) + " of dimension " + std::to_string(dim) +
                      " is named twice; each (dimension, tag) pair has one name");
    for (const auto& [key, other] : f.names)
      if (key.first == dim && other.name == text)
        lx.fail(name, "the physical name \"" + text + "\" is given to groups " + std::to_string(key.second) +
                          " and " + std::to_string(tag) + " of dimension " + std::to_string(dim) +
                          "; the scene would act on both under one name: rename one in Gmsh");
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
        q.cell.type = CellType::triangle;
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

} // namespace stratum::gmsh
