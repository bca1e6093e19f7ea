// Running one stage: its actions, its equilibrium problem, its load steps, and what each
// accepted step records (the pile head through its monitor, the VTK step, the recorders).
#include "output/pile_monitor.hpp"
#include "output/vtk_output.hpp"
#include "run/analysis_impl.hpp"
#include "run/static_problem.hpp"
#include "stratum/step_control.hpp"

#include <cmath>
#include <limits>
#include <optional>

namespace stratum {

namespace {

// The current stiffness of each accepted step against the stage's first (Bergan's current
// stiffness parameter): under load control dlambda / (F_ref . du), the load over the work-
// conjugate displacement of the load pattern; under displacement control (no load pattern on
// the free unknowns) du . df / dlambda^2 with df the change of the nodal forces (the reactions
// of the prescribed nodes). A stop counts as a collapse where it has fallen below
// collapse_stiffness (negative: the path has turned).
class StiffnessPath {
public:
  /// At the stage's start: the model's state and the forces f0 its active cells carry.
  StiffnessPath(const Model& m, const Eigen::VectorXd& f0)
      : u_prev_(m.u), f_prev_(f0), load_controlled_(m.load_ref.squaredNorm() > 0.0) {}

  /// Adds the accepted step the model is at (m.lambda, m.u, m.reactions).
  void add(const Model& m) {
    if (const double dl = m.lambda - lambda_prev_; dl > 0.0) {
      double kq;
      if (load_controlled_) {
        const double fu = m.load_ref.dot(m.u - u_prev_);
        kq = fu > 0.0 ? dl / fu : -1.0;
      } else {
        kq = (m.u - u_prev_).dot(m.reactions - f_prev_) / (dl * dl);
      }
      if (first_ == 0.0) first_ = kq;
      path_.push_back({m.lambda, kq});
    }
    lambda_prev_ = m.lambda;
    u_prev_ = m.u;
    f_prev_ = m.reactions;
  }

  /// The first step's stiffness was positive (a ratio against it means something).
  [[nodiscard]] bool has_first() const { return first_ > 0.0; }

  /// The stiffness a failed load-controlled attempt showed, over the first step's: its load-factor
  /// increment over the farthest work-conjugate displacement its iterations reached
  /// (StaticProblem::Reach). Infinite when it gives no evidence: no first step, no increment, or
  /// no iterate that went forward along the load pattern.
  [[nodiscard]] double attempt_ratio(const StaticProblem::Reach& a) const {
    const double dl = a.lambda - a.lambda_n;
    if (!(first_ > 0.0) || !(dl > 0.0) || !(a.along > 0.0)) return std::numeric_limits<double>::infinity();
    return dl / a.along / first_;
  }

  // The least stiffness over the last tenth of the load reached: a single stiff step just
  // before the stop (a contact closing, a point unloading) does not hide that the curve
  // had flattened (the Class-C pile: 0.72 on its last step, 0.0x just before).
  /// That least stiffness over the first's (1 when there is none).
  [[nodiscard]] double ratio() const {
    double least = std::numeric_limits<double>::infinity();
    const double from = 0.9 * lambda_prev_;
    for (const auto& [l, kq] : path_)
      if (l >= from) least = std::min(least, kq);
    return first_ > 0.0 && std::isfinite(least) ? least / first_ : 1.0;
  }

private:
  Eigen::VectorXd u_prev_, f_prev_;
  double lambda_prev_ = 0.0, first_ = 0.0;
  std::vector<std::array<double, 2>> path_; // (lambda, S) of each accepted step
  bool load_controlled_;
};

/// Analyzes the stage's matrix pattern and assembles the forces the active cells carry at the
/// stage's start (the states reverted after); false with the failure in summary.outcome.
bool initial_forces(Model& m, const Assembler& assembler, TimedLinearSolver& ls, const std::string& stage,
                    RunSummary& summary, Eigen::VectorXd& f0) {
  {
    SparseMatrix kpat = assembler.make_matrix();
    if (auto o = ls.analyze(kpat); !o.ok()) {
      summary.outcome = Outcome::failure(o.status, "stage \"" + stage + "\": " + o.message);
      return false;
    }
  }
  if (auto o = assembler.assemble(m, m.u, f0, nullptr); !o.ok()) {
    for (auto& dm : m.domains) dm.states.revert();
    summary.outcome = Outcome::failure(o.status, "stage \"" + stage + "\", initial state: " + o.message);
    return false;
  }
  for (auto& dm : m.domains) dm.states.revert();
  return true;
}

// Free DOFs: the stage starts in equilibrium with the forces the active cells carry and moves
// linearly to the target load (this releases the forces of removed cells over the steps).
// Fixed DOFs carry the target load, so that reactions are final forces.
/// Sets the model's load_base and load_ref from f0 and the target load, lambda to 0. A load that
/// jumps (StageState::load_jumps: before, after) is in full from the first step on: its change goes
/// into the base, not into the part that grows with the load factor.
void set_stage_load(Model& m, const Eigen::VectorXd& f0, const Eigen::VectorXd& target,
                    const std::vector<std::pair<LoadSpec, LoadSpec>>& jumps) {
  m.load_base = f0;
  for (const auto& [before, after] : jumps) {
    add_load(m, after, m.load_base);
    Eigen::VectorXd old = Eigen::VectorXd::Zero(m.u.size());
    add_load(m, before, old);
    m.load_base -= old;
  }
  m.load_ref = target - m.load_base;
  for (int d = 0; d < m.dofs.total(); ++d)
    if (m.dofs.eq[static_cast<std::size_t>(d)] < 0) m.load_base[d] = target[d], m.load_ref[d] = 0.0;
  m.lambda = 0.0;
}

/// The step settings of stage `st`: the scene's, with the stage's steps and cut-backs.
StepSettings stage_stepping(const scene::Settings& settings, const stage::Stage& st) {
  StepSettings stepping = settings.stepping;
  stepping.steps = st.steps;
  stepping.increments = st.increments;
  stepping.max_cutbacks = st.max_cutbacks;
  stepping.error_tolerance = st.error_tolerance;
  stepping.lambda_start = 0.0;
  stepping.lambda_end = 1.0;
  stepping.convergence = settings.convergence;
  return stepping;
}

/// The callbacks that commit and revert the material states, and the predictor where the stage
/// prescribes displacements.
StepCallbacks state_callbacks(Model& m, LinearSolver& ls) {
  StepCallbacks cb;
  cb.commit = [&m] {
    for (auto& dm : m.domains) dm.states.commit();
  };
  cb.revert = [&m] {
    for (auto& dm : m.domains) dm.states.revert();
  };
  // Prescribed displacements jump at the start of a step; without a predictor the first
  // iterate puts the whole jump into the cells next to the prescribed nodes.
  if (m.prescribed.size() > 0 && m.prescribed.cwiseAbs().maxCoeff() > 0.0)
    cb.predict = [&ls](NonlinearProblem& p, double l0, double l1, Eigen::VectorXd& x) {
      predict(p, ls, l0, l1, x);
    };
  return cb;
}

/// Moves the stage's reports and records (numbered with the stage) into the summary.
void collect_steps(StageResult& res, int stage, RunSummary& summary) {
  summary.cutbacks += res.cutbacks;
  for (auto& r : res.reports) summary.reports.push_back(std::move(r));
  for (auto& r : res.records) {
    r.stage = stage;
    summary.records.push_back(std::move(r));
  }
}

/// Failures that can mean "no equilibrium at this load": the iteration ran out of iterations,
/// diverged or met a singular tangent. NaN or Inf, a constitutive update that found no stress
/// (material_failure) and a fatal error say that a computation failed, not where equilibrium is.
bool can_mean_no_equilibrium(Status s) {
  return s == Status::not_converged || s == Status::diverged || s == Status::singular;
}

/// A failed step: in an until_failure stage a stop (collapse or numerical), otherwise the run's
/// failure. The stop is a collapse when the structure had lost its stiffness, by either of two
/// readings of Bergan's current stiffness against the stage's first step (README, docs/design.md
/// "How a stage ends"):
/// - the accepted steps: the least over the last tenth of the load below collapse_stiffness;
/// - the attempt that ended the stage (load control): cut back to the smallest increment dl
///   allowed, its iterations still found no equilibrium and went further along the load pattern
///   than dl / (collapse_stiffness S_1), the displacement a structure that kept collapse_stiffness
///   of its first stiffness S_1 would need for dl. Its stiffness dl / (F_ref . du), du the farthest
///   iterate, is then below collapse_stiffness: the load could not be raised by dl. This is what a
///   plateau reached by force control looks like (a perfectly plastic shaft slipping all at once):
///   the accepted steps stay stiff up to the limit and only the attempts past it move freely.
///   Only failures that can mean a missing equilibrium count (can_mean_no_equilibrium).
void stage_failed(const stage::Stage& st, const StageResult& res, const StiffnessPath& stiffness,
                  const StaticProblem::Reach& last_attempt, bool load_control, RunSummary& summary) {
  std::string message = "stage \"" + st.name + "\": " + res.outcome.message;
  if (st.until_failure && res.outcome.status != Status::fatal) { // a fatal error is no collapse
    summary.stiffness_ratio = stiffness.ratio();
    summary.collapse_stiffness = st.collapse_stiffness;
    summary.attempt_stiffness_ratio = load_control && can_mean_no_equilibrium(res.outcome.status)
                                          ? stiffness.attempt_ratio(last_attempt)
                                          : std::numeric_limits<double>::infinity();
    const bool collapse = stiffness.has_first() && (summary.stiffness_ratio < st.collapse_stiffness ||
                                                    summary.attempt_stiffness_ratio < st.collapse_stiffness);
    summary.stop_reason = collapse ? StopReason::collapse : StopReason::numerical;
    summary.stop_message = std::move(message);
  } else {
    summary.outcome = Outcome::failure(res.outcome.status, std::move(message));
  }
}

/// The largest |p| of the excess pore pressure at the nodes that carry one (0 without the field).
double largest_excess_pressure(const Model& m) {
  const int f = m.dofs.field("p");
  double largest = 0.0;
  if (f < 0) return largest;
  for (std::size_t n = 0; n + 1 < m.dofs.node_first.size(); ++n)
    if (const int d = m.dofs.dof(static_cast<int>(n), f); d >= 0)
      largest = std::max(largest, std::abs(m.u[d]));
  return largest;
}

} // namespace

void Analysis::Impl::record_pile(const PileObservation& o, RunSummary& summary) {
  if (!o.recorded) return;
  summary.load_settlement.push_back({o.load, o.settlement});
  state.head_load = o.load;
  state.head_settlement = o.settlement;
  if (o.components) summary.settlement_components.push_back(*o.components);
  state.axial_rows.insert(state.axial_rows.end(), o.axial.begin(), o.axial.end());
  state.shaft_rows.insert(state.shaft_rows.end(), o.shaft.begin(), o.shaft.end());
}

void Analysis::Impl::record_stage_loads(const std::vector<LoadSpec>& before) {
  auto named = [](const std::vector<LoadSpec>& list, const std::string& name) {
    return std::any_of(list.begin(), list.end(), [&](const LoadSpec& l) { return l.name == name; });
  };
  auto resultant = [&](const LoadSpec& l) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(sm.model.u.size());
    add_load(sm.model, l, f);
    // The y components by the DOF map: a node of a porous cell also carries p, so the unknowns
    // are not (ux, uy) pairs throughout.
    double fy = 0.0;
    for (std::size_t n = 0; n < sm.model.mesh.nodes.size(); ++n)
      if (const int d = sm.model.dofs.dof(static_cast<int>(n), field_uy); d >= 0) fy += f[d];
    return fy;
  };
  auto& stage_loads = state.stage_loads;
  stage_loads.clear();
  for (const auto& l : loads) stage_loads.push_back({l.name, named(before, l.name) ? 0 : 1, resultant(l)});
  for (const auto& l : before)
    if (!named(loads, l.name)) stage_loads.push_back({l.name, -1, resultant(l)});
}

void Analysis::Impl::update_tables(const RunSummary& summary, const std::vector<StepRecord>& live) {
  if (options.write_output) stratum::write_tables(view(), summary, recorders, live);
  last_tables = std::chrono::steady_clock::now();
}

bool Analysis::Impl::run_stage(std::size_t k, RunSummary& summary, VtkSeriesWriter* writer) {
  stage::Stage& st = sm.stages[k];
  const scene::Settings& settings = sm.settings;
  state.stage_name = st.name;
  state.stage_number = static_cast<int>(k) + 1;
  state.stage_step = 0;
  if (options.on_stage) options.on_stage(st.name, state.stage_number, static_cast<int>(sm.stages.size()));
  Model& m = sm.model;
  m.prescribed = k == 0 ? sm.initial_prescribed : Eigen::VectorXd::Zero(m.u.size());
  m.prescribed_base = m.u;

  // ---- actions, in order (stratum/stage_action.hpp)
  const std::vector<LoadSpec> loads_before = loads;
  StageState actions{m, loads, nullptr, {}, {}};
  for (const auto& a : st.actions) a->apply(actions);

  // ---- the stage's problem: equilibrium at its start, the target load at its end
  m.rebuild_dofs();
  // The stage's time (stratum/material.hpp, StepClock): a static stage lasts one unit of
  // pseudo-time, a consolidation stage its duration in seconds, so the total time at its start is
  // where the stages before it ended (state.time; a checkpoint keeps it, so a restart continues
  // it); the problem sets the times of each evaluation from the load factor.
  const double stage_start = state.time;
  const double stage_length = st.consolidation ? st.duration : 1.0;
  m.clock = StepClock{0.0, stage_start, 0.0, static_cast<int>(k) + 1, 1, st.consolidation};
  const Assembler assembler(m, settings.reuse_linear_stiffness, settings.threads);
  auto ls = std::make_unique<TimedLinearSolver>(
      make_linear_solver(settings.linear_solver, m.symmetric(), m.dofs.free_count), summary.times,
      !settings.reuse_symbolic);
  Eigen::VectorXd f0;
  if (!initial_forces(m, assembler, *ls, st.name, summary, f0)) return false;
  Eigen::VectorXd target = Eigen::VectorXd::Zero(m.u.size());
  for (const auto& l : loads) add_load(m, l, target);
  m.inflow.resize(0); // empty without an inflow: the problem then adds nothing
  for (const auto& l : loads)
    if (l.kind == LoadSpec::Kind::inflow) {
      if (m.inflow.size() == 0) m.inflow = Eigen::VectorXd::Zero(m.u.size());
      add_inflow(m, l, m.inflow);
    }
  record_stage_loads(loads_before);
  set_stage_load(m, f0, target, actions.load_jumps);
  StaticProblem problem(m, assembler, *ls, summary.times, st.consolidation ? st.duration : 0.0);

  // ---- the pile's quantities (output/pile_monitor.hpp)
  std::vector<std::size_t> itf;
  for (const auto& i : sm.interfaces.interfaces) itf.push_back(i.domain);
  const std::vector<int>* pile_cells =
      settings.pile_cells.empty() ? nullptr : &m.mesh.cell_sets.at(settings.pile_cells);
  PileMonitor pile(m, st, actions.head_load, loads_before, actions.head_nodes, pile_cells, std::move(itf),
                   sm.units);
  if (pile.has_head() && summary.load_settlement.empty()) record_pile(pile.observe(m, false), summary);

  // ---- load steps (stratum/step_control.hpp)
  const int nominal_steps = st.increments.empty() ? st.steps : static_cast<int>(st.increments.size());
  Eigen::VectorXd u = m.restrict_free(m.u);
  const StepSettings stepping = stage_stepping(settings, st);
  StepCallbacks cb = state_callbacks(m, *ls);
  // How far each attempt's iterations went along the load pattern (StaticProblem::Reach): kept
  // for the last attempt that failed, the evidence stage_failed reads.
  StaticProblem::Reach last_attempt;
  cb.commit = [&problem, commit = cb.commit] {
    commit();
    (void)problem.take_reach();
  };
  cb.revert = [&problem, &last_attempt, revert = cb.revert] {
    revert();
    last_attempt = problem.take_reach();
  };
  int step = 0;
  bool written = false;
  std::vector<StepRecord> live; // this stage's accepted steps, for the tables written during it
  StiffnessPath stiffness(m, f0);
  cb.accepted = [&](const StepRecord& rec, const StepReport& rep, const Eigen::VectorXd& x) {
    m.lambda = rec.lambda;
    m.clock.increment = rec.step + 1; // the next step's
    m.expand(x, m.lambda, m.u);
    m.reactions = problem.internal_force();
    stiffness.add(m);
    step = rec.step;
    state.stage_step = step;
    ++summary.steps_done;
    state.time = stage_start + m.lambda * stage_length;
    if (options.on_step) options.on_step(step, nominal_steps, m.lambda, rep);
    if (options.on_record) options.on_record(rec);
    // first: the step's VTK field data carries the head load it records
    record_pile(pile.observe(m, true), summary);
    written = writer && st.vtk && step % st.every == 0;
    if (written) timed(summary.times.output, [&] { write_step(*writer, view()); });
    for (auto& r : recorders)
      r.sample(m, static_cast<int>(k) + 1, step, m.lambda, rec.iterations, state.time);
    live.push_back(rec);
    live.back().stage = static_cast<int>(k) + 1;
    if (seconds_since(last_tables) >= settings.tables_every)
      timed(summary.times.output, [&] { update_tables(summary, live); });
  };
  bool settled = false, interrupted = false, dissipated = false;
  const bool watch = pile.watches_settlement();
  const bool watch_pressure = st.consolidation && st.until_excess_pressure > 0.0;
  if (watch || watch_pressure || options.interrupted)
    cb.stop = [&](double, const Eigen::VectorXd&) {
      if (watch && (settled = pile.settlement_reached(m))) return true;
      if (watch_pressure && (dissipated = largest_excess_pressure(m) < st.until_excess_pressure)) return true;
      return interrupted = options.interrupted && options.interrupted();
    };
  solver = sm.solver_factory->create(sm.solver_params);
  StageResult res = stratum::run_stage(problem, *solver, stepping, cb, u);
  collect_steps(res, static_cast<int>(k) + 1, summary);
  if (writer && st.vtk && step > 0 && !written)
    timed(summary.times.output, [&] { write_step(*writer, view()); });
  if (!res.outcome.ok()) {
    stage_failed(st, res, stiffness, last_attempt, !solver->path_following(), summary);
    return false;
  }
  if (dissipated) state.time = stage_start + m.lambda * stage_length; // the stage ends early, normally
  if (settled || interrupted) {
    summary.stop_reason = settled ? StopReason::settlement : StopReason::interrupted;
    return false;
  }
  if (st.reset_after) {
    m.u.setZero();
    if (writer && st.vtk) write_step(*writer, view());
  }
  return true;
}

} // namespace stratum
