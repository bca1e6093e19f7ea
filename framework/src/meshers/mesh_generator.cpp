// The structured block generator: graded rectangles of quad4 or quad8 cells, merged
// where their nodes coincide.
#include "../memory.hpp"

#include "edge_key.hpp"
#include "stratum/mesh_io.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <set>
#include <unordered_map>

namespace stratum {

namespace {

std::string block_label(const Block& b) { return "mesh block '" + b.name + "'"; }

void validate(const std::vector<Block>& blocks, int nodes_per_cell) {
  if (nodes_per_cell != 4 && nodes_per_cell != 8)
    throw Error("mesh generator: nodes_per_cell = " + std::to_string(nodes_per_cell) +
                " is not supported; allowed: 4 (quad4) or 8 (quad8)");
  if (blocks.empty()) throw Error("mesh generator: no mesh blocks given");
  std::set<std::string> names;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const Block& b = blocks[k];
    if (b.name.empty()) throw Error("mesh block " + std::to_string(k + 1) + " (1-based) has an empty name");
    if (b.name == "all") throw Error("mesh block name 'all' is reserved for the set of all cells");
    if (!names.insert(b.name).second) throw Error("mesh block name '" + b.name + "' is used more than once");
    const std::string what = block_label(b);
    for (double v : {b.x0, b.x1, b.y0, b.y1, b.grade_x, b.grade_y})
      if (!std::isfinite(v)) throw Error(what + ": coordinates and gradings must be finite numbers");
    if (!(b.x1 > b.x0))
      throw Error(what + ": x1 = " + number_text(b.x1) + " must be > x0 = " + number_text(b.x0));
    if (!(b.y1 > b.y0))
      throw Error(what + ": y1 = " + number_text(b.y1) + " must be > y0 = " + number_text(b.y0));
    if (b.nx < 1) throw Error(what + ": nx = " + std::to_string(b.nx) + " must be >= 1");
    if (b.ny < 1) throw Error(what + ": ny = " + std::to_string(b.ny) + " must be >= 1");
    if (!(b.grade_x > 0)) throw Error(what + ": grade_x = " + number_text(b.grade_x) + " must be > 0");
    if (!(b.grade_y > 0)) throw Error(what + ": grade_y = " + number_text(b.grade_y) + " must be > 0");
    const int s = nodes_per_cell == 8 ? 2 : 1;
    const std::int64_t grid = (std::int64_t{s} * b.nx + 1) * (std::int64_t{s} * b.ny + 1);
    if (grid > std::numeric_limits<int>::max() / 2)
      throw Error(what + ": " + std::to_string(b.nx) + " x " + std::to_string(b.ny) + " cells is too many");
  }
  // Refused up front rather than by std::bad_alloc after seconds of work: about 4 kB per cell
  // (nodes, cells, sets, point states of a 3 x 3 rule, the sparse matrix and its factors),
  // measured on the pile meshes to within a factor of 2.
  double cells = 0;
  for (const Block& b : blocks) cells += static_cast<double>(b.nx) * static_cast<double>(b.ny);
  const double need = 4096.0 * cells;
  char count[32];
  std::snprintf(count, sizeof count, "%.0f", cells);
  if (const auto no =
          memory_shortfall(need, std::string("mesh blocks: ") + count + " cells", "about 4 kB per cell");
      !no.empty())
    throw Error(no);
}

// n + 1 positions from a to b; the cell sizes form a geometric progression whose
// last / first ratio is `grade`. Each half is computed from its own end so that the
// small cells keep their relative accuracy.
std::vector<double> graded(double a, double b, int n, double grade) {
  std::vector<double> x(static_cast<std::size_t>(n) + 1);
  const double len = b - a;
  const double lr = n > 1 ? std::log(grade) / (n - 1) : 0.0;
  for (int i = 0; i <= n; ++i) {
    if (lr == 0.0) {
      x[i] = i <= n / 2 ? a + len * i / n : b - len * (n - i) / n;
    } else {
      const double den = std::expm1(n * lr);
      x[i] = i <= n / 2 ? a + len * (std::expm1(i * lr) / den)
                        : b - len * (std::exp(i * lr) * std::expm1((n - i) * lr) / den);
    }
  }
  x.front() = a;
  x.back() = b;
  return x;
}

// Positions of the fine grid: corners, and for quad8 (s = 2) the midpoints between them.
std::vector<double> fine_grid(const std::vector<double>& corners, int s) {
  if (s == 1) return corners;
  const std::size_t n = corners.size() - 1;
  std::vector<double> f(2 * n + 1);
  for (std::size_t i = 0; i <= n; ++i) f[2 * i] = corners[i];
  for (std::size_t i = 0; i < n; ++i) f[2 * i + 1] = 0.5 * (corners[i] + corners[i + 1]);
  return f;
}

// Finds nodes within `tol` (max-norm) of a point: a hash of tol-sized grid cells.
class NodeIndex {
public:
  NodeIndex(double x0, double y0, double tol) : x0_(x0), y0_(y0), tol_(tol) {}

  [[nodiscard]] int find(const std::vector<Eigen::Vector2d>& nodes, const Eigen::Vector2d& p) const {
    const auto [qx, qy] = quantize(p);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = map_.find(key(qx + dx, qy + dy));
        if (it != map_.end() && (nodes[it->second] - p).cwiseAbs().maxCoeff() <= tol_) return it->second;
      }
    return -1;
  }
  void insert(const Eigen::Vector2d& p, int id) {
    const auto [qx, qy] = quantize(p);
    map_.emplace(key(qx, qy), id);
  }

private:
  [[nodiscard]] std::pair<std::int64_t, std::int64_t> quantize(const Eigen::Vector2d& p) const {
    return {static_cast<std::int64_t>(std::floor((p.x() - x0_) / tol_)),
            static_cast<std::int64_t>(std::floor((p.y() - y0_) / tol_))};
  }
  static std::uint64_t key(std::int64_t qx, std::int64_t qy) {
    return (static_cast<std::uint64_t>(qx + 1) << 32) ^ static_cast<std::uint64_t>(qy + 1);
  }
  double x0_, y0_, tol_;
  std::unordered_map<std::uint64_t, int> map_;
};

enum Side { bottom, right, top, left };
constexpr const char* side_names[] = {"bottom", "right", "top", "left"};

// A boundary edge of a block with the block and side it belongs to.
struct SideEdge {
  Edge edge;
  std::size_t block;
  Side side;
};

// The blocks' bounding box and the tolerance for telling coordinates apart.
struct Bounds {
  double xmin, xmax, ymin, ymax, tol;
};

/// The bounding box of the blocks; throws where two blocks overlap.
Bounds bounds_of(const std::vector<Block>& blocks) {
  double xmin = blocks[0].x0, xmax = blocks[0].x1, ymin = blocks[0].y0, ymax = blocks[0].y1;
  for (const Block& b : blocks) {
    xmin = std::min(xmin, b.x0);
    xmax = std::max(xmax, b.x1);
    ymin = std::min(ymin, b.y0);
    ymax = std::max(ymax, b.y1);
  }
  const double tol = 1e-9 * std::max(xmax - xmin, ymax - ymin);

  for (std::size_t i = 0; i < blocks.size(); ++i)
    for (std::size_t j = i + 1; j < blocks.size(); ++j) {
      const Block& p = blocks[i];
      const Block& q = blocks[j];
      const double w = std::min(p.x1, q.x1) - std::max(p.x0, q.x0);
      const double h = std::min(p.y1, q.y1) - std::max(p.y0, q.y0);
      if (w > tol && h > tol) throw Error(block_label(p) + " and " + block_label(q) + " overlap");
    }
  return {xmin, xmax, ymin, ymax, tol};
}

/// Reserves the mesh's nodes and cells; throws when the node count does not fit an int.
void reserve(Mesh& mesh, const std::vector<Block>& blocks, int s) {
  std::size_t total_nodes = 0, total_cells = 0;
  for (const Block& b : blocks) {
    total_nodes += static_cast<std::size_t>(s * b.nx + 1) * static_cast<std::size_t>(s * b.ny + 1);
    total_cells += static_cast<std::size_t>(b.nx) * static_cast<std::size_t>(b.ny);
  }
  if (total_nodes > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw Error("mesh generator: too many nodes (" + std::to_string(total_nodes) + ")");
  mesh.nodes.reserve(total_nodes);
  mesh.cells.reserve(total_cells);
}

/// One block's node grid (s = 2: with midside points) as global node numbers.
class BlockGrid {
public:
  BlockGrid(int nx, int ny, int s) : s(s), nxf(s * nx), nyf(s * ny) {}
  [[nodiscard]] std::size_t at(int i, int j) const { return static_cast<std::size_t>(j) * (nxf + 1) + i; }
  /// The edge from grid point (ia, ja) to (ib, jb) (with its midside node for s = 2).
  [[nodiscard]] Edge edge(const std::vector<int>& id, int ia, int ja, int ib, int jb) const {
    Edge e{id[at(ia, ja)], id[at(ib, jb)], -1};
    if (s == 2) e.mid = id[at((ia + ib) / 2, (ja + jb) / 2)];
    return e;
  }
  const int s, nxf, nyf;
};

/// The block's nodes into the mesh, id[] their numbers on its grid; a boundary node that another
/// block already made is shared.
void block_nodes(Mesh& mesh, const Block& b, const BlockGrid& g, double tol, NodeIndex& boundary_nodes,
                 std::vector<int>& id) {
  const int s = g.s, nxf = g.nxf, nyf = g.nyf;
  const std::vector<double> xc = graded(b.x0, b.x1, b.nx, b.grade_x);
  const std::vector<double> yc = graded(b.y0, b.y1, b.ny, b.grade_y);
  for (const std::vector<double>* c : {&xc, &yc})
    for (std::size_t i = 0; i + 1 < c->size(); ++i)
      if (!((*c)[i + 1] - (*c)[i] > 2 * tol * s))
        throw Error(block_label(b) + ": the grading makes a cell of size " +
                    number_text((*c)[i + 1] - (*c)[i]) + ", too small to tell its nodes apart");
  const std::vector<double> xf = fine_grid(xc, s);
  const std::vector<double> yf = fine_grid(yc, s);

  // Nodes: row by row along the shorter side, so that the bandwidth stays small.
  id.assign(static_cast<std::size_t>(nxf + 1) * (nyf + 1), -1);
  std::vector<std::pair<Eigen::Vector2d, int>> new_boundary;
  const bool rows_along_x = nxf <= nyf;
  const int outer_n = rows_along_x ? nyf : nxf, inner_n = rows_along_x ? nxf : nyf;
  for (int o = 0; o <= outer_n; ++o)
    for (int in = 0; in <= inner_n; ++in) {
      const int i = rows_along_x ? in : o, j = rows_along_x ? o : in;
      if (s == 2 && i % 2 == 1 && j % 2 == 1) continue; // no centre node
      const Eigen::Vector2d p(xf[i], yf[j]);
      const bool on_boundary = i == 0 || j == 0 || i == nxf || j == nyf;
      int n = on_boundary ? boundary_nodes.find(mesh.nodes, p) : -1;
      if (n < 0) {
        n = static_cast<int>(mesh.nodes.size());
        mesh.nodes.push_back(p);
        if (on_boundary) new_boundary.emplace_back(p, n);
      }
      id[g.at(i, j)] = n;
    }
  for (const auto& [p, n] : new_boundary) boundary_nodes.insert(p, n);
}

/// The block's cells, row by row, into the mesh and its cell set.
void block_cells(Mesh& mesh, const Block& b, const BlockGrid& g, const std::vector<int>& id) {
  const int s = g.s;
  std::vector<int>& set = mesh.cell_sets[b.name];
  set.reserve(static_cast<std::size_t>(b.nx) * b.ny);
  for (int j = 0; j < b.ny; ++j)
    for (int i = 0; i < b.nx; ++i) {
      const int i0 = s * i, j0 = s * j, i1 = i0 + s, j1 = j0 + s;
      Cell c;
      c.nodes[0] = id[g.at(i0, j0)];
      c.nodes[1] = id[g.at(i1, j0)];
      c.nodes[2] = id[g.at(i1, j1)];
      c.nodes[3] = id[g.at(i0, j1)];
      if (s == 2) {
        c.nodes[4] = id[g.at(i0 + 1, j0)];
        c.nodes[5] = id[g.at(i1, j0 + 1)];
        c.nodes[6] = id[g.at(i0 + 1, j1)];
        c.nodes[7] = id[g.at(i0, j0 + 1)];
      }
      set.push_back(static_cast<int>(mesh.cells.size()));
      mesh.cells.push_back(c);
    }
}

/// Block k's sides as edge sets <name>.bottom, ... (each following the counter-clockwise boundary
/// of the block), their edges also into side_edges.
void block_sides(Mesh& mesh, const Block& b, std::size_t k, const BlockGrid& g, const std::vector<int>& id,
                 std::vector<SideEdge>& side_edges) {
  const int s = g.s, nxf = g.nxf, nyf = g.nyf;
  std::vector<Edge> sides[4];
  for (int i = 0; i < b.nx; ++i) sides[bottom].push_back(g.edge(id, s * i, 0, s * (i + 1), 0));
  for (int j = 0; j < b.ny; ++j) sides[right].push_back(g.edge(id, nxf, s * j, nxf, s * (j + 1)));
  for (int i = b.nx - 1; i >= 0; --i) sides[top].push_back(g.edge(id, s * (i + 1), nyf, s * i, nyf));
  for (int j = b.ny - 1; j >= 0; --j) sides[left].push_back(g.edge(id, 0, s * (j + 1), 0, s * j));
  for (int sd = 0; sd < 4; ++sd) {
    for (const Edge& e : sides[sd]) side_edges.push_back({e, k, static_cast<Side>(sd)});
    mesh.add_edge_set(b.name + "." + side_names[sd], std::move(sides[sd]));
  }
}

/// The edge sets bottom, right, top, left of the union's bounding box, each ordered along the
/// counter-clockwise boundary; throws where blocks touch without sharing nodes.
void outer_sides(Mesh& mesh, const std::vector<Block>& blocks, const std::vector<SideEdge>& side_edges,
                 const Bounds& box) {
  const double tol = box.tol;
  // An edge on a block side is on the boundary of the union unless another block has it too.
  std::unordered_map<std::uint64_t, int> uses;
  uses.reserve(side_edges.size());
  for (const SideEdge& se : side_edges) ++uses[edge_key(se.edge.a, se.edge.b)];

  std::vector<Edge> outer[4];
  for (const SideEdge& se : side_edges) {
    if (uses[edge_key(se.edge.a, se.edge.b)] > 1) continue;
    const Block& b = blocks[se.block];
    // A free edge inside another block's closed rectangle means the blocks touch
    // without sharing nodes there.
    const Eigen::Vector2d m = 0.5 * (mesh.nodes[se.edge.a] + mesh.nodes[se.edge.b]);
    for (std::size_t o = 0; o < blocks.size(); ++o) {
      const Block& q = blocks[o];
      if (o != se.block && m.x() >= q.x0 - tol && m.x() <= q.x1 + tol && m.y() >= q.y0 - tol &&
          m.y() <= q.y1 + tol)
        throw Error(block_label(b) + " and " + block_label(q) + " touch near (" + number_text(m.x()) + ", " +
                    number_text(m.y()) +
                    ") but their nodes do not match there; give the shared sides the same cells and grading");
    }
    const bool on_bbox = (se.side == bottom && std::abs(b.y0 - box.ymin) <= tol) ||
                         (se.side == right && std::abs(b.x1 - box.xmax) <= tol) ||
                         (se.side == top && std::abs(b.y1 - box.ymax) <= tol) ||
                         (se.side == left && std::abs(b.x0 - box.xmin) <= tol);
    if (on_bbox) outer[se.side].push_back(se.edge);
  }
  // Order each global side along the counter-clockwise boundary.
  const auto sort_by = [&mesh](std::vector<Edge>& edges, int axis, bool increasing) {
    std::sort(edges.begin(), edges.end(), [&](const Edge& p, const Edge& q) {
      const double u = mesh.nodes[p.a][axis], v = mesh.nodes[q.a][axis];
      return increasing ? u < v : u > v;
    });
  };
  sort_by(outer[bottom], 0, true);
  sort_by(outer[right], 1, true);
  sort_by(outer[top], 0, false);
  sort_by(outer[left], 1, false);
  for (int sd = 0; sd < 4; ++sd) mesh.add_edge_set(side_names[sd], std::move(outer[sd]));
}

} // namespace

Mesh generate_blocks(const std::vector<Block>& blocks, int nodes_per_cell) {
  validate(blocks, nodes_per_cell);
  const int s = nodes_per_cell == 8 ? 2 : 1;
  const Bounds box = bounds_of(blocks);

  Mesh mesh;
  reserve(mesh, blocks, s);
  NodeIndex boundary_nodes(box.xmin, box.ymin, box.tol);
  std::vector<SideEdge> side_edges;
  std::vector<int> id;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const Block& b = blocks[k];
    const BlockGrid g(b.nx, b.ny, s);
    block_nodes(mesh, b, g, box.tol, boundary_nodes, id);
    block_cells(mesh, b, g, id);
    block_sides(mesh, b, k, g, id, side_edges);
  }
  mesh.add_all_set();
  outer_sides(mesh, blocks, side_edges, box);
  return mesh;
}

} // namespace stratum
