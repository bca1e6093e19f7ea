// bench_linear: times assembly and solution of a linear axisymmetric quad8 problem
// from about 1e4 to 1e6 free DOF and writes the table to docs/benchmarks.md.
//
// The problem is the Lamé cylinder of inputs/verification/lame_axisymmetric.toml
// (a = 1, b = 2, height 0.5, E = 1000, nu = 0.3, p = 1, u_z = 0 on top and bottom),
// meshed with nx x nx/2 square quad8 cells, 3x3 Gauss. It is built through
// Analysis::from_string with the build tree's plugins, so the real plugin path is
// measured. Every phase is timed separately; the whole run() is timed for comparison.
// The result is checked against the closed form u(a) at every size.
//
// Usage: bench_linear [--max-dof N] [--repeat K] [--no-write] [--docs PATH] [--plugin-dir DIR]
// README.md in this folder describes the columns.
#include "cli.hpp"
#include "cylinder_series.hpp"
#include "docs_section.hpp"
#include "machine.hpp"
#include "stratum/analysis.hpp"
#include "stratum/linear_solver.hpp"
#include "stratum/model.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

using namespace stratum::bench; // median, fixed, size_for, seconds_since, ... (machine.hpp,
                                // cylinder_series.hpp)

constexpr double radius_a = 1.0, radius_b = 2.0, height = 0.5;
constexpr double young = 1000.0, poisson = 0.3, pressure = 1.0;
constexpr double tolerance = 1e-4;     ///< largest accepted relative error of u(a)
constexpr double target_dof = 1e5;     ///< the size of the acceptance target
constexpr double target_seconds = 2.0; ///< assembly + solve at target_dof
constexpr const char* begin_marker = "<!-- bench_linear:begin -->";
constexpr const char* end_marker = "<!-- bench_linear:end -->";

/// u(a) of the closed form (plane-strain ring; u_z = 0 on both faces makes it exact).
double exact_u_a() {
  const double a = radius_a, b = radius_b, nu = poisson;
  return (1 + nu) * pressure * a * a / (young * (b * b - a * a)) * ((1 - 2 * nu) * a + b * b / a);
}

struct Options {
  double max_dof = 1e6;
  int repeat = 3;
  bool write = true;
  std::string docs = std::string(STRATUM_SOURCE_DIR) + "/docs/benchmarks.md";
  std::string plugin_dir = STRATUM_PLUGIN_DIR;
};

std::string scene_text(const Size& s) {
  std::ostringstream t;
  t.precision(17);
  t << "title = \"bench_linear: Lame cylinder " << s.nx << " x " << s.ny << " quad8\"\n"
    << "[analysis]\nformulation = \"axisymmetric\"\nsolver = \"newton\"\nlinear_solver = \"auto\"\nthreads = "
       "1\nsteps = "
       "1\n"
    << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n"
    << "[[mesh.blocks]]\nname = \"ring\"\nx = [" << radius_a << ", " << radius_b << "]\ny = [0.0, " << height
    << "]\nnx = " << s.nx << "\nny = " << s.ny << "\n"
    << "[materials.steel]\nmodel = \"linear_elastic\"\nE = " << young << "\nnu = " << poisson << "\n"
    << "[[domains]]\ncells = \"ring\"\nelement = \"quad\"\nmaterial = \"steel\"\nintegration = 3\n"
    << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
    << "[[constraints]]\nnodes = \"top\"\nuy = 0.0\n"
    << "[[loads]]\ntype = \"pressure\"\nedges = \"ring.left\"\np = " << pressure << "\n"
    << "[output]\nvtk = false\n";
  return t.str();
}

/// Largest relative error of u_r over the nodes of the inner face r = a. `u` holds the
/// free unknowns when `free` is true, else it is the full-size displacement.
double u_a_error(const stratum::Model& m, const Eigen::VectorXd& u, bool free) {
  const auto it = m.mesh.node_sets.find("ring.left");
  if (it == m.mesh.node_sets.end() || it->second.empty())
    throw stratum::Error("bench_linear: no node set ring.left");
  const double exact = exact_u_a();
  double worst = 0.0;
  for (int n : it->second) {
    const int d = 2 * n;
    double ur = 0.0;
    if (free) {
      const int e = m.dofs.eq[static_cast<std::size_t>(d)];
      ur = e >= 0 ? u[e] : 0.0;
    } else {
      ur = u[d];
    }
    worst = std::max(worst, std::isfinite(ur) ? std::abs(ur - exact) / exact : INFINITY);
  }
  return worst;
}

/// The measurements of one repetition of one size.
struct Sample {
  double build = 0;        ///< Analysis::from_string: parse, plugins, mesh, model
  double assembler = 0;    ///< Assembler(model) (pattern + scatter maps) + make_matrix()
  double assembly = 0;     ///< one assemble(): internal force + tangent
  double analyze = 0;      ///< CHOLMOD symbolic analysis
  double factorize = 0;    ///< CHOLMOD numeric factorization
  double solve = 0;        ///< forward/back substitution
  double run = 0;          ///< the whole Analysis::run() (its own Assembler, 2 assemblies, auto solver)
  double solution_cpu = 0; ///< process CPU time of assembler + assembly + analyze + factorize + solve
  double err_direct = 0, err_run = 0;
  int free = 0;
  long long nnz = 0;
  std::string auto_name;
  int run_assemblies = 0;

  [[nodiscard]] double solution() const { return assembler + assembly + analyze + factorize + solve; }
  [[nodiscard]] double to_solution() const { return build + run; }
};

Sample measure(const Size& s, const std::string& plugin_dir) {
  Sample r;
  stratum::RunOptions ro;
  ro.plugin_dirs = {plugin_dir};
  ro.write_output = false;
  const std::string text = scene_text(s);
  auto t = Clock::now();
  auto analysis = stratum::Analysis::from_string(text, "bench_linear.toml", std::move(ro));
  r.build = seconds_since(t);
  stratum::Model& m = analysis->model();
  r.free = m.dofs.free_count;
  {
    const double cpu0 = cpu_seconds();
    t = Clock::now();
    const stratum::Assembler assembler(m);
    stratum::SparseMatrix k = assembler.make_matrix();
    r.assembler = seconds_since(t);
    r.nnz = k.nonZeros();

    const Eigen::VectorXd u = Eigen::VectorXd::Zero(m.dofs.total());
    Eigen::VectorXd f_int;
    t = Clock::now();
    if (auto o = assembler.assemble(m, u, f_int, &k); !o.ok())
      throw stratum::Error("assembly failed: " + o.message);
    r.assembly = seconds_since(t);
    // Loads enter the model when run() starts a stage: form the pressure's nodal forces here.
    Eigen::VectorXd f_ext = Eigen::VectorXd::Zero(m.dofs.total());
    stratum::add_edge_pressure(m, m.mesh.edge_sets.at("ring.left"), pressure, f_ext);
    const Eigen::VectorXd rhs = m.restrict_free(f_ext - f_int);

    auto ls = stratum::make_linear_solver("cholmod", true, r.free);
    Eigen::VectorXd x;
    t = Clock::now();
    if (auto o = ls->analyze(k); !o.ok()) throw stratum::Error(o.message);
    r.analyze = seconds_since(t);
    t = Clock::now();
    if (auto o = ls->factorize(k); !o.ok()) throw stratum::Error(o.message);
    r.factorize = seconds_since(t);
    t = Clock::now();
    if (auto o = ls->solve(rhs, x); !o.ok()) throw stratum::Error(o.message);
    r.solve = seconds_since(t);
    r.solution_cpu = cpu_seconds() - cpu0;
    r.err_direct = u_a_error(m, x, true);
    r.auto_name = stratum::make_linear_solver("auto", m.symmetric(), r.free)->name();
  } // frees the benchmark's own matrix, factor and maps before run() builds its own

  t = Clock::now();
  const stratum::RunSummary summary = analysis->run();
  r.run = seconds_since(t);
  if (!summary.outcome.ok()) throw stratum::Error("run() failed: " + summary.outcome.message);
  for (const auto& rep : summary.reports) r.run_assemblies += static_cast<int>(rep.residual_norms.size());
  r.err_run = u_a_error(m, m.u, false);
  return r;
}

/// Medians over the repetitions (errors: the largest).
struct Row {
  Size size;
  Sample med;
  double wall = 0;     ///< wall time of all repetitions of this size
  double peak_mib = 0; ///< process peak resident memory after this size
};

Row summarize(const Size& s, const std::vector<Sample>& v, double wall, double peak) {
  Row row{s, v.front(), wall, peak};
  auto med = [&](double Sample::*field) {
    std::vector<double> x;
    for (const auto& e : v) x.push_back(e.*field);
    return median(std::move(x));
  };
  for (double Sample::*f : {&Sample::build, &Sample::assembler, &Sample::assembly, &Sample::analyze,
                            &Sample::factorize, &Sample::solve, &Sample::run})
    row.med.*f = med(f);
  for (const auto& e : v) {
    row.med.err_direct = std::max(row.med.err_direct, e.err_direct);
    row.med.err_run = std::max(row.med.err_run, e.err_run);
  }
  return row;
}

/// The medians of the two compound columns: the median of the sums over the repetitions.
double median_of(const std::vector<Sample>& v, double (Sample::*f)() const) {
  std::vector<double> x;
  for (const auto& e : v) x.push_back((e.*f)());
  return median(std::move(x));
}

/// The closed-form u(a) with 7 significant digits.
std::string exact_text() {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6e", exact_u_a());
  return buf;
}

/// 1234567 -> "1 234 567".
/// A row of the table: the medians plus the medians of the compound figures.
struct Measured {
  Row row;
  double solution = 0, to_solution = 0, solution_cpu = 0;
};

// ---- console

void print_header() {
  std::printf("%9s %9s %10s | %7s %7s %7s %7s %7s %7s | %7s %7s | %7s %7s | %8s %8s | %6s %7s\n", "free DOF",
              "mesh", "nnz(K)", "build", "pattern", "assem", "analyze", "factor", "solve", "asm+sol", "cpu",
              "run()", "total", "err u(a)", "err run", "wall", "peakMiB");
  std::fflush(stdout);
}

void print_row(const Measured& e) {
  const auto& r = e.row;
  const auto& m = r.med;
  const std::string mesh = std::to_string(r.size.nx) + "x" + std::to_string(r.size.ny);
  std::printf(
      "%9d %9s %10lld | %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f | %7.3f %7.3f | %7.3f %7.3f | %8.1e %8.1e | "
      "%6.1f %7.0f\n",
      m.free, mesh.c_str(), m.nnz, m.build, m.assembler, m.assembly, m.analyze, m.factorize, m.solve,
      e.solution, e.solution_cpu, m.run, e.to_solution, m.err_direct, m.err_run, r.wall, r.peak_mib);
  std::fflush(stdout);
}

// ---- docs/benchmarks.md

std::string target_sentence(const std::vector<Measured>& rows) {
  const auto it = std::find_if(rows.begin(), rows.end(),
                               [](const Measured& m) { return m.row.size.target == target_dof; });
  if (it == rows.end())
    return "Target (1e5 DOF assembled and solved in under 2 s): not measured in this run.";
  const bool met = it->solution < target_seconds;
  std::ostringstream s;
  s << "Target (1e5 DOF assembled and solved in under 2 s): **" << (met ? "met" : "NOT met")
    << "**: " << fixed(it->solution, 2) << " s for pattern + assembly + analyze + factorize + solve at "
    << grouped(it->row.med.free) << " free DOF (process CPU time " << fixed(it->solution_cpu, 2)
    << " s); the whole time to solution (scene build + `run()`) is " << fixed(it->to_solution, 2) << " s"
    << (it->to_solution < target_seconds ? " (also under 2 s)." : ".");
  return s.str();
}

/// `load` is the 1-minute load average when the program started.
std::string section(const std::vector<Measured>& rows, const Options& o, const std::string& load) {
  const bool own_plugins = o.plugin_dir == STRATUM_PLUGIN_DIR;
  std::ostringstream s;
  s << begin_marker << "\n"
    << "## Linear axisymmetric quad8: assembly and solution\n\n"
    << "Generated by `build/release/bin/bench_linear` (source `tools/benchmarks/bench_linear.cpp`, columns "
       "explained in `tools/benchmarks/README.md`) on "
    << today_utc() << ": " << std::thread::hardware_concurrency() << " cores (" << cpu_model()
    << "), OPENBLAS_NUM_THREADS=" << env_or("OPENBLAS_NUM_THREADS", "unset")
    << ", OMP_NUM_THREADS=" << env_or("OMP_NUM_THREADS", "unset") << ", load average " << load
    << " at the start; median of " << o.repeat
    << " repetitions. Regenerate with `build/release/bin/bench_linear` (`--max-dof N` stops early, "
       "`--no-write` leaves this file alone). Wall times on these shared machines vary from run to run "
       "and grow with the load of other processes: compare ratios within one table.\n\n"
    << "Lamé cylinder a = 1, b = 2, height 0.5, E = 1000, nu = 0.3, p = 1, u_z = 0 on top and bottom; "
       "nx x nx/2 square quad8 cells, 3x3 Gauss; built with `Analysis::from_string` and "
    << (own_plugins ? std::string("the build tree's plugins") : "the plugins of `" + o.plugin_dir + "`")
    << ". Times in seconds. *pattern* = `Assembler(model)` + `make_matrix()`; *asm+solve* = pattern + "
       "assembly + analyze + factorize + solve with `make_linear_solver(\"cholmod\")`, and *(CPU)* the "
       "process CPU time (all threads) of that span, which competing processes hardly inflate; *run()* = "
       "`Analysis::run()` with `linear_solver = \"auto\"` (its own pattern, "
    << (rows.empty() ? 2 : rows.front().row.med.run_assemblies)
    << " assemblies with tangent since Newton assembles again to see convergence, analyze, factorize, "
       "solve); *total* = build + run(), the time to solution from TOML text; *err u(a)* = largest relative "
       "error of u_r on r = a against the closed form "
    << exact_text() << " m (direct solve / run()); *wall* = all repetitions of the size.\n\n"
    << "| free DOF | mesh | nnz(K) | build | pattern | assembly | analyze | factorize | solve | asm+solve "
       "| (CPU) | run() | total | auto | err u(a) | peak RSS | wall |\n"
    << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|\n";
  for (const auto& e : rows) {
    const auto& m = e.row.med;
    s << "| " << grouped(m.free) << " | " << e.row.size.nx << " x " << e.row.size.ny << " | "
      << grouped(m.nnz) << " | " << fixed(m.build, 3) << " | " << fixed(m.assembler, 3) << " | "
      << fixed(m.assembly, 3) << " | " << fixed(m.analyze, 3) << " | " << fixed(m.factorize, 3) << " | "
      << fixed(m.solve, 3) << " | **" << fixed(e.solution, 3) << "** | " << fixed(e.solution_cpu, 3) << " | "
      << fixed(m.run, 3) << " | " << fixed(e.to_solution, 3) << " | " << m.auto_name << " | "
      << sci(m.err_direct) << " / " << sci(m.err_run) << " | " << fixed(e.row.peak_mib, 0) << " MiB | "
      << fixed(e.row.wall, 1) << " |\n";
  }
  s << "\n" << target_sentence(rows) << "\n" << end_marker << "\n";
  return s.str();
}

/// Replaces this program's section of the file (or appends it), keeping the rest; atomic.
void write_docs(const std::string& path, const std::string& block) {
  stratum::bench::replace_docs_section(path, begin_marker, end_marker, block);
}

} // namespace

int main(int argc, char** argv) {
  const std::string load = load_average();
  Options opt;
  const auto cli =
      stratum::bench::Cli("bench_linear")
          .number("--max-dof", "largest size to run (default 1e6; sizes ~1e4, 3e4, 1e5, 3e5, 1e6)",
                  opt.max_dof)
          .count("--repeat", "repetitions per size, medians reported (default 3)", opt.repeat)
          .flag("--no-write", "do not update the docs file", opt.write, false)
          .docs(opt.docs)
          .plugin_dir(opt.plugin_dir);
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  std::printf("bench_linear: Lame cylinder, axisymmetric quad8, 3x3 Gauss; %u cores (%s), "
              "OPENBLAS_NUM_THREADS=%s, load %s; median of %d; times in s\n",
              std::thread::hardware_concurrency(), cpu_model().c_str(),
              env_or("OPENBLAS_NUM_THREADS", "unset").c_str(), load.c_str(), opt.repeat);
  print_header();
  std::vector<Measured> rows;
  bool accurate = true;
  try {
    for (double target : {1e4, 3e4, 1e5, 3e5, 1e6}) {
      if (target > opt.max_dof) break;
      const Size s = size_for(target);
      const auto t0 = Clock::now();
      std::vector<Sample> samples;
      for (int k = 0; k < opt.repeat; ++k) samples.push_back(measure(s, opt.plugin_dir));
      const Row row = summarize(s, samples, seconds_since(t0), peak_rss_mib());
      std::vector<double> cpu;
      for (const auto& e : samples) cpu.push_back(e.solution_cpu);
      const Measured m{row, median_of(samples, &Sample::solution), median_of(samples, &Sample::to_solution),
                       median(std::move(cpu))};
      print_row(m);
      rows.push_back(m);
      if (!(row.med.err_direct < tolerance) || !(row.med.err_run < tolerance)) {
        std::printf("WARNING: u(a) relative error %.3e (direct) / %.3e (run) at %d DOF exceeds %.0e\n",
                    row.med.err_direct, row.med.err_run, row.med.free, tolerance);
        std::fflush(stdout);
        accurate = false;
        break;
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_linear: %s\n", e.what());
    return 2;
  }
  std::printf("%s\n", target_sentence(rows).c_str());
  if (!accurate) return 1;
  if (opt.write) {
    try {
      write_docs(opt.docs, section(rows, opt, load));
      std::printf("wrote %s\n", opt.docs.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_linear: %s\n", e.what());
      return 2;
    }
  }
  return 0;
}
