// The nonlinear problem a stage solves (static equilibrium of the model), the linear solver
// wrapper that times it, and the tangent predictor of prescribed-displacement steps.
#pragma once

#include "run/timing.hpp"
#include "stratum/analysis.hpp"
#include "stratum/linear_solver.hpp"
#include "stratum/model.hpp"
#include "stratum/solver.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace stratum {

/// Static equilibrium of the model: R(u, lambda) = F_base + lambda F_ref - F_int(u).
class StaticProblem final : public NonlinearProblem {
public:
  /// `duration`: the physical time of a consolidation stage (s), over which its load factor runs
  /// from 0 to 1; 0 in a static stage, whose time is the load factor itself.
  StaticProblem(Model& m, const Assembler& a, LinearSolver& ls, RunTimes& times, double duration = 0.0)
      : m_(m), a_(a), ls_(ls), times_(times), start_(m.clock.total_time - m.clock.step_time),
        scale_(duration > 0.0 ? duration : 1.0) {
    ref_ = m.restrict_free(m.load_ref);
    weigh_other_fields();
  }
  Eigen::Index size() const override { return m_.dofs.free_count; }
  Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r, SparseMatrix* k) override {
    // The time of the step being tried: its start is the committed load factor (StepClock).
    m_.clock.step_time = m_.lambda * scale_;
    m_.clock.total_time = start_ + m_.clock.step_time;
    m_.clock.dtime = (lambda - m_.lambda) * scale_;
    m_.expand(u, lambda, full_);
    note_reach(lambda);
    Outcome o = timed(times_.assembly, [&] { return a_.assemble(m_, full_, fint_, k); });
    ++times_.assemblies;
    if (!o.ok()) return o;
    r.resize(size());
    for (int d = 0; d < m_.dofs.total(); ++d)
      if (const int e = m_.dofs.eq[d]; e >= 0) r[e] = m_.load_base[d] + lambda * m_.load_ref[d] - fint_[d];
    // A prescribed inflow adds the volume of the step (a static stage takes no time). The
    // continuity rows count a volume with the sign of the elements' f_int, -(what the point
    // gained): their residual is the volume gained less the volume that entered.
    if (m_.clock.transient && m_.inflow.size() == fint_.size())
      for (int d = 0; d < m_.dofs.total(); ++d)
        if (const int e = m_.dofs.eq[d]; e >= 0 && m_.inflow[d] != 0.0) r[e] -= m_.clock.dtime * m_.inflow[d];
    if (!other_rows_.empty()) weigh(r, k);
    return {};
  }
  SparseMatrix make_tangent() const override { return a_.make_matrix(); }
  const Eigen::VectorXd& reference_load() const override { return ref_; }
  LinearSolver& linear_solver() override { return ls_; }
  double force_scale(double lambda) const override {
    return std::max((m_.load_base + lambda * m_.load_ref).norm(), fint_.size() ? fint_.norm() : 0.0);
  }
  std::vector<Eigen::Index> node_set_dofs(const std::string& set, int component) const override {
    return m_.node_set_free_dofs(set, component);
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

  /// How far the evaluations of one attempted step went along the load pattern: the largest
  /// |F_ref . (u - u_n)| (work-conjugate displacement, either way) of the unknowns evaluated, from
  /// the committed state (Model::u at Model::lambda), and the load factor they were evaluated at.
  /// Either way: a tangent that has lost its stiffness in a mode the load works on sends Newton's
  /// correction along that mode with the sign of a pivot near zero, which round-off decides.
  struct Reach {
    double lambda_n = 0.0; ///< the committed load factor the attempt started from
    double lambda = 0.0;   ///< the load factor of its last evaluation (load control: its target)
    double along = 0.0;    ///< max |F_ref . (u - u_n)| over its evaluations (kN m; NaN iterates skipped)
    int evaluations = 0;
  };
  /// The reach of the evaluations since the last call (the attempt just committed or reverted),
  /// and starts a new one. Watching changes no number of the solution.
  Reach take_reach() {
    const Reach r = reach_;
    reach_ = Reach{};
    return r;
  }

private:
  /// The equations of fields besides the displacements (a pore pressure's continuity, a volume in
  /// m3) are multiplied by one factor per stage, c = mean |K_uu diagonal| / mean over their
  /// unknowns of the largest |K_up| (kPa/m: a volume error becomes the force it would cause), so
  /// that one residual norm weighs both kinds of equation: unscaled, a continuity residual would
  /// pass any force tolerance unsolved. Scaling rows changes no Newton correction (the tangent's
  /// rows are scaled alike), only the norms the convergence test and the line search read.
  void weigh_other_fields();
  void weigh(Eigen::VectorXd& r, SparseMatrix* k) const {
    for (Eigen::Index e : other_rows_) r[e] *= weight_;
    if (k == nullptr) return;
    for (int j = 0; j < k->outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(*k, j); it; ++it)
        if (is_other_[static_cast<std::size_t>(it.row())]) it.valueRef() *= weight_;
  }

  void note_reach(double lambda) {
    const double along = std::abs(m_.load_ref.dot(full_ - m_.u));
    if (reach_.evaluations++ == 0) reach_.lambda_n = m_.lambda;
    reach_.lambda = lambda;
    if (std::isfinite(along)) reach_.along = std::max(reach_.along, along);
  }

  Reach reach_;
  Model& m_;
  const Assembler& a_;
  LinearSolver& ls_;
  RunTimes& times_;
  double start_; ///< total time at the stage's start
  double scale_; ///< time per unit of load factor: the duration of a consolidation stage, else 1
  std::vector<Eigen::Index> other_rows_; ///< free equations of the fields besides the displacements
  std::vector<char> is_other_;           ///< per free equation: one of other_rows_
  double weight_ = 1.0;                  ///< their factor (weigh_other_fields)
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
void predict(NonlinearProblem& problem, LinearSolver& ls, double lambda_n, double lambda, Eigen::VectorXd& u);

} // namespace stratum
