// The nonlinear Goodman calibration target (`stratum fit goodman_nonlinear`, also under its
// older name `stratum fit contact`; docs/calibration.md): this plugin's contact-law parameters
// from direct-shear curves (digest 5.2, (3.53)-(3.54)): K_s = k_s0 + alpha (sigma_n/p_a)^m from
// the initial slopes, the peak and residual Coulomb lines from the peaks and the ends of the
// curves. Compression positive, kPa, m.
#include "goodman_nonlinear_calibration.hpp"

#include "common/calibration_plugin.hpp"
#include "stratum/calibration_toolkit.hpp"
#include "stratum/error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace stratum::goodman {

using namespace stratum::calibration;

namespace {

struct ContactFit {
  double k_s0 = 0, alpha = 0, m = 0;       ///< K_s = k_s0 + alpha (sigma_n/p_a)^m, kPa/m
  double c_peak = 0, phi_peak = 0;         ///< kPa, degrees
  double c_residual = 0, phi_residual = 0; ///< kPa, degrees
  std::vector<CurveResidual> residuals;
  std::vector<std::string> notes;
};

struct ContactOptions {
  bool fix_k_s0 = false; ///< hold k_s0 at the given value instead of fitting it
  double k_s0 = 0;
};

/// Coulomb line tau = c + sigma tan(phi) through (s, t); phi in degrees. Throws if unphysical.
void coulomb(const std::vector<double>& s, const std::vector<double>& t, const std::string& source,
             const std::string& which, double& c, double& phi) {
  double A = 0, B = 0;
  if (!fit_line(s, t, A, B))
    throw Error(source + ": the " + which + " line needs two or more normal stresses");
  if (!(B > 0))
    throw Error(source + ": the " + which + " strengths do not grow with sigma_n (slope " + number(B) +
                "); allowed: a Coulomb line with phi > 0");
  double tmax = 0;
  for (double v : t) tmax = std::max(tmax, v);
  if (A < -1e-9 * tmax)
    throw Error(source + ": the " + which + " line has c = " + number(A) +
                " kPa < 0; allowed: c >= 0 (check the curves, or fit a narrower sigma_n range)");
  c = std::max(A, 0.0);
  phi = std::atan(B) / deg;
}

ContactFit fit_contact(const std::vector<ShearCurve>& curves, const ContactOptions& options,
                       const std::string& source) {
  ContactFit out;
  const auto peaks = direct_shear_peaks(curves, source, "K_s(sigma_n) and the strength lines");
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
      throw Error(where + ": no initial slope: Kondner's transform du/tau = a + b du gives a = " +
                  number(k.a) + "; allowed: curves starting with a finite positive stiffness");
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
  for (std::size_t i = 0; i < s.size(); ++i)
    slopes += (i ? ", " : "") + number(Ks[i]) + " at " + number(s[i]);
  // returns false if the refinement does not converge
  auto fit_ks = [&](bool free, double k0) {
    std::vector<double> ls, lk;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!(Ks[i] - k0 > 0))
        throw Error(source + ": k_s0 = " + number(k0) + " kPa/m is not below the initial slope " +
                    number(Ks[i]) + " kPa/m at " + level_text("sigma_n", s[i]) +
                    "; allowed: k_s0 < every initial slope");
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
    out.notes.push_back(free_ok ? "the free fit gave k_s0 = " + number(out.k_s0) +
                                      " kPa/m < 0; refitted with k_s0 = 0"
                                : "the free fit of k_s0, alpha, m did not converge; refitted with k_s0 = 0");
    if (!fit_ks(false, 0.0))
      throw Error(
          source +
          ": the fit of alpha, m (k_s0 = 0) did not converge; initial slopes (kPa/m at sigma_n in kPa): " +
          slopes);
  } else if (!free_ok) {
    throw Error(source + ": the fit of alpha, m (k_s0 = " + number(k0) +
                ") did not converge; initial slopes (kPa/m at sigma_n in kPa): " + slopes);
  }
  if (out.m < 0)
    throw Error(source + ": m = " + number(out.m) +
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

/// The fit under the contact law's key names.
FittedParameters fitted(const ContactFit& f) {
  FittedParameters out;
  out.comments = {"Nonlinear Goodman contact (goodman_nonlinear, docs/calibration.md): K_s = k_s0 + alpha "
                  "(sigma_n/p_a)^m",
                  "in kPa/m, Coulomb peak and residual lines; angles in degrees, c in kPa."};
  out.values = {{"k_s0", f.k_s0, ""},
                {"alpha", f.alpha, ""},
                {"m", f.m, ""},
                {"c_peak", f.c_peak, ""},
                {"phi_peak", f.phi_peak, ""},
                {"c_residual", f.c_residual, ""},
                {"phi_residual", f.phi_residual, ""},
                {"p_a", p_a, ""}};
  out.residuals = f.residuals;
  out.notes = f.notes;
  return out;
}

Factory<Calibration> factory(const std::string& name, const std::string& summary) {
  Factory<Calibration> f;
  f.name = name;
  f.summary = summary;
  f.schema.real("k_s0", "kPa/m", "hold the initial shear stiffness k_s0 at this value instead of fitting it")
      .at_least(0.0)
      .defaults_to_computed(0.0, "fitted with three or more normal stresses, 0 with two");
  f.create = [](const Params& p) -> std::unique_ptr<Calibration> {
    ContactOptions o;
    o.fix_k_s0 = p.where("k_s0").known(); // given on the command line
    o.k_s0 = o.fix_k_s0 ? p.real("k_s0") : 0.0;
    return calibration_plugin::fitting(LabTest::direct_shear, [o](const LabCurves& curves) {
      return fitted(fit_contact(curves.direct_shear, o, curves.source));
    });
  };
  return f;
}

} // namespace

void register_calibration(Registry& registry) {
  const std::string what =
      "the goodman_nonlinear contact law's k_s0, alpha, m and peak and residual c, phi from "
      "direct-shear curves at several sigma_n";
  registry.add(factory("goodman_nonlinear", what));
  registry.add(factory("contact", what + " (the goodman_nonlinear target under its older name)"));
}

} // namespace stratum::goodman
