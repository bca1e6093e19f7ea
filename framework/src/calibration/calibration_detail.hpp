// Calibration, internal: what the reading, fitting and output parts share.
#pragma once

#include "calibration/calibration.hpp"

#include <Eigen/Dense>

#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

namespace stratum::calibration::detail {

constexpr double deg = std::numbers::pi / 180.0;

/// A number for messages: up to 6 significant digits.
inline std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

using ResidualFn = std::function<bool(const Eigen::VectorXd&, Eigen::VectorXd&)>;

struct LmResult {
  Eigen::VectorXd p;
  int iterations = 0;
  bool converged = false;
  double cost = 0;
};

/// Kondner's transform x/y = a + b x over the points 0..last with x > 0 and y > 0.
struct Kondner {
  double a = 0, b = 0;
  int points = 0;
};

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

/// Least-squares line y = a + b x. Returns false if the x values do not differ.
bool fit_line(const std::vector<double>& x, const std::vector<double>& y, double& a, double& b);
/// Levenberg-Marquardt with Marquardt's diagonal scaling and a central-difference Jacobian
/// (calibration_fit.cpp).
LmResult levenberg_marquardt(const ResidualFn& f, Eigen::VectorXd p, const Eigen::VectorXd& typical,
                             double cost_floor, int max_iterations = 500);
CurveResidual residual_of(const std::string& what, double level, const std::vector<double>& diff,
                          const std::string& unit);
/// Index of the (first) peak of y; throws where the curve has more than one loading branch.
std::size_t peak_index(const std::vector<double>& y, const std::vector<int>& lines, const std::string& file,
                       const std::string& name, const std::string& level);
Kondner kondner(const std::vector<double>& x, const std::vector<double>& y, std::size_t last);
std::size_t distinct_levels(const std::vector<double>& s);
HypResult fit_hyperbolic(const HypLaw& law, const std::vector<HypCurve>& curves, const std::string& source,
                         std::vector<CurveResidual>& residuals);
/// A HypCurve from the points up to the peak; checks the Kondner transform.
HypCurve hyp_curve(const HypLaw& law, double s, const std::vector<double>& x, const std::vector<double>& y,
                   std::size_t peak, const std::string& file, int first_line, const std::string& level);
std::string level_text(const std::string& name, double v);
std::string count(std::size_t n, const std::string& what);

} // namespace stratum::calibration::detail
