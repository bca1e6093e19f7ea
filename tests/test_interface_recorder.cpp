// The interface recorder of [[output.history]] (kind = "interface"): traction and jump at every
// point of an interface, one row per point and step, ordered along it, against closed forms:
//  - C2, a laterally confined column on an interface under a uniform pressure q: at every point
//    normal traction -q (tension positive), opening -q / k_n, no shear, no slip;
//  - C1, a rigid pile shaft pushed down past slip (Coulomb interface with c = tau_max, phi = 0):
//    at every point |shear traction| = tau_max, and the slip is the pile's displacement w less
//    the soil's at the shaft, tau_max r0 ln(rm / r0) / G (Randolph & Wroth's concentric
//    cylinders).
#include "contact_scenes.hpp"

#include "stratum/analysis.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace test_interface_recorder {

using namespace stratum;
using namespace stratum::testing;
namespace fs = std::filesystem;

namespace {

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  [[nodiscard]] std::size_t col(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    FAIL("no column " << name);
    return 0;
  }
  /// The rows of the last (stage, step).
  [[nodiscard]] std::vector<std::vector<double>> last_step() const {
    std::vector<std::vector<double>> out;
    for (const auto& r : rows)
      if (r[0] == rows.back()[0] && r[1] == rows.back()[1]) out.push_back(r);
    return out;
  }
};

Csv read_csv(const fs::path& p) {
  std::ifstream in(p);
  REQUIRE(in);
  Csv c;
  std::string line, x;
  std::getline(in, line);
  for (std::stringstream s(line); std::getline(s, x, ',');) c.header.push_back(x);
  while (std::getline(in, line)) {
    std::vector<double> r;
    for (std::stringstream s(line); std::getline(s, x, ',');) r.push_back(std::stod(x));
    REQUIRE(r.size() == c.header.size());
    c.rows.push_back(r);
  }
  return c;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("stratum_iface_rec_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

RunSummary run_scene(const std::string& text, const fs::path& out, std::unique_ptr<Analysis>& a) {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = out.string();
  a = Analysis::from_string(text, (out / "scene.toml").string(), std::move(o));
  return a->run();
}

} // namespace

TEST_CASE("interface recorder, C2 column: normal traction -q and opening -q/k_n at every point",
          "[recorders][contact]") {
  for (const char* kind : {"interface_line", "contact2"}) {
    CAPTURE(kind);
    ColumnSpec s;
    s.kind = kind;
    s.nodes_per_cell = 8;
    std::ostringstream t;
    t.precision(17);
    t << column_scene(s);
    t << "[[output.history]]\nname = \"base\"\nkind = \"interface\"\nset = \"base\"\n";
    // The scene's own checks: every point of the last step within the tolerance.
    t << "[[checks]]\nrecorder = \"base\"\nquantity = \"normal_traction\"\nexpected = " << -s.q
      << "\natol = " << 1e-6 * s.q << "\n";
    t << "[[checks]]\nrecorder = \"base\"\nquantity = \"opening\"\nexpected = " << -s.q / s.kn
      << "\nrtol = 1e-6\n";
    t << "[[checks]]\nrecorder = \"base\"\nquantity = \"shear_traction\"\nexpected = 0.0\natol = "
      << 1e-6 * s.q << "\n";
    const fs::path out = scratch(kind);
    std::unique_ptr<Analysis> a;
    const RunSummary sum = run_scene(t.str(), out, a);
    REQUIRE(sum.outcome.ok());
    REQUIRE(sum.checks.size() == 3);
    for (const auto& c : sum.checks) {
      INFO(c.label << " = " << c.value << ", expected " << c.expected);
      CHECK(c.pass);
    }
    const Csv csv = read_csv(out / "history" / "base.csv");
    // Each column with its unit (kN, m, kPa), as the curves' columns are.
    CHECK(csv.header == std::vector<std::string>{"stage", "step", "lambda", "s_m", "x_m", "y_m",
                                                 "shear_traction_kPa", "normal_traction_kPa", "slip_m",
                                                 "opening_m", "status"});
    const auto last = csv.last_step();
    REQUIRE(last.size() >= 3);                 // the 3-node edge: 3 node pairs, or the line element's points
    CHECK(csv.rows.size() == 2 * last.size()); // the start (step 0) and the one load step
    for (std::size_t i = 0; i < last.size(); ++i) {
      const auto& r = last[i];
      CAPTURE(i, r[csv.col("x_m")]);
      CHECK(r[csv.col("lambda")] == 1.0);
      CHECK(std::abs(r[csv.col("normal_traction_kPa")] + s.q) < 1e-6 * s.q);
      CHECK(std::abs(r[csv.col("opening_m")] + s.q / s.kn) < 1e-6 * s.q / s.kn);
      CHECK(std::abs(r[csv.col("shear_traction_kPa")]) < 1e-6 * s.q);
      CHECK(std::abs(r[csv.col("slip_m")]) < 1e-9);
      CHECK(r[csv.col("status")] == 0.0); // stick
      CHECK(r[csv.col("y_m")] == Approx(0.0).margin(1e-12));
      // Ordered along the base from its end nearest the set's first point: s is the distance
      // walked, here (a straight edge) the distance from the first row.
      CHECK(r[csv.col("s_m")] == Approx(std::abs(r[csv.col("x_m")] - last[0][csv.col("x_m")])).margin(1e-12));
      if (i > 0) CHECK(r[csv.col("s_m")] > last[i - 1][csv.col("s_m")]);
    }
    CHECK(last.back()[csv.col("s_m")] <= s.b + 1e-12);
    // A wrong expectation fails, at the worst point.
    std::string bad = t.str();
    bad.replace(bad.find("expected = " + std::to_string(static_cast<int>(-s.q))), 15, "expected = -101");
    const RunSummary sum2 = run_scene(bad, scratch(std::string(kind) + "_bad"), a);
    REQUIRE(sum2.checks.size() == 3);
    CHECK_FALSE(sum2.checks[0].pass);
    CHECK(sum2.checks[0].value == Approx(-s.q).epsilon(1e-6));
  }
}

TEST_CASE("interface recorder, C1 pile shaft after slip: |shear traction| = tau_max at every point",
          "[recorders][contact]") {
  PileSpec s;
  s.kind = "interface_line";
  std::string text =
      pile_scene(s) + "[[output.history]]\nname = \"shaft\"\nkind = \"interface\"\nset = \"shaft\"\n";
  const fs::path out = scratch("pile");
  std::unique_ptr<Analysis> a;
  const RunSummary sum = run_scene(text, out, a);
  REQUIRE(sum.outcome.ok());
  const Csv csv = read_csv(out / "history" / "shaft.csv");
  const auto last = csv.last_step();
  REQUIRE(last.size() >= static_cast<std::size_t>(2 * s.ny));
  // The slip: the pile's w_max less the soil's displacement at r0 (concentric cylinders).
  const double slip = s.w_max() - s.tau_max * s.r0 * s.zeta() / s.G();
  for (const auto& r : last) {
    CAPTURE(r[csv.col("y_m")], r[csv.col("shear_traction_kPa")], r[csv.col("slip_m")], slip);
    CHECK(std::abs(r[csv.col("shear_traction_kPa")]) == Approx(s.tau_max).epsilon(1e-6));
    CHECK(r[csv.col("status")] == 1.0); // slipping
    CHECK(r[csv.col("x_m")] == Approx(s.r0).margin(1e-12));
    // The jump u(pile) - u(soil) along the shaft (it includes the interface's elastic part
    // tau / k_s); 1e-3: the soil's displacement at r0 is a finite-element value (3e-5 found).
    CHECK(std::abs(r[csv.col("slip_m")]) == Approx(slip).epsilon(1e-3));
  }
  // Along the shaft: s runs over its length L.
  CHECK(last.front()[csv.col("s_m")] < 0.1 * s.L);
  CHECK(last.back()[csv.col("s_m")] > 0.9 * s.L);
  CHECK(last.back()[csv.col("s_m")] <= s.L + 1e-12);
}

TEST_CASE("interface recorder: an unknown interface is one located line", "[recorders][contact]") {
  ColumnSpec s;
  const std::string text =
      column_scene(s) + "[[output.history]]\nname = \"base\"\nkind = \"interface\"\nset = \"bsae\"\n";
  std::unique_ptr<Analysis> a;
  CHECK_THROWS_WITH(run_scene(text, scratch("unknown"), a),
                    Catch::Contains("scene.toml:") &&
                        Catch::Contains("set = \"bsae\" is not an interface of the scene; known: base") &&
                        Catch::Contains("did you mean 'base'"));
}

} // namespace test_interface_recorder
