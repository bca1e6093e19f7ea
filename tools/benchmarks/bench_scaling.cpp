// bench_scaling: cost per Newton iteration versus problem size, split into assembly,
// stress update and linear solve, for an elastic and an elastoplastic axisymmetric quad8
// problem from about 1e3 to 1e6 free DOF; fits the exponent of cost versus DOF and writes
// the table to docs/benchmarks.md (and a CSV for tools/plot_scaling.py).
//
// Both problems are the thick cylinder a = 1, b = 2, height 0.5 with u_z = 0 on top and
// bottom (a plane-strain ring in axisymmetry), meshed with nx x nx/2 square quad8 cells,
// 3x3 Gauss, built through Analysis::from_string with the build tree's plugins:
//   elastic       the Lamé cylinder of inputs/verification/lame_axisymmetric.toml
//                 (E = 1000, nu = 0.3, p = 1), one load step;
//   elastoplastic Hill's cylinder (verification P1, inputs/verification/hill_cylinder.toml):
//                 von Mises E = 2.1e8, nu = 0.3, sigma_y = 2.4e5, perfectly plastic,
//                 closest-point return, selective volumetric integration, p = 0.9 P_lim in
//                 two load steps (0.45 P_lim: elastic, then 0.9 P_lim: plastic zone to
//                 about r = 1.6), so Newton takes several iterations.
// The benchmark drives a full Newton loop itself (the newton plugin's iteration without
// line search): Assembler::assemble, then LinearSolver::factorize + solve of CHOLMOD.
// Every domain's material is wrapped in a timing decorator so that the time of the
// material update calls is separated from the rest of the element loops; the cost of
// the decorator's clock reads is calibrated and subtracted (see README.md).
//
// Usage: bench_scaling [--max-dof N] [--repeat K] [--repeat-large K] [--no-write] [--docs PATH]
//                      [--csv PATH] [--plugin-dir DIR]
// README.md in this folder describes the columns.
#include "cli.hpp"
#include "cylinder_series.hpp"
#include "docs_section.hpp"
#include "machine.hpp"
#include "stratum/analysis.hpp"
#include "stratum/iteration.hpp"
#include "stratum/linear_solver.hpp"
#include "stratum/material.hpp"
#include "stratum/model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace stratum::bench; // median, fixed, size_for, seconds_since, ... (machine.hpp,
                                // cylinder_series.hpp)

constexpr double radius_a = 1.0, radius_b = 2.0, height = 0.5;
// Elastic: the Lamé cylinder.
constexpr double lame_young = 1000.0, lame_poisson = 0.3, lame_pressure = 1.0;
constexpr double lame_tolerance = 1e-4; ///< largest accepted relative error of u(a)
// Elastoplastic: Hill's cylinder (verification P1 scaled to a = 1, b = 2).
constexpr double hill_young = 2.1e8, hill_poisson = 0.3, hill_sigma_y = 2.4e5;
constexpr double hill_fraction = 0.9;     ///< final pressure / P_lim
constexpr double hill_tolerance = 0.02;   ///< catalogue tolerance on u_b(P) (verification.md P1)
constexpr double newton_rtol = 1e-9;      ///< |R| <= rtol * force scale
constexpr double newton_atol = 1e-10;     ///< kN
constexpr int newton_max_iterations = 30; ///< per load step
constexpr double target_exponent = 1.3;   ///< issue 8: cost exponent vs DOF at most 1.3 in 2D
constexpr const char* begin_marker = "<!-- bench_scaling:begin -->";
constexpr const char* end_marker = "<!-- bench_scaling:end -->";

double hill_yield() { return 2.0 * hill_sigma_y / std::sqrt(3.0); }
double hill_limit() { return hill_yield() * std::log(radius_b / radius_a); }
/// Load factors of the elastoplastic load steps (of the pressure hill_fraction * P_lim).
constexpr double hill_steps[] = {0.5, 1.0};

/// u(a) of the Lamé closed form (u_z = 0 on both faces makes it exact).
double lame_u_a() {
  const double a = radius_a, b = radius_b, nu = lame_poisson;
  return (1 + nu) * lame_pressure * a * a / (lame_young * (b * b - a * a)) * ((1 - 2 * nu) * a + b * b / a);
}

/// u(b) of Hill's solution at pressure P in the plastic range: the plastic radius c from
/// P = Y (ln(c/a) + (1 - c^2/b^2)/2) (bisection), then u_b = Y c^2 (1 - nu^2) / (E b).
double hill_u_b(double p) {
  const double y = hill_yield(), a = radius_a, b = radius_b;
  auto pressure_at = [&](double c) { return y * (std::log(c / a) + 0.5 * (1 - c * c / (b * b))); };
  double lo = a, hi = b;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (pressure_at(mid) < p ? lo : hi) = mid;
  }
  const double c = 0.5 * (lo + hi);
  return y * c * c * (1 - hill_poisson * hill_poisson) / (hill_young * b);
}

enum class Problem { elastic, elastoplastic };
const char* problem_name(Problem p) { return p == Problem::elastic ? "elastic" : "elastoplastic"; }
/// The final pressure on r = a (kPa).
double pressure(Problem p) { return p == Problem::elastic ? lame_pressure : hill_fraction * hill_limit(); }

struct Options {
  double max_dof = 1e6;
  int repeat = 3;
  int repeat_large = 1; ///< repetitions of the sizes above 3e5 DOF
  bool write = true;
  std::string docs = std::string(STRATUM_SOURCE_DIR) + "/docs/benchmarks.md";
  std::string csv = std::string(STRATUM_SOURCE_DIR) + "/docs/figures/bench_scaling.csv";
  std::string plugin_dir = STRATUM_PLUGIN_DIR;
};

std::string scene_text(Problem problem, const Size& s) {
  std::ostringstream t;
  t.precision(17);
  t << "title = \"bench_scaling: " << problem_name(problem) << " cylinder " << s.nx << " x " << s.ny
    << " quad8\"\n"
    << "[analysis]\nformulation = \"axisymmetric\"\nsolver = \"newton\"\nlinear_solver = "
       "\"cholmod\"\nthreads = 1\n"
    << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n"
    << "[[mesh.blocks]]\nname = \"ring\"\nx = [" << radius_a << ", " << radius_b << "]\ny = [0.0, " << height
    << "]\nnx = " << s.nx << "\nny = " << s.ny << "\n";
  if (problem == Problem::elastic) {
    t << "[materials.ring]\nmodel = \"linear_elastic\"\nE = " << lame_young << "\nnu = " << lame_poisson
      << "\n"
      << "[[domains]]\ncells = \"ring\"\nelement = \"quad\"\nmaterial = \"ring\"\nintegration = 3\n";
  } else {
    t << "[materials.ring]\nmodel = \"von_mises\"\nE = " << hill_young << "\nnu = " << hill_poisson
      << "\nsigma_y = " << hill_sigma_y << "\nH = 0.0\nintegrator = \"closest_point\"\n"
      << "[[domains]]\ncells = \"ring\"\nelement = \"quad\"\nmaterial = \"ring\"\nintegration = 3\n"
      << "volumetric = \"selective\"\n";
  }
  t << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
    << "[[constraints]]\nnodes = \"top\"\nuy = 0.0\n"
    << "[[loads]]\ntype = \"pressure\"\nedges = \"ring.left\"\np = " << pressure(problem) << "\n"
    << "[output]\nvtk = false\n";
  return t.str();
}

/// Time spent in Material::update, accumulated by TimedMaterial; owned by one measurement.
struct UpdateClock {
  long long calls = 0;
  Clock::duration elapsed{};
};

/// A Material decorator: forwards everything to `inner` and adds the wall time of each
/// update() call to `clock`. Each timed interval also holds about one clock read (the tail
/// of the first and the head of the second); the calibration in clock_read_seconds() says
/// how long one takes.
class TimedMaterial final : public stratum::Material {
public:
  TimedMaterial(const stratum::Material& inner, UpdateClock& clock) : inner_(inner), clock_(clock) {}
  [[nodiscard]] int history_size() const override { return inner_.history_size(); }
  void init_history(const stratum::Vec6& stress, std::span<double> history) const override {
    inner_.init_history(stress, history);
  }
  [[nodiscard]] bool is_linear() const override { return inner_.is_linear(); }
  [[nodiscard]] bool symmetric_tangent() const override { return inner_.symmetric_tangent(); }
  [[nodiscard]] stratum::Outcome update(const stratum::MaterialInput& in,
                                        stratum::MaterialOutput& out) const override {
    const auto t0 = Clock::now();
    stratum::Outcome o = inner_.update(in, out);
    clock_.elapsed += Clock::now() - t0;
    ++clock_.calls;
    return o;
  }

private:
  const stratum::Material& inner_;
  UpdateClock& clock_;
};

/// Wall time of one Clock::now() call: the median over 5 batches of 1e6 reads.
double clock_read_seconds() {
  std::vector<double> v;
  for (int batch = 0; batch < 5; ++batch) {
    constexpr int n = 1000000;
    Clock::rep sink = 0;
    const auto t0 = Clock::now();
    for (int i = 0; i < n; ++i) sink += Clock::now().time_since_epoch().count() & 1;
    const double s = seconds_since(t0);
    v.push_back(s / (n + (sink < 0 ? 1 : 0)));
  }
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// The measurements of one repetition of one problem and size (totals over the whole run).
struct Sample {
  int free = 0;
  long long nnz = 0;
  double build = 0;           ///< Analysis::from_string
  double pattern = 0;         ///< Assembler(model) + make_matrix()
  double analyze = 0;         ///< CHOLMOD ordering + symbolic factorization (once)
  double assemble = 0;        ///< all assemble() calls, wall (stress update and clock reads included)
  double update = 0;          ///< time inside the timed update() calls (with one clock read each)
  long long updates = 0;      ///< update() calls
  double factorize = 0;       ///< all numeric factorizations
  double first_factorize = 0; ///< the first numeric factorization of the run (allocates the factor)
  double solve = 0;           ///< all forward/back substitutions
  double newton = 0;          ///< wall time of the Newton loops (all assemblies, factorizations, solves)
  double newton_cpu = 0;      ///< process CPU time of the same span
  double assemble_cpu = 0;    ///< process CPU time of the assemble() calls
  double solve_cpu = 0;       ///< process CPU time of the factorizations and solves
  int assemblies = 0;         ///< assemble() calls (iterations + one convergence check per step)
  int iterations = 0;         ///< corrections = factorizations
  double overhead = 0;        ///< measured decorator overhead of one assembly (decorated - plain)
  double overhead_est = 0;    ///< the same predicted from the calibration: 2 clock reads per update
  double error = 0;           ///< relative error of the checked displacement against the closed form
  double clock_read = 0;      ///< seconds per clock read (calibration)

  // Per iteration: assembly and stress update per assemble() call, solve per correction.
  [[nodiscard]] double asm_per_call() const {
    return (assemble - update - static_cast<double>(updates) * clock_read) / assemblies;
  }
  [[nodiscard]] double update_per_call() const {
    return (update - static_cast<double>(updates) * clock_read) / assemblies;
  }
  /// Stress update per call (one integration point), calibrated clock read taken out.
  [[nodiscard]] double update_per_point() const {
    return updates > 0 ? update / static_cast<double>(updates) - clock_read : 0.0;
  }
  /// Mean of the numeric factorizations after the first (NaN with a single one).
  [[nodiscard]] double later_factorize() const {
    return iterations > 1 ? (factorize - first_factorize) / (iterations - 1) : NAN;
  }
  [[nodiscard]] double solve_per_it() const { return (factorize + solve) / iterations; }
  [[nodiscard]] double per_iteration() const { return asm_per_call() + update_per_call() + solve_per_it(); }
  /// The whole Newton loop (with the convergence-check assemblies) per correction, the
  /// calibrated clock reads of the decorator taken out.
  [[nodiscard]] double newton_per_it() const {
    return (newton - 2.0 * static_cast<double>(updates) * clock_read) / iterations;
  }
  /// CPU time: one assembly with its stress update (both clock reads of the decorator
  /// taken out), one factorization + solve, and their sum.
  [[nodiscard]] double asm_cpu_per_call() const {
    return (assemble_cpu - 2.0 * static_cast<double>(updates) * clock_read) / assemblies;
  }
  [[nodiscard]] double solve_cpu_per_it() const { return solve_cpu / iterations; }
  [[nodiscard]] double per_iteration_cpu() const { return asm_cpu_per_call() + solve_cpu_per_it(); }
};

/// Relative error of the displacement the closed form predicts: u_r(a) for the elastic
/// problem, u_r(b) for the elastoplastic one (largest over the face's nodes).
double check_error(Problem problem, const stratum::Model& m) {
  const char* set = problem == Problem::elastic ? "ring.left" : "ring.right";
  const auto it = m.mesh.node_sets.find(set);
  if (it == m.mesh.node_sets.end() || it->second.empty())
    throw stratum::Error(std::string("bench_scaling: no node set ") + set);
  const double exact = problem == Problem::elastic ? lame_u_a() : hill_u_b(hill_fraction * hill_limit());
  double worst = 0.0;
  for (int n : it->second) {
    const double ur = m.u[2 * n];
    worst = std::max(worst, std::isfinite(ur) ? std::abs(ur - exact) / exact : INFINITY);
  }
  return worst;
}

Sample measure(Problem problem, const Size& s, const std::string& plugin_dir, double clock_read) {
  Sample r;
  r.clock_read = clock_read;
  stratum::RunOptions ro;
  ro.plugin_dirs = {plugin_dir};
  ro.write_output = false;
  auto t = Clock::now();
  auto analysis = stratum::Analysis::from_string(scene_text(problem, s), "bench_scaling.toml", std::move(ro));
  r.build = seconds_since(t);
  stratum::Model& m = analysis->model();
  r.free = m.dofs.free_count;
  // Analysis::run() applies a stage's loads when the stage starts; this program drives the
  // iterations itself, so it sets the reference load: the pressure on r = a.
  {
    const auto edges = m.mesh.edge_sets.find("ring.left");
    if (edges == m.mesh.edge_sets.end()) throw stratum::Error("bench_scaling: no edge set ring.left");
    m.load_base = Eigen::VectorXd::Zero(m.dofs.total());
    m.load_ref = Eigen::VectorXd::Zero(m.dofs.total());
    stratum::add_edge_pressure(m, edges->second, pressure(problem), m.load_ref);
  }

  // The decorators (and their clock) live in this scope; the original materials are put back
  // before they go.
  UpdateClock clock;
  std::vector<std::unique_ptr<TimedMaterial>> timed;
  std::vector<const stratum::Material*> plain;
  for (auto& dm : m.domains) {
    plain.push_back(dm.law.material);
    if (dm.law.material == nullptr) continue;
    timed.push_back(std::make_unique<TimedMaterial>(*dm.law.material, clock));
    dm.law.material = timed.back().get();
  }
  struct Restore {
    stratum::Model& m;
    const std::vector<const stratum::Material*>& plain;
    ~Restore() {
      for (std::size_t i = 0; i < m.domains.size(); ++i) m.domains[i].law.material = plain[i];
    }
  } restore{m, plain};

  t = Clock::now();
  const stratum::Assembler assembler(m);
  stratum::SparseMatrix k = assembler.make_matrix();
  r.pattern = seconds_since(t);
  r.nnz = k.nonZeros();
  auto ls = stratum::make_linear_solver("cholmod", m.symmetric(), r.free);
  t = Clock::now();
  if (auto o = ls->analyze(k); !o.ok()) throw stratum::Error("analyze: " + o.message);
  r.analyze = seconds_since(t);

  std::vector<double> steps = problem == Problem::elastic
                                  ? std::vector<double>{1.0}
                                  : std::vector<double>(std::begin(hill_steps), std::end(hill_steps));
  Eigen::VectorXd u = m.restrict_free(m.u), full, f_int, res, du;
  const double cpu0 = cpu_seconds();
  const auto newton0 = Clock::now();
  for (const double lambda : steps) {
    for (int it = 0;; ++it) {
      m.expand(u, lambda, full);
      double c0 = cpu_seconds();
      t = Clock::now();
      if (auto o = assembler.assemble(m, full, f_int, &k); !o.ok())
        throw stratum::Error("assembly failed: " + o.message);
      r.assemble += seconds_since(t);
      r.assemble_cpu += cpu_seconds() - c0;
      ++r.assemblies;
      const Eigen::VectorXd load = m.load_base + lambda * m.load_ref;
      res = m.restrict_free(load - f_int);
      const double scale = std::max(load.norm(), f_int.norm());
      if (res.norm() <= stratum::iteration::bound(newton_rtol, scale, newton_atol)) break;
      if (it >= newton_max_iterations)
        throw stratum::Error("Newton did not converge at lambda = " + std::to_string(lambda));
      c0 = cpu_seconds();
      t = Clock::now();
      if (auto o = ls->factorize(k); !o.ok()) throw stratum::Error("factorize: " + o.message);
      const double ft = seconds_since(t);
      if (r.iterations == 0) r.first_factorize = ft;
      r.factorize += ft;
      t = Clock::now();
      if (auto o = ls->solve(res, du); !o.ok()) throw stratum::Error("solve: " + o.message);
      r.solve += seconds_since(t);
      r.solve_cpu += cpu_seconds() - c0;
      ++r.iterations;
      u += du;
    }
    for (auto& dm : m.domains) dm.states.commit();
    m.u = full;
    m.lambda = lambda;
  }
  r.newton = seconds_since(newton0);
  r.newton_cpu = cpu_seconds() - cpu0;
  r.update = std::chrono::duration<double>(clock.elapsed).count();
  r.updates = clock.calls;
  r.error = check_error(problem, m);

  // Decorator overhead, measured: one more assembly at the converged state with the plain
  // materials and one with the decorators (trial states only; nothing is committed).
  {
    const long long calls0 = clock.calls;
    for (std::size_t i = 0; i < m.domains.size(); ++i) m.domains[i].law.material = plain[i];
    t = Clock::now();
    if (auto o = assembler.assemble(m, full, f_int, &k); !o.ok()) throw stratum::Error(o.message);
    const double bare = seconds_since(t);
    std::size_t j = 0;
    for (auto& dm : m.domains)
      if (dm.law.material != nullptr) dm.law.material = timed[j++].get();
    t = Clock::now();
    if (auto o = assembler.assemble(m, full, f_int, &k); !o.ok()) throw stratum::Error(o.message);
    r.overhead = seconds_since(t) - bare;
    r.overhead_est = 2.0 * static_cast<double>(clock.calls - calls0) * clock_read;
  }
  return r;
}

/// The medians over the repetitions of one problem and size.
struct Row {
  Problem problem = Problem::elastic;
  Size size;
  int free = 0;
  long long nnz = 0;
  int iterations = 0, assemblies = 0;
  double build = 0, pattern = 0, analyze = 0;
  double assembly = 0, update = 0, solve = 0, per_it = 0, newton_it = 0;
  double first_factorize = 0, later_factorize = 0;   ///< the first factorization, the mean of the others
  double asm_cpu = 0, solve_cpu = 0, per_it_cpu = 0; ///< process CPU time per assembly / iteration
  std::string load;                                  ///< 1-minute load average after this size
  double update_point = 0;                           ///< stress update per integration point
  double overhead = 0, overhead_est = 0;
  double error = 0; ///< the largest over the repetitions
  double wall = 0;  ///< all repetitions
  double peak_mib = 0;
  int repeats = 0;
};

Row summarize(Problem p, const Size& s, const std::vector<Sample>& v, double wall, double peak) {
  Row row;
  row.problem = p;
  row.size = s;
  row.free = v.front().free;
  row.nnz = v.front().nnz;
  row.iterations = v.front().iterations;
  row.assemblies = v.front().assemblies;
  auto med = [&](auto f) {
    std::vector<double> x;
    for (const auto& e : v) x.push_back(f(e));
    return median(std::move(x));
  };
  row.build = med([](const Sample& e) { return e.build; });
  row.pattern = med([](const Sample& e) { return e.pattern; });
  row.analyze = med([](const Sample& e) { return e.analyze; });
  row.assembly = med([](const Sample& e) { return e.asm_per_call(); });
  row.update = med([](const Sample& e) { return e.update_per_call(); });
  row.solve = med([](const Sample& e) { return e.solve_per_it(); });
  row.first_factorize = med([](const Sample& e) { return e.first_factorize; });
  row.later_factorize = med([](const Sample& e) { return e.later_factorize(); });
  row.update_point = med([](const Sample& e) { return e.update_per_point(); });
  row.per_it = med([](const Sample& e) { return e.per_iteration(); });
  row.newton_it = med([](const Sample& e) { return e.newton_per_it(); });
  row.asm_cpu = med([](const Sample& e) { return e.asm_cpu_per_call(); });
  row.solve_cpu = med([](const Sample& e) { return e.solve_cpu_per_it(); });
  row.per_it_cpu = med([](const Sample& e) { return e.per_iteration_cpu(); });
  row.overhead = med([](const Sample& e) { return e.overhead; });
  row.overhead_est = med([](const Sample& e) { return e.overhead_est; });
  for (const auto& e : v) row.error = std::max(row.error, e.error);
  row.wall = wall;
  row.peak_mib = peak;
  row.load = load_average();
  row.repeats = static_cast<int>(v.size());
  return row;
}

/// Least-squares slope of log(y) against log(x).
double fit_exponent(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 2) return NAN;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(x[i] > 0) || !(y[i] > 0)) return NAN;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  const double d = static_cast<double>(n) * sxx - sx * sx;
  return d > 0 ? (static_cast<double>(n) * sxy - sx * sy) / d : NAN;
}

/// The quantities whose exponent is fitted, as (label, member).
struct Component {
  const char* label;
  double Row::*field;
};
constexpr Component components[] = {{"assembly", &Row::assembly},
                                    {"stress update", &Row::update},
                                    {"solve", &Row::solve},
                                    {"total per iteration", &Row::per_it},
                                    {"Newton loop / iteration", &Row::newton_it},
                                    {"assembly + stress update (CPU)", &Row::asm_cpu},
                                    {"solve (CPU)", &Row::solve_cpu},
                                    {"total per iteration (CPU)", &Row::per_it_cpu},
                                    {"analyze (once)", &Row::analyze}};

struct Fit {
  double all = NAN;   ///< over every size run
  double upper = NAN; ///< over the three largest sizes
};

Fit fit(const std::vector<Row>& rows, Problem p, double Row::*field) {
  std::vector<double> x, y;
  for (const auto& r : rows)
    if (r.problem == p) {
      x.push_back(r.free);
      y.push_back(r.*field);
    }
  Fit f;
  f.all = fit_exponent(x, y);
  if (x.size() >= 3) {
    const std::vector<double> xu(x.end() - 3, x.end()), yu(y.end() - 3, y.end());
    f.upper = fit_exponent(xu, yu);
  }
  return f;
}

/// Seconds with three significant digits, in s or ms.
std::string secs(double v) {
  char buf[64];
  if (!std::isfinite(v)) return "-";
  if (std::abs(v) < 0.1)
    std::snprintf(buf, sizeof buf, "%.3g ms", 1e3 * v);
  else
    std::snprintf(buf, sizeof buf, "%.3g s", v);
  return buf;
}

// ---- console

void print_header() {
  std::printf("%-13s %9s %9s %4s %4s | %9s %9s %9s %9s %9s | %9s %9s %9s | %9s %15s | %8s %6s %7s %5s\n",
              "problem", "free DOF", "mesh", "its", "asm", "assembly", "update", "solve", "per it",
              "Newton/it", "asm CPU", "sol CPU", "it CPU", "analyze", "overhead m/est", "err", "wall",
              "peakMiB", "load");
  std::fflush(stdout);
}

void print_row(const Row& r) {
  const std::string mesh = std::to_string(r.size.nx) + "x" + std::to_string(r.size.ny);
  std::printf(
      "%-13s %9d %9s %4d %4d | %9.4f %9.4f %9.4f %9.4f %9.4f | %9.4f %9.4f %9.4f | %9.4f %7.4f/%7.4f | "
      "%8.1e %6.1f %7.0f %5s\n",
      problem_name(r.problem), r.free, mesh.c_str(), r.iterations, r.assemblies, r.assembly, r.update,
      r.solve, r.per_it, r.newton_it, r.asm_cpu, r.solve_cpu, r.per_it_cpu, r.analyze, r.overhead,
      r.overhead_est, r.error, r.wall, r.peak_mib, r.load.c_str());
  std::fflush(stdout);
}

std::string verdict(const std::vector<Row>& rows) {
  std::ostringstream s;
  bool any = false, met = true;
  for (Problem p : {Problem::elastic, Problem::elastoplastic}) {
    const Fit f = fit(rows, p, &Row::per_it);
    if (!std::isfinite(f.all)) continue;
    any = true;
    met = met && f.all <= target_exponent;
  }
  if (!any) return "Target (cost exponent versus DOF at most 1.3 in 2D up to 1e6 DOF): not measured.";
  double largest = 0;
  for (const auto& r : rows) largest = std::max(largest, static_cast<double>(r.free));
  s << "Target (cost exponent versus DOF at most 1.3 in 2D up to 1e6 DOF): **" << (met ? "met" : "NOT met")
    << "** for the total time per Newton iteration (least-squares fit over all sizes, up to "
    << grouped(static_cast<long long>(largest)) << " free DOF): elastic "
    << fixed(fit(rows, Problem::elastic, &Row::per_it).all, 2) << ", elastoplastic "
    << fixed(fit(rows, Problem::elastoplastic, &Row::per_it).all, 2)
    << " (on process CPU time per iteration, which competing processes inflate less: "
    << fixed(fit(rows, Problem::elastic, &Row::per_it_cpu).all, 2) << " and "
    << fixed(fit(rows, Problem::elastoplastic, &Row::per_it_cpu).all, 2) << ").";
  if (largest < 9e5) s << " The run stopped below 1e6 DOF, so the target's range is not covered.";
  // What limits it: the share of each component at the largest size and its local exponent.
  for (Problem p : {Problem::elastic, Problem::elastoplastic}) {
    const Row* last = nullptr;
    for (const auto& r : rows)
      if (r.problem == p) last = &r;
    if (last == nullptr || !(last->per_it > 0)) continue;
    s << " " << (p == Problem::elastic ? "Elastic" : "Elastoplastic") << " at " << grouped(last->free)
      << " DOF: solve " << fixed(100 * last->solve / last->per_it, 0)
      << " % of an iteration (exponent over the "
      << "3 largest sizes " << fixed(fit(rows, p, &Row::solve).upper, 2) << "), assembly "
      << fixed(100 * last->assembly / last->per_it, 0) << " % ("
      << fixed(fit(rows, p, &Row::assembly).upper, 2) << "), stress update "
      << fixed(100 * last->update / last->per_it, 0) << " % (" << fixed(fit(rows, p, &Row::update).upper, 2)
      << ").";
  }
  s << " Expected: assembly and stress update grow linearly with the number of cells, while a sparse "
       "Cholesky factorization with a nested-dissection ordering of a 2D mesh has O(n log n) fill and "
       "O(n^1.5) flops, so the solve's exponent tends to 1.5 and its share of an iteration grows with n: "
       "at large n the factorization sets the exponent of the total.";
  double solve_upper = 0;
  for (Problem p : {Problem::elastic, Problem::elastoplastic})
    if (const double e = fit(rows, p, &Row::solve).upper; std::isfinite(e))
      solve_upper = std::max(solve_upper, e);
  if (solve_upper > 0 && solve_upper < 1.4)
    s << " Measured up to this size the solve grows more slowly than n^1.5 (local exponent at most "
      << fixed(solve_upper, 2)
      << "): larger supernodes run the dense BLAS kernels at a higher flop rate, so the asymptote is not "
         "reached by 1e6 DOF and the target holds with a margin that shrinks as n grows.";
  return s.str();
}

// ---- docs/benchmarks.md and the CSV

std::string table(const std::vector<Row>& rows, Problem p) {
  std::ostringstream s;
  s << "| free DOF | mesh | nnz(K) | iterations | assemblies | assembly | stress update | solve | **per "
       "iteration** | factorize first / later | Newton loop / it | CPU: assembly + update | CPU: solve | "
       "CPU: per iteration | update / "
       "point | analyze | decorator overhead meas./est. | "
    << (p == Problem::elastic ? "err u(a)" : "err u(b)") << " | peak RSS | load | runs |\n"
    << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
       "---:|\n";
  for (const auto& r : rows) {
    if (r.problem != p) continue;
    s << "| " << grouped(r.free) << " | " << r.size.nx << " x " << r.size.ny << " | " << grouped(r.nnz)
      << " | " << r.iterations << " | " << r.assemblies << " | " << secs(r.assembly) << " | "
      << secs(r.update) << " | " << secs(r.solve) << " | **" << secs(r.per_it) << "** | "
      << secs(r.first_factorize) << " / " << secs(r.later_factorize) << " | " << secs(r.newton_it) << " | "
      << secs(r.asm_cpu) << " | " << secs(r.solve_cpu) << " | " << secs(r.per_it_cpu) << " | "
      << fixed(r.update_point * 1e9, 0) << " ns | " << secs(r.analyze) << " | " << secs(r.overhead) << " / "
      << secs(r.overhead_est) << " | " << sci(r.error) << " | " << fixed(r.peak_mib, 0) << " MiB | " << r.load
      << " | " << r.repeats << " |\n";
  }
  return s.str();
}

std::string exponent_table(const std::vector<Row>& rows) {
  std::ostringstream s;
  s << "| component | elastic: all sizes | elastic: 3 largest | elastoplastic: all sizes | elastoplastic: 3 "
       "largest |\n|---|---:|---:|---:|---:|\n";
  for (const auto& c : components) {
    const Fit e = fit(rows, Problem::elastic, c.field), p = fit(rows, Problem::elastoplastic, c.field);
    const bool total = c.field == &Row::per_it;
    const char* b = total ? "**" : "";
    s << "| " << b << c.label << b << " | " << b << fixed(e.all, 2) << b << " | " << fixed(e.upper, 2)
      << " | " << b << fixed(p.all, 2) << b << " | " << fixed(p.upper, 2) << " |\n";
  }
  return s.str();
}

std::string section(const std::vector<Row>& rows, const Options& o, const std::string& load,
                    double clock_read) {
  const bool own_plugins = o.plugin_dir == STRATUM_PLUGIN_DIR;
  std::ostringstream s;
  s << begin_marker << "\n"
    << "## Scaling: cost per Newton iteration versus DOF\n\n"
    << "Generated by `build/release/bin/bench_scaling` (source `tools/benchmarks/bench_scaling.cpp`, columns "
       "explained in `tools/benchmarks/README.md`) on "
    << today_utc() << ": " << std::thread::hardware_concurrency() << " cores (" << cpu_model()
    << "), OPENBLAS_NUM_THREADS=" << env_or("OPENBLAS_NUM_THREADS", "unset") << ", load average " << load
    << " at the start; median of " << o.repeat << " runs per size (" << o.repeat_large
    << " above 3e5 DOF). Regenerate with `build/release/bin/bench_scaling` (`--max-dof N` stops early, "
       "`--no-write` leaves this file alone), then `/usr/bin/python3 tools/plot_scaling.py` for the "
       "figure. Wall times on these shared machines grow with the load of other processes (the *load* "
       "column: the 1-minute load average after each size); the CPU columns (process CPU time) less so, "
       "though cache and memory-bandwidth contention inflate them too.\n\n"
    << "Thick cylinder a = 1, b = 2, height 0.5, u_z = 0 on top and bottom, axisymmetric, nx x nx/2 square "
       "quad8 cells, 3x3 Gauss, built with `Analysis::from_string` and "
    << (own_plugins ? std::string("the build tree's plugins") : "the plugins of `" + o.plugin_dir + "`")
    << ". *Elastic*: the Lamé cylinder (E = 1000, nu = 0.3, p = 1), one load step. *Elastoplastic*: Hill's "
       "cylinder (catalogue P1 scaled: von Mises E = 2.1e8, nu = 0.3, sigma_y = 2.4e5, H = 0, closest-point "
       "return, `volumetric = \"selective\"`), p = 0.9 P_lim in two load steps (0.45 P_lim, elastic; 0.9 "
       "P_lim, plastic to r = 1.6). The program drives full Newton itself (|R| <= 1e-9 x force scale; "
       "CHOLMOD, analyzed once per run).\n\n"
    << "Per iteration: *assembly* = one `Assembler::assemble` (element loops, scatter into K and f) without "
       "the material updates, *stress update* = the `Material::update` calls of one assembly (timed by a "
       "decorator around the material; each timed call holds about one clock read, and the calibrated "
       "cost of the two reads per call, "
    << fixed(clock_read * 1e9, 1)
    << " ns each, is subtracted: one from the stress update, one from the assembly), *solve* = numeric "
       "factorization + forward/back substitution of one correction, **per iteration** = their sum. "
       "*factorize first / later*: the run's first numeric factorization (it also allocates and first "
       "touches the factor's memory) and the mean of the later ones (elastoplastic only): the elastic "
       "problem's single factorization is a first one, so its solve column is dearer than the "
       "elastoplastic mean at the same size. The "
       "assemblies also include one convergence-check assembly per load step; *Newton loop / it* is the "
       "whole loop (all of them) divided by the corrections. *CPU:* the process CPU time of the "
       "assemble() calls (with their stress updates; the calibrated clock reads taken out) per assembly, of "
       "factorize + solve per correction, and their sum. *decorator overhead* = one decorated minus "
       "one plain assembly at the converged state, measured, against the calibrated estimate (two reads "
       "per call); it is noise-level next to an assembly. Times are medians over the runs.\n\n"
    << "### Elastic (Lamé cylinder)\n\n"
    << table(rows, Problem::elastic) << "\n### Elastoplastic (Hill's cylinder, von Mises)\n\n"
    << table(rows, Problem::elastoplastic)
    << "\n### Fitted exponents of time versus free DOF\n\nLeast-squares slope of log(time) against log(DOF), "
       "over every size run and over the three largest.\n\n"
    << exponent_table(rows)
    << "\nA dash: a value was not positive (the linear-elastic update costs about as much as the clock "
       "reads subtracted from it, so its time is at the decorator's resolution) or too few sizes.\n\n"
    << verdict(rows) << "\n\n"
    << "![time per Newton iteration versus DOF](figures/bench_scaling.png)\n"
    << end_marker << "\n";
  return s.str();
}

void write_csv(const std::string& path, const std::vector<Row>& rows) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  const auto tmp = p.parent_path() / ("." + p.filename().string() + ".tmp");
  {
    std::ofstream out(tmp);
    out.precision(6);
    out << "problem,free_dof,nx,ny,iterations,assemblies,assembly_s,stress_update_s,solve_s,per_iteration_s,"
           "newton_per_iteration_s,assembly_cpu_s,solve_cpu_s,per_iteration_cpu_s,analyze_s,"
           "first_factorize_s,later_factorize_s\n";
    for (const auto& r : rows)
      out << problem_name(r.problem) << "," << r.free << "," << r.size.nx << "," << r.size.ny << ","
          << r.iterations << "," << r.assemblies << "," << r.assembly << "," << r.update << "," << r.solve
          << "," << r.per_it << "," << r.newton_it << "," << r.asm_cpu << "," << r.solve_cpu << ","
          << r.per_it_cpu << "," << r.analyze << "," << r.first_factorize << "," << r.later_factorize << "\n";
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, p);
}

} // namespace

int main(int argc, char** argv) {
  const std::string load = load_average();
  Options opt;
  const auto cli =
      stratum::bench::Cli("bench_scaling")
          .number("--max-dof", "largest size to run (default 1e6; sizes ~1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 1e6)",
                  opt.max_dof)
          .count("--repeat", "runs per size up to 3e5 DOF, medians reported (default 3)", opt.repeat)
          .count("--repeat-large", "runs per size above 3e5 DOF (default 1)", opt.repeat_large)
          .flag("--no-write", "do not update the docs file and the CSV", opt.write, false)
          .docs(opt.docs)
          .text("--csv", "PATH",
                "CSV for tools/plot_scaling.py (default <source>/docs/figures/bench_scaling.csv)", opt.csv)
          .plugin_dir(opt.plugin_dir);
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  const double clock_read = clock_read_seconds();
  std::printf("bench_scaling: thick cylinder, axisymmetric quad8, 3x3 Gauss; %u cores (%s), "
              "OPENBLAS_NUM_THREADS=%s, load %s; median of %d (%d above 3e5 DOF); clock read %.1f ns; "
              "times in s\n",
              std::thread::hardware_concurrency(), cpu_model().c_str(),
              env_or("OPENBLAS_NUM_THREADS", "unset").c_str(), load.c_str(), opt.repeat, opt.repeat_large,
              clock_read * 1e9);
  print_header();
  std::vector<Row> rows;
  bool accurate = true;
  try {
    // Warm-up, not recorded: the first factorization of the process also pays one-off
    // initialisation (BLAS buffers), which would otherwise land on the smallest size.
    for (Problem p : {Problem::elastic, Problem::elastoplastic})
      (void)measure(p, size_for(1e3), opt.plugin_dir, clock_read);
    for (double target : {1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 1e6}) {
      if (target > opt.max_dof * 1.0001) break;
      const Size s = size_for(target);
      for (Problem p : {Problem::elastic, Problem::elastoplastic}) {
        const auto t0 = Clock::now();
        const int repeat = target > 3.1e5 ? opt.repeat_large : opt.repeat;
        std::vector<Sample> samples;
        for (int k = 0; k < repeat; ++k) samples.push_back(measure(p, s, opt.plugin_dir, clock_read));
        const Row row = summarize(p, s, samples, seconds_since(t0), peak_rss_mib());
        print_row(row);
        rows.push_back(row);
        const double tol = p == Problem::elastic ? lame_tolerance : hill_tolerance;
        if (!(row.error < tol)) {
          std::printf("WARNING: %s: relative error %.3e at %d DOF exceeds %.0e\n", problem_name(p), row.error,
                      row.free, tol);
          accurate = false;
        }
      }
      if (!accurate) break;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_scaling: %s\n", e.what());
    return 2;
  }
  std::printf("\nfitted exponents of time vs free DOF (all sizes / 3 largest):\n");
  for (const auto& c : components) {
    const Fit e = fit(rows, Problem::elastic, c.field), p = fit(rows, Problem::elastoplastic, c.field);
    std::printf("  %-24s elastic %5.2f / %5.2f   elastoplastic %5.2f / %5.2f\n", c.label, e.all, e.upper,
                p.all, p.upper);
  }
  std::printf("%s\n", verdict(rows).c_str());
  if (!accurate) return 1;
  if (opt.write) {
    try {
      stratum::bench::replace_docs_section(opt.docs, begin_marker, end_marker,
                                           section(rows, opt, load, clock_read));
      write_csv(opt.csv, rows);
      std::printf("wrote %s and %s\n", opt.docs.c_str(), opt.csv.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_scaling: %s\n", e.what());
      return 2;
    }
  }
  return 0;
}
