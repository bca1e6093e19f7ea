// stratum fit: model parameters from laboratory curves (docs/calibration.md).
//
//   stratum fit TARGET CURVES.csv [MORE.csv ...] [--OPTION VALUE ...] [--range MIN:MAX] [-o FILE.toml]
//
// A target is declared by the plugin that owns the parameters (stratum/calibration.hpp); the
// catalog's manifests say which library provides it, and only that library is opened. The
// target's options (--form E_B, --k_s0 5000) are those of its schema, checked like any plugin's
// parameters. --range MIN:MAX (kPa) keeps only the curves whose sigma_3 (or sigma_n) lies in
// [MIN, MAX], e.g. the loess' two parameter sets: --range 0:100 and --range 200:1000.
//
// The TOML fragment goes to stdout, or atomically to FILE with -o (then the residual
// comments are echoed to stderr).
#include "fit.hpp"

#include "files.hpp"
#include "guards.hpp"
#include "stratum/calibration.hpp"
#include "stratum/error.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"
#include "suggest.hpp"

#include <charconv>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <string_view>

namespace stratum::cli {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "(none: no plugin on the plugin path declares a calibration target)" : s;
}

bool parse_number(std::string_view t, double& x) {
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
  return !t.empty() && ec == std::errc() && end == t.data() + t.size() && std::isfinite(x);
}

/// "--form E_nu|E_B", "--k_s0 VALUE": one option of a target as the command line takes it.
std::string option_usage(const ParamSpec& spec) {
  std::string value;
  for (const auto& c : spec.choices) value += (value.empty() ? "" : "|") + c;
  return "--" + spec.name + " " + (value.empty() ? "VALUE" : value);
}

/// "--form E_nu|E_B, --range MIN:MAX, -o FILE": the options of a target.
std::string option_list(const Schema& schema) {
  std::string s;
  for (const auto& spec : schema.specs()) s += option_usage(spec) + ", ";
  return s + "--range MIN:MAX, -o FILE";
}

/// The value of the option `spec` as given on the command line, checked against its declaration.
ParamValue option_value(const ParamSpec& spec, const std::string& v) {
  const std::string unit = spec.unit.empty() || spec.unit == "-" ? "" : " " + spec.unit;
  switch (spec.type) {
  case ParamType::text: {
    if (spec.choices.empty()) return v;
    for (const auto& c : spec.choices)
      if (c == v) return v;
    std::string allowed;
    for (std::size_t i = 0; i < spec.choices.size(); ++i)
      allowed += (i == 0 ? "" : i + 1 == spec.choices.size() ? " or " : ", ") + spec.choices[i];
    throw Error("fit: --" + spec.name + " '" + v + "'; allowed: " + allowed + " (" + spec.meaning + ")" +
                did_you_mean(v, spec.choices));
  }
  case ParamType::real: {
    double x = 0;
    if (!parse_number(v, x) || !spec.in_range(x))
      throw Error("fit: --" + spec.name + " '" + v + "'; allowed: a number in " + spec.allowed() + unit +
                  " (" + spec.meaning + ")");
    return x;
  }
  case ParamType::integer: {
    long long x = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (v.empty() || ec != std::errc() || end != v.data() + v.size() ||
        !spec.in_range(static_cast<double>(x)))
      throw Error("fit: --" + spec.name + " '" + v + "'; allowed: an integer in " + spec.allowed() + unit);
    return x;
  }
  case ParamType::boolean:
    if (v == "true" || v == "false") return v == "true";
    throw Error("fit: --" + spec.name + " '" + v + "'; allowed: true or false");
  case ParamType::real_list:
    break;
  }
  throw Error("fit: --" + spec.name + ": a list option cannot be given on the command line");
}

} // namespace

std::string fit_help() {
  std::ostringstream o;
  o << "usage: stratum fit TARGET CURVES.csv [MORE.csv ...] [--OPTION VALUE ...] [--range MIN:MAX] [-o "
       "FILE]\n"
       "\n"
       "Fits a plugin's parameters to laboratory curves and prints them as a TOML fragment with the\n"
       "plugin's key names (docs/calibration.md). The plugin that owns the parameters declares the\n"
       "target (kind calibration in `stratum plugins`): what curves it reads and its options.\n"
       "\n"
       "targets on the plugin path:\n";
  PluginCatalog catalog(PluginCatalog::default_directories());
  Registry registry;
  for (const auto& t : catalog.known(PluginKind::calibration)) {
    try {
      catalog.require(registry, PluginKind::calibration, t);
    } catch (const Error& e) { // the help still shows, and says why a target is missing
      o << "  " << t << ": (not available: " << e.what() << ")\n";
      continue;
    }
    const Factory<Calibration>& f = registry.calibration(t);
    o << "  " << t << ": " << f.summary << "\n";
    for (const auto& spec : f.schema.specs())
      o << "      " << option_usage(spec) << ": " << spec.meaning
        << (spec.unit.empty() || spec.unit == "-" ? "" : " (" + spec.unit + ")") << "\n";
  }
  o << "\n"
       "options of every target:\n"
       "  --range MIN:MAX    keep only the curves whose sigma_3 (or sigma_n) lies in [MIN, MAX] kPa\n"
       "  -o, --out FILE     write the fragment to FILE (atomically) instead of stdout; the residual\n"
       "                     comments are echoed to stderr; never one of the CSV files\n"
       "  -h, --help         this text\n"
       "\n"
       "exit status: 0 fitted, 1 bad input or curves that the model cannot fit (one line on stderr),\n"
       "  2 FILE could not be written or memory ran out, 3 internal error\n";
  return o.str();
}

int fit(const std::vector<std::string>& args) {
  // The targets are found in the plugins' manifests; only the target's library is opened.
  PluginCatalog catalog(PluginCatalog::default_directories());
  const std::vector<std::string> targets = catalog.known(PluginKind::calibration);
  if (args.empty()) throw Error("fit: no target given; allowed: " + joined(targets));
  const std::string& target = args[0];
  bool found = false;
  for (const auto& t : targets) found = found || t == target;
  if (!found)
    throw Error("fit: unknown target '" + target + "'; allowed: " + joined(targets) +
                did_you_mean(target, targets));
  Registry registry;
  catalog.require(registry, PluginKind::calibration, target);
  const Factory<Calibration>& factory = registry.calibration(target);

  std::vector<std::string> files;
  std::string out;
  Params options;
  options.context = "fit " + target;
  std::map<std::string, std::string> given;
  double lo = 0, hi = HUGE_VAL;
  std::string range; // as given
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const std::string& what) -> const std::string& {
      if (i + 1 >= args.size()) throw Error("fit: " + a + " needs " + what);
      return args[++i];
    };
    const ParamSpec* spec =
        a.size() > 2 && a.rfind("--", 0) == 0 ? factory.schema.find(a.substr(2)) : nullptr;
    if (a == "-o" || a == "--out") {
      out = value("a file name");
    } else if (a == "--range") {
      const std::string& v = value("MIN:MAX in kPa");
      const auto colon = v.find(':');
      if (colon == std::string::npos || !parse_number(std::string_view(v).substr(0, colon), lo) ||
          !parse_number(std::string_view(v).substr(colon + 1), hi) || !(lo <= hi))
        throw Error("fit: --range '" + v + "'; allowed: MIN:MAX with MIN <= MAX in kPa, e.g. 0:100");
      range = v;
    } else if (spec) {
      const std::string& v = value(spec->choices.empty() ? "a value" : "one of its values");
      if (given.count(spec->name)) throw Error("fit " + target + ": " + a + " given twice");
      given[spec->name] = v;
      options.set(spec->name, option_value(*spec, v), SourceLocation{"command line " + a, 0, 0});
    } else if (a.size() > 1 && a[0] == '-') {
      std::vector<std::string> names = {"--range", "-o", "--out"};
      for (const auto& s : factory.schema.specs()) names.push_back("--" + s.name);
      throw Error("fit " + target + ": unknown option '" + a + "'; allowed: " + option_list(factory.schema) +
                  did_you_mean(a, names));
    } else {
      files.push_back(a);
    }
  }
  if (files.empty()) throw Error("fit " + target + ": no CSV file given (see docs/calibration.md)");
  // Options not given take their declared defaults (location unknown: the plugin can tell).
  for (const auto& spec : factory.schema.specs())
    if (!given.count(spec.name)) {
      if (spec.required())
        throw Error("fit " + target + ": --" + spec.name + " is required (" + spec.meaning + ")");
      options.set(spec.name, *spec.fallback);
    }
  const std::unique_ptr<Calibration> calibration = factory.create(options);

  if (!out.empty()) {
    refuse_output_over_inputs("-o", out, files);
    refuse_output_below_file("-o", out);
  }
  std::string header = "# stratum fit";
  for (const auto& a : args) header += " " + a;
  LabCurves curves;
  for (const auto& f : files) curves.source += (curves.source.empty() ? "" : ", ") + f;
  auto keep = [&](double level) { return level >= lo && level <= hi; };
  const bool triaxial = calibration->lab_test() == LabTest::triaxial;
  if (triaxial) {
    for (const auto& f : files)
      for (auto& c : calibration::read_triaxial_csv(f))
        if (keep(c.sigma3)) curves.triaxial.push_back(std::move(c));
  } else {
    for (const auto& f : files)
      for (auto& c : calibration::read_direct_shear_csv(f))
        if (keep(c.sigma_n)) curves.direct_shear.push_back(std::move(c));
  }
  if (!range.empty()) curves.source += " (--range " + range + ")";
  if (curves.triaxial.empty() && curves.direct_shear.empty())
    throw Error(curves.source + ": no curve has its " + (triaxial ? "sigma_3" : "sigma_n") + " in --range " +
                range + " kPa");
  const std::string text = in_phase("fitting " + target + " to " + curves.source,
                                    [&] { return write_fitted_toml(calibration->fit(curves), header); });
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
