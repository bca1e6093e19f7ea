// The Duncan-Chang calibration target (`stratum fit duncan_chang`, docs/calibration.md): the
// parameters of this plugin's material from drained triaxial curves at several sigma_3 (digest
// 3.2, thesis (2.22)-(2.38)). Kondner's transformed linear fit per curve as the start, then a
// Levenberg-Marquardt refinement of K, n, R_f, c, phi on the deviator stress of all curves
// together (the toolkit's fit_hyperbolic); the Poisson parameters G, F, d from the lateral
// strain, or the bulk-modulus parameters K_b, m (Duncan et al. 1980). Compression positive, kPa.
#include "duncan_chang_calibration.hpp"

#include "common/calibration_plugin.hpp"
#include "stratum/calibration_toolkit.hpp"
#include "stratum/error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace stratum::duncan_chang {

using namespace stratum::calibration;

namespace {

enum class DuncanChangForm { E_nu, E_B };

struct DuncanChangFit {
  DuncanChangForm form = DuncanChangForm::E_nu;
  double K = 0, n = 0, R_f = 0, phi = 0 /* degrees */, c = 0 /* kPa */;
  double G = 0, F = 0,
         d = 0;          ///< form E_nu: nu_i = G - F log10(sigma_3/p_a), -eps_3 = nu_i eps_1/(1 - d eps_1)
  double K_b = 0, m = 0; ///< form E_B: B = K_b p_a (sigma_3/p_a)^m
  /// The Kondner (transformed linear) estimates the refinement started from.
  double K0 = 0, n0 = 0, R_f0 = 0, phi0 = 0, c0 = 0;
  int iterations = 0; ///< Levenberg-Marquardt iterations of the deviator fit
  std::vector<CurveResidual> residuals;
  std::vector<std::string> notes; ///< decisions worth telling the user (dropped points, rules used)
};

DuncanChangFit fit_duncan_chang(const std::vector<TriaxialCurve>& curves, DuncanChangForm form,
                                const std::string& source) {
  DuncanChangFit out;
  out.form = form;
  if (curves.empty()) throw Error(source + ": no triaxial curves");
  std::vector<double> levels;
  for (const auto& c : curves) levels.push_back(c.sigma3);
  if (distinct_levels(levels) < 2)
    throw Error(source + ": all curves are at sigma_3 = " + number(levels[0]) +
                " kPa; K, n and c, phi need curves at two or more cell pressures");

  const HyperbolicLaw law{true, p_a, "q", "sigma_3", "eps_axial", "c", "phi", "K", "kPa"};
  std::vector<HyperbolicCurve> hc;
  std::vector<std::size_t> peaks;
  for (const auto& c : curves) {
    const std::string level = level_text("sigma_3", c.sigma3);
    const std::size_t k = peak_index(c.q, c.lines, c.file, "q_kPa", level);
    peaks.push_back(k);
    if (k + 1 < c.q.size())
      out.notes.push_back(level + ": " + count(c.q.size() - k - 1, "point") +
                          " after the peak (softening) not used");
    hc.push_back(hyperbolic_curve(law, c.sigma3, c.eps_a, c.q, k, c.file, c.lines[0], level));
  }
  const HyperbolicFit h = fit_hyperbolic(law, hc, source, out.residuals);
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
                    number(A) + ")");
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
                  std::to_string(lm.iterations) + " iterations from G = " + number(G0) +
                  ", F = " + number(-mF0) + ", d = " + number(d0) + ")");
    out.G = lm.p[0], out.F = lm.p[1], out.d = lm.p[2];
    for (std::size_t i = 0; i < lc.size(); ++i) {
      const double nu = out.G - out.F * lc[i].L;
      if (!(nu > 0) || !(nu < 0.5))
        throw Error(source + ": nu_i = G - F log10(sigma_3/p_a) = " + number(nu) + " at " +
                    level_text("sigma_3", curves[i].sigma3) + " (G = " + number(out.G) +
                    ", F = " + number(out.F) + "); allowed: 0 < nu_i < 0.5");
    }
    if (out.d < -1e-9)
      throw Error(source + ": d = " + number(out.d) +
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
        throw Error(where + ": no contraction before 70 % of the strength (eps_vol = " + number(ev_at) +
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
      out.notes.push_back("m = " + number(m) + " is outside the usual range 0..1 (Duncan et al. 1980)");
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

/// The fit under the material's key names (a [materials.NAME] table with model = "duncan_chang").
FittedParameters fitted(const DuncanChangFit& f) {
  FittedParameters out;
  out.comments = {"Duncan-Chang parameters (docs/calibration.md): paste into a [materials.NAME] table with",
                  "model = \"duncan_chang\". Compression positive; phi in degrees, c in kPa.",
                  "Kondner start: K = " + number(f.K0) + ", n = " + number(f.n0) +
                      ", R_f = " + number(f.R_f0) + ", phi = " + number(f.phi0) + ", c = " + number(f.c0) +
                      "; Levenberg-Marquardt: " + std::to_string(f.iterations) + " iterations"};
  out.values = {{"form", 0, f.form == DuncanChangForm::E_nu ? "E_nu" : "E_B"},
                {"K", f.K, ""},
                {"n", f.n, ""},
                {"R_f", f.R_f, ""},
                {"phi", f.phi, ""},
                {"c", f.c, ""}};
  if (f.form == DuncanChangForm::E_nu)
    out.values.insert(out.values.end(), {{"G", f.G, ""}, {"F", f.F, ""}, {"d", f.d, ""}});
  else
    out.values.insert(out.values.end(), {{"K_b", f.K_b, ""}, {"m", f.m, ""}});
  out.values.push_back({"p_a", p_a, ""});
  out.start = {{"K", f.K0, ""}, {"n", f.n0, ""}, {"R_f", f.R_f0, ""}, {"phi", f.phi0, ""}, {"c", f.c0, ""}};
  out.iterations = f.iterations;
  out.residuals = f.residuals;
  out.notes = f.notes;
  return out;
}

} // namespace

void register_calibration(Registry& registry) {
  Factory<Calibration> f;
  f.name = "duncan_chang";
  f.summary = "the duncan_chang material's K, n, R_f, phi, c and G, F, d (E_nu) or K_b, m (E_B) from drained "
              "triaxial curves at several sigma_3";
  f.schema
      .text("form", {"E_nu", "E_B"},
            "E_nu: the Poisson parameters G, F, d from the lateral strain; E_B: the bulk modulus "
            "parameters K_b, m from the volumetric strain")
      .defaults_to(std::string("E_nu"));
  f.create = [](const Params& p) -> std::unique_ptr<Calibration> {
    const DuncanChangForm form = p.text("form") == "E_B" ? DuncanChangForm::E_B : DuncanChangForm::E_nu;
    return calibration_plugin::fitting(LabTest::triaxial, [form](const LabCurves& curves) {
      return fitted(fit_duncan_chang(curves.triaxial, form, curves.source));
    });
  };
  registry.add(std::move(f));
}

} // namespace stratum::duncan_chang
