// The calibration toolkit (stratum/calibration_toolkit.hpp): the numerics every fit shares: a
// least-squares line, Kondner's transformed linear start, a small Levenberg-Marquardt solver and
// the hyperbolic fit of curves at several confining levels.
#include "stratum/calibration_toolkit.hpp"

#include "stratum/error.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace stratum::calibration {

// ================================================================ small numerics

/// Least-squares line y = a + b x. Returns false if the x values do not differ.
bool fit_line(const std::vector<double>& x, const std::vector<double>& y, double& a, double& b) {
  const auto n = static_cast<double>(x.size());
  if (x.size() < 2) return false;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= n, my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  const double xscale = std::max(std::abs(mx), 1e-300);
  if (!(sxx > 1e-24 * xscale * xscale * n)) return false;
  b = sxy / sxx;
  a = my - b * mx;
  return true;
}

/// Levenberg-Marquardt with Marquardt's diagonal scaling and a central-difference
/// Jacobian. `f` returns false where the parameters are outside the model's domain;
/// such trial steps are rejected like steps that raise the cost. `typical` gives the
/// magnitude of each parameter (for the difference steps). Converged when the step is
/// below 1e-11 of the parameters, or the cost below `cost_floor`.
LmResult levenberg_marquardt(const ResidualFn& f, Eigen::VectorXd p, const Eigen::VectorXd& typical,
                             double cost_floor, int max_iterations) {
  LmResult out;
  Eigen::VectorXd r;
  if (!f(p, r) || !r.allFinite()) {
    out.p = p;
    return out;
  }
  const auto np = p.size();
  double cost = 0.5 * r.squaredNorm();
  double lambda = 1e-3;
  Eigen::MatrixXd J(r.size(), np);
  Eigen::VectorXd rp, rm, r_new;
  for (int it = 1; it <= max_iterations; ++it) {
    out.iterations = it;
    if (cost <= cost_floor) {
      out.converged = true;
      break;
    }
    for (Eigen::Index j = 0; j < np; ++j) {
      const double h = 1e-6 * std::max(std::abs(p[j]), typical[j]);
      Eigen::VectorXd pp = p, pm = p;
      pp[j] += h;
      pm[j] -= h;
      const bool okp = f(pp, rp) && rp.allFinite(), okm = f(pm, rm) && rm.allFinite();
      if (okp && okm)
        J.col(j) = (rp - rm) / (2 * h);
      else if (okp)
        J.col(j) = (rp - r) / h;
      else if (okm)
        J.col(j) = (r - rm) / h;
      else
        return out;
    }
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    Eigen::VectorXd D = A.diagonal();
    for (Eigen::Index j = 0; j < np; ++j) D[j] = std::max(D[j], 1e-30);
    bool accepted = false;
    Eigen::VectorXd dp;
    while (lambda < 1e16) {
      Eigen::MatrixXd M = A;
      M.diagonal() += lambda * D;
      dp = M.ldlt().solve(-g);
      const Eigen::VectorXd trial = p + dp;
      if (dp.allFinite() && f(trial, r_new) && r_new.allFinite()) {
        const double c_new = 0.5 * r_new.squaredNorm();
        if (c_new <= cost) {
          p = trial;
          r = r_new;
          cost = c_new;
          lambda = std::max(lambda / 3, 1e-12);
          accepted = true;
          break;
        }
      }
      lambda *= 4;
    }
    if (!accepted) { // no step lowers the cost: a minimum if the scaled gradient vanishes
      double gs = 0;
      for (Eigen::Index j = 0; j < np; ++j) gs = std::max(gs, std::abs(g[j]) / std::sqrt(D[j]));
      out.converged = gs <= 1e-8 * std::sqrt(2 * cost + 1e-300);
      break;
    }
    bool small = true;
    for (Eigen::Index j = 0; j < np; ++j)
      if (std::abs(dp[j]) > 1e-11 * std::max(std::abs(p[j]), typical[j])) small = false;
    if (small) {
      out.converged = true;
      break;
    }
  }
  out.p = p;
  out.cost = cost;
  return out;
}

CurveResidual residual_of(const std::string& what, double level, const std::vector<double>& diff,
                          const std::string& unit) {
  CurveResidual c{what, level, static_cast<int>(diff.size()), 0, 0, unit};
  for (double d : diff) {
    c.rms += d * d;
    c.max = std::max(c.max, std::abs(d));
  }
  if (!diff.empty()) c.rms = std::sqrt(c.rms / static_cast<double>(diff.size()));
  return c;
}

/// Index of the peak of y: its (first) largest value. Before it, y may dip below its running
/// maximum by at most 5 % of the peak (scatter); a deeper dip means more than one loading
/// branch or peak, and throws.
std::size_t peak_index(const std::vector<double>& y, const std::vector<int>& lines, const std::string& file,
                       const std::string& name, const std::string& level) {
  const std::size_t k = static_cast<std::size_t>(std::max_element(y.begin(), y.end()) - y.begin());
  std::size_t top = 0;
  for (std::size_t j = 1; j < k; ++j) {
    if (y[j] < y[top] - 0.05 * y[k])
      throw Error({file, lines[j], 0}, name + " = " + number(y[j]) + " falls below the earlier " +
                                           number(y[top]) + " (line " + std::to_string(lines[top]) +
                                           ") by more than 5 % of the peak " + number(y[k]) + " of line " +
                                           std::to_string(lines[k]) + " (" + level + "); allowed: " + name +
                                           " rising to a single peak (dips up to 5 % of it), then optionally "
                                           "softening");
    if (y[j] > y[top]) top = j;
  }
  return k;
}

Kondner kondner(const std::vector<double>& x, const std::vector<double>& y, std::size_t last) {
  std::vector<double> xs, ts;
  for (std::size_t i = 0; i <= last && i < x.size(); ++i)
    if (x[i] > 0 && y[i] > 0) {
      xs.push_back(x[i]);
      ts.push_back(x[i] / y[i]);
    }
  Kondner k;
  k.points = static_cast<int>(xs.size());
  if (!fit_line(xs, ts, k.a, k.b)) k.a = k.b = std::nan("");
  return k;
}

std::size_t distinct_levels(const std::vector<double>& s) {
  return std::set<double>(s.begin(), s.end()).size();
}

std::vector<std::size_t> direct_shear_peaks(const std::vector<ShearCurve>& curves, const std::string& source,
                                            const std::string& what) {
  if (curves.empty()) throw Error(source + ": no direct-shear curves");
  std::vector<double> levels;
  for (const auto& c : curves) levels.push_back(c.sigma_n);
  if (distinct_levels(levels) < 2)
    throw Error(source + ": all curves are at sigma_n = " + number(levels[0]) + " kPa; " + what +
                " need curves at two or more normal stresses");
  std::vector<std::size_t> peaks;
  for (const auto& c : curves)
    peaks.push_back(peak_index(c.tau, c.lines, c.file, "tau_kPa", level_text("sigma_n", c.sigma_n)));
  return peaks;
}

// ================================================================ hyperbolic fit (shared)

namespace {

double strength(const HyperbolicLaw& law, double c, double phi, double s) {
  if (law.triaxial) return 2 * (c * std::cos(phi) + s * std::sin(phi)) / (1 - std::sin(phi));
  return c + s * std::tan(phi);
}

/// The same for the strengths: y_f = A + B s -> (c, phi). False if B <= 0.
bool strength_params(const HyperbolicLaw& law, double A, double B, double& c, double& phi) {
  if (!(B > 0)) return false;
  if (law.triaxial) {
    const double sp = B / (2 + B);
    phi = std::asin(sp);
    c = A * (1 - sp) / (2 * std::cos(phi));
  } else {
    phi = std::atan(B);
    c = A;
  }
  return true;
}

} // namespace

HyperbolicFit fit_hyperbolic(const HyperbolicLaw& law, const std::vector<HyperbolicCurve>& curves,
                             const std::string& source, std::vector<CurveResidual>& residuals) {
  HyperbolicFit res;
  // --- start: Kondner per curve, then straight lines across curves
  std::vector<double> logs, logE, ss, yf, ratio;
  for (const auto& c : curves) {
    logs.push_back(std::log(c.s / p_a));
    logE.push_back(std::log(c.E / law.unit));
    ss.push_back(c.s);
    yf.push_back(c.y_f);
    ratio.push_back(c.y_f / c.y_ult);
  }
  double lnK = 0, n0 = 0, A = 0, B = 0;
  if (!fit_line(logs, logE, lnK, n0) || !fit_line(ss, yf, A, B))
    throw Error(source + ": the curves need two or more different " + law.s_name);
  res.K0 = std::exp(lnK);
  res.n0 = n0;
  for (double r : ratio) res.R_f0 += r / static_cast<double>(ratio.size());
  if (!strength_params(law, A, B, res.c0, res.phi0))
    throw Error(source + ": the peak " + law.y_name + " does not grow with " + law.s_name + " (slope " +
                number(B) + " of the peaks against " + law.s_name + "), so " + law.phi_name +
                " would be <= 0; allowed: curves whose strength increases with " + law.s_name);

  // --- refinement on all points and the strengths at once
  double scale_y = 0, sum_y2 = 0;
  for (const auto& c : curves) {
    scale_y = std::max(scale_y, c.y_f);
    for (double y : c.y) sum_y2 += y * y;
  }
  const ResidualFn f = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r) {
    const double K = p[0], n = p[1], R_f = p[2], c = p[3], phi = p[4];
    if (!(K > 0) || !(R_f > 0) || !(phi > 0) || !(phi < 0.5 * std::numbers::pi - 1e-6)) return false;
    Eigen::Index m = 0;
    for (const auto& cv : curves) m += static_cast<Eigen::Index>(cv.x.size()) + 1;
    r.resize(m);
    Eigen::Index k = 0;
    for (const auto& cv : curves) {
      const double Ei = K * law.unit * std::pow(cv.s / p_a, n);
      const double yfm = strength(law, c, phi, cv.s);
      if (!(yfm > 0)) return false;
      for (std::size_t j = 0; j < cv.x.size(); ++j)
        r[k++] = cv.x[j] / (1 / Ei + R_f * cv.x[j] / yfm) - cv.y[j];
      r[k++] = std::sqrt(static_cast<double>(cv.x.size())) * (yfm - cv.y_f);
    }
    return true;
  };
  Eigen::VectorXd p0(5), typical(5);
  p0 << res.K0, res.n0, std::min(res.R_f0, 1.0), res.c0, res.phi0;
  typical << res.K0, 0.1, 0.1, 0.01 * scale_y, 0.01;
  const LmResult lm = levenberg_marquardt(f, p0, typical, 1e-28 * sum_y2);
  res.iterations = lm.iterations;
  if (!lm.converged)
    throw Error(source + ": the nonlinear refinement of " + law.K_name + ", n, R_f, " + law.c_name + ", " +
                law.phi_name + " did not converge (" + std::to_string(lm.iterations) +
                " Levenberg-Marquardt iterations from the Kondner start " + law.K_name + " = " +
                number(res.K0) + ", n = " + number(res.n0) + ", R_f = " + number(res.R_f0) +
                "); the curves are not hyperbolic enough");
  res.K = lm.p[0], res.n = lm.p[1], res.R_f = lm.p[2], res.c = lm.p[3], res.phi = lm.p[4];

  // --- physical limits
  if (res.R_f > 1 + 1e-9)
    throw Error(
        source + ": R_f = " + number(res.R_f) + " > 1: the peaks of " + law.y_name +
        " lie above the hyperbolas' asymptotes; allowed: 0 < R_f <= 1 (the curves are not hyperbolic)");
  if (res.n < 0)
    throw Error(source + ": n = " + number(res.n) + " < 0: the initial stiffness falls as " + law.s_name +
                " grows; allowed: n >= 0 (if the soil changes between stress levels, fit each range apart: "
                "stratum fit --range MIN:MAX)");
  if (res.c < -1e-9 * scale_y)
    throw Error(source + ": " + law.c_name + " = " + number(res.c) +
                " kPa < 0 from the peak strengths; allowed: " + law.c_name +
                " >= 0 (check the peaks, or fit a narrower " + law.s_name + " range)");
  res.c = std::max(res.c, 0.0);

  // --- residuals per curve
  for (const auto& cv : curves) {
    const double Ei = res.K * law.unit * std::pow(cv.s / p_a, res.n);
    const double yfm = strength(law, res.c, res.phi, cv.s);
    std::vector<double> d;
    for (std::size_t j = 0; j < cv.x.size(); ++j)
      d.push_back(cv.x[j] / (1 / Ei + res.R_f * cv.x[j] / yfm) - cv.y[j]);
    residuals.push_back(residual_of(law.y_name, cv.s, d, law.unit_y));
    residuals.push_back(residual_of(law.y_name + "_f", cv.s, {yfm - cv.y_f}, law.unit_y));
  }
  return res;
}

/// Builds a HyperbolicCurve from the points up to the peak; checks the Kondner transform.
HyperbolicCurve hyperbolic_curve(const HyperbolicLaw& law, double s, const std::vector<double>& x,
                                 const std::vector<double>& y, std::size_t peak, const std::string& file,
                                 int first_line, const std::string& level) {
  HyperbolicCurve c;
  c.s = s;
  c.file = file;
  c.first_line = first_line;
  c.y_f = y[peak];
  for (std::size_t i = 0; i <= peak; ++i)
    if (x[i] > 0) {
      c.x.push_back(x[i]);
      c.y.push_back(y[i]);
    }
  const Kondner k = kondner(x, y, peak);
  const std::string where = file + ":" + std::to_string(first_line) + ": curve at " + level;
  if (k.points < 3)
    throw Error(where + ": " + std::to_string(k.points) + " points with " + law.x_name + " > 0 and " +
                law.y_name + " > 0 up to the peak; allowed: at least 3");
  if (!(k.a > 0) || !(k.b > 0))
    throw Error(where + ": not hyperbolic: Kondner's transform " + law.x_name + "/" + law.y_name +
                " = a + b " + law.x_name + " gives a = " + number(k.a) + ", b = " + number(k.b) +
                "; allowed: curves that flatten toward an asymptote (a > 0, b > 0)");
  c.E = 1 / k.a;
  c.y_ult = 1 / k.b;
  return c;
}

std::string level_text(const std::string& name, double v) { return name + " = " + number(v) + " kPa"; }

std::string count(std::size_t n, const std::string& what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

} // namespace stratum::calibration
