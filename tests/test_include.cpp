// `include = ...` in scene files (toml_check.hpp, parse_with_includes): a shared material file,
// a value the scene overrides, and the errors (two includes setting one value, a cycle, a typo
// inside an included file, a missing file), each located.
#include "scene_helpers.hpp"

#include "stratum/error.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace test_include {

using Catch::Matchers::Contains;
using stratum::Analysis;
using stratum::RunOptions;
using stratum::testing::node_at;

namespace fs = std::filesystem;

namespace {

// One scratch folder per process (CTest runs the cases in parallel).
fs::path scratch() {
  const fs::path d = fs::temp_directory_path() / ("stratum_include_" + std::to_string(::getpid()));
  fs::create_directories(d / "materials");
  return d;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// tests/scenes/include/lame_body.toml: the Lamé cylinder without its material.
const std::string lame_body =
    "\n" + stratum::testing::read_text(stratum::testing::scene_path("include/lame_body.toml"));

std::unique_ptr<Analysis> from(const fs::path& p) {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  return Analysis::from_file(p.string(), std::move(o));
}

// u_r(a) of the thick cylinder under inner pressure p with u_z = 0 (plane strain):
// u(r) = p a^2 (1 + nu) / (E (b^2 - a^2)) [(1 - 2 nu) r + b^2 / r].
double lame_u(double E, double nu, double r) {
  const double a = 1.0, b = 2.0, p = 1.0;
  return p * a * a * (1 + nu) / (E * (b * b - a * a)) * ((1 - 2 * nu) * r + b * b / r);
}

double run_u_inner(const fs::path& scene) {
  auto an = from(scene);
  an->run();
  const auto& m = an->model();
  return m.u[2 * node_at(m, 1.0, 0.0)];
}

} // namespace

TEST_CASE("include: a shared material file is used, and a scene value overrides it", "[include]") {
  const fs::path d = scratch();
  write(d / "materials" / "steel.toml",
        "[materials.steel]\nmodel = \"linear_elastic\"\nE = 1000.0\nnu = 0.3\n");
  write(d / "lame.toml", "include = \"materials/steel.toml\"\n" + lame_body);
  // 8 x 2 quad8 cells: u(a) within 1e-3 of the closed form (the verification scene's tolerance).
  const double u1 = run_u_inner(d / "lame.toml");
  CHECK(std::abs(u1 / lame_u(1000.0, 0.3, 1.0) - 1.0) < 1e-3);

  write(d / "lame_stiff.toml",
        "include = [\"materials/steel.toml\"]\n" + lame_body + "[materials.steel]\nE = 2000.0\n");
  const double u2 = run_u_inner(d / "lame_stiff.toml");
  CHECK(std::abs(u2 / lame_u(2000.0, 0.3, 1.0) - 1.0) < 1e-3);
}

TEST_CASE("include: conflicts, cycles, typos and missing files are located errors", "[include]") {
  const fs::path d = scratch();
  write(d / "materials" / "a.toml", "[materials.steel]\nmodel = \"linear_elastic\"\nE = 1000.0\nnu = 0.3\n");
  write(d / "materials" / "b.toml", "[materials.steel]\nE = 1200.0\n");
  write(d / "two.toml", "include = [\"materials/a.toml\", \"materials/b.toml\"]\n" + lame_body);
  CHECK_THROWS_WITH(from(d / "two.toml"), Contains("b.toml:2:5") &&
                                              Contains("'materials.steel.E' is set here and at") &&
                                              Contains("a.toml:3:5"));

  write(d / "materials" / "loop1.toml", "include = \"loop2.toml\"\n");
  write(d / "materials" / "loop2.toml", "include = \"loop1.toml\"\n");
  write(d / "cycle.toml", "include = \"materials/loop1.toml\"\n" + lame_body);
  CHECK_THROWS_WITH(from(d / "cycle.toml"), Contains("loop2.toml:1:11") && Contains("cycle"));

  write(d / "materials" / "typo.toml",
        "[materials.steel]\nmodel = \"linear_elastic\"\nE = 1000.0\nnu = 0.3\nsigma_y = 5.0\n");
  write(d / "typo.toml", "include = \"materials/typo.toml\"\n" + lame_body);
  CHECK_THROWS_WITH(from(d / "typo.toml"), Contains("typo.toml:5:1") && Contains("sigma_y"));

  write(d / "missing.toml", "include = \"materials/none.toml\"\n" + lame_body);
  CHECK_THROWS_WITH(from(d / "missing.toml"),
                    Contains("missing.toml:1:11") && Contains("cannot open included file"));

  write(d / "materials" / "arr.toml", "[[stages]]\nname = \"a\"\n");
  write(d / "arr.toml", "include = \"materials/arr.toml\"\n[[stages]]\nname = \"b\"\n");
  CHECK_THROWS_WITH(from(d / "arr.toml"), Contains("array of tables"));

  write(d / "bad.toml", "include = 3\n" + lame_body);
  CHECK_THROWS_WITH(from(d / "bad.toml"), Contains("bad.toml:1:11") && Contains("allowed: a file name"));
  fs::remove_all(d);
}

TEST_CASE("include: the shared loess and concrete sets are those of the record's scene", "[include]") {
  // inputs/loess_pile/hypoelastic.toml (the Class-A scene) keeps its materials written out; the
  // shared files that the other pile scenes include must hold the same values.
  const std::string src = STRATUM_SOURCE_DIR;
  const toml::table record = toml::parse_file(src + "/inputs/loess_pile/hypoelastic.toml");
  for (const std::string name : {"loess_duncan_chang", "loess_far_linear", "concrete_mb30"}) {
    const toml::table shared = toml::parse_file(src + "/inputs/materials/" + name + ".toml");
    const toml::table* mats = shared["materials"].as_table();
    REQUIRE(mats);
    for (auto&& [key, value] : *mats) {
      INFO(name << ": [materials." << key.str() << "]");
      const toml::table* in_record = record["materials"][key.str()].as_table();
      REQUIRE(in_record);
      CHECK(*in_record == *value.as_table());
    }
  }
}

} // namespace test_include
