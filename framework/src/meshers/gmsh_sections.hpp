// Gmsh MSH 4.1 ASCII: the sections of a file as read (gmsh_sections.cpp), before they are made
// into a Mesh (gmsh_reader.cpp). Internal to the framework.
#pragma once

#include "stratum/mesh.hpp"

#include "gmsh_lexer.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace stratum::gmsh {

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

/// Number of corners of a cell read from the file: 3 for a triangle (slot 3 empty), else 4.
inline int corners(const Cell& c) { return c.nodes[3] < 0 ? 3 : 4; }

/// A coordinate for a message: 10 significant digits.
[[nodiscard]] std::string num(double v);

/// $MeshFormat (must come first: version 4.1, ASCII).
void read_format(Lexer& lx);
/// $PhysicalNames, $Entities, $Nodes, $Elements into `f`; `section` is the section's opening token.
void read_physical_names(Lexer& lx, GmshFile& f);
void read_entities(Lexer& lx, GmshFile& f);
void read_nodes(Lexer& lx, GmshFile& f, const Token& section);
void read_elements(Lexer& lx, GmshFile& f, const Token& section);

} // namespace stratum::gmsh
