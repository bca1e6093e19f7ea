// Calibration of model parameters from laboratory curves (`stratum fit`).
//
//  * Duncan-Chang (digest 3.2, thesis (2.22)-(2.38)) from drained triaxial curves at
//    several sigma_3: Kondner's transformed linear fit per curve as the start, then a
//    Levenberg-Marquardt refinement of K, n, R_f, c, phi on the deviator stress of all
//    curves together; the Poisson parameters G, F, d from the lateral strain, or the
//    bulk-modulus parameters K_b, m (Duncan et al. 1980).
//  * The nonlinear Goodman contact law (digest 5.2, (3.53)-(3.54)) from direct-shear
//    curves: K_s = k_s0 + alpha (sigma_n/p_a)^m from the initial slopes, the peak and
//    residual Coulomb lines from the peaks and the ends of the curves.
//  * The hyperbolic (Clough-Duncan) interface (3.65) from the same direct-shear curves.
//
// Everything here is compression-positive, as in the laboratory. Units: kPa, m.
// Bad input and curves that cannot be fitted raise stratum::Error with one line naming
// the file (and line), what is wrong and what is allowed. The formulas, the CSV format
// and the limits are documented in docs/calibration.md.
#pragma once

#include <string>
#include <vector>

namespace stratum::calibration {

inline constexpr double p_a = 100.0;    ///< atmospheric pressure, kPa
inline constexpr double gamma_w = 9.81; ///< unit weight of water, kN/m^3 (Clough-Duncan)

// ---------------------------------------------------------------- input curves

/// One drained triaxial compression curve at constant sigma_3 (compression positive).
struct TriaxialCurve {
  double sigma3 = 0;         ///< cell pressure, kPa
  std::vector<double> eps_a; ///< axial strain (fraction), increasing
  std::vector<double> q;     ///< deviator stress sigma_1 - sigma_3, kPa
  std::vector<double> eps_v; ///< volumetric strain (fraction); empty if not measured
  std::vector<double> eps_r; ///< radial strain eps_3 (fraction, negative = expansion); empty if not measured
  std::vector<int> lines;    ///< the CSV line of each point
  std::string file;          ///< where it came from
};

/// One direct-shear curve at constant normal stress (compression positive).
struct ShearCurve {
  double sigma_n = 0;      ///< normal stress, kPa
  std::vector<double> du;  ///< shear displacement, m, increasing
  std::vector<double> tau; ///< shear stress, kPa
  std::vector<int> lines;  ///< the CSV line of each point
  std::string file;        ///< where it came from
};

/// Reads triaxial curves: a header row with sigma3_kPa, eps_axial, q_kPa and optionally
/// eps_vol and/or eps_radial; '#' comment lines and blank lines are skipped; a new curve
/// starts wherever sigma3_kPa changes. Throws Error("file:line:col ...") on bad input.
[[nodiscard]] std::vector<TriaxialCurve> read_triaxial_csv(const std::string& path);

/// Reads direct-shear curves: columns sigma_n_kPa, du_m, tau_kPa; same rules.
[[nodiscard]] std::vector<ShearCurve> read_direct_shear_csv(const std::string& path);

// ---------------------------------------------------------------- results

/// How well one curve (or one derived quantity of a curve) is reproduced.
struct CurveResidual {
  std::string what; ///< e.g. "q", "-eps_3", "B", "K_s", "tau_peak"
  double level = 0; ///< sigma_3 or sigma_n of the curve, kPa
  int points = 0;   ///< points compared
  double rms = 0;   ///< root mean square of (model - data)
  double max = 0;   ///< largest |model - data|
  std::string unit; ///< of rms and max
};

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

struct ContactFit {                        ///< goodman_nonlinear
  double k_s0 = 0, alpha = 0, m = 0;       ///< K_s = k_s0 + alpha (sigma_n/p_a)^m, kPa/m
  double c_peak = 0, phi_peak = 0;         ///< kPa, degrees
  double c_residual = 0, phi_residual = 0; ///< kPa, degrees
  std::vector<CurveResidual> residuals;
  std::vector<std::string> notes;
};

struct InterfaceFit {                                 ///< hyperbolic_interface (Clough-Duncan)
  double K_I = 0, n = 0, R_f = 0, c_a = 0, delta = 0; ///< delta in degrees, c_a in kPa
  double K0 = 0, n0 = 0, R_f0 = 0, c_a0 = 0, delta0 = 0;
  int iterations = 0;
  std::vector<CurveResidual> residuals;
  std::vector<std::string> notes;
};

struct ContactOptions {
  bool fix_k_s0 = false; ///< hold k_s0 at the given value instead of fitting it
  double k_s0 = 0;
};

// ---------------------------------------------------------------- fits

/// `source` names the input in error messages (e.g. the file names).
[[nodiscard]] DuncanChangFit fit_duncan_chang(const std::vector<TriaxialCurve>& curves, DuncanChangForm form,
                                              const std::string& source);
[[nodiscard]] ContactFit fit_contact(const std::vector<ShearCurve>& curves, const ContactOptions& options,
                                     const std::string& source);
[[nodiscard]] InterfaceFit fit_hyperbolic_interface(const std::vector<ShearCurve>& curves,
                                                    const std::string& source);

// ---------------------------------------------------------------- output

/// TOML fragments with the parameter names of the plugins; the residuals and notes
/// are TOML comments. `header` is a comment line placed first (e.g. the command).
[[nodiscard]] std::string to_toml(const DuncanChangFit& fit, const std::string& header);
[[nodiscard]] std::string to_toml(const ContactFit& fit, const std::string& header);
[[nodiscard]] std::string to_toml(const InterfaceFit& fit, const std::string& header);

} // namespace stratum::calibration
