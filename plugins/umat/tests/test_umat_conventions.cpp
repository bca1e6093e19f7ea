// The umat adapter's calling conventions (issue 40): TIME, DTIME, KSTEP, KINC, COORDS, CELENT and
// DFGRD over staged scenes and the point driver, a UMAT that initialises at TIME(2) = 0, the
// guards after STATEV and PROPS, XIT, the missing-symbol message, and the utility routines
// (abaqus_utilities.h) against closed forms. The test UMATs: tests/umat/umat_probe.c and
// tests/umat/umat_mcc.c.
#include "scene_helpers.hpp"
#include "stratum/point_driver.hpp"
#include "umat/abaqus_utilities.h"
#include "umat/umat_material.hpp"

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace test_umat_conventions {

using namespace stratum;
namespace fs = std::filesystem;

namespace {

const std::string umat_dir = STRATUM_UMAT_DIR;
const std::string probe_lib = umat_dir + "/umat_probe.so";
const std::string mcc_lib = umat_dir + "/umat_mcc.so";

fs::path scratch() {
  static const fs::path dir = fs::temp_directory_path() / ("stratum_umat_conv_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

/// A 1 m x 1 m block of 2 x 1 plane-strain quads (cells 0.5 m x 1 m, 4 points each) on a fixed
/// base, pressed by 10 kPa in stage "first" (2 steps) and 10 kPa more in "second" (4 steps).
/// The material is the probe UMAT called `name` (its CMNAME chooses what it does).
std::string probe_scene(const std::string& name, int nstatv, const std::string& props = "[1000.0, 0.25]") {
  std::ostringstream t;
  t << "[analysis]\nformulation = \"plane_strain\"\n"
    << "[mesh]\ngenerator = \"blocks\"\n[[mesh.blocks]]\nname = \"b\"\nx = [0.0, 1.0]\ny = [0.0, 1.0]\n"
    << "nx = 2\nny = 1\n"
    << "[materials." << name << "]\nmodel = \"umat\"\nlibrary = \"" << probe_lib
    << "\"\nsymbol = \"probe_umat\"\nprops = " << props << "\nnstatv = " << nstatv << "\n"
    << "symmetric_tangent = true\n"
    << "[[domains]]\ncells = \"b\"\nelement = \"quad\"\nmaterial = \"" << name << "\"\n"
    << "[[constraints]]\nnodes = \"bottom\"\nux = 0.0\nuy = 0.0\n"
    << "[[stages]]\nname = \"first\"\nsteps = 2\n[[stages.actions]]\ntype = \"pressure\"\nname = \"p1\"\n"
    << "edges = \"b.top\"\np = 10.0\n"
    << "[[stages]]\nname = \"second\"\nsteps = 4\n[[stages.actions]]\ntype = \"pressure\"\nname = \"p2\"\n"
    << "edges = \"b.top\"\np = 10.0\n";
  return t.str();
}

/// What the CLOCK probe stored at point 0 after an accepted step.
struct Seen {
  double t1, t2, kstep, kinc, dtime, zero_count;
};

struct ExitResult {
  int code = -1;
  std::string err;
};

ExitResult stratum_cli(const std::string& args) {
  const fs::path e = scratch() / "stderr.txt", o = scratch() / "stdout.txt";
  const std::string cmd = "cd " + scratch().string() + " && STRATUM_PLUGIN_PATH= " + STRATUM_EXE + " " +
                          args + " >" + o.string() + " 2>" + e.string();
  const int status = std::system(cmd.c_str());
  std::ifstream in(e);
  std::stringstream ss;
  ss << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
}

fs::path write_scene(const std::string& file, const std::string& text) {
  const fs::path p = scratch() / file;
  std::ofstream(p) << text;
  return p;
}

} // namespace

TEST_CASE("umat: TIME, DTIME, KSTEP and KINC advance as documented over two load stages", "[umat]") {
  // Pseudo-time 1 per static stage (docs/design.md, "Time of a stage"): the values a UMAT sees in
  // step j of a stage of n steps are those of the start of the step, TIME(1) = (j - 1) / n,
  // TIME(2) = (stage - 1) + TIME(1), DTIME = 1 / n, KSTEP = stage, KINC = j. The probe stores them
  // in STATEV, read back from the committed state after every accepted step.
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  std::vector<Seen> seen;
  std::unique_ptr<Analysis> a;
  o.on_step = [&](int, int, double, const StepReport&) {
    const auto h = a->model().domains.at(0).states.committed(0).history();
    seen.push_back({h[0], h[1], h[2], h[3], h[4], h[8]});
  };
  a = Analysis::from_string(probe_scene("clock", 10), "clock.toml", o);
  const RunSummary s = a->run();
  INFO(s.outcome.message);
  REQUIRE(s.outcome.ok());
  REQUIRE(seen.size() == 6);
  for (std::size_t k = 0; k < seen.size(); ++k) {
    const bool first = k < 2;
    const int n = first ? 2 : 4, j = first ? static_cast<int>(k) + 1 : static_cast<int>(k) - 1;
    const double t1 = (j - 1.0) / n;
    INFO("accepted step " << k + 1 << ": stage " << (first ? 1 : 2) << ", increment " << j);
    CHECK(seen[k].t1 == Approx(t1).margin(1e-14));
    CHECK(seen[k].t2 == Approx((first ? 0.0 : 1.0) + t1).margin(1e-14));
    CHECK(seen[k].kstep == (first ? 1.0 : 2.0));
    CHECK(seen[k].kinc == static_cast<double>(j));
    CHECK(seen[k].dtime == Approx(1.0 / n).margin(1e-14));
    // TIME(2) = 0 in the first increment of the analysis only: its count stays 1 at every point.
    CHECK(seen[k].zero_count == 1.0);
  }

  // COORDS: the integration point's position (the quad's own point coordinates); CELENT: the
  // square root of the cell's area (0.5 m2); DFGRD1(1,1) - 1: the committed strain eps_xx.
  const Model& m = a->model();
  const Domain& d = m.domains.at(0);
  std::vector<int> nodes;
  Eigen::MatrixXd X, xp;
  for (std::size_t c = 0; c < d.cells.size(); ++c) {
    m.cell_nodes(d.cells[c], nodes, X);
    d.element->point_coordinates(m.element_data(d.cells[c], X), xp);
    for (std::size_t p = d.first_point[c]; p < d.first_point[c + 1]; ++p) {
      const auto st = d.states.committed(p);
      const auto h = st.history();
      const auto i = static_cast<Eigen::Index>(p - d.first_point[c]);
      CHECK(h[5] == Approx(xp(i, 0)).margin(1e-14));
      CHECK(h[6] == Approx(xp(i, 1)).margin(1e-14));
      CHECK(h[7] == Approx(std::sqrt(0.5)).epsilon(1e-14));
      CHECK(h[8] == 1.0);
      CHECK(h[9] == Approx(st.strain()[0]).margin(1e-15));
    }
  }
}

TEST_CASE("umat: a restart from the first stage's checkpoint continues TIME(2) and KSTEP", "[umat]") {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = (scratch() / "clock_full").string();
  const auto full = Analysis::from_string(probe_scene("clock", 10), (scratch() / "clock.toml").string(), o);
  const RunSummary s = full->run();
  REQUIRE(s.outcome.ok());
  REQUIRE(!s.checkpoints.empty());
  const std::string first = s.checkpoints.front();
  INFO(first);
  CHECK(first.find("first") != std::string::npos);

  RunOptions r;
  r.plugin_dirs = {STRATUM_PLUGIN_DIR};
  r.out_dir = (scratch() / "clock_restart").string();
  r.restart_from = first;
  std::vector<Seen> seen;
  std::unique_ptr<Analysis> a;
  r.on_step = [&](int, int, double, const StepReport&) {
    const auto h = a->model().domains.at(0).states.committed(0).history();
    seen.push_back({h[0], h[1], h[2], h[3], h[4], h[8]});
  };
  a = Analysis::from_string(probe_scene("clock", 10), (scratch() / "clock.toml").string(), r);
  const RunSummary rs = a->run();
  INFO(rs.outcome.message);
  REQUIRE(rs.outcome.ok());
  REQUIRE(seen.size() == 4); // the second stage only
  for (std::size_t k = 0; k < seen.size(); ++k) {
    CHECK(seen[k].t1 == Approx(0.25 * static_cast<double>(k)).margin(1e-14));
    CHECK(seen[k].t2 == Approx(1.0 + 0.25 * static_cast<double>(k)).margin(1e-14));
    CHECK(seen[k].kstep == 2.0);
    CHECK(seen[k].kinc == static_cast<double>(k + 1));
    CHECK(seen[k].zero_count == 1.0); // the restored state: TIME(2) = 0 was not seen again
  }
}

TEST_CASE("umat: Modified Cam-Clay initialising at TIME(2) = 0 is modified_cam_clay on unload-reload (1e-8)",
          "[umat]") {
  // tests/umat/umat_mcc.c sets p_c = OCR p_eq(sigma) when TIME(2) = 0, as many UMATs do. Before
  // issue 40 the adapter passed TIME = (0, 0) at every call, so the UMAT re-initialised p_c from
  // the current stress in every step and forgot its history (the unload-reload path of the issue
  // ended at -378 kPa instead of -987 kPa). Now TIME(2) = 0 only in the first step of the point
  // driver's path, and the UMAT follows the built-in model (the same equations, constant G, the
  // closest-point return; the elastic law composes exactly, so where the built-in splits a step
  // at the yield surface the answer is the same) to round-off.
  const std::string paths = R"(
[initial]
p = 100.0
[[paths]]
type = "oedometer"
axial_strain = -0.02
steps = 20
[[paths]]
type = "oedometer"
axial_strain = 0.004
steps = 8
[[paths]]
type = "oedometer"
axial_strain = -0.02
steps = 20
)";
  const std::string builtin = "[material]\nmodel = \"modified_cam_clay\"\nM = 1.2\nlambda = 0.077\n"
                              "kappa = 0.0066\ne0 = 1.0\nG = 5000.0\nocr = 1.5\np_min = 1.0\n"
                              "integrator = \"closest_point\"\n";
  const std::string umat = "[material]\nmodel = \"umat\"\nlibrary = \"" + mcc_lib +
                           "\"\nsymbol = \"mcc_umat\"\n"
                           "props = [1.2, 0.077, 0.0066, 1.0, 5000.0, 1.5, 1.0]\nnstatv = 1\n";
  const auto ref = PointDriver::from_string(builtin + paths, "mcc.toml", {STRATUM_PLUGIN_DIR})->run();
  const auto got = PointDriver::from_string(umat + paths, "mcc.toml", {STRATUM_PLUGIN_DIR})->run();
  INFO(ref.outcome.message << " | " << got.outcome.message);
  REQUIRE(ref.outcome.ok());
  REQUIRE(got.outcome.ok());
  REQUIRE(got.rows.size() == ref.rows.size());
  REQUIRE(ref.rows.size() == 49);
  double diff = 0.0, scale = 0.0;
  for (std::size_t r = 0; r < ref.rows.size(); ++r) {
    diff = std::max(diff, (got.rows[r].stress - ref.rows[r].stress).cwiseAbs().maxCoeff());
    scale = std::max(scale, ref.rows[r].stress.cwiseAbs().maxCoeff());
  }
  INFO("largest stress difference " << diff << " kPa of " << scale << " kPa");
  CHECK(diff <= 1e-8 * scale);
  // The path is plastic: the reload ends well beyond where the first loading ended (p_c grew).
  const double end_load = ref.rows[20].stress[1], end_reload = ref.rows[48].stress[1];
  CHECK(end_reload < 1.2 * end_load);
  CHECK(got.rows[48].stress[1] == Approx(end_reload).epsilon(1e-8));
}

TEST_CASE("umat: a UMAT writing past NSTATV or NPROPS ends stratum run with one located line",
          "[umat][cli]") {
  // NSTATV 1, nine state variables written: no heap corruption, no cut-back, exit 2 (a failed
  // stage, not a numerical stop) with the element, the point and the NSTATV that would fit.
  const fs::path statev = write_scene("overstatev.toml", probe_scene("overstatev", 1));
  // `stratum check` opens the library and checks its symbol; it calls no UMAT.
  const auto check = stratum_cli("check " + statev.string());
  INFO(check.err);
  CHECK(check.code == 0);
  const auto r = stratum_cli("run " + statev.string() + " --out " + (scratch() / "overstatev_out").string());
  INFO(r.err);
  CHECK((r.code == 1 || r.code == 2));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(r.err.find("fatal error") != std::string::npos);
  CHECK(r.err.find("(element 0, point 0; NOEL 1, NPT 1)") != std::string::npos);
  // Located: the scene's nstatv line (line 16 of probe_scene, after "nstatv = ").
  CHECK(r.err.find("the UMAT wrote STATEV(9) past NSTATV = 1 (" + statev.string() +
                   ":16:10); set nstatv = 9") != std::string::npos);

  // PROPS: two given, the UMAT writes PROPS(3..5).
  const fs::path props = write_scene("overprops.toml", probe_scene("overprops", 0));
  const auto p = stratum_cli("run " + props.string() + " --out " + (scratch() / "overprops_out").string());
  INFO(p.err);
  CHECK((p.code == 1 || p.code == 2));
  CHECK(std::count(p.err.begin(), p.err.end(), '\n') == 1);
  CHECK(p.err.find("the UMAT wrote PROPS(5) past NPROPS = 2 (" + props.string() +
                   ":15:9); give props 5 values") != std::string::npos);

  // In-process: the run stops at once (no cut-back), the status says it is no numerical failure.
  auto a = testing::scene(probe_scene("overstatev", 1));
  const RunSummary s = a->run();
  CHECK(s.outcome.status == Status::fatal);
  CHECK(s.cutbacks == 0);
  CHECK(s.steps_done == 0);
}

TEST_CASE("umat: a UMAT reading past NPROPS gets NaN that names NPROPS", "[umat]") {
  // The PROPS guards are quiet NaNs with a payload of their own: the stress computed from one
  // carries it, and the adapter says that the UMAT read more PROPS than given (a fatal error).
  auto a = testing::scene(probe_scene("readprops", 0));
  const RunSummary s = a->run();
  INFO(s.outcome.message);
  CHECK(s.outcome.status == Status::fatal);
  CHECK(s.outcome.message.find("computed from a PROPS entry past NPROPS = 2") != std::string::npos);
  CHECK(s.cutbacks == 0);
}

TEST_CASE("umat: a UMAT that calls XIT ends the run with one line naming the element and point",
          "[umat][cli]") {
  // The probe calls XIT from the second stage on: the first stage's steps are written, the run
  // ends with exit 2 and one line, as Abaqus ends its analysis.
  const fs::path scene = write_scene("xit.toml", probe_scene("xit", 0));
  const fs::path out = scratch() / "xit_out";
  const auto r = stratum_cli("run " + scene.string() + " --out " + out.string());
  INFO(r.err);
  CHECK(r.code == 2);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(r.err.find("stage \"second\"") != std::string::npos);
  CHECK(r.err.find("umat 'xit' (element 0, point 0; NOEL 1, NPT 1): the UMAT called XIT") !=
        std::string::npos);
  // The results so far: the first stage's checkpoint and VTK steps (the initial state and its two).
  int vtu = 0, checkpoints = 0;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (e.path().extension() == ".vtu") ++vtu;
    if (e.path().parent_path().filename() == "checkpoints") ++checkpoints;
  }
  CHECK(vtu >= 3);
  CHECK(checkpoints == 1);

  // In-process: Status::fatal, no cut-back, both steps of stage 1 done.
  auto a = testing::scene(probe_scene("xit", 0));
  const RunSummary s = a->run();
  CHECK(s.outcome.status == Status::fatal);
  CHECK(s.cutbacks == 0);
  CHECK(s.steps_done == 2);
}

TEST_CASE("umat: a missing symbol's message lists the library's UMAT-like symbols", "[umat]") {
  CHECK(umat::umat_like_symbols(probe_lib) == std::vector<std::string>{"probe_umat"});
  CHECK(umat::umat_like_symbols(mcc_lib) == std::vector<std::string>{"mcc_umat"});
  CHECK(umat::umat_like_symbols(STRATUM_SOURCE_DIR "/plugins/umat/README.md").empty()); // not ELF
  std::string message;
  try {
    umat::Library lib(probe_lib, "umat_");
  } catch (const Error& e) {
    message = e.what();
  }
  INFO(message);
  CHECK(message.find("has no symbol 'umat_'; it exports probe_umat (") != std::string::npos);
  CHECK(message.find('\n') == std::string::npos);
}

// ---------------------------------------------------------------- utility routines

namespace {

/// R = rotation by angle t about the unit axis n (Rodrigues).
Eigen::Matrix3d rotation(Eigen::Vector3d n, double t) {
  return Eigen::AngleAxisd(t, n.normalized()).matrix();
}

/// Stress-like (tensor shears) NTENS = 6 vector 11, 22, 33, 12, 13, 23 of a symmetric tensor.
std::array<double, 6> packed(const Eigen::Matrix3d& T, double shear = 1.0) {
  return {T(0, 0), T(1, 1), T(2, 2), shear * T(0, 1), shear * T(0, 2), shear * T(1, 2)};
}

} // namespace

TEST_CASE("umat utilities: SINV gives trace / 3 and the Mises stress of known tensors", "[umat]") {
  const int ndi = 3, nshr = 3, ndi4 = 3, nshr4 = 1;
  double s1 = 0, s2 = 0;
  const std::array<double, 6> uniaxial{100.0, 0, 0, 0, 0, 0};
  sinv_(uniaxial.data(), &s1, &s2, &ndi, &nshr);
  CHECK(s1 == Approx(100.0 / 3.0).epsilon(1e-15));
  CHECK(s2 == Approx(100.0).epsilon(1e-15));
  const std::array<double, 6> shear{0, 0, 0, 0, 0, 40.0}; // sigma_23 = tau: q = sqrt(3) tau
  sinv_(shear.data(), &s1, &s2, &ndi, &nshr);
  CHECK(s1 == 0.0);
  CHECK(s2 == Approx(std::sqrt(3.0) * 40.0).epsilon(1e-15));
  const std::array<double, 4> hydro_plus_shear{-50.0, -50.0, -50.0, 10.0}; // NTENS = 4
  sinv_(hydro_plus_shear.data(), &s1, &s2, &ndi4, &nshr4);
  CHECK(s1 == Approx(-50.0).epsilon(1e-15));
  CHECK(s2 == Approx(std::sqrt(3.0) * 10.0).epsilon(1e-15));
  // Invariance: a rotated tensor has the same invariants.
  const Eigen::Matrix3d D = Eigen::Vector3d(30.0, -10.0, -80.0).asDiagonal();
  const Eigen::Matrix3d R = rotation({1.0, 2.0, -0.5}, 0.7);
  const auto s = packed(R * D * R.transpose());
  sinv_(s.data(), &s1, &s2, &ndi, &nshr);
  CHECK(s1 == Approx(-20.0).epsilon(1e-13));
  const double q = std::sqrt(0.5 * (40.0 * 40.0 + 70.0 * 70.0 + 110.0 * 110.0));
  CHECK(s2 == Approx(q).epsilon(1e-13));
}

TEST_CASE("umat utilities: SPRINC and SPRIND give the principal values of a rotated diagonal tensor",
          "[umat]") {
  const int ndi = 3, nshr = 3, stress = 1, strain = 2;
  const Eigen::Matrix3d D = Eigen::Vector3d(-2.0, 3.0, 1.0).asDiagonal();
  const Eigen::Matrix3d R = rotation({0.3, -1.0, 2.0}, 1.1);
  const Eigen::Matrix3d T = R * D * R.transpose();
  std::array<double, 3> ps{};
  const auto s = packed(T);
  sprinc_(s.data(), ps.data(), &stress, &ndi, &nshr);
  CHECK(ps[0] == Approx(3.0).epsilon(1e-13)); // descending
  CHECK(ps[1] == Approx(1.0).epsilon(1e-13));
  CHECK(ps[2] == Approx(-2.0).epsilon(1e-13));
  // A strain: engineering shears (twice the tensor's) give the tensor's principal values.
  const auto e = packed(T, 2.0);
  sprinc_(e.data(), ps.data(), &strain, &ndi, &nshr);
  CHECK(ps[0] == Approx(3.0).epsilon(1e-13));
  CHECK(ps[2] == Approx(-2.0).epsilon(1e-13));
  // SPRIND: AN(K, I) is component I of direction K; T a_K = ps_K a_K, the directions orthonormal
  // and equal (up to sign) to R's columns of the matching diagonal entries.
  std::array<double, 9> an{};
  sprind_(s.data(), ps.data(), an.data(), &stress, &ndi, &nshr);
  Eigen::Matrix3d A; // row K = direction K
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) A(k, i) = an[static_cast<std::size_t>(k + 3 * i)];
  CHECK((A * A.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-13);
  const std::array<int, 3> column{1, 2, 0}; // 3, 1, -2 are D's entries 1, 2, 0
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = A.row(k).transpose();
    CHECK((T * a - ps[static_cast<std::size_t>(k)] * a).norm() <= 1e-12);
    CHECK(std::abs(a.dot(R.col(column[static_cast<std::size_t>(k)]))) == Approx(1.0).epsilon(1e-12));
  }
  // The plane layout NTENS = 4: s33 and the in-plane pair (s11 + s22)/2 +- sqrt(((s11 - s22)/2)^2 + s12^2).
  const int ndi4 = 3, nshr4 = 1;
  const std::array<double, 4> p4{-100.0, -40.0, -60.0, 40.0};
  sprinc_(p4.data(), ps.data(), &stress, &ndi4, &nshr4);
  CHECK(ps[0] == Approx(-70.0 + 50.0).epsilon(1e-14));
  CHECK(ps[1] == Approx(-60.0).epsilon(1e-14));
  CHECK(ps[2] == Approx(-70.0 - 50.0).epsilon(1e-14));
}

TEST_CASE("umat utilities: ROTSIG rotates stresses and strains, and back", "[umat]") {
  const int ndi = 3, nshr = 3, stress = 1, strain = 2;
  const Eigen::Matrix3d R = rotation({1.0, 1.0, 0.2}, -0.9);
  const Eigen::Matrix3d T = (Eigen::Matrix3d() << 10, 3, -2, 3, -5, 4, -2, 4, 7).finished();
  std::array<double, 9> r{}, rt{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      r[static_cast<std::size_t>(i + 3 * j)] = R(i, j); // column-major R(3, 3)
      rt[static_cast<std::size_t>(i + 3 * j)] = R(j, i);
    }
  const auto s = packed(T);
  std::array<double, 6> sp{}, back{};
  rotsig_(s.data(), r.data(), sp.data(), &stress, &ndi, &nshr);
  const auto expected = packed(R * T * R.transpose());
  for (std::size_t i = 0; i < 6; ++i) CHECK(sp[i] == Approx(expected[i]).margin(1e-13));
  rotsig_(sp.data(), rt.data(), back.data(), &stress, &ndi, &nshr);
  for (std::size_t i = 0; i < 6; ++i) CHECK(back[i] == Approx(s[i]).margin(1e-13));
  // A strain keeps engineering shears on both sides.
  const auto e = packed(T, 2.0);
  rotsig_(e.data(), r.data(), sp.data(), &strain, &ndi, &nshr);
  const auto expected_e = packed(R * T * R.transpose(), 2.0);
  for (std::size_t i = 0; i < 6; ++i) CHECK(sp[i] == Approx(expected_e[i]).margin(1e-13));
}

namespace {
void calls_xit(void* reached) {
  xit_();
  *static_cast<int*>(reached) = 1; // never: XIT does not return
}
void returns(void* reached) { *static_cast<int*>(reached) = 1; }
void nested(void* result) {
  int inner = 0;
  const int code = stratum_umat_guarded_call(&calls_xit, &inner);
  *static_cast<int*>(result) = code == 1 && inner == 0 ? 1 : -1; // the inner XIT lands here
}
} // namespace

TEST_CASE("umat utilities: XIT leaves the guarded call, which reports it", "[umat]") {
  int reached = 0;
  CHECK(stratum_umat_guarded_call(&calls_xit, &reached) == 1);
  CHECK(reached == 0);
  CHECK(stratum_umat_guarded_call(&returns, &reached) == 0);
  CHECK(reached == 1);
  int result = 0;
  CHECK(stratum_umat_guarded_call(&nested, &result) == 0); // an inner target, restored after
  CHECK(result == 1);
  reached = 0;
  CHECK(stratum_umat_guarded_call(&calls_xit, &reached) == 1);
}

} // namespace test_umat_conventions
