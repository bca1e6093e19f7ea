// bench_solvers: iterations, factorizations, linear solves and time per global solver
// on the strip footing of catalogue P4 (flexible footing, B/2 = 1 m, von Mises soil with
// k = 100 kPa, plane strain, 8-node quads), written to docs/benchmarks.md.
//
// Every load-controlled solver runs the same load path to 0.9 (2 + pi) k: 0.5 of it in one
// step, then steps of 0.04 (14 in all); the arc-length solver follows the curve from the same first
// increment until the load passes 0.99 (2 + pi) k or 40 steps. The mesh is finer than the
// test's (foot 6 x 12, side 8 x 12 cells).
//
// Usage: bench_solvers [--no-write] [--docs PATH] [--plugin-dir DIR]
#include "cli.hpp"
#include "docs_section.hpp"
#include "stratum/analysis.hpp"
#include "stratum/error.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr const char* begin_marker = "<!-- bench_solvers:begin -->";
constexpr const char* end_marker = "<!-- bench_solvers:end -->";

/// tools/benchmarks/scenes/footing_solvers.toml with `analysis` and `solver` lines added to its
/// [analysis] and [solver] tables and the pressure p (kPa, written with 6 significant digits).
std::string scene(const std::string& analysis, const std::string& solver, double p) {
  std::ifstream in(fs::path(STRATUM_SOURCE_DIR) / "tools" / "benchmarks" / "scenes" / "footing_solvers.toml");
  std::stringstream file;
  file << in.rdbuf();
  std::string t = file.str();
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = t.find(from);
    if (at == std::string::npos || t.find(from, at + 1) != std::string::npos)
      throw stratum::Error("bench_solvers: '" + from + "' must occur once in footing_solvers.toml");
    t.replace(at, from.size(), to);
  };
  replace("formulation = \"plane_strain\"\n", "formulation = \"plane_strain\"\n" + analysis + "\n");
  replace("[solver]\n", "[solver]\n" + solver + "\n");
  std::ostringstream load;
  load << "p = " << p << "\n";
  replace("p = 462.743\n", load.str());
  return t;
}

struct Row {
  std::string name;
  bool ok = false;
  int steps = 0, cutbacks = 0, iterations = 0, factorizations = 0, solves = 0, evaluations = 0;
  double seconds = 0, settlement = 0, q_end = 0;
  std::string message;
};

Row run(const std::string& name, const std::string& analysis, const std::string& solver, double p,
        const std::string& plugin_dir, bool path) {
  stratum::RunOptions o;
  o.plugin_dirs = {plugin_dir};
  o.write_output = false;
  auto an = stratum::Analysis::from_string(scene(analysis, solver, p), name + ".toml", o);
  const auto& m = an->model();
  int centre = 0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    if (std::hypot(m.mesh.nodes[n].x(), m.mesh.nodes[n].y()) < 1e-9) centre = static_cast<int>(n);
  const auto t0 = std::chrono::steady_clock::now();
  const auto s = an->run();
  Row r;
  r.name = name;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.ok = s.outcome.ok();
  r.message = s.outcome.message;
  r.steps = s.steps_done;
  r.cutbacks = s.cutbacks;
  for (const auto& rec : s.records) {
    r.iterations += rec.iterations;
    r.factorizations += rec.factorizations;
    r.evaluations += static_cast<int>(rec.residual_norms.size());
  }
  for (const auto& rep : s.reports) r.solves += rep.solves;
  r.settlement = -m.u[2 * centre + 1];
  r.q_end = p * m.lambda;
  (void)path;
  return r;
}

} // namespace

int main(int argc, char** argv) {
  bool write = true;
  std::string docs = (fs::path(STRATUM_SOURCE_DIR) / "docs" / "benchmarks.md").string();
  std::string plugin_dir = STRATUM_PLUGIN_DIR;
  const auto cli = stratum::bench::Cli("bench_solvers")
                       .flag("--no-write", "do not update the docs file", write, false)
                       .docs(docs)
                       .plugin_dir(plugin_dir);
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  const double q_lim = (2 + std::numbers::pi) * 100.0;
  const double p = 0.9 * q_lim;
  const std::string load = "increments = [0.5, 0.04]\nmax_cutbacks = 4";
  struct Case {
    std::string name, solver_name, params;
  };
  const std::vector<Case> cases{
      {"newton", "newton", ""},
      {"newton, line search 8", "newton", "line_search = 8"},
      {"modified_newton", "modified_newton", ""},
      {"modified_newton, refresh every 5", "modified_newton", "refresh_every = 5"},
      {"initial_stiffness", "initial_stiffness", ""},
      {"kinsol newton (line search)", "kinsol", "strategy = \"newton\""},
      {"kinsol picard, Anderson 5", "kinsol", "strategy = \"picard\""},
      {"kinsol fixed_point, Anderson 5", "kinsol", "strategy = \"fixed_point\""},
  };
  std::vector<Row> rows;
  for (const auto& c : cases) {
    rows.push_back(
        run(c.name, "solver = \"" + c.solver_name + "\"\n" + load, c.params, p, plugin_dir, false));
    const auto& r = rows.back();
    std::printf("%-34s %s steps %d cut-backs %d iterations %d factorizations %d solves %d evaluations %d "
                "%.2f s settlement %.6g\n",
                r.name.c_str(), r.ok ? "ok" : "FAILED", r.steps, r.cutbacks, r.iterations, r.factorizations,
                r.solves, r.evaluations, r.seconds, r.settlement);
    std::fflush(stdout);
  }
  // Arc length: the same first increment, then constant arc length, to the plateau.
  Row al = run("arc_length (cylindrical)",
               "solver = \"arc_length\"\nincrements = [0.5]\nmax_steps = 40\nmax_cutbacks = 4", "",
               q_lim * 1.2, plugin_dir, true);
  std::printf("%-34s %s steps %d iterations %d solves %d %.2f s q_end %.2f\n", al.name.c_str(),
              al.ok ? "ok" : "FAILED", al.steps, al.iterations, al.solves, al.seconds, al.q_end);

  std::ostringstream s;
  s << begin_marker << "\n## Global solvers on the strip footing (`bench_solvers`)\n\n"
    << "Flexible strip footing on von Mises soil (k = 100 kPa, catalogue P4), plane strain, foot 6 x 12 and "
       "side 8 x 12 quad8 cells, force_rtol = 1e-9. Load control to 0.9 (2 + pi) k = "
    << static_cast<int>(std::lround(p))
    << " kPa: half of it in one step, then steps of 0.04 of it (14 steps without cut-backs; a cut-back "
       "changes the load path, hence the settlement). Iterations are corrections (KINSOL: its "
       "nonlinear iterations), solves are right-hand sides solved with a factorization, evaluations are "
       "residual assemblies. Settlement under the footing centre; `newton` is the reference.\n\n"
    << "| solver | steps | cut-backs | iterations | factorizations | solves | evaluations | time (s) | "
       "settlement (m) | rel. diff. to newton |\n|---|---|---|---|---|---|---|---|---|---|\n";
  char buf[512];
  for (const auto& r : rows) {
    const double d = std::abs(r.settlement - rows[0].settlement) / rows[0].settlement;
    std::snprintf(buf, sizeof buf, "| %s%s | %d | %d | %d | %d | %d | %d | %.2f | %.6f | %.1e |\n",
                  r.name.c_str(), r.ok ? "" : " (failed)", r.steps, r.cutbacks, r.iterations,
                  r.factorizations, r.solves, r.evaluations, r.seconds, r.settlement, d);
    s << buf;
  }
  std::snprintf(
      buf, sizeof buf,
      "\nArc length (cylindrical, constant arc length from the first increment of 0.5 x 1.2 (2 + pi) k, "
      "40 steps): %d steps, %d iterations, %d solves, %.2f s; pressure at the last step %.1f kPa = "
      "%.4f (2 + pi) k.\n",
      al.steps, al.iterations, al.solves, al.seconds, al.q_end, al.q_end / q_lim);
  s << buf;
  s << "\nRun on the shared 2-core machine (other builds running): compare ratios, not absolute times.\n"
    << end_marker << "\n";
  std::cout << s.str();
  if (write) stratum::bench::replace_docs_section(docs, begin_marker, end_marker, s.str());
  return 0;
}
