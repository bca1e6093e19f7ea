// Piles through the full staged path on the axisymmetric_pile mesh (issue 7):
// - E3: an elastic pile bonded to elastic soil, head stiffness against Randolph & Wroth (1978);
// - C1: a stiff pile with a purely cohesive shaft interface, pushed down by a head displacement
//   after self-weight, boring with fresh-concrete pressure and placing the concrete: the shaft
//   slips everywhere at tau_max and carries 2 pi r0 L tau_max.
#include "scene_helpers.hpp"

#include "model/body_interfaces.hpp"
#include "output/interface_output.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>

namespace test_pile_scenes {

using namespace stratum;
using stratum::testing::scene;

namespace {

constexpr double pi = std::numbers::pi;

std::string exact(double v) {
  std::ostringstream o;
  o.precision(17);
  o << v;
  return o.str();
}

/// Randolph & Wroth (1978) head stiffness P / (w G r0) of a compressible pile in homogeneous
/// soil (rho = 1), verification catalogue E3.
double randolph_wroth(double L, double r0, double Ep, double G, double nu) {
  const double zeta = std::log(2.5 * L * (1 - nu) / r0);
  const double lambda = Ep / G;
  const double muL = std::sqrt(2.0 / (zeta * lambda)) * L / r0;
  const double t = std::tanh(muL) / muL;
  return (4 / (1 - nu) + 2 * pi / zeta * t * L / r0) / (1 + 4 / (1 - nu) / (pi * lambda) * t * L / r0);
}

struct StagedPile {
  double r0 = 0.5, L = 20.0, Es = 26000.0, nu = 0.3, Ep = 30e6;
  double near_radius = 5.0, near_depth = 30.0, domain_radius = 50.0, domain_depth = 60.0;
  int n_shaft = 16, n_near = 8, n_far = 6, n_below = 6, n_deep = 4;
  std::string loading; ///< the loading stage's actions
  std::string extra;   ///< interface and contact-law tables
  std::string concrete = "[[stages.actions]]\ntype = \"activate\"\ncells = \"pile\"\n";
  int steps = 1;
};

std::string staged_pile_scene(const StagedPile& s) {
  std::ostringstream t;
  t.precision(17);
  t << "[analysis]\nformulation = \"axisymmetric\"\n[convergence]\nforce_rtol = 1e-9\n";
  t << "[mesh]\ngenerator = \"axisymmetric_pile\"\nnodes_per_cell = 8\n[mesh.pile]\n";
  t << "radius = " << s.r0 << "\nlength = " << s.L << "\nnear_radius = " << s.near_radius
    << "\nnear_depth = " << s.near_depth << "\ndomain_radius = " << s.domain_radius
    << "\ndomain_depth = " << s.domain_depth << "\nn_shaft = " << s.n_shaft << "\nn_near = " << s.n_near
    << "\nn_far = " << s.n_far << "\nn_below = " << s.n_below << "\nn_deep = " << s.n_deep << "\n";
  t << "[materials.soil]\nmodel = \"linear_elastic\"\nE = " << s.Es << "\nnu = " << s.nu << "\n";
  t << "[materials.concrete]\nmodel = \"linear_elastic\"\nE = " << s.Ep << "\nnu = 0.2\n";
  for (const char* set : {"bore", "near", "far"})
    t << "[[domains]]\ncells = \"" << set << "\"\nelement = \"quad\"\nmaterial = \"soil\"\n";
  t << "[[domains]]\ncells = \"pile\"\nelement = \"quad\"\nmaterial = \"concrete\"\n";
  t << s.extra;
  t << "[[constraints]]\nnodes = \"axis\"\nux = 0.0\n[[constraints]]\nnodes = \"far_side\"\nux = 0.0\n";
  t << "[[constraints]]\nnodes = \"bottom\"\nux = 0.0\nuy = 0.0\n";
  t << "[output]\npile_cells = \"pile\"\n";
  t << "[[stages]]\nname = \"geostatic\"\n[[stages.actions]]\ntype = \"deactivate\"\ncells = \"pile\"\n";
  if (s.extra.find("[[interfaces]]") != std::string::npos)
    t << "[[stages.actions]]\ntype = \"deactivate\"\ncells = \"shaft_interface\"\n";
  t << "[[stages.actions]]\ntype = \"geostatic\"\ncells = \"soil\"\ngamma = 18.0\nK0 = 0.5\n";
  t << "[[stages]]\nname = \"boring\"\nsteps = 2\n[[stages.actions]]\ntype = \"deactivate\"\ncells = "
       "\"bore\"\n[[stages.actions]]\ntype = \"pressure\"\nname = \"fresh_concrete\"\nedges = \"hole\"\n"
       "gamma = 24.0\n";
  t << "[[stages]]\nname = \"concrete\"\n" << s.concrete;
  t << "[[stages.actions]]\ntype = \"remove\"\nname = \"fresh_concrete\"\n";
  t << "[[stages.actions]]\ntype = \"gravity\"\nname = \"pile_weight\"\ncells = \"pile\"\ngamma = 24.0\n";
  t << "[[stages]]\nname = \"loading\"\nsteps = " << s.steps
    << "\n[[stages.actions]]\ntype = \"reset_displacements\"\n"
    << s.loading;
  return t.str();
}

/// The scene text with one more line in its [analysis] table (staged_pile_scene writes it first).
std::string with_analysis(std::string text, const std::string& line) {
  const std::string key = "formulation = \"axisymmetric\"\n";
  const auto at = text.find(key);
  REQUIRE(at != std::string::npos);
  return text.insert(at + key.size(), line + "\n");
}

/// A short pile (r0 = 0.25, L = 3) on a small pile mesh with a cohesive (c = 15 kPa) Coulomb
/// interface on the shaft, placed with the hydrostatic fresh-concrete stress: the C1 path of
/// the tests that compare two runs bit for bit.
StagedPile small_slipping_pile() {
  StagedPile s;
  s.r0 = 0.25, s.L = 3.0, s.Ep = 30e6;
  s.near_radius = 2.0, s.near_depth = 4.5, s.domain_radius = 6.0, s.domain_depth = 9.0;
  s.n_shaft = 6, s.n_near = 4, s.n_far = 3, s.n_below = 3, s.n_deep = 2;
  s.extra = "[contact_laws.shaft]\nmodel = \"coulomb_elastoplastic\"\nk_s = 1e5\nk_n = 1e6\nc = 15.0\n"
            "sigma_t = 1000.0\n[[interfaces]]\nname = \"shaft_interface\"\nedges = \"hole\"\ncells = "
            "\"pile\"\nelement = \"interface_line\"\nlaw = \"shaft\"\ncsv = false\n";
  s.concrete = "[[stages.actions]]\ntype = \"activate\"\ncells = \"pile\"\nstress = \"hydrostatic\"\ngamma = "
               "24.0\n[[stages.actions]]\ntype = \"activate\"\ncells = \"shaft_interface\"\nstress = "
               "\"hydrostatic\"\ngamma = 24.0\n";
  return s;
}

} // namespace

TEST_CASE("E3 guard: the Randolph-Wroth formula reproduces the catalogue's worked case", "[verification]") {
  const double G = 10e3;
  CHECK(randolph_wroth(20.0, 0.5, 30e6, G, 0.3) == Approx(59.0485).epsilon(1e-5));
}

TEST_CASE("E3 elastic pile through the staged path: head stiffness within 15 % of Randolph-Wroth",
          "[stages][verification]") {
  StagedPile s;
  const double P = 1000.0;
  s.loading = "[[stages.actions]]\ntype = \"load\"\ncells = \"pile\"\nforce = " + std::to_string(P) + "\n";
  auto a = scene(staged_pile_scene(s), "e3_pile.toml");
  const auto run = a->run();
  INFO(run.outcome.message);
  REQUIRE(run.outcome.ok());
  REQUIRE(run.load_settlement.size() == 2);
  CHECK(run.load_settlement.front()[0] == 0.0);
  CHECK(run.load_settlement.front()[1] == 0.0);
  const double w = 1e-3 * run.load_settlement.back()[1];
  const double G = s.Es / (2 * (1 + s.nu));
  const double fe = P / (w * G * s.r0);
  const double rw = randolph_wroth(s.L, s.r0, s.Ep, G, s.nu);
  CAPTURE(fe, rw, w);
  CHECK(std::abs(fe - rw) <= 0.15 * rw);

  // The same pile under a head displacement: the head load is the reaction on the head nodes. The
  // pile is stiff (E_p / G = 3000), so a uniform head displacement and a uniform head pressure give
  // the same stiffness to well within 1 %.
  s.loading = "[[stages.actions]]\ntype = \"load\"\ncells = \"pile\"\nsettlement = " + exact(w) + "\n";
  auto b = scene(staged_pile_scene(s), "e3_pile_displaced.toml");
  const auto run_b = b->run();
  INFO(run_b.outcome.message);
  REQUIRE(run_b.outcome.ok());
  REQUIRE(run_b.load_settlement.size() == 2);
  CHECK(run_b.load_settlement.front()[0] == 0.0);
  CHECK(run_b.load_settlement.back()[1] == Approx(1e3 * w).epsilon(1e-9));
  CHECK(run_b.load_settlement.back()[0] == Approx(P).epsilon(0.01));
}

TEST_CASE("C1 stiff pile with shaft slip through the staged path: the shaft carries 2 pi r0 L tau_max",
          "[stages][contact]") {
  // A short stiff pile; the interface is purely cohesive (phi = 0), so its strength does not depend
  // on the normal stress the boring and the fresh concrete left on it.
  StagedPile s;
  s.r0 = 0.25, s.L = 3.0, s.Es = 20000.0, s.Ep = 1e9;
  s.near_radius = 2.0, s.near_depth = 4.5, s.domain_radius = 6.0, s.domain_depth = 9.0;
  s.n_shaft = 10, s.n_near = 6, s.n_far = 3, s.n_below = 4, s.n_deep = 2;
  const double tau = 15.0, ks = 1e5;
  s.extra = "[contact_laws.shaft]\nmodel = \"coulomb_elastoplastic\"\nk_s = " + std::to_string(ks) +
            "\nk_n = 1e6\nc = " + std::to_string(tau) +
            "\nsigma_t = 1000.0\n[[interfaces]]\nname = \"shaft_interface\"\nedges = \"hole\"\ncells = "
            "\"pile\"\nelement = \"interface_line\"\nlaw = \"shaft\"\ncsv = false\n";
  s.concrete = "[[stages.actions]]\ntype = \"activate\"\ncells = \"pile\"\nstress = \"hydrostatic\"\ngamma = "
               "24.0\n[[stages.actions]]\ntype = \"activate\"\ncells = \"shaft_interface\"\nstress = "
               "\"hydrostatic\"\ngamma = 24.0\n";
  const double w_max = 0.02;
  s.steps = 20;
  s.loading =
      "[[stages.actions]]\ntype = \"load\"\ncells = \"pile\"\nsettlement = " + std::to_string(w_max) + "\n";
  auto a = scene(staged_pile_scene(s), "c1_pile.toml");
  const auto run = a->run();
  INFO(run.outcome.message);
  REQUIRE(run.outcome.ok());
  REQUIRE(run.load_settlement.size() == 21);
  CHECK(run.load_settlement.back()[1] == Approx(1e3 * w_max).epsilon(1e-9));
  // At the end every point on the shaft wall slips at tau_max (pile moving down: shear on the soil
  // side is downward), so the shaft carries exactly 2 pi r0 L tau_max whatever the quadrature.
  const Model& m = a->model();
  int shaft_points = 0;
  for (const auto& d : m.domains) {
    const auto pts = interface_points(m, d);
    for (const auto& q : pts) {
      if (std::abs(q.x.x() - s.r0) > 1e-9 || q.x.y() < -s.L + 1e-9) continue;
      ++shaft_points;
      CAPTURE(q.x.y(), q.traction[0], q.traction[1]);
      CHECK(std::abs(q.traction[0]) == Approx(tau).epsilon(1e-6));
      CHECK(q.state == ContactState::slip);
    }
  }
  CHECK(shaft_points >= 2 * s.n_shaft);
  // The base carries the rest: the head load exceeds the shaft's share.
  const double shaft_capacity = 2 * pi * s.r0 * s.L * tau;
  CHECK(run.load_settlement.back()[0] > shaft_capacity);
}

TEST_CASE("reusing the stiffness of linear cells or the symbolic analysis changes no number of a staged run",
          "[stages]") {
  // The C1 path (linear soil and pile, a nonlinear interface, cells removed and placed, 10 load
  // steps with slip): the assembler keeps the linear cells' stiffness from the first assembly of
  // each stage (reuse_linear_stiffness = true, the default) or recomputes it every time. The
  // cached matrices are the recomputed ones, so every settlement and load must agree bit for bit
  // (a wrong cache slot or a cache kept across a stage's activation would change them). Likewise
  // with the symbolic analysis repeated before every factorization (reuse_symbolic = false): the
  // ordering comes from the same pattern, so the factors and every number are the same.
  StagedPile s = small_slipping_pile();
  s.Es = 20000.0;
  s.steps = 10;
  s.loading = "[[stages.actions]]\ntype = \"load\"\ncells = \"pile\"\nsettlement = 0.02\n";
  const std::string on = staged_pile_scene(s);
  auto a = scene(on, "reuse_on.toml");
  const auto ra = a->run();
  INFO(ra.outcome.message);
  REQUIRE(ra.outcome.ok());
  REQUIRE(ra.load_settlement.size() == 11);
  CHECK(ra.load_settlement.back()[0] > 2 * pi * s.r0 * s.L * 15.0); // shaft at tau_max plus the base
  for (const char* setting : {"reuse_linear_stiffness = false", "reuse_symbolic = false"}) {
    INFO(setting);
    auto b = scene(with_analysis(on, setting), "reuse_off.toml");
    const auto rb = b->run();
    INFO(rb.outcome.message);
    REQUIRE(rb.outcome.ok());
    REQUIRE(rb.load_settlement.size() == ra.load_settlement.size());
    for (std::size_t i = 0; i < ra.load_settlement.size(); ++i) {
      CHECK(ra.load_settlement[i][0] == rb.load_settlement[i][0]);
      CHECK(ra.load_settlement[i][1] == rb.load_settlement[i][1]);
    }
    CHECK((a->model().u - b->model().u).cwiseAbs().maxCoeff() == 0.0);
    CHECK(b->model().u.cwiseAbs().maxCoeff() > 0.0);
  }
}

TEST_CASE("the element loop on several threads changes no number of a staged nonlinear run", "[stages]") {
  // The C1 path with Duncan-Chang soil (explicit update, so the material and its tangent work at
  // every point) and a slipping interface: the cells are evaluated by one thread or by three
  // (more than this machine's cores, so the threads interleave), and their contributions are
  // summed in cell order either way. Every load, settlement, displacement and point state must
  // agree bit for bit; a race on a point state or a sum in thread order would show here.
  StagedPile s = small_slipping_pile();
  s.steps = 6;
  s.loading = "[[stages.actions]]\ntype = \"load\"\ncells = \"pile\"\nsettlement = 0.01\n";
  std::string text = staged_pile_scene(s);
  const auto from = text.find("[materials.soil]\n"), to = text.find("[materials.concrete]\n");
  REQUIRE(to != std::string::npos);
  REQUIRE(from < to);
  text.replace(from, to - from,
               "[materials.soil]\nmodel = \"duncan_chang\"\nupdate = \"explicit\"\nK = 500.0\nn = 0.82\n"
               "R_f = 0.8\nphi = 26.0\nc = 10.0\nK_ur = 800.0\nG = 0.18\nF = 0.22\nd = 20.0\n"
               "tangent_stabilization = 200.0\n");
  // The loess scene's iteration settings: the explicit update switches branches between
  // iterations, and Newton meets 1e-5 but not the elastic tests' 1e-9.
  const std::string tol = "force_rtol = 1e-9\n";
  REQUIRE(text.find(tol) != std::string::npos);
  text.replace(text.find(tol), tol.size(),
               "force_rtol = 1e-5\nmax_iterations = 40\n[solver]\nline_search = 4\n");
  auto a = scene(with_analysis(text, "threads = 1"), "threads_1.toml");
  auto b = scene(with_analysis(text, "threads = 3"), "threads_3.toml");
  const auto ra = a->run(), rb = b->run();
  INFO(ra.outcome.message << " / " << rb.outcome.message);
  REQUIRE(ra.outcome.ok());
  REQUIRE(rb.outcome.ok());
  REQUIRE(ra.load_settlement.size() >= 7); // 6 steps and the start, and any cut-back steps
  REQUIRE(rb.load_settlement.size() == ra.load_settlement.size());
  for (std::size_t i = 0; i < ra.load_settlement.size(); ++i) {
    CHECK(ra.load_settlement[i][0] == rb.load_settlement[i][0]);
    CHECK(ra.load_settlement[i][1] == rb.load_settlement[i][1]);
  }
  CHECK(ra.load_settlement.back()[1] == Approx(10.0).margin(1e-9)); // the prescribed 10 mm
  CHECK((a->model().u - b->model().u).cwiseAbs().maxCoeff() == 0.0);
  REQUIRE(a->model().domains.size() == b->model().domains.size());
  for (std::size_t d = 0; d < a->model().domains.size(); ++d)
    CHECK(a->model().domains[d].states.committed_data() == b->model().domains[d].states.committed_data());
}

TEST_CASE("far-boundary springs: the geostatic stage starts them at K0 gamma z and the soil stays put",
          "[stages][contact]") {
  // The far side of the pile mesh on two-node springs (contact2 split off the edge set, outer
  // copies fixed) instead of rollers: the thesis' boundary contact elements (the scene's header).
  const double gamma = 18.0, K0 = 0.5; // as in the scene file
  auto a = stratum::testing::test_scene("pile/far_springs.toml");
  const auto run = a->run();
  INFO(run.outcome.message);
  REQUIRE(run.outcome.ok());
  CHECK(run.cutbacks == 0);
  const Model& m = a->model();
  int springs = 0;
  double first_residual = 0.0;
  for (const auto& d : m.domains)
    for (const auto& q : interface_points(m, d)) {
      ++springs;
      const double expected = -K0 * gamma * std::max(-q.x.y(), 0.0); // normal traction, tension positive
      CAPTURE(q.x.y(), q.traction[1], expected);
      CHECK(std::abs(q.traction[1] - expected) <= 1e-6 * gamma * 9.0);
      CHECK(std::abs(q.traction[0]) <= 1e-6 * gamma * 9.0);
    }
  CHECK(springs > 10);
  // The springs hold the soil where it was: the stage's solve moved nothing (before its reset).
  for (const auto& r : run.records)
    first_residual = std::max(first_residual, r.residual_norms.empty() ? 0.0 : r.residual_norms.front());
  CHECK(first_residual <= 1e-6 * gamma * 9.0 * 6.0 * 6.0);
}

TEST_CASE("a run without VTK output still writes its curves and diagnostics into a new directory",
          "[stages][output]") {
  namespace fs = std::filesystem;
  StagedPile s;
  s.n_shaft = 4, s.n_near = 3, s.n_far = 2, s.n_below = 2, s.n_deep = 1;
  s.loading = "[[stages.actions]]\ntype = \"load\"\ncells = \"pile\"\nforce = 100.0\n";
  std::string text = staged_pile_scene(s);
  text.replace(text.find("[output]\n"), 9, "[output]\nvtk = false\n");
  for (auto at = text.find("[[stages]]\nname"); at != std::string::npos;
       at = text.find("[[stages]]\nname", at + 1))
    text.insert(text.find('\n', text.find("name", at)) + 1, "checkpoint = false\n");
  const fs::path dir = fs::temp_directory_path() / "stratum_no_vtk_test" / "deeper";
  fs::remove_all(dir.parent_path());
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = dir.string();
  auto a = Analysis::from_string(text, "no_vtk.toml", std::move(o));
  const auto run = a->run();
  INFO(run.outcome.message);
  REQUIRE(run.outcome.ok());
  CHECK(fs::exists(dir / "diagnostics.csv"));
  CHECK(fs::exists(dir / "curves" / "load_settlement.csv"));
  CHECK(run.checkpoints.empty());
  CHECK(run.pvd.empty());
  fs::remove_all(dir.parent_path());
}

TEST_CASE("settlement components of an elastic pile in elastic soil close: head = shortening + base, shaft + "
          "base load = head load",
          "[stages][pile]") {
  // An elastic pile bonded to elastic soil through an elastic interface (a Coulomb law whose
  // strength is never reached), loaded at its head in 3 steps. The head and toe settlements are
  // area means over the pile's cross-section; the shortening integrates the vertical strain of the
  // pile's integration points: for full integration the three close to round-off (1e-8). The
  // interface forces on the pile balance the head load to the solver's tolerance (1e-9 relative
  // residual, checked at 1e-6).
  StagedPile s = small_slipping_pile();
  s.extra = "[contact_laws.shaft]\nmodel = \"coulomb_elastoplastic\"\nk_s = 1e5\nk_n = 1e6\nc = 1e6\n"
            "sigma_t = 1e6\n[[interfaces]]\nname = \"shaft_interface\"\nedges = \"hole\"\ncells = "
            "\"pile\"\nelement = \"interface_line\"\nlaw = \"shaft\"\ncsv = false\n";
  s.Ep = 3e5; // a compressible pile, so that the shortening is a visible part of the head settlement
  s.steps = 3;
  const double P = 200.0;
  s.loading = "[[stages.actions]]\ntype = \"load\"\ncells = \"pile\"\nforce = " + std::to_string(P) + "\n";
  auto a = scene(staged_pile_scene(s), "components.toml");
  const auto run = a->run();
  INFO(run.outcome.message);
  REQUIRE(run.outcome.ok());
  const auto& rows = run.settlement_components;
  REQUIRE(rows.size() == 4);
  for (double v : rows.front()) CHECK(v == 0.0);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& r = rows[i];
    CAPTURE(i, r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7]);
    CHECK(r[0] == Approx(P * static_cast<double>(i) / 3.0).epsilon(1e-12));
    CHECK(std::abs(r[1] - (r[2] + r[3])) <= 1e-8 * std::abs(r[1]));
    // Each part is a real share: the pile shortens, the toe moves, the shaft slips elastically.
    CHECK(r[2] > 0.05 * r[1]);
    CHECK(r[3] > 0.05 * r[1]);
    CHECK(r[4] > 0.0);
    CHECK(r[5] > 0.0);
    CHECK(r[6] > 0.0);
    CHECK(r[7] > 0.0);
    CHECK(std::abs(r[6] + r[7] - r[0]) <= 1e-6 * r[0]);
    // The head's area mean and the nodal mean of the load-settlement curve agree for a stiff head.
    CHECK(r[1] == Approx(run.load_settlement[i][1]).epsilon(0.02));
  }
  // Linear problem: every component grows in proportion to the load.
  for (std::size_t k = 1; k < 8; ++k) CHECK(rows[3][k] == Approx(3.0 * rows[1][k]).epsilon(1e-6));
}

} // namespace test_pile_scenes
