// The loess-pile scene end to end through the command line, on a coarser mesh and load
// programme than the default run: staged construction, head load, curves, checkpoints,
// a restart from the concrete stage, the plots.
#include <catch2/catch.hpp>
#include <map>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace test_loess_pile {

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void replace(std::string& s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  s.replace(at, from.size(), to);
}

int sh(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The default scene on a coarse mesh, its head loaded to `force` kN in `steps` steps.
std::string coarse_scene(const std::string& steps, const std::string& force) {
  std::string scene = slurp(fs::path(STRATUM_SOURCE_DIR) / "inputs/loess_pile/hypoelastic.toml");
  replace(scene, "n_shaft = 12", "n_shaft = 6");
  replace(scene, "n_near = 8", "n_near = 4");
  replace(scene, "n_far = 5", "n_far = 2");
  replace(scene, "n_below = 6", "n_below = 3");
  replace(scene, "n_deep = 3", "n_deep = 1");
  replace(scene, "steps = 240 ", "steps = " + steps + " ");
  replace(scene, "force = 150.0", "force = " + force);
  return scene;
}

const std::string exe = std::string("STRATUM_PLUGIN_PATH=") + STRATUM_PLUGIN_DIR + " " + STRATUM_EXE;

} // namespace

TEST_CASE("the loess pile scene runs end to end and writes its curves", "[loess_pile][cli]") {
  const fs::path dir = fs::temp_directory_path() / ("stratum_loess_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "pile.toml") << coarse_scene("2", "10.0");
  // tools/run itself, on this build tree (it builds nothing here: the tree is up to date).
  REQUIRE(sh("cd " + dir.string() + " && STRATUM_BUILD=" + STRATUM_BINARY_DIR + " " + STRATUM_SOURCE_DIR +
             "/tools/run pile.toml > run.txt 2> err.txt") == 0);
  const std::string out = slurp(dir / "run.txt");
  INFO(out << slurp(dir / "err.txt"));
  CHECK(out.find("load (kN)   settlement (mm)") != std::string::npos);
  CHECK(out.find("\n       10.0  ") != std::string::npos); // the table's last row
  CHECK(out.find("run time: ") != std::string::npos);
  const fs::path res = dir / "out" / "pile";
  const std::string ls = slurp(res / "curves" / "load_settlement.csv");
  CHECK(ls.rfind("load_kN,settlement_mm\n0,0\n", 0) == 0);
  CHECK(std::count(ls.begin(), ls.end(), '\n') == 4); // header, 0, 5 and 10 kN
  CHECK(slurp(res / "curves" / "axial_force.csv").rfind("load_kN,depth_m,axial_force_kN\n", 0) == 0);
  {
    // The shaft carries load: at 10 kN the axial force at the deepest section is well below the
    // force near the head (it was not when the shaft interface opened in the concrete stage).
    std::istringstream in(slurp(res / "curves" / "axial_force.csv"));
    std::string line;
    std::getline(in, line);
    double top = -1.0, bottom = -1.0, top_depth = 1e9, bottom_depth = -1.0;
    while (std::getline(in, line)) {
      double load = 0, depth = 0, force = 0;
      char c1 = 0, c2 = 0;
      std::istringstream row(line);
      row >> load >> c1 >> depth >> c2 >> force;
      if (std::abs(load - 10.0) > 1e-9) continue;
      if (depth < top_depth) top_depth = depth, top = force;
      if (depth > bottom_depth) bottom_depth = depth, bottom = force;
    }
    INFO("axial force at 10 kN: " << top << " kN at " << top_depth << " m, " << bottom << " kN at "
                                  << bottom_depth << " m");
    CHECK(top == Approx(10.0).epsilon(0.05));
    CHECK(bottom < 0.8 * top);
  }
  CHECK(slurp(res / "curves" / "shaft_traction.csv")
            .rfind("load_kN,depth_m,shear_traction_kPa,normal_traction_kPa,slip_mm,status\n", 0) == 0);
  // Only the shaft's points: at the toe depth one row per load (the shaft's last point), not also
  // the corner point of the base's first interface cell (found at 03c8311: a second row there with
  // the base's vertical normal traction).
  {
    std::istringstream rows(slurp(res / "curves" / "shaft_traction.csv"));
    std::string line;
    std::getline(rows, line);
    std::map<std::string, std::vector<double>> depths; // per load level
    while (std::getline(rows, line)) {
      const auto c1 = line.find(','), c2 = line.find(',', c1 + 1);
      depths[line.substr(0, c1)].push_back(std::stod(line.substr(c1 + 1, c2 - c1 - 1)));
    }
    REQUIRE(depths.size() > 2);
    for (const auto& [load, d] : depths) {
      const double toe = *std::max_element(d.begin(), d.end());
      INFO("load " << load << " kN, toe depth " << toe);
      CHECK(std::count(d.begin(), d.end(), toe) == 1);
    }
  }
  CHECK(fs::exists(res / "pile.pvd"));
  CHECK(fs::exists(res / "diagnostics.csv"));
  REQUIRE(fs::exists(res / "checkpoints" / "3_concrete.ckpt"));

  // Restart from the concrete stage: the loading stage gives the same curve, bit for bit.
  REQUIRE(
      sh("cd " + dir.string() + " && " + exe +
         " run pile.toml --out restarted --restart-from out/pile/checkpoints/3_concrete.ckpt > r.txt 2>&1") ==
      0);
  CHECK(slurp(dir / "restarted" / "curves" / "load_settlement.csv") == ls);

  // The integration points carry the per-point status "plastic" (Material::point_status): the
  // Duncan-Chang soil reports 0, 1 or 2, linear cells (pile, far zone) -1, interfaces -1.
  {
    int last = -1;
    for (const auto& e : fs::directory_iterator(res)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("pile_ip_", 0) == 0) last = std::max(last, std::stoi(n.substr(8)));
    }
    REQUIRE(last > 0);
    auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    reader->SetFileName((res / ("pile_ip_" + std::to_string(last) + ".vtp")).string().c_str());
    reader->Update();
    vtkDataArray* plastic = reader->GetOutput()->GetPointData()->GetArray("plastic");
    REQUIRE(plastic != nullptr);
    int soil = 0, other = 0;
    for (vtkIdType i = 0; i < plastic->GetNumberOfTuples(); ++i) {
      const double v = plastic->GetTuple1(i);
      CHECK((v == -1.0 || v == 0.0 || v == 1.0 || v == 2.0));
      (v >= 0 ? soil : other) += 1;
    }
    CHECK(soil > 100);
    CHECK(other > 10);
  }

  // The plots that tools/run drew: its set-up installs python3-matplotlib, so they must exist.
  CHECK(fs::file_size(res / "curves" / "load_settlement.png") > 1000);
  CHECK(fs::file_size(res / "curves" / "axial_force.png") > 1000);
  CHECK(fs::file_size(res / "curves" / "shaft_traction.png") > 1000);
  // The plastic zone at a chosen load (without ParaView's modules the script draws it with VTK's
  // Python reader, python3-vtk9, a dependency of libvtk9-dev, and matplotlib).
  REQUIRE(sh("/usr/bin/python3 " + std::string(STRATUM_SOURCE_DIR) + "/tools/plastic_zone.py " +
             res.string() + " --load 5 -o " + (dir / "zone.png").string() + " > /dev/null") == 0);
  CHECK(fs::file_size(dir / "zone.png") > 1000);
  fs::remove_all(dir);
}

TEST_CASE("a pile loaded past its capacity stops cleanly and names the step that failed",
          "[loess_pile][cli]") {
  // The coarse scene to 150 kN in 30 kN steps: far beyond what its shaft and base carry, so a
  // step fails after its 5 cut-backs; the run ends normally (exit 0)
  // with the stop line on stdout, and stderr names the step that failed, which starts at the
  // last converged level of the curve.
  const fs::path dir = fs::temp_directory_path() / ("stratum_loess_stop_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // Without the settlement limit: with the branch-consistent iteration the coarse mesh's large
  // steps converge past 27 mm (42 mm at 118 kN), so the limit would end the run first; the next
  // step then fails (Newton's contraction test) after its cut-backs.
  // With the force test alone: the scene's displacement test makes the last steps before the
  // collapse harder to converge on this coarse mesh, and the run then ends one step earlier
  // (116 kN, exit 4) as a numerical failure of a still-stiff structure, which is not the case
  // this test is about.
  std::string scene = coarse_scene("5", "150.0");
  replace(scene, "stop_settlement = 0.027", "stop_settlement = 0.0");
  replace(scene, "displacement_test = true", "displacement_test = false");
  std::ofstream(dir / "pile.toml") << scene;
  REQUIRE(sh("cd " + dir.string() + " && " + exe + " run pile.toml > run.txt 2> err.txt") == 0);
  const std::string out = slurp(dir / "run.txt"), err = slurp(dir / "err.txt");
  INFO(out << err);
  CHECK(out.find("\nstopped: collapse: a load step found no equilibrium after its cut-backs") !=
        std::string::npos);
  const std::string lead =
      "stratum: the step that stopped the run at the collapse: stage \"loading\": step from load factor ";
  const auto at = err.find(lead);
  REQUIRE(at != std::string::npos);
  CHECK(err.find("(gave up after 5 cut-backs)", at) != std::string::npos);
  const double from = std::stod(err.substr(at + lead.size()));
  const std::string ls = slurp(dir / "out" / "pile" / "curves" / "load_settlement.csv");
  const auto last = ls.rfind('\n', ls.size() - 2);
  const double last_load = std::stod(ls.substr(last + 1));
  // The message prints the load factor to 6 significant digits (relative rounding <= 5e-6 for
  // factors >= 0.1), the CSV the load to 10.
  REQUIRE(from >= 0.1);
  CHECK(last_load == Approx(150.0 * from).epsilon(5e-6));
  CHECK(last_load < 150.0);
  fs::remove_all(dir);
}

namespace {

// A load-settlement curve from a CSV file (lines starting with '#' are comments, then a header).
std::vector<std::pair<double, double>> read_curve(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<std::pair<double, double>> c;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    const auto comma = line.find(',');
    c.emplace_back(std::stod(line.substr(0, comma)), std::stod(line.substr(comma + 1)));
  }
  return c;
}
// Linear interpolation: settlement at a load (x = 0), or load at a settlement (x = 1).
double interpolate(const std::vector<std::pair<double, double>>& c, double v, bool load_at_settlement) {
  for (std::size_t i = 1; i < c.size(); ++i) {
    double a0 = c[i - 1].first, a1 = c[i].first, b0 = c[i - 1].second, b1 = c[i].second;
    if (load_at_settlement) std::swap(a0, b0), std::swap(a1, b1);
    if (a0 <= v && v <= a1 && a1 > a0) return b0 + (b1 - b0) * (v - a0) / (a1 - a0);
  }
  return std::nan("");
}

} // namespace

TEST_CASE("the default loess pile scene against its converged reference curve",
          "[loess_pile][cli][reference]") {
  // tests/data/loess_pile_reference.csv: the default scene's whole curve with 0.0625 kN load
  // steps (its header says how and at which commit it was computed). The scene loads in
  // 0.625 kN steps; the explicit update is first order in the step (docs/benchmarks.md: +0.22,
  // +0.05, -0.35 and -1.45 % at 15, 30, 45 and 60 kN, +0.64 % in the load at 27 mm). The bounds
  // are the targets of issue 18 (1 % in settlement, 2 % in the load at 27 mm) up to 45 kN, where
  // perturbations of the scene (another LU, the tolerance by a factor 1.4, 4 % of the step count)
  // move the curve by 0.2 % at most, so the test does not pass by luck. At 60 kN the same
  // perturbations spread it over 3 % (the increment rule has several equilibrium states near
  // failure, or none: plugins/duncan_chang/README.md, "Why the settlement near failure is a
  // band"); 2.5 % there guards this scene's schedule against changes, it is not a statement of
  // accuracy. A solver that accepted states on the wrong branches, or a changed model, moves the
  // curve by more.
  const auto ref = read_curve(fs::path(STRATUM_SOURCE_DIR) / "tests/data/loess_pile_reference.csv");
  REQUIRE(ref.size() > 500);
  const fs::path dir = fs::temp_directory_path() / ("stratum_loess_ref_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string scene = slurp(fs::path(STRATUM_SOURCE_DIR) / "inputs/loess_pile/hypoelastic.toml");
  replace(scene, "vtk = true", "vtk = false"); // no effect on the numbers
  std::ofstream(dir / "pile.toml") << scene;
  REQUIRE(sh("cd " + dir.string() + " && " + exe + " run pile.toml --out out > run.txt 2>&1") == 0);
  const auto curve = read_curve(dir / "out" / "curves" / "load_settlement.csv");
  INFO(slurp(dir / "run.txt"));
  // load (kN), largest relative deviation from the reference
  const std::vector<std::pair<double, double>> bounds{
      {15.0, 0.01}, {30.0, 0.01}, {45.0, 0.01}, {60.0, 0.025}};
  for (const auto& [load, tol] : bounds) {
    const double w = interpolate(curve, load, false), w_ref = interpolate(ref, load, false);
    INFO(load << " kN: " << w << " mm against the reference " << w_ref << " mm");
    CHECK(std::abs(w - w_ref) <= tol * w_ref);
  }
  // The load at 27 mm (10 % of the diameter), within 2 % of the reference's.
  const double p = interpolate(curve, 27.0, true), p_ref = interpolate(ref, 27.0, true);
  INFO("load at 27 mm: " << p << " kN against the reference " << p_ref << " kN");
  CHECK(std::abs(p - p_ref) <= 0.02 * p_ref);
  fs::remove_all(dir);
}

} // namespace test_loess_pile
