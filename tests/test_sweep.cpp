// Parameter studies (framework/src/sweep/sweep.hpp): the random numbers and distributions against closed
// forms, the designs' structure, TOML paths, and samples of the elastic pile and an elastic
// point checked against linear elasticity. The command line, MPI and resume: tests/sweep/run.sh.
#include "sweep/sweep.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>

namespace test_sweep {

using namespace stratum;
using namespace stratum::sweep;

namespace {

const std::string src = STRATUM_SOURCE_DIR;
const std::string pile = src + "/inputs/examples/elastic_pile.toml";

/// A study of the elastic pile (absolute base path), from the given design and parameter blocks.
Study pile_study(const std::string& study_table, const std::string& rest) {
  return Study::from_string("[study]\nscene = \"" + pile + "\"\n" + study_table + "\n" + rest,
                            "test_study.toml");
}

/// The cells of samples.csv's row (no quoted commas in these tests).
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream ss(row);
  std::string c;
  while (std::getline(ss, c, ',')) out.push_back(c);
  if (!row.empty() && row.back() == ',') out.push_back("");
  return out;
}

struct Env {
  Env() { setenv("STRATUM_PLUGIN_PATH", STRATUM_PLUGIN_DIR, 1); }
};

} // namespace

TEST_CASE("normal quantile: tabulated values and the round trip through erfc", "[sweep]") {
  // Phi^-1 at tabulated probabilities (e.g. Abramowitz and Stegun, table 26.5).
  CHECK(normal_quantile(0.5) == Approx(0.0).margin(1e-15));
  CHECK(normal_quantile(0.975) == Approx(1.959963984540054).epsilon(1e-13));
  CHECK(normal_quantile(0.95) == Approx(1.644853626951472).epsilon(1e-13));
  CHECK(normal_quantile(0.025) == Approx(-1.959963984540054).epsilon(1e-13));
  CHECK(normal_quantile(0.001) == Approx(-3.090232306167813).epsilon(1e-12));
  for (double p : {1e-12, 1e-6, 0.01, 0.02425, 0.1, 0.3, 0.7, 0.9, 0.97575, 0.999})
    CHECK(normal_cdf(normal_quantile(p)) == Approx(p).epsilon(1e-12));
}

TEST_CASE("distributions: quantiles of uniform, normal, lognormal and truncated normal", "[sweep]") {
  Parameter p;
  p.distribution = Distribution::uniform;
  p.lower = 2.0, p.upper = 6.0;
  CHECK(p.quantile(0.25) == Approx(3.0));
  p.distribution = Distribution::normal;
  p.mean = 10.0, p.sd = 2.0;
  CHECK(p.quantile(0.975) == Approx(10.0 + 2.0 * 1.959963984540054).epsilon(1e-13));
  // Lognormal by the mean and sd of the value: median = mean / sqrt(1 + cov^2).
  p.distribution = Distribution::lognormal;
  p.mean = 20000.0, p.sd = 6000.0;
  CHECK(p.quantile(0.5) == Approx(20000.0 / std::sqrt(1.09)).epsilon(1e-13));
  // Its 97.5 % point: exp(mu + 1.96 sigma) with sigma^2 = ln(1 + cov^2).
  const double s = std::sqrt(std::log(1.09));
  CHECK(p.quantile(0.975) ==
        Approx(20000.0 / std::sqrt(1.09) * std::exp(1.959963984540054 * s)).epsilon(1e-12));
  // Truncated at the mean from below: the median is the normal's 75 % point.
  p.distribution = Distribution::truncated_normal;
  p.mean = 10.0, p.sd = 2.0, p.lower = 10.0, p.upper = INFINITY;
  CHECK(p.quantile(0.5) == Approx(10.0 + 2.0 * 0.6744897501960817).epsilon(1e-12));
  // Symmetric truncation keeps the median; every quantile stays inside.
  p.lower = 8.0, p.upper = 12.0;
  CHECK(p.quantile(0.5) == Approx(10.0).epsilon(1e-14));
  CHECK(p.quantile(1e-9) >= 8.0);
  CHECK(p.quantile(1.0 - 1e-9) <= 12.0);
}

TEST_CASE("the random numbers are std::mt19937_64's, whose sequence the C++ standard fixes", "[sweep]") {
  // [rand.predef]: the 10000th output of a default-constructed mt19937_64 (seed 5489).
  Rng r(5489);
  double u = 0.0;
  for (int i = 0; i < 10000; ++i) u = r.uniform();
  CHECK(u == (static_cast<double>(9981545732273789042ULL >> 11) + 0.5) * 0x1.0p-53);
  Rng q(1);
  for (int i = 0; i < 1000; ++i) {
    const double v = q.uniform();
    REQUIRE((v > 0.0 && v < 1.0));
    REQUIRE(q.below(7) < 7);
  }
}

TEST_CASE("curve_at interpolates on the first crossing and is NaN beyond the curve", "[sweep]") {
  const std::vector<std::array<double, 2>> c = {{0, 0}, {10, 1}, {20, 3}};
  CHECK(curve_at(c, 15.0) == Approx(2.0));
  CHECK(curve_at(c, 0.0) == 0.0);
  CHECK(curve_at(c, 20.0) == Approx(3.0));
  CHECK(std::isnan(curve_at(c, 20.5)));
  CHECK(std::isnan(curve_at({}, 1.0)));
  const std::vector<std::array<double, 2>> down = {{0, 0}, {-1, 4}, {-2, 10}};
  CHECK(curve_at(down, -1.5) == Approx(7.0));
  CHECK(format_number(std::nan("")) == "");
  CHECK(format_number(-0.0) == "0");
  CHECK(format_number(1.0 / 3.0) == "0.3333333333");
}

TEST_CASE("Latin hypercube: every parameter has one sample in each of the n strata", "[sweep]") {
  const int n = 25;
  const Study st =
      pile_study("design = \"latin_hypercube\"\nsamples = " + std::to_string(n) + "\nseed = 3",
                 "[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\nlower = 1000.0\nupper = "
                 "2000.0\n[[parameters]]\nname = \"nu\"\npath = \"materials.soil.nu\"\nlower = 0.1\n"
                 "upper = 0.4\n");
  REQUIRE(st.samples().size() == static_cast<std::size_t>(n));
  for (std::size_t j = 0; j < 2; ++j) {
    const double lo = j ? 0.1 : 1000.0, hi = j ? 0.4 : 2000.0;
    std::set<int> strata;
    for (const auto& s : st.samples())
      strata.insert(static_cast<int>(std::floor((s.values[j] - lo) / (hi - lo) * n)));
    CHECK(strata.size() == static_cast<std::size_t>(n));
    CHECK(*strata.begin() == 0);
    CHECK(*strata.rbegin() == n - 1);
  }
  // The same seed gives the same samples; another seed others.
  const Study again =
      pile_study("design = \"latin_hypercube\"\nsamples = 25\nseed = 3",
                 "[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\nlower = 1000.0\nupper "
                 "= 2000.0\n[[parameters]]\nname = \"nu\"\npath = \"materials.soil.nu\"\nlower = "
                 "0.1\nupper = 0.4\n");
  CHECK(again.samples()[7].values == st.samples()[7].values);
  const Study other = pile_study("design = \"monte_carlo\"\nsamples = 2000\nseed = 4",
                                 "[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\ndistribution = "
                                 "\"normal\"\nmean = 1000.0\nsd = 100.0\n");
  // Monte Carlo: the sample mean within 4 standard errors (100 / sqrt(2000) = 2.2) of the mean.
  double mean = 0.0;
  for (const auto& s : other.samples()) mean += s.values[0] / 2000.0;
  CHECK(std::abs(mean - 1000.0) < 4 * 100.0 / std::sqrt(2000.0));
}

TEST_CASE("grid and one-at-a-time designs: order, base run, integer keys rounded", "[sweep]") {
  const Study g =
      pile_study("design = \"grid\"", "[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\n"
                                      "values = [1.0, 2.0]\n[[parameters]]\nname = \"steps\"\npath = "
                                      "\"stages.loading.steps\"\nlow = 2\nhigh = 5\nlevels = 3\n");
  REQUIRE(g.samples().size() == 6);
  CHECK(g.samples()[1].values == std::vector<double>{1.0, 4.0}); // 3.5 rounded: an integer key
  CHECK(g.samples()[3].values == std::vector<double>{2.0, 2.0}); // the last parameter varies fastest
  CHECK(g.header() == "index,E,steps,status,reason");
  const Study o =
      pile_study("design = \"one_at_a_time\"",
                 "[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\nlow = 10000.0\nhigh = "
                 "30000.0\n[[parameters]]\nname = \"stiff\"\npaths = [\"materials.soil.E\", "
                 "\"materials.concrete.E\"]\nscale = true\nlow = 0.5\nhigh = 2.0\n");
  REQUIRE(o.samples().size() == 5);
  CHECK(o.samples()[0].varied == "base");
  CHECK(o.samples()[0].values == std::vector<double>{20000.0, 1.0}); // the base scene's value; factor 1
  CHECK(o.samples()[4].varied == "stiff:high");
  CHECK(o.samples()[4].values == std::vector<double>{20000.0, 2.0});
  // The scene of sample 4: both moduli doubled.
  const auto t = toml::parse(o.scene_text(4));
  CHECK(t["materials"]["soil"]["E"].value<double>() == 40000.0);
  CHECK(t["materials"]["concrete"]["E"].value<double>() == 63.0e6);
  CHECK(t["analysis"]["threads"].value<int64_t>() == 1); // one element-loop thread per sample
}

TEST_CASE("paths: array elements, whole arrays scaled, [[stages]] by name, located errors", "[sweep]") {
  const std::string base = src + "/inputs/loess_pile/hypoelastic.toml";
  const std::string head = "[study]\nscene = \"" + base + "\"\ndesign = \"one_at_a_time\"\n";
  const Study st =
      Study::from_string(head + "[[parameters]]\nname = \"K1\"\npath = \"materials.loess.K[1]\"\n"
                                "low = 60.0\nhigh = 80.0\n[[parameters]]\nname = \"K\"\npath = "
                                "\"materials.loess.K\"\nscale = true\nlow = 0.8\nhigh = 1.2\n"
                                "[[parameters]]\nname = \"steps\"\npath = \"stages.loading.steps\"\n"
                                "low = 30\nhigh = 90\n",
                         "s.toml");
  CHECK(st.samples()[0].values == std::vector<double>{70.0, 1.0, 240.0}); // the scene's K[1] and steps
  auto t = toml::parse(st.scene_text(1));                                 // K1 low
  CHECK(t["materials"]["loess"]["K"][0].value<double>() == 500.0);
  CHECK(t["materials"]["loess"]["K"][1].value<double>() == 60.0);
  t = toml::parse(st.scene_text(4)); // K scaled by 1.2
  CHECK(t["materials"]["loess"]["K"][0].value<double>() == Approx(600.0).epsilon(1e-15));
  CHECK(t["materials"]["loess"]["K"][1].value<double>() == Approx(84.0).epsilon(1e-15));
  t = toml::parse(st.scene_text(6)); // steps high
  CHECK(t["stages"][3]["steps"].value<int64_t>() == 90);
  CHECK(t["stages"][3]["name"].value<std::string>() == "loading");

  auto error_of = [&](const std::string& text) {
    try {
      (void)Study::from_string(text, "s.toml");
    } catch (const Error& e) {
      return e;
    }
    FAIL("no error");
    return Error("");
  };
  const Error a =
      error_of(head + "[[parameters]]\nname = \"x\"\npath = \"stages.unloading.steps\"\nlow = 1\nhigh = 2\n");
  CHECK(a.where().line == 6);
  CHECK(a.where().column == 8);
  CHECK(a.message().find("no entry named 'unloading'") != std::string::npos);
  CHECK(a.message().find("geostatic, boring, concrete, loading") != std::string::npos);
  const Error b =
      error_of(head + "[[parameters]]\nname = \"x\"\npath = \"materials.loess.K[2]\"\nlow = 1\nhigh = 2\n");
  CHECK(b.message().find("index 2 is beyond") != std::string::npos);
  const Error c =
      error_of(head + "[[parameters]]\nname = \"x\"\npath = \"materials.loess.model\"\nlow = 1\nhigh = 2\n");
  CHECK(c.message().find("not a number") != std::string::npos);
  const Error d = error_of(head + "[[parameters]]\nname = \"x\"\npath = \"title\"\nmean = 1.0\n");
  CHECK(d.where().line == 7);
  CHECK(d.message().find("unknown key 'mean'") != std::string::npos);
}

TEST_CASE("elastic pile samples: settlement proportional to the load and to 1 / stiffness", "[sweep]") {
  const Env env;
  const Study st =
      pile_study("design = \"one_at_a_time\"",
                 "[[parameters]]\nname = \"stiff\"\npaths = [\"materials.soil.E\", "
                 "\"materials.concrete.E\"]\nscale = true\nlow = 0.5\nhigh = 2.0\n"
                 "[[quantities]]\nname = \"s\"\ntype = \"curve\"\nx = \"load\"\ny = \"settlement\"\n"
                 "at = [30.0, 120.0, 121.0]\n[[quantities]]\nname = \"P\"\ntype = \"curve\"\n"
                 "x = \"settlement\"\ny = \"load\"\nat = 0.5\n[[quantities]]\nname = \"Pmax\"\ntype = "
                 "\"last\"\ny = \"load\"\n[[quantities]]\nname = \"n\"\ntype = \"steps\"\n");
  CHECK(st.header() == "index,varied,stiff,s@30,s@120,s@121,P,Pmax,n,status,reason");
  const std::string out = (std::filesystem::temp_directory_path() / "stratum_sweep_unit").string();
  std::vector<std::vector<std::string>> rows;
  for (int i = 0; i < 3; ++i) {
    const SampleResult r = st.run(i, out);
    INFO(r.row);
    REQUIRE(r.status == "converged");
    rows.push_back(cells(r.row));
  }
  const double s30 = std::stod(rows[0][3]);
  CHECK(s30 > 0.0);
  // Linear: the 120 kN settlement is 4 times the 30 kN one; beyond 120 kN the cell is empty.
  CHECK(std::stod(rows[0][4]) == Approx(4 * s30).epsilon(1e-6));
  CHECK(rows[0][5].empty());
  // The load at settlement s: 30 s / s30.
  CHECK(std::stod(rows[0][6]) == Approx(30.0 * 0.5 / s30).epsilon(1e-6));
  CHECK(rows[0][7] == "120");
  CHECK(rows[0][8] == "8");
  // Every modulus times f: every displacement over f.
  CHECK(std::stod(rows[1][3]) == Approx(2.0 * s30).epsilon(1e-6));
  CHECK(std::stod(rows[2][3]) == Approx(0.5 * s30).epsilon(1e-6));
  CHECK(rows[2][9] == "converged");
  CHECK(!std::filesystem::exists(out)); // no per-sample output unless asked for
}

TEST_CASE(
    "a study reads recorder quantities of a non-pile scene: an elastic footing's reaction scales with E",
    "[sweep]") {
  // tests/scenes/sweep/elastic_footing.toml: a footing pushed 10 mm into a linear elastic layer
  // in 4 steps. Linear: the reaction at any settlement is proportional to E and to the
  // settlement, so R(5 mm) = R(10 mm) / 2 and R / E is the same in every sample.
  const Env env;
  const std::string base = src + "/tests/scenes/sweep/elastic_footing.toml";
  const auto study = [&](const std::string& quantities) {
    return Study::from_string("[study]\nscene = \"" + base +
                                  "\"\ndesign = \"grid\"\n[[parameters]]\nname = \"E\"\npath = "
                                  "\"materials.soil.E\"\nvalues = [1.0e4, 2.0e4, 4.0e4]\n" +
                                  quantities,
                              "test_study.toml");
  };
  const Study st =
      study("[[quantities]]\nname = \"R5\"\ntype = \"curve\"\nx = \"footing.uy\"\ny = \"footing.ry\"\n"
            "at = -0.005\n[[quantities]]\nname = \"Rmin\"\ntype = \"min\"\ny = \"footing.ry\"\n"
            "[[quantities]]\nname = \"Rmax\"\ntype = \"max\"\ny = \"footing.ry\"\n"
            "[[quantities]]\nname = \"Rpush\"\ntype = \"last\"\ny = \"footing.ry\"\nstage = \"push\"\n"
            "[[quantities]]\nname = \"t\"\ntype = \"last\"\ny = \"run.time\"\n"
            "[[quantities]]\nname = \"R_at_half\"\ntype = \"curve\"\nx = \"run.lambda\"\n"
            "y = \"run.time\"\nat = 0.5\n");
  CHECK(st.header() == "index,E,R5,Rmin,Rmax,Rpush,t,R_at_half,status,reason");
  const std::string out = (std::filesystem::temp_directory_path() / "stratum_sweep_footing").string();
  std::vector<std::vector<double>> v;
  for (int i = 0; i < 3; ++i) {
    const SampleResult r = st.run(i, out);
    INFO(r.row);
    REQUIRE(r.status == "converged");
    std::vector<double> row;
    for (const auto& c : cells(r.row))
      row.push_back(c.empty() || !std::isdigit(static_cast<unsigned char>(c.back())) ? 0.0 : std::stod(c));
    v.push_back(row);
  }
  const double per_E = v[0][2] / v[0][1];
  CHECK(per_E < 0.0); // the support pushes the footing's nodes down
  for (const auto& row : v) {
    CHECK(row[2] / row[1] == Approx(per_E).epsilon(1e-9)); // R5 / E
    CHECK(row[3] == Approx(2.0 * row[2]).epsilon(1e-9));   // the least (most negative): the end, 10 mm
    CHECK(row[4] == 0.0);                                  // the largest: the start
    CHECK(row[5] == row[3]);                               // the stage's last row is the run's
    CHECK(row[6] == 1.0);                                  // one static stage: time 1
    CHECK(row[7] == 0.5);                                  // time at load factor 0.5
  }
  const auto refused = [&](const std::string& quantities, const std::string& what) {
    INFO(what);
    REQUIRE_THROWS_WITH(study(quantities), Catch::Matchers::Contains(what));
  };
  refused(
      "[[quantities]]\nname = \"R\"\ntype = \"last\"\ny = \"footing.rz\"\n",
      "test_study.toml:11:5 [[quantities]] 1 y = \"footing.rz\" is not allowed; allowed: load, settlement, "
      "footing.stage, footing.step, footing.lambda, footing.uy, footing.ry, run.stage");
  refused("[[quantities]]\nname = \"R\"\ntype = \"last\"\ny = \"footing.ry\"\nstage = \"pull\"\n",
          "stage = \"pull\" is not a stage of the base scene; its stages: push");
  refused(
      "[[quantities]]\nname = \"R\"\ntype = \"curve\"\nx = \"settlement\"\ny = \"footing.ry\"\nat = 1.0\n",
      "must both be recorder columns or both the pile curve's");
  refused("[[quantities]]\nname = \"R\"\ntype = \"last\"\ny = \"load\"\nstage = \"push\"\n",
          "stage acts only on recorder columns");
}

TEST_CASE("a study reads a pile's settlement components: head = shortening + base", "[sweep]") {
  // The elastic pile with its cells named ([output] pile_cells): its head settlement (the area
  // mean over the head; the curve's `settlement` is the mean of the head's nodes) is its
  // shortening plus its base settlement (pile_components.hpp: to round-off for a prismatic pile of
  // fully integrated cells), at any load and for any stiffness.
  const Env env;
  const Study st = pile_study(
      "design = \"one_at_a_time\"\n[fixed]\n\"output.pile_cells\" = \"pile\"",
      "[[parameters]]\nname = \"stiff\"\npath = \"materials.soil.E\"\nscale = true\nlow = 0.5\nhigh = 2.0\n"
      "[[quantities]]\nname = \"s\"\ntype = \"curve\"\nx = \"load\"\ny = \"head_settlement\"\nat = 60.0\n"
      "[[quantities]]\nname = \"short\"\ntype = \"curve\"\nx = \"load\"\ny = \"pile_shortening\"\nat = 60.0\n"
      "[[quantities]]\nname = \"base\"\ntype = \"curve\"\nx = \"load\"\ny = \"base_settlement\"\nat = "
      "60.0\n");
  const std::string out = (std::filesystem::temp_directory_path() / "stratum_sweep_components").string();
  for (int i = 0; i < 3; ++i) {
    const SampleResult r = st.run(i, out);
    INFO(r.row);
    REQUIRE(r.status == "converged");
    const auto c = cells(r.row);
    const double s = std::stod(c[3]), shortening = std::stod(c[4]), base = std::stod(c[5]);
    CHECK(shortening > 0.0);
    CHECK(base > 0.0);
    CHECK(s == Approx(shortening + base).epsilon(1e-9));
  }
  // Without the pile's cells the components are not columns.
  REQUIRE_THROWS_WITH(
      pile_study("design = \"one_at_a_time\"",
                 "[[parameters]]\nname = \"stiff\"\npath = \"materials.soil.E\"\nscale = "
                 "true\nlow = 0.5\nhigh = 2.0\n[[quantities]]\nname = \"b\"\ntype = "
                 "\"last\"\ny = \"base_settlement\"\n"),
      Catch::Matchers::Contains("y = \"base_settlement\" is not allowed; allowed: load, settlement"));
}

TEST_CASE("a point-file study: drained triaxial q = E eps_axial, and a failing sample is a row", "[sweep]") {
  const Env env;
  const Study st = Study::from_string(
      "[study]\npoint = \"" + src +
          "/inputs/point/elastic_paths.toml\"\ndesign = \"grid\"\n[[parameters]]\nname = \"E\"\npath = "
          "\"material.E\"\nvalues = [10000.0, 20000.0, -5.0]\n[[quantities]]\nname = \"q\"\ntype = "
          "\"curve\"\n"
          "x = \"eps_axial\"\ny = \"q\"\nat = 0.005\n[[quantities]]\nname = \"n\"\ntype = \"steps\"\n",
      "p.toml");
  const auto a = cells(st.run(0, "unused").row), b = cells(st.run(1, "unused").row);
  // Radial stress constant: q = E eps_axial exactly (E = 10 000 kPa: q = 50 kPa at 0.5 %).
  CHECK(std::stod(a[2]) == Approx(50.0).epsilon(1e-9));
  CHECK(std::stod(b[2]) == Approx(100.0).epsilon(1e-9));
  // steps: every path's steps, as the point file gives them.
  long long steps = 0;
  const toml::table file = toml::parse_file(src + "/inputs/point/elastic_paths.toml");
  for (const auto& path : *file["paths"].as_array())
    steps += path.as_table()->get("steps")->value<long long>().value();
  CHECK(a[3] == std::to_string(steps));
  const SampleResult bad = st.run(2, "unused");
  CHECK(bad.status == "failed");
  CHECK(bad.row.find("failed,\"") != std::string::npos);
  CHECK(bad.row.find("E = -5") != std::string::npos);
}

} // namespace test_sweep
