// Running one stage: its actions, its equilibrium problem, its load steps, and what each
// accepted step records (the pile head, the curves, the VTK step, the recorders).
#include "analysis_impl.hpp"
#include "output/pile_components.hpp"
#include "output/pile_curves.hpp"
#include "run/static_problem.hpp"
#include "stratum/body_interfaces.hpp"
#include "stratum/step_control.hpp"

#include <cmath>
#include <optional>
#include <set>

namespace stratum {

bool Analysis::Impl::run_stage(std::size_t k, RunSummary& summary, VtkSeriesWriter* writer,
                               std::vector<std::array<double, 3>>& axial_rows) {
  stage::Stage& st = stages[k];
  stage_name = st.name;
  stage_number = static_cast<int>(k) + 1;
  stage_step = 0;
  if (options.on_stage) options.on_stage(st.name, stage_number, static_cast<int>(stages.size()));
  Model& m = model;
  m.prescribed = k == 0 ? initial_prescribed : Eigen::VectorXd::Zero(m.u.size());
  m.prescribed_base = m.u;

  // ---- actions, in order (stratum/stage_action.hpp)
  const std::vector<LoadSpec> loads_before = loads;
  StageState actions{m, loads, nullptr, {}};
  for (const auto& a : st.actions) a->apply(actions);
  const LoadSpec* head = actions.head_load;
  const std::vector<int>& head_disp = actions.head_nodes; // nodes of a displacement-controlled pile head

  // ---- the stage's problem: equilibrium at its start, the target load at its end
  m.rebuild_dofs();
  const Assembler assembler(m, settings.reuse_linear_stiffness, settings.threads);
  auto ls = std::make_unique<TimedLinearSolver>(
      make_linear_solver(settings.linear_solver, m.symmetric(), m.dofs.free_count), summary.times,
      !settings.reuse_symbolic);
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
  for (const auto& l : loads) add_load(m, l, target);
  record_stage_loads(loads_before);
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
  if (head) head_nodes = load_nodes(m, *head);
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
      for (int n : head_nodes) {
        const int d = m.dofs.dof(n, field_uy);
        P -= m.reactions[d] - m.load_base[d];
      }
    return P;
  };
  const std::vector<int>* pile =
      settings.pile_cells.empty() ? nullptr : &m.mesh.cell_sets.at(settings.pile_cells);
  std::optional<PileComponents> components; // curves/settlement_components.csv (pile_components.hpp)
  auto record = [&] {
    if (!has_head) return;
    const double load = head_load();
    const double small = units.small_length_factor(); // m -> mm (Units::small_length)
    summary.load_settlement.push_back({load, small * mean_settlement(m, head_nodes)});
    last_head_load = load;
    last_head_settlement = summary.load_settlement.back()[1];
    if (pile) {
      if (!components) {
        std::vector<std::size_t> itf;
        for (const auto& i : interfaces.interfaces) itf.push_back(i.domain);
        components.emplace(m, *pile, std::move(itf));
      }
      summary.settlement_components.push_back(components->row(m, load, small));
    }
    if (pile)
      for (const auto& [y, n] : axial_profile(m, *pile, 1e6 * units.length_in_m())) // levels: micrometres
        axial_rows.push_back({load, y, n});
    // Shaft tractions: the points of the interface cells that lie on the vertical wall (every
    // point at the largest radius); a cell of the base that only touches the wall at its
    // corner is not the shaft's (its traction is the base's shear and vertical normal).
    for (const auto& itf : interfaces.interfaces) {
      const auto pts = interface_points(m, m.domains[itf.domain]);
      double rmax = 0.0;
      for (const auto& q : pts) rmax = std::max(rmax, q.x.x());
      const double tol = 1e-9 * std::max(1.0, rmax); // relative: any length unit
      std::set<int> off_wall;
      for (const auto& q : pts)
        if (q.x.x() <= rmax - tol) off_wall.insert(q.cell);
      for (const auto& q : pts)
        if (!off_wall.count(q.cell))
          shaft_rows.push_back({load, q.x.y(), q.traction[0], q.traction[1], small * q.jump[0],
                                static_cast<double>(static_cast<int>(q.state))});
    }
  };
  if (has_head && summary.load_settlement.empty()) record();

  // ---- load steps (stratum/step_control.hpp)
  const int nominal_steps = st.increments.empty() ? st.steps : static_cast<int>(st.increments.size());
  Eigen::VectorXd u = m.restrict_free(m.u);
  StepSettings stepping = settings.stepping;
  stepping.steps = st.steps;
  stepping.increments = st.increments;
  stepping.max_cutbacks = st.max_cutbacks;
  stepping.error_tolerance = st.error_tolerance;
  stepping.lambda_start = 0.0;
  stepping.lambda_end = 1.0;
  stepping.convergence = settings.convergence;
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
    if (options.write_output && seconds_since(last_tables) >= settings.tables_every)
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
  StageResult res = stratum::run_stage(problem, *solver, stepping, cb, u);
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

} // namespace stratum
