// Tests of the mesh: the block generator, Mesh::check and the Gmsh 4.1 reader.
#include "stratum/mesh_io.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#ifndef STRATUM_TEST_DATA_DIR
#error "STRATUM_TEST_DATA_DIR must name the tests/data directory"
#endif

namespace test_mesh_io {

using namespace stratum;

namespace {

std::string data(const std::string& name) { return std::string(STRATUM_TEST_DATA_DIR) + "/" + name; }

// Signed area of the corner polygon of a cell.
double area(const Mesh& m, const Cell& c) {
  double a = 0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = m.nodes[c.nodes[k]];
    const Eigen::Vector2d& q = m.nodes[c.nodes[(k + 1) % 4]];
    a += 0.5 * (p.x() * q.y() - q.x() * p.y());
  }
  return a;
}

// The message of the Error thrown by f ("" when nothing is thrown).
template <class F> std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

Block block(std::string name, double x0, double x1, double y0, double y1, int nx, int ny) {
  Block b;
  b.name = std::move(name);
  b.x0 = x0;
  b.x1 = x1;
  b.y0 = y0;
  b.y1 = y1;
  b.nx = nx;
  b.ny = ny;
  return b;
}

bool same(const std::vector<Edge>& p, const std::vector<Edge>& q) {
  return std::equal(p.begin(), p.end(), q.begin(), q.end(),
                    [](const Edge& e, const Edge& f) { return e.a == f.a && e.b == f.b && e.mid == f.mid; });
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

TEST_CASE("generate_blocks: quad4 node and cell counts", "[mesh]") {
  const Mesh m = generate_blocks({block("soil", 0, 3, -2, 0, 3, 5)}, 4);
  CHECK(m.nodes.size() == 4u * 6u);
  CHECK(m.cells.size() == 15u);
  for (const Cell& c : m.cells) {
    CHECK(c.shape() == 0x0Fu);
    CHECK(c.count() == 4);
  }
  CHECK(m.cell_sets.at("soil").size() == 15u);
  CHECK(m.cell_sets.at("all").size() == 15u);
  CHECK_NOTHROW(m.check());
}

TEST_CASE("generate_blocks: quad8 node and cell counts", "[mesh]") {
  const int nx = 4, ny = 3;
  const Mesh m = generate_blocks({block("soil", 0, 4, 0, 3, nx, ny)}, 8);
  CHECK(m.nodes.size() == static_cast<std::size_t>((2 * nx + 1) * (2 * ny + 1) - nx * ny));
  CHECK(m.cells.size() == static_cast<std::size_t>(nx * ny));
  for (const Cell& c : m.cells) {
    CHECK(c.shape() == 0xFFu);
    // Midside nodes at the middle of their edges.
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d mid = 0.5 * (m.nodes[c.nodes[k]] + m.nodes[c.nodes[(k + 1) % 4]]);
      CHECK((m.nodes[c.nodes[4 + k]] - mid).norm() < 1e-14);
    }
  }
  // All nodes distinct.
  std::set<std::pair<double, double>> points;
  for (const auto& p : m.nodes) points.emplace(p.x(), p.y());
  CHECK(points.size() == m.nodes.size());
  CHECK_NOTHROW(m.check());
}

TEST_CASE("generate_blocks: adjacent blocks share their interface nodes", "[mesh]") {
  SECTION("side by side, quad4") {
    const Mesh m = generate_blocks({block("a", 0, 1, 0, 1, 2, 3), block("b", 1, 3, 0, 1, 4, 3)}, 4);
    CHECK(m.nodes.size() == 3u * 4u + 5u * 4u - 4u);
    CHECK(m.cells.size() == 6u + 12u);
    CHECK(m.node_sets.at("a.right") == m.node_sets.at("b.left"));
    CHECK_NOTHROW(m.check());
  }
  SECTION("stacked, quad8") {
    const Mesh m = generate_blocks({block("lower", 0, 2, -1, 0, 2, 1), block("upper", 0, 2, 0, 1, 2, 2)}, 8);
    const std::size_t lower = 5 * 3 - 2, upper = 5 * 5 - 4, shared = 5;
    CHECK(m.nodes.size() == lower + upper - shared);
    CHECK(m.node_sets.at("lower.top") == m.node_sets.at("upper.bottom"));
    CHECK(m.node_sets.at("lower.top").size() == shared);
    CHECK_NOTHROW(m.check());
  }
}

TEST_CASE("generate_blocks: grading", "[mesh]") {
  Block b = block("soil", 0, 10, 0, 5, 8, 6);
  b.grade_x = 4.0;
  b.grade_y = 0.25;
  const Mesh m = generate_blocks({b}, 8);
  // Corner x positions along the bottom and y positions along the left side.
  std::vector<double> xs, ys;
  for (const Edge& e : m.edge_sets.at("soil.bottom")) xs.push_back(m.nodes[e.b].x() - m.nodes[e.a].x());
  for (const Edge& e : m.edge_sets.at("soil.right")) ys.push_back(m.nodes[e.b].y() - m.nodes[e.a].y());
  REQUIRE(xs.size() == 8u);
  REQUIRE(ys.size() == 6u);
  CHECK(std::abs(xs.back() / xs.front() - 4.0) < 1e-12);
  CHECK(std::abs(ys.back() / ys.front() - 0.25) < 1e-12);
  const double r = std::pow(4.0, 1.0 / 7.0);
  for (std::size_t i = 1; i < xs.size(); ++i) CHECK(std::abs(xs[i] / xs[i - 1] - r) < 1e-12);
  double sum = 0;
  for (double h : xs) sum += h;
  CHECK(std::abs(sum - 10.0) < 1e-12);
  CHECK_NOTHROW(m.check());
}

TEST_CASE("generate_blocks: total cell area equals the block area", "[mesh]") {
  Block a = block("a", 0, 3, 0, 2, 7, 5);
  a.grade_x = 3;
  a.grade_y = 0.5;
  Block b = block("b", 3, 5, 0, 2, 3, 5);
  b.grade_y = 0.5; // conforming with a
  for (int npc : {4, 8}) {
    const Mesh m = generate_blocks({a, b}, npc);
    double total = 0;
    for (const Cell& c : m.cells) {
      const double ac = area(m, c);
      CHECK(ac > 0);
      total += ac;
    }
    CHECK(std::abs(total - 10.0) < 1e-12);
  }
}

TEST_CASE("generate_blocks: sets", "[mesh]") {
  const int nx = 3, ny = 2;
  const Mesh m = generate_blocks({block("soil", 1, 4, -1, 1, nx, ny)}, 8);
  const auto& bottom = m.edge_sets.at("bottom");
  REQUIRE(bottom.size() == static_cast<std::size_t>(nx));
  for (const Edge& e : bottom) {
    CHECK(m.nodes[e.a].y() == -1.0);
    CHECK(m.nodes[e.b].y() == -1.0);
    CHECK(m.nodes[e.mid].y() == -1.0);
    CHECK(m.nodes[e.b].x() > m.nodes[e.a].x()); // +x
  }
  CHECK(m.nodes[bottom.front().a].x() == 1.0); // ordered along the boundary
  CHECK(m.node_sets.at("bottom").size() == static_cast<std::size_t>(2 * nx + 1));

  const auto& right = m.edge_sets.at("right");
  REQUIRE(right.size() == static_cast<std::size_t>(ny));
  for (const Edge& e : right) {
    CHECK(m.nodes[e.a].x() == 4.0);
    CHECK(m.nodes[e.b].y() > m.nodes[e.a].y()); // +y
  }
  const auto& top = m.edge_sets.at("top");
  REQUIRE(top.size() == static_cast<std::size_t>(nx));
  for (const Edge& e : top) {
    CHECK(m.nodes[e.a].y() == 1.0);
    CHECK(m.nodes[e.b].x() < m.nodes[e.a].x()); // -x
  }
  const auto& left = m.edge_sets.at("left");
  REQUIRE(left.size() == static_cast<std::size_t>(ny));
  for (const Edge& e : left) {
    CHECK(m.nodes[e.a].x() == 1.0);
    CHECK(m.nodes[e.b].y() < m.nodes[e.a].y()); // -y
  }
  // The outward normal (dy, -dx) of every boundary edge points away from the body.
  const Eigen::Vector2d centre(2.5, 0.0);
  for (const char* side : {"bottom", "right", "top", "left"})
    for (const Edge& e : m.edge_sets.at(side)) {
      const Eigen::Vector2d d = m.nodes[e.b] - m.nodes[e.a];
      const Eigen::Vector2d normal(d.y(), -d.x());
      CHECK(normal.dot(m.nodes[e.a] - centre) > 0);
    }
  for (const char* side : {"bottom", "right", "top", "left"}) {
    CHECK(same(m.edge_sets.at(std::string("soil.") + side), m.edge_sets.at(side)));
    CHECK(m.node_sets.at(std::string("soil.") + side) == m.node_sets.at(side));
  }
}

TEST_CASE("generate_blocks: global sets cover only the outer boundary", "[mesh]") {
  // An L shape: 'base' below, 'wall' on its left part above.
  const Mesh m = generate_blocks({block("base", 0, 4, 0, 1, 4, 1), block("wall", 0, 2, 1, 3, 2, 2)}, 4);
  CHECK(m.nodes.size() == 10u + 9u - 3u);
  CHECK(m.cell_sets.at("base").size() == 4u);
  CHECK(m.cell_sets.at("wall").size() == 4u);
  CHECK(m.edge_sets.at("bottom").size() == 4u);
  CHECK(m.edge_sets.at("left").size() == 3u);  // 1 from base + 2 from wall
  CHECK(m.edge_sets.at("right").size() == 1u); // base only: the wall does not reach x = 4
  CHECK(m.edge_sets.at("top").size() == 2u);   // wall only
  for (const Edge& e : m.edge_sets.at("left")) CHECK(m.nodes[e.b].y() < m.nodes[e.a].y());
  // 'left' ordered along the boundary (downwards), starting at the top of the wall.
  CHECK(m.nodes[m.edge_sets.at("left").front().a].y() == 3.0);
  // The interface base.top / wall.bottom is shared by two cells: never in a global set.
  for (const Edge& e : m.edge_sets.at("top")) CHECK(m.nodes[e.a].y() == 3.0);
  CHECK_NOTHROW(m.check());
}

TEST_CASE("generate_blocks: bad arguments are rejected", "[mesh]") {
  const Block good = block("soil", 0, 1, 0, 1, 2, 2);
  CHECK(contains(error_of([&] { (void)generate_blocks({good}, 6); }), "nodes_per_cell = 6"));
  CHECK(contains(error_of([&] { (void)generate_blocks({good}, 6); }), "allowed: 4 (quad4) or 8 (quad8)"));
  CHECK(contains(error_of([&] { (void)generate_blocks({}, 4); }), "no mesh blocks"));

  Block b = good;
  b.nx = 0;
  CHECK(error_of([&] { (void)generate_blocks({b}, 4); }) == "mesh block 'soil': nx = 0 must be >= 1");
  b = good;
  b.ny = -1;
  CHECK(error_of([&] { (void)generate_blocks({b}, 4); }) == "mesh block 'soil': ny = -1 must be >= 1");
  b = good;
  b.x1 = 0;
  CHECK(error_of([&] { (void)generate_blocks({b}, 4); }) == "mesh block 'soil': x1 = 0 must be > x0 = 0");
  b = good;
  b.y0 = 2;
  CHECK(error_of([&] { (void)generate_blocks({b}, 8); }) == "mesh block 'soil': y1 = 1 must be > y0 = 2");
  b = good;
  b.grade_x = 0;
  CHECK(error_of([&] { (void)generate_blocks({b}, 4); }) == "mesh block 'soil': grade_x = 0 must be > 0");
  b = good;
  b.grade_y = -2;
  CHECK(error_of([&] { (void)generate_blocks({b}, 4); }) == "mesh block 'soil': grade_y = -2 must be > 0");
  b = good;
  b.name = "";
  CHECK(error_of([&] { (void)generate_blocks({b}, 4); }) == "mesh block 1 (1-based) has an empty name");
  CHECK(error_of([&] {
          (void)generate_blocks({good, block("soil", 1, 2, 0, 1, 2, 2)}, 4);
        }) == "mesh block name 'soil' is used more than once");
  CHECK(contains(error_of([&] {
                   (void)generate_blocks({good, block("b", 0.5, 2, 0.5, 1, 2, 2)}, 4);
                 }),
                 "mesh block 'soil' and mesh block 'b' overlap"));
  // Touching sides with different divisions: hanging nodes.
  CHECK(contains(error_of([&] {
                   (void)generate_blocks({good, block("b", 1, 2, 0, 1, 2, 3)}, 4);
                 }),
                 "their nodes do not match"));
}

TEST_CASE("Mesh::check rejects broken cells", "[mesh]") {
  Mesh m = generate_blocks({block("soil", 0, 2, 0, 1, 2, 1)}, 4);
  REQUIRE_NOTHROW(m.check());
  SECTION("clockwise") {
    std::swap(m.cells[1].nodes[1], m.cells[1].nodes[3]);
    const std::string msg = error_of([&] { m.check(); });
    CHECK(starts_with(msg, "mesh cell 1 (0-based): corner"));
    CHECK(contains(msg, "counter-clockwise"));
  }
  SECTION("degenerate") {
    m.cells[0].nodes[2] = m.cells[0].nodes[1];
    CHECK(starts_with(error_of([&] { m.check(); }), "mesh cell 0 (0-based)"));
  }
  SECTION("missing corner") {
    m.cells[1].nodes[2] = -1;
    CHECK(error_of([&] { m.check(); }) == "mesh cell 1 (0-based): corner slot 2 is empty");
  }
  SECTION("missing node") {
    m.cells[0].nodes[5] = 99;
    CHECK(starts_with(error_of([&] { m.check(); }), "mesh cell 0 (0-based): slot 5 refers to node 99"));
  }
  SECTION("bad set") {
    m.cell_sets["x"] = {7};
    CHECK(starts_with(error_of([&] { m.check(); }), "mesh cell set 'x': cell 7 does not exist"));
  }
}

TEST_CASE("Mesh::add_edge_set makes the node set", "[mesh]") {
  Mesh m;
  m.add_edge_set("e", {{5, 2, -1}, {2, 7, 3}});
  CHECK(m.edge_sets.at("e").size() == 2u);
  CHECK(m.node_sets.at("e") == std::vector<int>{2, 3, 5, 7});
}

TEST_CASE("read_gmsh: two 8-node quadrangles with physical groups", "[mesh]") {
  const Mesh m = read_gmsh(data("two_quad8.msh"));
  // 14 nodes in the file; tag 99 belongs to no quadrangle and is dropped.
  REQUIRE(m.nodes.size() == 13u);
  REQUIRE(m.cells.size() == 2u);
  // Node tags 1 2 3 4 10 11 12 20 30 31 32 40 50 -> indices 0..12 in file order.
  CHECK(m.nodes[0] == Eigen::Vector2d(0, 0));
  CHECK(m.nodes[1] == Eigen::Vector2d(2, 0));
  CHECK(m.nodes[2] == Eigen::Vector2d(2, 1));
  CHECK(m.nodes[4] == Eigen::Vector2d(1, 0));
  CHECK(m.nodes[6] == Eigen::Vector2d(1.5, 0));
  CHECK(m.nodes[12] == Eigen::Vector2d(1, 0.5));
  // Element 100 is counter-clockwise already.
  CHECK(m.cells[0].nodes == std::array<int, 8>{0, 4, 8, 3, 5, 12, 10, 11});
  // Element 101 is clockwise in the file (10 30 3 2 | 50 31 20 12) and is turned around.
  CHECK(m.cells[1].nodes == std::array<int, 8>{4, 1, 2, 8, 6, 7, 9, 12});
  REQUIRE_NOTHROW(m.check());

  CHECK(m.cell_sets.at("soil") == std::vector<int>{0, 1});
  CHECK(m.cell_sets.at("all") == std::vector<int>{0, 1});

  // 3-node lines, the second one written backwards: both follow the boundary (+x).
  const auto& base = m.edge_sets.at("base");
  REQUIRE(base.size() == 2u);
  CHECK((base[0].a == 0 && base[0].b == 4 && base[0].mid == 5));
  CHECK((base[1].a == 4 && base[1].b == 1 && base[1].mid == 6));
  CHECK(m.node_sets.at("base") == std::vector<int>{0, 1, 4, 5, 6});
  // A 2-node line written downwards on the right side: oriented +y, midside node from the cell.
  const auto& side = m.edge_sets.at("side");
  REQUIRE(side.size() == 1u);
  CHECK((side[0].a == 1 && side[0].b == 2 && side[0].mid == 7));
  // An unnamed physical curve (tag 7) on the top.
  const auto& top = m.edge_sets.at("physical_7");
  REQUIRE(top.size() == 2u);
  CHECK((top[0].a == 2 && top[0].b == 8 && top[0].mid == 9));
  CHECK((top[1].a == 8 && top[1].b == 3 && top[1].mid == 10));
  // A physical point.
  CHECK(m.node_sets.at("anchor") == std::vector<int>{0});
}

TEST_CASE("read_gmsh: a 3-node triangle is a cell with slots 0-2", "[mesh]") {
  const Mesh m = read_gmsh(data("triangle.msh"));
  REQUIRE(m.cells.size() == 1u);
  CHECK(m.cells[0].nodes == std::array<int, 8>{0, 1, 2, -1, -1, -1, -1, -1});
  CHECK(m.cells[0].shape() == 0x07u);
  REQUIRE_NOTHROW(m.check());
}

TEST_CASE("read_gmsh: errors name the file and line", "[mesh]") {
  SECTION("10-node triangle") {
    const std::string path = data("triangle10.msh");
    CHECK(error_of([&] { (void)read_gmsh(path); }) ==
          path +
              ":16:5 element type 21 (10-node triangle) is not supported; allowed: 3- and 6-node triangles "
              "(gmsh -order 1 or 2), 4-, 8- and 9-node quadrangles");
  }
  SECTION("binary") {
    const std::string path = data("binary.msh");
    CHECK(error_of([&] { (void)read_gmsh(path); }) ==
          path + ":2:5 binary .msh is not supported; save as ASCII 4.1");
  }
  SECTION("version") {
    const std::string path = data("version22.msh");
    const std::string msg = error_of([&] { (void)read_gmsh(path); });
    CHECK(starts_with(msg, path + ":2:"));
    CHECK(contains(msg, "version 2.2 is not supported"));
  }
  SECTION("z") {
    const std::string path = data("nonzero_z.msh");
    const std::string msg = error_of([&] { (void)read_gmsh(path); });
    CHECK(starts_with(msg, path + ":13:5 node 3 has z = 0.25"));
  }
  SECTION("missing file") {
    const std::string path = data("no_such_mesh.msh");
    CHECK(error_of([&] { (void)read_gmsh(path); }) == "cannot open mesh file '" + path + "'");
  }
}

} // namespace test_mesh_io
