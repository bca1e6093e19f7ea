// Tests of calibration (stratum/calibration.hpp, docs/calibration.md): synthetic curves generated
// from the closed forms are written as CSV, read back and fitted by the calibration targets of
// the plugins that own the parameters, found through the plugin catalog as `stratum fit` finds
// them (helpers: tests/calibration_helpers.hpp). Each target's recovery of its generating
// parameters (1e-3 relative) is tested beside its plugin: plugins/duncan_chang/tests/,
// plugins/goodman_nonlinear/tests/, plugins/hyperbolic_interface/tests/. Here: curves that cannot
// be fitted and malformed CSV give one clear message (with file:line for the CSV), a target is
// found through the plugin that declares it, and the framework's sources hold none of the
// plugins' key names.
//
// Closed forms (compression positive, p_a = 100 kPa):
//   Duncan-Chang  q = eps/(1/E_i + R_f eps/q_f), E_i = K p_a (s3/p_a)^n,
//                 q_f = 2(c cos phi + s3 sin phi)/(1 - sin phi)          (2.22)-(2.28)
//                 -eps_3 = f eps/(1 - d eps), f = G - F log10(s3/p_a)   (2.32)-(2.33)
//                 eps_v = q/(3B), B = K_b p_a (s3/p_a)^m                 (Duncan et al. 1980)
//   Goodman       K_s = k_s0 + alpha (sn/p_a)^m, tau_p = c_p + sn tan phi_p,
//                 tau_r = c_r + sn tan phi_r                             (3.53)-(3.54)
//   Clough-Duncan tau = du/(1/(K_I gamma_w (sn/p_a)^n) + R_f du/tau_f), tau_f = c_a + sn tan delta (3.65)
#include "calibration_helpers.hpp"
#include "stratum/calibration.hpp"
#include "stratum/error.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/registry.hpp"

#include <catch2/catch.hpp>

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

namespace test_calibration {

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using namespace stratum::testing::calibration_tests;
namespace fs = std::filesystem;
namespace cal = stratum::calibration;

TEST_CASE("fit: curves that cannot be fitted give one clear message", "[fit]") {
  const DC p{500, 0.82, 0.80, 26, 10, 0.18, 0.22, 20, 0, 0};
  auto fit_text = [](const std::string& name, const std::string& csv, const std::string& form = "E_nu") {
    const auto path = write(name, csv);
    return error_of([&] { (void)fit_duncan_chang(cal::read_triaxial_csv(path), form, path); });
  };
  // a single sigma_3
  auto e = fit_text("single.csv", triax_header + triaxial_rows(p, 50, 10, false));
  CHECK_THAT(e, Contains("all curves are at sigma_3 = 50 kPa; K, n and c, phi need curves at two or more"));
  // too few points
  e = fit_text("few.csv", triax_header + triaxial_rows(p, 50, 10, false) + triaxial_rows(p, 100, 2, false));
  CHECK_THAT(
      e, Contains(":13: curve at sigma_3 = 100 kPa: 2 points with eps_axial > 0 and q > 0 up to the peak; "
                  "allowed: at least 3"));
  // a straight line is not a hyperbola
  std::string lin = triax_header;
  for (double s3 : {50.0, 100.0})
    for (int k = 0; k <= 5; ++k) lin += num(s3) + "," + num(0.001 * k) + "," + num(30 * k * s3 / 50) + ",0\n";
  e = fit_text("linear.csv", lin);
  CHECK_THAT(e, Contains("curve at sigma_3 = 50 kPa: not hyperbolic: Kondner's transform"));
  // initial modulus falling with sigma_3: n < 0
  DC neg = p;
  neg.n = -0.5;
  e = fit_text("neg_n.csv",
               triax_header + triaxial_rows(neg, 50, 10, false) + triaxial_rows(neg, 200, 10, false));
  CHECK_THAT(e, Contains("n = -0.5 < 0: the initial stiffness falls as sigma_3 grows; allowed: n >= 0"));
  // strengths above the asymptotes: long plateaus close to q_ult, then a last point at
  // 1.3 q_ult on every curve, give R_f > 1
  std::string jump = triax_header;
  for (double s3 : {50.0, 100.0}) {
    const double Ei = p.K * pa * std::pow(s3 / pa, p.n), qu = q_f(p, s3) / p.R_f;
    for (int k = 0; k <= 20; ++k) {
      const double e1 = 0.5 * k * k / 400;
      jump += num(s3) + "," + num(e1) + "," + num(e1 / (1 / Ei + e1 / qu)) + ",0.001\n";
    }
    jump += num(s3) + ",0.51," + num(1.3 * qu) + ",0.001\n";
  }
  e = fit_text("jump.csv", jump);
  INFO(e);
  CHECK_THAT(e, Contains("> 1: the peaks of q lie above the hyperbolas' asymptotes; allowed: 0 < R_f <= 1"));
  // no volumetric information for the Poisson parameters
  std::string nov = "sigma3_kPa,eps_axial,q_kPa\n";
  for (double s3 : {50.0, 100.0}) {
    std::istringstream rows(triaxial_rows(p, s3, 8, false));
    for (std::string l; std::getline(rows, l);) nov += l.substr(0, l.rfind(',')) + "\n";
  }
  e = fit_text("novol.csv", nov);
  CHECK_THAT(e, Contains("form E_nu needs the column eps_vol or eps_radial"));
  // a second peak
  std::string twin = triax_header + triaxial_rows(p, 100, 8, false) + triaxial_rows(p, 50, 8, false);
  twin += "50,0.05,90,0\n50,0.06,200,0\n";
  e = fit_text("twin.csv", twin);
  CHECK_THAT(e, Contains("twin.csv:20:1 q_kPa = 90 falls below the earlier "));
  // dilation from the start for E_B
  DC dil = p;
  dil.K_b = -50; // eps_v = q/(3B) < 0
  dil.m = 0;
  e = fit_text("dilate.csv",
               triax_header + triaxial_rows(dil, 50, 10, true) + triaxial_rows(dil, 100, 10, true), "E_B");
  CHECK_THAT(e, Contains("no contraction before 70 % of the strength"));
  // contact: strengths falling with sigma_n
  const auto path =
      write("falling.csv", "sigma_n_kPa,du_m,tau_kPa\n25,0,0\n25,0.001,10\n25,0.002,20\n25,0.003,30\n"
                           "50,0,0\n50,0.001,12\n50,0.002,18\n50,0.003,20\n");
  e = error_of([&] { (void)fit_contact(cal::read_direct_shear_csv(path), {}, path); });
  CHECK_THAT(e, Contains("the peak strengths do not grow with sigma_n"));
}

TEST_CASE("fit: malformed CSV is located by line and column", "[fit]") {
  auto err = [](const std::string& name, const std::string& csv) {
    const auto path = write(name, csv);
    return std::make_pair(path, error_of([&] { (void)cal::read_triaxial_csv(path); }));
  };
  auto [p1, e1] = err("bad_number.csv", "# a comment\nsigma3_kPa,eps_axial,q_kPa\n50,0,0\n50,0.01,abc\n");
  CHECK(e1 ==
        p1 + ":4:9 'abc' in column q_kPa is not a finite number (allowed: decimal numbers such as 0.012 or "
             "1.2e-2)");
  auto [p2, e2] = err("fields.csv", "sigma3_kPa,eps_axial,q_kPa\n50,0,0\n\n50,0.01\n");
  CHECK(e2 ==
        p2 + ":4:1 2 fields, the header has 3 (allowed: one number per header column, comma-separated)");
  auto [p3, e3] = err("header.csv", "sigma3_kPa, eps_axial, q, eps_vol\n");
  CHECK_THAT(e3, StartsWith(p3 + ":1:24 unknown column 'q' in the header; allowed: required sigma3_kPa, "
                                 "eps_axial, q_kPa; optional eps_vol, eps_radial"));
  auto [p4, e4] = err("missing.csv", "sigma3_kPa,eps_axial\n");
  CHECK_THAT(e4, StartsWith(p4 + ":1:1 the header has no column 'q_kPa'"));
  auto [p5, e5] = err("percent.csv", "sigma3_kPa,eps_axial,q_kPa\n50,0,0\n50,2.5,30\n");
  CHECK(
      e5 ==
      p5 +
          ":3:4 eps_axial = 2.5; allowed: 0 <= eps_axial < 1 (a fraction, compression positive: 0.05 = 5 %)");
  auto [p6, e6] = err("order.csv", "sigma3_kPa,eps_axial,q_kPa\n50,0,0\n50,0.02,30\n50,0.01,35\n");
  CHECK_THAT(e6, StartsWith(p6 + ":4:4 eps_axial = 0.01 does not increase (previous point 0.02 on line 3)"));
  auto [p7, e7] = err("negative.csv", "sigma3_kPa,eps_axial,q_kPa\n-50,0,0\n");
  CHECK(e7 == p7 + ":2:1 sigma3_kPa = -50; allowed: > 0 (compression positive, kPa)");
  auto [p10, e10] = err("semicolon.csv", "sigma3_kPa;eps_axial;q_kPa\n50;0;0\n");
  CHECK_THAT(e10, StartsWith(p10 + ":1:1 the header 'sigma3_kPa;eps_axial;q_kPa' is not comma-separated"));
  // a byte-order mark, CRLF line ends, blanks and a leading '+' are accepted
  const auto p11 =
      write("bom.csv", "\xEF\xBB\xBFsigma3_kPa , eps_axial,q_kPa\r\n 50, 0, 0\r\n50,+1e-3,+12.5\r\n");
  const auto c11 = cal::read_triaxial_csv(p11);
  REQUIRE(c11.size() == 1);
  CHECK(c11[0].q == std::vector<double>{0.0, 12.5});
  CHECK(c11[0].eps_a[1] == 1e-3);
  CHECK(c11[0].lines == std::vector<int>{2, 3});
  auto [p8, e8] = err("empty.csv", "# nothing\n\n");
  CHECK_THAT(e8, Contains("empty file: no header row"));
  const auto p9 = write("shear_bad.csv", "sigma_n_kPa,du_m,tau_kPa\n25,0,0\n25,0.001,-3\n");
  CHECK(error_of([&] { (void)cal::read_direct_shear_csv(p9); }) ==
        p9 + ":3:10 tau_kPa = -3; allowed: >= 0 (shear in one direction)");
  CHECK(error_of([] { (void)cal::read_triaxial_csv("/nonexistent/curves.csv"); }) ==
        "cannot open data file '/nonexistent/curves.csv'");
}

TEST_CASE("fit: a calibration target is found through the plugin that declares it", "[fit]") {
  stratum::PluginCatalog catalog({STRATUM_PLUGIN_DIR});
  const auto targets = catalog.known(stratum::PluginKind::calibration);
  for (const char* t : {"contact", "duncan_chang", "goodman_nonlinear", "hyperbolic_interface"})
    CHECK(std::find(targets.begin(), targets.end(), t) != targets.end());
  // Only the library that declares the target is opened, and it is the model's own plugin.
  stratum::Registry registry;
  catalog.require(registry, stratum::PluginKind::calibration, "duncan_chang");
  REQUIRE(catalog.opened().size() == 1);
  CHECK(fs::path(catalog.opened()[0]).filename() == "stratum_duncan_chang.so");
  CHECK(registry.has(stratum::PluginKind::material, "duncan_chang"));
  CHECK(!registry.has(stratum::PluginKind::calibration, "hyperbolic_interface"));
  CHECK(registry.calibration("duncan_chang").schema.find("form") != nullptr); // --form E_nu|E_B
  catalog.require(registry, stratum::PluginKind::calibration, "contact");
  CHECK(fs::path(catalog.opened().back()).filename() == "stratum_goodman_nonlinear.so");
  // An unknown target: the known ones and the nearest name.
  CHECK_THAT(
      error_of([&] { catalog.require(registry, stratum::PluginKind::calibration, "duncan_chnag"); }),
      StartsWith("unknown calibration 'duncan_chnag'; known: contact, duncan_chang, goodman_nonlinear, "
                 "hyperbolic_interface") &&
          Contains("did you mean 'duncan_chang'?"));
}

TEST_CASE("fit: the framework's sources hold none of the plugins' key names", "[fit]") {
  // The TOML keys the calibration targets write belong to their plugins (and the model names
  // to the manifests): no string literal of the framework (SDK headers, kernel, program) spells
  // them. Left out: short names (K, n, c, m, ...), too common to tell apart; R_f, the failure
  // ratio of the toolkit's own hyperbola (its messages name it); p_a and gamma_w, physical
  // constants that the units reference names as examples.
  const std::vector<std::string> keys = {
      "K_b", "k_s0", "c_peak", "phi_peak",     "c_residual",        "phi_residual",        "K_I",
      "c_a", "E_nu", "E_B",    "duncan_chang", "goodman_nonlinear", "hyperbolic_interface"};
  std::vector<std::string> found;
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(STRATUM_SOURCE_DIR) / "framework")) {
    const auto ext = e.path().extension();
    if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
    ++files;
    std::ifstream in(e.path());
    int line = 0;
    for (std::string text; std::getline(in, text);) {
      ++line;
      // the string literals of the line's code (comments may name models; literals may not)
      std::vector<std::string> literals;
      bool in_literal = false;
      for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (!in_literal && c == '/' && i + 1 < text.size() && text[i + 1] == '/') break;
        if (!in_literal && c == '\'' && i + 2 < text.size()) { // a character literal: '"', '\\'
          i += text[i + 1] == '\\' ? 3 : 2;
          continue;
        }
        if (c == '"') {
          in_literal = !in_literal;
          if (in_literal) literals.emplace_back();
        } else if (in_literal) {
          if (c == '\\' && i + 1 < text.size()) ++i; // an escaped character
          literals.back() += text[i];
        }
      }
      for (const auto& lit : literals)
        for (const auto& k : keys)
          if (std::regex_search(lit, std::regex("(^|[^A-Za-z0-9_])" + k + "($|[^A-Za-z0-9_])")))
            found.push_back(e.path().string() + ":" + std::to_string(line) + ": " + k + " in \"" + lit +
                            "\"");
    }
  }
  CHECK(files > 50);
  INFO("found: " << [&] {
    std::string s;
    for (const auto& f : found) s += "\n  " + f;
    return s;
  }());
  CHECK(found.empty());
}

} // namespace test_calibration
