// How an until_failure stage classifies its stop when the limit is a plateau reached by force
// control (issue 40): the accepted steps stay stiff up to the limit, so only the attempts past it
// show that the load could not be raised (framework/src/run/run_stage.cpp, stage_failed;
// docs/design.md, "How a stage ends"). Each case runs the stratum program on a scene of
// tests/scenes and reads its summary.toml.
#include "scene_helpers.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace test_collapse_plateau {

namespace fs = std::filesystem;

namespace {

fs::path scratch() {
  static const fs::path d = [] {
    const auto p = fs::temp_directory_path() / ("stratum_test_plateau_" + std::to_string(getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return d;
}

struct Run {
  int code = -1;
  std::string out, err;
  toml::table summary;
};

/// Runs `stratum run` on `text` (written as scratch()/name.toml) into scratch()/name.
Run run(const std::string& name, const std::string& text) {
  const fs::path dir = scratch();
  std::ofstream(dir / (name + ".toml")) << text;
  const std::string cmd = "cd " + dir.string() + " && " + STRATUM_EXE + " run " + name + ".toml --out " +
                          name + " > " + name + ".out 2> " + name + ".err";
  const int status = std::system(cmd.c_str());
  Run r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = stratum::testing::read_text((dir / (name + ".out")).string());
  r.err = stratum::testing::read_text((dir / (name + ".err")).string());
  if (fs::exists(dir / name / "summary.toml"))
    r.summary = toml::parse_file((dir / name / "summary.toml").string());
  return r;
}

std::string scene(const std::string& relative) {
  return stratum::testing::read_text(stratum::testing::source_path(relative));
}

// The plateau of tests/scenes/collapse/plateau_pile.toml: the whole shaft at its adhesion,
// P_lim = c_a 2 pi r L with c_a = 20 kPa, r = 0.25 m, L = 4 m (no base: nothing is below it).
const double c_a = 20.0, radius = 0.25, length = 4.0;
const double p_lim = c_a * 2.0 * std::numbers::pi * radius * length; // 125.66 kN
const double p_target = 150.0;                                       // the head load at lambda = 1

} // namespace

TEST_CASE("a force-controlled run to a plateau stops as a collapse just below the closed-form plateau",
          "[cli][collapse]") {
  const std::string text = scene("tests/scenes/collapse/plateau_pile.toml");
  REQUIRE(text.find("force = 150.0") != std::string::npos);
  REQUIRE(text.find("c = 20.0") != std::string::npos);
  const Run r = run("plateau", text);
  INFO(r.out << r.err);
  CHECK(r.code == 0); // a collapse ends the run normally (README, "Exit codes")
  CHECK(r.out.find("\nstopped: collapse: ") != std::string::npos);
  CHECK(r.err.find("stratum: the step that stopped the run at the collapse: ") != std::string::npos);
  const auto& s = r.summary;
  CHECK(s["ended"].value_or(std::string()) == "stopped");
  CHECK(s["stop_reason"].value_or(std::string()) == "collapse");
  // The finding: the accepted steps alone call this stop numerical (their least current
  // stiffness over the last tenth of the load is 0.48 of the first step's, above
  // collapse_stiffness = 0.1); the last attempt's iterations went along the load as if the
  // structure had no stiffness left (4e-16 measured).
  CHECK(s["stiffness_ratio"].value_or(0.0) > 0.1);
  CHECK(s["attempt_stiffness_ratio"].value_or(1.0) < 0.1);
  // The last converged load: below the plateau (no equilibrium above it), by less than 1 % (the
  // smallest increment is 15 kN / 2^8 = 0.059 kN = 0.047 % of P_lim; 125.625 kN measured, 99.97 %).
  const double last = s["head_load"].value_or(0.0);
  WARN("last load " << last << " kN = " << last / p_lim << " P_lim (P_lim = " << p_lim << " kN)");
  CHECK(last < p_lim);
  CHECK(last > 0.99 * p_lim);
  CHECK(last < p_target);
  // The pile's shaft carries it all: the shaft load of the last row is the head load (no base).
  const std::string comp =
      stratum::testing::read_text((scratch() / "plateau" / "curves" / "settlement_components.csv").string());
  const auto row = comp.rfind('\n', comp.size() - 2);
  std::vector<double> f;
  std::stringstream ls(comp.substr(row + 1));
  for (std::string x; std::getline(ls, x, ',');) f.push_back(std::stod(x));
  REQUIRE(f.size() == 8); // load, head, shortening, base, slip mean, slip top, shaft load, base load
  CHECK(f[0] == Approx(last).epsilon(1e-9));
  CHECK(f[6] == Approx(last).epsilon(1e-6));
  CHECK(std::abs(f[7]) < 1e-6 * last);
}

TEST_CASE("a NaN from the soil below the plateau still stops as a numerical failure",
          "[cli][collapse][umat]") {
  // The same pile with the soil as the C von Mises UMAT (tests/umat/umat_mises.c, elastic with
  // sigma_y = 1e9 and the same E, nu) returning NaN once a total strain component exceeds 5e-5,
  // which the soil next to the shaft reaches at about half the plateau: every attempt past that
  // load fails with a non-finite stress. NaN says that a computation failed, not that the
  // structure gave way: exit 4, and the attempt gives no evidence (no attempt_stiffness_ratio).
  std::string text = scene("tests/scenes/collapse/plateau_pile.toml");
  text = stratum::testing::replace_once(
      text, "model = \"linear_elastic\"\nE = 5.0e5\nnu = 0.3\n",
      "model = \"umat\"\nlibrary = \"" + std::string(STRATUM_UMAT_DIR) +
          "/umat_mises.so\"\nsymbol = \"mises_umat\"\n"
          "props = [5.0e5, 0.3, 1.0e9, 0.0, 0.0, 5.0e-5, 0.0]\nnstatv = 1\nsymmetric_tangent = true\n");
  const Run r = run("plateau_nan", text);
  INFO(r.out << r.err);
  CHECK(r.code == 4);
  CHECK(r.out.find("\nstopped: numerical failure: ") != std::string::npos);
  CHECK(r.err.find("non-finite STRESS") != std::string::npos);
  const auto& s = r.summary;
  CHECK(s["stop_reason"].value_or(std::string()) == "numerical");
  CHECK_FALSE(s.contains("attempt_stiffness_ratio"));
  CHECK(s["head_load"].value_or(p_lim) < 0.95 * p_lim);
  CHECK(s["head_load"].value_or(0.0) > 0.0);
}

TEST_CASE("the attempt's evidence leaves a stiff structure's numerical stop and a collapse as they were",
          "[cli][collapse]") {
  // Hill's cylinder beyond its limit (tests/scenes/cli/hill_to_collapse.toml): a collapse by the
  // accepted steps (their stiffness falls to 5e-4 of the first), whose last attempt fails in the
  // return mapping (a material failure: no attempt evidence). Exit 0, as before.
  const std::string text = scene("tests/scenes/cli/hill_to_collapse.toml");
  const Run c = run("hill_collapse", text);
  INFO(c.out << c.err);
  CHECK(c.code == 0);
  CHECK(c.summary["stop_reason"].value_or(std::string()) == "collapse");
  CHECK(c.summary["stiffness_ratio"].value_or(1.0) < 0.1);
  // With two Newton iterations per step the first plastic steps fail while the cylinder is still
  // nearly elastic: the last attempt's iterations stay where a stiff structure's would (0.90 of
  // the first step's stiffness measured), so the stop stays numerical, exit 4.
  std::string two = text;
  two = stratum::testing::replace_once(two, "max_iterations = 30", "max_iterations = 2");
  two = stratum::testing::replace_once(two, "max_cutbacks = 8", "max_cutbacks = 1");
  const Run n = run("hill_numerical", two);
  INFO(n.out << n.err);
  CHECK(n.code == 4);
  CHECK(n.summary["stop_reason"].value_or(std::string()) == "numerical");
  const double attempt = n.summary["attempt_stiffness_ratio"].value_or(0.0);
  CHECK(attempt > 0.5);
  CHECK(attempt < 2.0);
}

} // namespace test_collapse_plateau
