// stratum fit: model parameters from laboratory curves (docs/calibration.md).
//
//   stratum fit duncan_chang CURVES.csv [MORE.csv ...] [--form E_nu|E_B] [-o FILE.toml]
//   stratum fit contact DIRECT_SHEAR.csv [...] [--k_s0 VALUE] [-o FILE.toml]
//   stratum fit hyperbolic_interface DIRECT_SHEAR.csv [...] [-o FILE.toml]
//
// --range MIN:MAX (kPa) keeps only the curves whose sigma_3 (or sigma_n) lies in
// [MIN, MAX], e.g. the loess' two parameter sets: --range 0:100 and --range 200:1000.
//
// The TOML fragment goes to stdout, or atomically to FILE with -o (then the residual
// comments are echoed to stderr).
#include "fit.hpp"

#include "calibration/calibration.hpp"
#include "stratum/error.hpp"
#include "stratum/files.hpp"

#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string_view>

namespace stratum::cli {

namespace {

constexpr const char* targets = "duncan_chang, contact (goodman_nonlinear), hyperbolic_interface";

} // namespace

const char* fit_help() {
  return "usage: stratum fit duncan_chang CURVES.csv [MORE.csv ...] [--form E_nu|E_B] [--range MIN:MAX] [-o "
         "FILE]\n"
         "       stratum fit contact DIRECT_SHEAR.csv [...] [--k_s0 VALUE] [--range MIN:MAX] [-o FILE]\n"
         "       stratum fit hyperbolic_interface DIRECT_SHEAR.csv [...] [--range MIN:MAX] [-o FILE]\n"
         "\n"
         "Fits model parameters to laboratory curves and prints them as a TOML fragment\n"
         "(docs/calibration.md). duncan_chang reads drained triaxial curves (sigma3_kPa, eps_axial,\n"
         "q_kPa, ...); contact (alias goodman_nonlinear) and hyperbolic_interface read direct-shear\n"
         "curves (sigma_n_kPa, du_m, tau_kPa).\n"
         "\n"
         "options:\n"
         "  --form E_nu|E_B    duncan_chang: Poisson parameters G, F, d (E_nu, the default) or bulk\n"
         "                     modulus parameters K_b, m (E_B)\n"
         "  --k_s0 VALUE       contact: fix the initial shear stiffness (kPa/m, >= 0) instead of fitting it\n"
         "  --range MIN:MAX    keep only the curves whose sigma_3 (or sigma_n) lies in [MIN, MAX] kPa\n"
         "  -o, --out FILE     write the fragment to FILE (atomically) instead of stdout; the residual\n"
         "                     comments are echoed to stderr\n"
         "  -h, --help         this text\n"
         "\n"
         "exit status: 0 fitted, 1 bad input or curves that the model cannot fit (one line on stderr),\n"
         "  3 internal error\n";
}

int fit(const std::vector<std::string>& args) {
  namespace cal = calibration;
  if (args.empty()) throw Error(std::string("fit: no target given; allowed: ") + targets);
  std::string target = args[0];
  if (target == "goodman_nonlinear") target = "contact";
  if (target != "duncan_chang" && target != "contact" && target != "hyperbolic_interface")
    throw Error("fit: unknown target '" + args[0] + "'; allowed: " + targets);
  std::vector<std::string> files;
  std::string out;
  cal::DuncanChangForm form = cal::DuncanChangForm::E_nu;
  cal::ContactOptions copt;
  const std::string options = target == "duncan_chang" ? "--form E_nu|E_B, --range MIN:MAX, -o FILE"
                              : target == "contact"    ? "--k_s0 VALUE, --range MIN:MAX, -o FILE"
                                                       : "--range MIN:MAX, -o FILE";
  double lo = 0, hi = HUGE_VAL;
  std::string range; // as given
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* what) -> const std::string& {
      if (i + 1 >= args.size()) throw Error("fit: " + a + " needs " + what);
      return args[++i];
    };
    if (a == "-o" || a == "--out") {
      out = value("a file name");
    } else if (a == "--form" && target == "duncan_chang") {
      const std::string& v = value("E_nu or E_B");
      if (v == "E_nu")
        form = cal::DuncanChangForm::E_nu;
      else if (v == "E_B")
        form = cal::DuncanChangForm::E_B;
      else
        throw Error("fit: --form '" + v +
                    "'; allowed: E_nu (Poisson parameters G, F, d) or E_B (bulk modulus "
                    "parameters K_b, m)");
    } else if (a == "--k_s0" && target == "contact") {
      const std::string& v = value("a stiffness in kPa/m");
      double x = 0;
      const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
      if (ec != std::errc() || end != v.data() + v.size() || !std::isfinite(x) || x < 0)
        throw Error("fit: --k_s0 '" + v + "'; allowed: a number >= 0 (kPa/m)");
      copt.fix_k_s0 = true;
      copt.k_s0 = x;
    } else if (a == "--range") {
      const std::string& v = value("MIN:MAX in kPa");
      const auto colon = v.find(':');
      auto parse = [&](std::string_view t, double& x) {
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
        return !t.empty() && ec == std::errc() && end == t.data() + t.size() && std::isfinite(x);
      };
      if (colon == std::string::npos || !parse(std::string_view(v).substr(0, colon), lo) ||
          !parse(std::string_view(v).substr(colon + 1), hi) || !(lo <= hi))
        throw Error("fit: --range '" + v + "'; allowed: MIN:MAX with MIN <= MAX in kPa, e.g. 0:100");
      range = v;
    } else if (a.size() > 1 && a[0] == '-') {
      throw Error("fit " + target + ": unknown option '" + a + "'; allowed: " + options);
    } else {
      files.push_back(a);
    }
  }
  if (files.empty()) throw Error("fit " + target + ": no CSV file given (see docs/calibration.md)");

  std::string source, header = "# stratum fit";
  for (const auto& a : args) header += " " + a;
  for (const auto& f : files) source += (source.empty() ? "" : ", ") + f;

  auto keep = [&](double level) { return level >= lo && level <= hi; };
  auto none_left = [&](std::size_t n) {
    if (n == 0)
      throw Error(source + ": no curve has its " + (target == "duncan_chang" ? "sigma_3" : "sigma_n") +
                  " in --range " + range + " kPa");
  };
  if (!range.empty()) source += " (--range " + range + ")";
  std::string text;
  if (target == "duncan_chang") {
    std::vector<cal::TriaxialCurve> curves;
    for (const auto& f : files)
      for (auto& c : cal::read_triaxial_csv(f))
        if (keep(c.sigma3)) curves.push_back(std::move(c));
    none_left(curves.size());
    text = cal::to_toml(cal::fit_duncan_chang(curves, form, source), header);
  } else {
    std::vector<cal::ShearCurve> curves;
    for (const auto& f : files)
      for (auto& c : cal::read_direct_shear_csv(f))
        if (keep(c.sigma_n)) curves.push_back(std::move(c));
    none_left(curves.size());
    text = target == "contact" ? cal::to_toml(cal::fit_contact(curves, copt, source), header)
                               : cal::to_toml(cal::fit_hyperbolic_interface(curves, source), header);
  }
  if (out.empty()) {
    std::cout << text;
    return 0;
  }
  stratum::write_file_atomically(out, text);
  std::istringstream lines(text);
  for (std::string l; std::getline(lines, l);)
    if (l.rfind("#   ", 0) == 0 || l.rfind("# note", 0) == 0) std::cerr << l << "\n";
  std::cout << "written: " << out << "\n";
  return 0;
}

} // namespace stratum::cli
