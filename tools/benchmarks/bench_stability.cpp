// bench_stability: the numerical stability matrix (issue 8, deliverable 3). Every scene of
// inputs/verification and inputs/loess_pile, and extreme variants of them (nu = 0.499,
// phi = 1 degree, contact normal stiffness x 1e6, Duncan-Chang near failure, the cap at the
// apex), runs with 1, 2, 5, 10, 20, 50 and 100 load increments under each load-controlled
// solver and each stress integrator its material offers. Each run is a `stratum run` child
// process with a time limit; its outcome (stability_harness.hpp) is converged, stopped
// (loading to failure), a clean failure (exit 2 with one message line), or a bug: crash,
// timeout, NaN/Inf in an output, silent failure, input error. The table goes to
// docs/benchmarks.md.
//
// Usage: bench_stability [--quick | --full] [--filter TEXT] [--timeout S] [--no-write] [--docs PATH]
//                        [--keep DIR]
#include "docs_section.hpp"
#include "stability_harness.hpp"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
namespace st = stratum::bench::stability;

namespace {

constexpr const char* begin_marker = "<!-- bench_stability:begin -->";
constexpr const char* end_marker = "<!-- bench_stability:end -->";

/// One block of the matrix: a scene and the solvers, integrators and increments it runs with.
struct Block {
  st::Scene scene;
  std::vector<std::string> solvers;
  std::vector<std::string> integrators; ///< empty: the scene's own (no integrator choice)
  std::vector<int> increments;
};

struct Run {
  std::string scene, solver, integrator;
  int increments = 0;
  st::Outcome outcome;
};

std::vector<Block> matrix(const fs::path& src, bool quick, bool full) {
  const std::vector<int> all{1, 2, 5, 10, 20, 50, 100};
  const std::vector<int> few{1, 5, 20};
  const std::vector<std::string> solvers{"newton", "modified_newton", "initial_stiffness", "kinsol"};
  const auto& inc = quick ? few : all;
  std::vector<Block> b;
  auto add = [&](st::Scene s, std::vector<std::string> sv, std::vector<std::string> integ,
                 std::vector<int> n) {
    if (integ.empty()) integ = s.integrators;
    b.push_back({std::move(s), std::move(sv), std::move(integ), std::move(n)});
  };
  // The default matrix is sized for about half an hour on the shared 2-core machine; --full
  // runs every solver x integrator x increment combination of every block (hours).
  const auto pick = [&](const std::vector<int>& n) { return full ? all : n; };
  const auto sv = [&](const std::vector<std::string>& s) { return full ? solvers : s; };
  const std::vector<std::string> newton{"newton"}, others{"modified_newton", "initial_stiffness", "kinsol"};
  // Linear scenes: every solver and increment count.
  for (const char* f :
       {"inputs/verification/lame_axisymmetric.toml", "inputs/verification/lame_plane_strain.toml",
        "inputs/verification/circular_load.toml"})
    add(st::input_scene(src, f), solvers, {}, inc);
  const auto lame = st::input_scene(src, "inputs/verification/lame_axisymmetric.toml");
  const auto circ = st::input_scene(src, "inputs/verification/circular_load.toml");
  const auto hill = st::input_scene(src, "inputs/verification/hill_cylinder.toml");
  const auto strip = st::input_scene(src, "inputs/verification/strip_footing.toml");
  add(st::variant(lame, "nu=0.499", "[materials.steel]", "nu", "0.499"), solvers, {}, inc);
  add(st::variant(circ, "nu=0.499", "[materials.soil]", "nu", "0.499"), solvers, {}, pick(few));
  // Hill's cylinder: Newton with every integrator and increment count, the other solvers with
  // closest_point at 1, 5, 20.
  add(hill, newton, {}, inc);
  add(hill, others, {"closest_point"}, pick(few));
  add(st::variant(hill, "nu=0.499", "[materials.steel]", "nu", "0.499"), sv(newton),
      {"forward_euler", "closest_point"}, pick(few));
  // Small extreme samples: every solver and update, 1, 5, 20 increments.
  add(st::duncan_chang_near_failure(0.99), solvers, {}, pick(few));
  add(st::duncan_chang_near_failure(1.05), solvers, {}, pick(few));
  add(st::cap_near_apex(), solvers, {}, pick(few));
  // The strip footing (520 quad8 cells, about a minute of CPU for 100 steps): Newton with
  // closest_point at 1, 5, 20 increments, the other solvers and integrators at 5.
  add(strip, newton, {"closest_point"}, pick(few));
  add(strip, sv(others), {"closest_point"}, pick({5}));
  // The explicit and generalized-midpoint integrators have no consistent tangent: Newton then
  // converges linearly on the footing and a run takes minutes, so --quick leaves them (and the
  // two slowest variants) to the default matrix.
  if (!quick) {
    add(strip, newton, {"forward_euler", "modified_euler", "trapezoidal", "midpoint", "cutting_plane"},
        pick({5}));
    add(st::variant(strip, "nu=0.499", "[materials.clay]", "nu", "0.499"), sv(newton), {"closest_point"},
        pick({5}));
  }
  add(st::strip_footing_mohr_coulomb(strip), sv(newton),
      quick ? std::vector<std::string>{"closest_point"}
            : std::vector<std::string>{"forward_euler", "closest_point"},
      pick({5}));
  // The loess pile scenes (staged; minutes of wall time a run here): Newton, the scenes' solver,
  // with their own update/integration at 1 and 5 loading steps; the extreme variants at 5.
  auto hypo = st::input_scene(src, "inputs/loess_pile/hypoelastic.toml");
  auto cap = st::input_scene(src, "inputs/loess_pile/cap.toml");
  hypo.name = "loess_pile/hypoelastic";
  cap.name = "loess_pile/cap";
  for (const auto& s : {hypo, cap}) {
    add(s, sv(newton), {s.integrators.front()}, quick ? std::vector<int>{5} : pick({1, 5}));
    add(st::variant(s, "k_n x 1e6", "[contact_laws.loess_concrete]", "k_n", "1.0e13"), sv(newton),
        {s.integrators.front()}, pick({5}));
  }
  add(st::variant(hypo, "phi=1", "[materials.loess]", "phi", "[1.0, 1.0]"), sv(newton), {"explicit"},
      pick({5}));
  // Hardening Soil (an analysis after the field test): no integrator choice, Newton at 1 and 5
  // loading steps; a run takes about a minute, so --quick (the CTest matrix) leaves it out.
  if (!quick) {
    auto hsoil = st::input_scene(src, "inputs/loess_pile/hardening_soil.toml");
    hsoil.name = "loess_pile/hardening_soil";
    add(hsoil, sv(newton), {}, pick({1, 5}));
  }
  if (full) { // one block per scene: every solver, integrator and increment count
    std::vector<Block> f;
    for (auto& blk : b) {
      bool seen = false;
      for (const auto& g : f) seen = seen || g.scene.name == blk.scene.name;
      if (!seen) f.push_back({blk.scene, solvers, blk.scene.integrators, all});
    }
    return f;
  }
  return b;
}

} // namespace

int main(int argc, char** argv) {
  bool write = true, quick = false, full = false;
  double timeout = 300; // s; a run of the footing with a non-consistent tangent takes minutes
  std::string filter;
  fs::path docs = fs::path(STRATUM_SOURCE_DIR) / "docs" / "benchmarks.md";
  fs::path keep;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--no-write")
      write = false;
    else if (a == "--quick")
      quick = true;
    else if (a == "--full")
      full = true;
    else if (a == "--docs" && i + 1 < argc)
      docs = argv[++i];
    else if (a == "--filter" && i + 1 < argc)
      filter = argv[++i];
    else if (a == "--timeout" && i + 1 < argc)
      timeout = std::stod(argv[++i]);
    else if (a == "--keep" && i + 1 < argc)
      keep = argv[++i];
    else {
      std::cerr << "usage: bench_stability [--quick | --full] [--filter TEXT] [--timeout S] [--no-write] "
                   "[--docs PATH] "
                   "[--keep DIR]\n";
      return 2;
    }
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe").parent_path() / "stratum";
  if (!fs::exists(exe)) {
    std::cerr << "bench_stability: " << exe << " not found (build the stratum target)\n";
    return 2;
  }
  const fs::path work = fs::temp_directory_path() / ("stratum_stability_" + std::to_string(getpid()));
  const auto blocks = matrix(STRATUM_SOURCE_DIR, quick, full);
  std::vector<Run> runs;
  std::map<std::string, std::map<st::Kind, int>> counts;
  std::map<std::string, double> seconds;
  std::vector<std::string> order;
  const auto t0 = std::chrono::steady_clock::now();
  int bugs = 0;
  const st::Kind kinds[] = {st::Kind::converged, st::Kind::stopped, st::Kind::numerical,
                            st::Kind::failed,    st::Kind::crash,   st::Kind::timeout,
                            st::Kind::nan_inf,   st::Kind::silent,  st::Kind::input_error};
  const auto render = [&](bool complete, double total) {
    std::ostringstream s;
    s << begin_marker << "\n## Numerical stability matrix (`bench_stability`)\n\n"
      << "Every scene of `inputs/verification` and `inputs/loess_pile` and extreme variants (nu = 0.499, a "
         "Mohr-Coulomb soil with phi = 1 degree, contact normal stiffness x 1e6, Duncan-Chang samples at "
         "0.99 "
         "and "
         "1.05 of the failure deviator, a cap-model sample with the cap at the apex), each run a `stratum "
         "run` "
         "child process (time limit "
      << timeout
      << " s) with 1 to 100 load increments (staged scenes: the `steps` of the last, loading stage) under "
         "the "
         "load-controlled solvers `newton`, `modified_newton`, `initial_stiffness` and `kinsol` (Newton "
         "strategy) and the stress integrators of the scene's material (`integrator` of von Mises and "
         "Mohr-Coulomb, `update` of Duncan-Chang, `integration` of the cap model). Which combinations run "
         "per "
         "scene: tools/benchmarks/README.md (the default matrix; `--full` runs every combination). "
         "Outcomes: *converged* (exit 0, every stage at load factor 1, all outputs finite), *stopped* (exit "
         "0 "
         "with the stop line of a stage loaded `until_failure`: a collapse, the current stiffness below "
         "`collapse_stiffness` of the stage's first step), *numerical* (exit 4: such a stage stopped by a "
         "step that did not converge while the structure was still stiff, a defect of the solver or its "
         "settings), *failed* (exit 2 with one message line: a "
         "clean "
         "numerical failure), and the bugs *crash* (signal or exit status 3), *timeout*, *NaN/Inf* (in any "
         ".vtu/.vtp array, CSV file or the printed table), *silent* (exit 0 short of the target, or exit 2 "
         "without a clear message) and *input error* (a variant the harness built wrongly). "
      << (quick  ? "**Reduced matrix (`--quick`).** "
          : full ? "**Full matrix (`--full`).** "
                 : "")
      << "\n\n"
      << "| scene | runs | converged | stopped (collapse) | numerical | failed | crash | timeout | NaN/Inf | "
         "silent | input error | time (s) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::map<st::Kind, int> sum;
    int nruns = 0;
    for (const auto& name : order) {
      auto& c = counts[name];
      int n = 0;
      for (auto k : kinds) n += c[k], sum[k] += c[k];
      nruns += n;
      s << "| " << name << " | " << n;
      for (auto k : kinds) s << " | " << c[k];
      char buf[32];
      std::snprintf(buf, sizeof buf, " | %.0f |\n", seconds[name]);
      s << buf;
    }
    s << "| **all** | " << nruns;
    for (auto k : kinds) s << " | " << sum[k];
    char buf[64];
    std::snprintf(buf, sizeof buf, " | %.0f |\n", total);
    s << buf;
    if (!complete) s << "\n**Partial: the run is still going (" << runs.size() << " runs so far).**\n";
    s << "\nEvery run that did not converge (integrator `-`: the material has no choice):\n\n"
      << "| scene | integrator | solver | increments | outcome | message |\n|---|---|---|---|---|---|\n";
    for (const auto& r : runs) {
      if (r.outcome.kind == st::Kind::converged) continue;
      std::string msg = r.outcome.message;
      // the child's scene file lives in this process's temporary folder: name it by the row instead
      const std::string tmp = (work / "run" / "scene.toml").string();
      for (std::size_t at; (at = msg.find(tmp)) != std::string::npos;)
        msg.replace(at, tmp.size(), "scene.toml");
      for (auto& ch : msg)
        if (ch == '|') ch = '/';
      s << "| " << r.scene << " | " << (r.integrator.empty() ? "-" : r.integrator) << " | " << r.solver
        << " | " << r.increments << " | " << st::to_string(r.outcome.kind) << " | " << msg << " |\n";
    }
    s << "\nRun on the shared 2-core machine; `OPENBLAS_NUM_THREADS=1` in every child.\n"
      << end_marker << "\n";
    return s.str();
  };
  std::printf("%-40s %-15s %-18s %5s  %-11s %7s  %s\n", "scene", "integrator", "solver", "incr", "outcome",
              "time(s)", "message");
  for (const auto& blk : blocks) {
    if (!filter.empty() && blk.scene.name.find(filter) == std::string::npos) continue;
    if (!counts.contains(blk.scene.name)) order.push_back(blk.scene.name);
    const std::vector<std::string> integ =
        blk.integrators.empty() ? std::vector<std::string>{""} : blk.integrators;
    for (const auto& in : integ)
      for (const auto& sv : blk.solvers)
        for (int n : blk.increments) {
          Run r{blk.scene.name, sv, in, n, {}};
          const fs::path dir = work / "run";
          r.outcome = st::run_case(exe, st::run_text(blk.scene, sv, in, n), dir, timeout);
          ++counts[r.scene][r.outcome.kind];
          seconds[r.scene] += r.outcome.seconds;
          if (st::is_bug(r.outcome.kind)) {
            ++bugs;
            if (!keep.empty()) {
              const fs::path k = keep / ("run" + std::to_string(runs.size()));
              fs::create_directories(k);
              fs::copy(dir, k, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
            }
          }
          std::printf("%-40s %-15s %-18s %5d  %-11s %7.2f  %s\n", r.scene.c_str(),
                      in.empty() ? "-" : in.c_str(), sv.c_str(), n, st::to_string(r.outcome.kind),
                      r.outcome.seconds, r.outcome.message.substr(0, 160).c_str());
          std::fflush(stdout);
          runs.push_back(std::move(r));
        }
    // The table so far, so that an interrupted run still leaves its results.
    if (write && filter.empty())
      stratum::bench::replace_docs_section(
          docs, begin_marker, end_marker,
          render(false, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const std::string section = render(true, total);
  std::cout << "\n" << section;
  if (write && filter.empty()) stratum::bench::replace_docs_section(docs, begin_marker, end_marker, section);
  std::printf("%zu runs, %d bugs (crash, timeout, NaN/Inf, silent, input error), %.0f s\n", runs.size(), bugs,
              total);
  return bugs ? 1 : 0;
}
