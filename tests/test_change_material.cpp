// A stage that changes a domain's material (issue 39, `change_material`): the closed form of a
// confined column whose upper layer changes twice (tests/scenes/stages/change_material.toml),
// restarts after each stage, what a restart may and may not change, and located input errors.
#include "scene_helpers.hpp"

#include "stratum/error.hpp"

#include <catch2/catch.hpp>

#include <filesystem>

#include <unistd.h>

namespace test_change_material {

using namespace stratum;
namespace fs = std::filesystem;

namespace {

const std::string path = stratum::testing::scene_path("stages/change_material.toml");
const std::string text = stratum::testing::read_text(path);

/// The oedometric modulus E (1 - nu) / ((1 + nu)(1 - 2 nu)).
double oedometric(double E, double nu) { return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)); }

std::unique_ptr<Analysis> run_scene(const std::string& toml, const fs::path& out,
                                    const std::string& restart = "") {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = out.string();
  o.restart_from = restart;
  return Analysis::from_string(toml, path, std::move(o));
}

/// The surface settlement: minus the mean uy of the nodes at y = 0.
double surface_settlement(const Model& m) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < m.mesh.nodes.size(); ++i)
    if (std::abs(m.mesh.nodes[i].y()) < 1e-12) sum += m.u[m.dofs.dof(static_cast<int>(i), field_uy)], ++n;
  return -sum / n;
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  s.replace(at, from.size(), to);
  return s;
}

} // namespace

TEST_CASE("change_material: each layer strains with its material of the stage, stresses carry over",
          "[stages][change_material]") {
  const fs::path out = fs::temp_directory_path() / ("stratum_change_material_" + std::to_string(::getpid()));
  fs::remove_all(out);
  auto a = run_scene(text, out / "full");
  const auto s = a->run();
  REQUIRE(s.outcome.ok());
  REQUIRE(s.checkpoints.size() == 3);
  const Model& m = a->model();
  const double nu = 0.3, H = 2.0;
  const double soft = oedometric(10000.0, nu), improved = oedometric(40000.0, nu),
               relaxed = oedometric(20000.0, nu);
  const double expected =
      100.0 * (H / soft + H / soft) + 50.0 * (H / improved + H / soft) + 30.0 * (H / relaxed + H / soft);
  // Uniform strain in each layer: the quadratic elements reproduce it to rounding.
  CHECK(surface_settlement(m) == Approx(expected).epsilon(1e-10));
  // The upper domain ends with `relaxed` (no history), the lower keeps `soft`.
  CHECK(m.domains[0].law.material->history_size() == 0);
  for (const auto& dm : m.domains)
    for (std::size_t p = 0; p < dm.states.points(); ++p) {
      const auto st = dm.states.committed(p).stress();
      CHECK(st[1] == Approx(-180.0).epsilon(1e-10));
      CHECK(st[0] == Approx(-180.0 * nu / (1.0 - nu)).epsilon(1e-10));
    }

  SECTION("a restart after each stage is bit-identical to the full run") {
    for (std::size_t k = 0; k < 2; ++k) {
      auto b = run_scene(text, out / ("restart" + std::to_string(k)), s.checkpoints[k]);
      const auto sb = b->run();
      REQUIRE(sb.outcome.ok());
      CHECK(sb.stages_done == 3);
      CHECK((b->model().u.array() == m.u.array()).all());
      for (std::size_t d = 0; d < m.domains.size(); ++d) {
        CHECK(b->model().domains[d].law.material->history_size() ==
              m.domains[d].law.material->history_size());
        CHECK(b->model().domains[d].states.committed_data() == m.domains[d].states.committed_data());
      }
    }
  }
  SECTION("before the stage that names it, a material may be edited; the restart uses the new one") {
    const std::string edited = replaced(text, "E = 40000.0", "E = 80000.0");
    auto b = run_scene(edited, out / "edited", s.checkpoints[0]);
    const auto sb = b->run();
    REQUIRE(sb.outcome.ok());
    const double stiffer = 100.0 * (H / soft + H / soft) + 50.0 * (H / oedometric(80000.0, nu) + H / soft) +
                           30.0 * (H / relaxed + H / soft);
    CHECK(surface_settlement(b->model()) == Approx(stiffer).epsilon(1e-10));
  }
  SECTION("after the stage that named it, an edited material is refused, located at its table") {
    const std::string edited = replaced(text, "E = 40000.0", "E = 80000.0");
    auto b = run_scene(edited, out / "refused", s.checkpoints[1]);
    CHECK_THROWS_WITH(b->run(),
                      Catch::Contains("change_material.toml:") &&
                          Catch::Contains("[materials.improved] differs from the scene that wrote"));
  }
  SECTION("a material the domains name stays global: editing `soft` is refused after any stage") {
    const std::string edited = replaced(text, "E = 10000.0", "E = 11000.0");
    auto b = run_scene(edited, out / "soft", s.checkpoints[0]);
    CHECK_THROWS_WITH(b->run(), Catch::Contains("[materials.soft] differs"));
  }
  fs::remove_all(out);
}

TEST_CASE("change_material: the point's history starts from its stress (Cam-Clay's p_c)",
          "[stages][change_material]") {
  // After stage 1 the lower layer continues as Modified Cam-Clay in a stage that adds no load:
  // its preconsolidation pressure starts on the yield surface through the point's stress
  // (normally consolidated, ocr = 1): p_c = p + q^2 / (M^2 p), compression positive.
  const std::string clay = R"(
[materials.clay]
model = "modified_cam_clay"
lambda = 0.2
kappa = 0.04
M = 1.2
nu = 0.3
e0 = 1.0
)";
  std::string toml = text.substr(0, text.find("[[stages]]\nname = \"improve\""));
  toml = replaced(toml, "[materials.relaxed]", clay + "[materials.relaxed]");
  toml += R"([[stages]]
name = "clay"
steps = 1
[[stages.actions]]
type = "change_material"
domain = "lower"
material = "clay"
)";
  const fs::path out = fs::temp_directory_path() / ("stratum_change_clay_" + std::to_string(::getpid()));
  fs::remove_all(out);
  auto a = run_scene(toml, out);
  const auto s = a->run();
  REQUIRE(s.outcome.ok());
  const Domain& lower = a->model().domains[1];
  REQUIRE(lower.law.material->history_size() == 1);
  REQUIRE(lower.states.points() > 0);
  for (std::size_t p = 0; p < lower.states.points(); ++p) {
    const auto st = lower.states.committed(p);
    const Vec6 sig = st.stress();
    const double mean = -(sig[0] + sig[1] + sig[2]) / 3.0;
    const double q =
        std::sqrt(0.5 * ((sig[0] - sig[1]) * (sig[0] - sig[1]) + (sig[1] - sig[2]) * (sig[1] - sig[2]) +
                         (sig[2] - sig[0]) * (sig[2] - sig[0])) +
                  3.0 * sig[3] * sig[3]);
    CHECK(mean == Approx(100.0 * (1.0 + 2.0 * 0.3 / 0.7) / 3.0).epsilon(1e-9)); // the stress carried over
    CHECK(st.history()[0] == Approx(mean + q * q / (1.44 * mean)).epsilon(1e-9));
  }
  fs::remove_all(out);
}

TEST_CASE("change_material: bad input is located and lists what is allowed", "[stages][change_material]") {
  using stratum::testing::build_error;
  const std::string domain_typo = replaced(text, "domain = \"upper\"\nmaterial = \"improved\"",
                                           "domain = \"uper\"\nmaterial = \"improved\"");
  CHECK_THAT(build_error(domain_typo, path), Catch::Contains("change_material.toml:88:") &&
                                                 Catch::Contains("domain = \"uper\" is not a [[domains]]") &&
                                                 Catch::Contains("known: upper, lower"));
  const std::string material_typo = replaced(text, "material = \"improved\"", "material = \"improvd\"");
  CHECK_THAT(build_error(material_typo, path),
             Catch::Contains("change_material.toml:89:") &&
                 Catch::Contains("material = \"improvd\" is not a [materials") &&
                 Catch::Contains("known: improved, relaxed, soft"));
  const std::string undrained = replaced(text, "cells = \"upper\"\nelement = \"quad\"\nmaterial = \"soft\"",
                                         "cells = \"upper\"\nelement = \"quad\"\nmaterial = \"soft\"\n"
                                         "drainage = \"undrained\"\nfluid_stiffness = 1.0e6");
  CHECK_THAT(build_error(undrained, path), Catch::Contains("is undrained"));
}

TEST_CASE("constraints: a component a constraint leaves out is free", "[stages][constraints]") {
  // Issue 39: the scene reference says ux/uy left out of a [[constraints]] entry are free (not
  // prescribed to 0). The column's sides give only ux = 0: their nodes settle with the column,
  // the top ones as much as the nodes inside (uniform oedometric strain).
  const fs::path out = fs::temp_directory_path() / ("stratum_constraint_free_" + std::to_string(::getpid()));
  fs::remove_all(out);
  auto a = run_scene(text, out);
  REQUIRE(a->run().outcome.ok());
  const Model& m = a->model();
  const double settlement = surface_settlement(m);
  REQUIRE(settlement > 0.0);
  int sides = 0;
  for (const char* set : {"left", "right"})
    for (int n : m.mesh.node_sets.at(set)) {
      CHECK(m.u[m.dofs.dof(n, field_ux)] == 0.0);
      if (std::abs(m.mesh.nodes[static_cast<std::size_t>(n)].y()) < 1e-12) {
        CHECK(-m.u[m.dofs.dof(n, field_uy)] == Approx(settlement).epsilon(1e-10));
        ++sides;
      }
    }
  CHECK(sides == 2);
  fs::remove_all(out);
}

} // namespace test_change_material
