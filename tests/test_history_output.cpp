// Named history variables (Material::history_names(), "name [unit]") reach the integration-point
// VTK output: a block under geostatic stress with the cap, Duncan-Chang and Modified Cam-Clay
// soils, whose initial history has a closed form at every point, written and read back with VTK.
#include "scene_helpers.hpp"

#include <catch2/catch.hpp>

#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>
#include <unistd.h>
#include <vector>

namespace test_history_output {

namespace fs = std::filesystem;
using namespace stratum;

namespace {

constexpr double gamma_soil = 18.0, K0 = 0.6, surface = 1.0; // ground 1 m above the block top

/// The geostatic stress at depth y, compression positive: vertical and horizontal.
struct Geo {
  double sv, sh;
};
Geo geostatic(double y) {
  const double sv = gamma_soil * (surface - y);
  return {sv, K0 * sv};
}

/// Runs tests/scenes/history/<name>.toml (history/block.toml with a material) and returns the last
/// integration-point cloud read back by VTK.
vtkSmartPointer<vtkPolyData> run_and_read(const std::string& name) {
  const fs::path out =
      fs::temp_directory_path() / ("stratum_history_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(out);
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = out.string();
  auto a = Analysis::from_file(stratum::testing::scene_path("history/" + name + ".toml"), o);
  const auto s = a->run();
  INFO(s.outcome.message);
  REQUIRE(s.outcome.ok());
  int last = -1;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string n = e.path().filename().string();
    const auto at = n.find("_ip_");
    if (at != std::string::npos) last = std::max(last, std::stoi(n.substr(at + 4)));
  }
  REQUIRE(last >= 1);
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName((out / (name + "_ip_" + std::to_string(last) + ".vtp")).string().c_str());
  reader->Update();
  vtkSmartPointer<vtkPolyData> cloud = reader->GetOutput();
  REQUIRE(cloud->GetNumberOfPoints() == 8 * 4);
  fs::remove_all(out);
  return cloud;
}

/// Checks a named scalar field at every point against expected(y), relative tolerance tol.
void check_field(vtkPolyData* cloud, const char* name, const std::function<double(double)>& expected,
                 double tol) {
  vtkDataArray* f = cloud->GetPointData()->GetArray(name);
  INFO("field " << name);
  REQUIRE(f != nullptr);
  REQUIRE(f->GetNumberOfComponents() == 1);
  for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); ++i) {
    double x[3];
    cloud->GetPoint(i, x);
    const double want = expected(x[1]), got = f->GetComponent(i, 0);
    INFO("point at y = " << x[1] << ": " << got << " vs " << want);
    CHECK(std::abs(got - want) <= tol * std::max(1.0, std::abs(want)));
  }
}

} // namespace

TEST_CASE("history output: the cap position kappa of the cap model, with its unit", "[output][cap_sandler]") {
  // A cap far above the geostatic stresses (Z = 2000 kPa in J1): no point widens it, so kappa is
  // the root of X(kappa) = kappa + R (A - C exp(-B kappa)) = Z everywhere (2.147)-(2.148).
  const double A = 190.0, B = 0.0015, C = 110.0, R = 2.5, Z = 2000.0;
  auto cloud = run_and_read("cap");
  double lo = -1000.0, hi = Z; // X is increasing in kappa
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (mid + R * (A - C * std::exp(-B * mid)) < Z ? lo : hi) = mid;
  }
  const double kappa = 0.5 * (lo + hi);
  check_field(
      cloud, "kappa [kPa]", [&](double) { return kappa; }, 1e-9);
  check_field(
      cloud, "eps_v_p [-]", [](double) { return 0.0; }, 1e-12);
  check_field(
      cloud, "regime [-]", [](double) { return 0.0; }, 0.0);
}

TEST_CASE("history output: the largest stress level and deviator of Duncan-Chang, with units",
          "[output][duncan_chang]") {
  // S = q / q_f with q_f = 2 (c cos phi + sigma_3 sin phi) / (1 - sin phi) (2.28) at the
  // geostatic stress: sigma_1 the vertical, sigma_3 = K0 sigma_1.
  const double phi = 30.0 * std::numbers::pi / 180.0, c = 10.0;
  auto cloud = run_and_read("duncan_chang");
  auto q = [](double y) {
    const Geo g = geostatic(y);
    return g.sv - g.sh;
  };
  auto S = [&](double y) {
    const double s3 = geostatic(y).sh;
    return q(y) / (2.0 * (c * std::cos(phi) + s3 * std::sin(phi)) / (1.0 - std::sin(phi)));
  };
  check_field(cloud, "q_max [kPa]", q, 1e-6);
  check_field(cloud, "S_max [-]", S, 1e-6);
}

TEST_CASE("history output: the preconsolidation pressure of Modified Cam-Clay, with its unit",
          "[output][cam_clay]") {
  // p_c0 = ocr (p + q^2 / (M^2 p)) at the geostatic p and q (the ellipse through the stress).
  const double M = 1.2, ocr = 1.5;
  auto cloud = run_and_read("cam_clay");
  check_field(
      cloud, "p_c [kPa]",
      [&](double y) {
        const Geo g = geostatic(y);
        const double p = (g.sv + 2.0 * g.sh) / 3.0, qq = g.sv - g.sh;
        return ocr * (p + qq * qq / (M * M * p));
      },
      1e-6);
}

} // namespace test_history_output
