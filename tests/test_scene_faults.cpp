// Scenes that used to go wrong late or silently (the fuzzing of issue 40): each is now refused
// with one located line while the scene is built, so by `stratum check` before anything runs, or
// it gets a warning, or it is built as the user meant (a polar ring's seam).
//
// The base is the soil column of tests/scenes/stages/column.toml (axisymmetric, linear elastic,
// held at the sides and the bottom); each case appends stages or replaces one line of it.
#include "scene_helpers.hpp"

#include <catch2/catch.hpp>

#include "stratum/mesh_io.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace test_scene_faults {

using namespace stratum;
namespace fs = std::filesystem;
using stratum::testing::read_text;
using stratum::testing::replace_once;
using stratum::testing::scene_path;

namespace {

const std::string column = read_text(scene_path("stages/column.toml"));

/// The line number the next appended line of `text` gets.
int next_line(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
}

/// The message of the error that building `text` (as faults.toml) throws; "" when it builds.
std::string build_error(const std::string& text) { return testing::build_error(text, "faults.toml"); }

std::vector<std::string> build_warnings(const std::string& text) {
  return testing::scene(text, "faults.toml")->warnings();
}

const std::string gravity_stage =
    "[[stages]]\nname = \"geostatic\"\n[[stages.actions]]\ntype = \"geostatic\"\n"
    "gamma = 18.0\nK0 = 0.5\n";

} // namespace

TEST_CASE("faults: names that become file names are plain", "[scene][faults]") {
  // The checkpoint of a stage is checkpoints/<n>_<name>.ckpt: "a/../../../escaped" wrote outside
  // --out, "a/b" made a folder; an empty name and a newline were accepted.
  const int line = next_line(column) + 1;
  const std::vector<std::string> names{
      "a/../../../escaped", "a/b", "", "two\\nlines", ".hidden", "tab\\there", std::string(65, 'x')};
  for (const std::string& name : names) {
    INFO(name);
    const std::string e = build_error(column + "[[stages]]\nname = \"" + name +
                                      "\"\n[[stages.actions]]\ntype = \"gravity\"\ngamma = 18.0\n");
    CHECK(e.rfind("faults.toml:" + std::to_string(line) + ":8 ", 0) == 0);
    CHECK_THAT(e, Catch::Contains("[[stages]] #1 name = ") &&
                      Catch::Contains("the output names files after it, so it may use letters, digits"));
  }
  CHECK(build_error(column + "[[stages]]\nname = \"load-2.b+c_d\"\n[[stages.actions]]\ntype = \"gravity\"\n"
                             "gamma = 18.0\n") == "");
  // A recorder's name is its history file's: the same rule.
  const std::string e = build_error(column +
                                    "[[output.history]]\nname = \"up/../x\"\nkind = \"node\"\n"
                                    "at = [0.0, 0.0]\n" +
                                    gravity_stage);
  CHECK_THAT(e, Catch::Contains("faults.toml:" + std::to_string(next_line(column) + 1) + ":8 ") &&
                    Catch::Contains("name = \"up/../x\" contains a path separator"));
}

TEST_CASE("faults: a number near the largest double is refused where it is written", "[scene][faults]") {
  // E = 1e308 passed the range check (0, inf) and ended as "solution contains NaN".
  const std::string text = replace_once(column, "E = 20000.0", "E = 1e308") + gravity_stage;
  CHECK_THAT(build_error(text),
             Catch::Contains("faults.toml:") &&
                 Catch::Contains("[materials.soil] E = 1e+308 is larger in magnitude than 1e20"));
  CHECK(build_error(replace_once(column, "E = 20000.0", "E = 1e20") + gravity_stage) == "");
}

TEST_CASE("faults: loads that act on nothing, and two head loads at once", "[scene][faults]") {
  const std::string base = column + gravity_stage;
  SECTION("a head load on a deactivated bore") {
    // It "completed" with zero settlement: the top faces of inactive cells carry nothing.
    const int at = next_line(base);
    const std::string e = build_error(base + "[[stages]]\nname = \"push\"\n[[stages.actions]]\ntype = "
                                             "\"deactivate\"\ncells = \"bore\"\n[[stages.actions]]\ntype = "
                                             "\"load\"\ncells = \"bore\"\nforce = 10.0\n");
    CHECK(e.rfind("faults.toml:" + std::to_string(at) +
                      ":1 stage \"push\": the load 'head' (head load on the top "
                      "of cell set 'bore') acts on nothing",
                  0) == 0);
  }
  SECTION("a second head load while the first stays applied") {
    // Curve and summary reported the first one's 120 kN for the settlement under 180 kN.
    const std::string first = base + "[[stages]]\nname = \"push\"\n[[stages.actions]]\ntype = "
                                     "\"load\"\nedges = \"bore.top\"\nforce = 120.0\n";
    const int at = next_line(first);
    const std::string second =
        "[[stages]]\nname = \"more\"\n[[stages.actions]]\ntype = \"load\"\nname = \"head2\"\n"
        "edges = \"bore.top\"\nforce = 60.0\n";
    CHECK_THAT(build_error(first + second), Catch::StartsWith("faults.toml:" + std::to_string(at) +
                                                              ":1 stage \"more\": the head loads 'head' "
                                                              "and 'head2' act together"));
    // Removing the first in that stage is the way: it builds.
    CHECK(build_error(first + second + "[[stages.actions]]\ntype = \"remove\"\nname = \"head\"\n") == "");
  }
  SECTION("a pressure on edges of cells without a domain") {
    // The `below` block has no [[domains]] entry: its edges' pressure was dropped without a word.
    const std::string blocks = replace_once(
        column, "[materials.soil]",
        "[[mesh.blocks]]\nname = \"cap\"\nx = [0.0, 0.5]\ny = [0.0, 0.5]\nnx = 2\nny = 1\n[materials.soil]");
    const std::string e =
        build_error(blocks + gravity_stage +
                    "[[stages]]\nname = \"press\"\n[[stages.actions]]\ntype = \"pressure\"\n"
                    "edges = \"cap.top\"\np = 10.0\n");
    CHECK_THAT(
        e, Catch::Contains("stage \"press\": the load 'pressure@press' (pressure on edge set 'cap.top') acts "
                           "on nothing"));
  }
}

TEST_CASE("faults: a part of the mesh no constraint holds", "[scene][faults]") {
  // A block that touches nothing (an isolated cell) was solved into a singular-matrix failure.
  const std::string text =
      replace_once(column, "[materials.soil]",
                   "[[mesh.blocks]]\nname = \"loose\"\nx = [20.0, 21.0]\ny = [0.0, 1.0]\nnx = 1\nny = 1\n"
                   "[materials.soil]") +
      "[[domains]]\ncells = \"loose\"\nelement = \"quad\"\nmaterial = \"soil\"\n" + gravity_stage;
  CHECK_THAT(build_error(text),
             Catch::Contains("stage \"geostatic\": a part of the mesh (1 cell, 8 nodes") &&
                 Catch::Contains("is held by no constraint in y: its stiffness is singular"));
}

TEST_CASE("faults: displacement control is checked against the mesh before the run", "[scene][faults]") {
  const std::string base =
      replace_once(column, "[analysis]\n", "[analysis]\nsolver = \"displacement_control\"\n");
  const std::string stage = gravity_stage;
  SECTION("increment = 0 ran 10 000 steps and 'completed'") {
    const int at = next_line(base) + 1;
    CHECK_THAT(build_error(base + "[solver]\nincrement = 0.0\nnodes = \"top\"\n" + stage),
               Catch::StartsWith("faults.toml:" + std::to_string(at) +
                                 ":13 displacement_control increment = 0 "
                                 "would never move"));
  }
  SECTION("a node set the mesh lacks passed check and failed as a singular matrix") {
    const int at = next_line(base) + 2;
    CHECK_THAT(build_error(base + "[solver]\nincrement = 0.01\nnodes = \"tpo\"\n" + stage),
               Catch::StartsWith("faults.toml:" + std::to_string(at) +
                                 ":9 displacement_control nodes = \"tpo\" is "
                                 "not a node set of the mesh"));
  }
  SECTION("a dof beyond the free unknowns") {
    const int at = next_line(base) + 2;
    CHECK_THAT(build_error(base + "[solver]\nincrement = 0.01\ndof = 100000\n" + stage),
               Catch::StartsWith("faults.toml:" + std::to_string(at) +
                                 ":7 stage \"geostatic\": displacement_control "
                                 "dof = 100000 is not a free unknown"));
  }
}

TEST_CASE("faults: a polar ring over 360 degrees is closed at its seam", "[scene][faults][mesh]") {
  // The seam was left open: the nodes at 0 and 360 degrees were two.
  const std::string ring =
      "[analysis]\nformulation = \"plane_strain\"\n[mesh]\ngenerator = \"blocks\"\n"
      "nodes_per_cell = 8\ntransform = \"polar\"\n[[mesh.blocks]]\nname = \"ring\"\n"
      "x = [1.0, 2.0]\ny = [0.0, 360.0]\nnx = 2\nny = 12\n[materials.soil]\nmodel = "
      "\"linear_elastic\"\nE = 1000.0\nnu = 0.3\n[[domains]]\ncells = \"ring\"\nelement = "
      "\"quad\"\nmaterial = \"soil\"\n[[constraints]]\nnodes = \"left\"\nux = 0.0\nuy = 0.0\n"
      "[[stages]]\nname = \"press\"\n[[stages.actions]]\ntype = \"pressure\"\nedges = "
      "\"ring.left\"\np = 10.0\n";
  const auto a = testing::scene(ring, "ring.toml");
  // 2 x 12 serendipity cells: (2 nx + 1) (2 ny) - nx ny nodes once the row at 360 degrees is the one at 0.
  CHECK(a->model().mesh.nodes.size() == static_cast<std::size_t>(5 * 24 - 2 * 12));
  // Every node at most once at any place.
  const auto& x = a->model().mesh.nodes;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) REQUIRE((x[i] - x[j]).norm() > 1e-6);
  CHECK(a->warnings().empty());
}

TEST_CASE("faults: a Gmsh mesh cut at a duplicated node, and two groups of one name",
          "[scene][faults][mesh]") {
  // Both were accepted without a word: the duplicated node leaves a crack in the body; the two
  // groups named alike were merged, so that a pressure acted on both faces.
  const fs::path dir = fs::temp_directory_path() / ("stratum_faults_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string original = read_text(testing::source_path("tests/data/two_quad8.msh"));
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  // Node 99 (unused, at (3, 3)) moves onto node 10 at (1, 0), and the second quadrangle and its
  // base line take it.
  const std::string cut = write(
      "cut.msh", replace_once(replace_once(replace_once(original, "1 0.5 0\n3 3 0\n", "1 0.5 0\n1 0 0\n"),
                                           "101 10 30 3 2", "101 99 30 3 2"),
                              "201 2 10 12", "201 2 99 12"));
  const std::string scene =
      "[analysis]\nformulation = \"plane_strain\"\n[mesh]\ngenerator = \"gmsh\"\nfile = \"" + cut +
      "\"\n[materials.soil]\nmodel = \"linear_elastic\"\nE = 1000.0\nnu = 0.3\n[[domains]]\n"
      "cells = \"soil\"\nelement = \"quad\"\nmaterial = \"soil\"\n[[constraints]]\nnodes = "
      "\"base\"\nux = 0.0\nuy = 0.0\n[[stages]]\nname = \"press\"\n[[stages.actions]]\ntype = "
      "\"pressure\"\nedges = \"side\"\np = 10.0\n";
  const auto warnings = build_warnings(scene);
  CHECK(std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) {
          return w.find("[mesh] 1 pair of nodes at one place with no interface between them, e.g. nodes 4 "
                        "and 13 at "
                        "(1, 0) m: the mesh is cut there") != std::string::npos;
        }) == 1);
  // Without the cut: no such warning.
  const std::string whole = write("whole.msh", original);
  for (const auto& w : build_warnings(replace_once(scene, cut, whole)))
    CHECK_THAT(w, !Catch::Contains("nodes at one place"));

  // The side (tag 3) named "base" as tag 2 is: refused at the second name.
  const std::string twice = write("twice.msh", replace_once(original, "1 3 \"side\"", "1 3 \"base\""));
  try {
    (void)read_gmsh(twice);
    FAIL("read_gmsh accepted two physical curves named \"base\"");
  } catch (const Error& e) {
    CHECK_THAT(std::string(e.what()),
               Catch::StartsWith(
                   twice + ":8:5 the physical name \"base\" is given to groups 2 and 3 of dimension 1"));
  }
  fs::remove_all(dir);
}

TEST_CASE("faults: nodes at one place with no interface between them are warned about",
          "[scene][faults][mesh]") {
  // Two blocks side by side, each meshed on its own: the generator joins them; a Gmsh mesh of two
  // surfaces without a shared boundary does not. Here: a block moved onto the column's top.
  const std::string text =
      replace_once(column, "[materials.soil]",
                   "[[mesh.blocks]]\nname = \"lid\"\nx = [0.0, 0.5]\ny = [0.0, 1.0]\nnx = 2\nny = 1\n"
                   "[materials.soil]") +
      "[[domains]]\ncells = \"lid\"\nelement = \"quad\"\nmaterial = \"soil\"\n" + gravity_stage;
  // The block generator shares the nodes of touching blocks, so this scene has no cut: no warning.
  for (const auto& w : build_warnings(text)) CHECK_THAT(w, !Catch::Contains("nodes at one place"));
}

} // namespace test_scene_faults
