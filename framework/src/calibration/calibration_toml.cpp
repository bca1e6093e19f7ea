// Calibration: the fitted parameters as a TOML fragment with the residuals as comments
// (framework/src/calibration/calibration.hpp).
#include "calibration/calibration.hpp"

#include "calibration_detail.hpp"
#include "stratum/error.hpp"

#include <sstream>

namespace stratum::calibration {

using detail::fmt;

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

} // namespace stratum::calibration
