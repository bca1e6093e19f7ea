// Calibration targets: `stratum fit TARGET CURVES.csv ...` fits a plugin's parameters to
// laboratory curves. The plugin that owns the parameters declares the target, registered
// through its entry point like its other factories:
//
//   registry.add(stratum::Factory<stratum::Calibration>{"my_model", "one line", options, create});
//
// and listed in its manifest (`PROVIDES calibration:my_model`), so that `stratum fit my_model`
// opens only that library. The factory's schema declares the target's options (`--form E_B`
// on the command line is the text option `form`); `create` gets them checked, with every
// option the user gave located (Params::where(name).known()) and the others at their defaults.
//
// The program reads the curves (the CSV formats of docs/calibration.md, chosen by lab_test()),
// keeps those in --range and hands them to fit(); it writes the FittedParameters as a TOML
// fragment with the plugin's own key names (write_fitted_toml). The numerics shared by fits
// (least-squares lines, Kondner's transform, Levenberg-Marquardt, hyperbolas across confining
// levels) are in stratum/calibration_toolkit.hpp.
//
// Everything here is compression-positive, as in the laboratory. Units: kPa, m.
#pragma once

#include <string>
#include <vector>

namespace stratum {

namespace calibration {

inline constexpr double p_a = 100.0;    ///< atmospheric pressure, kPa
inline constexpr double gamma_w = 9.81; ///< unit weight of water, kN/m^3

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

/// How well one curve (or one derived quantity of a curve) is reproduced.
struct CurveResidual {
  std::string what; ///< e.g. "q", "-eps_3", "B", "K_s", "tau_peak"
  double level = 0; ///< sigma_3 or sigma_n of the curve, kPa
  int points = 0;   ///< points compared
  double rms = 0;   ///< root mean square of (model - data)
  double max = 0;   ///< largest |model - data|
  std::string unit; ///< of rms and max
};

} // namespace calibration

/// The laboratory test whose curves a target fits.
enum class LabTest { triaxial, direct_shear };
/// "triaxial", "direct_shear".
[[nodiscard]] const char* to_string(LabTest t);

/// The curves handed to a fit: those of its lab test (the other list is empty).
struct LabCurves {
  std::vector<calibration::TriaxialCurve> triaxial;
  std::vector<calibration::ShearCurve> direct_shear;
  std::string source; ///< the input for messages: the file names (and the --range)
};

/// One fitted parameter under the plugin's key name: a number, or a text (e.g. a form) when
/// `text` is not empty.
struct FittedValue {
  std::string name;
  double value = 0;
  std::string text;
};

/// What a fit returns; write_fitted_toml turns it into the TOML fragment.
struct FittedParameters {
  std::vector<std::string> comments; ///< lines written first (without "# "): the model, units, the start
  std::vector<FittedValue> values;   ///< the parameters in the order written
  std::vector<calibration::CurveResidual> residuals;
  std::vector<std::string> notes; ///< decisions worth telling the user (dropped points, rules used)
  std::vector<FittedValue> start; ///< the estimates a refinement started from (for programs and tests)
  int iterations = 0;             ///< of the main refinement (0: none)

  /// The number (text) of a parameter; throws Error naming the parameters when absent.
  [[nodiscard]] double value(const std::string& name) const;
  [[nodiscard]] const std::string& text(const std::string& name) const;
  [[nodiscard]] double start_value(const std::string& name) const;
};

/// The TOML fragment: `header` (a comment line, e.g. the command), the comments, the residuals
/// (RMS and max per curve) and the notes as comments, then one `name = value` line per value
/// (numbers with 9 significant digits, always with a '.' or an exponent).
[[nodiscard]] std::string write_fitted_toml(const FittedParameters& fit, const std::string& header);

/// A calibration target, created from its checked options.
class Calibration {
public:
  virtual ~Calibration() = default;
  /// The laboratory test whose curves fit() takes.
  [[nodiscard]] virtual LabTest lab_test() const = 0;
  /// Fits the parameters to the curves (at least one). Curves that the model cannot fit throw
  /// Error with one line naming the curve (file:line where it helps), what is wrong and what is
  /// allowed.
  [[nodiscard]] virtual FittedParameters fit(const LabCurves& curves) const = 0;
};

} // namespace stratum
