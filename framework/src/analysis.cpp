#include "stratum/analysis.hpp"

#include "checkpoint.hpp"
#include "output_folder.hpp"
#include "pile_components.hpp"
#include "recorders.hpp"
#include "scene_fingerprint.hpp"
#include "scene_interfaces.hpp"
#include "stage.hpp"
#include "status_output.hpp"
#include "stratum/interfaces.hpp"
#include "stratum/mesh_io.hpp"
#include "stratum/step_control.hpp"
#include "stratum/vtk_output.hpp"
#include "toml_check.hpp"
#include "worker_pool.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Runs f() and adds its wall time to `seconds`; returns what f returns.
template <class F> decltype(auto) timed(double& seconds, F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  struct Add {
    double& s;
    std::chrono::steady_clock::time_point t0;
    ~Add() { s += seconds_since(t0); }
  } add{seconds, t0};
  return f();
}

using io::check_table;
using io::location;
using io::require_string;
using io::show;

/// Static equilibrium of the model: R(u, lambda) = F_base + lambda F_ref - F_int(u).
class StaticProblem final : public NonlinearProblem {
public:
  StaticProblem(Model& m, const Assembler& a, LinearSolver& ls, RunTimes& times)
      : m_(m), a_(a), ls_(ls), times_(times) {
    ref_ = m.restrict_free(m.load_ref);
  }
  Eigen::Index size() const override { return m_.dofs.free_count; }
  Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r, SparseMatrix* k) override {
    m_.expand(u, lambda, full_);
    Outcome o = timed(times_.assembly, [&] { return a_.assemble(m_, full_, fint_, k); });
    ++times_.assemblies;
    if (!o.ok()) return o;
    r.resize(size());
    for (int d = 0; d < m_.dofs.total(); ++d)
      if (const int e = m_.dofs.eq[d]; e >= 0) r[e] = m_.load_base[d] + lambda * m_.load_ref[d] - fint_[d];
    return {};
  }
  SparseMatrix make_tangent() const override { return a_.make_matrix(); }
  const Eigen::VectorXd& reference_load() const override { return ref_; }
  LinearSolver& linear_solver() override { return ls_; }
  double force_scale(double lambda) const override {
    return std::max((m_.load_base + lambda * m_.load_ref).norm(), fint_.size() ? fint_.norm() : 0.0);
  }
  std::vector<Eigen::Index> node_set_dofs(const std::string& set, int component) const override {
    std::vector<Eigen::Index> v;
    auto it = m_.mesh.node_sets.find(set);
    if (it == m_.mesh.node_sets.end() || component < 0 || component > 1) return v;
    for (int n : it->second)
      if (const int e = m_.dofs.eq[static_cast<std::size_t>(2 * n + component)]; e >= 0) v.push_back(e);
    return v;
  }
  bool renew_decisions() override {
    bool any = false;
    for (auto& d : m_.domains) {
      const int slot = d.law.material ? d.law.material->decision_slot() : -1;
      if (slot < 0) continue;
      any = true;
      for (std::size_t p = 0; p < d.states.points(); ++p)
        d.states.trial(p).history()[static_cast<std::size_t>(slot)] = 0.0;
    }
    return any;
  }
  double step_error() const override {
    double e = 0.0;
    for (const auto& d : m_.domains) {
      if (!d.law.material) continue;
      for (std::size_t c = 0; c < d.cells.size(); ++c) {
        if (!m_.is_active(d.cells[c])) continue;
        for (std::size_t p = d.first_point[c]; p < d.first_point[c + 1]; ++p)
          e = std::max(e, d.law.material->step_error(d.states.trial(p).history()));
      }
    }
    return e;
  }
  const Eigen::VectorXd& internal_force() const { return fint_; }

private:
  Model& m_;
  const Assembler& a_;
  LinearSolver& ls_;
  RunTimes& times_;
  Eigen::VectorXd ref_, full_, fint_;
};

/// Forwards to a linear solver and adds the time of each call to the run's RunTimes. With
/// analyze_each, every factorization is preceded by a symbolic analysis of the matrix (only
/// to measure what reusing the stage's analysis saves; the results are the same).
class TimedLinearSolver final : public LinearSolver {
public:
  TimedLinearSolver(std::unique_ptr<LinearSolver> inner, RunTimes& times, bool analyze_each)
      : inner_(std::move(inner)), times_(times), analyze_each_(analyze_each) {}
  std::string name() const override { return inner_->name(); }
  Outcome analyze(const SparseMatrix& a) override {
    ++times_.analyses;
    return timed(times_.analyze, [&] { return inner_->analyze(a); });
  }
  Outcome factorize(const SparseMatrix& a) override {
    if (analyze_each_)
      if (auto o = analyze(a); !o.ok()) return o;
    ++times_.factorizations;
    return timed(times_.factorize, [&] { return inner_->factorize(a); });
  }
  Outcome solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    ++times_.solves;
    return timed(times_.solve, [&] { return inner_->solve(b, x); });
  }

private:
  std::unique_ptr<LinearSolver> inner_;
  RunTimes& times_;
  bool analyze_each_;
};

/// Tangent (Euler) predictor for a step from lambda_n to lambda: u += K_n^-1 dR/dlambda (lambda -
/// lambda_n), with dR/dlambda (which carries the prescribed-displacement increment through the
/// elements) by a one-sided difference at the converged state. Leaves u unchanged when any part
/// fails; Newton then starts from u_n as without a predictor.
void predict(NonlinearProblem& problem, LinearSolver& ls, double lambda_n, double lambda,
             Eigen::VectorXd& u) {
  SparseMatrix k = problem.make_tangent();
  Eigen::VectorXd r0, r1, du;
  constexpr double eps = 1e-6;
  if (!problem.evaluate(u, lambda_n, r0, &k).ok()) return;
  if (!problem.evaluate(u, lambda_n + eps * (lambda - lambda_n), r1, nullptr).ok()) return;
  if (!ls.factorize(k).ok() || !ls.solve((r1 - r0) / eps, du).ok() || !du.allFinite()) return;
  u += du;
}

Schema analysis_schema() {
  Schema s;
  s.text("formulation", {"axisymmetric", "plane_strain"}, "2D idealisation of the whole scene")
      .defaults_to(std::string("axisymmetric"));
  s.text("solver", {}, "solver plugin that solves each load step; its parameters go in [solver]")
      .defaults_to(std::string("newton"));
  s.text("linear_solver", linear_solver_names(), "sparse direct solver; auto = by size and symmetry")
      .defaults_to(std::string("auto"));
  s.boolean("reuse_linear_stiffness",
            "compute the stiffness of cells with a linear material once per stage (false: at every "
            "assembly; the results are the same, for measuring what the reuse saves)")
      .defaults_to(true);
  s.boolean("reuse_symbolic",
            "analyze the sparsity pattern of the stage's matrix once and reuse it in every "
            "factorization (false: analyze before each one; the results are the same, for measuring "
            "what the reuse saves)")
      .defaults_to(true);
  s.integer("threads", "-",
            "threads that evaluate the elements and materials (0 = all of the machine's; the results "
            "are the same for any count)")
      .at_least(0)
      .at_most(256)
      .defaults_to(0LL);
  s.integer("steps", "-", "number of equal load increments from load factor 0 to 1")
      .at_least(1)
      .defaults_to(1LL);
  s.integer("max_cutbacks", "-", "how many times a failed step may be halved before the run stops")
      .at_least(0)
      .at_most(30)
      .defaults_to(4LL);
  // Step control (stratum/step_control.hpp).
  StepSettings d;
  s.real_list("increments", "-", "explicit load-factor increments (the last one repeats); replaces steps")
      .defaults_to(std::vector<double>{});
  s.boolean("automatic", "grow the increment after fast convergence").defaults_to(false);
  s.integer("fast_iterations", "-", "a step converged in at most this many iterations counts as fast")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.fast_iterations));
  s.real("growth", "-", "increment (arc length) factor after a fast step").at_least(1).defaults_to(d.growth);
  s.real("max_increment", "-", "largest grown load increment; 0: the whole range")
      .at_least(0)
      .defaults_to(0.0);
  s.real("arc_length", "-", "path-following solvers: first step size; 0: from the first increment")
      .at_least(0)
      .defaults_to(0.0);
  s.real("max_arc_length", "-", "path-following solvers: largest grown step size; 0: unbounded")
      .at_least(0)
      .defaults_to(0.0);
  s.real("error_tolerance", "-",
         "load control: largest local error estimate of the materials' updates per step (relative "
         "stress, Material::step_error); a step above it is repeated smaller, and the next step is "
         "sized from it, never beyond the listed increments; 0: off (steps as listed)")
      .at_least(0)
      .defaults_to(0.0);
  s.integer("max_steps", "-", "accepted steps at most (path following stops there, load control fails)")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.max_steps));
  return s;
}

Schema convergence_schema() {
  Schema s;
  Convergence c;
  s.real("force_rtol", "-", "residual force relative to the force scale")
      .greater_than(0)
      .defaults_to(c.force_rtol);
  s.real("force_atol", "kN", "absolute residual force bound").at_least(0).defaults_to(c.force_atol);
  s.real("disp_rtol", "-", "displacement correction relative to the step's displacement")
      .at_least(0)
      .defaults_to(c.disp_rtol);
  s.real("disp_atol", "m", "absolute displacement correction bound").at_least(0).defaults_to(c.disp_atol);
  s.real("energy_rtol", "-", "energy criterion (4.21) of the thesis; 0 disables it")
      .at_least(0)
      .defaults_to(0.0);
  s.real("energy_atol", "kN m", "absolute bound of the energy criterion").at_least(0).defaults_to(0.0);
  s.boolean("displacement_test", "also require the displacement-correction test").defaults_to(false);
  s.integer("max_iterations", "-", "iterations per step before it counts as failed")
      .at_least(1)
      .defaults_to(static_cast<long long>(c.max_iterations));
  return s;
}

Schema mesh_schema() {
  Schema s;
  s.text("generator", {"blocks", "gmsh", "axisymmetric_pile"},
         "structured graded blocks, a Gmsh file, or the bored-pile mesh ([mesh.pile])");
  s.text("file", {}, "Gmsh .msh 4.1 ASCII file, relative to the scene file").defaults_to(std::string());
  s.integer("nodes_per_cell", "-", "4 (bilinear) or 8 (serendipity) for generated blocks")
      .at_least(4)
      .at_most(8)
      .defaults_to(8LL);
  s.text("transform", {"none", "polar"},
         "polar maps generated (x, y) to (x cos y, x sin y) with y in degrees: rings and sectors")
      .defaults_to(std::string("none"));
  return s;
}

Schema block_schema() {
  Schema s;
  s.text("name", {}, "cell set name of the block; its edges become <name>.left/right/bottom/top");
  s.real_list("x", "m", "[x0, x1] extent (axisymmetric: radius)");
  s.real_list("y", "m", "[y0, y1] extent (axisymmetric: height)");
  s.integer("nx", "-", "cells along x").at_least(1).defaults_to(1LL);
  s.integer("ny", "-", "cells along y").at_least(1).defaults_to(1LL);
  s.real("grade_x", "-", "last/first cell size along x").greater_than(0).defaults_to(1.0);
  s.real("grade_y", "-", "last/first cell size along y").greater_than(0).defaults_to(1.0);
  return s;
}

Schema output_schema() {
  Schema s;
  s.boolean("vtk", "write .vtu/.pvd files").defaults_to(true);
  s.boolean("integration_points", "write the integration-point cloud (.vtp)").defaults_to(true);
  s.integer("every", "-", "write every n-th step (the last step is always written)")
      .at_least(1)
      .defaults_to(1LL);
  s.text("pile_head", {}, "edge set of the loaded pile head: curves/load_settlement.csv")
      .defaults_to(std::string());
  s.text("pile_cells", {}, "cell set of the pile: curves/axial_force.csv").defaults_to(std::string());
  s.real("tables_every", "s",
         "diagnostics.csv and the curves are rewritten (atomically) at every stage's end and at most "
         "this often during a stage, so that they grow while a long run goes on; 0: after every step")
      .at_least(0)
      .defaults_to(5.0);
  return s;
}

const toml::table& table_at(const toml::table& root, std::string_view key, const std::string& ctx) {
  const toml::node* n = root.get(key);
  if (!n) throw Error(location(root), ctx + " missing required table [" + std::string(key) + "]");
  if (!n->is_table())
    throw Error(location(*n), ctx + " " + std::string(key) + " must be a table, got " + io::type_name(*n));
  return *n->as_table();
}

const toml::table empty_table;

const toml::table& optional_table(const toml::table& root, std::string_view key) {
  const toml::node* n = root.get(key);
  if (!n) return empty_table;
  if (!n->is_table())
    throw Error(location(*n), std::string(key) + " must be a table, got " + io::type_name(*n));
  return *n->as_table();
}

/// Array of tables [[key]] (absent = empty).
std::vector<const toml::table*> table_list(const toml::table& root, std::string_view key) {
  std::vector<const toml::table*> v;
  const toml::node* n = root.get(key);
  if (!n) return v;
  const auto* a = n->as_array();
  if (!a)
    throw Error(location(*n), std::string(key) + " must be an array of tables [[" + std::string(key) + "]]");
  for (const auto& e : *a) {
    if (!e.is_table())
      throw Error(location(e), std::string(key) + " entries must be tables [[" + std::string(key) + "]]");
    v.push_back(e.as_table());
  }
  return v;
}

} // namespace

struct Analysis::Impl {
  std::string path, title;
  RunOptions options;
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::vector<std::unique_ptr<Material>> materials;
  std::vector<std::unique_ptr<Element>> elements;
  SceneInterfaces interfaces; ///< contact laws, interface elements, named interfaces
  /// The stage's solver: created afresh for every stage from the factory and its checked
  /// parameters, so that nothing a solver keeps (a reference load, a factorization) outlives
  /// the stage it was made for.
  std::unique_ptr<Solver> solver;
  const Factory<Solver>* solver_factory = nullptr;
  Params solver_params;
  Model model;
  std::string linear_solver = "auto";
  bool reuse_linear_stiffness = true;
  bool reuse_symbolic = true;
  int threads = 1; ///< element-loop threads, resolved ([analysis] threads, 0 = the machine's)
  StepSettings stepping;
  Convergence convergence;
  bool vtk = true, ip_output = true;
  int every = 1;
  std::vector<stage::Stage> stages;
  std::vector<stage::LoadSpec> loads; ///< loads applied at the current state, in order
  Eigen::VectorXd initial_prescribed; ///< [[constraints]] values, applied over the first stage
  std::string fingerprint;
  std::vector<FingerprintPart> parts; ///< checked on restart (scene_fingerprint.hpp)
  double time = 0.0;                  ///< output time: stage number - 1 + load factor
  // What the VTK field data of a step says (write_step): the stage running, its step, and the
  // pile head's load and settlement where a head is monitored (NaN otherwise).
  std::string stage_name = "initial";
  int stage_number = 0, stage_step = 0;
  double last_head_load = std::numeric_limits<double>::quiet_NaN(),
         last_head_settlement = std::numeric_limits<double>::quiet_NaN();
  std::string pile_cells; ///< [output] pile_cells: curves/axial_force.csv
  std::string out_dir;    ///< where the run writes (for the interface CSV files)

  void build(const toml::table& root);
  stage::LoadSpec parse_load(const toml::table& t, const std::string& where_ctx,
                             const std::string& default_name);
  stage::Stage parse_stage(const toml::table& t, const std::string& ctx, std::set<std::string>& load_names);
  /// Runs stage k; false when the run ends here (failure in summary.outcome, or an early stop).
  bool run_stage(std::size_t k, RunSummary& summary, VtkSeriesWriter* writer,
                 std::vector<std::array<double, 3>>& axial_rows);
  std::vector<std::array<double, 6>> shaft_rows; ///< load, y, shear, normal, slip (mm), status
  std::vector<Recorder> recorders;               ///< [[output.history]]
  std::vector<Check> checks;                     ///< [[checks]]
  void write_tables(const RunSummary& summary, const std::vector<std::array<double, 3>>& axial_rows,
                    const std::vector<StepRecord>& live);
  std::chrono::steady_clock::time_point last_tables = std::chrono::steady_clock::now();
  double tables_every = 5.0; ///< seconds between rewrites of the tables during a stage
  void write_step(VtkSeriesWriter& w, double time) const;
};

void Analysis::Impl::build(const toml::table& root) {
  // ---- top level
  static const std::vector<std::string_view> top_keys{
      "title", "analysis", "convergence", "solver",  "mesh",         "materials",  "domains", "constraints",
      "loads", "stages",   "output",      "plugins", "contact_laws", "interfaces", "checks"};
  for (auto&& [key, value] : root) {
    const std::string k(key.str());
    if (std::find(top_keys.begin(), top_keys.end(), k) == top_keys.end()) {
      std::string allowed;
      for (auto t : top_keys) allowed += (allowed.empty() ? "" : ", ") + std::string(t);
      throw Error(location(key.source()), "unknown key '" + k + "' at the top level; allowed: " + allowed +
                                              did_you_mean(k, top_keys));
    }
  }
  if (const auto* t = root.get("title")) {
    if (!t->is_string()) throw Error(location(*t), "title must be a string");
    title = t->as_string()->get();
  }

  // ---- plugins: search path
  std::vector<std::string> dirs =
      options.plugin_dirs.empty() ? PluginCatalog::default_directories() : options.plugin_dirs;
  {
    const auto& pt = optional_table(root, "plugins");
    for (auto&& [key, value] : pt) {
      if (key.str() != "path")
        throw Error(location(key.source()),
                    "[plugins] unknown key '" + std::string(key.str()) + "'; allowed: path");
      const auto* a = value.as_array();
      if (!a) throw Error(location(value), "[plugins] path must be an array of directory strings");
      std::vector<std::string> extra;
      for (const auto& e : *a) {
        if (!e.is_string()) throw Error(location(e), "[plugins] path entries must be strings");
        fs::path d = e.as_string()->get();
        if (d.is_relative()) d = fs::path(path).parent_path() / d;
        extra.push_back(d.string());
      }
      dirs.insert(dirs.begin(), extra.begin(), extra.end());
    }
  }
  catalog = std::make_unique<PluginCatalog>(dirs);

  // ---- analysis, convergence, output
  const auto ap = check_table(optional_table(root, "analysis"), analysis_schema(), "[analysis]");
  model.formulation =
      ap.text("formulation") == "axisymmetric" ? Formulation::axisymmetric : Formulation::plane_strain;
  linear_solver = ap.text("linear_solver");
  reuse_linear_stiffness = ap.flag("reuse_linear_stiffness");
  reuse_symbolic = ap.flag("reuse_symbolic");
  threads = resolve_threads(ap.integer("threads"));
  stepping.steps = static_cast<int>(ap.integer("steps"));
  stepping.max_cutbacks = static_cast<int>(ap.integer("max_cutbacks"));
  stepping.increments = ap.real_list("increments");
  for (double v : stepping.increments)
    if (!(v > 0)) throw Error(ap.where("increments"), "[analysis] increments must all be > 0");
  stepping.automatic = ap.flag("automatic");
  stepping.fast_iterations = static_cast<int>(ap.integer("fast_iterations"));
  stepping.growth = ap.real("growth");
  stepping.max_increment = ap.real("max_increment");
  stepping.arc_length = ap.real("arc_length");
  stepping.max_arc_length = ap.real("max_arc_length");
  stepping.max_steps = static_cast<int>(ap.integer("max_steps"));
  stepping.error_tolerance = ap.real("error_tolerance");
  const auto cp = check_table(optional_table(root, "convergence"), convergence_schema(), "[convergence]");
  convergence.force_rtol = cp.real("force_rtol");
  convergence.force_atol = cp.real("force_atol");
  convergence.disp_rtol = cp.real("disp_rtol");
  convergence.disp_atol = cp.real("disp_atol");
  convergence.energy_rtol = cp.real("energy_rtol");
  convergence.energy_atol = cp.real("energy_atol");
  convergence.displacement_test = cp.flag("displacement_test");
  convergence.max_iterations = static_cast<int>(cp.integer("max_iterations"));
  const auto op = check_table(optional_table(root, "output"), output_schema(), "[output]", {"history"});
  vtk = op.flag("vtk");
  ip_output = op.flag("integration_points");
  every = static_cast<int>(op.integer("every"));
  tables_every = op.real("tables_every");
  pile_cells = op.text("pile_cells");
  const SourceLocation pile_cells_at = op.where("pile_cells");

  // ---- solver plugin
  {
    const std::string name = ap.text("solver");
    try {
      catalog->require(registry, PluginKind::solver, name);
    } catch (const Error& e) {
      throw Error(ap.where("solver").known() ? ap.where("solver") : location(root),
                  "[analysis] solver = \"" + name + "\": " + e.message());
    }
    const auto& f = registry.solver(name);
    solver_factory = &f;
    solver_params = check_table(optional_table(root, "solver"), f.schema, "[solver]");
    solver = f.create(solver_params); // checks the parameters now; each stage gets its own (run_stage)
  }

  // ---- mesh
  {
    const auto& mt = table_at(root, "mesh", "scene");
    const auto mp = check_table(mt, mesh_schema(), "[mesh]", {"blocks", "pile"});
    if (mp.text("generator") == "axisymmetric_pile") {
      if (model.formulation != Formulation::axisymmetric)
        throw Error(
            mp.where("generator"),
            "[mesh] generator = \"axisymmetric_pile\" needs [analysis] formulation = \"axisymmetric\"");
      const PileMesh d;
      Schema ps;
      ps.real("radius", "m", "pile radius").greater_than(0).defaults_to(d.radius);
      ps.real("length", "m", "pile length below the ground surface y = 0")
          .greater_than(0)
          .defaults_to(d.length);
      ps.real("near_radius", "m", "outer radius of the near (nonlinear) zone")
          .greater_than(0)
          .defaults_to(d.near_radius);
      ps.real("near_depth", "m", "depth of the near zone").greater_than(0).defaults_to(d.near_depth);
      ps.real("domain_radius", "m", "radius of the model").greater_than(0).defaults_to(d.domain_radius);
      ps.real("domain_depth", "m", "depth of the model").greater_than(0).defaults_to(d.domain_depth);
      ps.integer("n_pile", "-", "cells across the pile radius")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_pile));
      ps.integer("n_shaft", "-", "cells along the pile")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_shaft));
      ps.integer("n_near", "-", "cells across the near zone")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_near));
      ps.integer("n_far", "-", "cells across the far zone")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_far));
      ps.integer("n_below", "-", "cells from the pile base to near_depth")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_below));
      ps.integer("n_deep", "-", "cells from near_depth to domain_depth")
          .at_least(1)
          .defaults_to(static_cast<long long>(d.n_deep));
      ps.real("grade_near", "-", "outer/inner cell width in the near zone")
          .greater_than(0)
          .defaults_to(d.grade_near);
      ps.real("grade_far", "-", "outer/inner cell width in the far zone")
          .greater_than(0)
          .defaults_to(d.grade_far);
      ps.real("grade_below", "-", "lower/upper cell height below the base")
          .greater_than(0)
          .defaults_to(d.grade_below);
      ps.real("grade_deep", "-", "lower/upper cell height in the deep zone")
          .greater_than(0)
          .defaults_to(d.grade_deep);
      const auto pp = check_table(optional_table(mt, "pile"), ps, "[mesh.pile]");
      PileMesh spec;
      spec.radius = pp.real("radius"), spec.length = pp.real("length");
      spec.near_radius = pp.real("near_radius"), spec.near_depth = pp.real("near_depth");
      spec.domain_radius = pp.real("domain_radius"), spec.domain_depth = pp.real("domain_depth");
      spec.nodes_per_cell = static_cast<int>(mp.integer("nodes_per_cell"));
      spec.n_pile = static_cast<int>(pp.integer("n_pile")),
      spec.n_shaft = static_cast<int>(pp.integer("n_shaft"));
      spec.n_near = static_cast<int>(pp.integer("n_near")),
      spec.n_far = static_cast<int>(pp.integer("n_far"));
      spec.n_below = static_cast<int>(pp.integer("n_below")),
      spec.n_deep = static_cast<int>(pp.integer("n_deep"));
      spec.grade_near = pp.real("grade_near"), spec.grade_far = pp.real("grade_far");
      spec.grade_below = pp.real("grade_below"), spec.grade_deep = pp.real("grade_deep");
      try {
        model.mesh = generate_pile(spec);
      } catch (const Error& e) {
        throw Error(location(optional_table(mt, "pile")), e.message());
      }
    } else if (mp.text("generator") == "blocks") {
      const int npc = static_cast<int>(mp.integer("nodes_per_cell"));
      if (npc != 4 && npc != 8)
        throw Error(mp.where("nodes_per_cell"),
                    "[mesh] nodes_per_cell = " + std::to_string(npc) + " is not allowed; allowed: 4 or 8");
      std::vector<Block> blocks;
      const auto list = table_list(mt, "blocks");
      if (list.empty())
        throw Error(location(mt), "[mesh] generator = \"blocks\" needs at least one [[mesh.blocks]]");
      for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string ctx = "[[mesh.blocks]] #" + std::to_string(i + 1);
        const auto bp = check_table(*list[i], block_schema(), ctx);
        Block b;
        b.name = bp.text("name");
        for (const char* xy : {"x", "y"}) {
          const auto& v = bp.real_list(xy);
          if (v.size() != 2 || !(v[1] > v[0]))
            throw Error(bp.where(xy), ctx + " " + xy + " must be [min, max] with max > min");
        }
        b.x0 = bp.real_list("x")[0], b.x1 = bp.real_list("x")[1];
        b.y0 = bp.real_list("y")[0], b.y1 = bp.real_list("y")[1];
        b.nx = static_cast<int>(bp.integer("nx")), b.ny = static_cast<int>(bp.integer("ny"));
        b.grade_x = bp.real("grade_x"), b.grade_y = bp.real("grade_y");
        blocks.push_back(b);
      }
      try {
        model.mesh = generate_blocks(blocks, npc);
      } catch (const Error& e) {
        if (e.where().known()) throw;
        // The generator names the block; locate the first block table that carries that name.
        SourceLocation at = location(mt);
        for (std::size_t i = 0; i < list.size(); ++i)
          if (e.message().find("'" + blocks[i].name + "'") != std::string::npos) {
            at = location(*list[i]);
            if (e.message().find("used more than once") == std::string::npos) break;
          }
        throw Error(at, "[mesh] " + e.message());
      }
      if (mp.text("transform") == "polar")
        for (auto& x : model.mesh.nodes) {
          const double r = x.x(), t = x.y() * std::numbers::pi / 180.0;
          x = Eigen::Vector2d(r * std::cos(t), r * std::sin(t));
        }
    } else {
      if (mt.get("blocks"))
        throw Error(location(*mt.get("blocks")), "[mesh] blocks are only used with generator = \"blocks\"");
      if (mp.text("file").empty())
        throw Error(location(mt), "[mesh] generator = \"gmsh\" needs file = \"...\"");
      fs::path f = mp.text("file");
      if (f.is_relative()) f = fs::path(path).parent_path() / f;
      std::error_code ec;
      if (!fs::is_regular_file(f, ec))
        throw Error(mp.where("file"), "[mesh] file = \"" + mp.text("file") + "\": " +
                                          (fs::exists(f, ec) ? "is not a regular file (a folder?)"
                                                             : "no such file ('" + f.string() + "')") +
                                          "; give a Gmsh .msh 4.1 ASCII file");
      model.mesh = read_gmsh(f.string());
    }
    model.mesh.check();
    if (!pile_cells.empty() && !model.mesh.cell_sets.count(pile_cells))
      throw Error(pile_cells_at,
                  "[output] pile_cells = \"" + pile_cells +
                      "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
    if (model.formulation == Formulation::axisymmetric)
      for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n)
        if (model.mesh.nodes[n].x() < -1e-12)
          throw Error(location(mt), "[mesh] node " + std::to_string(n) + " has a negative radius x = " +
                                        std::to_string(model.mesh.nodes[n].x()) +
                                        " in an axisymmetric scene");
  }

  // ---- materials
  std::map<std::string, const Material*> material_by_name;
  {
    const auto& mats = optional_table(root, "materials");
    for (auto&& [key, value] : mats) {
      const std::string name(key.str());
      const std::string ctx = "[materials." + name + "]";
      const auto* t = value.as_table();
      if (!t) throw Error(location(value), ctx + " must be a table");
      const std::string model_name = require_string(*t, "model", ctx);
      try {
        catalog->require(registry, PluginKind::material, model_name);
      } catch (const Error& e) {
        throw Error(location(*t->get("model")), ctx + " model = \"" + model_name + "\": " + e.message());
      }
      const auto& f = registry.material(model_name);
      materials.push_back(f.create(check_table(*t, f.schema, ctx, {"model"})));
      material_by_name[name] = materials.back().get();
    }
  }

  // ---- domains
  const auto domain_list = table_list(root, "domains");
  if (domain_list.empty()) throw Error(location(root), "scene has no [[domains]]: nothing to analyse");
  std::vector<int> owner(model.mesh.cells.size(), -1);
  for (std::size_t i = 0; i < domain_list.size(); ++i) {
    const auto& t = *domain_list[i];
    const std::string ctx = "[[domains]] #" + std::to_string(i + 1);
    const std::string cells = require_string(t, "cells", ctx);
    const std::string element = require_string(t, "element", ctx);
    const std::string material = require_string(t, "material", ctx);
    auto cs = model.mesh.cell_sets.find(cells);
    if (cs == model.mesh.cell_sets.end())
      throw Error(location(*t.get("cells")),
                  ctx + " cells = \"" + cells +
                      "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets, cells));
    auto mat = material_by_name.find(material);
    if (mat == material_by_name.end())
      throw Error(location(*t.get("material")),
                  ctx + " material = \"" + material +
                      "\" is not defined; defined: " + key_list(material_by_name, material));
    try {
      catalog->require(registry, PluginKind::element, element);
    } catch (const Error& e) {
      throw Error(location(*t.get("element")), ctx + " element = \"" + element + "\": " + e.message());
    }
    const auto& f = registry.element(element);
    // The element's formulation follows [analysis] unless the domain states it (then they must agree).
    const std::string form = model.formulation == Formulation::axisymmetric ? "axisymmetric" : "plane_strain";
    auto ep = check_table(t, f.schema, ctx, {"cells", "element", "material"});
    if (f.schema.find("formulation")) {
      if (const auto* fv = t.get("formulation"); fv && ep.text("formulation") != form)
        throw Error(location(*fv), ctx + " formulation = " + show(*fv) +
                                       " contradicts [analysis] formulation = \"" + form + "\"");
      ep.set("formulation", form, ep.where("formulation"));
    }
    elements.push_back(f.create(ep));
    Domain dm;
    dm.name = cells;
    dm.set_id = static_cast<int>(i);
    dm.element = elements.back().get();
    dm.law.material = mat->second;
    dm.cells = cs->second;
    dm.first_point.assign(dm.cells.size() + 1, 0);
    for (std::size_t c = 0; c < dm.cells.size(); ++c) {
      const int cell = dm.cells[c];
      if (owner[cell] >= 0)
        throw Error(location(*t.get("cells")), ctx + " cell " + std::to_string(cell) +
                                                   " already belongs to [[domains]] #" +
                                                   std::to_string(owner[cell] + 1));
      owner[cell] = static_cast<int>(i);
      const unsigned shape = model.mesh.cells[cell].shape();
      try {
        dm.element->check_shape(shape);
        std::vector<int> cn;
        Eigen::MatrixX2d cx;
        model.cell_nodes(cell, cn, cx);
        dm.element->check_geometry(ElementData{cell, shape, &cx});
      } catch (const Error& e) {
        throw Error(location(*t.get("element")), ctx + " cell " + std::to_string(cell) + ": " + e.message());
      }
      dm.first_point[c + 1] = dm.first_point[c] + static_cast<std::size_t>(dm.element->num_points(shape));
    }
    dm.states = StateStore(dm.first_point.back(), dm.law.material->history_size());
    for (std::size_t p = 0; p < dm.states.points(); ++p) {
      auto slot = dm.states.committed_for_init(p);
      dm.law.material->init_history(Vec6::Zero(), slot.history());
    }
    dm.states.revert();
    model.domains.push_back(std::move(dm));
  }
  read_scene_interfaces(root, *catalog, registry, model, interfaces);

  // ---- constraints
  const auto ndof = static_cast<Eigen::Index>(model.mesh.nodes.size() * DofMap::per_node);
  std::vector<char> fixed(static_cast<std::size_t>(ndof), 0);
  model.prescribed = Eigen::VectorXd::Zero(ndof);
  for (const auto* t : table_list(root, "constraints")) {
    const std::string ctx = "[[constraints]] at line " + std::to_string(location(*t).line);
    const std::string set = require_string(*t, "nodes", ctx);
    auto ns = model.mesh.node_sets.find(set);
    if (ns == model.mesh.node_sets.end())
      throw Error(location(*t->get("nodes")),
                  "[[constraints]] nodes = \"" + set +
                      "\" is not a node set of the mesh; known: " + key_list(model.mesh.node_sets, set));
    Schema s;
    s.real("ux", "m", "prescribed x (radial) displacement at load factor 1").defaults_to(0.0);
    s.real("uy", "m", "prescribed y (vertical) displacement at load factor 1").defaults_to(0.0);
    const auto p = check_table(*t, s, "[[constraints]]", {"nodes"});
    bool any = false;
    for (int c = 0; c < 2; ++c) {
      const char* k = c == 0 ? "ux" : "uy";
      if (!t->get(k)) continue;
      any = true;
      for (int n : ns->second) {
        const auto d = static_cast<std::size_t>(n) * 2 + static_cast<std::size_t>(c);
        if (fixed[d] && model.prescribed[static_cast<Eigen::Index>(d)] != p.real(k))
          throw Error(p.where(k), "[[constraints]] " + std::string(k) + " on node " + std::to_string(n) +
                                      " contradicts an earlier constraint");
        fixed[d] = 1;
        model.prescribed[static_cast<Eigen::Index>(d)] = p.real(k);
      }
    }
    if (!any)
      throw Error(location(*t),
                  "[[constraints]] nodes = \"" + set + "\" constrains nothing; give ux and/or uy");
  }
  // Nodes that no active cell uses carry no stiffness: rebuild_dofs() fixes them too.
  model.constrained = fixed;
  model.active.assign(model.mesh.cells.size(), 1);
  model.rebuild_dofs();
  model.u = Eigen::VectorXd::Zero(ndof);
  model.reactions = Eigen::VectorXd::Zero(ndof);

  // ---- loads of a scene without stages, and the stages
  const auto legacy_loads = table_list(root, "loads");
  const auto stage_list = table_list(root, "stages");
  if (const auto* st = root.get("stages"); st && stage_list.empty())
    throw Error(location(*st), "stages = [] holds no stage; give at least one [[stages]] table, or leave "
                               "the key out and load the scene with [[loads]]");
  // Nothing holds the model: its matrix is singular (found on 997ba04: one "converged" iteration).
  // A head pushed down by a prescribed settlement holds it too.
  if (table_list(root, "constraints").empty()) {
    bool prescribed = false;
    for (const auto* st : stage_list)
      for (const auto* a : table_list(*st, "actions")) prescribed = prescribed || a->get("settlement");
    if (!prescribed)
      throw Error(location(root),
                  "the scene has no [[constraints]]: nothing holds the model against rigid-body "
                  "motion (its matrix is singular); fix some nodes, e.g. [[constraints]] nodes = "
                  "\"bottom\", ux = 0.0, uy = 0.0");
  }
  // A scene without stages whose [[loads]] are absent and whose constraints prescribe nothing.
  if (stage_list.empty() && legacy_loads.empty() && model.prescribed.cwiseAbs().maxCoeff() == 0.0)
    throw Error(location(root), "the scene applies nothing: no [[loads]], no [[stages]] and no non-zero "
                                "[[constraints]] value; a run would solve a zero load");
  if (!stage_list.empty() && !legacy_loads.empty())
    throw Error(location(*legacy_loads.front()),
                "[[loads]] cannot be combined with [[stages]]; give loads as actions of a stage");
  initial_prescribed = model.prescribed;
  model.prescribed_base = Eigen::VectorXd::Zero(ndof);
  model.load_base = Eigen::VectorXd::Zero(ndof);
  model.load_ref = Eigen::VectorXd::Zero(ndof);
  std::set<std::string> load_names;
  if (stage_list.empty()) {
    stage::Stage st;
    st.name = "load";
    st.where = location(root);
    st.steps = stepping.steps;
    st.increments = stepping.increments;
    st.max_cutbacks = stepping.max_cutbacks;
    st.error_tolerance = stepping.error_tolerance;
    st.every = every;
    st.vtk = vtk;
    st.checkpoint = false;
    for (std::size_t i = 0; i < legacy_loads.size(); ++i) {
      stage::Action a;
      a.kind = stage::Action::Kind::add_load;
      a.where = location(*legacy_loads[i]);
      a.load = parse_load(*legacy_loads[i], "[[loads]]", "load#" + std::to_string(i + 1));
      st.actions.push_back(a);
    }
    stages.push_back(std::move(st));
  } else {
    for (std::size_t i = 0; i < stage_list.size(); ++i)
      stages.push_back(parse_stage(*stage_list[i], "[[stages]] #" + std::to_string(i + 1), load_names));
    // What a stage inherits (docs/scene.md "What a stage inherits"): [analysis] max_cutbacks,
    // error_tolerance, the step-control keys, and [output] vtk and every are defaults of every
    // stage; [analysis] steps and increments describe the one load case of a scene without
    // stages and cannot act here (found on 997ba04: steps = 10 silently ran 1 step per stage).
    if (const auto* at = root["analysis"].as_table())
      for (const char* key : {"steps", "increments"})
        if (const auto* v = at->get(key))
          throw Error(location(*v), std::string("[analysis] ") + key +
                                        " cannot act in a scene with [[stages]]: each stage gives its own " +
                                        key + " (steps default to 1); move it into the stages");
    // A stage that may end the run early (until_failure, stop_settlement) must be the last one:
    // otherwise the later stages would silently never run.
    for (std::size_t i = 0; i + 1 < stages.size(); ++i)
      if (stages[i].until_failure || stages[i].stop_settlement > 0)
        throw Error(stages[i].where,
                    "[[stages]] \"" + stages[i].name + "\" has " +
                        (stages[i].until_failure ? "until_failure = true" : "stop_settlement") +
                        ", which ends the run, but stage \"" + stages[i + 1].name +
                        "\" follows it; only the last stage may load to failure or to a "
                        "settlement limit");
    std::set<std::string> seen;
    for (const auto& st : stages)
      if (!seen.insert(st.name).second)
        throw Error(st.where,
                    "[[stages]] name = \"" + st.name + "\" is used twice; stage names must be unique");
  }

  // Recorders and checks (recorders.hpp).
  {
    const auto list = table_list(optional_table(root, "output"), "history");
    for (std::size_t i = 0; i < list.size(); ++i) {
      recorders.emplace_back(*list[i], "[[output.history]] #" + std::to_string(i + 1), model);
      for (std::size_t j = 0; j + 1 < recorders.size(); ++j)
        if (recorders[j].name() == recorders.back().name())
          throw Error(location(*list[i]), "[[output.history]] #" + std::to_string(i + 1) + " name = \"" +
                                              recorders.back().name() +
                                              "\" is used twice; names must be unique");
    }
    const auto cl = table_list(root, "checks");
    for (std::size_t i = 0; i < cl.size(); ++i)
      checks.push_back(parse_check(*cl[i], "[[checks]] #" + std::to_string(i + 1), recorders));
  }

  // What a checkpoint must match: mesh size, domain layout, stage names.
  std::ostringstream fp;
  fp << "nodes " << model.mesh.nodes.size() << " cells " << model.mesh.cells.size();
  for (const auto& dm : model.domains)
    fp << " domain " << dm.name << ':' << dm.states.points() << 'x' << dm.states.stride();
  fp << " stages";
  for (const auto& st : stages) fp << ' ' << st.name;
  fingerprint = fp.str();
  parts = scene_parts(root, model.mesh, STRATUM_VERSION);
}

stage::LoadSpec Analysis::Impl::parse_load(const toml::table& t, const std::string& where_ctx,
                                           const std::string& default_name) {
  const std::string type = require_string(t, "type", where_ctx);
  const std::string ctx = where_ctx + " type = \"" + type + "\"";
  stage::LoadSpec spec;
  auto check_set = [&](const auto& sets, const Params& p, const char* key, const char* what) {
    if (!sets.count(p.text(key)))
      throw Error(p.where(key).known() ? p.where(key) : location(t),
                  ctx + " " + key + " = \"" + p.text(key) + "\" is not " + what +
                      " of the mesh; known: " + key_list(sets, p.text(key)));
  };
  if (type == "pressure") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(default_name);
    s.text("edges", {}, "edge set");
    s.real("p", "kPa", "normal pressure at and above the surface, positive pushing into the body")
        .defaults_to(0.0);
    s.real("gamma", "kN/m3", "pressure gradient with depth below `surface` (fresh concrete: its unit weight)")
        .at_least(0)
        .defaults_to(0.0);
    s.real("surface", "m", "level y where the depth-dependent part starts").defaults_to(0.0);
    s.real("critical_depth", "m", "depth below which the pressure stops growing (bilinear envelope)")
        .greater_than(0)
        .defaults_to(std::numeric_limits<double>::infinity());
    const auto p = check_table(t, s, ctx, {"type"});
    check_set(model.mesh.edge_sets, p, "edges", "an edge set");
    spec.kind = stage::LoadSpec::Kind::pressure;
    spec.name = p.text("name"), spec.set = p.text("edges");
    spec.p = p.real("p"), spec.gamma = p.real("gamma"), spec.surface = p.real("surface");
    spec.critical_depth = p.real("critical_depth");
  } else if (type == "load") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(std::string("head"));
    s.text("edges", {}, "edge set carrying the load").defaults_to(std::string());
    s.text("cells", {}, "or: a cell set whose top faces carry it (a pile head)").defaults_to(std::string());
    s.real("force", "kN", "total downward force at the end of the stage (axisymmetric: whole circle)");
    const auto p = check_table(t, s, ctx, {"type"});
    if (p.text("edges").empty() == p.text("cells").empty())
      throw Error(location(t),
                  ctx + " needs exactly one of edges = \"<edge set>\" or cells = \"<cell set>\"");
    spec.kind = stage::LoadSpec::Kind::pressure;
    spec.name = p.text("name");
    if (!p.text("edges").empty()) {
      check_set(model.mesh.edge_sets, p, "edges", "an edge set");
      spec.set = p.text("edges");
    } else {
      check_set(model.mesh.cell_sets, p, "cells", "a cell set");
      spec.set = p.text("cells");
      spec.top_of_cells = true;
    }
    spec.total_force = p.real("force");
  } else if (type == "force") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(default_name);
    s.text("nodes", {}, "node set");
    s.real("fx", "kN", "force per node along x (axisymmetric: total over the circle)").defaults_to(0.0);
    s.real("fy", "kN", "force per node along y (axisymmetric: total over the circle)").defaults_to(0.0);
    const auto p = check_table(t, s, ctx, {"type"});
    check_set(model.mesh.node_sets, p, "nodes", "a node set");
    spec.kind = stage::LoadSpec::Kind::force;
    spec.name = p.text("name"), spec.set = p.text("nodes");
    spec.fx = p.real("fx"), spec.fy = p.real("fy");
  } else if (type == "gravity") {
    Schema s;
    s.text("name", {}, "name by which a later stage removes the load").defaults_to(default_name);
    s.text("cells", {}, "cell set (only its active cells are loaded)").defaults_to(std::string("all"));
    s.real("gamma", "kN/m3", "unit weight, acting downwards (-y)").at_least(0);
    const auto p = check_table(t, s, ctx, {"type"});
    check_set(model.mesh.cell_sets, p, "cells", "a cell set");
    spec.kind = stage::LoadSpec::Kind::gravity;
    spec.name = p.text("name"), spec.set = p.text("cells");
    spec.gamma = p.real("gamma");
  } else {
    throw Error(location(*t.get("type")), ctx + " is not allowed; allowed: one of: pressure, force, gravity" +
                                              std::string(where_ctx == "[[loads]]" ? "" : ", load"));
  }
  if (where_ctx == "[[loads]]" && type == "load")
    throw Error(location(*t.get("type")), ctx + " is only allowed as a stage action");
  return spec;
}

stage::Stage Analysis::Impl::parse_stage(const toml::table& t, const std::string& ctx,
                                         std::set<std::string>& load_names) {
  using stage::Action;
  Schema s;
  s.text("name", {}, "stage name (checkpoints and output are named after it)");
  s.integer("steps", "-", "equal load increments of the stage").at_least(1).defaults_to(1LL);
  s.real_list("increments", "-", "load-factor increments summing to 1 (instead of steps)")
      .defaults_to(std::vector<double>{});
  s.integer("max_cutbacks", "-", "halvings of a failed step before the stage fails")
      .at_least(0)
      .at_most(30)
      .defaults_to(static_cast<long long>(stepping.max_cutbacks));
  s.real("error_tolerance", "-",
         "error-controlled load steps in this stage ([analysis] error_tolerance: the meaning and "
         "the default); 0: the steps as listed")
      .at_least(0)
      .defaults_to(stepping.error_tolerance);
  s.boolean("until_failure", "a step failing after its cut-backs ends the run normally (loading to failure)")
      .defaults_to(false);
  s.real("collapse_stiffness", "-",
         "with until_failure: the stop counts as a collapse when the least current stiffness of the "
         "steps over the last tenth of the load reached (Bergan's parameter: dlambda / (F_ref . du) "
         "under load control) is below this fraction of the stage's first step; otherwise it is a "
         "numerical failure (exit 4)")
      .greater_than(0)
      .at_most(1)
      .defaults_to(0.1);
  s.real("stop_settlement", "m", "stop once the mean settlement of `monitor` exceeds this (0: never)")
      .at_least(0)
      .defaults_to(0.0);
  s.text("monitor", {}, "edge or node set whose mean downward displacement is the settlement")
      .defaults_to(std::string());
  s.boolean("vtk", "write VTK output during this stage").defaults_to(vtk);
  s.integer("every", "-", "write every n-th step").at_least(1).defaults_to(static_cast<long long>(every));
  s.boolean("checkpoint", "write a checkpoint at the end of the stage").defaults_to(true);
  const auto p = check_table(t, s, ctx, {"actions"});
  stage::Stage st;
  st.name = p.text("name");
  st.where = location(t);
  st.steps = static_cast<int>(p.integer("steps"));
  st.increments = p.real_list("increments");
  if (!st.increments.empty()) {
    double sum = 0.0;
    for (double v : st.increments) {
      if (!(v > 0)) throw Error(p.where("increments"), ctx + " increments must all be > 0");
      sum += v;
    }
    if (std::abs(sum - 1.0) > 1e-9)
      throw Error(p.where("increments"),
                  ctx + " increments sum to " + std::to_string(sum) + "; they must sum to 1");
    if (t.get("steps")) throw Error(p.where("steps"), ctx + " give either steps or increments, not both");
  }
  st.max_cutbacks = static_cast<int>(p.integer("max_cutbacks"));
  st.error_tolerance = p.real("error_tolerance");
  st.until_failure = p.flag("until_failure");
  st.collapse_stiffness = p.real("collapse_stiffness");
  if (t.get("collapse_stiffness") && !st.until_failure)
    throw Error(p.where("collapse_stiffness"),
                ctx + " collapse_stiffness acts only in a stage with until_failure = true");
  st.stop_settlement = p.real("stop_settlement");
  st.monitor = p.text("monitor");
  if (!st.monitor.empty() && !model.mesh.node_sets.count(st.monitor))
    throw Error(p.where("monitor"),
                ctx + " monitor = \"" + st.monitor +
                    "\" is not a node or edge set of the mesh; known: " + key_list(model.mesh.node_sets));
  st.vtk = p.flag("vtk");
  st.every = static_cast<int>(p.integer("every"));
  st.checkpoint = p.flag("checkpoint");

  const auto actions = table_list(t, "actions");
  for (std::size_t i = 0; i < actions.size(); ++i) {
    const auto& at = *actions[i];
    const std::string actx = ctx + " [[stages.actions]] #" + std::to_string(i + 1);
    const std::string type = require_string(at, "type", actx);
    Action a;
    a.where = location(at);
    auto cell_set = [&](const Params& q, const char* key) {
      if (!model.mesh.cell_sets.count(q.text(key)))
        throw Error(q.where(key).known() ? q.where(key) : a.where,
                    actx + " " + key + " = \"" + q.text(key) +
                        "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
      return q.text(key);
    };
    if (type == "geostatic") {
      Schema g;
      g.text("cells", {}, "cells that receive the initial stress and their self-weight")
          .defaults_to(std::string("all"));
      g.real("gamma", "kN/m3", "unit weight").greater_than(0);
      g.real("K0", "-", "earth pressure coefficient at rest, sigma_h = K0 sigma_v").greater_than(0);
      g.real("surface", "m", "ground level y").defaults_to(0.0);
      g.text("name", {}, "name of the self-weight load it adds").defaults_to(std::string("self_weight"));
      const auto q = check_table(at, g, actx + " type = \"geostatic\"", {"type"});
      a.kind = Action::Kind::geostatic;
      a.cells = cell_set(q, "cells");
      a.gamma = q.real("gamma"), a.K0 = q.real("K0"), a.surface = q.real("surface");
      a.load.kind = stage::LoadSpec::Kind::gravity;
      a.load.name = q.text("name"), a.load.set = a.cells, a.load.gamma = a.gamma;
      if (!load_names.insert(a.load.name).second)
        throw Error(a.where, actx + " adds a load named \"" + a.load.name + "\", which is already applied");
      st.reset_after = true;
    } else if (type == "deactivate" || type == "activate") {
      Schema g;
      g.text("cells", {}, "cell set");
      if (type == "activate") {
        g.text(
             "stress", {"zero", "hydrostatic"},
             "initial stress of the placed cells: none, or a fluid's -gamma (surface - y) in all directions")
            .defaults_to(std::string("zero"));
        g.real("gamma", "kN/m3", "unit weight of the fluid for stress = \"hydrostatic\"")
            .at_least(0)
            .defaults_to(0.0);
        g.real("surface", "m", "fluid surface level y").defaults_to(0.0);
      }
      const auto q = check_table(at, g, actx + " type = \"" + type + "\"", {"type"});
      a.kind = type == "activate" ? Action::Kind::activate : Action::Kind::deactivate;
      a.cells = cell_set(q, "cells");
      if (type == "activate") {
        a.hydrostatic = q.text("stress") == "hydrostatic";
        a.gamma = q.real("gamma"), a.surface = q.real("surface");
      }
    } else if (type == "remove") {
      Schema g;
      g.text("name", {}, "name of an applied load");
      const auto q = check_table(at, g, actx + " type = \"remove\"", {"type"});
      if (!load_names.erase(q.text("name"))) {
        std::string known;
        for (const auto& n : load_names) known += (known.empty() ? "" : ", ") + n;
        throw Error(q.where("name"),
                    actx + " name = \"" + q.text("name") +
                        "\" is not an applied load; applied: " + (known.empty() ? "(none)" : known));
      }
      a.kind = Action::Kind::remove_load;
      a.name = q.text("name");
    } else if (type == "displacement") {
      Schema g;
      g.text("nodes", {}, "node set");
      g.real("ux", "m", "x displacement increment over the stage").defaults_to(0.0);
      g.real("uy", "m", "y displacement increment over the stage").defaults_to(0.0);
      const auto q = check_table(at, g, actx + " type = \"displacement\"", {"type"});
      if (!model.mesh.node_sets.count(q.text("nodes")))
        throw Error(q.where("nodes"),
                    actx + " nodes = \"" + q.text("nodes") +
                        "\" is not a node set of the mesh; known: " + key_list(model.mesh.node_sets));
      if (!at.get("ux") && !at.get("uy"))
        throw Error(a.where, actx + " prescribes nothing; give ux and/or uy");
      a.kind = Action::Kind::displacement;
      a.nodes = q.text("nodes");
      if (at.get("ux")) a.ux = q.real("ux");
      if (at.get("uy")) a.uy = q.real("uy");
    } else if (type == "load" && at.get("settlement")) {
      // Head displacement: the top faces of a cell set (a pile head) pushed down by `settlement`
      // over the stage; the head load is then the reaction on those nodes.
      Schema g;
      g.text("cells", {}, "cell set whose top faces are pushed down (a pile head)");
      g.real("settlement", "m", "downward head displacement at the end of the stage").greater_than(0);
      const auto q = check_table(at, g, actx + " type = \"load\" (head displacement)", {"type"});
      a.kind = Action::Kind::displacement;
      a.cells = cell_set(q, "cells");
      a.uy = -q.real("settlement");
    } else if (type == "reset_displacements") {
      (void)check_table(at, Schema{}, actx + " type = \"reset_displacements\"", {"type"});
      a.kind = Action::Kind::reset_displacements;
    } else if (type == "pressure" || type == "force" || type == "gravity" || type == "load") {
      a.kind = Action::Kind::add_load;
      a.load = parse_load(at, actx, type + "@" + st.name);
      if (!load_names.insert(a.load.name).second)
        throw Error(a.where, actx + " adds a load named \"" + a.load.name +
                                 "\", which is already applied; remove it first or choose another name");
    } else {
      throw Error(
          location(*at.get("type")),
          actx + " type = \"" + type +
              "\" is not allowed; allowed: one of: geostatic, deactivate, activate, pressure, load, force, "
              "gravity, remove, displacement, reset_displacements");
    }
    st.actions.push_back(std::move(a));
  }
  return st;
}

void Analysis::Impl::write_step(VtkSeriesWriter& w, double time) const {
  const Model& m = model;
  OutputStep out;
  out.time = time;
  out.mesh = &m.mesh;
  out.texts = {{"stage", stage_name}};
  out.values = {{"stage_number", stage_number},
                {"step", stage_step},
                {"load_factor", m.lambda},
                {"head_load_kN", last_head_load},
                {"head_settlement_mm", last_head_settlement}};
  Field disp{"displacement", 3, std::vector<double>(m.mesh.nodes.size() * 3, 0.0)};
  Field reac{"reaction", 3, std::vector<double>(m.mesh.nodes.size() * 3, 0.0)};
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    for (int c = 0; c < 2; ++c) {
      const auto d = static_cast<Eigen::Index>(2 * n + static_cast<std::size_t>(c));
      disp.values[3 * n + static_cast<std::size_t>(c)] = m.u[d];
      if (m.dofs.eq[static_cast<std::size_t>(d)] < 0)
        reac.values[3 * n + static_cast<std::size_t>(c)] =
            m.reactions[d] - m.load_base[d] - m.lambda * m.load_ref[d];
    }
  out.point_fields = {std::move(disp), std::move(reac)};
  const std::vector<std::string> voigt{"xx", "yy", "zz", "xy", "yz", "zx"};
  Field stress{"stress", 6, {}, voigt}, set_id{"set_id", 1, {}};
  Field ip_stress{"stress", 6, {}, voigt}, ip_strain{"strain", 6, {}, voigt}, ip_plastic{"plastic", 1, {}};
  // Named history components (Material::history_names()): one scalar field per name over all
  // integration points; NaN where a domain's material has no component of that name.
  std::vector<Field> ip_history;
  std::vector<std::vector<int>> history_index(m.domains.size()); // field -> history slot, per domain
  if (ip_output)
    for (std::size_t d = 0; d < m.domains.size(); ++d) {
      if (!m.domains[d].law.material) continue;
      const auto names = m.domains[d].law.material->history_names();
      const auto n =
          std::min<std::size_t>(names.size(), static_cast<std::size_t>(m.domains[d].states.history_size()));
      for (std::size_t k = 0; k < n; ++k) {
        std::size_t f = 0;
        while (f < ip_history.size() && ip_history[f].name != names[k]) ++f;
        if (f == ip_history.size()) ip_history.push_back(Field{names[k], 1, {}});
        for (auto& idx : history_index) idx.resize(ip_history.size(), -1);
        history_index[d][f] = static_cast<int>(k);
      }
    }
  std::size_t total_points = 0;
  for (const auto& dm : m.domains)
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci)
      if (m.is_active(dm.cells[ci])) total_points += dm.first_point[ci + 1] - dm.first_point[ci];
  out.ip_coords.resize(static_cast<Eigen::Index>(ip_output ? total_points : 0), 2);
  Eigen::Index row = 0;
  std::vector<int> nodes;
  Eigen::MatrixX2d x, xp;
  Eigen::VectorXd wts;
  for (std::size_t d = 0; d < m.domains.size(); ++d)
    for (std::size_t ci = 0; ci < m.domains[d].cells.size(); ++ci) {
      const auto& dm = m.domains[d];
      const int c = dm.cells[ci];
      if (!m.is_active(c)) continue; // removed (bored) or not yet placed
      out.cells.push_back(c);
      m.cell_nodes(c, nodes, x);
      ElementData data{c, m.mesh.cells[c].shape(), &x};
      dm.element->point_weights(data, wts);
      Vec6 avg = Vec6::Zero();
      for (std::size_t p = dm.first_point[ci]; p < dm.first_point[ci + 1]; ++p) {
        const auto slot = dm.states.committed(p);
        avg += wts[static_cast<Eigen::Index>(p - dm.first_point[ci])] * slot.stress();
        if (ip_output) {
          for (int k = 0; k < 6; ++k) {
            ip_stress.values.push_back(slot.stress()[k]);
            ip_strain.values.push_back(slot.strain()[k]);
          }
          ip_plastic.values.push_back(
              dm.law.material ? dm.law.material->point_status(slot.stress(), slot.history()) : -1.0);
          for (std::size_t f = 0; f < ip_history.size(); ++f) {
            const int k = history_index[d].empty() ? -1 : history_index[d][f];
            ip_history[f].values.push_back(k >= 0 ? slot.history()[static_cast<std::size_t>(k)]
                                                  : std::numeric_limits<double>::quiet_NaN());
          }
        }
      }
      for (int k = 0; k < 6; ++k) stress.values.push_back(avg[k]);
      set_id.values.push_back(dm.set_id);
      if (ip_output) {
        dm.element->point_coordinates(data, xp);
        out.ip_coords.middleRows(row, xp.rows()) = xp;
        row += xp.rows();
      }
    }
  out.cell_fields = {std::move(stress), std::move(set_id)};
  if (ip_output) out.ip_fields = {std::move(ip_stress), std::move(ip_strain), std::move(ip_plastic)};
  for (auto& f : ip_history) out.ip_fields.push_back(std::move(f));
  add_status_names(m, out, ip_output); // "domain", "domains", "plastic_regimes_<domain>"
  if (ip_output && !interfaces.interfaces.empty()) append_interface_fields(m, out.ip_fields);
  w.write(out);
  for (const auto& itf : interfaces.interfaces)
    if (itf.csv)
      write_interface_csv(interface_points(m, m.domains[itf.domain]),
                          (fs::path(out_dir) / (fs::path(path).stem().string() + "_" + itf.name + "_" +
                                                std::to_string(w.steps_written() - 1) + ".csv"))
                              .string());
}

Analysis::Analysis(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Analysis::~Analysis() = default;

std::unique_ptr<Analysis> Analysis::from_string(const std::string& text, const std::string& path,
                                                RunOptions options) {
  toml::table root = io::parse_with_includes(text, path);
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->options = std::move(options);
  impl->build(root);
  return std::unique_ptr<Analysis>(new Analysis(std::move(impl)));
}

std::unique_ptr<Analysis> Analysis::from_file(const std::string& path, RunOptions options) {
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path))
    throw Error(SourceLocation{path, 0, 0}, "cannot open scene file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return from_string(ss.str(), path, std::move(options));
}

const Model& Analysis::model() const { return impl_->model; }
Model& Analysis::model() { return impl_->model; }
std::vector<std::string> Analysis::opened_libraries() const { return impl_->catalog->opened(); }
std::string Analysis::title() const { return impl_->title; }

namespace {

/// Mean downward displacement of a node set (m).
double mean_settlement(const Model& m, const std::vector<int>& nodes) {
  if (nodes.empty()) return 0.0;
  double s = 0.0;
  for (int n : nodes) s -= m.u[2 * n + 1];
  return s / static_cast<double>(nodes.size());
}

/// Axial force N(y) (kN, compression positive) of the active cells of a set, from the stress
/// sigma_yy at the integration points: for each cell, the points of one row (equal y) give the
/// weighted mean of sigma_yy times the cell's cross-section area (axisymmetric: the ring). Exact
/// for rectangular cells; rows at the same level from different cells are added.
std::vector<std::array<double, 2>> axial_profile(const Model& m, const std::vector<int>& cells) {
  std::map<long long, std::array<double, 2>> rows; // key: y in micrometres
  std::vector<int> set(cells);
  std::sort(set.begin(), set.end());
  std::vector<int> nodes;
  Eigen::MatrixX2d x, xp;
  Eigen::VectorXd w;
  for (const auto& dm : m.domains) {
    if (!dm.law.material) continue;
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const int c = dm.cells[ci];
      if (!m.is_active(c) || !std::binary_search(set.begin(), set.end(), c)) continue;
      m.cell_nodes(c, nodes, x);
      const ElementData data{c, m.mesh.cells[c].shape(), &x};
      dm.element->point_coordinates(data, xp);
      dm.element->point_weights(data, w);
      const double r0 = x.col(0).minCoeff(), r1 = x.col(0).maxCoeff();
      const double area =
          m.formulation == Formulation::axisymmetric ? std::numbers::pi * (r1 * r1 - r0 * r0) : r1 - r0;
      std::map<long long, std::array<double, 2>> local; // sum w sigma, sum w
      for (Eigen::Index p = 0; p < xp.rows(); ++p) {
        const auto key = std::llround(xp(p, 1) * 1e6);
        const double sy =
            dm.states.committed(dm.first_point[ci] + static_cast<std::size_t>(p)).stress()[voigt::yy];
        local[key][0] += w[p] * sy;
        local[key][1] += w[p];
      }
      for (const auto& [key, v] : local) {
        rows[key][0] = static_cast<double>(key) * 1e-6;
        rows[key][1] += -area * v[0] / v[1];
      }
    }
  }
  std::vector<std::array<double, 2>> out;
  for (auto it = rows.rbegin(); it != rows.rend(); ++it) out.push_back(it->second);
  return out;
}

void write_text_atomically(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    if (!out) throw Error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

} // namespace

bool Analysis::Impl::run_stage(std::size_t k, RunSummary& summary, VtkSeriesWriter* writer,
                               std::vector<std::array<double, 3>>& axial_rows) {
  using stage::Action;
  stage::Stage& st = stages[k];
  stage_name = st.name;
  stage_number = static_cast<int>(k) + 1;
  stage_step = 0;
  Model& m = model;
  m.prescribed = k == 0 ? initial_prescribed : Eigen::VectorXd::Zero(m.u.size());
  m.prescribed_base = m.u;

  // ---- actions, in order
  const stage::LoadSpec* head = nullptr;
  std::vector<int> head_disp; // nodes of a displacement-controlled pile head
  for (const Action& a : st.actions) {
    switch (a.kind) {
    case Action::Kind::geostatic:
      stage::set_geostatic(m, m.mesh.cell_sets.at(a.cells), a.gamma, a.K0, a.surface);
      loads.push_back(a.load);
      break;
    case Action::Kind::deactivate:
      for (int c : m.mesh.cell_sets.at(a.cells)) m.active[static_cast<std::size_t>(c)] = 0;
      break;
    case Action::Kind::activate: {
      const auto& cells = m.mesh.cell_sets.at(a.cells);
      for (int c : cells) m.active[static_cast<std::size_t>(c)] = 1;
      stage::set_placed_stress(m, cells, a.hydrostatic, a.gamma, a.surface);
      break;
    }
    case Action::Kind::add_load:
      loads.push_back(a.load);
      if (std::isfinite(a.load.total_force)) head = &a.load;
      break;
    case Action::Kind::remove_load:
      std::erase_if(loads, [&](const stage::LoadSpec& l) { return l.name == a.name; });
      break;
    case Action::Kind::displacement:
      if (!a.cells.empty()) { // head displacement of a pile: its current top nodes
        stage::LoadSpec top;
        top.set = a.cells, top.top_of_cells = true;
        head_disp = stage::load_nodes(m, top);
        for (int n : head_disp) m.constrained[2 * n + 1] = 1, m.prescribed[2 * n + 1] = a.uy;
        break;
      }
      for (int n : m.mesh.node_sets.at(a.nodes)) {
        if (std::isfinite(a.ux)) m.constrained[2 * n] = 1, m.prescribed[2 * n] = a.ux;
        if (std::isfinite(a.uy)) m.constrained[2 * n + 1] = 1, m.prescribed[2 * n + 1] = a.uy;
      }
      break;
    case Action::Kind::reset_displacements:
      m.u.setZero();
      m.prescribed_base.setZero();
      break;
    }
  }

  // ---- the stage's problem: equilibrium at its start, the target load at its end
  m.rebuild_dofs();
  const Assembler assembler(m, reuse_linear_stiffness, threads);
  auto ls = std::make_unique<TimedLinearSolver>(
      make_linear_solver(linear_solver, m.symmetric(), m.dofs.free_count), summary.times, !reuse_symbolic);
  {
    SparseMatrix kpat = assembler.make_matrix();
    if (auto o = ls->analyze(kpat); !o.ok()) {
      summary.outcome = Outcome::failure(o.status, "stage \"" + st.name + "\": " + o.message);
      return false;
    }
  }
  Eigen::VectorXd f0;
  if (auto o = assembler.assemble(m, m.u, f0, nullptr); !o.ok()) {
    for (auto& dm : m.domains) dm.states.revert();
    summary.outcome = Outcome::failure(o.status, "stage \"" + st.name + "\", initial state: " + o.message);
    return false;
  }
  for (auto& dm : m.domains) dm.states.revert();
  Eigen::VectorXd target = Eigen::VectorXd::Zero(m.u.size());
  for (const auto& l : loads) stage::add_load(m, l, target);
  // Free DOFs: the stage starts in equilibrium with the forces the active cells carry and moves
  // linearly to the target load (this releases the forces of removed cells over the steps).
  // Fixed DOFs carry the target load, so that reactions are final forces.
  m.load_base = f0;
  m.load_ref = target - f0;
  for (int d = 0; d < m.dofs.total(); ++d)
    if (m.dofs.eq[static_cast<std::size_t>(d)] < 0) m.load_base[d] = target[d], m.load_ref[d] = 0.0;
  m.lambda = 0.0;
  StaticProblem problem(m, assembler, *ls, summary.times);

  const std::vector<int>* monitor = nullptr;
  if (!st.monitor.empty()) monitor = &m.mesh.node_sets.at(st.monitor);
  std::vector<int> head_nodes;
  if (head) head_nodes = stage::load_nodes(m, *head);
  const bool displaced_head = !head && !head_disp.empty();
  if (displaced_head) head_nodes = head_disp;
  const bool has_head = head || displaced_head;
  if (!monitor && has_head) monitor = &head_nodes;
  const double force = head ? head->total_force : 0.0;
  // The head load (kN, downward positive): the applied force, or the reaction on a displaced head.
  // m.reactions holds the internal forces; a fixed DOF's external load is in load_base.
  bool stepped = false;
  auto head_load = [&] {
    if (!displaced_head) return m.lambda * force;
    double P = 0.0;
    if (stepped)
      for (int n : head_nodes) P -= m.reactions[2 * n + 1] - m.load_base[2 * n + 1];
    return P;
  };
  const std::vector<int>* pile = pile_cells.empty() ? nullptr : &m.mesh.cell_sets.at(pile_cells);
  std::optional<PileComponents> components; // curves/settlement_components.csv (pile_components.hpp)
  auto record = [&] {
    if (!has_head) return;
    const double load = head_load();
    summary.load_settlement.push_back({load, 1e3 * mean_settlement(m, head_nodes)});
    last_head_load = load;
    last_head_settlement = summary.load_settlement.back()[1];
    if (pile) {
      if (!components) {
        std::vector<std::size_t> itf;
        for (const auto& i : interfaces.interfaces) itf.push_back(i.domain);
        components.emplace(m, *pile, std::move(itf));
      }
      summary.settlement_components.push_back(components->row(m, load));
    }
    if (pile)
      for (const auto& [y, n] : axial_profile(m, *pile)) axial_rows.push_back({load, y, n});
    // Shaft tractions: the interface points on the vertical wall (the largest radius).
    for (const auto& itf : interfaces.interfaces) {
      const auto pts = interface_points(m, m.domains[itf.domain]);
      double rmax = 0.0;
      for (const auto& q : pts) rmax = std::max(rmax, q.x.x());
      for (const auto& q : pts)
        if (q.x.x() > rmax - 1e-9)
          shaft_rows.push_back({load, q.x.y(), q.traction[0], q.traction[1], 1e3 * q.jump[0],
                                static_cast<double>(static_cast<int>(q.state))});
    }
  };
  if (has_head && summary.load_settlement.empty()) record();

  // ---- load steps (stratum/step_control.hpp)
  const int nominal_steps = st.increments.empty() ? st.steps : static_cast<int>(st.increments.size());
  Eigen::VectorXd u = m.restrict_free(m.u);
  StepSettings settings = stepping;
  settings.steps = st.steps;
  settings.increments = st.increments;
  settings.max_cutbacks = st.max_cutbacks;
  settings.error_tolerance = st.error_tolerance;
  settings.lambda_start = 0.0;
  settings.lambda_end = 1.0;
  settings.convergence = convergence;
  StepCallbacks cb;
  cb.commit = [&] {
    for (auto& dm : m.domains) dm.states.commit();
  };
  cb.revert = [&] {
    for (auto& dm : m.domains) dm.states.revert();
  };
  // Prescribed displacements jump at the start of a step; without a predictor the first
  // iterate puts the whole jump into the cells next to the prescribed nodes.
  if (m.prescribed.size() > 0 && m.prescribed.cwiseAbs().maxCoeff() > 0.0)
    cb.predict = [&](NonlinearProblem& p, double l0, double l1, Eigen::VectorXd& x) {
      predict(p, *ls, l0, l1, x);
    };
  int step = 0;
  bool written = false;
  std::vector<StepRecord> live; // this stage's accepted steps, for the tables written during it
  // The current stiffness of each accepted step against the stage's first (Bergan's current
  // stiffness parameter): under load control dlambda / (F_ref . du), the load over the work-
  // conjugate displacement of the load pattern; under displacement control (no load pattern on
  // the free unknowns) du . df / dlambda^2 with df the change of the nodal forces (the reactions
  // of the prescribed nodes). A stop counts as a collapse where it has fallen below
  // collapse_stiffness (negative: the path has turned).
  Eigen::VectorXd u_prev = m.u, f_prev = f0;
  double lambda_prev = 0.0, stiffness_first = 0.0;
  std::vector<std::array<double, 2>> stiffness_path; // (lambda, S) of each accepted step
  const bool load_controlled = m.load_ref.squaredNorm() > 0.0;
  cb.accepted = [&](const StepRecord& rec, const StepReport& rep, const Eigen::VectorXd& x) {
    m.lambda = rec.lambda;
    m.expand(x, m.lambda, m.u);
    m.reactions = problem.internal_force();
    if (const double dl = m.lambda - lambda_prev; dl > 0.0) {
      double kq;
      if (load_controlled) {
        const double fu = m.load_ref.dot(m.u - u_prev);
        kq = fu > 0.0 ? dl / fu : -1.0;
      } else {
        kq = (m.u - u_prev).dot(m.reactions - f_prev) / (dl * dl);
      }
      if (stiffness_first == 0.0) stiffness_first = kq;
      stiffness_path.push_back({m.lambda, kq});
    }
    lambda_prev = m.lambda;
    u_prev = m.u;
    f_prev = m.reactions;
    stepped = true;
    step = rec.step;
    stage_step = step;
    ++summary.steps_done;
    time = static_cast<double>(k) + m.lambda;
    if (options.on_step) options.on_step(step, nominal_steps, m.lambda, rep);
    if (options.on_record) options.on_record(rec);
    record(); // first: the step's VTK field data carries the head load it records
    written = writer && st.vtk && step % st.every == 0;
    if (written) timed(summary.times.output, [&] { write_step(*writer, time); });
    for (auto& r : recorders) r.sample(m, static_cast<int>(k) + 1, step, m.lambda, rec.iterations);
    live.push_back(rec);
    live.back().stage = static_cast<int>(k) + 1;
    if (options.write_output && seconds_since(last_tables) >= tables_every)
      timed(summary.times.output, [&] { write_tables(summary, axial_rows, live); });
  };
  bool settled = false, interrupted = false;
  const bool watch = st.stop_settlement > 0 && monitor;
  if (watch || options.interrupted)
    cb.stop = [&](double, const Eigen::VectorXd&) {
      if (watch && (settled = mean_settlement(m, *monitor) > st.stop_settlement)) return true;
      return interrupted = options.interrupted && options.interrupted();
    };
  solver = solver_factory->create(solver_params);
  StageResult res = stratum::run_stage(problem, *solver, settings, cb, u);
  summary.cutbacks += res.cutbacks;
  for (auto& r : res.reports) summary.reports.push_back(std::move(r));
  for (auto& r : res.records) {
    r.stage = static_cast<int>(k) + 1;
    summary.records.push_back(std::move(r));
  }
  if (writer && st.vtk && step > 0 && !written)
    timed(summary.times.output, [&] { write_step(*writer, time); });
  if (!res.outcome.ok()) {
    std::string message = "stage \"" + st.name + "\": " + res.outcome.message;
    if (st.until_failure) {
      // The least stiffness over the last tenth of the load reached: a single stiff step just
      // before the stop (a contact closing, a point unloading) does not hide that the curve
      // had flattened (the Class-C pile: 0.72 on its last step, 0.0x just before).
      double least = std::numeric_limits<double>::infinity();
      const double from = 0.9 * lambda_prev;
      for (const auto& [l, kq] : stiffness_path)
        if (l >= from) least = std::min(least, kq);
      summary.stiffness_ratio = stiffness_first > 0.0 && std::isfinite(least) ? least / stiffness_first : 1.0;
      const bool collapse = stiffness_first > 0.0 && summary.stiffness_ratio < st.collapse_stiffness;
      summary.stop_reason = collapse ? "collapse" : "numerical";
      summary.stop_message = std::move(message);
    } else {
      summary.outcome = Outcome::failure(res.outcome.status, std::move(message));
    }
    return false;
  }
  if (settled) {
    summary.stop_reason = "settlement";
    return false;
  }
  if (interrupted) {
    summary.stop_reason = "interrupted";
    return false;
  }
  if (st.reset_after) {
    m.u.setZero();
    if (writer && st.vtk) write_step(*writer, time);
  }
  return true;
}

/// diagnostics.csv and the curves, each replaced atomically: at the end of every stage, every few
/// seconds during a stage (so that a long run's tables grow while it runs and a kill loses at
/// most the last seconds), and at the end. `live`: the accepted steps of the running stage (its
/// failed attempts join at the stage's end).
void Analysis::Impl::write_tables(const RunSummary& summary,
                                  const std::vector<std::array<double, 3>>& axial_rows,
                                  const std::vector<StepRecord>& live) {
  Model& m = model;
  if (options.write_output)
    for (const auto& r : recorders)
      write_text_atomically(fs::path(summary.out_dir) / "history" / (r.name() + ".csv"), r.csv());
  if (options.write_output) {
    if (live.empty()) {
      write_step_records((fs::path(summary.out_dir) / "diagnostics.csv").string(), summary.records);
    } else {
      std::vector<StepRecord> all = summary.records;
      all.insert(all.end(), live.begin(), live.end());
      write_step_records((fs::path(summary.out_dir) / "diagnostics.csv").string(), all);
    }
  }
  if (options.write_output && !summary.load_settlement.empty()) {
    std::ostringstream ls, af;
    ls << std::setprecision(10) << "load_kN,settlement_mm\n";
    for (const auto& r : summary.load_settlement) ls << r[0] << ',' << r[1] << '\n';
    write_text_atomically(fs::path(summary.out_dir) / "curves" / "load_settlement.csv", ls.str());
    if (!axial_rows.empty()) {
      af << std::setprecision(10) << "load_kN,depth_m,axial_force_kN\n";
      double top = -std::numeric_limits<double>::infinity();
      for (int c : m.mesh.cell_sets.at(pile_cells))
        for (int n : m.mesh.cells[static_cast<std::size_t>(c)].nodes)
          if (n >= 0) top = std::max(top, m.mesh.nodes[static_cast<std::size_t>(n)].y());
      for (const auto& r : axial_rows) af << r[0] << ',' << top - r[1] << ',' << r[2] << '\n';
      write_text_atomically(fs::path(summary.out_dir) / "curves" / "axial_force.csv", af.str());
      if (!shaft_rows.empty()) {
        std::ostringstream st;
        st << std::setprecision(10)
           << "load_kN,depth_m,shear_traction_kPa,normal_traction_kPa,slip_mm,status\n";
        static const char* names[] = {"stick", "slip", "open"};
        for (const auto& r : shaft_rows)
          st << r[0] << ',' << top - r[1] << ',' << r[2] << ',' << r[3] << ',' << r[4] << ','
             << names[static_cast<int>(r[5])] << '\n';
        write_text_atomically(fs::path(summary.out_dir) / "curves" / "shaft_traction.csv", st.str());
      }
    }
    if (!summary.settlement_components.empty()) {
      std::ostringstream sc;
      sc << std::setprecision(10) << PileComponents::header << '\n';
      for (const auto& r : summary.settlement_components)
        for (std::size_t i = 0; i < r.size(); ++i) sc << r[i] << (i + 1 < r.size() ? ',' : '\n');
      write_text_atomically(fs::path(summary.out_dir) / "curves" / "settlement_components.csv", sc.str());
    }
  }
  last_tables = std::chrono::steady_clock::now();
}

RunSummary Analysis::run() {
  const auto t_run = std::chrono::steady_clock::now();
  Impl& s = *impl_;
  Model& m = s.model;
  RunSummary summary;
  summary.out_dir =
      s.options.out_dir.empty() ? (fs::path("out") / fs::path(s.path).stem()).string() : s.options.out_dir;
  s.out_dir = summary.out_dir;
  std::size_t first = 0;
  if (!s.options.restart_from.empty()) {
    const std::string& path = s.options.restart_from;
    Checkpoint c = read_checkpoint(path);
    if (c.fingerprint != s.fingerprint)
      throw Error(path + ": the checkpoint belongs to another scene (it has \"" + c.fingerprint +
                  "\", this scene has \"" + s.fingerprint + "\")");
    std::vector<FingerprintPart> saved;
    for (std::size_t i = 0; i < c.part_names.size() && i < c.part_digests.size() && i < c.part_stages.size();
         ++i)
      saved.push_back({c.part_names[i], c.part_digests[i], c.part_stages[i], {}});
    SourceLocation where;
    if (const std::string why = fingerprint_mismatch(saved, s.parts, c.stages_done, &where); !why.empty())
      throw Error(where, "--restart-from " + path + ": " + why);
    if (c.states.size() != m.domains.size() || c.u.size() != static_cast<std::size_t>(m.u.size()))
      throw Error(path + ": the checkpoint does not match the scene's model size");
    m.u = Eigen::Map<const Eigen::VectorXd>(c.u.data(), static_cast<Eigen::Index>(c.u.size()));
    m.reactions =
        Eigen::Map<const Eigen::VectorXd>(c.reactions.data(), static_cast<Eigen::Index>(c.reactions.size()));
    m.active = c.active;
    m.constrained = c.constrained;
    s.loads = c.loads;
    for (std::size_t d = 0; d < m.domains.size(); ++d) m.domains[d].states.restore(c.states[d]);
    s.time = c.time;
    first = static_cast<std::size_t>(c.stages_done);
    summary.stages_done = c.stages_done;
  }

  // The folder is this run's while it writes; what an earlier run left there moves aside (after
  // a checkpoint in it was read above), so that no file of two runs mixes.
  std::optional<OutputFolder> folder;
  if (s.options.write_output) {
    folder.emplace(summary.out_dir);
    folder->move_aside_previous(fs::path(s.path).stem().string(), static_cast<int>(first));
  }
  std::unique_ptr<VtkSeriesWriter> writer;
  if (s.options.write_output && s.vtk) {
    writer = std::make_unique<VtkSeriesWriter>(summary.out_dir, fs::path(s.path).stem().string());
    timed(summary.times.output, [&] { s.write_step(*writer, s.time); });
  }
  std::vector<std::array<double, 3>> axial_rows;
  // The recorders' first row: the state the run starts from (step 0 of its first stage).
  for (auto& r : s.recorders) r.sample(m, static_cast<int>(first) + 1, 0, 0.0, 0);
  for (std::size_t k = first; k < s.stages.size(); ++k) {
    const bool go_on = s.run_stage(k, summary, writer.get(), axial_rows);
    if (!summary.outcome.ok()) break;
    if (go_on && k + 1 < s.stages.size())
      timed(summary.times.output, [&] { s.write_tables(summary, axial_rows, {}); });
    summary.stages_done = static_cast<int>(k + 1);
    if (s.stages[k].checkpoint && s.options.write_output && go_on) {
      const auto t_ckpt = std::chrono::steady_clock::now();
      Checkpoint c;
      c.fingerprint = s.fingerprint;
      for (const auto& p : s.parts)
        if (p.stage <= static_cast<int>(k)) {
          c.part_names.push_back(p.name);
          c.part_digests.push_back(p.digest);
          c.part_stages.push_back(p.stage);
        }
      c.stages_done = static_cast<int>(k + 1);
      c.stage_name = s.stages[k].name;
      c.u.assign(m.u.data(), m.u.data() + m.u.size());
      c.reactions.assign(m.reactions.data(), m.reactions.data() + m.reactions.size());
      c.active = m.active;
      c.constrained = m.constrained;
      c.loads = s.loads;
      for (const auto& dm : m.domains) c.states.push_back(dm.states.committed_data());
      c.time = s.time;
      const auto path = (fs::path(summary.out_dir) / "checkpoints" /
                         (std::to_string(k + 1) + "_" + s.stages[k].name + ".ckpt"))
                            .string();
      write_checkpoint(path, c);
      summary.checkpoints.push_back(path);
      summary.times.checkpoint += seconds_since(t_ckpt);
    }
    if (!go_on) {
      if (!summary.stop_reason.empty()) summary.stages_done = static_cast<int>(k); // ended early
      break;
    }
  }
  if (writer) summary.pvd = writer->pvd_path();
  const auto t_out = std::chrono::steady_clock::now();
  s.write_tables(summary, axial_rows, {});
  summary.checks = evaluate_checks(s.checks, s.recorders);
  summary.times.output += seconds_since(t_out);
  summary.times.total = seconds_since(t_run);
  return summary;
}

} // namespace stratum
