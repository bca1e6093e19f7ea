#include "stratum/step_control.hpp"

#include "files.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace stratum {

void convergence_rates(const std::vector<double>& r, double& order, double& contraction) {
  order = contraction = 0.0;
  const std::size_t n = r.size();
  if (n >= 2 && r[n - 2] > 0) contraction = r[n - 1] / r[n - 2];
  if (n >= 3 && r[n - 1] > 0 && r[n - 2] > 0 && r[n - 3] > 0 && r[n - 2] != r[n - 3]) {
    const double q = std::log(r[n - 1] / r[n - 2]) / std::log(r[n - 2] / r[n - 3]);
    if (std::isfinite(q)) order = q;
  }
}

namespace {

using Clock = std::chrono::steady_clock;

StepRecord make_record(int step, double lambda_n, const StepReport& rep, double seconds, int cutbacks) {
  StepRecord r;
  r.step = step;
  r.accepted = rep.outcome.ok();
  r.lambda_n = lambda_n;
  r.lambda = rep.lambda;
  r.iterations = rep.iterations;
  r.factorizations = rep.factorizations;
  r.residual_norms = rep.residual_norms;
  convergence_rates(rep.residual_norms, r.order, r.contraction);
  r.seconds = seconds;
  r.cutbacks = cutbacks;
  r.arc_length = rep.arc_length;
  r.message = rep.outcome.message;
  return r;
}

void call(const std::function<void()>& f) {
  if (f) f();
}

std::string gave_up(const StepRecord& r, int cuts, bool path) {
  std::ostringstream m;
  m << "step from load factor " << r.lambda_n;
  if (path)
    m << " (step size " << r.arc_length << ")";
  else
    m << " to " << r.lambda;
  m << " failed: " << r.message << " (gave up after " << cuts << " cut-backs)";
  return m.str();
}

/// What both step loops carry from one accepted step to the next: the accepted displacements
/// and the last step's increment (a solver may extrapolate it).
struct Accepted {
  Eigen::VectorXd& u;
  Eigen::VectorXd previous;
  double previous_dlambda = 0.0;

  /// Sets the next request's extrapolation data.
  void prepare(StepRequest& req) const {
    if (previous.size()) {
      req.previous_increment = &previous;
      req.previous_dlambda = previous_dlambda;
    }
  }
  /// Commits the converged `trial` at `lambda`, records the step and reports it; true when the
  /// caller's stop rule ends the stage (res.stopped is then set).
  bool commit(const StepCallbacks& cb, const StepRecord& rec, const StepReport& rep,
              const Eigen::VectorXd& trial, double lambda, StageResult& res) {
    call(cb.commit);
    previous = trial - u;
    previous_dlambda = lambda - res.lambda;
    u = trial;
    res.lambda = lambda;
    ++res.steps_done;
    res.records.push_back(rec);
    if (cb.accepted) cb.accepted(rec, rep, u);
    if (cb.stop && cb.stop(res.lambda, u)) {
      res.stopped = true;
      return true;
    }
    return false;
  }
};

/// Load control: increments of lambda, cut back on failure, grown after fast steps.
StageResult load_control(NonlinearProblem& problem, const Solver& solver, const StepSettings& s,
                         const StepCallbacks& cb, Eigen::VectorXd& u) {
  StageResult res;
  res.lambda = s.lambda_start;
  const double range = s.lambda_end - s.lambda_start;
  const double dir = range >= 0 ? 1.0 : -1.0;
  const double eps = 1e-12 * std::max(1.0, std::abs(s.lambda_end));
  // Boundaries of the listed increments (the last one repeats until lambda_end).
  auto nominal_at = [&](std::size_t i) {
    if (s.increments.empty()) return std::abs(range) / std::max(1, s.steps);
    return std::abs(s.increments[std::min(i, s.increments.size() - 1)]);
  };
  std::size_t entry = 0;
  double boundary = s.lambda_start + dir * nominal_at(0);
  double nominal = nominal_at(0);
  double dl = nominal;
  const double max_inc = s.max_increment > 0 ? s.max_increment : std::max(std::abs(range), nominal);
  int cuts_here = 0;
  bool recovering = false;
  Accepted accepted{u, {}, 0.0};
  while (dir * (s.lambda_end - res.lambda) > eps) {
    if (res.steps_done >= s.max_steps) {
      res.outcome = Outcome::failure(
          Status::not_converged, "stage stopped after max_steps = " + std::to_string(s.max_steps) + " steps");
      return res;
    }
    StepRequest req;
    req.lambda_n = res.lambda;
    double target = res.lambda + dir * dl;
    if (!s.automatic && dir * (target - boundary) > -eps) target = boundary; // land on the listed boundary
    if (dir * (target - s.lambda_end) > -eps) target = s.lambda_end;
    req.lambda = target;
    req.convergence = s.convergence;
    accepted.prepare(req);
    Eigen::VectorXd trial = u;
    const auto t0 = Clock::now();
    if (cb.predict) cb.predict(problem, req.lambda_n, req.lambda, trial);
    StepReport rep = solver.solve(problem, req, trial);
    rep.lambda = req.lambda; // load control: the target, whatever the solver wrote
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    StepRecord rec = make_record(res.steps_done + 1, req.lambda_n, rep, secs, cuts_here);
    res.reports.push_back(rep);
    if (!rep.outcome.ok()) {
      call(cb.revert);
      res.records.push_back(rec);
      if (rep.outcome.status == Status::fatal) { // no retry: the run ends here
        res.outcome = rep.outcome;
        return res;
      }
      // Give up when the increment is already max_cutbacks halvings below the nominal one.
      const double floor = nominal * std::ldexp(1.0, -s.max_cutbacks);
      if (std::abs(req.lambda - req.lambda_n) <= floor * (1 + 1e-9)) {
        res.outcome = Outcome::failure(rep.outcome.status, gave_up(rec, s.max_cutbacks, false));
        return res;
      }
      dl = 0.5 * std::abs(req.lambda - req.lambda_n);
      ++cuts_here;
      ++res.cutbacks;
      continue;
    }
    const double taken = std::abs(req.lambda - req.lambda_n);
    // Error control: the local error estimate of the converged step against the tolerance. The
    // estimate is second order in the step (a first- against a second-order update), so the
    // step scales with sqrt(tol / error), with a safety factor 0.9, within [1/4, 4].
    double error_factor = 0.0;
    if (s.error_tolerance > 0.0) {
      const double e = problem.step_error();
      error_factor = e > 0.0 ? std::clamp(0.9 * std::sqrt(s.error_tolerance / e), 0.25, 4.0) : 4.0;
      const double floor = nominal * std::ldexp(1.0, -s.max_cutbacks);
      if (e > s.error_tolerance && taken > floor * (1 + 1e-9)) {
        call(cb.revert);
        rec.accepted = false;
        std::ostringstream m;
        m << "local error estimate " << e << " above error_tolerance " << s.error_tolerance;
        rec.message = m.str();
        res.records.push_back(rec);
        dl = std::max(floor, taken * std::min(error_factor, 0.9));
        ++res.error_rejections;
        continue;
      }
    }
    if (accepted.commit(cb, rec, rep, trial, req.lambda, res)) return res;
    if (!s.automatic && dir * (res.lambda - boundary) > -eps) {
      ++entry;
      nominal = nominal_at(entry);
      boundary = res.lambda + dir * nominal;
    }
    if (cuts_here > 0) recovering = true;
    if (s.automatic) {
      if (recovering)
        dl = std::min(nominal, 2 * taken);
      else if (rep.iterations <= s.fast_iterations)
        dl = std::min(max_inc, std::max(dl, taken) * s.growth);
      if (dl >= nominal) recovering = false;
    } else if (s.error_tolerance > 0.0) {
      // The error sizes the next step (after a cut-back, at most double the taken one).
      dl = std::min(nominal, taken * error_factor);
      if (recovering) dl = std::min(dl, 2 * taken);
      if (dl >= nominal) recovering = false;
    } else {
      dl = recovering ? std::min(nominal, 2 * taken) : nominal;
      if (dl >= nominal) recovering = false;
    }
    cuts_here = 0;
  }
  return res;
}

/// Path following: the solver chooses lambda for a given step size.
StageResult path_following(NonlinearProblem& problem, const Solver& solver, const StepSettings& s,
                           const StepCallbacks& cb, Eigen::VectorXd& u) {
  StageResult res;
  res.lambda = s.lambda_start;
  const double range = s.lambda_end - s.lambda_start;
  const double dir = range >= 0 ? 1.0 : -1.0;
  double first_dl = s.increments.empty() ? std::abs(range) / std::max(1, s.steps) : std::abs(s.increments[0]);
  double size = s.arc_length; // 0 until the first step reports its size
  double nominal = size;
  int cuts_here = 0, depth = 0;
  Accepted accepted{u, {}, 0.0};
  while (dir * (s.lambda_end - res.lambda) > 1e-12 * std::max(1.0, std::abs(s.lambda_end))) {
    if (res.steps_done >= s.max_steps) {
      res.stopped = true;
      return res;
    }
    StepRequest req;
    req.lambda_n = res.lambda;
    req.lambda = res.lambda + dir * first_dl;
    req.convergence = s.convergence;
    req.arc_length = size;
    accepted.prepare(req);
    Eigen::VectorXd trial = u;
    const auto t0 = Clock::now();
    StepReport rep = solver.solve(problem, req, trial);
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    if (!rep.outcome.ok()) {
      rep.lambda = req.lambda_n; // nothing reached
      if (rep.arc_length <= 0) rep.arc_length = size;
    }
    StepRecord rec = make_record(res.steps_done + 1, req.lambda_n, rep, secs, cuts_here);
    res.reports.push_back(rep);
    if (!rep.outcome.ok()) {
      call(cb.revert);
      res.records.push_back(rec);
      if (rep.outcome.status == Status::fatal) { // no retry: the run ends here
        res.outcome = rep.outcome;
        return res;
      }
      if (depth >= s.max_cutbacks) {
        res.outcome = Outcome::failure(rep.outcome.status, gave_up(rec, depth, true));
        return res;
      }
      ++depth;
      ++cuts_here;
      ++res.cutbacks;
      if (size > 0)
        size *= 0.5;
      else if (rep.arc_length > 0)
        size = 0.5 * rep.arc_length;
      else
        first_dl *= 0.5;
      continue;
    }
    if (accepted.commit(cb, rec, rep, trial, rep.lambda, res)) return res;
    if (nominal <= 0) nominal = rep.arc_length;
    // Thesis (4.19): the next size is beta times the measured size of this step.
    double next = rep.arc_length > 0 ? rep.arc_length : size;
    if (s.automatic && rep.iterations <= s.fast_iterations && cuts_here == 0) {
      next *= s.growth;
      if (s.max_arc_length > 0) next = std::min(next, s.max_arc_length);
      if (depth > 0) --depth;
    } else if (depth > 0) {
      next = std::min(2 * next, nominal); // recover after a cut
      --depth;
    }
    size = next;
    cuts_here = 0;
  }
  return res;
}

} // namespace

StageResult run_stage(NonlinearProblem& problem, const Solver& solver, const StepSettings& settings,
                      const StepCallbacks& callbacks, Eigen::VectorXd& u) {
  return solver.path_following() ? path_following(problem, solver, settings, callbacks, u)
                                 : load_control(problem, solver, settings, callbacks, u);
}

void write_step_records(const std::string& path, const std::vector<StepRecord>& records) {
  std::ostringstream out;
  {
    out << "stage,step,accepted,lambda_n,lambda,iterations,factorizations,first_residual,last_residual,order,"
           "contraction,seconds,cutbacks,arc_length,residuals,message\n";
    out << std::setprecision(10);
    for (const auto& r : records) {
      out << r.stage << ',' << r.step << ',' << (r.accepted ? 1 : 0) << ',' << r.lambda_n << ',' << r.lambda
          << ',' << r.iterations << ',' << r.factorizations << ','
          << (r.residual_norms.empty() ? 0.0 : r.residual_norms.front()) << ','
          << (r.residual_norms.empty() ? 0.0 : r.residual_norms.back()) << ',' << r.order << ','
          << r.contraction << ',' << r.seconds << ',' << r.cutbacks << ',' << r.arc_length << ',';
      for (std::size_t i = 0; i < r.residual_norms.size(); ++i) out << (i ? ";" : "") << r.residual_norms[i];
      std::string msg = r.message;
      std::replace(msg.begin(), msg.end(), '"', '\'');
      out << ",\"" << msg << "\"\n";
    }
  }
  write_file_atomically(path, out.str()); // creates the folder: without VTK nothing made it yet
}

} // namespace stratum
