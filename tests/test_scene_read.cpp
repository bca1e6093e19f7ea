// Reading a scene into a typed scene::Scene before anything is built (framework/src/scene/scene.hpp):
// the values arrive typed and located, nothing is created or meshed while reading, text errors
// are found before mesh errors, and what needs the mesh is checked when the scene is built.
#include "scene/scene.hpp"
#include "scene/toml_check.hpp"
#include "scene_helpers.hpp"
#include "stratum/analysis.hpp"
#include "stratum/error.hpp"

#include <catch2/catch.hpp>

#include <string>

namespace test_scene_read {

using Catch::Matchers::Contains;

namespace {

// A small two-stage scene (tests/scenes/read/two_stages.toml): blocks mesh, one material, a
// constraint, a gravity stage and a pressure stage, a recorder and a check. Its header comment
// takes the first 5 lines; the locations below are the file's.
std::string scene_file() { return stratum::testing::scene_path("read/two_stages.toml"); }

struct Read {
  stratum::PluginCatalog catalog{std::vector<std::string>{STRATUM_PLUGIN_DIR}};
  stratum::Registry registry;
  Read() { stratum::register_builtin_factories(registry); }
  stratum::scene::Scene operator()(const std::string& text) {
    return stratum::scene::read(stratum::io::parse_with_includes(text, scene_file()), scene_file(), catalog,
                                registry);
  }
};

} // namespace

TEST_CASE("scene::read gives the typed, located scene and creates nothing", "[scene][read]") {
  Read read;
  const std::string scene_text = stratum::testing::read_text(scene_file());
  const auto sc = read(scene_text);
  CHECK(sc.title == "read test");
  CHECK(sc.settings.formulation == stratum::Formulation::plane_strain);
  REQUIRE(sc.mesh.source == stratum::scene::MeshSpec::Source::blocks);
  REQUIRE(sc.mesh.blocks.size() == 1);
  CHECK(sc.mesh.blocks[0].nx == 4);
  CHECK(sc.mesh.block_at[0].line == 13);
  REQUIRE(sc.materials.size() == 1);
  CHECK(sc.materials[0].name == "clay");
  // A plugin's value with its location, as the plugin's schema typed it.
  CHECK(sc.materials[0].plugin.params.real("E") == 20000.0);
  CHECK(sc.materials[0].plugin.params.where("E").line == 21);
  CHECK(sc.materials[0].plugin.params.where("E").column == 5);
  REQUIRE(sc.domains.size() == 1);
  CHECK(sc.domains[0].cells == "soil");
  CHECK(sc.domains[0].cells_at.line == 24);
  CHECK(sc.domains[0].material_index == 0);
  REQUIRE(sc.constraints.size() == 1);
  CHECK(sc.constraints[0].value[0] == 0.0);
  CHECK(sc.constraints[0].value_at[1].line == 30);
  REQUIRE(sc.stages.size() == 2);
  CHECK(sc.staged);
  CHECK(sc.stages[0].settings.steps == 2);
  CHECK(sc.stages[1].settings.monitor == "top");
  CHECK(sc.stages[1].monitor_at.line == 39);
  REQUIRE(sc.stages[1].actions.size() == 1);
  CHECK(sc.stages[1].actions[0].plugin.params.real("p") == 50.0);
  CHECK(sc.stages[0].settings.actions.empty()); // actions are created when the scene is built
  REQUIRE(sc.history.size() == 1);
  CHECK(sc.history[0].quantities == std::vector<std::string>{"uy"});
  REQUIRE(sc.checks.size() == 1);
  CHECK(sc.checks[0].expected == -0.001);
  // The material's and element's libraries are opened (their schemas checked the tables);
  // nothing else is.
  const auto opened = read.catalog.opened();
  CHECK(opened.size() == 3); // linear_elastic, quad, newton
}

TEST_CASE("scene::read finds text errors without building, set names are checked when the scene is built",
          "[scene][read]") {
  Read read;
  const std::string scene_text = stratum::testing::read_text(scene_file());
  auto replaced = [](std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  // A material no domain can find: a text error, located at the domain's value.
  CHECK_THROWS_WITH(
      read(replaced(scene_text, "material = \"clay\"", "material = \"clya\"")),
      Contains("two_stages.toml:26:12 [[domains]] #1 material = \"clya\" is not defined; defined: clay"));
  // A check naming a quantity its recorder does not record: found without a mesh.
  CHECK_THROWS_WITH(read(replaced(scene_text, "quantity = \"uy\"", "quantity = \"ux\"")),
                    Contains("two_stages.toml:51:12") && Contains("is not recorded by \"top\""));
  // A text error and a mesh error in one scene: the text error is reported (the mesh is
  // never built), wherever the sections stand in the file.
  const std::string both = replaced(replaced(scene_text, "cells = \"soil\"", "cells = \"sol\""),
                                    "name = \"surcharge\"", "name = \"weight\"");
  CHECK_THROWS_WITH(read(both), Contains("[[stages]] name = \"weight\" is used twice"));
  // A set name is a mesh question: reading accepts it, building refuses it at its value.
  const std::string bad_set = replaced(scene_text, "cells = \"soil\"", "cells = \"sol\"");
  CHECK_NOTHROW(read(bad_set));
  stratum::RunOptions options;
  options.plugin_dirs = {STRATUM_PLUGIN_DIR};
  CHECK_THROWS_WITH(
      stratum::Analysis::from_string(bad_set, scene_file(), options),
      Contains("two_stages.toml:24:9 [[domains]] #1 cells = \"sol\" is not a cell set of the mesh"));
  const std::string bad_monitor = replaced(scene_text, "monitor = \"top\"", "monitor = \"tpo\"");
  CHECK_NOTHROW(read(bad_monitor));
  CHECK_THROWS_WITH(
      stratum::Analysis::from_string(bad_monitor, scene_file(), options),
      Contains("two_stages.toml:39:11 [[stages]] #2 monitor = \"tpo\" is not a node or edge set"));
}

} // namespace test_scene_read
