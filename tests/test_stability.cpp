// The reduced numerical stability matrix (issue 8): a representative subset of
// tools/benchmarks/bench_stability's runs, each a `stratum run` child process, asserting no crash,
// no timeout, no NaN/Inf in any output and no silent failure. First the harness itself is
// shown to catch each of those.
#include "../tools/benchmarks/stability_harness.hpp"

#include <catch2/catch.hpp>

#include <vtkDoubleArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace test_stability {

namespace fs = std::filesystem;
namespace st = stratum::bench::stability;

namespace {

fs::path scratch(const std::string& name) {
  const auto d = fs::temp_directory_path() / ("stratum_test_stability_" + std::to_string(getpid())) / name;
  fs::create_directories(d);
  return d;
}

/// A stand-in for the stratum executable: a shell script doing `body`.
fs::path fake_exe(const fs::path& dir, const std::string& body) {
  const auto p = dir / "fake_stratum.sh";
  {
    std::ofstream f(p);
    f << "#!/bin/sh\n" << body << "\n";
  }
  chmod(p.c_str(), 0755);
  return p;
}

} // namespace

TEST_CASE("stability harness: TOML edits", "[stability]") {
  const std::string t =
      "title = \"x\"\n[analysis]\nsteps = 25 # c\n[solver]\nline_search = 8\n[materials.a]\n"
      "model = \"von_mises\"\n";
  std::string r = st::set_steps(t, 7);
  CHECK(r.find("steps = 7\n") != std::string::npos);
  CHECK(r.find("steps = 25") == std::string::npos);
  r = st::set_solver(r, "kinsol");
  CHECK(r.find("[solver]") == std::string::npos);
  CHECK(r.find("solver = \"kinsol\"") != std::string::npos);
  r = st::set_key(r, "[materials.a]", "integrator", "\"midpoint\"");
  CHECK(r.find("[materials.a]\nintegrator = \"midpoint\"\n") != std::string::npos);
  const std::string staged = "[analysis]\n[[stages]]\nname = \"a\"\nsteps = 4\n[[stages]]\nname = \"b\"\n"
                             "steps = 60\n[[stages.actions]]\ntype = \"load\"\n";
  const std::string s2 = st::set_steps(staged, 3);
  CHECK(s2.find("steps = 4\n") != std::string::npos);
  CHECK(s2.find("name = \"b\"\nsteps = 3\n") != std::string::npos);
}

TEST_CASE("stability harness: a scene's relative includes run from the harness' folder", "[stability]") {
  // Found in issue 25's evidence: the pile scenes include ../materials/*.toml, which did not
  // exist beside the harness' copy of the scene (every run an input error).
  const std::string text = "title = \"t\"\ninclude = [  # shared sets\n  \"../materials/a.toml\",\n"
                           "  \"/abs/b.toml\",\n]\n[analysis]\nsolver = \"newton\"\n";
  const std::string r = st::absolute_includes(text, "/src/inputs/loess_pile");
  CHECK(r.find("\"/src/inputs/materials/a.toml\"") != std::string::npos);
  CHECK(r.find("\"/abs/b.toml\"") != std::string::npos);
  CHECK(r.find("[analysis]\nsolver = \"newton\"\n") != std::string::npos);
  CHECK(st::absolute_includes("[analysis]\n", "/x") == "[analysis]\n");
  // The single-string form, and a key that only starts with "include" is left alone.
  CHECK(st::absolute_includes("include = \"m.toml\"\n[a]\nx = [\"y\"]\n", "/s/d") ==
        "include = \"/s/d/m.toml\"\n[a]\nx = [\"y\"]\n");
  CHECK(st::absolute_includes("[a]\nincluded = \"m.toml\"\n", "/s") == "[a]\nincluded = \"m.toml\"\n");
  // The committed pile scene through input_scene: every include resolves.
  const auto s = st::input_scene(STRATUM_SOURCE_DIR, "inputs/loess_pile/hardening_soil.toml");
  CHECK(s.text.find("../materials") == std::string::npos);
  CHECK(s.text.find(std::string(STRATUM_SOURCE_DIR)) != std::string::npos);
  // The model of a scene whose soil set is included (inputs/materials/loess_cap.toml) chooses the
  // integrators the matrix varies, as when the set was written in the scene.
  const auto cap = st::input_scene(STRATUM_SOURCE_DIR, "inputs/loess_pile/cap.toml");
  CHECK(cap.text.find("model = \"cap_sandler\"") == std::string::npos);
  CHECK(cap.integ_table == "[materials.loess]");
  CHECK(cap.integ_key == "integrator");
  CHECK(cap.integrators == std::vector<std::string>{"closest_point", "sandler_rubin"});
}

TEST_CASE("stability harness: catches crashes, NaN/Inf and silent failures", "[stability]") {
  const auto dir = scratch("harness");
  SECTION("NaN in CSV text and Inf in a VTK array") {
    long n = 0;
    CHECK(st::scan_text("a,b\n1,2.5e-3\n\"message with inf inside\",3\n", n).empty());
    CHECK(st::scan_text("1,-nan,3\n", n) == "-nan");
    CHECK(st::scan_text("1,\"residual is NaN or Inf\",nan\n", n) == "nan");
    CHECK(st::scan_text("1;2;inf\n", n) == "inf");
    const auto out = dir / "vtk";
    fs::create_directories(out);
    vtkNew<vtkUnstructuredGrid> g;
    vtkNew<vtkPoints> p;
    p->InsertNextPoint(0, 0, 0);
    p->InsertNextPoint(1, 0, 0);
    g->SetPoints(p);
    vtkNew<vtkDoubleArray> a;
    a->SetName("stress");
    a->InsertNextValue(1.0);
    a->InsertNextValue(std::numeric_limits<double>::infinity());
    g->GetPointData()->AddArray(a);
    vtkNew<vtkXMLUnstructuredGridWriter> w;
    w->SetFileName((out / "s_0.vtu").c_str());
    w->SetInputData(g);
    w->SetDataModeToAppended();
    w->SetCompressorTypeToZLib();
    REQUIRE(w->Write() == 1);
    st::Outcome o;
    CHECK(st::scan_outputs(out, o) == "s_0.vtu: stress");
  }
  SECTION("a history variable NaN over whole domains is complete; a NaN within a domain is not") {
    auto cloud = [](std::vector<double> values) {
      auto g = vtkSmartPointer<vtkUnstructuredGrid>::New();
      vtkNew<vtkPoints> p;
      vtkNew<vtkDoubleArray> domain, h;
      domain->SetName("domain");
      h->SetName("kappa [kPa]");
      for (int i = 0; i < 4; ++i) {
        p->InsertNextPoint(i, 0, 0);
        domain->InsertNextValue(i < 2 ? 0 : 1);
        h->InsertNextValue(values[static_cast<std::size_t>(i)]);
      }
      g->SetPoints(p);
      g->GetPointData()->AddArray(domain);
      g->GetPointData()->AddArray(h);
      return g;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    long n = 0;
    CHECK(st::scan_dataset(cloud({1.0, 2.0, nan, nan}), n).empty()); // domain 1 has no kappa
    CHECK(st::scan_dataset(cloud({1.0, nan, nan, nan}), n) == "kappa [kPa]");
    CHECK(st::scan_dataset(cloud({1.0, 2.0, std::numeric_limits<double>::infinity(), 3.0}), n) ==
          "kappa [kPa]");
  }
  SECTION("a signal is a crash") {
    const auto o = st::run_case(fake_exe(dir, "kill -SEGV $$"), "", dir / "run", 10);
    CHECK(o.kind == st::Kind::crash);
  }
  SECTION("exit 3 is a crash") {
    const auto o =
        st::run_case(fake_exe(dir, "echo 'stratum: internal error: x' >&2; exit 3"), "", dir / "run", 10);
    CHECK(o.kind == st::Kind::crash);
  }
  SECTION("a hang is a timeout") {
    const auto o = st::run_case(fake_exe(dir, "sleep 30"), "", dir / "run", 0.5);
    CHECK(o.kind == st::Kind::timeout);
    CHECK(o.seconds < 10);
  }
  SECTION("exit 0 short of load factor 1 is silent") {
    const std::string csv =
        "stage,step,accepted,lambda_n,lambda,iterations\\n1,1,1,0,0.5,3\\n1,2,0,0.5,1,40\\n";
    const auto o = st::run_case(
        fake_exe(dir, "mkdir -p \"$4\"; printf '" + csv + "' > \"$4/diagnostics.csv\"; echo 'done: 1 steps'"),
        "", dir / "run", 10);
    CHECK(o.kind == st::Kind::silent);
  }
  SECTION("exit 0 with NaN in the printed table") {
    const std::string csv = "stage,step,accepted,lambda_n,lambda\\n1,1,1,0,1\\n";
    const auto o =
        st::run_case(fake_exe(dir, "mkdir -p \"$4\"; printf '" + csv +
                                       "' > \"$4/diagnostics.csv\"; echo 'done: 1 steps'; echo '  nan  1.0'"),
                     "", dir / "run", 10);
    CHECK(o.kind == st::Kind::nan_inf);
  }
  SECTION("exit 4 is a numerical stop, and needs its 'stopped: numerical failure' line") {
    const std::string csv = "stage,step,accepted,lambda_n,lambda\\n1,1,1,0,0.5\\n1,2,0,0.5,1\\n";
    const auto o =
        st::run_case(fake_exe(dir, "mkdir -p \"$4\"; printf '" + csv +
                                       "' > \"$4/diagnostics.csv\"; echo 'done: 1 steps'; "
                                       "echo 'stopped: numerical failure: Newton not converging'; exit 4"),
                     "", dir / "run", 10);
    CHECK(o.kind == st::Kind::numerical);
    CHECK(o.exit_code == 4);
    // The same exit without the line says nothing of why: silent.
    const auto s = st::run_case(fake_exe(dir, "mkdir -p \"$4\"; printf '" + csv +
                                                  "' > \"$4/diagnostics.csv\"; echo 'done: 1 steps'; exit 4"),
                                "", dir / "run", 10);
    CHECK(s.kind == st::Kind::silent);
  }
  SECTION("exit 2 needs one message line") {
    CHECK(st::run_case(fake_exe(dir, "exit 2"), "", dir / "run", 10).kind == st::Kind::silent);
    CHECK(st::run_case(fake_exe(dir, "echo 'stratum: s.toml: not converged: x' >&2; exit 2"), "", dir / "run",
                       10)
              .kind == st::Kind::failed);
  }
  std::error_code ec;
  fs::remove_all(dir.parent_path(), ec);
}

TEST_CASE("stability matrix, reduced: no crash, NaN/Inf or silent failure", "[stability]") {
  const fs::path src = STRATUM_SOURCE_DIR;
  std::vector<st::Scene> scenes;
  for (const char* f :
       {"inputs/verification/lame_axisymmetric.toml", "inputs/verification/lame_plane_strain.toml",
        "inputs/verification/circular_load.toml", "inputs/verification/hill_cylinder.toml",
        "inputs/verification/strip_footing.toml"})
    scenes.push_back(st::input_scene(src, f));
  scenes.push_back(st::variant(scenes[0], "nu=0.499", "[materials.steel]", "nu", "0.499"));
  scenes.push_back(st::variant(scenes[3], "nu=0.499", "[materials.steel]", "nu", "0.499"));
  scenes.push_back(st::duncan_chang_near_failure(0.99));
  scenes.push_back(st::cap_near_apex());
  const auto dir = scratch("matrix");
  const auto t0 = std::chrono::steady_clock::now();
  int runs = 0, converged = 0;
  std::vector<std::pair<std::string, std::string>> seen; // case, outcome
  for (const auto& s : scenes) {
    std::vector<std::string> integ{""};
    if (s.integrators == st::plasticity_integrators()) // the general plasticity models
      integ = {"forward_euler", "closest_point"};
    else if (!s.integrators.empty())
      integ = s.integrators;
    // The strip footing (520 quad8 cells) is the expensive one: Newton at 5 increments only.
    const bool strip = s.name.rfind("strip_footing", 0) == 0;
    const std::vector<std::string> solvers =
        strip ? std::vector<std::string>{"newton"} : std::vector<std::string>{"newton", "modified_newton"};
    const std::vector<int> increments = strip ? std::vector<int>{5} : std::vector<int>{1, 5, 20};
    for (const auto& in : integ)
      for (const auto& solver : solvers)
        for (int n : increments) {
          const auto o = st::run_case(STRATUM_EXE, st::run_text(s, solver, in, n), dir / "run", 120);
          INFO(s.name << ", " << (in.empty() ? "-" : in) << ", " << solver << ", " << n
                      << " increments: " << st::to_string(o.kind) << " (" << o.message << ")");
          CHECK_FALSE(st::is_bug(o.kind));
          const std::string key =
              s.name + " | " + (in.empty() ? "-" : in) + " | " + solver + " | " + std::to_string(n);
          seen.emplace_back(key, st::to_string(o.kind));
          // The outputs were really read: diagnostics.csv at least, and numbers in it.
          CHECK(o.files_checked >= 1);
          CHECK(o.values_checked > 0);
          ++runs;
          converged += o.kind == st::Kind::converged;
        }
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  WARN(runs << " runs, " << converged << " converged, " << secs << " s");
  // Each case pinned to its outcome (found on 997ba04: the matrix accepted any clean failure and
  // needed only half of its cases to converge). The linear scenes converge with every solver and
  // increment count; what does not converge, and why:
  // - modified Newton keeps the first (elastic) matrix of a step: Hill's perfectly plastic
  //   cylinder to 0.99 P_lim in one (or, with the consistent return, five) increments and the
  //   Duncan-Chang sample at 0.99 q_f with the incremental update in 1 or 5 do not reach the
  //   tolerance in max_iterations;
  // - the strip footing with forward-Euler stresses (no consistent tangent) in 5 increments.
  // A change either way (a new failure, or a case that starts converging) fails here and is
  // looked at, then the table is updated with the reason.
  const std::map<std::string, std::string> not_converged{
      {"hill_cylinder | forward_euler | modified_newton | 1", "failed"},
      {"hill_cylinder | closest_point | modified_newton | 1", "failed"},
      {"hill_cylinder | closest_point | modified_newton | 5", "failed"},
      {"hill_cylinder nu=0.499 | forward_euler | modified_newton | 1", "failed"},
      {"hill_cylinder nu=0.499 | closest_point | modified_newton | 1", "failed"},
      {"strip_footing | forward_euler | newton | 5", "failed"},
      {"duncan_chang sample q/q_f=0.99 | incremental | modified_newton | 1", "failed"},
      {"duncan_chang sample q/q_f=0.99 | incremental | modified_newton | 5", "failed"},
  };
  std::size_t pinned = 0;
  for (const auto& [key, kind] : seen) {
    const auto it = not_converged.find(key);
    INFO(key);
    CHECK(kind == (it == not_converged.end() ? "converged" : it->second));
    pinned += it != not_converged.end();
  }
  CHECK(seen.size() == 74);
  CHECK(pinned == not_converged.size()); // every pinned case ran
  std::error_code ec;
  fs::remove_all(dir.parent_path(), ec);
}

TEST_CASE("stability harness: diagnostics.csv may record the NaN of a rejected attempt only", "[stability]") {
  const auto dir = scratch("diag");
  const std::string head = "stage,step,accepted,lambda_n,lambda,iterations,residuals,message\n";
  {
    std::ofstream f(dir / "diagnostics.csv");
    f << head << "1,1,0,0,1,2,1;nan,\"residual is NaN or Inf\"\n1,1,1,0,0.5,3,1;1e-9,\"\"\n";
  }
  st::Outcome o;
  CHECK(st::scan_outputs(dir, o).empty());
  {
    std::ofstream f(dir / "diagnostics.csv");
    f << head << "1,1,1,0,1,2,1;nan,\"\"\n";
  }
  CHECK(st::scan_outputs(dir, o) == "diagnostics.csv: nan");
  std::error_code ec;
  fs::remove_all(dir.parent_path(), ec);
}

} // namespace test_stability
