// The umat adapter (plugins/umat): Abaqus UMAT libraries run as Stratum materials.
//
// The references are our own plugins: the Fortran linear-elastic UMAT (tests/umat/umat_elastic.f90)
// must give linear_elastic's numbers, the C von Mises UMAT (tests/umat/umat_mises.c) von_mises'
// (closest_point, the consistent tangent), at a material point on every path kind of
// `stratum point` to 1e-12 and on the Lamé and Hill scenes to 1e-10, in axisymmetry and plane
// strain. Both UMATs and the built-in plugins are written from the same closed forms, so the
// only admissible difference is rounding.
#include "scene_helpers.hpp"
#include "stratum/point_driver.hpp"
#include "umat/umat_material.hpp"

#include <catch2/catch.hpp>

#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

namespace test_umat {

using namespace stratum;
namespace fs = std::filesystem;

namespace {

const std::string umat_dir = STRATUM_UMAT_DIR;
const std::string mises_lib = umat_dir + "/umat_mises.so";
const std::string elastic_lib = umat_dir + "/umat_elastic.so";

// ---------------------------------------------------------------- material blocks

std::string builtin_elastic() { return "model = \"linear_elastic\"\nE = 10000.0\nnu = 0.25\n"; }
std::string fortran_elastic(int ntens = 0) {
  return "model = \"umat\"\nlibrary = \"" + elastic_lib +
         "\"\nprops = [10000.0, 0.25]\nprop_names = \"E nu\"\n" +
         "symmetric_tangent = true\nntens = " + std::to_string(ntens) + "\n";
}
std::string builtin_mises(double E = 10000.0, double nu = 0.25, double sy = 50.0, double H = 1000.0) {
  std::ostringstream o;
  o.precision(17);
  o << "model = \"von_mises\"\nE = " << E << "\nnu = " << nu << "\nsigma_y = " << sy << "\nH = " << H
    << "\nintegrator = \"closest_point\"\n";
  return o.str();
}
std::string c_mises(double E = 10000.0, double nu = 0.25, double sy = 50.0, double H = 1000.0, int ntens = 0,
                    const std::string& extra_props = "", const std::string& extra = "") {
  std::ostringstream o;
  o.precision(17);
  o << "model = \"umat\"\nlibrary = \"" << mises_lib << "\"\nsymbol = \"mises_umat\"\nprops = [" << E << ", "
    << nu << ", " << sy << ", " << H << extra_props << "]\nnstatv = 1\nstatev_names = \"ep\"\n"
    << "symmetric_tangent = true\nntens = " << ntens << "\n"
    << extra;
  return o.str();
}

// ---------------------------------------------------------------- material point

/// Every path kind of `stratum point`, in the plane (no yz, zx shear anywhere):
/// plugins/umat/tests/scenes/plane_paths.toml.
const std::string plane_paths =
    "\n" + testing::read_text(testing::source_path("plugins/umat/tests/scenes/plane_paths.toml"));

/// A mixed path with out-of-plane shears (NTENS = 6 only).
const std::string shear_3d_path = R"(
[[paths]]
type = "mixed"
control = ["strain", "strain", "stress", "strain", "strain", "strain"]
increment = [0.001, -0.003, 0.0, 0.002, 0.004, -0.003]
steps = 6
)";

PointRun run_point(const std::string& material, const std::string& paths) {
  const auto d =
      PointDriver::from_string("[material]\n" + material + paths, "point.toml", {STRATUM_PLUGIN_DIR});
  return d->run();
}

/// Largest difference of stress (kPa) and strain between two runs, relative to the largest
/// magnitude of each in the reference.
std::pair<double, double> point_difference(const PointRun& a, const PointRun& ref) {
  REQUIRE(a.outcome.ok());
  REQUIRE(ref.outcome.ok());
  REQUIRE(a.rows.size() == ref.rows.size());
  double ds = 0, de = 0, ss = 0, se = 0;
  for (std::size_t r = 0; r < ref.rows.size(); ++r) {
    ds = std::max(ds, (a.rows[r].stress - ref.rows[r].stress).cwiseAbs().maxCoeff());
    de = std::max(de, (a.rows[r].strain - ref.rows[r].strain).cwiseAbs().maxCoeff());
    ss = std::max(ss, ref.rows[r].stress.cwiseAbs().maxCoeff());
    se = std::max(se, ref.rows[r].strain.cwiseAbs().maxCoeff());
  }
  return {ds / ss, de / se};
}

// ---------------------------------------------------------------- scenes

struct SceneCase {
  std::string formulation; ///< axisymmetric or plane_strain
  bool hill = false;       ///< Hill's von Mises cylinder (else Lamé's elastic one)
};

std::string scene_toml(const SceneCase& c, const std::string& material, const std::string& extra = "") {
  const bool axi = c.formulation == "axisymmetric";
  std::ostringstream t;
  t << "[analysis]\nformulation = \"" << c.formulation << "\"\n";
  if (c.hill) t << "steps = 25\nmax_cutbacks = 3\n[convergence]\nforce_rtol = 1e-9\nmax_iterations = 30\n";
  t << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n";
  if (!axi) t << "transform = \"polar\"\n";
  const double a = c.hill ? 0.1 : 1.0, b = 2 * a;
  t << "[[mesh.blocks]]\nname = \"ring\"\nx = [" << a << ", " << b << "]\ny = [0.0, "
    << (axi ? 0.5 * a : 90.0) << "]\nnx = " << (c.hill ? 16 : 8) << "\nny = " << (axi ? 2 : 8) << "\n";
  t << "[materials.m]\n" << material;
  t << "[[domains]]\ncells = \"ring\"\nelement = \"quad\"\nmaterial = \"m\"\nintegration = 3\n";
  if (c.hill) t << "volumetric = \"selective\"\n";
  if (axi)
    t << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n[[constraints]]\nnodes = \"top\"\nuy = 0.0\n";
  else
    t << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n[[constraints]]\nnodes = \"top\"\nux = 0.0\n";
  // Hill: 0.99 of the limit pressure Y ln(b/a), Y = 2 sigma_y / sqrt(3) (the scene in inputs/).
  t << "[[loads]]\ntype = \"pressure\"\nedges = \"ring.left\"\np = " << (c.hill ? 190170.0 : 1.0) << "\n";
  t << extra;
  return t.str();
}

struct SceneResult {
  RunSummary summary;
  Eigen::VectorXd u;
  std::vector<Vec6> stress;
  std::vector<double> h0; ///< first history component per point (0 when none)
};

SceneResult run_scene(const std::string& toml) {
  auto a = testing::scene(toml);
  SceneResult r;
  r.summary = a->run();
  const Model& m = a->model();
  r.u = m.u;
  for (const auto& dm : m.domains)
    for (std::size_t p = 0; p < dm.states.points(); ++p) {
      const auto s = dm.states.committed(p);
      r.stress.push_back(s.stress());
      r.h0.push_back(s.history().empty() ? 0.0 : s.history()[0]);
    }
  return r;
}

/// Largest differences of displacement and stress, each relative to the reference's largest.
std::pair<double, double> scene_difference(const SceneResult& a, const SceneResult& ref) {
  REQUIRE(a.u.size() == ref.u.size());
  REQUIRE(a.stress.size() == ref.stress.size());
  double ds = 0, ss = 0;
  for (std::size_t p = 0; p < ref.stress.size(); ++p) {
    ds = std::max(ds, (a.stress[p] - ref.stress[p]).cwiseAbs().maxCoeff());
    ss = std::max(ss, ref.stress[p].cwiseAbs().maxCoeff());
  }
  return {(a.u - ref.u).cwiseAbs().maxCoeff() / ref.u.cwiseAbs().maxCoeff(), ds / ss};
}

fs::path scratch() {
  static const fs::path dir = fs::temp_directory_path() / ("stratum_umat_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string error_of(const std::string& toml, const std::string& path) {
  try {
    RunOptions o;
    o.plugin_dirs = {STRATUM_PLUGIN_DIR};
    o.write_output = false;
    (void)Analysis::from_string(toml, path, o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

} // namespace

// ---------------------------------------------------------------- layout

TEST_CASE("umat: Stratum's Voigt order <-> Abaqus' NTENS = 6 and NTENS = 4 layouts", "[umat]") {
  Vec6 v;
  v << 1, 2, 3, 4, 5, 6; // xx yy zz xy yz zx
  double a[6];
  umat::to_abaqus(umat::Layout::three_d(), v, a);
  // Abaqus 3D: 11 22 33 12 13 23 -> zx (6) before yz (5)
  CHECK(a[0] == 1);
  CHECK(a[1] == 2);
  CHECK(a[2] == 3);
  CHECK(a[3] == 4);
  CHECK(a[4] == 6);
  CHECK(a[5] == 5);
  CHECK(umat::from_abaqus(umat::Layout::three_d(), a) == v);
  double b[4];
  umat::to_abaqus(umat::Layout::plane(), v, b);
  CHECK((b[0] == 1 && b[1] == 2 && b[2] == 3 && b[3] == 4));
  Vec6 back = umat::from_abaqus(umat::Layout::plane(), b);
  CHECK(back.head<4>() == v.head<4>());
  CHECK(back[4] == 0.0);
  CHECK(back[5] == 0.0);

  // A non-symmetric DDSDDE(i, j) = 10 i + j (Fortran indices, column-major storage).
  for (const auto l : {umat::Layout::three_d(), umat::Layout::plane()}) {
    std::vector<double> dd(static_cast<std::size_t>(l.ntens * l.ntens));
    for (int i = 1; i <= l.ntens; ++i)
      for (int j = 1; j <= l.ntens; ++j)
        dd[static_cast<std::size_t>((i - 1) + (j - 1) * l.ntens)] = 10 * i + j;
    const Mat6 D = umat::tangent_from_abaqus(l, dd.data());
    const auto& idx = l.index();
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const int ai = idx[static_cast<std::size_t>(i)], aj = idx[static_cast<std::size_t>(j)];
        if (ai >= 0 && aj >= 0) CHECK(D(i, j) == 10 * (ai + 1) + (aj + 1));
      }
    if (l.ntens == 4) {
      // out-of-plane shears: uncoupled, with the in-plane shear stiffness DDSDDE(4, 4) = 44
      CHECK(D(4, 4) == 44.0);
      CHECK(D(5, 5) == 44.0);
      CHECK(D.row(4).sum() == 44.0);
      CHECK(D.col(5).sum() == 44.0);
    }
    std::vector<double> again(dd.size());
    umat::tangent_to_abaqus(l, D, again.data());
    CHECK(again == dd);
  }
}

// ---------------------------------------------------------------- material point

#ifdef STRATUM_HAVE_FORTRAN_UMAT
TEST_CASE("umat: the Fortran elastic UMAT is linear_elastic on every point path (1e-12)", "[umat]") {
  const auto ref = run_point(builtin_elastic(), plane_paths);
  for (int ntens : {0, 4, 6}) {
    const auto [ds, de] = point_difference(run_point(fortran_elastic(ntens), plane_paths), ref);
    INFO("ntens = " << ntens << ": stress " << ds << ", strain " << de);
    CHECK(ds <= 1e-12);
    CHECK(de <= 1e-12);
  }
  // Out-of-plane shears: NTENS = 6 (automatic or forced); NTENS = 4 refuses the state.
  const auto ref3 = run_point(builtin_elastic(), plane_paths + shear_3d_path);
  for (int ntens : {0, 6}) {
    const auto [ds, de] =
        point_difference(run_point(fortran_elastic(ntens), plane_paths + shear_3d_path), ref3);
    INFO("3D path, ntens = " << ntens << ": stress " << ds << ", strain " << de);
    CHECK(ds <= 1e-12);
    CHECK(de <= 1e-12);
  }
  const auto four = run_point(fortran_elastic(4), plane_paths + shear_3d_path);
  CHECK(four.outcome.status == Status::material_failure);
  CHECK(four.outcome.message.find("ntens = 4 cannot carry the out-of-plane shears") != std::string::npos);
}
#endif

TEST_CASE("umat: the C von Mises UMAT is von_mises on every point path (1e-12)", "[umat]") {
  const auto ref = run_point(builtin_mises(), plane_paths);
  // The paths yield: the reference ends with plastic strain.
  for (int ntens : {0, 4, 6}) {
    const auto [ds, de] =
        point_difference(run_point(c_mises(10000, 0.25, 50, 1000, ntens), plane_paths), ref);
    INFO("ntens = " << ntens << ": stress " << ds << ", strain " << de);
    CHECK(ds <= 1e-12);
    CHECK(de <= 1e-12);
  }
  const auto ref3 = run_point(builtin_mises(), plane_paths + shear_3d_path);
  for (int ntens : {0, 6}) {
    const auto [ds, de] =
        point_difference(run_point(c_mises(10000, 0.25, 50, 1000, ntens), plane_paths + shear_3d_path), ref3);
    INFO("3D path, ntens = " << ntens << ": stress " << ds << ", strain " << de);
    CHECK(ds <= 1e-12);
    CHECK(de <= 1e-12);
  }
}

/// Drucker-Prager paths: cone (undrained, shear, oedometer) and apex (isotropic extension), then
/// out-of-plane shear from the apex. Strain control except the triaxial and simple-shear stresses.
const std::string dp_paths = R"(
[initial]
p = 100.0
[[paths]]
type = "triaxial_drained"
axial_strain = -0.004
steps = 4
[[paths]]
type = "triaxial_undrained"
axial_strain = -0.02
steps = 20
[[paths]]
type = "simple_shear"
shear_strain = 0.01
steps = 10
[[paths]]
type = "oedometer"
axial_strain = -0.01
steps = 5
[[paths]]
type = "isotropic"
volumetric_strain = 0.05
steps = 5
)";

std::string builtin_dp() {
  return "model = \"drucker_prager\"\nE = 10000.0\nnu = 0.3\nc = 10.0\nphi = 30.0\npsi = 10.0\n"
         "cone = \"compression\"\nintegrator = \"closest_point\"\n";
}
std::string c_dp(int ntens = 0) {
  return "model = \"umat\"\nlibrary = \"" + umat_dir + "/umat_dp.so\"\nsymbol = \"dp_umat\"\n" +
         "props = [10000.0, 0.3, 10.0, 30.0, 10.0]\nprop_names = \"E nu c phi psi\"\nnstatv = 1\n" +
         "ntens = " + std::to_string(ntens) + "\n";
}

TEST_CASE("umat: the C Drucker-Prager UMAT is drucker_prager (compression cone) on cone and apex paths",
          "[umat]") {
  const auto ref = run_point(builtin_dp(), dp_paths);
  REQUIRE(ref.outcome.ok());
  // the last path ends at the apex: hydrostatic tension c cot(phi)
  const double apex = 10.0 / std::tan(30.0 * std::numbers::pi / 180.0);
  CHECK(std::abs(ref.rows.back().stress[0] - apex) <= 1e-9 * apex);
  for (int ntens : {0, 4, 6}) {
    const auto [ds, de] = point_difference(run_point(c_dp(ntens), dp_paths), ref);
    INFO("ntens = " << ntens << ": stress " << ds << ", strain " << de);
    CHECK(ds <= 1e-12);
    CHECK(de <= 1e-12);
  }
  // Out-of-plane shears, strain-controlled (the apex tangent is zero: no stress control there).
  const std::string shear_3d_strain = R"(
[[paths]]
type = "mixed"
control = ["strain", "strain", "strain", "strain", "strain", "strain"]
increment = [-0.02, -0.03, -0.02, 0.002, 0.004, -0.003]
steps = 6
)";
  const auto ref3 = run_point(builtin_dp(), dp_paths + shear_3d_strain);
  const auto [ds, de] = point_difference(run_point(c_dp(0), dp_paths + shear_3d_strain), ref3);
  INFO("3D path: stress " << ds << ", strain " << de);
  CHECK(ds <= 1e-12);
  CHECK(de <= 1e-12);
}

TEST_CASE("umat: the C Drucker-Prager UMAT's non-symmetric cone tangent matches finite differences",
          "[umat]") {
  auto lib = std::make_shared<const umat::Library>(umat_dir + "/umat_dp.so", "dp_umat");
  umat::Settings s;
  s.name = "fd";
  s.props = {10000.0, 0.3, 10.0, 30.0, 10.0};
  s.nstatv = 1;
  s.statev = {0.0};
  s.statev_names = {"ep"};
  for (int ntens : {4, 6}) {
    s.ntens = ntens;
    const umat::UmatMaterial m(lib, s);
    Vec6 stress_n, strain_n = Vec6::Zero(), de;
    stress_n << -20, -30, -25, 5, 0, 0;
    de << 1e-3, -4e-3, 0.5e-3, 1e-2, 0, 0;
    if (ntens == 6) stress_n[4] = 8, stress_n[5] = -6, de[4] = 1e-3, de[5] = -2e-3;
    std::vector<double> h0(static_cast<std::size_t>(m.history_size()), 0.0);
    auto eval = [&](const Vec6& d, Vec6& sig, Mat6& D, std::vector<double>& h) {
      h.assign(h0.size(), 0.0);
      MaterialOutput out{sig, h, D};
      return m.update(MaterialInput{stress_n, strain_n, h0, d, {0, 0}}, out);
    };
    Vec6 sig;
    Mat6 D;
    std::vector<double> h;
    REQUIRE(eval(de, sig, D, h).ok());
    REQUIRE(h[0] > 0.0);                                                               // on the cone
    REQUIRE(std::abs(sig[0] - sig[1]) > 1.0);                                          // not at the apex
    CHECK((D - D.transpose()).cwiseAbs().maxCoeff() > 1e-3 * D.cwiseAbs().maxCoeff()); // psi < phi
    const int n = ntens;
    for (int j = 0; j < n; ++j) {
      const double eps = 1e-7;
      Vec6 dp = de, dm = de, sp, sm;
      dp[j] += eps, dm[j] -= eps;
      Mat6 Dp, Dm;
      std::vector<double> hp, hm;
      REQUIRE(eval(dp, sp, Dp, hp).ok());
      REQUIRE(eval(dm, sm, Dm, hm).ok());
      const Vec6 fd = (sp - sm) / (2 * eps);
      for (int i = 0; i < n; ++i) {
        INFO("ntens " << ntens << " D(" << i << ", " << j << ") = " << D(i, j) << ", fd " << fd[i]);
        CHECK(std::abs(D(i, j) - fd[i]) <= 1e-5 * D.cwiseAbs().maxCoeff());
      }
    }
  }
}

TEST_CASE("umat: the C von Mises UMAT's tangent through the adapter matches finite differences", "[umat]") {
  auto lib = std::make_shared<const umat::Library>(mises_lib, "mises_umat");
  umat::Settings s;
  s.name = "fd";
  s.props = {10000.0, 0.25, 50.0, 1000.0};
  s.nstatv = 1;
  s.statev = {0.01};
  s.statev_names = {"ep"};
  for (int ntens : {4, 6}) {
    s.ntens = ntens;
    const umat::UmatMaterial m(lib, s);
    Vec6 stress_n, strain_n = Vec6::Zero(), de;
    stress_n << -80, -120, -90, 15, 0, 0;
    de << 1e-3, -3e-3, 0.5e-3, 2e-3, 0, 0;
    if (ntens == 6) stress_n[4] = 8, stress_n[5] = -6, de[4] = 1e-3, de[5] = -2e-3;
    std::vector<double> h0(static_cast<std::size_t>(m.history_size()));
    m.init_history(stress_n, h0);
    auto eval = [&](const Vec6& d, Vec6& sig, Mat6& D, std::vector<double>& h) {
      h.assign(h0.size(), 0.0);
      MaterialOutput out{sig, h, D};
      return m.update(MaterialInput{stress_n, strain_n, h0, d, {0, 0}}, out);
    };
    Vec6 sig;
    Mat6 D;
    std::vector<double> h;
    REQUIRE(eval(de, sig, D, h).ok());
    REQUIRE(h[0] > 0.01); // plastic
    const int n = ntens == 6 ? 6 : 4;
    for (int j = 0; j < n; ++j) {
      const double eps = 1e-7;
      Vec6 dp = de, dm = de, sp, sm;
      dp[j] += eps, dm[j] -= eps;
      Mat6 Dp, Dm;
      std::vector<double> hp, hm;
      REQUIRE(eval(dp, sp, Dp, hp).ok());
      REQUIRE(eval(dm, sm, Dm, hm).ok());
      const Vec6 fd = (sp - sm) / (2 * eps);
      for (int i = 0; i < n; ++i) {
        INFO("ntens " << ntens << " D(" << i << ", " << j << ") = " << D(i, j) << ", fd " << fd[i]);
        CHECK(std::abs(D(i, j) - fd[i]) <= 1e-5 * D.cwiseAbs().maxCoeff());
      }
    }
  }
}

// ---------------------------------------------------------------- scenes

#ifdef STRATUM_HAVE_FORTRAN_UMAT
TEST_CASE("umat: Lamé's cylinder with the Fortran elastic UMAT is linear_elastic's (1e-10)", "[umat]") {
  const std::string E1000 = "model = \"linear_elastic\"\nE = 1000.0\nnu = 0.3\n";
  const std::string umat = "model = \"umat\"\nlibrary = \"" + elastic_lib + "\"\nprops = [1000.0, 0.3]\n";
  for (const std::string f : {"axisymmetric", "plane_strain"}) {
    const SceneCase c{f, false};
    const auto ref = run_scene(scene_toml(c, E1000));
    const auto got = run_scene(scene_toml(c, umat));
    REQUIRE(ref.summary.outcome.ok());
    REQUIRE(got.summary.outcome.ok());
    const auto [du, ds] = scene_difference(got, ref);
    INFO(f << ": displacement " << du << ", stress " << ds);
    CHECK(du <= 1e-10);
    CHECK(ds <= 1e-10);
  }
}
#endif

TEST_CASE("umat: Hill's cylinder with the C von Mises UMAT is von_mises' (1e-10)", "[umat]") {
  for (const std::string f : {"plane_strain", "axisymmetric"}) {
    const SceneCase c{f, true};
    const auto ref = run_scene(scene_toml(c, builtin_mises(2.1e8, 0.3, 2.4e5, 0.0)));
    const auto got = run_scene(scene_toml(c, c_mises(2.1e8, 0.3, 2.4e5, 0.0)));
    REQUIRE(ref.summary.outcome.ok());
    REQUIRE(got.summary.outcome.ok());
    CHECK(got.summary.steps_done == ref.summary.steps_done);
    const auto [du, ds] = scene_difference(got, ref);
    double dh = 0, hmax = 0;
    for (std::size_t p = 0; p < ref.h0.size(); ++p)
      dh = std::max(dh, std::abs(got.h0[p] - ref.h0[p])), hmax = std::max(hmax, ref.h0[p]);
    INFO(f << ": displacement " << du << ", stress " << ds << ", ep " << dh << " of " << hmax);
    CHECK(hmax > 0.0); // the ring has yielded
    CHECK(du <= 1e-10);
    CHECK(ds <= 1e-10);
    CHECK(dh <= 1e-10 * hmax);
  }
}

// ---------------------------------------------------------------- failures

TEST_CASE("umat: PNEWDT < 1 cuts the step back, and the smaller step passes", "[umat]") {
  // Lamé, one step: the hoop strain at the inner face is about 1.9e-3, so a step larger than
  // 1.2e-3 of strain asks for PNEWDT = 0.5; the halves pass.
  const SceneCase c{"axisymmetric", false};
  const auto ref = run_scene(scene_toml(c, builtin_mises(1000.0, 0.3, 1e9, 0.0)));
  const auto got = run_scene(scene_toml(c, c_mises(1000.0, 0.3, 1e9, 0.0, 0, ", 1.2e-3")));
  REQUIRE(ref.summary.outcome.ok());
  REQUIRE(got.summary.outcome.ok());
  CHECK(ref.summary.cutbacks == 0);
  CHECK(got.summary.cutbacks == 1);
  CHECK(got.summary.steps_done == 2);
  REQUIRE(!got.summary.records.empty());
  CHECK(!got.summary.records.front().accepted);
  CHECK(got.summary.records.front().message.find("PNEWDT = 0.5 < 1") != std::string::npos);
  CHECK(got.summary.records.back().accepted);
  const auto [du, ds] = scene_difference(got, ref);
  CHECK(du <= 1e-10);
  CHECK(ds <= 1e-10);
}

TEST_CASE("umat: a NaN from the UMAT is cut back and ends the run with a status, no number", "[umat]") {
  const SceneCase c{"axisymmetric", false};
  // NaN once a total strain exceeds 1e-3 (the full load needs 1.9e-3): the load factor stalls
  // near 0.5 and the cut-backs run out.
  for (int where : {0, 1, 2}) {
    const std::string props = ", 0.0, 1e-3, " + std::to_string(where);
    const auto got = run_scene(scene_toml(c, c_mises(1000.0, 0.3, 1e9, 0.0, 0, props)));
    INFO("NaN in " << (where == 0   ? "STRESS"
                       : where == 1 ? "DDSDDE"
                                    : "STATEV")
                   << ": " << got.summary.outcome.message);
    CHECK(got.summary.outcome.status == Status::non_finite);
    CHECK(got.summary.outcome.message.find(where == 0   ? "non-finite STRESS"
                                           : where == 1 ? "non-finite DDSDDE"
                                                        : "non-finite STATEV(1) (ep)") != std::string::npos);
    CHECK(got.summary.cutbacks >= 4);
    CHECK(got.u.allFinite());
    for (std::size_t p = 0; p < got.stress.size(); ++p) {
      CHECK(got.stress[p].allFinite());
      CHECK(std::isfinite(got.h0[p]));
    }
  }
}

TEST_CASE("umat: a library or symbol that cannot be loaded is a located error at check time", "[umat]") {
  const std::string scene_path = (scratch() / "bad.toml").string();
  const SceneCase c{"axisymmetric", false};
  auto err = [&](const std::string& material) { return error_of(scene_toml(c, material), scene_path); };

  std::string e = err("model = \"umat\"\nlibrary = \"libnothere.so\"\nprops = [1.0]\n");
  INFO(e);
  CHECK(e.find(scene_path + ":") == 0);
  CHECK(e.find("[materials.m] library = \"libnothere.so\": no such file '" +
               (scratch() / "libnothere.so").string()) != std::string::npos);
  CHECK(e.find('\n') == std::string::npos);

  // The C library exports mises_umat, not the default umat_.
  e = err("model = \"umat\"\nlibrary = \"" + mises_lib + "\"\nprops = [1.0]\n");
  INFO(e);
  CHECK(e.find(scene_path + ":") == 0);
  CHECK(e.find("has no symbol 'umat_'") != std::string::npos);
  CHECK(e.find('\n') == std::string::npos);

  // Not a shared library at all.
  std::ofstream(scratch() / "fake.so") << "not a library\n";
  e = err("model = \"umat\"\nlibrary = \"fake.so\"\nprops = [1.0]\n");
  INFO(e);
  CHECK(e.find("cannot load the UMAT library") != std::string::npos);
  CHECK(e.find('\n') == std::string::npos);

  e = err("model = \"umat\"\nlibrary = \"" + mises_lib + "\"\nsymbol = \"mises_umat\"\nprops = [1.0, 2.0]\n" +
          "prop_names = \"E\"\n");
  CHECK(e.find("prop_names names 1 properties but props has 2") != std::string::npos);
  e = err("model = \"umat\"\nlibrary = \"" + mises_lib + "\"\nsymbol = \"mises_umat\"\nnstatv = 2\n" +
          "statev = [0.0]\n");
  CHECK(e.find("statev has 1 initial values but nstatv = 2") != std::string::npos);
  e = err("model = \"umat\"\nlibrary = \"" + mises_lib + "\"\nsymbol = \"mises_umat\"\nnstatv = 1\n" +
          "statev_names = \"plastic\"\n");
  CHECK(e.find("is the name of a built-in output field") != std::string::npos);
  e = err("model = \"umat\"\nlibrary = \"" + mises_lib + "\"\nsymbol = \"mises_umat\"\nntens = 5\n");
  CHECK(e.find("ntens = 5 is not allowed") != std::string::npos);
}

TEST_CASE("umat: the state variables reach the integration-point output by name", "[umat]") {
  const fs::path out = scratch() / "vtk";
  fs::remove_all(out);
  const SceneCase c{"plane_strain", true};
  const std::string toml =
      scene_toml(c, c_mises(2.1e8, 0.3, 2.4e5, 0.0), "[output]\nvtk = true\nintegration_points = true\n");
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = out.string();
  auto a = Analysis::from_string(toml, "hill_umat.toml", o);
  const auto s = a->run();
  REQUIRE(s.outcome.ok());
  // the last .vtp
  int last = -1;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("hill_umat_ip_", 0) == 0 && e.path().extension() == ".vtp")
      last = std::max(last, std::stoi(n.substr(13)));
  }
  REQUIRE(last >= 0);
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName((out / ("hill_umat_ip_" + std::to_string(last) + ".vtp")).string().c_str());
  reader->Update();
  vtkDataArray* ep = reader->GetOutput()->GetPointData()->GetArray("ep");
  REQUIRE(ep != nullptr);
  const auto& dm = a->model().domains[0];
  REQUIRE(static_cast<std::size_t>(ep->GetNumberOfTuples()) == dm.states.points());
  double most = 0;
  for (vtkIdType i = 0; i < ep->GetNumberOfTuples(); ++i) {
    CHECK(ep->GetTuple1(i) == dm.states.committed(static_cast<std::size_t>(i)).history()[0]);
    most = std::max(most, ep->GetTuple1(i));
  }
  CHECK(most > 0.0);
  // SSE, SPD, SCD are kept in the history but not written.
  CHECK(reader->GetOutput()->GetPointData()->GetArray("statev_2") == nullptr);
}

TEST_CASE("umat: default state-variable names are statev_1 .. statev_n", "[umat]") {
  auto lib = std::make_shared<const umat::Library>(mises_lib, "mises_umat");
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  const SceneCase c{"axisymmetric", false};
  auto a = Analysis::from_string(
      scene_toml(c, "model = \"umat\"\nlibrary = \"" + mises_lib +
                        "\"\nsymbol = \"mises_umat\"\nprops = [1000.0, 0.3, 1e9, 0.0]\nnstatv = 3\n"),
      "names.toml", o);
  const auto names = a->model().domains[0].law.material->history_names();
  CHECK(names == std::vector<std::string>{"statev_1", "statev_2", "statev_3"});
  CHECK(a->model().domains[0].law.material->history_size() == 6);
}

TEST_CASE("umat: the loess pile runs through all its stages with the soil as a UMAT", "[umat]") {
  // inputs/loess_pile/umat_example.toml with its library path pointed at this build tree.
  const std::string path = std::string(STRATUM_SOURCE_DIR) + "/inputs/loess_pile/umat_example.toml";
  std::ifstream in(path);
  REQUIRE(in);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string toml = ss.str();
  const std::string rel = "\"../../build/release/tests/umat/umat_dp.so\"";
  const auto at = toml.find(rel);
  REQUIRE(at != std::string::npos);
  toml.replace(at, rel.size(), "\"" + umat_dir + "/umat_dp.so\"");
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  auto a = Analysis::from_string(toml, path, o);
  const auto s = a->run();
  INFO(s.outcome.message << " " << s.stop_message);
  REQUIRE(s.outcome.ok());
  // All four stages ran: the loading stage (4) either reaches its full load (150 kN) or ends
  // at its settlement limit (27 mm), which the summary counts as ended early.
  REQUIRE(!s.records.empty());
  CHECK(s.records.back().stage == 4);
  CHECK(s.records.back().accepted);
  REQUIRE(!s.load_settlement.empty());
  const auto last = s.load_settlement.back();
  if (s.stop_reason == StopReason::settlement) {
    CHECK(s.stages_done == 3);
    CHECK(last[1] >= 27.0);
  } else {
    CHECK(s.stages_done == 4);
    CHECK(last[0] >= 150.0 - 1e-9);
  }
  // The soil yielded somewhere: the UMAT's STATEV(1) (eps_bar_p) > 0 at some point of the bore or near zone.
  double most = 0;
  for (const auto& dm : a->model().domains)
    if (dm.law.material && dm.law.material->history_names() == std::vector<std::string>{"eps_bar_p"})
      for (std::size_t p = 0; p < dm.states.points(); ++p)
        most = std::max(most, dm.states.committed(p).history()[0]);
  CHECK(most > 0.0);
}

TEST_CASE("umat: stratum check names the library line, stratum run ends a NaN run cleanly", "[umat][cli]") {
  auto run = [](const std::string& args, std::string& err) {
    const fs::path e = scratch() / "stderr.txt", o = scratch() / "stdout.txt";
    const std::string cmd = "cd " + scratch().string() + " && STRATUM_PLUGIN_PATH= " + STRATUM_EXE + " " +
                            args + " >" + o.string() + " 2>" + e.string();
    const int status = std::system(cmd.c_str());
    std::ifstream in(e);
    std::stringstream ss;
    ss << in.rdbuf();
    err = ss.str();
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  const SceneCase c{"axisymmetric", false};
  // A missing symbol: one line, file:line:col of `library = ...`, non-zero exit.
  const fs::path bad = scratch() / "bad_symbol.toml";
  const std::string text =
      scene_toml(c, "model = \"umat\"\nlibrary = \"" + mises_lib + "\"\nprops = [1.0]\n");
  std::ofstream(bad) << text;
  const auto line =
      1 + std::count(text.begin(), text.begin() + static_cast<long>(text.find("library =")), '\n');
  std::string err;
  CHECK(run("check " + bad.string(), err) != 0);
  INFO(err);
  CHECK(err.find(bad.string() + ":" + std::to_string(line) + ":11 [materials.m] library = ") !=
        std::string::npos);
  CHECK(err.find("has no symbol 'umat_'") != std::string::npos);
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);

  // A UMAT that returns NaN: the run stops after its cut-backs with a message and exit 2 (a step
  // that did not converge; 1 is for bad input).
  const fs::path nan = scratch() / "nan.toml";
  std::ofstream(nan) << scene_toml(c, c_mises(1000.0, 0.3, 1e9, 0.0, 0, ", 0.0, 1e-3, 0"));
  const int code = run("run " + nan.string() + " --out " + (scratch() / "nan_out").string(), err);
  INFO(err);
  CHECK(code == 2);
  CHECK(err.find("non-finite STRESS") != std::string::npos);
}

} // namespace test_umat
