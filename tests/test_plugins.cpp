// The plugin registry and loader: load on demand, ABI check, unknown and
// duplicate names, schema validation messages.
#include "scene/toml_check.hpp"
#include "scene_helpers.hpp"
#include "stratum/plugin.hpp"
#include "stratum/plugin_loader.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>

namespace test_plugins {

using namespace stratum;

namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}
const std::string toy = std::string(STRATUM_TOY_DIR);
} // namespace

TEST_CASE("plugins: only the libraries a scene names are opened", "[plugins]") {
  PluginCatalog catalog({STRATUM_PLUGIN_DIR, toy + "/good"});
  Registry reg;
  CHECK(catalog.opened().empty()); // manifests only
  const auto known = catalog.known(PluginKind::material);
  CHECK(std::find(known.begin(), known.end(), "linear_elastic") != known.end());
  CHECK(std::find(known.begin(), known.end(), "toy") != known.end());
  catalog.require(reg, PluginKind::material, "toy");
  REQUIRE(catalog.opened().size() == 1);
  CHECK(catalog.opened()[0].find("toy_good.so") != std::string::npos);
  CHECK(reg.has(PluginKind::material, "toy"));
  CHECK_FALSE(reg.has(PluginKind::material, "linear_elastic"));
  catalog.require(reg, PluginKind::material, "toy"); // once only
  CHECK(catalog.opened().size() == 1);

  // A whole scene opens exactly its element, material and solver libraries.
  auto an = stratum::testing::scene(R"(
[mesh]
generator = "blocks"
nodes_per_cell = 4
[[mesh.blocks]]
name = "b"
x = [1.0, 2.0]
y = [0.0, 1.0]
[materials.m]
model = "linear_elastic"
E = 1.0
[[domains]]
cells = "b"
element = "quad"
material = "m"
[[constraints]]
nodes = "bottom"
ux = 0.0
uy = 0.0
[[loads]]
type = "gravity"
gamma = 1.0
)");
  CHECK(an->opened_libraries().size() == 3);
}

TEST_CASE("plugins: an ABI mismatch names both numbers and the library", "[plugins]") {
  PluginCatalog catalog({toy + "/abi"});
  Registry reg;
  const auto msg = message_of([&] { catalog.require(reg, PluginKind::material, "old_abi"); });
  CHECK(msg.find("toy_old_abi.so was built for plugin ABI version 999, this Stratum expects version " +
                 std::to_string(STRATUM_PLUGIN_ABI_VERSION)) != std::string::npos);
}

TEST_CASE("plugins: duplicate names name both libraries", "[plugins]") {
  PluginCatalog catalog({toy + "/dup"});
  Registry reg;
  const auto msg = message_of([&] { catalog.require(reg, PluginKind::material, "twin"); });
  CHECK(msg.find("duplicate material 'twin': provided by ") != std::string::npos);
  CHECK(msg.find("toy_twin_a.so") != std::string::npos);
  CHECK(msg.find("toy_twin_b.so") != std::string::npos);
  // The registry itself refuses a second factory of the same name.
  Registry r2;
  auto make = [] {
    return Factory<Solver>{.name = "s",
                           .summary = "",
                           .schema = {},
                           .create = [](const Params&) { return std::unique_ptr<Solver>(); },
                           .library = {}};
  };
  r2.set_current_library("libA.so");
  r2.add(make());
  r2.set_current_library("libB.so");
  CHECK(message_of([&] { r2.add(make()); }) ==
        "duplicate solver 's': registered by libA.so and again by libB.so");
}

TEST_CASE("plugins: unknown names list the known ones", "[plugins]") {
  PluginCatalog catalog({STRATUM_PLUGIN_DIR});
  Registry reg;
  const auto msg = message_of([&] { catalog.require(reg, PluginKind::element, "quad9"); });
  CHECK(msg.rfind("unknown element 'quad9'; known: contact2, hex8, interface_line, quad, quad8p4, "
                  "tet4, thin_layer, tri3, tri6, tri6p3, wedge6 "
                  "(plugin path ",
                  0) == 0);
  const auto msg2 = message_of([&] { (void)reg.solver("arc"); });
  CHECK(msg2 == "unknown solver 'arc'; known: (none)");
}

TEST_CASE("plugins: a manifest that promises what the library does not register", "[plugins]") {
  PluginCatalog catalog({toy + "/liar"});
  Registry reg;
  const auto msg = message_of([&] { catalog.require(reg, PluginKind::material, "promised"); });
  CHECK(msg.find("its manifest lists material 'promised' but the library did not register it") !=
        std::string::npos);
}

TEST_CASE("schema: ranges, defaults and the messages of check_table", "[plugins]") {
  Schema s;
  s.real("E", "kPa", "Young's modulus").greater_than(0);
  s.real("nu", "-", "Poisson's ratio").greater_than(-1).less_than(0.5).defaults_to(0.3);
  s.integer("n", "-", "count").at_least(1).at_most(4).defaults_to(2LL);
  s.text("mode", {"a", "b"}, "mode").defaults_to(std::string("a"));
  CHECK(s.find("nu")->allowed() == "(-1, 0.5)");
  CHECK(s.find("n")->allowed() == "[1, 4]");
  CHECK(s.find("E")->allowed() == "(0, inf)");
  CHECK(s.find("mode")->allowed() == "one of: a, b");
  CHECK(message_of([&] { s.real("E", "", ""); }) == "schema declares parameter 'E' twice");

  auto check = [&](const std::string& text) {
    const auto t = toml::parse(std::string_view(text), std::string_view("x.toml"));
    return io::check_table(t, s, "[m]");
  };
  const auto p = check("E = 5\n");
  CHECK(p.real("E") == 5.0); // integers are accepted as numbers
  CHECK(p.real("nu") == 0.3);
  CHECK(p.integer("n") == 2);
  CHECK(p.text("mode") == "a");
  CHECK(p.where("E").str() == "x.toml:1:5");
  CHECK_FALSE(p.where("nu").known());
  CHECK(message_of([&] { (void)check("nu = 0.2\n"); }) ==
        "x.toml:1:1 [m] missing required parameter 'E' (Young's modulus, kPa)");
  CHECK(message_of([&] { (void)check("E = 0\n"); }) == "x.toml:1:5 [m] E = 0 is outside (0, inf)");
  CHECK(message_of([&] { (void)check("E = 1\nn = 2.5\n"); }) ==
        "x.toml:2:5 [m] n = 2.5 has the wrong type: expected an integer, got a number");
  CHECK(message_of([&] { (void)check("E = 1\nn = 5\n"); }) == "x.toml:2:5 [m] n = 5 is outside [1, 4]");
  CHECK(message_of([&] { (void)check("E = 1\nmode = \"c\"\n"); }) ==
        "x.toml:2:8 [m] mode = \"c\" is not allowed; allowed: one of: a, b");
  CHECK(message_of([&] { (void)check("E = 1\nnan = 1\n"); }) ==
        "x.toml:2:1 [m] unknown key 'nan'; allowed: E, nu, n, mode");
  CHECK(message_of([&] { (void)check("E = nan\n"); }) == "x.toml:1:5 [m] E = nan is outside (0, inf)");
}

} // namespace test_plugins
