// Calibration from laboratory curves: CSV reading, the transformed linear (Kondner)
// starts, a small Levenberg-Marquardt solver and the TOML output. See
// stratum/calibration.hpp and docs/calibration.md.
#include "stratum/calibration.hpp"

#include "stratum/error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <set>
#include <sstream>

namespace stratum::calibration {

namespace {

namespace fs = std::filesystem;
constexpr double deg = std::numbers::pi / 180.0;

/// A number for messages: up to 6 significant digits.
std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// ================================================================ CSV

struct Column {
  std::string name;
  bool required;
};

struct CsvRow {
  int line = 0;
  std::vector<double> value; ///< per declared column; NaN if the column is absent
  std::vector<int> col;      ///< 1-based character column of each field (0 if absent)
};

struct CsvTable {
  std::vector<bool> present; ///< per declared column
  std::vector<CsvRow> rows;
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::string column_list(const std::vector<Column>& cols, bool required) {
  std::string s;
  for (const auto& c : cols)
    if (c.required == required) s += (s.empty() ? "" : ", ") + c.name;
  return s.empty() ? "none" : s;
}

/// Reads a comma-separated table with a header row of known column names.
CsvTable read_csv(const std::string& path, const std::vector<Column>& cols) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path + "'");
  const std::string allowed =
      "required " + column_list(cols, true) + "; optional " + column_list(cols, false);
  CsvTable t;
  t.present.assign(cols.size(), false);
  std::vector<int> field_of; // header field -> declared column
  bool have_header = false;
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    if (line == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3); // a UTF-8 byte-order mark
    const std::string text = trim(raw);
    if (text.empty() || text[0] == '#') continue;
    // split, remembering where every field starts
    std::vector<std::string> fields;
    std::vector<int> starts;
    std::size_t pos = 0;
    while (true) {
      const auto comma = raw.find(',', pos);
      const std::string f = raw.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
      const auto lead = f.find_first_not_of(" \t");
      starts.push_back(static_cast<int>(pos + (lead == std::string::npos ? 0 : lead)) + 1);
      fields.push_back(trim(f));
      if (comma == std::string::npos) break;
      pos = comma + 1;
    }
    if (!have_header) {
      have_header = true;
      for (std::size_t i = 0; i < fields.size(); ++i) {
        const auto it =
            std::find_if(cols.begin(), cols.end(), [&](const Column& c) { return c.name == fields[i]; });
        if (it == cols.end() && fields[i].find(';') != std::string::npos)
          throw Error({path, line, starts[i]}, "the header '" + text +
                                                   "' is not comma-separated; allowed: columns separated by "
                                                   "commas, " +
                                                   allowed);
        if (it == cols.end())
          throw Error({path, line, starts[i]},
                      "unknown column '" + fields[i] + "' in the header; allowed: " + allowed +
                          " (stresses in kPa, strains as fractions, displacements in m)");
        const int k = static_cast<int>(it - cols.begin());
        if (t.present[k]) throw Error({path, line, starts[i]}, "column '" + fields[i] + "' appears twice");
        t.present[k] = true;
        field_of.push_back(k);
      }
      for (std::size_t k = 0; k < cols.size(); ++k)
        if (cols[k].required && !t.present[k])
          throw Error({path, line, 1}, "the header has no column '" + cols[k].name + "'; " + allowed);
      continue;
    }
    if (fields.size() != field_of.size())
      throw Error({path, line, 1}, std::to_string(fields.size()) + " fields, the header has " +
                                       std::to_string(field_of.size()) +
                                       " (allowed: one number per header column, comma-separated)");
    CsvRow row;
    row.line = line;
    row.value.assign(cols.size(), std::nan(""));
    row.col.assign(cols.size(), 0);
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string& f = fields[i];
      const int k = field_of[i];
      double v = 0;
      const char* first = f.data() + (f.size() > 1 && f[0] == '+' ? 1 : 0);
      const auto [end, ec] = std::from_chars(first, f.data() + f.size(), v);
      if (f.empty() || ec != std::errc() || end != f.data() + f.size() || !std::isfinite(v))
        throw Error({path, line, starts[i]},
                    "'" + f + "' in column " + cols[k].name +
                        " is not a finite number (allowed: decimal numbers such as 0.012 or 1.2e-2)");
      row.value[k] = v;
      row.col[k] = starts[i];
    }
    t.rows.push_back(std::move(row));
  }
  if (!have_header) throw Error({path, line, 0}, "empty file: no header row; " + allowed);
  if (t.rows.empty()) throw Error({path, line, 0}, "no data rows after the header");
  return t;
}

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

using ResidualFn = std::function<bool(const Eigen::VectorXd&, Eigen::VectorXd&)>;

struct LmResult {
  Eigen::VectorXd p;
  int iterations = 0;
  bool converged = false;
  double cost = 0;
};

/// Levenberg-Marquardt with Marquardt's diagonal scaling and a central-difference
/// Jacobian. `f` returns false where the parameters are outside the model's domain;
/// such trial steps are rejected like steps that raise the cost. `typical` gives the
/// magnitude of each parameter (for the difference steps). Converged when the step is
/// below 1e-11 of the parameters, or the cost below `cost_floor`.
LmResult levenberg_marquardt(const ResidualFn& f, Eigen::VectorXd p, const Eigen::VectorXd& typical,
                             double cost_floor, int max_iterations = 500) {
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
      throw Error({file, lines[j], 0}, name + " = " + fmt(y[j]) + " falls below the earlier " + fmt(y[top]) +
                                           " (line " + std::to_string(lines[top]) +
                                           ") by more than 5 % of the peak " + fmt(y[k]) + " of line " +
                                           std::to_string(lines[k]) + " (" + level + "); allowed: " + name +
                                           " rising to a single peak (dips up to 5 % of it), then optionally "
                                           "softening");
    if (y[j] > y[top]) top = j;
  }
  return k;
}

/// Kondner's transform x/y = a + b x over the points 0..last with x > 0 and y > 0.
struct Kondner {
  double a = 0, b = 0;
  int points = 0;
};
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

// ================================================================ hyperbolic fit (shared)

/// One curve prepared for a hyperbolic fit: the points up to the peak.
struct HypCurve {
  double s = 0;            ///< sigma_3 or sigma_n
  std::vector<double> x;   ///< strain or displacement, > 0
  std::vector<double> y;   ///< stress
  double y_f = 0;          ///< peak stress (failure)
  double E = 0, y_ult = 0; ///< Kondner estimates
  std::string file;
  int first_line = 0;
};

/// The hyperbola y = x / (1/E_i + R_f x / y_f) with E_i = K u (s/p_a)^n, fitted to curves
/// at several s. Duncan-Chang: u = p_a, y_f = 2(c cos phi + s sin phi)/(1 - sin phi).
/// Clough-Duncan interface: u = gamma_w, y_f = c + s tan(phi).
struct HypLaw {
  bool triaxial = true;
  double unit = p_a;
  std::string y_name, s_name, x_name, c_name, phi_name, K_name, unit_y;
};

struct HypResult {
  double K = 0, n = 0, R_f = 0, c = 0, phi = 0; // phi in radians
  double K0 = 0, n0 = 0, R_f0 = 0, c0 = 0, phi0 = 0;
  int iterations = 0;
};

double strength(const HypLaw& law, double c, double phi, double s) {
  if (law.triaxial) return 2 * (c * std::cos(phi) + s * std::sin(phi)) / (1 - std::sin(phi));
  return c + s * std::tan(phi);
}

/// The same for the strengths: y_f = A + B s -> (c, phi). False if B <= 0.
bool strength_params(const HypLaw& law, double A, double B, double& c, double& phi) {
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

HypResult fit_hyperbolic(const HypLaw& law, const std::vector<HypCurve>& curves, const std::string& source,
                         std::vector<CurveResidual>& residuals) {
  HypResult res;
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
                fmt(B) + " of the peaks against " + law.s_name + "), so " + law.phi_name +
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
                " Levenberg-Marquardt iterations from the Kondner start " + law.K_name + " = " + fmt(res.K0) +
                ", n = " + fmt(res.n0) + ", R_f = " + fmt(res.R_f0) +
                "); the curves are not hyperbolic enough");
  res.K = lm.p[0], res.n = lm.p[1], res.R_f = lm.p[2], res.c = lm.p[3], res.phi = lm.p[4];

  // --- physical limits
  if (res.R_f > 1 + 1e-9)
    throw Error(
        source + ": R_f = " + fmt(res.R_f) + " > 1: the peaks of " + law.y_name +
        " lie above the hyperbolas' asymptotes; allowed: 0 < R_f <= 1 (the curves are not hyperbolic)");
  if (res.n < 0)
    throw Error(source + ": n = " + fmt(res.n) + " < 0: the initial stiffness falls as " + law.s_name +
                " grows; allowed: n >= 0 (if the soil changes between stress levels, fit each range apart: "
                "stratum fit --range MIN:MAX)");
  if (res.c < -1e-9 * scale_y)
    throw Error(source + ": " + law.c_name + " = " + fmt(res.c) +
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

/// Builds a HypCurve from the points up to the peak; checks the Kondner transform.
HypCurve hyp_curve(const HypLaw& law, double s, const std::vector<double>& x, const std::vector<double>& y,
                   std::size_t peak, const std::string& file, int first_line, const std::string& level) {
  HypCurve c;
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
                " = a + b " + law.x_name + " gives a = " + fmt(k.a) + ", b = " + fmt(k.b) +
                "; allowed: curves that flatten toward an asymptote (a > 0, b > 0)");
  c.E = 1 / k.a;
  c.y_ult = 1 / k.b;
  return c;
}

std::string level_text(const std::string& name, double v) { return name + " = " + fmt(v) + " kPa"; }

std::string count(std::size_t n, const std::string& what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

} // namespace

// ================================================================ reading

std::vector<TriaxialCurve> read_triaxial_csv(const std::string& path) {
  const std::vector<Column> cols = {
      {"sigma3_kPa", true}, {"eps_axial", true}, {"q_kPa", true}, {"eps_vol", false}, {"eps_radial", false}};
  const CsvTable t = read_csv(path, cols);
  std::vector<TriaxialCurve> out;
  for (const auto& row : t.rows) {
    const double s3 = row.value[0], ea = row.value[1], q = row.value[2];
    auto at = [&](int k) { return SourceLocation{path, row.line, row.col[k]}; };
    if (!(s3 > 0))
      throw Error(at(0), "sigma3_kPa = " + fmt(s3) + "; allowed: > 0 (compression positive, kPa)");
    if (ea < 0 || ea >= 1)
      throw Error(at(1), "eps_axial = " + fmt(ea) +
                             "; allowed: 0 <= eps_axial < 1 (a fraction, compression positive: 0.05 = 5 %)");
    if (q < 0) throw Error(at(2), "q_kPa = " + fmt(q) + "; allowed: >= 0 (sigma_1 - sigma_3 in compression)");
    for (int k : {3, 4})
      if (t.present[k] && std::abs(row.value[k]) >= 1)
        throw Error(at(k), cols[k].name + " = " + fmt(row.value[k]) + "; allowed: |" + cols[k].name +
                               "| < 1 (a fraction, compression positive)");
    if (out.empty() || out.back().sigma3 != s3) {
      out.emplace_back();
      out.back().sigma3 = s3;
      out.back().file = path;
    } else if (!(ea > out.back().eps_a.back())) {
      throw Error(at(1),
                  "eps_axial = " + fmt(ea) + " does not increase (previous point " +
                      fmt(out.back().eps_a.back()) + " on line " + std::to_string(out.back().lines.back()) +
                      "); allowed: each curve (a block of rows with one sigma3_kPa) in increasing eps_axial");
    }
    TriaxialCurve& c = out.back();
    c.eps_a.push_back(ea);
    c.q.push_back(q);
    if (t.present[3]) c.eps_v.push_back(row.value[3]);
    if (t.present[4]) c.eps_r.push_back(row.value[4]);
    c.lines.push_back(row.line);
  }
  return out;
}

std::vector<ShearCurve> read_direct_shear_csv(const std::string& path) {
  const std::vector<Column> cols = {{"sigma_n_kPa", true}, {"du_m", true}, {"tau_kPa", true}};
  const CsvTable t = read_csv(path, cols);
  std::vector<ShearCurve> out;
  for (const auto& row : t.rows) {
    const double sn = row.value[0], du = row.value[1], tau = row.value[2];
    auto at = [&](int k) { return SourceLocation{path, row.line, row.col[k]}; };
    if (!(sn > 0))
      throw Error(at(0), "sigma_n_kPa = " + fmt(sn) + "; allowed: > 0 (compression positive, kPa)");
    if (du < 0 || du >= 1)
      throw Error(at(1), "du_m = " + fmt(du) + "; allowed: 0 <= du_m < 1 (shear displacement in metres)");
    if (tau < 0) throw Error(at(2), "tau_kPa = " + fmt(tau) + "; allowed: >= 0 (shear in one direction)");
    if (out.empty() || out.back().sigma_n != sn) {
      out.emplace_back();
      out.back().sigma_n = sn;
      out.back().file = path;
    } else if (!(du > out.back().du.back())) {
      throw Error(at(1),
                  "du_m = " + fmt(du) + " does not increase (previous point " + fmt(out.back().du.back()) +
                      " on line " + std::to_string(out.back().lines.back()) +
                      "); allowed: each curve (a block of rows with one sigma_n_kPa) in increasing du_m");
    }
    ShearCurve& c = out.back();
    c.du.push_back(du);
    c.tau.push_back(tau);
    c.lines.push_back(row.line);
  }
  return out;
}

// ================================================================ Duncan-Chang

DuncanChangFit fit_duncan_chang(const std::vector<TriaxialCurve>& curves, DuncanChangForm form,
                                const std::string& source) {
  DuncanChangFit out;
  out.form = form;
  if (curves.empty()) throw Error(source + ": no triaxial curves");
  std::vector<double> levels;
  for (const auto& c : curves) levels.push_back(c.sigma3);
  if (distinct_levels(levels) < 2)
    throw Error(source + ": all curves are at sigma_3 = " + fmt(levels[0]) +
                " kPa; K, n and c, phi need curves at two or more cell pressures");

  const HypLaw law{true, p_a, "q", "sigma_3", "eps_axial", "c", "phi", "K", "kPa"};
  std::vector<HypCurve> hc;
  std::vector<std::size_t> peaks;
  for (const auto& c : curves) {
    const std::string level = level_text("sigma_3", c.sigma3);
    const std::size_t k = peak_index(c.q, c.lines, c.file, "q_kPa", level);
    peaks.push_back(k);
    if (k + 1 < c.q.size())
      out.notes.push_back(level + ": " + count(c.q.size() - k - 1, "point") +
                          " after the peak (softening) not used");
    hc.push_back(hyp_curve(law, c.sigma3, c.eps_a, c.q, k, c.file, c.lines[0], level));
  }
  const HypResult h = fit_hyperbolic(law, hc, source, out.residuals);
  out.K = h.K, out.n = h.n, out.R_f = h.R_f, out.c = h.c, out.phi = h.phi / deg;
  out.K0 = h.K0, out.n0 = h.n0, out.R_f0 = h.R_f0, out.c0 = h.c0, out.phi0 = h.phi0 / deg;
  out.iterations = h.iterations;
  out.notes.push_back("q_f of each curve is its largest q (the last point if the curve has no peak)");

  // the volumetric / lateral strains of the used (pre-peak, eps_axial > 0) points
  for (const auto& c : curves)
    if (c.eps_v.empty() && c.eps_r.empty())
      throw Error(source + ": form " + std::string(form == DuncanChangForm::E_nu ? "E_nu" : "E_B") +
                  " needs the column eps_vol or eps_radial; the curve at " + level_text("sigma_3", c.sigma3) +
                  " has neither");
  auto lateral = [](const TriaxialCurve& c, std::size_t i) { // -eps_3, expansion positive
    return c.eps_r.empty() ? 0.5 * (c.eps_a[i] - c.eps_v[i]) : -c.eps_r[i];
  };
  auto volumetric = [](const TriaxialCurve& c, std::size_t i) {
    return c.eps_v.empty() ? c.eps_a[i] + 2 * c.eps_r[i] : c.eps_v[i];
  };

  if (form == DuncanChangForm::E_nu) {
    // per curve: eps_1 / (-eps_3) = 1/f - (d/f) eps_1
    struct Lat {
      double L;
      std::vector<double> e1, lat;
    };
    std::vector<Lat> lc;
    std::vector<double> Ls, fs, ds;
    double sum2 = 0;
    for (std::size_t i = 0; i < curves.size(); ++i) {
      const auto& c = curves[i];
      Lat l{std::log10(c.sigma3 / p_a), {}, {}};
      std::vector<double> xs, ts;
      for (std::size_t j = 0; j <= peaks[i]; ++j) {
        if (!(c.eps_a[j] > 0)) continue;
        const double lat = lateral(c, j);
        l.e1.push_back(c.eps_a[j]);
        l.lat.push_back(lat);
        sum2 += lat * lat;
        if (lat > 0) {
          xs.push_back(c.eps_a[j]);
          ts.push_back(c.eps_a[j] / lat);
        }
      }
      double A = 0, B = 0;
      const std::string where =
          c.file + ":" + std::to_string(c.lines[0]) + ": curve at " + level_text("sigma_3", c.sigma3);
      if (xs.size() < 3)
        throw Error(where + ": " + std::to_string(xs.size()) +
                    " points with lateral expansion (-eps_3 > 0) up to the peak; allowed: at least 3");
      if (!fit_line(xs, ts, A, B) || !(A > 0))
        throw Error(where +
                    ": the lateral strain is not a hyperbola -eps_3 = f eps_1/(1 - d eps_1) with f > 0 "
                    "(transform eps_1/(-eps_3) = 1/f - (d/f) eps_1 gives 1/f = " +
                    fmt(A) + ")");
      Ls.push_back(l.L);
      fs.push_back(1 / A);
      ds.push_back(-B / A);
      lc.push_back(std::move(l));
    }
    double G0 = 0, mF0 = 0, d0 = 0;
    if (!fit_line(Ls, fs, G0, mF0)) throw Error(source + ": G, F need curves at two or more cell pressures");
    for (double d : ds) d0 += d / static_cast<double>(ds.size());
    const ResidualFn f = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r) {
      Eigen::Index m = 0;
      for (const auto& l : lc) m += static_cast<Eigen::Index>(l.e1.size());
      r.resize(m);
      Eigen::Index k = 0;
      for (const auto& l : lc) {
        const double nu = p[0] - p[1] * l.L;
        for (std::size_t j = 0; j < l.e1.size(); ++j) {
          const double den = 1 - p[2] * l.e1[j];
          if (!(den > 0)) return false;
          r[k++] = nu * l.e1[j] / den - l.lat[j];
        }
      }
      return true;
    };
    Eigen::VectorXd p0(3), typical(3);
    p0 << G0, -mF0, d0;
    typical << 0.1, 0.1, std::max(std::abs(d0), 1.0);
    const LmResult lm = levenberg_marquardt(f, p0, typical, 1e-28 * sum2);
    if (!lm.converged)
      throw Error(source + ": the fit of G, F, d to the lateral strains did not converge (" +
                  std::to_string(lm.iterations) + " iterations from G = " + fmt(G0) + ", F = " + fmt(-mF0) +
                  ", d = " + fmt(d0) + ")");
    out.G = lm.p[0], out.F = lm.p[1], out.d = lm.p[2];
    for (std::size_t i = 0; i < lc.size(); ++i) {
      const double nu = out.G - out.F * lc[i].L;
      if (!(nu > 0) || !(nu < 0.5))
        throw Error(source + ": nu_i = G - F log10(sigma_3/p_a) = " + fmt(nu) + " at " +
                    level_text("sigma_3", curves[i].sigma3) + " (G = " + fmt(out.G) + ", F = " + fmt(out.F) +
                    "); allowed: 0 < nu_i < 0.5");
    }
    if (out.d < -1e-9)
      throw Error(source + ": d = " + fmt(out.d) +
                  " < 0: the lateral strain grows slower than linearly with eps_1; allowed: d >= 0");
    out.d = std::max(out.d, 0.0);
    for (std::size_t i = 0; i < lc.size(); ++i) {
      const double nu = out.G - out.F * lc[i].L;
      std::vector<double> dd;
      for (std::size_t j = 0; j < lc[i].e1.size(); ++j)
        dd.push_back(nu * lc[i].e1[j] / (1 - out.d * lc[i].e1[j]) - lc[i].lat[j]);
      out.residuals.push_back(residual_of("-eps_3", curves[i].sigma3, dd, ""));
    }
  } else {
    // Duncan et al. (1980): B = q / (3 eps_v) at 70 % of the strength, or where eps_v
    // has its maximum if that comes first; then B = K_b p_a (sigma_3/p_a)^m.
    std::vector<double> Ls, lnB, Bs;
    for (std::size_t i = 0; i < curves.size(); ++i) {
      const auto& c = curves[i];
      const std::string where =
          c.file + ":" + std::to_string(c.lines[0]) + ": curve at " + level_text("sigma_3", c.sigma3);
      const double q70 = 0.7 * c.q[peaks[i]];
      std::size_t j70 = 0;
      while (j70 <= peaks[i] && c.q[j70] < q70) ++j70;
      if (j70 == 0)
        throw Error(where + ": the first point is already at 70 % of the strength; allowed: curves sampled "
                            "from the start of shearing");
      const double t = (q70 - c.q[j70 - 1]) / (c.q[j70] - c.q[j70 - 1]);
      double q_at = q70, ev_at = volumetric(c, j70 - 1) + t * (volumetric(c, j70) - volumetric(c, j70 - 1));
      for (std::size_t j = 0; j < j70; ++j)
        if (volumetric(c, j) > ev_at) { // the volume change has levelled off before 70 %
          ev_at = volumetric(c, j);
          q_at = c.q[j];
        }
      if (!(ev_at > 0) || !(q_at > 0))
        throw Error(where + ": no contraction before 70 % of the strength (eps_vol = " + fmt(ev_at) +
                    "); allowed for form E_B: curves whose volume first decreases (eps_vol > 0)");
      const double B = q_at / (3 * ev_at);
      Ls.push_back(std::log(c.sigma3 / p_a));
      lnB.push_back(std::log(B / p_a));
      Bs.push_back(B);
    }
    double lnKb = 0, m = 0;
    if (!fit_line(Ls, lnB, lnKb, m))
      throw Error(source + ": K_b, m need curves at two or more cell pressures");
    out.K_b = std::exp(lnKb);
    out.m = m;
    if (m < 0 || m > 1)
      out.notes.push_back("m = " + fmt(m) + " is outside the usual range 0..1 (Duncan et al. 1980)");
    for (std::size_t i = 0; i < curves.size(); ++i) {
      const double Bm = out.K_b * p_a * std::pow(curves[i].sigma3 / p_a, out.m);
      out.residuals.push_back(residual_of("B", curves[i].sigma3, {Bm - Bs[i]}, "kPa"));
    }
    out.notes.push_back(
        "B of each curve = q/(3 eps_vol) at 70 % of q_f, or at the largest eps_vol before that "
        "(Duncan et al. 1980)");
  }
  return out;
}

// ================================================================ contact laws

namespace {

std::vector<std::size_t> shear_peaks(const std::vector<ShearCurve>& curves, const std::string& source,
                                     const std::string& what) {
  if (curves.empty()) throw Error(source + ": no direct-shear curves");
  std::vector<double> levels;
  for (const auto& c : curves) levels.push_back(c.sigma_n);
  if (distinct_levels(levels) < 2)
    throw Error(source + ": all curves are at sigma_n = " + fmt(levels[0]) + " kPa; " + what +
                " need curves at two or more normal stresses");
  std::vector<std::size_t> peaks;
  for (const auto& c : curves)
    peaks.push_back(peak_index(c.tau, c.lines, c.file, "tau_kPa", level_text("sigma_n", c.sigma_n)));
  return peaks;
}

/// Coulomb line tau = c + sigma tan(phi) through (s, t); phi in degrees. Throws if unphysical.
void coulomb(const std::vector<double>& s, const std::vector<double>& t, const std::string& source,
             const std::string& which, double& c, double& phi) {
  double A = 0, B = 0;
  if (!fit_line(s, t, A, B))
    throw Error(source + ": the " + which + " line needs two or more normal stresses");
  if (!(B > 0))
    throw Error(source + ": the " + which + " strengths do not grow with sigma_n (slope " + fmt(B) +
                "); allowed: a Coulomb line with phi > 0");
  double tmax = 0;
  for (double v : t) tmax = std::max(tmax, v);
  if (A < -1e-9 * tmax)
    throw Error(source + ": the " + which + " line has c = " + fmt(A) +
                " kPa < 0; allowed: c >= 0 (check the curves, or fit a narrower sigma_n range)");
  c = std::max(A, 0.0);
  phi = std::atan(B) / deg;
}

} // namespace

ContactFit fit_contact(const std::vector<ShearCurve>& curves, const ContactOptions& options,
                       const std::string& source) {
  ContactFit out;
  const auto peaks = shear_peaks(curves, source, "K_s(sigma_n) and the strength lines");
  // initial slopes: Kondner on the points below 70 % of the peak
  std::vector<double> s, Ks, tp, tr;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const auto& c = curves[i];
    const std::string level = level_text("sigma_n", c.sigma_n);
    const std::string where = c.file + ":" + std::to_string(c.lines[0]) + ": curve at " + level;
    const double peak = c.tau[peaks[i]];
    std::size_t last = 0;
    int below = 0;
    for (std::size_t j = 0; j <= peaks[i]; ++j)
      if (c.du[j] > 0 && c.tau[j] > 0 && c.tau[j] <= 0.7 * peak) last = j, ++below;
    if (below < 2) {
      int seen = 0;
      for (std::size_t j = 0; j <= peaks[i] && seen < 2; ++j)
        if (c.du[j] > 0 && c.tau[j] > 0) last = j, ++seen;
      if (seen < 2)
        throw Error(where + ": " + std::to_string(seen) +
                    " points with du_m > 0 and tau_kPa > 0 up to the peak; allowed: at least 2");
      out.notes.push_back(level + ": fewer than 2 points below 70 % of the peak; the initial slope uses the "
                                  "first 2 points");
    }
    const Kondner k = kondner(c.du, c.tau, last);
    if (!(k.a > 0))
      throw Error(where + ": no initial slope: Kondner's transform du/tau = a + b du gives a = " + fmt(k.a) +
                  "; allowed: curves starting with a finite positive stiffness");
    s.push_back(c.sigma_n);
    Ks.push_back(1 / k.a);
    tp.push_back(peak);
    tr.push_back(c.tau.back());
    if (peaks[i] + 1 == c.tau.size())
      out.notes.push_back(level + ": no post-peak branch, so its residual strength is its peak");
  }

  // K_s = k_s0 + alpha (sigma_n / p_a)^m, relative residuals
  const bool free_k0 = !options.fix_k_s0 && distinct_levels(s) >= 3;
  if (!options.fix_k_s0 && !free_k0)
    out.notes.push_back("two normal stresses only: k_s0 = 0, alpha and m through both initial slopes");
  std::string slopes; // for messages
  for (std::size_t i = 0; i < s.size(); ++i) slopes += (i ? ", " : "") + fmt(Ks[i]) + " at " + fmt(s[i]);
  // returns false if the refinement does not converge
  auto fit_ks = [&](bool free, double k0) {
    std::vector<double> ls, lk;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!(Ks[i] - k0 > 0))
        throw Error(source + ": k_s0 = " + fmt(k0) + " kPa/m is not below the initial slope " + fmt(Ks[i]) +
                    " kPa/m at " + level_text("sigma_n", s[i]) + "; allowed: k_s0 < every initial slope");
      ls.push_back(std::log(s[i] / p_a));
      lk.push_back(std::log(Ks[i] - k0));
    }
    double la = 0, m0 = 0;
    if (!fit_line(ls, lk, la, m0)) throw Error(source + ": alpha, m need two or more normal stresses");
    const ResidualFn f = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r) {
      const double kk = free ? p[2] : k0;
      r.resize(static_cast<Eigen::Index>(s.size()));
      for (std::size_t i = 0; i < s.size(); ++i)
        r[static_cast<Eigen::Index>(i)] = (kk + p[0] * std::pow(s[i] / p_a, p[1])) / Ks[i] - 1;
      return p[0] > 0;
    };
    Eigen::VectorXd p0(free ? 3 : 2), typical(free ? 3 : 2);
    p0[0] = std::exp(la), p0[1] = m0;
    typical[0] = p0[0], typical[1] = 0.1;
    if (free) p0[2] = k0, typical[2] = 0.01 * p0[0];
    const LmResult lm = levenberg_marquardt(f, p0, typical, 1e-28 * static_cast<double>(s.size()));
    if (!lm.converged) return false;
    out.alpha = lm.p[0], out.m = lm.p[1], out.k_s0 = free ? lm.p[2] : k0;
    return true;
  };
  const double k0 = options.fix_k_s0 ? options.k_s0 : 0.0;
  const bool free_ok = fit_ks(free_k0, k0);
  if (free_k0 && (!free_ok || out.k_s0 < 0)) {
    out.notes.push_back(free_ok ? "the free fit gave k_s0 = " + fmt(out.k_s0) +
                                      " kPa/m < 0; refitted with k_s0 = 0"
                                : "the free fit of k_s0, alpha, m did not converge; refitted with k_s0 = 0");
    if (!fit_ks(false, 0.0))
      throw Error(
          source +
          ": the fit of alpha, m (k_s0 = 0) did not converge; initial slopes (kPa/m at sigma_n in kPa): " +
          slopes);
  } else if (!free_ok) {
    throw Error(source + ": the fit of alpha, m (k_s0 = " + fmt(k0) +
                ") did not converge; initial slopes (kPa/m at sigma_n in kPa): " + slopes);
  }
  if (out.m < 0)
    throw Error(source + ": m = " + fmt(out.m) +
                " < 0: the initial shear stiffness falls as sigma_n grows; "
                "allowed: m >= 0");
  coulomb(s, tp, source, "peak", out.c_peak, out.phi_peak);
  coulomb(s, tr, source, "residual", out.c_residual, out.phi_residual);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double km = out.k_s0 + out.alpha * std::pow(s[i] / p_a, out.m);
    out.residuals.push_back(residual_of("K_s", s[i], {km - Ks[i]}, "kPa/m"));
    out.residuals.push_back(
        residual_of("tau_peak", s[i], {out.c_peak + s[i] * std::tan(out.phi_peak * deg) - tp[i]}, "kPa"));
    out.residuals.push_back(residual_of(
        "tau_residual", s[i], {out.c_residual + s[i] * std::tan(out.phi_residual * deg) - tr[i]}, "kPa"));
  }
  out.notes.push_back(
      "initial slope of each curve: Kondner's du/tau = a + b du on the points below 70 % of the "
      "peak, K_s = 1/a; residual strength = the last point");
  return out;
}

InterfaceFit fit_hyperbolic_interface(const std::vector<ShearCurve>& curves, const std::string& source) {
  InterfaceFit out;
  const auto peaks = shear_peaks(curves, source, "K_I, n and c_a, delta");
  const HypLaw law{false, gamma_w, "tau", "sigma_n", "du", "c_a", "delta", "K_I", "kPa"};
  std::vector<HypCurve> hc;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const auto& c = curves[i];
    const std::string level = level_text("sigma_n", c.sigma_n);
    if (peaks[i] + 1 < c.tau.size())
      out.notes.push_back(level + ": " + count(c.tau.size() - peaks[i] - 1, "point") +
                          " after the peak (softening) not used");
    hc.push_back(hyp_curve(law, c.sigma_n, c.du, c.tau, peaks[i], c.file, c.lines[0], level));
  }
  const HypResult h = fit_hyperbolic(law, hc, source, out.residuals);
  out.K_I = h.K, out.n = h.n, out.R_f = h.R_f, out.c_a = h.c, out.delta = h.phi / deg;
  out.K0 = h.K0, out.n0 = h.n0, out.R_f0 = h.R_f0, out.c_a0 = h.c0, out.delta0 = h.phi0 / deg;
  out.iterations = h.iterations;
  out.notes.push_back("tau_f of each curve is its largest tau (the last point if the curve has no peak)");
  return out;
}

// ================================================================ output

namespace {

/// A TOML float: 9 significant digits, always with a '.' or an exponent.
std::string tnum(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v + 0.0);
  std::string s = buf;
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string comments(const std::vector<CurveResidual>& rs, const std::vector<std::string>& notes) {
  std::ostringstream o;
  o << "# residuals (model - data) per curve:\n";
  for (const auto& r : rs) {
    const std::string u = r.unit.empty() ? "" : " " + r.unit;
    o << "#   " << r.what << " at " << fmt(r.level) << " kPa: ";
    if (r.points == 1)
      o << "|difference| " << fmt(r.max) << u;
    else
      o << r.points << " points, RMS " << fmt(r.rms) << u << ", max " << fmt(r.max) << u;
    o << "\n";
  }
  for (const auto& n : notes) { // wrapped at about 100 characters
    std::string line = "# note:";
    std::istringstream words(n);
    for (std::string w; words >> w;) {
      if (line.size() + 1 + w.size() > 100) {
        o << line << "\n";
        line = "#  ";
      }
      line += " " + w;
    }
    o << line << "\n";
  }
  return o.str();
}

} // namespace

std::string to_toml(const DuncanChangFit& f, const std::string& header) {
  std::ostringstream o;
  o << header << "\n"
    << "# Duncan-Chang parameters (docs/calibration.md): paste into a [materials.NAME] table with\n"
    << "# model = \"duncan_chang\". Compression positive; phi in degrees, c in kPa.\n"
    << "# Kondner start: K = " << fmt(f.K0) << ", n = " << fmt(f.n0) << ", R_f = " << fmt(f.R_f0)
    << ", phi = " << fmt(f.phi0) << ", c = " << fmt(f.c0) << "; Levenberg-Marquardt: " << f.iterations
    << " iterations\n"
    << comments(f.residuals, f.notes);
  o << "form = \"" << (f.form == DuncanChangForm::E_nu ? "E_nu" : "E_B") << "\"\n"
    << "K = " << tnum(f.K) << "\n"
    << "n = " << tnum(f.n) << "\n"
    << "R_f = " << tnum(f.R_f) << "\n"
    << "phi = " << tnum(f.phi) << "\n"
    << "c = " << tnum(f.c) << "\n";
  if (f.form == DuncanChangForm::E_nu)
    o << "G = " << tnum(f.G) << "\n"
      << "F = " << tnum(f.F) << "\n"
      << "d = " << tnum(f.d) << "\n";
  else
    o << "K_b = " << tnum(f.K_b) << "\n"
      << "m = " << tnum(f.m) << "\n";
  o << "p_a = " << tnum(p_a) << "\n";
  return o.str();
}

std::string to_toml(const ContactFit& f, const std::string& header) {
  std::ostringstream o;
  o << header << "\n"
    << "# Nonlinear Goodman contact (goodman_nonlinear, docs/calibration.md): K_s = k_s0 + alpha "
       "(sigma_n/p_a)^m\n"
    << "# in kPa/m, Coulomb peak and residual lines; angles in degrees, c in kPa.\n"
    << comments(f.residuals, f.notes);
  o << "k_s0 = " << tnum(f.k_s0) << "\n"
    << "alpha = " << tnum(f.alpha) << "\n"
    << "m = " << tnum(f.m) << "\n"
    << "c_peak = " << tnum(f.c_peak) << "\n"
    << "phi_peak = " << tnum(f.phi_peak) << "\n"
    << "c_residual = " << tnum(f.c_residual) << "\n"
    << "phi_residual = " << tnum(f.phi_residual) << "\n"
    << "p_a = " << tnum(p_a) << "\n";
  return o.str();
}

std::string to_toml(const InterfaceFit& f, const std::string& header) {
  std::ostringstream o;
  o << header << "\n"
    << "# Hyperbolic (Clough-Duncan) interface (hyperbolic_interface, docs/calibration.md):\n"
    << "# K_st = K_I gamma_w (sigma_n/p_a)^n (1 - R_f tau/(c_a + sigma_n tan delta))^2; delta in degrees.\n"
    << "# Kondner start: K_I = " << fmt(f.K0) << ", n = " << fmt(f.n0) << ", R_f = " << fmt(f.R_f0)
    << ", c_a = " << fmt(f.c_a0) << ", delta = " << fmt(f.delta0) << "; Levenberg-Marquardt: " << f.iterations
    << " iterations\n"
    << comments(f.residuals, f.notes);
  o << "K_I = " << tnum(f.K_I) << "\n"
    << "n = " << tnum(f.n) << "\n"
    << "R_f = " << tnum(f.R_f) << "\n"
    << "c_a = " << tnum(f.c_a) << "\n"
    << "delta = " << tnum(f.delta) << "\n"
    << "gamma_w = " << tnum(gamma_w) << "\n"
    << "p_a = " << tnum(p_a) << "\n";
  return o.str();
}

void write_file_atomically(const std::string& path, const std::string& text) {
  const fs::path final_path(path);
  if (final_path.has_parent_path()) fs::create_directories(final_path.parent_path());
  const fs::path tmp = final_path.parent_path() / ("." + final_path.filename().string() + ".tmp");
  {
    std::ofstream o(tmp);
    if (!o) throw Error("cannot write '" + path + "'");
    o << text;
    o.flush();
    if (!o) {
      o.close();
      fs::remove(tmp);
      throw Error("cannot write '" + path + "'");
    }
  }
  std::error_code ec;
  fs::rename(tmp, final_path, ec);
  if (ec) {
    fs::remove(tmp);
    throw Error("cannot write '" + path + "': " + ec.message());
  }
}

} // namespace stratum::calibration
