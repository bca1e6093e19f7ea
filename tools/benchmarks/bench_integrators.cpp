// Work-precision benchmark of the shared stress-integration library (plasticity/integrate.hpp).
//
// (a) Krieg & Krieg iso-error maps (docs/verification.md M3): perfectly plastic von Mises,
//     G = 1, R = sqrt(2/3) sigma_y = 1, eps_y = R/(2G); one step of de = a n0 + b t0 from
//     s0 = R n0 over (a/eps_y, b/eps_y) in [0,10]^2 on a 21 x 21 grid, for every scheme.
//     Writes docs/figures/iso_error_<scheme>.csv (columns de_n/eps_y, de_t/eps_y, error %).
// (b) Modified Cam-Clay undrained triaxial (M1): M = 1.2, lambda = 0.077, kappa = 0.0066,
//     e0 = 1, nu = 0.3, p0 = 200 kPa normally consolidated, 10 % axial strain in N equal steps.
//     Errors of the end state against the closed form q/p = M sqrt((p0/p)^(1/Lambda) - 1) at the
//     computed p and against a 20000-step closest-point reference; time (median of 3) and yield
//     evaluations. Writes docs/figures/mcc_error_cost.csv.
// Then rewrites its section of docs/benchmarks.md (temp file + rename).
//
// Usage: bench_integrators [--no-write] [--root DIR]   (DIR defaults to the source tree)
#include "../../plugins/cam_clay/cam_clay.hpp"
#include "../../plugins/mohr_coulomb/mohr_coulomb.hpp"
#include "../../plugins/von_mises/von_mises.hpp"
#include "cli.hpp"
#include "docs_section.hpp"
#include "stratum/plasticity/integrate.hpp"
#include "stratum/plasticity/invariants.hpp"
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace pl = stratum::plasticity;
namespace vm = stratum::von_mises;
namespace cc = stratum::cam_clay;
namespace mc = stratum::mohr_coulomb;
namespace fs = std::filesystem;

constexpr const char* begin_marker = "<!-- bench_integrators:begin -->";
constexpr const char* end_marker = "<!-- bench_integrators:end -->";
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

const std::array<pl::Scheme, 6> all_schemes = {pl::Scheme::forward_euler, pl::Scheme::modified_euler,
                                               pl::Scheme::trapezoidal,   pl::Scheme::midpoint,
                                               pl::Scheme::cutting_plane, pl::Scheme::closest_point};

/// Runs `run` three times: its last result and the median of the three wall times (s).
template <class Run> auto median_of_three_runs(Run&& run) {
  std::array<double, 3> times{};
  decltype(run()) result;
  for (double& t : times) {
    const auto t0 = std::chrono::steady_clock::now();
    result = run();
    t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::sort(times.begin(), times.end());
  return std::pair{result, times[1]};
}

/// The settings used throughout: forward Euler without substeps (the step count is the knob),
/// modified Euler with its default STOL = 1e-6, alpha = 0.5 for the generalised midpoint/trapezoidal.
pl::Settings settings_for(pl::Scheme s) {
  pl::Settings st;
  st.scheme = s;
  st.substeps = 1;
  st.alpha = 0.5;
  return st;
}

double tnorm(const Vec6& s) { return std::sqrt(s.head<3>().squaredNorm() + 2.0 * s.tail<3>().squaredNorm()); }

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// ---------------------------------------------------------------------------------- Krieg & Krieg
struct Krieg {
  double G = 1.0, R = 1.0, a = 0.0, b = 0.0;
  Vec6 n0, t0;

  Krieg(double a_, double b_) : a(a_), b(b_) {
    n0 << 1.0 / std::sqrt(2.0), -1.0 / std::sqrt(2.0), 0, 0, 0, 0;
    t0 << 0, 0, 0, 1.0 / std::sqrt(2.0), 0, 0;
  }
  [[nodiscard]] vm::Constants constants() const {
    vm::Constants c;
    c.nu = 0.3;
    c.E = 2.0 * G * (1.0 + c.nu);
    c.sigma_y = std::sqrt(1.5) * R;
    c.H = 0.0;
    return c;
  }
  [[nodiscard]] Vec6 de() const { return a * pl::to_strain_like(n0) + b * pl::to_strain_like(t0); }
  [[nodiscard]] Vec6 start() const { return R * n0; }
  [[nodiscard]] Vec6 exact() const {
    const double rho = std::hypot(a, b), phi = std::atan2(a, b), k = 2.0 * G * rho / R;
    const double chi = 2.0 * (std::atan(std::tan(phi / 2.0 + M_PI / 4.0) * std::exp(k)) - M_PI / 4.0);
    const double psi = chi - phi;
    return R * (std::cos(psi) * n0 + std::sin(psi) * t0);
  }
};

/// One-step error (%) of the Krieg & Krieg case; NaN if the integrator fails.
double krieg_error_pct(pl::Scheme s, double a, double b) {
  const Krieg k(a, b);
  const vm::VonMisesModel m(k.constants());
  std::array<double, 1> q{0.0};
  Vec6 sigma;
  Mat6 T;
  const pl::Result r = pl::integrate(m, settings_for(s), k.start(), k.de(), sigma, q, T);
  if (!r.outcome.ok() || !sigma.allFinite()) return nan;
  return 100.0 * tnorm(sigma - k.exact()) / tnorm(k.exact());
}

struct IsoSummary {
  pl::Scheme scheme;
  double max = 0.0, mean = 0.0, ref = nan, corner = nan;
  int failures = 0;
};

IsoSummary iso_map(pl::Scheme s, const fs::path& csv) {
  constexpr int n = 21;
  const double eps_y = 0.5; // R / (2 G)
  IsoSummary sum{s};
  std::ofstream out(csv);
  out << "de_n_over_eps_y,de_t_over_eps_y,error_pct\n";
  int count = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double xn = 0.5 * i, xt = 0.5 * j;
      const double e = krieg_error_pct(s, xn * eps_y, xt * eps_y);
      out << xn << ',' << xt << ',' << fmt("%.10g", e) << '\n';
      if (std::isnan(e)) {
        ++sum.failures;
        continue;
      }
      sum.max = std::max(sum.max, e);
      sum.mean += e;
      ++count;
      if (i == 2 && j == 2) sum.ref = e;
      if (i == n - 1 && j == n - 1) sum.corner = e;
    }
  sum.mean /= std::max(count, 1);
  if (!out) throw std::runtime_error("cannot write " + csv.string());
  return sum;
}

// ---------------------------------------------------------------------------------- Cam-Clay
constexpr double M_ = 1.2, lambda_ = 0.077, kappa_ = 0.0066, p0_ = 200.0, axial_ = 0.10;
constexpr double Lambda_ = (lambda_ - kappa_) / lambda_;

cc::Constants mcc_constants() {
  cc::Constants c;
  c.variant = cc::Variant::modified;
  c.M = M_;
  c.lambda = lambda_;
  c.kappa = kappa_;
  c.e0 = 1.0;
  c.nu = 0.3;
  c.G = 0.0;
  c.p_min = 1.0;
  return c;
}

Vec6 undrained(double d) {
  Vec6 e = Vec6::Zero();
  e[1] = -d;
  e[0] = e[2] = d / 2;
  return e;
}

struct McRun {
  bool ok = true;
  double p = nan, q = nan;
  pl::Counters counters;
};

/// Undrained triaxial to 10 % axial strain in N equal steps from the isotropic NC state p0.
McRun mcc_run(const cc::Model& m, const pl::Settings& s, int N) {
  McRun r;
  Vec6 sigma = Vec6::Zero();
  sigma[0] = sigma[1] = sigma[2] = -p0_;
  std::array<double, 1> xi{std::log(p0_)};
  const Vec6 de = undrained(axial_ / N);
  for (int i = 0; i < N; ++i) {
    Vec6 out;
    Mat6 T;
    const pl::Result res = pl::integrate(m, s, sigma, de, out, xi, T, &r.counters);
    if (!res.outcome.ok() || !out.allFinite() || !std::isfinite(xi[0]) || pl::p_comp(out) < 1.0) {
      r.ok = false;
      return r;
    }
    sigma = out;
  }
  r.p = pl::p_comp(sigma);
  r.q = pl::q_mises(sigma);
  return r;
}

struct McRow {
  pl::Scheme scheme;
  int steps = 0;
  bool ok = false;
  double err_eta = nan, err_p = nan, err_q = nan, time = nan;
  long yield_evaluations = 0, iterations = 0;
};

// ---------------------------------------------------------------------------------- Mohr-Coulomb
/// Rounded Mohr-Coulomb (phi = 20 deg, within the convex range of the Gudehus rounding, psi = 5 deg,
/// c = 10 kPa, E = 20 MPa, nu = 0.3) from p0 = 100 kPa along a non-proportional strain path: the
/// increment of step i turns from compression a = (1/4, -1, 1/4, 0, 0, 0) to shear b = (0, 0, 0, 3/2, 0, 0)
/// over the path, de_i = (0.02/N) (cos t_i a + sin t_i b), t_i = (i + 1/2) pi / (2N). A proportional
/// path would end on a stationary stress that every scheme finds exactly; this one keeps the stress
/// moving over the surface, so the end state depends on how well the path is integrated.
struct MohrRun {
  bool ok = true;
  Vec6 sigma = Vec6::Constant(nan);
  pl::Counters counters;
};

MohrRun mohr_run(const mc::RoundedModel& m, const pl::Settings& s, int N) {
  MohrRun r;
  Vec6 sigma = Vec6::Zero();
  sigma[0] = sigma[1] = sigma[2] = -100.0;
  Vec6 a = Vec6::Zero(), b = Vec6::Zero();
  a[0] = a[2] = 0.25, a[1] = -1.0;
  b[3] = 1.5;
  const double d = 0.02 / N;
  std::array<double, 0> none{};
  for (int i = 0; i < N; ++i) {
    const double t = (i + 0.5) * std::numbers::pi / (2.0 * N);
    const Vec6 de = d * (std::cos(t) * a + std::sin(t) * b);
    Vec6 out;
    Mat6 T;
    const pl::Result res = pl::integrate(m, s, sigma, de, out, none, T, &r.counters);
    if (!res.outcome.ok() || !out.allFinite()) {
      r.ok = false;
      return r;
    }
    sigma = out;
  }
  r.sigma = sigma;
  return r;
}

// ---------------------------------------------------------------------------------- output
std::string pct(double v) { return std::isnan(v) ? "fail" : fmt(v != 0.0 && v < 0.01 ? "%.2e" : "%.3f", v); }
std::string sci(double v) { return std::isnan(v) ? "fail" : std::isinf(v) ? "inf" : fmt("%.1e", v); }

void write_section(const fs::path& path, const std::string& block) {
  stratum::bench::replace_docs_section(path, begin_marker, end_marker, block);
}

/// The row of a scheme and step count (rows holds every pair).
const McRow& row_of(const std::vector<McRow>& rows, pl::Scheme s, int N) {
  for (const McRow& r : rows)
    if (r.scheme == s && r.steps == N) return r;
  throw std::runtime_error("no row");
}

const IsoSummary& iso_of(const std::vector<IsoSummary>& iso, pl::Scheme s) {
  for (const IsoSummary& r : iso)
    if (r.scheme == s) return r;
  throw std::runtime_error("no iso summary");
}

/// Smallest N whose end-p error is below tol (0 if none).
int steps_for(const std::vector<McRow>& rows, pl::Scheme s, double tol) {
  for (const McRow& r : rows)
    if (r.scheme == s && r.ok && r.err_p < tol) return r.steps;
  return 0;
}

/// Failed step counts of a scheme, as text.
std::string failures_of(const std::vector<McRow>& rows, pl::Scheme s) {
  std::string out;
  for (const McRow& r : rows)
    if (r.scheme == s && !r.ok) out += (out.empty() ? "" : ", ") + std::to_string(r.steps);
  return out.empty() ? "none" : out;
}

/// "Which integrator when", stated with the measured numbers.
std::string guidance(const std::vector<IsoSummary>& iso, const std::vector<McRow>& rows) {
  using S = pl::Scheme;
  std::ostringstream g;
  const McRow &cp1 = row_of(rows, S::closest_point, 1), &cp10 = row_of(rows, S::closest_point, 10);
  const McRow &me1 = row_of(rows, S::modified_euler, 1), &cut1000 = row_of(rows, S::cutting_plane, 1000);
  const McRow& fe1000 = row_of(rows, S::forward_euler, 1000);
  g << "**Which integrator when** (from the numbers above):\n\n"
    << "- *closest_point* is the default for implicit FE: it returns the consistent tangent, never failed, "
       "its worst one-step von Mises error is bounded ("
    << pct(iso_of(iso, S::closest_point).max) << " %), and on MCC it is accurate from few steps: end-p error "
    << sci(cp1.err_p) << " in one 10 % step, " << sci(cp10.err_p) << " in 10 steps ("
    << cp10.yield_evaluations
    << " yield evaluations); error below 1e-6 from N = " << steps_for(rows, S::closest_point, 1e-6) << ".\n"
    << "- *modified_euler* (error-controlled substepping) is the choice for very large or few increments "
       "and models without second derivatives: its error is set by STOL, not by N ("
    << sci(me1.err_p) << " in one step) but it costs a fixed ~" << me1.yield_evaluations
    << " yield evaluations even for one step, and it offers only the continuum tangent.\n"
    << "- *cutting_plane* is cheap per step (no second derivatives, bounded one-step error like "
       "closest_point) but is only first order on MCC (end-p error "
    << sci(cut1000.err_p) << " at N = 1000): use it for explicit dynamics or many small steps.\n"
    << "- *trapezoidal* / *midpoint* (alpha = 0.5) are very accurate once the step is moderate but failed "
       "at N = "
    << failures_of(rows, S::trapezoidal) << " (trapezoidal) and " << failures_of(rows, S::midpoint)
    << " (midpoint) and reach " << pct(iso_of(iso, S::midpoint).max)
    << " % one-step error on the von Mises map; prefer closest_point.\n"
    << "- *forward_euler* without substeps is only a reference: " << pct(iso_of(iso, S::forward_euler).max)
    << " % worst one-step error and still " << sci(fe1000.err_p) << " (p) / " << sci(fe1000.err_q)
    << " (q) after 1000 MCC steps; if used, give it many substeps.\n";
  return g.str();
}

int run(int argc, char** argv) {
  bool write = true;
  std::string root_dir = STRATUM_SOURCE_DIR;
  const auto cli =
      stratum::bench::Cli("bench_integrators")
          .flag("--no-write", "do not update docs/benchmarks.md (the CSVs in docs/figures are written)",
                write, false)
          .text("--root", "DIR", "the source tree to write into (default: this one)", root_dir);
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  const fs::path root = root_dir;
  const fs::path figures = root / "docs" / "figures";
  fs::create_directories(figures);

  // (a) iso-error maps
  std::vector<IsoSummary> iso;
  std::cout << "Krieg & Krieg one-step iso-error maps (21 x 21 over [0,10]^2 in eps_y), error %\n";
  std::cout << "scheme           max        mean      (1,1)=(a,b)=(0.5,0.5)   (10,10)  failures\n";
  for (pl::Scheme s : all_schemes) {
    iso.push_back(iso_map(s, figures / (std::string("iso_error_") + pl::to_string(s) + ".csv")));
    const IsoSummary& r = iso.back();
    std::printf("%-15s %9.4g %9.4g %12.5g %18.4g %6d\n", pl::to_string(s), r.max, r.mean, r.ref, r.corner,
                r.failures);
  }

  // (b) MCC error vs cost
  const cc::Model mcc(mcc_constants());
  pl::Settings ref_settings = settings_for(pl::Scheme::closest_point);
  ref_settings.ftol = 1e-12;
  const McRun ref = mcc_run(mcc, ref_settings, 20000);
  if (!ref.ok) throw std::runtime_error("the 20000-step closest-point reference failed");
  std::printf("\nMCC undrained reference (20000 closest-point steps): p = %.6f q = %.6f kPa\n", ref.p, ref.q);
  const std::vector<int> step_counts = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000};
  std::vector<McRow> rows;
  std::ofstream csv(figures / "mcc_error_cost.csv");
  csv << "scheme,steps,ok,err_eta_closed_form,err_p_ref,err_q_ref,time_s,yield_evaluations,iterations\n";
  std::cout << "scheme          steps  err q/p(cf)  err p(ref)  err q(ref)   time ms   yield ev\n";
  for (pl::Scheme s : all_schemes)
    for (int N : step_counts) {
      McRow row{s, N};
      const auto [r, time] = median_of_three_runs([&] { return mcc_run(mcc, settings_for(s), N); });
      row.ok = r.ok;
      row.time = time;
      row.yield_evaluations = r.counters.yield_evaluations;
      row.iterations = r.counters.iterations;
      if (r.ok) {
        const double closed = M_ * std::sqrt(std::pow(p0_ / r.p, 1 / Lambda_) - 1);
        row.err_eta = std::abs(r.q / r.p / closed - 1);
        row.err_p = std::abs(r.p / ref.p - 1);
        row.err_q = std::abs(r.q / ref.q - 1);
      }
      rows.push_back(row);
      csv << pl::to_string(s) << ',' << N << ',' << (row.ok ? 1 : 0) << ',' << fmt("%.6e", row.err_eta) << ','
          << fmt("%.6e", row.err_p) << ',' << fmt("%.6e", row.err_q) << ',' << fmt("%.6e", row.time) << ','
          << row.yield_evaluations << ',' << row.iterations << '\n';
      std::printf("%-15s %5d %11s %11s %11s %9.3f %10ld\n", pl::to_string(s), N, sci(row.err_eta).c_str(),
                  sci(row.err_p).c_str(), sci(row.err_q).c_str(), 1e3 * row.time, row.yield_evaluations);
    }
  if (!csv) throw std::runtime_error("cannot write mcc_error_cost.csv");

  // (c) rounded Mohr-Coulomb error vs cost against a 20000-step closest-point reference
  mc::Parameters mp;
  mp.E = 2.0e4, mp.nu = 0.3, mp.c = 10.0, mp.phi = 20.0, mp.psi = 5.0, mp.form = mc::Form::rounded;
  const mc::RoundedModel mohr(mp);
  // Reference: the second-order midpoint rule with 20000 steps (closest_point is first order on
  // this path and would leave its own error, ~5e-6, in every comparison).
  pl::Settings mref_settings = settings_for(pl::Scheme::midpoint);
  mref_settings.ftol = 1e-12;
  const MohrRun mref = mohr_run(mohr, mref_settings, 20000);
  if (!mref.ok) throw std::runtime_error("the 20000-step midpoint Mohr-Coulomb reference failed");
  std::printf("\nMohr-Coulomb (rounded) reference: p = %.6f q = %.6f kPa\n", pl::p_comp(mref.sigma),
              pl::q_mises(mref.sigma));
  struct MohrRow {
    pl::Scheme scheme;
    int steps;
    double err, time;
    long yield_evaluations;
  };
  std::vector<MohrRow> mrows;
  std::ofstream mcsv(figures / "mc_error_cost.csv");
  mcsv << "scheme,steps,ok,err_sigma_ref,time_s,yield_evaluations\n";
  for (pl::Scheme s : all_schemes)
    for (int N : step_counts) {
      const auto [r, time] = median_of_three_runs([&] { return mohr_run(mohr, settings_for(s), N); });
      const double err = r.ok ? tnorm(r.sigma - mref.sigma) / tnorm(mref.sigma) : nan;
      mrows.push_back({s, N, err, time, r.counters.yield_evaluations});
      mcsv << pl::to_string(s) << ',' << N << ',' << (r.ok ? 1 : 0) << ',' << fmt("%.6e", err) << ','
           << fmt("%.6e", time) << ',' << r.counters.yield_evaluations << '\n';
      std::printf("%-15s %5d %11s %9.3f %10ld\n", pl::to_string(s), N, sci(err).c_str(), 1e3 * time,
                  r.counters.yield_evaluations);
    }
  if (!mcsv) throw std::runtime_error("cannot write mc_error_cost.csv");
  if (!write) return 0;

  // markdown section
  std::ostringstream md;
  md << begin_marker << "\n## Stress integrators: accuracy and cost\n\n"
     << "Generated by `build/release/bin/bench_integrators` (source "
        "`tools/benchmarks/bench_integrators.cpp`); "
        "regenerate with `build/release/bin/bench_integrators` then `python3 tools/plot_integrators.py` (a "
        "python3 with matplotlib, e.g. Debian's `/usr/bin/python3` "
        "with python3-matplotlib) "
        "(figures and CSVs in `docs/figures/`; `--no-write` leaves this file alone). Settings: "
        "forward_euler without substeps (substeps = 1), modified_euler with STOL = 1e-6, "
        "trapezoidal/midpoint with alpha = 0.5, FTOL = 1e-9, max 50 local iterations.\n\n"
     << "### Krieg & Krieg iso-error maps (von Mises, one step)\n\n"
     << "Perfectly plastic von Mises, G = 1, R = sqrt(2/3) sigma_y = 1, eps_y = R/(2G) = 0.5; one step of "
        "de = a n0 + b t0 from s0 = R n0 (verification.md M3), 21 x 21 grid over (a/eps_y, b/eps_y) in "
        "[0,10]^2. Error = |sigma - sigma_exact| / |sigma_exact| in %. Column (1,1) is (a, b) = (0.5, 0.5), "
        "the catalogue's check (12.095 % for closest_point).\n\n"
     << "| scheme | max % | mean % | (1,1) % | (10,10) % | failures |\n|---|---:|---:|---:|---:|---:|\n";
  for (const IsoSummary& r : iso)
    md << "| " << pl::to_string(r.scheme) << " | " << pct(r.max) << " | " << pct(r.mean) << " | "
       << pct(r.ref) << " | " << pct(r.corner) << " | " << r.failures << " |\n";
  md << "\n";
  for (const IsoSummary& r : iso)
    md << "![iso-error " << pl::to_string(r.scheme) << "](figures/iso_error_" << pl::to_string(r.scheme)
       << ".png) ";
  md << "\n\n### Modified Cam-Clay undrained triaxial: error vs cost\n\n"
     << "M = 1.2, lambda = 0.077, kappa = 0.0066, e0 = 1, nu = 0.3 (G = 3K(1-2nu)/(2(1+nu)), K = v p/kappa), "
        "normally consolidated p0 = 200 kPa, 10 % axial strain (isochoric) in N equal steps. "
        "*err q/p* = |q/p / (M sqrt((p0/p)^(1/Lambda) - 1)) - 1| at the computed end p (closed form, M1); "
        "*err p*, *err q* = relative errors of the end p, q against a 20000-step closest_point run (FTOL "
        "1e-12: p = "
     << fmt("%.4f", ref.p) << ", q = " << fmt("%.4f", ref.q)
     << " kPa). Time = median of 3 runs of all N steps, steady_clock, ms. *yield ev* = yield-function "
        "evaluations of the whole run.\n\n"
     << "| scheme | N | err q/p | err p | err q | time ms | yield ev "
        "|\n|---|---:|---:|---:|---:|---:|---:|\n";
  for (const McRow& r : rows)
    md << "| " << pl::to_string(r.scheme) << " | " << r.steps << " | " << sci(r.err_eta) << " | "
       << sci(r.err_p) << " | " << sci(r.err_q) << " | " << fmt("%.3f", 1e3 * r.time) << " | "
       << r.yield_evaluations << " |\n";
  md << "\n![MCC error vs cost](figures/mcc_error_cost.png)\n\n";
  md << "### Rounded Mohr-Coulomb compression path: error vs cost\n\n"
     << "Gudehus-rounded Mohr-Coulomb (phi = 20 deg, psi = 5 deg, c = 10 kPa, E = 20 MPa, nu = 0.3), from "
        "p0 = 100 kPa along a strain path whose increments turn from triaxial compression (d/4, -d, d/4) "
        "to shear (gamma_xy = 3d/2) over N steps (total length 0.02), so the stress keeps moving over the "
        "surface. At small N the error is dominated by the path itself (its direction is sampled at N "
        "points), which every scheme shares; the orders show from N = 10 on. *err* = |sigma - sigma_ref| / "
        "|sigma_ref| "
        "against a 20000-step midpoint (alpha = 0.5) run (FTOL 1e-12); no closed form exists for this "
        "path.\n\n"
     << "| scheme | N=1 | N=10 | N=100 | N=1000 | yield ev (N=100) | time ms (N=100) |\n"
        "|---|---:|---:|---:|---:|---:|---:|\n";
  for (pl::Scheme sc : all_schemes) {
    auto at = [&](int N) -> const MohrRow& {
      for (const auto& r : mrows)
        if (r.scheme == sc && r.steps == N) return r;
      throw std::runtime_error("missing Mohr-Coulomb row");
    };
    md << "| " << pl::to_string(sc) << " | " << sci(at(1).err) << " | " << sci(at(10).err) << " | "
       << sci(at(100).err) << " | " << sci(at(1000).err) << " | " << at(100).yield_evaluations << " | "
       << fmt("%.3f", 1e3 * at(100).time) << " |\n";
  }
  md << "\n";
  md << guidance(iso, rows);
  md << end_marker << "\n";
  write_section(root / "docs" / "benchmarks.md", md.str());
  std::cout << "\nwrote " << (root / "docs" / "benchmarks.md").string() << "\n";
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bench_integrators: " << e.what() << "\n";
    return 1;
  }
}
