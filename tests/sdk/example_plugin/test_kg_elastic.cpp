// Tests of the example_kg_elastic plugin, built against the installed framework.
//  1. The material alone: the moduli mean what they say, and the tangent agrees with
//     central finite differences of the stress (the check every material should pass).
//  2. The plugin through the framework: a Lamé cylinder run in-process, u(a) against
//     the closed form.
// Prints what it checked; exits non-zero on the first failure.
//   usage: test_kg_elastic [scene.toml]   (default: lame_kg.toml beside the sources)
#include "kg_elastic.hpp"

#include <stratum/analysis.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

int failures = 0;

void expect(bool ok, const char* what, double got, double want) {
  std::printf("%-4s %-44s got %.9g  expected %.9g\n", ok ? "ok" : "FAIL", what, got, want);
  if (!ok) ++failures;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

/// stress after the increment `de` from the state (s_n, e_n); the tangent goes to *D when given.
stratum::Vec6 respond(const stratum::Material& m, const stratum::Vec6& s_n, const stratum::Vec6& e_n,
                      const stratum::Vec6& de, stratum::Mat6* D = nullptr) {
  std::vector<double> h_n(static_cast<std::size_t>(m.history_size())), h(h_n.size());
  m.init_history(s_n, h_n);
  stratum::Vec6 s;
  stratum::Mat6 t;
  stratum::MaterialOutput out{s, h, t};
  const stratum::Outcome r = m.update(stratum::MaterialInput{s_n, e_n, h_n, de, {}}, out);
  if (!r.ok()) throw std::runtime_error("update failed: " + r.message);
  if (D) *D = t;
  return s;
}

void material_checks() {
  const double K = 1000.0, G = 600.0;
  const example_kg::KGElastic m(K, G);

  // Volumetric strain e in all three directions: mean stress K * 3e. Engineering shear g: tau = G g.
  stratum::Vec6 zero = stratum::Vec6::Zero(), de = stratum::Vec6::Zero();
  de.head<3>().setConstant(1e-3);
  const stratum::Vec6 s_vol = respond(m, zero, zero, de);
  expect(rel(s_vol.head<3>().mean(), K * 3e-3) < 1e-12, "mean stress = K * volumetric strain",
         s_vol.head<3>().mean(), K * 3e-3);
  de.setZero();
  de[stratum::voigt::xy] = 2e-3;
  const stratum::Vec6 s_shear = respond(m, zero, zero, de);
  expect(rel(s_shear[stratum::voigt::xy], G * 2e-3) < 1e-12, "shear stress = G * engineering shear",
         s_shear[stratum::voigt::xy], G * 2e-3);

  // Tangent against central differences, from a loaded state with a general increment.
  stratum::Vec6 s_n, e_n;
  s_n << -50, -80, -60, 5, -3, 2;
  e_n << -1e-3, -2e-3, 5e-4, 1e-3, 0, -2e-4;
  de << 3e-4, -1e-4, 2e-4, -5e-4, 1e-4, 3e-4;
  stratum::Mat6 D;
  respond(m, s_n, e_n, de, &D);
  stratum::Mat6 fd;
  const double step = 1e-7;
  for (int j = 0; j < 6; ++j) {
    stratum::Vec6 dp = de, dm = de;
    dp[j] += step;
    dm[j] -= step;
    fd.col(j) = (respond(m, s_n, e_n, dp) - respond(m, s_n, e_n, dm)) / (2 * step);
  }
  const double err = (fd - D).norm() / D.norm();
  expect(err < 1e-6, "tangent vs finite differences (rel. error)", err, 0.0);
  expect((D - D.transpose()).norm() == 0.0, "tangent symmetric (|D - D^T|)", (D - D.transpose()).norm(), 0.0);

  // A NaN increment comes back as an Outcome, not an exception.
  de[0] = std::nan("");
  stratum::Vec6 s;
  stratum::Mat6 t;
  stratum::MaterialOutput out{s, {}, t};
  const stratum::Outcome r = m.update(stratum::MaterialInput{s_n, e_n, {}, de, {3, 1}}, out);
  expect(r.status == stratum::Status::non_finite, "NaN increment -> Status::non_finite",
         static_cast<double>(r.status), static_cast<double>(stratum::Status::non_finite));
}

void lame_check(const std::string& scene) {
  stratum::RunOptions options;
  // Our plugin first, then the installed ones (quad, newton, ...).
  options.plugin_dirs = {EXAMPLE_PLUGIN_DIR, STRATUM_PLUGIN_DIR};
  options.write_output = false;
  auto analysis = stratum::Analysis::from_file(scene, options);
  const stratum::RunSummary summary = analysis->run();
  if (!summary.outcome.ok()) {
    std::printf("FAIL run: %s: %s\n", stratum::to_string(summary.outcome.status),
                summary.outcome.message.c_str());
    ++failures;
    return;
  }
  const stratum::Model& model = analysis->model();
  int node = -1;
  for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n)
    if ((model.mesh.nodes[n] - Eigen::Vector2d(1.0, 0.0)).norm() < 1e-12) node = static_cast<int>(n);
  if (node < 0) {
    std::printf("FAIL no mesh node at (1, 0)\n");
    ++failures;
    return;
  }
  // Closed form with E and nu from K and G.
  const double K = 1000.0, G = 600.0, a = 1.0, b = 2.0, p = 1.0;
  const double E = 9 * K * G / (3 * K + G), nu = (3 * K - 2 * G) / (2 * (3 * K + G));
  const double exact = (1 + nu) * p * a * a / (E * (b * b - a * a)) * ((1 - 2 * nu) * a + b * b / a);
  const double u_a = model.u[2 * node]; // radial component of node (1, 0)
  std::printf("     Lamé cylinder: E = %g kPa, nu = %g, %zu nodes, relative error %.3g\n", E, nu,
              model.mesh.nodes.size(), rel(u_a, exact));
  expect(rel(u_a, exact) < 1e-3, "u_r(a) [m] within 1e-3 of the closed form", u_a, exact);
}

} // namespace

int main(int argc, char** argv) {
  try {
    material_checks();
    lame_check(argc > 1 ? argv[1] : EXAMPLE_SCENE);
  } catch (const std::exception& e) {
    std::printf("FAIL %s\n", e.what());
    return 1;
  }
  std::printf("%s\n", failures ? "test_kg_elastic: FAILED" : "test_kg_elastic: all checks passed");
  return failures ? 1 : 0;
}
