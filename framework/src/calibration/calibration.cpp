// Calibration from laboratory curves: the transformed linear (Kondner) starts, a small
// Levenberg-Marquardt solver and the fits (reading: calibration_csv.cpp; output:
// calibration_toml.cpp). See framework/src/calibration/calibration.hpp and docs/calibration.md.
#include "calibration/calibration.hpp"

#include "calibration_detail.hpp"
#include "stratum/error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <set>
#include <sstream>

namespace stratum::calibration {

using namespace detail;

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

} // namespace stratum::calibration
