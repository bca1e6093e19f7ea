// Calibration: the fitted parameters as a TOML fragment with the residuals as comments
// (stratum/calibration.hpp, write_fitted_toml), and the accessors of FittedParameters.
#include "stratum/calibration.hpp"

#include "stratum/error.hpp"
#include "stratum/parameters.hpp"

#include <cstdio>
#include <sstream>

namespace stratum {

const char* to_string(LabTest t) { return t == LabTest::triaxial ? "triaxial" : "direct_shear"; }

namespace {

/// A TOML float: 9 significant digits, always with a '.' or an exponent.
std::string tnum(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v + 0.0);
  std::string s = buf;
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string comments(const std::vector<calibration::CurveResidual>& rs,
                     const std::vector<std::string>& notes) {
  std::ostringstream o;
  o << "# residuals (model - data) per curve:\n";
  for (const auto& r : rs) {
    const std::string u = r.unit.empty() ? "" : " " + r.unit;
    o << "#   " << r.what << " at " << number(r.level) << " kPa: ";
    if (r.points == 1)
      o << "|difference| " << number(r.max) << u;
    else
      o << r.points << " points, RMS " << number(r.rms) << u << ", max " << number(r.max) << u;
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

const FittedValue& find(const std::vector<FittedValue>& values, const std::string& name, const char* what) {
  for (const auto& v : values)
    if (v.name == name) return v;
  std::string known;
  for (const auto& v : values) known += (known.empty() ? "" : ", ") + v.name;
  throw Error(std::string("no fitted ") + what + " '" + name + "'; the fit gives " +
              (known.empty() ? "(none)" : known));
}

} // namespace

double FittedParameters::value(const std::string& name) const {
  return find(values, name, "parameter").value;
}

const std::string& FittedParameters::text(const std::string& name) const {
  return find(values, name, "parameter").text;
}

double FittedParameters::start_value(const std::string& name) const {
  return find(start, name, "start value").value;
}

std::string write_fitted_toml(const FittedParameters& fit, const std::string& header) {
  std::ostringstream o;
  o << header << "\n";
  for (const auto& c : fit.comments) o << "# " << c << "\n";
  o << comments(fit.residuals, fit.notes);
  for (const auto& v : fit.values) {
    o << v.name << " = ";
    if (v.text.empty())
      o << tnum(v.value);
    else {
      o << '"';
      for (char c : v.text) {
        if (c == '"' || c == '\\') o << '\\';
        o << c;
      }
      o << '"';
    }
    o << "\n";
  }
  return o.str();
}

} // namespace stratum
