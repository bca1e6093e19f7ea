// The hyperbolic_interface plugin's calibration target: direct-shear curves from the Clough-Duncan
// hyperbola tau = du/(1/(K_I gamma_w (sn/p_a)^n) + R_f du/tau_f), tau_f = c_a + sn tan delta (3.65)
// are fitted back through the plugin catalog; the generating parameters return to 1e-3 relative.
#include "calibration_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace test_hyperbolic_interface_calibration { // one namespace per test file: the test files build in
                                                  // batches (unity)

using Catch::Matchers::Contains;
using namespace stratum::testing::calibration_tests;
namespace cal = stratum::calibration;

TEST_CASE("fit: hyperbolic (Clough-Duncan) interface parameters", "[fit]") {
  const double K_I = 20000, n = 0.8, R_f = 0.85, c_a = 5, delta = 25;
  std::string csv = "sigma_n_kPa,du_m,tau_kPa\n";
  for (double sn : {25.0, 50.0, 100.0, 200.0}) {
    const double Ki = K_I * cal::gamma_w * std::pow(sn / pa, n), tf = c_a + sn * std::tan(delta * deg);
    const double uf = tf / Ki / (1 - R_f);
    for (int k = 0; k <= 12; ++k) {
      const double du = uf * k / 12;
      csv += num(sn) + "," + num(du) + "," + num(du / (1 / Ki + R_f * du / tf)) + "\n";
    }
  }
  const auto path = write("interface.csv", csv);
  const auto fit = fit_hyperbolic_interface(cal::read_direct_shear_csv(path), path);
  check_rel("K_I", fit.value("K_I"), K_I);
  check_rel("n", fit.value("n"), n);
  check_rel("R_f", fit.value("R_f"), R_f);
  check_rel("c_a", fit.value("c_a"), c_a);
  check_rel("delta", fit.value("delta"), delta);
  const std::string toml = stratum::write_fitted_toml(fit, "# test");
  CHECK_THAT(toml, Contains("\ngamma_w = 9.81\n"));
}

} // namespace test_hyperbolic_interface_calibration
