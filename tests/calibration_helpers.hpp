// Helpers of the calibration tests (tests/test_calibration.cpp and the plugins' own,
// plugins/{duncan_chang,goodman_nonlinear,hyperbolic_interface}/tests/): synthetic curves from
// the closed forms written as CSV into a scratch folder, and the fits run through the plugin
// catalog as `stratum fit` runs them.
#pragma once

#include "stratum/calibration.hpp"
#include "stratum/error.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace stratum::testing::calibration_tests {

namespace fs = std::filesystem;
namespace cal = stratum::calibration;
constexpr double deg = std::numbers::pi / 180;
constexpr double pa = 100;

inline fs::path scratch() {
  static const fs::path dir = fs::temp_directory_path() / ("stratum_fit_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

inline std::string write(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p.string();
}

inline std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.12g", v);
  return b;
}

struct DC {
  double K, n, R_f, phi, c; // phi in degrees
  double G, F, d;           // E_nu
  double K_b, m;            // E_B
};

inline double q_f(const DC& p, double s3) {
  const double sp = std::sin(p.phi * deg);
  return 2 * (p.c * std::cos(p.phi * deg) + s3 * sp) / (1 - sp);
}

/// Triaxial CSV rows for one curve: `points` equal strain steps up to failure (q = q_f),
/// then `after` softening points; eps_vol from the lateral hyperbola or from B.
inline std::string triaxial_rows(const DC& p, double s3, int points, bool bulk, int after = 0) {
  const double Ei = p.K * pa * std::pow(s3 / pa, p.n), qf = q_f(p, s3);
  const double eps_f = qf / Ei / (1 - p.R_f);
  const double f = p.G - p.F * std::log10(s3 / pa), B = p.K_b * pa * std::pow(s3 / pa, p.m);
  std::string s;
  for (int k = 0; k <= points + after; ++k) {
    const double e = eps_f * k / points;
    double q = e / (1 / Ei + p.R_f * e / qf);
    if (k > points) q = qf * (1 - 0.02 * (k - points)); // softening after the peak
    const double ev = bulk ? q / (3 * B) : e - 2 * f * e / (1 - p.d * e);
    s += num(s3) + "," + num(e) + "," + num(q) + "," + num(ev) + "\n";
  }
  return s;
}

inline void check_rel(const char* name, double got, double want, double tol = 1e-3) {
  INFO(name << ": fitted " << got << ", generated " << want);
  CHECK(std::abs(got - want) <= tol * std::abs(want));
}

template <class F> std::string error_of(F&& f) {
  try {
    f();
  } catch (const stratum::Error& e) {
    return e.what();
  }
  return "(no error)";
}

inline const std::string triax_header = "sigma3_kPa,eps_axial,q_kPa,eps_vol\n";

/// The fit of a calibration target through the plugin that declares it, as `stratum fit` runs it:
/// the catalog finds the library in the manifests, opens it, and the factory makes the target
/// from its options (those given located, the others at their defaults).
inline stratum::FittedParameters fit_target(const std::string& target, stratum::LabCurves curves,
                                            const std::map<std::string, stratum::ParamValue>& given = {}) {
  stratum::PluginCatalog catalog({STRATUM_PLUGIN_DIR});
  stratum::Registry registry;
  catalog.require(registry, stratum::PluginKind::calibration, target);
  const auto& factory = registry.calibration(target);
  stratum::Params options;
  for (const auto& spec : factory.schema.specs()) {
    const auto it = given.find(spec.name);
    if (it != given.end())
      options.set(spec.name, it->second, {"test", 1, 1});
    else
      options.set(spec.name, *spec.fallback);
  }
  return factory.create(options)->fit(curves);
}

inline stratum::FittedParameters fit_duncan_chang(std::vector<cal::TriaxialCurve> curves,
                                                  const std::string& form, const std::string& source) {
  stratum::LabCurves c;
  c.triaxial = std::move(curves);
  c.source = source;
  return fit_target("duncan_chang", std::move(c), {{"form", form}});
}

inline stratum::FittedParameters fit_contact(std::vector<cal::ShearCurve> curves, std::optional<double> k_s0,
                                             const std::string& source) {
  stratum::LabCurves c;
  c.direct_shear = std::move(curves);
  c.source = source;
  if (k_s0) return fit_target("goodman_nonlinear", std::move(c), {{"k_s0", *k_s0}});
  return fit_target("goodman_nonlinear", std::move(c));
}

inline stratum::FittedParameters fit_hyperbolic_interface(std::vector<cal::ShearCurve> curves,
                                                          const std::string& source) {
  stratum::LabCurves c;
  c.direct_shear = std::move(curves);
  c.source = source;
  return fit_target("hyperbolic_interface", std::move(c));
}

struct Goodman {
  double k_s0, alpha, m, c_p, phi_p, c_r, phi_r;
};

/// Linear up to the peak, linear softening to the residual over 3 mm, then flat.
inline std::string shear_rows(const Goodman& g, double sn) {
  const double K = g.k_s0 + g.alpha * std::pow(sn / pa, g.m);
  const double tp = g.c_p + sn * std::tan(g.phi_p * deg), tr = g.c_r + sn * std::tan(g.phi_r * deg);
  const double up = tp / K;
  std::string s;
  for (int k = 0; k <= 8; ++k) s += num(sn) + "," + num(up * k / 8) + "," + num(K * up * k / 8) + "\n";
  for (int k = 1; k <= 6; ++k) {
    const double du = up + 0.0005 * k;
    s += num(sn) + "," + num(du) + "," + num(du >= up + 0.003 ? tr : tp + (tr - tp) * (du - up) / 0.003) +
         "\n";
  }
  return s;
}

} // namespace stratum::testing::calibration_tests
