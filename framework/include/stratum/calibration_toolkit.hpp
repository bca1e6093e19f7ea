// The toolkit for calibration targets (stratum/calibration.hpp): the numerics that fits of
// different models share, so that a plugin's fit is only its model. Implemented in libstratum
// (framework/src/calibration/); the formulas and the rules (peak, points used, convergence) are
// those of docs/calibration.md.
//
//   fit_line             least-squares straight line
//   kondner              Kondner's transform x/y = a + b x of a hyperbola
//   levenberg_marquardt  nonlinear least squares with Marquardt's scaling
//   peak_index           the peak of a curve, refusing a second loading branch
//   fit_hyperbolic       y = x/(1/E_i + R_f x/y_f) with E_i = K u (s/p_a)^n and a Coulomb strength
//                        y_f(s), fitted to curves at several confining levels s (Duncan-Chang's
//                        triaxial form and Clough-Duncan's direct-shear form)
//   residual_of          RMS and max of model - data for the fragment's comments
//
// Compression positive, kPa, m. Errors are stratum::Error with one line.
#pragma once

#include "stratum/calibration.hpp"
#include "stratum/parameters.hpp" // stratum::number, for messages

#include <Eigen/Dense>

#include <cstddef>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

namespace stratum::calibration {

inline constexpr double deg = std::numbers::pi / 180.0;

/// Least-squares line y = a + b x. Returns false if the x values do not differ.
bool fit_line(const std::vector<double>& x, const std::vector<double>& y, double& a, double& b);

/// The residuals r(p) of a least-squares problem; false where p is outside the model's domain.
using ResidualFn = std::function<bool(const Eigen::VectorXd&, Eigen::VectorXd&)>;

struct LmResult {
  Eigen::VectorXd p;
  int iterations = 0;
  bool converged = false;
  double cost = 0; ///< 0.5 |r|^2 at p
};

/// Levenberg-Marquardt with Marquardt's diagonal scaling and a central-difference Jacobian.
/// Trial steps outside the domain are rejected like steps that raise the cost. `typical` gives
/// the magnitude of each parameter (for the difference steps). Converged when the step is below
/// 1e-11 of the parameters, or the cost below `cost_floor`.
LmResult levenberg_marquardt(const ResidualFn& f, Eigen::VectorXd p, const Eigen::VectorXd& typical,
                             double cost_floor, int max_iterations = 500);

/// Kondner's transform x/y = a + b x over the points 0..last with x > 0 and y > 0 (a, b NaN
/// when fewer than two such points differ in x).
struct Kondner {
  double a = 0, b = 0;
  int points = 0;
};
Kondner kondner(const std::vector<double>& x, const std::vector<double>& y, std::size_t last);

/// RMS and max of the differences (model - data) of one curve or one derived quantity.
CurveResidual residual_of(const std::string& what, double level, const std::vector<double>& diff,
                          const std::string& unit);

/// Index of the (first) peak of y. Before it, y may dip below its running maximum by at most 5 %
/// of the peak (scatter); a deeper dip (a second loading branch) throws, located at its line.
/// `name` is the column (e.g. "q_kPa"), `level` the curve (level_text).
std::size_t peak_index(const std::vector<double>& y, const std::vector<int>& lines, const std::string& file,
                       const std::string& name, const std::string& level);

/// The peak of each direct-shear curve; throws unless there are curves at two or more normal
/// stresses (`what`: the parameters that need them, for the message).
std::vector<std::size_t> direct_shear_peaks(const std::vector<ShearCurve>& curves, const std::string& source,
                                            const std::string& what);

/// How many different values.
std::size_t distinct_levels(const std::vector<double>& s);
/// "sigma_3 = 25 kPa".
std::string level_text(const std::string& name, double v);
/// "1 point", "3 points".
std::string count(std::size_t n, const std::string& what);

// ---------------------------------------------------------------- hyperbolas across levels

/// The hyperbola y = x / (1/E_i + R_f x / y_f) with E_i = K u (s/p_a)^n, fitted to curves at
/// several levels s, and its strength: triaxial (Duncan-Chang, u = p_a):
/// y_f = 2 (c cos phi + s sin phi)/(1 - sin phi); direct shear (Clough-Duncan, u = gamma_w):
/// y_f = c + s tan phi. The names are the plugin's, for messages.
struct HyperbolicLaw {
  bool triaxial = true;
  double unit = p_a;
  std::string y_name, s_name, x_name, c_name, phi_name, K_name, unit_y;
};

/// One curve prepared for the fit: the points up to the peak.
struct HyperbolicCurve {
  double s = 0;            ///< sigma_3 or sigma_n
  std::vector<double> x;   ///< strain or displacement, > 0
  std::vector<double> y;   ///< stress
  double y_f = 0;          ///< peak stress (failure)
  double E = 0, y_ult = 0; ///< Kondner estimates
  std::string file;
  int first_line = 0;
};

struct HyperbolicFit {
  double K = 0, n = 0, R_f = 0, c = 0, phi = 0;      ///< phi in radians
  double K0 = 0, n0 = 0, R_f0 = 0, c0 = 0, phi0 = 0; ///< the Kondner start
  int iterations = 0;
};

/// A HyperbolicCurve from the points up to the peak; checks Kondner's transform (at least 3
/// points, a > 0, b > 0), located at the curve's first line.
HyperbolicCurve hyperbolic_curve(const HyperbolicLaw& law, double s, const std::vector<double>& x,
                                 const std::vector<double>& y, std::size_t peak, const std::string& file,
                                 int first_line, const std::string& level);

/// Kondner starts per curve, straight lines across the levels, then Levenberg-Marquardt on
/// K, n, R_f, c, phi over all points and the strengths; checks 0 < R_f <= 1, n >= 0, c >= 0.
/// Appends the residuals of each curve (y and y_f) to `residuals`.
HyperbolicFit fit_hyperbolic(const HyperbolicLaw& law, const std::vector<HyperbolicCurve>& curves,
                             const std::string& source, std::vector<CurveResidual>& residuals);

} // namespace stratum::calibration
