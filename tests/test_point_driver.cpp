// The material-point driver on linear elasticity: every path kind against its
// closed form, and malformed point files.
#include "stratum/point_driver.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace test_point_driver {

using namespace stratum;

TEST_CASE("point driver: elastic closed forms for every path kind", "[point]") {
  const std::string file = std::string(STRATUM_SOURCE_DIR) + "/inputs/point/elastic_paths.toml";
  auto d = PointDriver::from_file(file, {STRATUM_PLUGIN_DIR});
  const auto r = d->run();
  REQUIRE(r.outcome.ok());
  REQUIRE(r.rows.size() == 1 + 10 + 10 + 5 + 5 + 4 + 2);
  const double E = 1e4, nu = 0.25, K = E / (3 * (1 - 2 * nu)), G = E / (2 * (1 + nu));
  const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)), tol = 1e-9;
  // 1: drained triaxial: uniaxial stress change E * eps, radial strain -nu eps.
  const auto& a = r.rows[10];
  CHECK(a.stress[1] - (-100) == Approx(E * -0.01).epsilon(tol));
  CHECK(a.stress[0] == Approx(-100).epsilon(tol));
  CHECK(a.strain[0] == Approx(nu * 0.01).epsilon(tol));
  // 2: undrained back to eps_axial = 0 with eps_v unchanged: deviatoric unloading.
  const auto& b = r.rows[20];
  CHECK(b.strain[1] == Approx(0).margin(1e-14));
  const double ev_b = b.strain[0] + b.strain[1] + b.strain[2];
  CHECK(ev_b == Approx(a.strain[0] + a.strain[1] + a.strain[2]).epsilon(tol));
  // 3: oedometer: axial stress change M de, radial lambda de.
  const auto& c = r.rows[25];
  CHECK(c.stress[1] - b.stress[1] == Approx(M * -0.005).epsilon(tol));
  CHECK(c.stress[0] - b.stress[0] == Approx((M - 2 * G) * -0.005).epsilon(tol));
  // 4: isotropic unloading by 50 kPa: de_v = 50 / K (tension positive).
  const auto& e = r.rows[30];
  CHECK((e.strain[0] + e.strain[1] + e.strain[2]) - (c.strain[0] + c.strain[1] + c.strain[2]) ==
        Approx(50.0 / K).epsilon(tol));
  CHECK((e.stress[0] + e.stress[1] + e.stress[2]) / 3 - (c.stress[0] + c.stress[1] + c.stress[2]) / 3 ==
        Approx(50.0).epsilon(tol));
  // 5: simple shear: tau = G gamma, sigma_yy unchanged.
  const auto& f = r.rows[34];
  CHECK(f.stress[3] == Approx(G * 0.002).epsilon(tol));
  CHECK(f.stress[1] == Approx(e.stress[1]).epsilon(tol));
  // 6: mixed = drained triaxial again.
  const auto& g = r.rows[36];
  CHECK(g.stress[1] - f.stress[1] == Approx(E * -0.001).epsilon(tol));

  const auto csv = std::filesystem::temp_directory_path() / "stratum_point_test.csv";
  PointDriver::write_csv(r, csv.string());
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  CHECK(header.find("step,path,eps_xx") == 0);
  CHECK(header.find("eps_axial,eps_vol,p_kPa,q_kPa") != std::string::npos);
  int lines = 0;
  for (std::string l; std::getline(in, l);) ++lines;
  CHECK(lines == 37);
  std::filesystem::remove(csv);
}

TEST_CASE("point driver: malformed point files give located one-line errors", "[point][cli]") {
  auto msg = [](const std::string& text) {
    try {
      PointDriver::from_string(text, "p.toml", {STRATUM_PLUGIN_DIR});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string mat = "[material]\nmodel = \"linear_elastic\"\nE = 100.0\n";
  CHECK(msg(mat + "[[paths]]\ntype = \"triaxial\"\n") ==
        "p.toml:5:8 [[paths]] #1 type = \"triaxial\" is not allowed; allowed: one of: triaxial_drained, "
        "triaxial_undrained, oedometer, isotropic, simple_shear, mixed");
  CHECK(
      msg(mat + "[[paths]]\ntype = \"oedometer\"\n") ==
      "p.toml:4:1 [[paths]] #1 missing required parameter 'axial_strain' (total axial strain of the segment, "
      "tension positive (compression < 0))");
  CHECK(msg(mat + "[[paths]]\ntype = \"oedometer\"\naxial_strain = -0.1\nsteps = 0\n") ==
        "p.toml:7:9 [[paths]] #1 steps = 0 is outside [1, 2147483647]");
  // 2^32 + 1 passes a 64-bit range check and is 1 when cut to 32 bits: refused at its value.
  CHECK(msg(mat + "[[paths]]\ntype = \"oedometer\"\naxial_strain = -0.1\nsteps = 4294967297\n") ==
        "p.toml:7:9 [[paths]] #1 steps = 4294967297 is outside [1, 2147483647]");
  // Every row stays in memory until the CSV is written: a run that cannot fit is refused up
  // front, at the longest path's steps, with the estimate (about 1 kB per row; 2^31 - 1 rows
  // would need 2.1 TB, more than any machine this runs on).
  const std::string big = msg(mat + "[[paths]]\ntype = \"oedometer\"\naxial_strain = -0.1\nsteps = 10\n" +
                              "[[paths]]\ntype = \"oedometer\"\naxial_strain = 0.1\nsteps = 2147483647\n");
  CHECK(big.find("p.toml:11:9 the paths' 2147483657 steps would need about 2147.5 GB of memory") == 0);
  CHECK(big.find("use fewer steps") != std::string::npos);
  CHECK(msg(mat + "[initial]\nstress = [1.0, 2.0]\n[[paths]]\ntype = \"oedometer\"\naxial_strain = 0.1\n") ==
        "p.toml:5:10 [initial] stress must have 6 numbers (xx, yy, zz, xy, yz, zx)");
  CHECK(msg("[material]\nmodel = \"plastic\"\n")
            .find("p.toml:2:9 [material] model = \"plastic\": unknown material "
                  "'plastic'; known: ") == 0);
}

TEST_CASE("point driver: every example in inputs/point runs, MCC examples reach M1 failure", "[point]") {
  int examples = 0;
  for (const auto& e :
       std::filesystem::directory_iterator(std::string(STRATUM_SOURCE_DIR) + "/inputs/point")) {
    if (e.path().extension() != ".toml") continue;
    ++examples;
    auto d = PointDriver::from_file(e.path().string(), {STRATUM_PLUGIN_DIR});
    const auto r = d->run();
    INFO(e.path().filename().string() << ": " << r.outcome.message);
    CHECK(r.outcome.ok());
    const auto& last = r.rows.back().stress;
    const double p = -(last[0] + last[1] + last[2]) / 3;
    const double q = std::abs(last[1] - last[0]);
    const double M = 1.2, lambda = 0.077, kappa = 0.0066, p0 = 200;
    if (e.path().filename() == "mcc_undrained.toml") {
      const double Lambda = (lambda - kappa) / lambda, pf = p0 * std::pow(0.5, Lambda);
      CHECK(p == Approx(pf).epsilon(1e-4)); // 106.121
      CHECK(q == Approx(M * pf).epsilon(1e-4));
    }
    if (e.path().filename() == "drained_triaxial_mcc.toml") {
      const double pf = 3 * p0 / (3 - M); // 333.333
      CHECK(p == Approx(pf).epsilon(1e-3));
      CHECK(q == Approx(M * pf).epsilon(1e-3));
    }
  }
  CHECK(examples >= 3);
}

TEST_CASE("point driver: a state without stiffness is a failure, not rows of zero stress", "[point]") {
  // Found on 997ba04: a Duncan-Chang point from p = 0 wrote 300 rows of zero stress with exit 0
  // (E_i = K p_a (sigma_3 / p_a)^n = 0 at sigma_3 = 0). The same point from p = 25 kPa runs.
  const std::string mat = "[material]\nmodel = \"duncan_chang\"\nK = 500.0\nn = 0.82\nR_f = 0.8\nphi = 26.0\n"
                          "c = 0.0\nK_ur = 800.0\nG = 0.18\nF = 0.22\nd = 20.0\n";
  const std::string path = "[[paths]]\ntype = \"triaxial_drained\"\naxial_strain = -0.01\nsteps = 20\n";
  const auto zero =
      PointDriver::from_string(mat + "[initial]\np = 0.0\n" + path, "p.toml", {STRATUM_PLUGIN_DIR})->run();
  CHECK_FALSE(zero.outcome.ok());
  CHECK(zero.outcome.message.find("no stiffness at its initial state") != std::string::npos);
  CHECK(zero.rows.size() == 1); // the initial state only
  const auto confined =
      PointDriver::from_string(mat + "[initial]\np = 25.0\n" + path, "p.toml", {STRATUM_PLUGIN_DIR})->run();
  CHECK(confined.outcome.ok());
  CHECK(confined.rows.size() == 21);
}

TEST_CASE("point driver: [material] from takes a set of an included shared file, keys beside it override",
          "[point][include]") {
  namespace fs = std::filesystem;
  const fs::path d = fs::temp_directory_path() / ("stratum_point_from_" + std::to_string(::getpid()));
  fs::create_directories(d / "materials");
  std::ofstream(d / "materials" / "soil.toml")
      << "[materials.soil]\nmodel = \"linear_elastic\"\nE = 1000.0\nnu = 0.25\n[materials.other]\n"
         "model = \"linear_elastic\"\nE = 5.0\n";
  const std::string path = "[[paths]]\ntype = \"isotropic\"\npressure = 100.0\nsteps = 1\n";
  auto run = [&](const std::string& name, const std::string& text) {
    std::ofstream(d / name) << text;
    return PointDriver::from_file((d / name).string(), {STRATUM_PLUGIN_DIR})->run();
  };
  // Isotropic compression by 100 kPa: eps_v = -100 / K with K = E / (3 (1 - 2 nu)); nu from the
  // set, E from the set or from the key beside `from`.
  auto eps_v = [](const PointRun& r) {
    const auto& e = r.rows.back().strain;
    return e[0] + e[1] + e[2];
  };
  const auto set = run("set.toml", "include = \"materials/soil.toml\"\n[material]\nfrom = \"soil\"\n" + path);
  REQUIRE(set.outcome.ok());
  CHECK(eps_v(set) == Approx(-100.0 / (1000.0 / (3 * 0.5))).epsilon(1e-12));
  const auto stiff = run(
      "stiff.toml", "include = \"materials/soil.toml\"\n[material]\nfrom = \"soil\"\nE = 2000.0\n" + path);
  REQUIRE(stiff.outcome.ok());
  CHECK(eps_v(stiff) == Approx(-100.0 / (2000.0 / (3 * 0.5))).epsilon(1e-12));
  // Errors: a set that is not there (with the known ones), [materials] without `from`, and a bad
  // value of the set, each located (the last in the shared file).
  auto error = [&](const std::string& name, const std::string& text) {
    try {
      run(name, text);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string typo =
      error("typo.toml", "include = \"materials/soil.toml\"\n[material]\nfrom = \"sol\"\n" + path);
  CHECK(typo.find("/typo.toml:3:8 [material] from = \"sol\": no table [materials.sol]") != std::string::npos);
  CHECK(typo.find("known: other, soil; did you mean 'soil'?") != std::string::npos);
  const std::string unused = error("unused.toml", "include = \"materials/soil.toml\"\n[material]\n"
                                                  "model = \"linear_elastic\"\nE = 1.0\n" +
                                                      path);
  CHECK(unused.find("materials/soil.toml:1:1") != std::string::npos);
  CHECK(unused.find("is used through [material] from = \"<name>\"") != std::string::npos);
  std::ofstream(d / "materials" / "bad.toml") << "[materials.soil]\nmodel = \"linear_elastic\"\nE = -1.0\n";
  const std::string bad =
      error("bad.toml", "include = \"materials/bad.toml\"\n[material]\nfrom = \"soil\"\n" + path);
  CHECK(bad.find("materials/bad.toml:3:5") != std::string::npos);
  fs::remove_all(d);
}

} // namespace test_point_driver
