// Back-analysis (framework/src/sweep/back_analysis.hpp, docs/calibrate.md): synthetic recovery.
// Each case makes its own data: the program runs the scene with known parameters, and the test
// adds Gaussian noise of a stated standard deviation (a fixed seed), then calibrates from a start
// away from the truth. Checked: the least-squares estimate and its standard error against their
// closed forms where the model is linear in 1/f (an elastic pile whose every modulus is scaled by
// f), the truth inside the 95 % intervals (soil modulus of the elastic pile; c and phi of a
// Mohr-Coulomb strip footing), a product of two parameters reported as not determined, the
// journal's resume, and the located refusals of bad input. The command line and MPI:
// tests/calibrate/run.sh.
#include "sweep/back_analysis.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace test_calibrate {

using namespace stratum;
using namespace stratum::sweep;
namespace fs = std::filesystem;

namespace {

const std::string src = STRATUM_SOURCE_DIR;
const std::string pile = src + "/inputs/examples/elastic_pile.toml";
const std::string footing = src + "/inputs/examples/strip_footing_mohr_coulomb.toml";

struct Env {
  Env() { setenv("STRATUM_PLUGIN_PATH", STRATUM_PLUGIN_DIR, 1); }
};

fs::path work_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("stratum_test_calibrate_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

BatchRunner local(const BackAnalysis& ba) {
  return [&ba](const std::vector<std::vector<double>>& batch) {
    std::vector<Evaluation> out;
    for (const auto& p : batch) out.push_back(ba.evaluate(p));
    return out;
  };
}

/// Writes "x,y" data: y of the computed curve at the abscissae, plus N(0, sd) noise (seeded).
/// Returns the noise-free values.
std::vector<double> write_data(const fs::path& file, const std::vector<std::array<double, 2>>& curve,
                               const std::vector<double>& xs, double sd, std::uint64_t seed) {
  Rng rng(seed);
  std::ofstream o(file);
  o << "# synthetic: computed with known parameters, plus Gaussian noise of sd " << sd << "\n";
  o << "x_measured,y_measured\n";
  std::vector<double> clean;
  for (double x : xs) {
    const double y = curve_at(curve, x);
    REQUIRE(std::isfinite(y));
    clean.push_back(y);
    char b[64];
    std::snprintf(b, sizeof b, "%.17g,%.17g\n", x, y + sd * normal_quantile(rng.uniform()));
    o << b;
  }
  return clean;
}

/// The whole computed curve of a data set at the given values (its first data set).
std::vector<std::array<double, 2>> curve_at_values(const BackAnalysis& ba, const std::vector<double>& p) {
  std::vector<std::vector<std::array<double, 2>>> curves;
  const fs::path out = work_dir("curve");
  const Evaluation e = ba.evaluate(p, out.string(), &curves);
  REQUIRE(e.status != "failed");
  return curves.at(0);
}

/// A calibration file for the elastic pile: head settlement against load.
std::string pile_calibration(const std::string& params, const std::string& data) {
  return "[calibration]\nscene = \"" + pile + "\"\n\n" + params + "\n[[data]]\nname = \"head\"\nfile = \"" +
         data +
         "\"\nx_column = \"x_measured\"\ny_column = \"y_measured\"\nx = \"load\"\ny = \"settlement\"\n";
}

const std::vector<double> loads = {15, 30, 45, 60, 75, 90, 105, 120};

} // namespace

TEST_CASE("calibrate (a): every modulus of the elastic pile by a factor f: the estimate and its "
          "standard error equal their closed forms",
          "[calibrate]") {
  Env env;
  const fs::path dir = work_dir("a_factor");
  // s_k(f) = S_k / f exactly (linear elasticity, every modulus scaled): S_k from the run at f = 1.
  const std::string params =
      "[[parameters]]\nname = \"f\"\npaths = [\"materials.soil.E\", "
      "\"materials.concrete.E\"]\nscale = true\nstart = 2.5\nlower = 0.1\nupper = 10.0\n"
      "log = true\n";
  const std::string data = (dir / "data.csv").string();
  { std::ofstream(data) << "x_measured,y_measured\n0,0\n1,1\n"; }
  const BackAnalysis probe = BackAnalysis::from_string(pile_calibration(params, data), "a.toml");
  const auto curve = curve_at_values(probe, {1.0});
  const double f_true = 0.8;
  std::vector<double> S;
  for (double x : loads) S.push_back(curve_at(curve, x));
  // The data at f_true with noise of 2 % of the largest settlement.
  const double sd = 0.02 * std::abs(S.back()) / f_true;
  std::vector<std::array<double, 2>> truth;
  for (const auto& xy : curve) truth.push_back({xy[0], xy[1] / f_true});
  (void)write_data(data, truth, loads, sd, 7);
  const BackAnalysis ba = BackAnalysis::from_string(pile_calibration(params, data), "a.toml");
  std::vector<double> d;
  for (std::size_t k = 0; k < loads.size(); ++k) d.push_back(ba.data()[0].ys[k]);

  Journal journal("", ba.hash(), 1, ba.points());
  const FitResult r = calibrate(ba, journaled(journal, local(ba)));
  // Least squares of S_k g - d_k in g = 1/f: g = sum S d / sum S^2.
  double sd_ = 0, ss = 0;
  for (std::size_t k = 0; k < S.size(); ++k) sd_ += S[k] * d[k], ss += S[k] * S[k];
  const double f_hat = ss / sd_;
  CHECK(r.best[0] == Approx(f_hat).epsilon(1e-6));
  // The residual standard deviation and the standard error of ln f: d r / d ln f = -S_k / f.
  double rss = 0, jj = 0;
  for (std::size_t k = 0; k < S.size(); ++k) {
    rss += (S[k] / f_hat - d[k]) * (S[k] / f_hat - d[k]);
    jj += (S[k] / f_hat) * (S[k] / f_hat);
  }
  const double sigma = std::sqrt(rss / 7.0);
  CHECK(r.sigma == Approx(sigma).epsilon(1e-5));
  CHECK(r.se_z[0] == Approx(sigma / std::sqrt(jj)).epsilon(1e-4));
  CHECK(r.t95 == Approx(2.364624251592785).epsilon(1e-12)); // Student's t, 0.975, 7 degrees of freedom
  CHECK(r.determined[0]);
  CHECK(r.low95[0] < f_true);
  CHECK(r.high95[0] > f_true);
  CHECK(r.converged);

  SECTION("forward differences reach the same estimate; two iterations are reported as not converged") {
    const auto with = [&](const std::string& settings) {
      return BackAnalysis::from_string(
          pile_calibration(params, data)
              .replace(pile_calibration(params, data).find("\n\n"), 2, "\n" + settings + "\n\n"),
          "a.toml");
    };
    const BackAnalysis fw = with("differences = \"forward\"");
    CHECK_FALSE(fw.settings().central);
    Journal j1("", fw.hash(), 1, fw.points());
    const FitResult rf = calibrate(fw, journaled(j1, local(fw)));
    CHECK(rf.best[0] == Approx(f_hat).epsilon(1e-6));
    CHECK(rf.se_z[0] == Approx(sigma / std::sqrt(jj)).epsilon(1e-2)); // a one-sided difference: first order
    const BackAnalysis two = with("max_iterations = 2");
    Journal j2("", two.hash(), 1, two.points());
    const FitResult r2 = calibrate(two, journaled(j2, local(two)));
    CHECK_FALSE(r2.converged);
    CHECK(r2.iterations == 2);
    REQUIRE_FALSE(r2.notes.empty());
    CHECK_THAT(r2.notes[0], Catch::Contains("did not converge"));
  }
  SECTION("an upper bound below the estimate: the fit stops at it and says that the interval is not valid") {
    std::string text = pile_calibration(params, data);
    text.replace(text.find("upper = 10.0"), 12, "upper = 0.7");
    text.replace(text.find("start = 2.5"), 11, "start = 0.5");
    const BackAnalysis capped = BackAnalysis::from_string(text, "a.toml");
    Journal j3("", capped.hash(), 1, capped.points());
    const FitResult rb = calibrate(capped, journaled(j3, local(capped)));
    REQUIRE(f_hat > 0.7);
    CHECK(rb.best[0] <= 0.7);
    CHECK(rb.best[0] > 0.7 * std::exp(-1e-3 * std::log(0.7 / 0.1)));
    CHECK(rb.at_bound[0]);
    bool noted = false;
    for (const auto& n : rb.notes) noted = noted || n.find("ends on a bound") != std::string::npos;
    CHECK(noted);
  }
}

TEST_CASE("calibrate (a): the elastic pile's soil modulus is recovered inside its 95 % interval",
          "[calibrate]") {
  Env env;
  const fs::path dir = work_dir("a_soil");
  const std::string params =
      "[[parameters]]\nname = \"E_soil\"\npath = \"materials.soil.E\"\nstart = 60000.0\n"
      "lower = 2000.0\nupper = 200000.0\nlog = true\n";
  const std::string data = (dir / "data.csv").string();
  { std::ofstream(data) << "x_measured,y_measured\n0,0\n1,1\n"; }
  const double E_true = 25000.0;
  const BackAnalysis probe = BackAnalysis::from_string(pile_calibration(params, data), "a.toml");
  const auto curve = curve_at_values(probe, {E_true});
  const auto clean = write_data(data, curve, loads, 0.01 * std::abs(curve_at(curve, 120.0)), 11);
  const BackAnalysis ba = BackAnalysis::from_string(pile_calibration(params, data), "a.toml");
  Journal journal("", ba.hash(), 1, ba.points());
  const FitResult r = calibrate(ba, journaled(journal, local(ba)));
  CHECK(r.determined[0]);
  CHECK(r.low95[0] < E_true);
  CHECK(r.high95[0] > E_true);
  CHECK(r.best[0] == Approx(E_true).epsilon(0.05));
  CHECK(r.dof == 7);
  CHECK(r.notes.empty());

  SECTION("an interrupted calibration resumes from its journal and ends where the whole one ended") {
    const std::string jf = (dir / "journal.csv").string();
    struct Stop {};
    int left = 4;
    {
      Journal j(jf, ba.hash(), 1, ba.points());
      const BatchRunner dying = [&](const std::vector<std::vector<double>>& batch) {
        std::vector<Evaluation> out;
        for (const auto& p : batch) {
          if (left-- == 0) throw Stop{}; // the process killed after four runs
          out.push_back(ba.evaluate(p));
        }
        return out;
      };
      CHECK_THROWS_AS(calibrate(ba, journaled(j, dying)), Stop);
      CHECK(j.size() >= 1);
    }
    Journal j(jf, ba.hash(), 1, ba.points());
    const std::size_t kept = j.size();
    CHECK(kept >= 1);
    const FitResult again = calibrate(ba, journaled(j, local(ba)));
    CHECK(j.reused() >= kept);
    CHECK(again.best[0] == r.best[0]); // bit for bit: the optimizer asked for the same points
    CHECK(again.se_z[0] == r.se_z[0]);
    // A journal of another calibration is refused.
    CHECK_THROWS_WITH(Journal(jf, "0123456789abcdef", 1, ba.points()),
                      Catch::Contains("belongs to another calibration"));
  }
}

TEST_CASE("calibrate (c): two factors that only enter as their product are reported as not determined",
          "[calibrate]") {
  Env env;
  const fs::path dir = work_dir("c_product");
  const std::string params =
      "[[parameters]]\nname = \"A\"\npaths = [\"materials.soil.E\", \"materials.concrete.E\"]\nscale = true\n"
      "start = 2.0\nlower = 0.1\nupper = 10.0\nlog = true\n"
      "[[parameters]]\nname = \"B\"\npaths = [\"materials.soil.E\", \"materials.concrete.E\"]\nscale = true\n"
      "start = 1.0\nlower = 0.1\nupper = 10.0\nlog = true\n";
  const std::string data = (dir / "data.csv").string();
  { std::ofstream(data) << "x_measured,y_measured\n0,0\n1,1\n2,2\n"; }
  const BackAnalysis probe = BackAnalysis::from_string(pile_calibration(params, data), "c.toml");
  const auto curve = curve_at_values(probe, {1.0, 1.0});
  std::vector<std::array<double, 2>> truth;
  for (const auto& xy : curve) truth.push_back({xy[0], xy[1] / 0.8}); // A B = 0.8
  (void)write_data(data, truth, loads, 0.01 * std::abs(truth.back()[1]), 5);
  const BackAnalysis ba = BackAnalysis::from_string(pile_calibration(params, data), "c.toml");
  Journal journal("", ba.hash(), 2, ba.points());
  const FitResult r = calibrate(ba, journaled(journal, local(ba)));
  // The data fix the product (it fits), not the factors.
  CHECK(r.best[0] * r.best[1] == Approx(0.8).epsilon(0.03));
  CHECK_FALSE(r.determined[0]);
  CHECK_FALSE(r.determined[1]);
  CHECK(r.singular[1] < 1e-6 * r.singular[0]);
  // The undetermined direction is ln A - ln B (equal weights, opposite signs).
  CHECK(std::abs(r.directions(0, 1)) == Approx(std::sqrt(0.5)).epsilon(1e-3));
  CHECK(r.directions(0, 1) * r.directions(1, 1) < 0.0);
  REQUIRE_FALSE(r.notes.empty());
  CHECK_THAT(r.notes[0],
             Catch::Contains("not determined") && Catch::Contains("ln A") && Catch::Contains("ln B"));
  const auto files = report_files(ba, r);
  CHECK_THAT(files.at("report.md"), Catch::Contains("not determined"));
  CHECK_THAT(files.at("parameters.csv"), Catch::Contains(",inf,false,"));
}

TEST_CASE("calibrate (b): c and phi of a Mohr-Coulomb strip footing from its load-settlement curve",
          "[calibrate]") {
  Env env;
  const fs::path dir = work_dir("b_footing");
  // The example footing (associated flow: psi follows phi) on a coarser mesh, 12 steps to 6 mm,
  // no output files. Weightless soil: c and phi act together, the report says how strongly.
  const std::string fixed = "[fixed]\n\"mesh.blocks[0].nx\" = 4\n\"mesh.blocks[0].ny\" = 6\n"
                            "\"mesh.blocks[1].nx\" = 5\n\"mesh.blocks[1].ny\" = 6\n\"analysis.steps\" = 12\n"
                            "\"output.vtk\" = false\n";
  const std::string params = "[[parameters]]\nname = \"c\"\npath = \"materials.clay.c\"\nstart = 16.0\n"
                             "lower = 1.0\nupper = 50.0\nlog = true\n"
                             "[[parameters]]\nname = \"phi\"\npaths = [\"materials.clay.phi\", "
                             "\"materials.clay.psi\"]\nstart = 24.0\nlower = 5.0\nupper = 45.0\n";
  const std::string data = (dir / "data.csv").string();
  const std::string text = "[calibration]\nscene = \"" + footing + "\"\nstep = 0.01\ntolerance = 1e-6\n" +
                           fixed + "\n" + params + "\n[[data]]\nname = \"footing\"\nfile = \"" + data +
                           "\"\nx_column = \"x_measured\"\ny_column = \"y_measured\"\nx = \"footing.uy\"\n"
                           "y = \"footing.ry\"\n";
  { std::ofstream(data) << "x_measured,y_measured\n0,0\n-0.001,1\n-0.002,2\n"; }
  const BackAnalysis probe = BackAnalysis::from_string(text, "b.toml");
  const double c_true = 10.0, phi_true = 30.0;
  const auto curve = curve_at_values(probe, {c_true, phi_true});
  std::vector<double> xs;
  for (int k = 1; k <= 13; ++k) xs.push_back(-0.00045 * k); // inside the computed -6 mm
  // Noise: 1 % of the reaction at 5.5 mm.
  (void)write_data(data, curve, xs, 0.01 * std::abs(curve_at(curve, -0.0055)), 3);
  const BackAnalysis ba = BackAnalysis::from_string(text, "b.toml");
  Journal journal("", ba.hash(), 2, ba.points());
  const FitResult r = calibrate(ba, journaled(journal, local(ba)));
  INFO(report_files(ba, r).at("report.md"));
  CHECK(r.determined[0]);
  CHECK(r.determined[1]);
  CHECK(r.low95[0] < c_true);
  CHECK(r.high95[0] > c_true);
  CHECK(r.low95[1] < phi_true);
  CHECK(r.high95[1] > phi_true);
  CHECK(r.correlation(0, 1) < -0.9); // more c, less phi: the same bearing curve
}

TEST_CASE("calibrate: bad input is refused with its place", "[calibrate]") {
  Env env;
  const fs::path dir = work_dir("bad");
  const std::string good = (dir / "good.csv").string(), back = (dir / "back.csv").string();
  std::ofstream(good) << "# gauges\nx_measured,y_measured\n15,1\n30,2\n45,3\n";
  std::ofstream(back) << "x_measured,y_measured\n15,1\n30,2\n25,3\n";
  const std::string E =
      "[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\nstart = 2e4\nlower = 1e3\n"
      "upper = 1e5\n";
  const auto refused = [](const std::string& text, const std::string& where, const std::string& what) {
    try {
      (void)BackAnalysis::from_string(text, "bad.toml");
      FAIL("accepted: " << text);
    } catch (const Error& e) {
      INFO(e.what());
      CHECK_THAT(std::string(e.what()), Catch::StartsWith(where) && Catch::Contains(what));
    }
  };
  refused(
      pile_calibration("[[parameters]]\nname = \"E\"\npath = \"materials.sol.E\"\nstart = 2e4\nlower = 1e3\n"
                       "upper = 1e5\n",
                       good),
      "bad.toml:6:8", "materials.sol.E");
  refused(
      pile_calibration("[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\nstart = 2e4\nlower = 1e5\n"
                       "upper = 1e3\n",
                       good),
      "bad.toml:8:9", "reversed");
  refused(pile_calibration(E, back), back + ":4:1", "strictly monotonic");
  refused(pile_calibration(E, good).replace(pile_calibration(E, good).find("y_column = \"y_measured\""), 23,
                                            "y_column = \"s_mm\""),
          "bad.toml:", "is not a column of");
  refused(pile_calibration(E + "[[parameters]]\nname = \"nu\"\npath = \"materials.soil.nu\"\nstart = 0.3\n"
                               "lower = 0.1\nupper = 0.45\n[[parameters]]\nname = \"Ec\"\npath = "
                               "\"materials.concrete.E\"\nstart = 3e7\nlower = 1e7\nupper = 5e7\n",
                           good),
          "bad.toml:", "more points than parameters");
  refused(
      pile_calibration("[[parameters]]\nname = \"E\"\npath = \"materials.soil.E\"\nstart = 2e4\nlower = 0.0\n"
                       "upper = 1e5\nlog = true\n",
                       good),
      "bad.toml:8:9", "lower must be > 0");
  refused(pile_calibration(E, good) + "stage = \"loading\"\n",
          "bad.toml:", "stage acts only on recorder columns");
}

} // namespace test_calibrate
