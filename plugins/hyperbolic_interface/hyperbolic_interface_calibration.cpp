// The hyperbolic (Clough-Duncan) interface calibration target (`stratum fit
// hyperbolic_interface`, docs/calibration.md): this plugin's contact-law parameters from
// direct-shear curves at several sigma_n (digest 5.3, (3.65)): the toolkit's hyperbolic fit with
// du for the strain, gamma_w for p_a in the modulus and tau_f = c_a + sigma_n tan delta.
// Compression positive, kPa, m.
#include "hyperbolic_interface_calibration.hpp"

#include "common/calibration_plugin.hpp"
#include "stratum/calibration_toolkit.hpp"
#include "stratum/error.hpp"

#include <memory>
#include <string>
#include <vector>

namespace stratum::hyperbolic_interface {

using namespace stratum::calibration;

namespace {

struct InterfaceFit {
  double K_I = 0, n = 0, R_f = 0, c_a = 0, delta = 0; ///< delta in degrees, c_a in kPa
  double K0 = 0, n0 = 0, R_f0 = 0, c_a0 = 0, delta0 = 0;
  int iterations = 0;
  std::vector<CurveResidual> residuals;
  std::vector<std::string> notes;
};

InterfaceFit fit_hyperbolic_interface(const std::vector<ShearCurve>& curves, const std::string& source) {
  InterfaceFit out;
  const auto peaks = direct_shear_peaks(curves, source, "K_I, n and c_a, delta");
  const HyperbolicLaw law{false, gamma_w, "tau", "sigma_n", "du", "c_a", "delta", "K_I", "kPa"};
  std::vector<HyperbolicCurve> hc;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const auto& c = curves[i];
    const std::string level = level_text("sigma_n", c.sigma_n);
    if (peaks[i] + 1 < c.tau.size())
      out.notes.push_back(level + ": " + count(c.tau.size() - peaks[i] - 1, "point") +
                          " after the peak (softening) not used");
    hc.push_back(hyperbolic_curve(law, c.sigma_n, c.du, c.tau, peaks[i], c.file, c.lines[0], level));
  }
  const HyperbolicFit h = fit_hyperbolic(law, hc, source, out.residuals);
  out.K_I = h.K, out.n = h.n, out.R_f = h.R_f, out.c_a = h.c, out.delta = h.phi / deg;
  out.K0 = h.K0, out.n0 = h.n0, out.R_f0 = h.R_f0, out.c_a0 = h.c0, out.delta0 = h.phi0 / deg;
  out.iterations = h.iterations;
  out.notes.push_back("tau_f of each curve is its largest tau (the last point if the curve has no peak)");
  return out;
}

/// The fit under the contact law's key names.
FittedParameters fitted(const InterfaceFit& f) {
  FittedParameters out;
  out.comments = {
      "Hyperbolic (Clough-Duncan) interface (hyperbolic_interface, docs/calibration.md):",
      "K_st = K_I gamma_w (sigma_n/p_a)^n (1 - R_f tau/(c_a + sigma_n tan delta))^2; delta in degrees.",
      "Kondner start: K_I = " + number(f.K0) + ", n = " + number(f.n0) + ", R_f = " + number(f.R_f0) +
          ", c_a = " + number(f.c_a0) + ", delta = " + number(f.delta0) +
          "; Levenberg-Marquardt: " + std::to_string(f.iterations) + " iterations"};
  out.values = {{"K_I", f.K_I, ""},     {"n", f.n, ""},           {"R_f", f.R_f, ""}, {"c_a", f.c_a, ""},
                {"delta", f.delta, ""}, {"gamma_w", gamma_w, ""}, {"p_a", p_a, ""}};
  out.start = {
      {"K_I", f.K0, ""}, {"n", f.n0, ""}, {"R_f", f.R_f0, ""}, {"c_a", f.c_a0, ""}, {"delta", f.delta0, ""}};
  out.iterations = f.iterations;
  out.residuals = f.residuals;
  out.notes = f.notes;
  return out;
}

} // namespace

void register_calibration(Registry& registry) {
  Factory<Calibration> f;
  f.name = "hyperbolic_interface";
  f.summary = "the hyperbolic_interface contact law's K_I, n, R_f, c_a, delta from direct-shear curves at "
              "several sigma_n";
  f.create = [](const Params&) -> std::unique_ptr<Calibration> {
    return calibration_plugin::fitting(LabTest::direct_shear, [](const LabCurves& curves) {
      return fitted(fit_hyperbolic_interface(curves.direct_shear, curves.source));
    });
  };
  registry.add(std::move(f));
}

} // namespace stratum::hyperbolic_interface
