// Back-analysis: the optimizer (Ceres' Levenberg-Marquardt with bounds, on a finite-difference
// Jacobian whose runs go to the batch runner at once), the statistics at the optimum and the
// report files (framework/src/sweep/back_analysis.hpp; method: docs/calibrate.md).
#include "sweep/back_analysis.hpp"

#include <boost/math/distributions/students_t.hpp>
#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace stratum::sweep {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

/// Where the model is evaluated for one Jacobian: the values, and for each parameter the two
/// points of its difference quotient (indices into the batch; 0 is the base point).
struct Stencil {
  std::vector<std::vector<double>> batch;
  std::vector<std::array<std::size_t, 2>> pair;
  std::vector<std::array<double, 2>> dz;
};

class Problem {
public:
  Problem(const BackAnalysis& ba, const BatchRunner& run) : ba_(ba), run_(run) {
    for (const auto& f : ba.parameters()) {
      lo_.push_back(f.to_z(f.lower));
      hi_.push_back(f.to_z(f.upper));
    }
  }
  [[nodiscard]] std::size_t n() const { return lo_.size(); }
  /// p from z (the start values exactly at the start: exp(ln p) need not give p back).
  [[nodiscard]] std::vector<double> values(const double* z) const {
    std::vector<double> p(n());
    for (std::size_t j = 0; j < n(); ++j) {
      const auto& f = ba_.parameters()[j];
      p[j] = z[j] == f.to_z(f.start) ? f.start : f.from_z(std::clamp(z[j], lo_[j], hi_[j]));
    }
    return p;
  }
  std::vector<Evaluation> run(const std::vector<std::vector<double>>& batch) const {
    runs_ += static_cast<int>(batch.size());
    return run_(batch);
  }
  [[nodiscard]] int runs() const { return runs_; }

  /// The points of a difference Jacobian at z: central (z - h, z + h) or forward (z, z + h), one
  /// sided where a bound is nearer than h.
  [[nodiscard]] Stencil stencil(const double* z, double shrink = 1.0,
                                const std::vector<bool>& only = {}) const {
    Stencil s;
    s.batch.push_back(values(z));
    const double step = shrink * ba_.settings().step;
    for (std::size_t j = 0; j < n(); ++j) {
      if (!only.empty() && !only[j]) {
        s.pair.push_back({0, 0});
        s.dz.push_back({z[j], z[j]});
        continue;
      }
      const auto& f = ba_.parameters()[j];
      double h = f.log ? step : step * std::max(std::abs(z[j]), 1e-3 * (hi_[j] - lo_[j]));
      h = std::min(h, 0.25 * (hi_[j] - lo_[j]));
      double a = ba_.settings().central ? z[j] - h : z[j], b = z[j] + h;
      if (b > hi_[j]) b = z[j], a = z[j] - h;
      if (a < lo_[j]) a = z[j];
      std::array<std::size_t, 2> idx{};
      std::array<double, 2> at{a, b};
      for (int side = 0; side < 2; ++side) {
        if (at[static_cast<std::size_t>(side)] == z[j]) {
          idx[static_cast<std::size_t>(side)] = 0;
          continue;
        }
        std::vector<double> zz(z, z + n());
        zz[j] = at[static_cast<std::size_t>(side)];
        idx[static_cast<std::size_t>(side)] = s.batch.size();
        s.batch.push_back(values(zz.data()));
      }
      s.pair.push_back(idx);
      s.dz.push_back({a, b});
    }
    return s;
  }

  /// The residuals and their Jacobian at z; false when the base run does not give every point,
  /// or a column has no usable difference. A run that fails beside the point (a model that does
  /// not converge there) leaves a one-sided difference; where both sides fail, the column is
  /// tried again with a step four times shorter.
  bool jacobian(const double* z, Eigen::VectorXd& r, Eigen::MatrixXd& J, std::string* why = nullptr) const {
    const Stencil s = stencil(z);
    const std::vector<Evaluation> ev = run(s.batch);
    if (!ev[0].usable()) {
      if (why) *why = "the run at the point itself did not give every measured point";
      return false;
    }
    r = ba_.residuals(ev[0]);
    J.resize(r.size(), static_cast<Eigen::Index>(n()));
    std::vector<bool> retry(n(), false);
    const auto column = [&](const Stencil& st, const std::vector<Evaluation>& e, std::size_t j) {
      auto [ia, ib] = st.pair[j];
      auto [za, zb] = st.dz[j];
      if (!e[ia].usable()) ia = 0, za = z[j];
      if (!e[ib].usable()) ib = 0, zb = z[j];
      if (ia == ib) return false;
      J.col(static_cast<Eigen::Index>(j)) = (ba_.residuals(e[ib]) - ba_.residuals(e[ia])) / (zb - za);
      return true;
    };
    bool any = false;
    for (std::size_t j = 0; j < n(); ++j) any |= retry[j] = !column(s, ev, j);
    if (!any) return true;
    const Stencil s2 = stencil(z, 0.25, retry);
    const std::vector<Evaluation> ev2 = run(s2.batch);
    for (std::size_t j = 0; j < n(); ++j)
      if (retry[j] && !column(s2, ev2, j)) {
        if (why) {
          const Evaluation& bad = ev2[s2.pair[j][1]].usable() ? ev2[s2.pair[j][0]] : ev2[s2.pair[j][1]];
          *why = "the runs beside " + ba_.parameters()[j].target.name + " = " + format_number(values(z)[j]) +
                 " failed: " + (bad.reason.empty() ? "they do not give every measured point" : bad.reason);
        }
        return false;
      }
    return true;
  }

  const BackAnalysis& ba_;
  const BatchRunner& run_;
  std::vector<double> lo_, hi_;
  mutable int runs_ = 0;
};

class Cost final : public ceres::CostFunction {
public:
  explicit Cost(const Problem& p) : p_(p) {
    set_num_residuals(static_cast<int>(p.ba_.points()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(p.n()));
  }
  bool Evaluate(double const* const* z, double* residuals, double** jacobians) const override {
    const auto m = static_cast<Eigen::Index>(p_.ba_.points());
    for (std::size_t j = 0; j < p_.n(); ++j)
      if (!(z[0][j] >= p_.lo_[j] && z[0][j] <= p_.hi_[j])) return false; // outside the bounds
    Eigen::VectorXd r;
    if (jacobians && jacobians[0]) {
      Eigen::MatrixXd J;
      if (!p_.jacobian(z[0], r, J)) return false;
      // Ceres wants the Jacobian row-major.
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[0], m,
                                                                                         J.cols()) = J;
    } else {
      const std::vector<Evaluation> ev = p_.run({p_.values(z[0])});
      if (!ev[0].usable()) return false; // Ceres then shortens the step
      r = p_.ba_.residuals(ev[0]);
    }
    Eigen::Map<Eigen::VectorXd>(residuals, m) = r;
    return true;
  }

private:
  const Problem& p_;
};

class Progress final : public ceres::IterationCallback {
public:
  Progress(const FitProgress& f, const Problem& p) : f_(f), p_(p) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (f_) f_(s.iteration, s.cost, p_.runs());
    return ceres::SOLVER_CONTINUE;
  }

private:
  const FitProgress& f_;
  const Problem& p_;
};

std::string where_not_reached(const BackAnalysis& ba, const Evaluation& e) {
  std::size_t k = 0;
  for (const auto& d : ba.data())
    for (std::size_t i = 0; i < d.xs.size(); ++i, ++k)
      if (!std::isfinite(e.computed.at(k)))
        return "its computed curve " + d.y + "(" + d.x + ") does not reach " + d.x_column + " = " +
               format_number(d.xs[i]) + " of data '" + d.name + "' (" + d.file + ":" +
               std::to_string(d.lines[i]) + ")";
  return {};
}

/// The statistics at the optimum (FitResult's second half).
void statistics(const BackAnalysis& ba, const std::vector<double>& z, FitResult& r) {
  const auto& ps = ba.parameters();
  const auto n = static_cast<Eigen::Index>(ps.size());
  const Eigen::MatrixXd& J = r.jacobian;
  r.dof = static_cast<int>(r.residuals.size()) - static_cast<int>(n);
  r.sigma = std::sqrt(r.residuals.squaredNorm() / r.dof);
  r.t95 = boost::math::quantile(boost::math::complement(boost::math::students_t(r.dof), 0.025));
  // Columns scaled to relative changes: d r / d ln p for every parameter.
  Eigen::VectorXd D(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const auto& f = ps[static_cast<std::size_t>(j)];
    D[j] = f.log ? 1.0 : std::max(std::abs(z[static_cast<std::size_t>(j)]), 1e-12 * (f.upper - f.lower));
  }
  const Eigen::MatrixXd Js = J * D.asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Js, Eigen::ComputeThinV);
  r.singular = svd.singularValues();
  r.directions = svd.matrixV();
  const double smax = r.singular.size() ? r.singular[0] : 0.0;
  // C_s = sigma^2 V S^-2 V^T over the directions the data see; a direction they do not see (a
  // singular value at rounding level) leaves every parameter in it without an interval.
  Eigen::MatrixXd Cs = Eigen::MatrixXd::Zero(n, n);
  std::vector<bool> blind(static_cast<std::size_t>(n), false);
  r.combination_se.clear();
  for (Eigen::Index k = 0; k < r.singular.size(); ++k) {
    const double s = r.singular[k];
    const bool seen = s > 1e-12 * smax && s > 0.0;
    const double se = seen ? r.sigma / s : infinity;
    r.combination_se.push_back(se);
    if (seen) Cs += (r.sigma * r.sigma / (s * s)) * r.directions.col(k) * r.directions.col(k).transpose();
    if (!(se <= ba.settings().determined))
      for (Eigen::Index j = 0; j < n; ++j)
        if (std::abs(r.directions(j, k)) > 0.1) blind[static_cast<std::size_t>(j)] = true;
  }
  r.se_z.assign(ps.size(), infinity);
  r.low95.assign(ps.size(), -infinity);
  r.high95.assign(ps.size(), infinity);
  r.determined.assign(ps.size(), false);
  r.at_bound.assign(ps.size(), false);
  r.correlation = Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t j = 0; j < ps.size(); ++j) {
    const auto& f = ps[j];
    // A trial point outside the box is a failed step, so the optimizer nears a bound that stops
    // it without landing on it: within 1e-3 of the range (in z) counts as on the bound.
    const double zlo = f.to_z(f.lower), zhi = f.to_z(f.upper), tol = 1e-3 * (zhi - zlo);
    r.at_bound[j] = z[j] <= zlo + tol || z[j] >= zhi - tol;
    if (blind[j]) continue;
    const auto J_ = static_cast<Eigen::Index>(j);
    r.se_z[j] = D[J_] * std::sqrt(Cs(J_, J_));
    r.determined[j] = true;
    r.low95[j] = f.from_z(z[j] - r.t95 * r.se_z[j]);
    r.high95[j] = f.from_z(z[j] + r.t95 * r.se_z[j]);
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      if (r.determined[static_cast<std::size_t>(i)] && r.determined[static_cast<std::size_t>(j)])
        r.correlation(i, j) = Cs(i, j) / std::sqrt(Cs(i, i) * Cs(j, j));

  // Findings in words.
  for (Eigen::Index k = 0; k < r.singular.size(); ++k) {
    if (r.combination_se[static_cast<std::size_t>(k)] <= ba.settings().determined) continue;
    std::string combo, names;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double v = r.directions(j, k);
      if (std::abs(v) <= 0.1) continue;
      char b[32];
      std::snprintf(b, sizeof b, "%+.3f", v);
      combo +=
          std::string(combo.empty() ? "" : " ") + b + " ln " + ps[static_cast<std::size_t>(j)].target.name;
      names += (names.empty() ? "" : ", ") + ps[static_cast<std::size_t>(j)].target.name;
    }
    const double se = r.combination_se[static_cast<std::size_t>(k)];
    r.notes.push_back("not determined: the data do not fix the combination " + combo + " (singular value " +
                      format_number(r.singular[k] / smax) + " of the largest; its standard error " +
                      (std::isfinite(se) ? format_number(se) : std::string("infinite")) +
                      " exceeds determined = " + format_number(ba.settings().determined) + "). " + names +
                      " have no interval: fix all but one of them, or add measurements that separate them.");
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j)
      if (std::abs(r.correlation(i, j)) > 0.95)
        r.notes.push_back(ps[static_cast<std::size_t>(i)].target.name + " and " +
                          ps[static_cast<std::size_t>(j)].target.name + " are strongly correlated (" +
                          format_number(r.correlation(i, j)) +
                          "): the data fix a combination of them better than each one");
  for (std::size_t j = 0; j < ps.size(); ++j)
    if (r.at_bound[j])
      r.notes.push_back(ps[j].target.name + " ends on a bound (" + format_number(r.best[j]) +
                        "): the least-squares minimum may lie beyond it; its interval assumes an interior "
                        "minimum and is not valid");
}

std::string cell(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return format_number(v);
}

} // namespace

FitResult calibrate(const BackAnalysis& ba, const BatchRunner& run, const FitProgress& progress) {
  const Problem problem(ba, run);
  const std::size_t n = problem.n();
  FitResult r;
  std::vector<double> z(n);
  for (std::size_t j = 0; j < n; ++j) {
    const auto& f = ba.parameters()[j];
    r.start.push_back(f.start);
    z[j] = f.to_z(f.start);
  }
  // The start point first: a start whose run does not give every point is the user's to change.
  const Evaluation e0 = problem.run({r.start}).at(0);
  if (!e0.usable())
    throw Error(ba.path() + ": the run at the start values does not give every measured point: " +
                (e0.status == "failed" ? "it failed (" + e0.reason + ")" : where_not_reached(ba, e0)) +
                "; start elsewhere, or leave out the points it cannot reach");
  r.start_cost = 0.5 * ba.residuals(e0).squaredNorm();

  // Ceres also reports a failure through glog (a timestamped line on stderr); its summary is
  // what we report, in one line, so glog's messages below FATAL are off (glog's own setting).
  FLAGS_minloglevel = google::GLOG_FATAL;
  Cost cost(problem);
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem cp(po);
  // The bounds are not given to Ceres: with bounds its trust-region steps end in a line search
  // that asks for a Jacobian (2n runs) at every trial point. A step out of the box is an
  // evaluation that fails instead (Cost::Evaluate), which shrinks the trust region as any
  // rejected step does.
  cp.AddResidualBlock(&cost, nullptr, z.data());
  ceres::Solver::Options o;
  o.minimizer_type = ceres::TRUST_REGION;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = ceres::DENSE_QR;
  // A first step of about half the Gauss-Newton step (the Jacobian is scaled to unit columns): a
  // model run is expensive, and Ceres' default (1e4, a full step) overshoots on curves convex in
  // the parameter (a settlement ~ 1/E), where every shrinking retry costs a run.
  o.initial_trust_region_radius = 1.0;
  o.max_num_iterations = ba.settings().max_iterations;
  o.function_tolerance = ba.settings().tolerance;
  o.parameter_tolerance = ba.settings().tolerance;
  o.gradient_tolerance = 1e-3 * ba.settings().tolerance;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  o.num_threads = 1;
  Progress cb(progress, problem);
  o.callbacks.push_back(&cb);
  ceres::Solver::Summary s;
  ceres::Solve(o, &cp, &s);
  r.iterations = static_cast<int>(s.iterations.size()) - 1;
  r.termination = s.message;
  r.converged = s.termination_type == ceres::CONVERGENCE;
  if (!s.IsSolutionUsable()) throw FitFailed(ba.path() + ": the optimizer failed: " + s.message);
  r.best = problem.values(z.data());
  // The statistics need the residuals and the Jacobian at the best point.
  std::string why;
  if (!problem.jacobian(z.data(), r.residuals, r.jacobian, &why))
    throw FitFailed(ba.path() + ": no Jacobian at the best point for the intervals: " + why);
  r.best_eval = problem.run({r.best}).at(0);
  r.cost = 0.5 * r.residuals.squaredNorm();
  if (!r.converged)
    r.notes.push_back("the optimizer did not converge (" + s.message + "): the values are its last point");
  statistics(ba, z, r);
  r.runs = problem.runs();
  return r;
}

std::map<std::string, std::string> report_files(const BackAnalysis& ba, const FitResult& r) {
  const auto& ps = ba.parameters();
  std::map<std::string, std::string> files;
  std::ostringstream p;
  p << "name,start,lower,upper,log,value,standard_error,relative_standard_error,ci95_low,ci95_high,"
       "determined,"
       "at_bound\n";
  for (std::size_t j = 0; j < ps.size(); ++j) {
    const auto& f = ps[j];
    // The standard error of p from that of z (delta method: dp = p dz for ln p).
    const double se = f.log ? r.best[j] * r.se_z[j] : r.se_z[j];
    const double rel = f.log ? r.se_z[j] : r.se_z[j] / std::abs(r.best[j]);
    p << f.target.name << "," << cell(f.start) << "," << cell(f.lower) << "," << cell(f.upper) << ","
      << (f.log ? "true" : "false") << "," << cell(r.best[j]) << "," << cell(se) << "," << cell(rel) << ","
      << cell(r.low95[j]) << "," << cell(r.high95[j]) << "," << (r.determined[j] ? "true" : "false") << ","
      << (r.at_bound[j] ? "true" : "false") << "\n";
  }
  files["parameters.csv"] = p.str();

  std::ostringstream c;
  c << "parameter";
  for (const auto& f : ps) c << "," << f.target.name;
  c << "\n";
  for (std::size_t i = 0; i < ps.size(); ++i) {
    c << ps[i].target.name;
    for (std::size_t j = 0; j < ps.size(); ++j)
      c << "," << cell(r.correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
    c << "\n";
  }
  files["correlation.csv"] = c.str();

  std::ostringstream sv;
  sv << "index,singular_value,relative,standard_error";
  for (const auto& f : ps) sv << ",ln_" << f.target.name;
  sv << "\n";
  for (Eigen::Index k = 0; k < r.singular.size(); ++k) {
    sv << k << "," << cell(r.singular[k]) << "," << cell(r.singular[k] / r.singular[0]) << ","
       << cell(r.combination_se[static_cast<std::size_t>(k)]);
    for (Eigen::Index j = 0; j < r.directions.rows(); ++j) sv << "," << cell(r.directions(j, k));
    sv << "\n";
  }
  files["singular_values.csv"] = sv.str();

  std::ostringstream jr, rs;
  jr << "data,line,x";
  for (const auto& f : ps) jr << ",d_r/d_" << (f.log ? "ln_" : "") << f.target.name;
  jr << "\n";
  rs << "data,line,x,measured,computed,weight,residual\n";
  Eigen::Index k = 0;
  for (const auto& d : ba.data())
    for (std::size_t i = 0; i < d.xs.size(); ++i, ++k) {
      jr << d.name << "," << d.lines[i] << "," << cell(d.xs[i]);
      for (Eigen::Index j = 0; j < r.jacobian.cols(); ++j) jr << "," << cell(r.jacobian(k, j));
      jr << "\n";
      rs << d.name << "," << d.lines[i] << "," << cell(d.xs[i]) << "," << cell(d.ys[i]) << ","
         << cell(r.best_eval.computed.at(static_cast<std::size_t>(k))) << "," << cell(d.weight) << ","
         << cell(r.residuals[k]) << "\n";
    }
  files["jacobian.csv"] = jr.str();
  files["residuals.csv"] = rs.str();

  std::ostringstream md;
  md << "# Calibration of " << ba.base_path() << "\n\n"
     << "Calibration file: " << ba.path() << " (hash " << ba.hash() << ").\n\n"
     << "Optimizer: Ceres Levenberg-Marquardt, " << r.iterations << " iterations, " << r.runs
     << " model runs asked for; " << r.termination << "\n\n"
     << "Cost 0.5 |r|^2: " << cell(r.start_cost) << " at the start, " << cell(r.cost)
     << " at the best point; " << ba.points() << " measured points, " << ps.size() << " parameters, " << r.dof
     << " degrees of freedom; the residuals' standard deviation sigma = " << cell(r.sigma)
     << " (weighted units); Student's t(0.975, " << r.dof << ") = " << cell(r.t95) << ".\n\n"
     << "| parameter | start | best | standard error | 95 % interval | note |\n|---|---|---|---|---|---|\n";
  for (std::size_t j = 0; j < ps.size(); ++j) {
    const auto& f = ps[j];
    md << "| " << f.target.name << (f.log ? " (log)" : "") << " | " << cell(f.start) << " | "
       << cell(r.best[j]) << " | "
       << (r.determined[j] ? cell(f.log ? r.best[j] * r.se_z[j] : r.se_z[j]) : "-") << " | "
       << (r.determined[j] ? cell(r.low95[j]) + " to " + cell(r.high95[j]) : "not determined") << " | "
       << (r.at_bound[j] ? "on a bound" : "") << " |\n";
  }
  md << "\nSingular values of the Jacobian in relative parameter changes (d r / d ln p), largest first: ";
  for (Eigen::Index k = 0; k < r.singular.size(); ++k) md << (k ? ", " : "") << cell(r.singular[k]);
  md << ".\n\n";
  if (r.notes.empty())
    md << "Every parameter is determined by the data (docs/calibrate.md, \"Reading the report\").\n";
  for (const auto& note : r.notes) md << "- " << note << "\n";
  md << "\nResiduals per data set (weighted, computed - measured):\n\n";
  k = 0;
  for (const auto& d : ba.data()) {
    double ss = 0, mx = 0;
    for (std::size_t i = 0; i < d.xs.size(); ++i, ++k) {
      ss += r.residuals[k] * r.residuals[k];
      mx = std::max(mx, std::abs(r.residuals[k]));
    }
    md << "- " << d.name << " (" << d.file << ", " << d.xs.size() << " points): RMS "
       << cell(std::sqrt(ss / static_cast<double>(d.xs.size()))) << ", largest " << cell(mx) << "\n";
  }
  files["report.md"] = md.str();
  return files;
}

} // namespace stratum::sweep
