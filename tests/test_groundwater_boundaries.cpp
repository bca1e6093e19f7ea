// Groundwater boundaries and outputs (docs/groundwater.md) against closed forms:
//  * a sealed column (laterally held, fixed at its base, its top free of load) with water
//    entering through its top at the rate q for the time t. Every volume that enters stays:
//      integral of (eps_v + (n/K_w) p) = q t per unit area, and eps_v = p / M in one dimension
//    (the total vertical stress stays 0, so sigma'_v = p), so the mean excess pressure is
//      p_mean = q t / (H (1/M + n/K_w))  and the top rises by  H p_mean / M,
//    both to 1e-9 (the continuity equations conserve the volume exactly). Long after
//    H^2 / c_v the profile is the parabola of a uniform rise, its top above its base by
//      q gamma_w H / (2 k),
//    which implicit Euler (exact for a rise linear in time) and linear pressures (exact at the
//    nodes in one dimension) give to 1e-6. The point recorder's total vertical stress is 0 and
//    its effective one the pore pressure. Plane strain and axisymmetric (the 2 pi r weight).
//  * a sloped phreatic line (a polyline): the steady pore pressure gamma_w (level(x) - y) at every
//    node, to round-off, and the seepage force: under the whole line the skeleton is pushed along
//    the fall of the level by gamma_w |d level / dx| per unit volume, so the lateral supports of a
//    submerged block carry gamma_w |slope| A together (1e-9).
//  * bad input: a polyline outside the mesh, a level and a line together, x not increasing, an
//    inflow through edges of no porous cell.
#include "scene_helpers.hpp"

#include <catch2/catch.hpp>

#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <unistd.h>

namespace test_groundwater_boundaries {

using namespace stratum;
using Catch::Matchers::Contains;

namespace {

constexpr double E = 10000.0, nu = 0.3, Hc = 2.0, k_perm = 1e-6, n_por = 0.4, K_w = 2.2e6, gw = 10.0;
constexpr double q_in = 1e-7; // m/s

double constrained() { return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
double compliance() { return 1.0 / constrained() + n_por / K_w; }
double cv() { return k_perm / (gw * compliance()); }

std::unique_ptr<Analysis> build(const std::string& toml, RunOptions o = {}) {
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  return Analysis::from_string(toml, "boundaries.toml", std::move(o));
}

/// The sealed column, 1 x 8 quad8p4 cells, water entering its top for `duration` seconds.
std::string inflow_column(const std::string& formulation, double duration) {
  std::ostringstream s;
  s.precision(17);
  s << "[analysis]\nformulation = \"" << formulation << "\"\nsolver = \"newton\"\n"
    << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n[[mesh.blocks]]\nname = \"soil\"\nx = ["
    << (formulation == "axisymmetric" ? "0.5, 1.5" : "0.0, 1.0") << "]\ny = [0.0, " << Hc
    << "]\nnx = 1\nny = 8\n"
    << "[materials.soil]\nmodel = \"linear_elastic\"\nE = " << E << "\nnu = " << nu << "\n"
    << "[[domains]]\ncells = \"soil\"\nelement = \"quad8p4\"\nformulation = \"" << formulation
    << "\"\nmaterial = \"soil\"\npermeability = " << k_perm << "\nporosity = " << n_por
    << "\nfluid_bulk_modulus = " << K_w << "\nunit_weight_water = " << gw << "\n"
    << "[[constraints]]\nnodes = \"left\"\nux = 0.0\n[[constraints]]\nnodes = \"right\"\nux = 0.0\n"
    << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
    << "[[stages]]\nname = \"recharge\"\ntype = \"consolidation\"\nduration = " << duration
    << "\nsteps = 50\n[[stages.actions]]\ntype = \"inflow\"\nedges = \"soil.top\"\nq = " << q_in << "\n"
    << "[[output.history]]\nname = \"mid\"\nkind = \"point\"\nat = ["
    << (formulation == "axisymmetric" ? 1.0 : 0.5)
    << ", 1.0]\nquantities = [\"p\", \"p_excess\", \"syy\", \"syy_eff\", \"syy_total\", \"sxx_total\"]\n";
  // Checks that always pass: the test reads the recorded values from their results.
  for (const char* q : {"p", "p_excess", "syy", "syy_eff", "syy_total", "sxx_total"})
    s << "[[checks]]\nrecorder = \"mid\"\nquantity = \"" << q << "\"\nexpected = 0.0\natol = 1e15\n";
  return s.str();
}

} // namespace

TEST_CASE("groundwater: water entering a sealed column stays in it and rises as the closed form",
          "[groundwater]") {
  const std::string formulation = GENERATE(std::string("plane_strain"), std::string("axisymmetric"));
  INFO(formulation);
  const double duration = 10.0 * Hc * Hc / cv();
  auto a = build(inflow_column(formulation, duration));
  const RunSummary r = a->run();
  REQUIRE(r.outcome.ok());
  const Model& m = a->model();
  const int f = m.dofs.field("p");
  REQUIRE(f >= 0);
  // The pressures along the left side, by height (linear between the corner nodes).
  std::vector<std::pair<double, double>> profile;
  const double left = formulation == "axisymmetric" ? 0.5 : 0.0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    if (const int d = m.dofs.dof(static_cast<int>(n), f);
        d >= 0 && std::abs(m.mesh.nodes[n].x() - left) < 1e-12)
      profile.emplace_back(m.mesh.nodes[n].y(), m.u[d]);
  std::sort(profile.begin(), profile.end());
  REQUIRE(profile.size() == 9);
  double integral = 0.0;
  for (std::size_t i = 1; i < profile.size(); ++i)
    integral += 0.5 * (profile[i].second + profile[i - 1].second) * (profile[i].first - profile[i - 1].first);
  const double mean = integral / Hc;
  CHECK(mean == Approx(q_in * duration / (Hc * compliance())).epsilon(1e-9));
  CHECK(profile.back().second - profile.front().second ==
        Approx(q_in * gw * Hc / (2.0 * k_perm)).epsilon(1e-6));
  double rise = 0.0;
  int top = 0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    if (std::abs(m.mesh.nodes[n].y() - Hc) < 1e-12)
      rise += m.u[m.dofs.dof(static_cast<int>(n), field_uy)], ++top;
  CHECK(rise / top == Approx(Hc * mean / constrained()).epsilon(1e-9));
  // The point recorder: no load, so no total vertical stress; the effective stress is the pressure.
  const auto col = [&](const std::string& q) {
    for (const auto& c : r.checks)
      if (c.label == "mid." + q) return c.value;
    FAIL("no check of " << q);
    return 0.0;
  };
  CHECK(col("p") > 0.9 * mean);
  CHECK(col("p_excess") == col("p")); // no water table: all of it is excess
  CHECK(std::abs(col("syy_total")) < 1e-9 * col("p"));
  CHECK(col("syy_eff") == Approx(col("p")).epsilon(1e-9));
  CHECK(col("syy") == col("syy_eff")); // a porous element's points carry the effective stress
  CHECK(col("sxx_total") == Approx(col("syy_eff") * nu / (1.0 - nu) - col("p")).epsilon(1e-9));
}

TEST_CASE("groundwater: the integration-point cloud carries pore pressure, effective and total stress",
          "[groundwater][vtk]") {
  // The sealed column after water entered: no load, so every point's total vertical stress is 0,
  // its effective vertical stress its pore pressure, all of which is excess (no water table).
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / ("stratum_point_water_" + std::to_string(::getpid()));
  fs::remove_all(out);
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = out.string();
  std::string scene = inflow_column("plane_strain", Hc * Hc / cv());
  scene = stratum::testing::replace_once(scene, "steps = 50", "steps = 4");
  auto a = Analysis::from_string(scene, "boundaries.toml", std::move(o));
  REQUIRE(a->run().outcome.ok());
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName((out / "boundaries_ip_4.vtp").string().c_str());
  reader->Update();
  vtkPolyData* cloud = reader->GetOutput();
  REQUIRE(cloud->GetNumberOfPoints() == 8 * 9);
  vtkDataArray* p = cloud->GetPointData()->GetArray("pore_pressure [kPa]");
  vtkDataArray* excess = cloud->GetPointData()->GetArray("excess_pore_pressure [kPa]");
  vtkDataArray* effective = cloud->GetPointData()->GetArray("effective_stress [kPa]");
  vtkDataArray* total = cloud->GetPointData()->GetArray("total_stress [kPa]");
  REQUIRE((p && excess && effective && total));
  REQUIRE(total->GetNumberOfComponents() == 6);
  double largest = 0.0;
  for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); ++i) {
    largest = std::max(largest, p->GetComponent(i, 0));
    CHECK(excess->GetComponent(i, 0) == p->GetComponent(i, 0));
    CHECK(effective->GetComponent(i, 1) == Approx(p->GetComponent(i, 0)).epsilon(1e-9));
    CHECK(std::abs(total->GetComponent(i, 1)) < 1e-9 * std::max(1.0, p->GetComponent(i, 0)));
  }
  CHECK(largest > 1.0);
  fs::remove_all(out);
}

namespace {

/// A 10 x 6 m block of 8-node u-p cells under a phreatic polyline, fixed laterally and at its
/// base, its self-weight applied by a geostatic stage.
std::string sloped_block(const std::string& line_x, const std::string& line_y) {
  return R"([analysis]
formulation = "plane_strain"
solver = "newton"
[mesh]
generator = "blocks"
nodes_per_cell = 8
[[mesh.blocks]]
name = "soil"
x = [0.0, 10.0]
y = [-6.0, 0.0]
nx = 10
ny = 6
[materials.soil]
model = "linear_elastic"
E = 20000.0
nu = 0.3
[[domains]]
cells = "soil"
element = "quad8p4"
formulation = "plane_strain"
material = "soil"
permeability = 1e-7
porosity = 0.35
fluid_bulk_modulus = 2.2e6
unit_weight_water = 10.0
[[constraints]]
nodes = "left"
ux = 0.0
[[constraints]]
nodes = "right"
ux = 0.0
[[constraints]]
nodes = "bottom"
uy = 0.0
[[stages]]
name = "geostatic"
[[stages.actions]]
type = "geostatic"
gamma = 18.0
gamma_sat = 20.0
gamma_w = 10.0
K0 = 0.5
water_line_x = )" +
         line_x + "\nwater_line_y = " + line_y + "\n";
}

} // namespace

TEST_CASE("groundwater: a sloped phreatic line, hydrostatic in every vertical, pushes the skeleton along "
          "its fall",
          "[groundwater]") {
  SECTION("a line through the block: the steady pressure at every node") {
    auto a = build(sloped_block("[-1.0, 4.0, 11.0]", "[-1.0, -2.0, -5.5]"));
    REQUIRE(a->run().outcome.ok());
    const Model& m = a->model();
    REQUIRE(m.water.present());
    int wet = 0;
    for (const auto& x : m.mesh.nodes) {
      // The level through (-1, -1), (4, -2), (11, -5.5), linear between the points.
      const double level = x.x() < 4.0 ? -1.0 - 0.2 * (x.x() + 1.0) : -2.0 - 0.5 * (x.x() - 4.0);
      const double expected = x.y() < level ? 10.0 * (level - x.y()) : 0.0;
      CHECK(m.water.pressure(x.x(), x.y()) == Approx(expected).margin(1e-12));
      wet += x.y() < level;
    }
    CHECK(wet > 0);
  }
  SECTION("a submerged block: its supports carry the seepage force gamma_w |slope| A") {
    auto a = build(sloped_block("[0.0, 10.0]", "[1.0, 0.5]"));
    REQUIRE(a->run().outcome.ok());
    const Model& m = a->model();
    double rx = 0.0;
    for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
      if (const int d = m.dofs.dof(static_cast<int>(n), field_ux); d >= 0 && m.dofs.eq[d] < 0)
        rx += m.reactions[d] - m.load_base[d] - m.lambda * m.load_ref[d];
    // The level falls by 0.05 per metre: the water pushes the skeleton along +x with 0.5 kN/m3
    // over 60 m2; the supports hold it back.
    CHECK(rx == Approx(-10.0 * 0.05 * 60.0).epsilon(1e-9));
  }
}

TEST_CASE("groundwater: a phreatic polyline and an inflow refuse bad input with one located line",
          "[groundwater]") {
  const auto refused = [](const std::string& toml, const std::string& what) {
    INFO(what);
    REQUIRE_THROWS_WITH(build(toml), Contains(what));
  };
  refused(sloped_block("[2.0, 11.0]", "[-1.0, -2.0]"),
          "boundaries.toml:43:16 [[stages]] #1 [[stages.actions]] #1 type = \"geostatic\" water_line_x runs "
          "from 2 to "
          "11 but the mesh from x = 0 to 10: the phreatic polyline lies partly outside the mesh");
  refused(sloped_block("[0.0, 10.0, 10.0]", "[-1.0, -2.0, -3.0]"),
          "water_line_x must increase strictly; 10 follows 10 (point 3)");
  refused(sloped_block("[0.0, 10.0]", "[-1.0]"), "a phreatic polyline needs the same number, at least 2");
  refused(sloped_block("[0.0, 10.0]", "[-1.0, -2.0]") + "water_level = -1.0\n",
          "give either water_level (a horizontal level) or water_line_x and water_line_y");
  // An inflow through the top of displacement-only cells: no node there carries a pore pressure.
  std::string dry = sloped_block("[0.0, 10.0]", "[-1.0, -2.0]");
  dry = stratum::testing::replace_once(dry, "element = \"quad8p4\"", "element = \"quad\"");
  dry = stratum::testing::replace_once(
      dry, "permeability = 1e-7\nporosity = 0.35\nfluid_bulk_modulus = 2.2e6\nunit_weight_water = 10.0\n",
      "");
  refused(
      dry +
          "[[stages]]\nname = \"recharge\"\n[[stages.actions]]\ntype = \"inflow\"\nedges = \"soil.top\"\nq = "
          "1e-7\n",
      "inflow: no node of edge set \"soil.top\" carries a pore pressure p; the set must bound cells of a "
      "porous "
      "element");
  refused(inflow_column("plane_strain", 10.0) +
              "[[stages.actions]]\ntype = \"water_level\"\nline_x = [0.0, 0.5]\n"
              "line_y = [1.0, 1.0]\n",
          "line_x runs from 0 to 0.5 but the mesh from x = 0 to 1");
}

} // namespace test_groundwater_boundaries
