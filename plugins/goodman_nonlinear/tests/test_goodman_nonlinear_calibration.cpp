// The goodman_nonlinear plugin's calibration target: direct-shear curves from the closed forms
// K_s = k_s0 + alpha (sn/p_a)^m, tau_p = c_p + sn tan phi_p, tau_r = c_r + sn tan phi_r ((3.53)-(3.54))
// are fitted back through the plugin catalog; the generating parameters return to 1e-3 relative.
#include "calibration_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace test_goodman_nonlinear_calibration { // one namespace per test file: the test files build in batches
                                               // (unity)

using Catch::Matchers::Contains;
using namespace stratum::testing::calibration_tests;
namespace cal = stratum::calibration;

TEST_CASE("fit: Goodman contact parameters from direct-shear curves", "[fit]") {
  const Goodman g{5000, 20000, 0.89, 10, 29, 2, 24};
  std::string csv = "sigma_n_kPa,du_m,tau_kPa\n";
  for (double sn : {25.0, 50.0, 75.0, 100.0}) csv += shear_rows(g, sn);
  const auto path = write("goodman.csv", csv);
  const auto fit = fit_contact(cal::read_direct_shear_csv(path), {}, path);
  check_rel("k_s0", fit.value("k_s0"), g.k_s0);
  check_rel("alpha", fit.value("alpha"), g.alpha);
  check_rel("m", fit.value("m"), g.m);
  check_rel("c_peak", fit.value("c_peak"), g.c_p);
  check_rel("phi_peak", fit.value("phi_peak"), g.phi_p);
  check_rel("c_residual", fit.value("c_residual"), g.c_r);
  check_rel("phi_residual", fit.value("phi_residual"), g.phi_r);
  const std::string toml = stratum::write_fitted_toml(fit, "# test");
  for (const char* key : {"k_s0", "alpha", "m", "c_peak", "phi_peak", "c_residual", "phi_residual", "p_a"})
    CHECK_THAT(toml, Contains(std::string("\n") + key + " = "));

  // Two normal stresses (the thesis reading K_so = 0): alpha and m through both slopes.
  const Goodman g0{0, 400, 0.89, 10, 29, 10, 29};
  const auto path2 =
      write("goodman2.csv", "sigma_n_kPa,du_m,tau_kPa\n" + shear_rows(g0, 25) + shear_rows(g0, 75));
  const auto fit2 = fit_contact(cal::read_direct_shear_csv(path2), {}, path2);
  CHECK(fit2.value("k_s0") == 0.0);
  check_rel("alpha", fit2.value("alpha"), g0.alpha);
  check_rel("m", fit2.value("m"), g0.m);
  check_rel("phi_peak", fit2.value("phi_peak"), g0.phi_p);
  check_rel("c_residual", fit2.value("c_residual"), g0.c_r);

  // slopes that want k_s0 < 0: refitted with k_s0 = 0, and said so
  const Goodman gneg{-2000, 20000, 0.89, 10, 29, 2, 24};
  std::string csvneg = "sigma_n_kPa,du_m,tau_kPa\n";
  for (double sn : {25.0, 50.0, 75.0}) csvneg += shear_rows(gneg, sn);
  const auto pathneg = write("goodman_neg.csv", csvneg);
  const auto fitneg = fit_contact(cal::read_direct_shear_csv(pathneg), {}, pathneg);
  CHECK(fitneg.value("k_s0") == 0.0);
  CHECK(fitneg.value("m") > g.m); // a steeper power law takes the place of the negative offset
  CHECK_THAT(stratum::write_fitted_toml(fitneg, "#"),
             Contains("# note: the free fit gave k_s0 = -2000 kPa/m < 0; refitted with k_s0 = 0"));

  // k_s0 held at a given value
  const auto fit3 = fit_contact(cal::read_direct_shear_csv(path), 5000.0, path);
  CHECK(fit3.value("k_s0") == 5000.0);
  check_rel("alpha", fit3.value("alpha"), g.alpha);
  check_rel("m", fit3.value("m"), g.m);
}

} // namespace test_goodman_nonlinear_calibration
