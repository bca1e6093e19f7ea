// Stage actions and mesh generators as registered plugin kinds: each action reads its table
// against its own schema (unknown keys are located errors with a suggestion), unknown types and
// generators list what is allowed, and the registry and the plugin manifests know both kinds.
// The out-of-tree plugins of both kinds are exercised by tests/sdk (sdk.out_of_tree_plugin).
#include "scene_helpers.hpp"
#include "stages/builtin_actions.hpp"

#include "stratum/registry.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

namespace test_stage_actions {

using namespace stratum;
using stratum::testing::scene;

namespace {

// tests/scenes/stage_actions/column.toml: a plane-strain soil column without loads or stages.
const std::string column_path = stratum::testing::scene_path("stage_actions/column.toml");
const std::string column = stratum::testing::read_text(column_path);

/// The column with `stages` appended, built under the column file's name (errors located in it).
std::unique_ptr<Analysis> column_with(const std::string& stages) {
  return scene(column + stages, column_path);
}

/// "stage_actions/column.toml:<line>:" of the first line of `text` from `from` on that contains `needle`.
std::string at_line_of(const std::string& text, const std::string& needle, std::size_t from = 0) {
  const auto pos = text.find(needle, from);
  REQUIRE(pos != std::string::npos);
  return "stage_actions/column.toml:" +
         std::to_string(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n') + 1) + ":";
}

std::string one_stage(const std::string& action) {
  return "[[stages]]\nname = \"s\"\n[[stages.actions]]\n" + action;
}

} // namespace

TEST_CASE("every built-in stage action is registered under its type", "[stages][registry]") {
  Registry r;
  stage::register_builtin_actions(r);
  for (const auto& type : stage::builtin_action_types()) {
    INFO(type);
    CHECK(r.has(PluginKind::stage_action, type));
  }
  CHECK(r.names(PluginKind::stage_action).size() == stage::builtin_action_types().size());
  // A plugin cannot take a built-in's name.
  CHECK_THROWS_WITH(
      r.add(Factory<StageAction>{"geostatic", "twin", Schema{}, r.stage_action("geostatic").create, {}}),
      Catch::Contains("duplicate stage_action 'geostatic'"));
  PluginKind k{};
  CHECK(plugin_kind_from_string("stage_action", k));
  CHECK(k == PluginKind::stage_action);
  CHECK(plugin_kind_from_string("mesh_generator", k));
  CHECK(k == PluginKind::mesh_generator);
  CHECK_FALSE(plugin_kind_from_string("mesher", k));
}

TEST_CASE("an action's table is checked against that action's schema", "[stages]") {
  auto fails = [](const std::string& action, const std::string& located_at, const std::string& says) {
    const std::string text = column + one_stage(action);
    INFO(action);
    const std::string at =
        located_at.empty() ? "stage_actions/column.toml:" : at_line_of(text, located_at, column.size());
    CHECK_THROWS_WITH(scene(text, column_path), Catch::Contains(at) && Catch::Contains(says));
  };
  // A misspelt key of a pressure action, with the closest allowed key.
  fails("type = \"pressure\"\nedges = \"soil.top\"\npp = 10.0\n", "pp =", "unknown key 'pp'");
  // A key of another action: geostatic has no `edges`.
  fails("type = \"geostatic\"\ngamma = 18.0\nK0 = 0.5\nedges = \"soil.top\"\n",
        "edges =", "unknown key 'edges'");
  // A set the mesh does not have, with the nearest name.
  fails("type = \"deactivate\"\ncells = \"sol\"\n",
        "cells =", "cells = \"sol\" is not a cell set of the mesh");
  fails("type = \"force\"\nnodes = \"lft\"\nfx = 1.0\n", "nodes =", "did you mean 'left'");
  // The head load: a force or a settlement, not both; a force needs its value.
  fails("type = \"load\"\ncells = \"soil\"\nforce = 10.0\nsettlement = 0.01\n",
        "force =", "force cannot act with settlement");
  fails("type = \"load\"\ncells = \"soil\"\n", "[[stages.actions]]",
        "needs force = <kN> (or settlement = <m>");
  // A second load of the same name while the first is applied (located at the second action's table).
  fails("type = \"gravity\"\ngamma = 1.0\nname = \"g\"\n[[stages.actions]]\ntype = \"gravity\"\ngamma = 2.0\n"
        "name = \"g\"\n",
        "", "adds a load named \"g\", which is already applied");
}

TEST_CASE("an unknown action type lists the built-in ones first, with a suggestion", "[stages]") {
  const std::string text = column + one_stage("type = \"geostatc\"\n");
  CHECK_THROWS_WITH(scene(text, column_path),
                    Catch::Contains(at_line_of(text, "geostatc") + "8") &&
                        Catch::Contains("allowed: one of: geostatic, deactivate, activate, pressure, load, "
                                        "force, gravity, remove, displacement, reset_displacements") &&
                        Catch::Contains("did you mean 'geostatic'"));
}

TEST_CASE("the actions of a stage act as before they were objects", "[stages]") {
  // A 1D column under a surface pressure q (plane strain, nu = 0, sides held: oedometric with
  // M = E): the surface settles q H / E; removing the load in a second stage brings it back.
  const double q = 50.0, H = 2.0, E = 10000.0;
  auto a =
      column_with(one_stage("type = \"pressure\"\nedges = \"soil.top\"\np = 50.0\nname = \"q\"\n") +
                  "[[stages]]\nname = \"unload\"\n[[stages.actions]]\ntype = \"remove\"\nname = \"q\"\n");
  auto& m = a->model();
  const auto first = a->run();
  REQUIRE(first.outcome.ok());
  CHECK(first.stages_done == 2);
  const int top = stratum::testing::node_at(m, 0.5, 0.0);
  CHECK(std::abs(m.u[2 * top + 1]) < 1e-12 * q * H / E);

  auto b = column_with(one_stage("type = \"pressure\"\nedges = \"soil.top\"\np = 50.0\n"));
  REQUIRE(b->run().outcome.ok());
  const int t = stratum::testing::node_at(b->model(), 0.5, 0.0);
  CHECK(std::abs(b->model().u[2 * t + 1] + q * H / E) < 1e-6 * q * H / E);
}

TEST_CASE("mesh generators are a plugin kind, blocks and gmsh stay the scene's own", "[mesh]") {
  // tests/scenes/stage_actions/mesh_tail.toml: each case appends its [mesh] table, whose lines
  // follow the file's last line n.
  const std::string tail_path = stratum::testing::scene_path("stage_actions/mesh_tail.toml");
  const std::string tail = stratum::testing::read_text(tail_path);
  const auto n = std::count(tail.begin(), tail.end(), '\n');
  const auto with_mesh = [&](const std::string& mesh) { return scene(tail + mesh, tail_path); };
  const auto at = [&](long line, int column) {
    return "stage_actions/mesh_tail.toml:" + std::to_string(n + line) + ":" + std::to_string(column);
  };
  CHECK_THROWS_WITH(with_mesh("[mesh]\ngenerator = \"axisymmetric_pil\"\n"),
                    Catch::Contains(at(2, 13) + " [mesh] generator = \"axisymmetric_pil\" is not allowed; "
                                                "allowed: one of: blocks, gmsh, axisymmetric_pile") &&
                        Catch::Contains("did you mean 'axisymmetric_pile'"));
  // A generator's parameters are checked against its schema, located in its table.
  CHECK_THROWS_WITH(with_mesh("[mesh]\ngenerator = \"axisymmetric_pile\"\n[mesh.pile]\nradius = -1.0\n"),
                    Catch::Contains(at(4, 10)) && Catch::Contains("radius = -1 is outside"));
  CHECK_THROWS_WITH(with_mesh("[mesh]\ngenerator = \"axisymmetric_pile\"\n[mesh.pile]\nradiu = 1.0\n"),
                    Catch::Contains(at(4, 1)) && Catch::Contains("did you mean 'radius'"));
  // [mesh.pile] where it cannot act (a blocks mesh) is an error, not ignored.
  CHECK_THROWS_WITH(
      with_mesh("[mesh]\ngenerator = \"blocks\"\n[[mesh.blocks]]\nname = \"a\"\nx = [0.0, 1.0]\n"
                "y = [0.0, 1.0]\n[mesh.pile]\nradius = 1.0\n"),
      Catch::Contains("'pile'"));
  // The pile generator needs an axisymmetric scene: located at its table.
  CHECK_THROWS_WITH(with_mesh("[analysis]\nformulation = \"plane_strain\"\n[mesh]\ngenerator = "
                              "\"axisymmetric_pile\"\n[mesh.pile]\nradius = 0.2\n"),
                    Catch::Contains(at(5, 1)) &&
                        Catch::Contains("needs [analysis] formulation = \"axisymmetric\""));
  // Built through the registry, the pile mesh has its documented sets.
  auto a = with_mesh("[mesh]\ngenerator = \"axisymmetric_pile\"\n");
  for (const char* set : {"pile", "bore", "near", "far", "soil", "all"}) {
    INFO(set);
    CHECK(a->model().mesh.cell_sets.count(set) == 1);
  }
}

} // namespace test_stage_actions
