// The "plastic" output field of every material (Material::point_status) and the names each model
// gives its regimes (Material::status_names): a point driven into each regime by the model's own
// update reports that regime, and the committed stress agrees with the closed form of the
// surface it is reported on. Lade's regimes are in test_lade.cpp (they need its triaxial driver),
// Duncan-Chang's in test_duncan_chang.cpp, Hardening-Soil's names in test_hardening_soil.cpp
// (its codes are the active sets its tests check). The VTK side (the names in the field data, the
// plastic radius of Hill's cylinder) is at the end.
#include "cam_clay/cam_clay.hpp"
#include "drucker_prager/drucker_prager.hpp"
#include "linear_elastic/elastic_math.hpp"
#include "mohr_coulomb/mohr_coulomb.hpp"
#include "nonlinear_elastic_no_tension/nonlinear_elastic_no_tension.hpp"
#include "thin_layer_hyperbolic/thin_layer_hyperbolic.hpp"
#include "von_mises/von_mises.hpp"

#include "stratum/elasticity.hpp"
#include "stratum/stress.hpp"

#include <catch2/catch.hpp>

#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace test_point_status {

namespace {

using stratum::Mat6;
using stratum::Material;
using stratum::Vec6;

/// One integration point driven by a material's own update.
struct Driven {
  const Material& m;
  Vec6 stress;
  Vec6 strain = Vec6::Zero();
  std::vector<double> history;
  Driven(const Material& mat, const Vec6& s0)
      : m(mat), stress(s0), history(static_cast<std::size_t>(mat.history_size())) {
    m.init_history(stress, history);
  }
  void step(const Vec6& de) {
    Vec6 s;
    Mat6 T;
    std::vector<double> h(history.size());
    const stratum::MaterialInput in{stress, strain, history, de, {}};
    stratum::MaterialOutput out{s, h, T};
    REQUIRE(m.update(in, out).ok());
    stress = s, strain += de, history = h;
  }
  /// n equal substeps of de.
  void path(const Vec6& de, int n) {
    for (int k = 0; k < n; ++k) step(de / n);
  }
  [[nodiscard]] int status() const { return m.point_status(stress, history); }
};

Vec6 isotropic(double sigma) {
  Vec6 s = Vec6::Zero();
  s[0] = s[1] = s[2] = sigma;
  return s;
}
Vec6 shear_xy(double gamma) {
  Vec6 e = Vec6::Zero();
  e[3] = gamma;
  return e;
}
Vec6 normal(double exx, double eyy, double ezz) {
  Vec6 e = Vec6::Zero();
  e[0] = exx, e[1] = eyy, e[2] = ezz;
  return e;
}
/// Every code a model reports has a name.
void check_named(const Material& m, int largest_code) {
  const auto names = m.status_names();
  REQUIRE(static_cast<int>(names.size()) > largest_code);
  for (const auto& n : names) CHECK(!n.empty());
}

} // namespace

TEST_CASE("point_status: linear elastic is always elastic", "[point_status]") {
  const stratum::linear_elastic::LinearElastic m(stratum::isotropic_stiffness(1e4, 0.3));
  Driven p(m, Vec6::Zero());
  p.step(normal(0.1, -0.2, 0.0));
  CHECK(p.status() == 0);
  CHECK(m.status_names() == std::vector<std::string>{"elastic"});
}

TEST_CASE("point_status: von Mises, elastic below and 1 on the yield surface", "[point_status][von_mises]") {
  namespace vm = stratum::von_mises;
  vm::Constants c;
  c.E = 1e5, c.nu = 0.3, c.sigma_y = 200.0, c.H = 1000.0;
  const vm::VonMisesMaterial m(c, stratum::plasticity::Settings{});
  // Simple shear from rest: q = sqrt(3) G gamma; first yield at gamma_y = sigma_y / (sqrt(3) G).
  const double G = c.G(), gy = c.sigma_y / (std::sqrt(3.0) * G);
  Driven e(m, Vec6::Zero());
  e.step(shear_xy(0.9 * gy));
  CHECK(e.status() == 0);
  Driven y(m, Vec6::Zero());
  y.path(shear_xy(3.0 * gy), 10);
  REQUIRE(y.history[0] > 0.0);
  CHECK(y.status() == 1);
  // On the surface: q = sigma_y + H eps_bar_p (closed form of the hardening law).
  CHECK(stratum::plasticity::q_mises(y.stress) == Approx(c.sigma_y + c.H * y.history[0]).epsilon(1e-9));
  // Unloading by a tenth of the last shear: elastic again, plastic strain kept.
  y.step(shear_xy(-0.3 * gy));
  CHECK(y.status() == 0);
  check_named(m, 1);
}

TEST_CASE("point_status: Mohr-Coulomb face, edge, tension cut-off and apex, Tresca",
          "[point_status][mohr_coulomb]") {
  namespace mc = stratum::mohr_coulomb;
  mc::Parameters p;
  p.E = 1e4, p.nu = 0.3, p.c = 10.0, p.phi = 30.0, p.psi = 0.0;
  const double sp = 0.5, cp = std::sqrt(3.0) / 2.0;
  auto f_mc = [&](const Vec6& s) { // (1 + sin phi) t1 - (1 - sin phi) t3 - 2 c cos phi
    const auto t = stratum::principal_tension(s);
    return (1.0 + sp) * t[2] - (1.0 - sp) * t[0] - 2.0 * p.c * cp;
  };
  const mc::MohrCoulomb m(p, stratum::plasticity::Settings{});
  check_named(m, 4);
  SECTION("elastic") {
    Driven d(m, isotropic(-100.0));
    d.step(shear_xy(1e-3)); // tau = G gamma = 3.8 kPa, far below the strength
    CHECK(d.status() == 0);
  }
  SECTION("face: simple shear keeps t2 strictly between t1 and t3") {
    Driven d(m, isotropic(-100.0));
    d.path(shear_xy(0.05), 5);
    CHECK(std::abs(f_mc(d.stress)) < 1e-8 * 100.0);
    CHECK(d.status() == 1);
  }
  SECTION("edge: isochoric triaxial compression (lateral strains equal), t1 = t2") {
    Driven d(m, isotropic(-100.0));
    d.path(normal(0.025, -0.05, 0.025), 5);
    const auto t = stratum::principal_tension(d.stress);
    CHECK(t[2] - t[1] < 1e-8 * 100.0);
    CHECK(std::abs(f_mc(d.stress)) < 1e-8 * 100.0);
    CHECK(d.status() == 2);
  }
  SECTION("apex: isotropic extension returns to c cot phi") {
    Driven d(m, Vec6::Zero());
    d.step(normal(0.01, 0.01, 0.01));
    CHECK(d.stress[0] == Approx(p.c / std::tan(std::numbers::pi / 6.0)).epsilon(1e-9));
    CHECK(d.status() == 4);
  }
  SECTION("tension cut-off T = 5 kPa: uniaxial extension (nu = 0) stops at t1 = T") {
    mc::Parameters q = p;
    q.nu = 0.0, q.tension = 5.0;
    const mc::MohrCoulomb mt(q, stratum::plasticity::Settings{});
    Driven d(mt, Vec6::Zero());
    d.step(normal(1e-3, 0.0, 0.0)); // trial sxx = 10 kPa; f_mc(trial) = 15 - 17.3 < 0
    CHECK(d.stress[0] == Approx(5.0).epsilon(1e-9));
    CHECK(d.status() == 3);
    d.step(normal(0.01, 0.01, 0.01)); // then all three at T: the apex of the cut-off
    CHECK(d.stress[1] == Approx(5.0).epsilon(1e-9));
    CHECK(d.status() == 4);
  }
  SECTION("Tresca (phi = 0): a side of the prism in shear, an edge in triaxial compression") {
    mc::Parameters t = p;
    t.phi = 0.0;
    const mc::MohrCoulomb mt(t, stratum::plasticity::Settings{});
    Driven s(mt, isotropic(-100.0));
    s.path(shear_xy(0.05), 5);
    CHECK(std::abs(s.stress[3]) == Approx(t.c).epsilon(1e-9)); // tau = c
    CHECK(s.status() == 1);
    Driven e(mt, isotropic(-100.0));
    e.path(normal(0.025, -0.05, 0.025), 5);
    CHECK(e.stress[0] - e.stress[1] == Approx(2.0 * t.c).epsilon(1e-9)); // t1 - t3 = 2 c
    CHECK(e.status() == 2);
  }
  SECTION("rounded form: shear on the surface, apex") {
    mc::Parameters r = p;
    r.form = mc::Form::rounded;
    const mc::MohrCoulomb mr(r, stratum::plasticity::Settings{});
    Driven s(mr, isotropic(-100.0));
    s.path(shear_xy(0.05), 10);
    CHECK(s.status() == 1);
    Driven a(mr, Vec6::Zero());
    a.step(normal(0.01, 0.01, 0.01));
    CHECK(a.status() == 4);
    Driven e(mr, isotropic(-100.0));
    e.step(shear_xy(1e-3));
    CHECK(e.status() == 0);
  }
}

TEST_CASE("point_status: Drucker-Prager cone and apex", "[point_status][drucker_prager]") {
  namespace dp = stratum::drucker_prager;
  dp::Parameters p;
  p.E = 1e4, p.nu = 0.3, p.c = 10.0, p.phi = 30.0, p.psi = 10.0;
  const dp::DruckerPrager m(p, stratum::plasticity::Settings{});
  check_named(m, 2);
  Driven e(m, isotropic(-100.0));
  e.step(shear_xy(1e-3));
  CHECK(e.status() == 0);
  Driven s(m, isotropic(-100.0));
  s.path(shear_xy(0.05), 5);
  CHECK(s.status() == 1);
  // f = alpha I1 + sqrt(J2) - k c on the cone (constants of the compression cone).
  const auto cc = dp::cone_constants(p.cone, dp::radians(p.phi));
  CHECK(cc.alpha * 3.0 * stratum::plasticity::mean(s.stress) + std::sqrt(stratum::plasticity::j2(s.stress)) ==
        Approx(cc.k * p.c).epsilon(1e-8));
  Driven a(m, Vec6::Zero());
  a.step(normal(0.01, 0.01, 0.01));
  CHECK(stratum::plasticity::mean(a.stress) == Approx(cc.k * p.c / (3.0 * cc.alpha)).epsilon(1e-9));
  CHECK(a.status() == 2);
}

TEST_CASE("point_status: Cam-Clay hardening (wet), softening (dry) and critical state",
          "[point_status][cam_clay]") {
  namespace cc = stratum::cam_clay;
  for (const cc::Variant v : {cc::Variant::modified, cc::Variant::original}) {
    INFO((v == cc::Variant::modified ? "Modified Cam-Clay" : "Cam-Clay"));
    cc::Constants c;
    c.variant = v, c.M = 1.2, c.lambda = 0.2, c.kappa = 0.02, c.e0 = 1.0, c.G = 3000.0;
    const cc::CamClay nc(c, cc::Initial{1.0, 0.0}, stratum::plasticity::Settings{});
    check_named(nc, 3);
    // Normally consolidated at p = 100 kPa: isotropic compression hardens p_c (wet side, eta = 0).
    Driven h(nc, isotropic(-100.0));
    const double pc0 = h.history[0];
    h.path(normal(-0.005, -0.005, -0.005), 5);
    CHECK(h.history[0] > pc0);
    CHECK(h.status() == 1);
    // Unloading: inside the locus.
    h.step(normal(0.001, 0.001, 0.001));
    CHECK(h.status() == 0);
    // Heavily overconsolidated (OCR 10): undrained shear (no volume change) yields on the dry side.
    const cc::CamClay oc(c, cc::Initial{10.0, 0.0}, stratum::plasticity::Settings{});
    Driven d(oc, isotropic(-100.0));
    const double pcd = d.history[0];
    int k = 0;
    while (d.status() == 0 && k++ < 400) d.step(shear_xy(2e-4));
    REQUIRE(d.status() != 0);
    CHECK(stratum::plasticity::q_mises(d.stress) > c.M * cc::pressure(d.stress)); // eta > M
    CHECK(d.history[0] < pcd);                                                    // softening
    CHECK(d.status() == 2);
    // The critical state: the point of the locus where q = M p (MCC p = p_c / 2, OCC p = p_c / e).
    const double pc = 200.0, pcs = v == cc::Variant::modified ? pc / 2.0 : pc / std::exp(1.0);
    Vec6 s = isotropic(-pcs);
    s[0] -= 2.0 / 3.0 * c.M * pcs, s[1] += 1.0 / 3.0 * c.M * pcs, s[2] += 1.0 / 3.0 * c.M * pcs; // q = M p
    REQUIRE(stratum::plasticity::q_mises(s) == Approx(c.M * pcs).epsilon(1e-12));
    REQUIRE(cc::pressure(s) == Approx(pcs).epsilon(1e-12));
    const std::vector<double> hist{pc};
    CHECK(nc.point_status(s, hist) == 3);
  }
}

TEST_CASE("point_status: no-tension model counts the directions cut off", "[point_status][no_tension]") {
  namespace ne = stratum::nonlinear_elastic;
  ne::Constants c;
  c.A = 500.0, c.B = 300.0, c.tensile_strength = 0.0;
  const ne::NoTension m(c);
  check_named(m, 3);
  Driven e(m, isotropic(-100.0));
  e.step(normal(1e-5, 0.0, 0.0));
  CHECK(e.status() == 0);
  // Extension in x with the lateral strains chosen so that the other stresses stay compressive
  // (K and G scale alike with p: d sigma_yy = (K - 2G/3) de_xx + (K + 4G/3) de_yy + ... < 0).
  Driven one(m, isotropic(-10.0));
  one.step(normal(0.05, -0.025, -0.025));
  CHECK(one.stress[0] == Approx(0.0).margin(1e-9));
  CHECK(one.stress[1] < 0.0);
  CHECK(one.status() == 1);
  Driven two(m, isotropic(-10.0));
  two.step(normal(0.05, 0.05, -0.05));
  CHECK(two.stress[2] < 0.0);
  CHECK(two.status() == 2);
  Driven three(m, isotropic(-10.0));
  three.step(normal(0.05, 0.05, 0.05));
  CHECK(three.status() == 3);
}

TEST_CASE("point_status: thin-layer interface below failure, failed, in tension",
          "[point_status][thin_layer]") {
  namespace tl = stratum::thin_layer_hyperbolic;
  tl::Constants c;
  c.E = 2e4, c.nu = 0.3, c.K_I = 2000.0, c.n = 0.89, c.R_f = 0.9, c.c_a = 10.0, c.delta = 29.0;
  const tl::ThinLayerHyperbolic m(c);
  check_named(m, 2);
  Vec6 s0 = Vec6::Zero();
  s0[c.normal()] = -100.0;
  const double tf = c.tau_f(100.0); // c_a + sigma_n tan delta
  REQUIRE(tf == Approx(10.0 + 100.0 * std::tan(29.0 * std::numbers::pi / 180.0)).epsilon(1e-12));
  Driven b(m, s0);
  b.step(shear_xy(1e-5));
  CHECK(std::abs(b.stress[3]) < tf);
  CHECK(b.status() == 0);
  Driven f(m, s0);
  f.path(shear_xy(0.5), 50);
  CHECK(std::abs(f.stress[3]) == Approx(tf).epsilon(1e-9));
  CHECK(f.status() == 1);
  Driven t(m, s0);
  Vec6 open = Vec6::Zero();
  open[c.normal()] = 0.1;
  t.step(open);
  REQUIRE(t.stress[c.normal()] > 0.0);
  CHECK(t.status() == 2);
}

TEST_CASE("VTK: the plastic field of Hill's cylinder, its domain and regime names read back",
          "[point_status][output][cli]") {
  // Hill's cylinder at 0.99 P_lim (inputs/verification/hill_cylinder.toml): the plastic zone
  // reaches c = 0.18359 m from P = Y [ln(c/a) + (1 - c^2/b^2)/2] (Tresca; von Mises in plane
  // strain is close to it). Points well inside (r < c - 0.01 m) must report 1, well outside
  // (r > c + 0.01 m) 0; the file names both codes.
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / ("stratum_status_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string scene = std::string(STRATUM_SOURCE_DIR) + "/inputs/verification/hill_cylinder.toml";
  const std::string cmd = std::string("STRATUM_PLUGIN_PATH= ") + STRATUM_EXE + " run " + scene + " --out " +
                          out.string() + " > " + (out.string() + ".log") + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(out / "hill_cylinder_ip.pvd");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::regex ds(R"re(file="([^"]+)")re");
  std::string last;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), ds); it != std::sregex_iterator(); ++it)
    last = (*it)[1];
  REQUIRE(!last.empty());
  auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  r->SetFileName((out / last).string().c_str());
  r->Update();
  vtkPolyData* data = r->GetOutput();
  vtkFieldData* fd = data->GetFieldData();
  auto* domains = vtkStringArray::SafeDownCast(fd->GetAbstractArray("domains"));
  REQUIRE(domains != nullptr);
  REQUIRE(domains->GetNumberOfValues() == 1);
  const std::string dname = domains->GetValue(0);
  auto* regimes = vtkStringArray::SafeDownCast(fd->GetAbstractArray(("plastic_regimes_" + dname).c_str()));
  REQUIRE(regimes != nullptr);
  REQUIRE(regimes->GetNumberOfValues() == 2);
  CHECK(regimes->GetValue(0) == "elastic");
  CHECK(regimes->GetValue(1) == "on the yield surface");
  vtkDataArray* plastic = data->GetPointData()->GetArray("plastic");
  vtkDataArray* domain = data->GetPointData()->GetArray("domain");
  REQUIRE(plastic != nullptr);
  REQUIRE(domain != nullptr);
  const double c = 0.18359;
  int inner = 0, outer = 0;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
    double x[3];
    data->GetPoint(i, x);
    const double rr = std::hypot(x[0], x[1]);
    CHECK(domain->GetTuple1(i) == 0.0);
    if (rr < c - 0.01) {
      ++inner;
      CHECK(plastic->GetTuple1(i) == 1.0);
    } else if (rr > c + 0.01) {
      ++outer;
      CHECK(plastic->GetTuple1(i) == 0.0);
    }
  }
  CHECK(inner > 100);
  CHECK(outer > 10);
  // tools/plastic_zone.py (matplotlib route) draws it and, with --vtp, writes the categories it
  // coloured: the legend's labels are the model's names read from the file.
  const std::string tool = std::string("/usr/bin/python3 ") + STRATUM_SOURCE_DIR + "/tools/plastic_zone.py " +
                           out.string() + " --step last --vtp -o " + (out / "zone.png").string() + " >> " +
                           (out.string() + ".log") + " 2>&1";
  REQUIRE(std::system(tool.c_str()) == 0);
  CHECK(fs::file_size(out / "zone.png") > 10000);
  auto z = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  z->SetFileName((out / ("plastic_zone_" +
                         last.substr(last.rfind('_') + 1, last.find('.') - last.rfind('_') - 1) + ".vtp"))
                     .string()
                     .c_str());
  z->Update();
  auto* legend =
      vtkStringArray::SafeDownCast(z->GetOutput()->GetFieldData()->GetAbstractArray("regime_names"));
  REQUIRE(legend != nullptr);
  REQUIRE(legend->GetNumberOfValues() == 2);
  CHECK(legend->GetValue(0) == "elastic");
  CHECK(legend->GetValue(1) == "on the yield surface");
  vtkDataArray* regime = z->GetOutput()->GetPointData()->GetArray("regime");
  REQUIRE(regime != nullptr);
  for (vtkIdType i = 0; i < regime->GetNumberOfTuples(); ++i)
    CHECK(regime->GetTuple1(i) == plastic->GetTuple1(i)); // one model: category = its code
  fs::remove_all(out);
}

} // namespace test_point_status
