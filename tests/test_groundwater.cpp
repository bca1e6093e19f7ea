// Groundwater (docs/groundwater.md) against closed forms, whole scenes with the u-p elements of
// plugins/biot:
//  * a sealed oedometer loaded undrained: the excess pore pressure p = q (K_w/n) / (M + K_w/n)
//    at every node and the settlement H (q - p) / M, plane strain and axisymmetric (1e-8);
//  * Terzaghi's one-dimensional consolidation: a column of height H drained at its top (the drain
//    opens when the consolidation stage starts), impermeable and fixed at its base, under a load
//    q applied undrained. The excess pore pressure follows the series
//      p(z, t) = p0 sum_m (2 / M_m) sin(M_m z / H) exp(-M_m^2 T),  M_m = pi (2m + 1) / 2,
//    z the depth below the drained top, T = c_v t / H^2, c_v = k / (gamma_w (1/M + n/K_w)) (the
//    fluid's compressibility included), and the degree of consolidation (from the settlement)
//      U(T) = 1 - sum_m (2 / M_m^2) exp(-M_m^2 T).
//    Asserted at T = 0.05, 0.1, 0.2, 0.5, 1: the isochrones within 1 % of p0 at every pressure
//    node, U(T) within 1 % of the series value; for 40 quad8p4 cells and for 160 tri6p3 triangles
//    (a Gmsh mesh).
//  * Mandel's problem (plane strain): a quarter of a 2a x 2b specimen (a = 1, b = 1) squeezed by
//    the pressure s0 through a rigid, smooth plate (an isotropic plate of E = 1e9 kPa on a
//    zero-strength interface of shear stiffness 1e-3 kPa/m, so that it neither bends nor holds
//    the specimen's top back), drained at its sides x = +-a from the consolidation's start.
//    The undrained response is p0 = B (1 + nu_u) s0 / 3 with Skempton's B = (K_w/n) / (K + K_w/n)
//    and nu_u = (3 K_u - 2 G) / (2 (3 K_u + G)), K_u = K + K_w/n; then the centre's pressure
//    first rises (Mandel-Cryer) and follows Cheng and Detournay's (1988) series
//      p(x, t) = (2 s0 B (1 + nu_u) / 3) sum_i sin a_i / (a_i - sin a_i cos a_i) (cos(a_i x / a)
//                - cos a_i) exp(-a_i^2 c t / a^2),  tan a_i = (1 - nu) / (nu_u - nu) a_i,
//      c = 2 (k / gamma_w) G (1 - nu)(nu_u - nu) / ((1 - 2 nu)^2 (1 - nu_u)).
//    Asserted at T = c t / a^2 = 0.01 ... 1: within 2 % of p0 (the issue's bound; measured
//    0.2 % at T = 1 with 60 implicit Euler steps between the marks, 0.6 % with 20), and the rise above p0.
//  * the geostatic stage below a phreatic level: the steady pore pressure gamma_w (z_w - y) and
//    the effective stresses sigma'_v = -(gamma (z_0 - max(y, z_w)) + (gamma_sat - gamma_w)
//    max(z_w - y, 0)), sigma'_h = K0 sigma'_v at every point, to round-off; the buoyant
//    self-weight holds them in equilibrium (no displacement, no excess pressure);
//  * a displacement domain with drainage = "undrained" (the fluid's stiffness K_w/n added to the
//    skeleton, an excess pressure per point) gives the sealed oedometer's p0 at every point and
//    the same settlement as the u-p cells, to 1e-8;
//  * undrained triaxial compression of Modified Cam-Clay as a boundary-value problem (one
//    axisymmetric quad8p4 cell, an incompressible pore fluid, all boundaries closed) follows the
//    material-point driver's isochoric path (inputs/point/mcc_undrained.toml) to 1e-6 of p0.
#include "scene_helpers.hpp"

#include "stratum/point_driver.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace test_groundwater {

using namespace stratum;

namespace {

constexpr double E = 10000.0, nu = 0.3, q = 100.0, H = 10.0;
constexpr double k_perm = 1e-8, n_por = 0.4, K_w = 2.2e6, gamma_w = 10.0;

/// The constrained (oedometric) modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu)).
double oedometric() { return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
double fluid() { return K_w / n_por; }
double p0() { return q * fluid() / (oedometric() + fluid()); }
double cv() { return k_perm / (gamma_w * (1.0 / oedometric() + n_por / K_w)); }

double terzaghi_p(double depth, double T) {
  double s = 0.0;
  for (int m = 0; m < 400; ++m) {
    const double Mm = std::numbers::pi * (2.0 * m + 1.0) / 2.0;
    s += 2.0 / Mm * std::sin(Mm * depth / H) * std::exp(-Mm * Mm * T);
  }
  return p0() * s;
}

double terzaghi_U(double T) {
  double s = 0.0;
  for (int m = 0; m < 400; ++m) {
    const double Mm = std::numbers::pi * (2.0 * m + 1.0) / 2.0;
    s += 2.0 / (Mm * Mm) * std::exp(-Mm * Mm * T);
  }
  return 1.0 - s;
}

/// A column of 1 x ny 8-node u-p cells (width 1, height H), held laterally and at its base,
/// loaded by q on its top in a static stage (undrained); `more` follows (further stages).
std::string column(const std::string& formulation, int ny, const std::string& more) {
  std::ostringstream s;
  s.precision(17);
  s << "[analysis]\nformulation = \"" << formulation << "\"\nsolver = \"newton\"\n"
    << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n"
    << "[[mesh.blocks]]\nname = \"soil\"\nx = [" << (formulation == "axisymmetric" ? "0.5, 1.5" : "0.0, 1.0")
    << "]\ny = [0.0, " << H << "]\nnx = 1\nny = " << ny << "\n"
    << "[materials.soil]\nmodel = \"linear_elastic\"\nE = " << E << "\nnu = " << nu << "\n"
    << "[[domains]]\ncells = \"soil\"\nelement = \"quad8p4\"\nformulation = \"" << formulation
    << "\"\nmaterial = \"soil\"\npermeability = " << k_perm << "\nporosity = " << n_por
    << "\nfluid_bulk_modulus = " << K_w << "\nunit_weight_water = " << gamma_w << "\n"
    << "[[constraints]]\nnodes = \"left\"\nux = 0.0\n[[constraints]]\nnodes = \"right\"\nux = 0.0\n"
    << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
    << "[[stages]]\nname = \"load\"\n[[stages.actions]]\ntype = \"pressure\"\nedges = \"soil.top\"\np = " << q
    << "\n"
    << more;
  return s.str();
}

/// The same column of 6-node u-p triangles (tri6p3): 2 x 40 rectangles of a Gmsh mesh
/// (tests/scenes/groundwater/column_tri6.msh, written by make_column_tri6.py beside it), each split
/// along an alternating diagonal; its edge sets are top, bottom, left, right.
std::string tri_column(const std::string& more) {
  std::string s = column("plane_strain", 1, more);
  s = testing::replace_once(s,
                            "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n[[mesh.blocks]]\nname = "
                            "\"soil\"\nx = [0.0, 1.0]\ny = [0.0, 10]\nnx = 1\nny = 1\n",
                            "[mesh]\ngenerator = \"gmsh\"\nfile = \"" +
                                testing::scene_path("groundwater/column_tri6.msh") + "\"\n");
  s = testing::replace_once(s, "element = \"quad8p4\"", "element = \"tri6p3\"");
  for (auto at = s.find("\"soil.top\""); at != std::string::npos; at = s.find("\"soil.top\""))
    s.replace(at, 10, "\"top\"");
  return s;
}

std::unique_ptr<Analysis> build(const std::string& toml, RunOptions o = {}) {
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  return Analysis::from_string(toml, "groundwater.toml", std::move(o));
}

/// Mean vertical displacement of the top nodes.
double top_settlement(const Model& m) {
  double s = 0.0;
  int count = 0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    if (std::abs(m.mesh.nodes[n].y() - H) < 1e-9)
      s -= m.u[m.dofs.dof(static_cast<int>(n), field_uy)], ++count;
  return s / count;
}

} // namespace

TEST_CASE("groundwater: a sealed oedometer loaded undrained carries p = q (K_w/n) / (M + K_w/n)",
          "[groundwater]") {
  for (const std::string formulation : {"plane_strain", "axisymmetric"}) {
    INFO(formulation);
    auto a = build(column(formulation, 4, ""));
    const RunSummary s = a->run();
    REQUIRE(s.outcome.ok());
    const Model& m = a->model();
    const int f = m.dofs.field("p");
    REQUIRE(f >= 0);
    int nodes = 0;
    for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
      if (const int d = m.dofs.dof(static_cast<int>(n), f); d >= 0) {
        CHECK(m.u[d] == Approx(p0()).epsilon(1e-8));
        ++nodes;
      }
    CHECK(nodes == 10); // the corners of 4 cells stacked
    CHECK(top_settlement(m) == Approx(H * (q - p0()) / oedometric()).epsilon(1e-8));
  }
}

TEST_CASE("groundwater: Terzaghi's consolidation follows the series solution within 1 %", "[groundwater]") {
  // Time steps: 60 equal ones between the listed T (implicit Euler is first order in time: with
  // 20 the error at T = 0.5 was 0.5 %), 40 geometric ones from T = 1e-5 to 0.01 before them.
  const std::vector<double> marks{0.05, 0.1, 0.2, 0.5, 1.0};
  const double duration = marks.back() * H * H / cv();
  std::vector<double> T_end; // the end of each step, as a time factor
  for (int i = 0; i <= 40; ++i) T_end.push_back(1e-5 * std::pow(0.01 / 1e-5, i / 40.0));
  double from = T_end.back();
  for (double mark : marks) {
    const int n = 60;
    for (int i = 1; i <= n; ++i) T_end.push_back(from + (mark - from) * i / n);
    from = mark;
  }
  std::ostringstream inc;
  inc.precision(17);
  double prev = 0.0;
  for (std::size_t i = 0; i < T_end.size(); ++i) {
    const double last = i + 1 == T_end.size() ? 1.0 : T_end[i] / marks.back();
    inc << (i ? ", " : "") << last - prev;
    prev = last;
  }
  // The increments must sum to 1 within the reader's 1e-9: rounding the last one does that.
  std::ostringstream more;
  more.precision(17);
  more << "[[stages]]\nname = \"consolidate\"\ntype = \"consolidation\"\nduration = " << duration
       << "\nincrements = [" << inc.str()
       << "]\n[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n";

  std::map<double, std::vector<std::array<double, 2>>> isochrones; // T -> (depth, p)
  std::map<double, double> settlement;
  double undrained = 0.0;
  Analysis* analysis = nullptr;
  RunOptions o;
  o.on_step = [&](int, int, double lambda, const StepReport&) {
    const Model& m = analysis->model();
    if (m.clock.stage == 1) {
      undrained = top_settlement(m);
      return;
    }
    const double T = lambda * marks.back();
    for (double mark : marks) {
      if (std::abs(T - mark) > 1e-9 * mark) continue;
      settlement[mark] = top_settlement(m);
      const int f = m.dofs.field("p");
      for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
        if (const int d = m.dofs.dof(static_cast<int>(n), f); d >= 0)
          isochrones[mark].push_back({H - m.mesh.nodes[n].y(), m.u[d]});
    }
  };
  const bool triangles = GENERATE(false, true);
  INFO((triangles ? "tri6p3, 160 triangles" : "quad8p4, 40 quadrilaterals"));
  auto a = build(triangles ? tri_column(more.str()) : column("plane_strain", 40, more.str()), std::move(o));
  analysis = a.get();
  const RunSummary s = a->run();
  REQUIRE(s.outcome.ok());
  REQUIRE(isochrones.size() == marks.size());
  CHECK(undrained == Approx(H * (q - p0()) / oedometric()).epsilon(1e-8));
  const double final_settlement = H * q / oedometric();
  for (double T : marks) {
    INFO("T = " << T);
    double worst = 0.0;
    for (const auto& [depth, p] : isochrones[T]) worst = std::max(worst, std::abs(p - terzaghi_p(depth, T)));
    INFO("largest |p - series| / p0 = " << worst / p0());
    CHECK(worst <= 0.01 * p0());
    const double U = (settlement[T] - undrained) / (final_settlement - undrained);
    INFO("U = " << U << ", series " << terzaghi_U(T));
    CHECK(U == Approx(terzaghi_U(T)).epsilon(0.01));
  }
}

namespace {

/// Mandel's quarter specimen (see the top of the file), the consolidation stage's increments
/// given.
std::string mandel_scene(double duration, const std::string& increments) {
  std::ostringstream s;
  s.precision(17);
  s << R"([analysis]
formulation = "plane_strain"
solver = "newton"
[mesh]
generator = "blocks"
nodes_per_cell = 8
[[mesh.blocks]]
name = "soil"
x = [0.0, 1.0]
y = [0.0, 1.0]
nx = 20
ny = 4
[[mesh.blocks]]
name = "plate"
x = [0.0, 1.0]
y = [1.0, 1.1]
nx = 20
ny = 1
[materials.soil]
model = "linear_elastic"
E = 10000.0
nu = 0.2
[materials.plate]
model = "linear_elastic"
E = 1.0e9
nu = 0.0
[contact_laws.smooth]
model = "coulomb_elastoplastic"
k_s = 1.0e-3
k_n = 1.0e10
c = 1.0e6
[[interfaces]]
name = "smooth"
edges = "soil.top"
cells = "plate"
element = "interface_line"
law = "smooth"
[[domains]]
cells = "soil"
element = "quad8p4"
formulation = "plane_strain"
material = "soil"
permeability = 1e-6
porosity = 0.3
fluid_bulk_modulus = 2.2e6
unit_weight_water = 10.0
[[domains]]
cells = "plate"
element = "quad"
formulation = "plane_strain"
material = "plate"
[[constraints]]
nodes = "left"
ux = 0.0
[[constraints]]
nodes = "bottom"
uy = 0.0
[[stages]]
name = "load"
[[stages.actions]]
type = "pressure"
edges = "plate.top"
p = 100.0
[[stages]]
name = "consolidate"
type = "consolidation"
)";
  s << "duration = " << duration << "\nincrements = [" << increments << "]\n";
  s << "[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.right\"\n";
  return s.str();
}

/// Increments (as a TOML list) whose step ends fall on every mark (fractions of the last mark):
/// `geometric` steps from marks[0] * 1e-3 to marks[0], then `per_mark` equal ones between marks.
std::string increments_through(const std::vector<double>& marks, int geometric, int per_mark) {
  std::vector<double> ends;
  for (int i = 0; i <= geometric; ++i) ends.push_back(1e-3 * marks[0] * std::pow(1e3, double(i) / geometric));
  for (std::size_t k = 1; k < marks.size(); ++k)
    for (int i = 1; i <= per_mark; ++i)
      ends.push_back(marks[k - 1] + (marks[k] - marks[k - 1]) * i / per_mark);
  std::ostringstream inc;
  inc.precision(17);
  double prev = 0.0;
  for (std::size_t i = 0; i < ends.size(); ++i) {
    const double end = i + 1 == ends.size() ? 1.0 : ends[i] / marks.back();
    inc << (i ? ", " : "") << end - prev;
    prev = end;
  }
  return inc.str();
}

} // namespace

TEST_CASE("groundwater: Mandel's problem, the centre's pressure rises and follows the series within 2 %",
          "[groundwater]") {
  constexpr double Em = 1e4, num = 0.2, nm = 0.3, Kwm = 2.2e6, km = 1e-6, gwm = 10.0, a = 1.0, s0 = 100.0;
  const double K = Em / (3.0 * (1.0 - 2.0 * num)), G = Em / (2.0 * (1.0 + num)), Kf = Kwm / nm;
  const double B = Kf / (Kf + K), Ku = K + Kf;
  const double nuu = (3.0 * Ku - 2.0 * G) / (2.0 * (3.0 * Ku + G));
  const double c = 2.0 * (km / gwm) * G * (1.0 - num) * (nuu - num) /
                   ((1.0 - 2.0 * num) * (1.0 - 2.0 * num) * (1.0 - nuu));
  const double p0 = B * (1.0 + nuu) * s0 / 3.0;
  // The roots of tan a = C a: one in (0, pi/2), then one in (i pi, i pi + pi/2).
  const double C = (1.0 - num) / (nuu - num);
  std::vector<double> roots;
  for (int i = 0; i < 300; ++i) {
    double lo = i * std::numbers::pi + 1e-12, hi = i * std::numbers::pi + std::numbers::pi / 2 - 1e-12;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (std::tan(mid) - C * mid > 0.0 ? hi : lo) = mid;
    }
    roots.push_back(0.5 * (lo + hi));
  }
  auto series = [&](double x, double T) {
    double sum = 0.0;
    for (double r : roots)
      sum += std::sin(r) / (r - std::sin(r) * std::cos(r)) * (std::cos(r * x / a) - std::cos(r)) *
             std::exp(-r * r * T);
    return 2.0 * s0 * B * (1.0 + nuu) / 3.0 * sum;
  };
  const std::vector<double> marks{0.01, 0.05, 0.1, 0.2, 0.5, 1.0};
  const double duration = marks.back() * a * a / c;
  std::map<double, double> centre;
  double undrained = 0.0;
  Analysis* analysis = nullptr;
  RunOptions o;
  o.on_step = [&](int, int, double lambda, const StepReport&) {
    const Model& m = analysis->model();
    const double p = m.u[m.dofs.dof(testing::node_at(m, 0.0, 0.0), m.dofs.field("p"))];
    if (m.clock.stage == 1) undrained = p;
    for (double mark : marks)
      if (m.clock.stage == 2 && std::abs(lambda * marks.back() - mark) <= 1e-9 * mark) centre[mark] = p;
  };
  auto an = build(mandel_scene(duration, increments_through(marks, 20, 60)), std::move(o));
  analysis = an.get();
  const RunSummary s = an->run();
  REQUIRE(s.outcome.ok());
  REQUIRE(centre.size() == marks.size());
  CHECK(undrained == Approx(p0).epsilon(1e-6));
  CHECK(centre[0.05] > 1.05 * p0); // Mandel-Cryer: the centre's pressure first rises
  for (double T : marks) {
    INFO("T = " << T << ": p = " << centre[T] << ", series " << series(0.0, T) << ", p0 " << p0);
    CHECK(std::abs(centre[T] - series(0.0, T)) <= 0.02 * p0);
  }
}

TEST_CASE("groundwater: the geostatic stage below a phreatic level sets p = gamma_w (z_w - y) and effective "
          "stresses",
          "[groundwater]") {
  constexpr double gamma = 17.0, gamma_sat = 20.0, gw = 9.81, K0 = 0.55, top = 10.0;
  for (double level : {10.0, 6.0}) {
    INFO("water level " << level);
    std::ostringstream s;
    s.precision(17);
    s << R"([analysis]
formulation = "axisymmetric"
[mesh]
generator = "blocks"
nodes_per_cell = 8
[[mesh.blocks]]
name = "soil"
x = [0.5, 1.5]
y = [0.0, 10.0]
nx = 1
ny = 10
[materials.soil]
model = "linear_elastic"
E = 10000.0
nu = 0.3
[[domains]]
cells = "soil"
element = "quad8p4"
material = "soil"
permeability = 1e-8
porosity = 0.4
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
)";
    s << "gamma = " << gamma << "\ngamma_sat = " << gamma_sat << "\ngamma_w = " << gw << "\nK0 = " << K0
      << "\nsurface = " << top << "\nwater_level = " << level << "\n";
    auto a = build(s.str());
    const RunSummary r = a->run();
    REQUIRE(r.outcome.ok());
    const Model& m = a->model();
    REQUIRE(m.water.present());
    for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
      const double y = m.mesh.nodes[n].y();
      CHECK(m.water.pressure(m.mesh.nodes[n].x(), y) ==
            Approx(y < level ? gw * (level - y) : 0.0).margin(1e-12));
      if (const int d = m.dofs.dof(static_cast<int>(n), m.dofs.field("p")); d >= 0)
        CHECK(std::abs(m.u[d]) < 1e-9); // no excess pressure: the buoyant weight holds the stress
    }
    const Domain& dm = m.domains[0];
    int points = 0;
    Eigen::MatrixXd x, xp;
    std::vector<int> nodes;
    for (std::size_t c = 0; c < dm.cells.size(); ++c) {
      m.cell_nodes(dm.cells[c], nodes, x);
      dm.element->point_coordinates(m.element_data(dm.cells[c], x), xp);
      for (Eigen::Index i = 0; i < xp.rows(); ++i, ++points) {
        const double y = xp(i, 1);
        const double sv = -(gamma * (top - std::max(y, level)) + (gamma_sat - gw) * std::max(level - y, 0.0));
        const Vec6 st = dm.states.committed(dm.first_point[c] + static_cast<std::size_t>(i)).stress();
        CHECK(st[1] == Approx(sv).epsilon(1e-12));
        CHECK(st[0] == Approx(K0 * sv).epsilon(1e-12));
        CHECK(st[2] == Approx(K0 * sv).epsilon(1e-12));
      }
    }
    CHECK(points == 90);
  }
}

TEST_CASE("groundwater: undrained triaxial compression of Modified Cam-Clay follows the point driver",
          "[groundwater]") {
  const std::string mcc = R"(model = "modified_cam_clay"
M = 1.2
lambda = 0.077
kappa = 0.0066
e0 = 1.0
nu = 0.3
ocr = 1.0
integrator = "closest_point"
)";
  constexpr int steps = 150;
  constexpr double axial = -0.15, p0 = 200.0;
  std::ostringstream point;
  point << "[material]\n"
        << mcc << "[initial]\np = " << p0 << "\n[[paths]]\ntype = \"triaxial_undrained\"\n"
        << "axial_strain = " << axial << "\nsteps = " << steps << "\n";
  const PointRun path = PointDriver::from_string(point.str(), "mcc.toml", {STRATUM_PLUGIN_DIR})->run();
  REQUIRE(path.outcome.ok());
  REQUIRE(path.rows.size() == steps + 1);

  std::ostringstream s;
  s << R"([analysis]
formulation = "axisymmetric"
solver = "newton"
[convergence]
force_rtol = 1e-11
[mesh]
generator = "blocks"
nodes_per_cell = 8
[[mesh.blocks]]
name = "soil"
x = [0.0, 1.0]
y = [0.0, 1.0]
nx = 1
ny = 1
[materials.soil]
)" << mcc
    << R"([[domains]]
cells = "soil"
element = "quad8p4"
material = "soil"
permeability = 0.0
porosity = 0.5
fluid_bulk_modulus = 0.0
[[constraints]]
nodes = "left"
ux = 0.0
[[constraints]]
nodes = "bottom"
uy = 0.0
[[stages]]
name = "consolidated"
[[stages.actions]]
type = "geostatic"
gamma = 0.0
surcharge = 200.0
K0 = 1.0
surface = 1.0
[[stages.actions]]
type = "pressure"
name = "cell_pressure"
edges = "soil.right"
p = 200.0
[[stages.actions]]
type = "pressure"
name = "ram"
edges = "soil.top"
p = 200.0
[[stages]]
name = "shear"
)"
    << "steps = " << steps
    << "\n[[stages.actions]]\ntype = \"displacement\"\nnodes = \"soil.top\"\nuy = " << axial << "\n";
  std::vector<Vec6> bvp;
  Analysis* analysis = nullptr;
  RunOptions o;
  o.on_step = [&](int, int, double, const StepReport&) {
    const Model& m = analysis->model();
    if (m.clock.stage == 2) bvp.push_back(m.domains[0].states.committed(4).stress());
  };
  auto a = build(s.str(), std::move(o));
  analysis = a.get();
  const RunSummary r = a->run();
  REQUIRE(r.outcome.ok());
  REQUIRE(bvp.size() == steps);
  auto invariants = [](const Vec6& st) {
    const double p = -(st[0] + st[1] + st[2]) / 3.0;
    Vec6 dev = st;
    for (int i = 0; i < 3; ++i) dev[i] += p;
    const double q = std::sqrt(1.5 * (dev.head<3>().squaredNorm() + 2.0 * dev.tail<3>().squaredNorm()));
    return std::array<double, 2>{p, q};
  };
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    const auto b = invariants(bvp[static_cast<std::size_t>(k)]);
    const auto d = invariants(path.rows[static_cast<std::size_t>(k + 1)].stress);
    worst = std::max({worst, std::abs(b[0] - d[0]), std::abs(b[1] - d[1])});
  }
  INFO("largest difference in p' or q: " << worst << " kPa");
  CHECK(worst <= 1e-6 * p0);
  // And the path is the closed form's: at failure q/p' -> M, p'_f = 106.121 kPa (the point file's note).
  const auto last = invariants(bvp.back());
  CHECK(last[1] / last[0] == Approx(1.2).epsilon(2e-3));
}

namespace {

/// The message of the error building `text` (as groundwater.toml) throws; "" when it builds.
std::string build_error(const std::string& text) { return testing::build_error(text, "groundwater.toml"); }

const std::string consolidate =
    "[[stages]]\nname = \"consolidate\"\ntype = \"consolidation\"\nduration = 1000.0\n"
    "[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n";

} // namespace

TEST_CASE("groundwater: bad input gets one located line", "[groundwater]") {
  const std::string ok = column("plane_strain", 2, consolidate);
  REQUIRE(build_error(ok).empty());
  using Catch::Contains;
  // Permeability missing or negative: the domain's table says so at its line.
  CHECK_THAT(build_error(testing::replace_once(ok, "permeability = 1e-08\n", "")),
             Contains("groundwater.toml:") && Contains("permeability"));
  CHECK_THAT(build_error(testing::replace_once(ok, "permeability = 1e-08", "permeability = -1e-08")),
             Contains("groundwater.toml:22:") && Contains("permeability"));
  // A time step of zero: the duration must be positive; increments must be positive.
  CHECK_THAT(build_error(testing::replace_once(ok, "duration = 1000.0", "duration = 0.0")),
             Contains("duration") && Contains("(0, inf)"));
  CHECK_THAT(build_error(testing::replace_once(ok, "duration = 1000.0",
                                               "duration = 1000.0\nincrements = [0.5, 0.0, 0.5]")),
             Contains("increments must all be > 0"));
  CHECK_THAT(build_error(testing::replace_once(ok, "duration = 1000.0\n", "")),
             Contains("needs its duration"));
  // A duration in a static stage; a consolidation stage in a model without a pore pressure.
  CHECK_THAT(build_error(testing::replace_once(ok, "type = \"consolidation\"\n", "")),
             Contains("acts only in a stage with type = \"consolidation\""));
  std::string dry = testing::replace_once(ok, "element = \"quad8p4\"", "element = \"quad\"");
  for (const char* key : {"permeability = 1e-08\n", "porosity = 0.40000000000000002\n",
                          "fluid_bulk_modulus = 2200000\n", "unit_weight_water = 10\n"})
    dry = testing::replace_once(dry, key, "");
  dry = testing::replace_once(dry, "[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n", "");
  CHECK_THAT(build_error(dry), Contains("no domain carries a pore pressure p"));
  // A drain on nodes that carry no pore pressure.
  CHECK_THAT(build_error(testing::replace_once(
                 dry, "duration = 1000.0\n",
                 "duration = 1000.0\n[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n")),
             Contains("carries a pore pressure p"));
  // A path-following solver would run the consolidation's time backwards.
  CHECK_THAT(build_error(testing::replace_once(ok, "solver = \"newton\"", "solver = \"arc_length\"")),
             Contains("needs a load-controlled solver") && Contains("arc_length"));
  // No drained boundary anywhere: a warning, the scene still runs.
  const auto sealed = testing::scene(
      testing::replace_once(ok, "[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n", ""),
      "groundwater.toml");
  REQUIRE(sealed->warnings().size() == 1);
  CHECK_THAT(sealed->warnings()[0], Contains("no drained boundary"));
}

TEST_CASE(
    "groundwater: a displacement domain with drainage = undrained carries the excess pressure at its points",
    "[groundwater]") {
  std::string text = column("axisymmetric", 4, "");
  text = testing::replace_once(text, "element = \"quad8p4\"", "element = \"quad\"\ndrainage = \"undrained\"");
  std::ostringstream kf;
  kf.precision(17);
  kf << "fluid_stiffness = " << fluid() << "\n";
  for (const char* key :
       {"permeability = 1e-08\n", "porosity = 0.40000000000000002\n", "fluid_bulk_modulus = 2200000\n"})
    text = testing::replace_once(text, key, "");
  text = testing::replace_once(text, "unit_weight_water = 10\n", kf.str());
  auto a = build(text);
  const RunSummary s = a->run();
  REQUIRE(s.outcome.ok());
  const Model& m = a->model();
  CHECK(m.dofs.field("p") < 0); // no pressure unknowns: the points carry it
  CHECK(top_settlement(m) == Approx(H * (q - p0()) / oedometric()).epsilon(1e-8));
  const Domain& dm = m.domains[0];
  REQUIRE(dm.law.material->history_names().front() == "p_excess [kPa]");
  for (std::size_t p = 0; p < dm.states.points(); ++p) {
    CHECK(dm.states.committed(p).history()[0] == Approx(p0()).epsilon(1e-8));
    CHECK(dm.states.committed(p).stress()[1] == Approx(-q).epsilon(1e-8)); // the total stress
  }
  // Bad input: drainage on a porous element, fluid_stiffness missing or out of place, a misspelling.
  const std::string porous = column("axisymmetric", 4, "");
  CHECK_THAT(build_error(testing::replace_once(
                 porous, "element = \"quad8p4\"",
                 "element = \"quad8p4\"\ndrainage = \"undrained\"\nfluid_stiffness = 1e6")),
             Catch::Contains("carries the pore pressure p itself"));
  CHECK_THAT(build_error(testing::replace_once(text, kf.str(), "")),
             Catch::Contains("needs fluid_stiffness"));
  CHECK_THAT(
      build_error(testing::replace_once(text, "drainage = \"undrained\"", "drainage = \"non_porous\"")),
      Catch::Contains("fluid_stiffness acts only with drainage = \"undrained\""));
  CHECK_THAT(build_error(testing::replace_once(text, "drainage = \"undrained\"", "drainage = \"undraind\"")),
             Catch::Contains("is not allowed") && Catch::Contains("did you mean"));
}

TEST_CASE("groundwater: a consolidation stage ends once the excess pressure is below until_excess_pressure",
          "[groundwater]") {
  // Terzaghi's column: the drained top from the consolidation's start, 40 equal steps over T = 1;
  // the stage is to end at the first step whose largest |p| is below 30 kPa, and a third stage
  // (static) follows at the time where it ended.
  const double duration = 1.0 * H * H / cv();
  std::ostringstream more;
  more.precision(17);
  more << "[[stages]]\nname = \"consolidate\"\ntype = \"consolidation\"\nduration = " << duration
       << "\nsteps = 40\nuntil_excess_pressure = 30.0\n[[stages.actions]]\ntype = \"drain\"\nnodes = "
          "\"soil.top\"\n"
       << "[[stages]]\nname = \"more\"\n[[stages.actions]]\ntype = \"pressure\"\nname = \"extra\"\nedges = "
          "\"soil.top\"\np = 10.0\n";
  struct Sample {
    int stage;
    double lambda, largest, stage_start;
  };
  std::vector<Sample> samples;
  Analysis* analysis = nullptr;
  RunOptions o;
  o.on_step = [&](int, int, double lambda, const StepReport&) {
    const Model& m = analysis->model();
    double largest = 0.0;
    for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
      if (const int d = m.dofs.dof(static_cast<int>(n), m.dofs.field("p")); d >= 0)
        largest = std::max(largest, std::abs(m.u[d]));
    samples.push_back({m.clock.stage, lambda, largest, m.clock.total_time - m.clock.step_time});
  };
  auto a = build(column("plane_strain", 10, more.str()), std::move(o));
  analysis = a.get();
  const RunSummary s = a->run();
  REQUIRE(s.outcome.ok());
  CHECK(s.stages_done == 3);
  std::vector<Sample> consolidation;
  for (const auto& x : samples)
    if (x.stage == 2) consolidation.push_back(x);
  REQUIRE(consolidation.size() >= 2);
  const Sample last = consolidation.back(), before = consolidation[consolidation.size() - 2];
  CHECK(last.largest < 30.0);    // it ended when the pressure was below the bound
  CHECK(before.largest >= 30.0); // and not a step earlier
  // The base is the slowest point: by the series' first term its pressure falls below 0.3 p0 at
  // (4/pi) exp(-pi^2 T / 4) = 0.3, T = 0.59.
  CHECK(last.lambda > 0.5);
  CHECK(last.lambda < 0.7);
  CHECK(last.stage_start == Approx(1.0)); // the static load stage counts one unit
  const Sample next = samples.back();
  REQUIRE(next.stage == 3);
  CHECK(next.stage_start == Approx(1.0 + last.lambda * duration).epsilon(1e-12));
}

TEST_CASE("groundwater: seal closes a drained boundary again", "[groundwater]") {
  // The column drains through its top for a while (T = 0.1), then the top is sealed and the water
  // only evens out inside: the top's pressure, held at 0 while drained, rises towards the mean, and
  // no water leaves (the mean excess pressure stays, to the storage's small share).
  const double duration = 0.1 * H * H / cv();
  std::ostringstream more;
  more.precision(17);
  more << "[[stages]]\nname = \"drain\"\ntype = \"consolidation\"\nduration = " << duration
       << "\nsteps = 20\n[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n"
       << "[[stages]]\nname = \"sealed\"\ntype = \"consolidation\"\nduration = " << 10.0 * duration
       << "\nsteps = 20\n[[stages.actions]]\ntype = \"seal\"\nnodes = \"soil.top\"\n";
  std::map<int, std::pair<double, double>> end_of; // stage -> (top p, settlement)
  Analysis* analysis = nullptr;
  RunOptions o;
  o.on_step = [&](int, int, double, const StepReport&) {
    const Model& m = analysis->model();
    const int top = testing::node_at(m, 0.0, H);
    end_of[m.clock.stage] = {m.u[m.dofs.dof(top, m.dofs.field("p"))], top_settlement(m)};
  };
  auto a = build(column("plane_strain", 10, more.str()), std::move(o));
  analysis = a.get();
  const RunSummary s = a->run();
  REQUIRE(s.outcome.ok());
  CHECK(end_of[2].first == 0.0);       // drained: held at 0
  CHECK(end_of[3].first > 0.2 * p0()); // sealed: the pressure came back to the top
  // Sealed, the skeleton's volume changes only by the fluid's compression: the settlement moves by
  // far less than it did while draining.
  CHECK(std::abs(end_of[3].second - end_of[2].second) <
        0.01 * (end_of[2].second - H * (q - p0()) / oedometric()));
}

TEST_CASE("groundwater: the clay pile scene loads undrained, consolidates and loads drained to 10 % of d",
          "[groundwater]") {
  // inputs/clay_pile/clay_pile.toml (docs/validation/clay_pile.md). What is asserted is physics the
  // scene must show, not its own earlier numbers: the undrained load raises the excess pressure
  // beside the shaft; consolidation lets it fall to a small part of that and adds settlement
  // without load; the drained stage, 100 times longer than the consolidation, keeps it small while
  // the head load grows to the 10 % of d stop.
  struct Sample {
    int stage;
    double head, p_shaft, largest;
  };
  std::vector<Sample> samples;
  Analysis* analysis = nullptr;
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  o.on_step = [&](int, int, double, const StepReport&) {
    const Model& m = analysis->model();
    const int pf = m.dofs.field("p");
    double largest = 0.0, head = 0.0;
    int heads = 0;
    for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
      const auto& x = m.mesh.nodes[n];
      if (const int d = m.dofs.dof(static_cast<int>(n), pf); d >= 0 && x.x() > 0.3 - 1e-9)
        largest = std::max(largest, std::abs(m.u[d])); // the clay's nodes (the bore's are left alone)
      if (std::abs(x.y()) < 1e-9 && x.x() < 0.3 + 1e-9)
        head -= m.u[m.dofs.dof(static_cast<int>(n), field_uy)], ++heads;
    }
    const int shaft = testing::node_at(m, 0.3, -5.0);
    samples.push_back({m.clock.stage, head / heads, m.u[m.dofs.dof(shaft, pf)], largest});
  };
  auto a = Analysis::from_file(testing::source_path("inputs/clay_pile/clay_pile.toml"), std::move(o));
  analysis = a.get();
  const RunSummary s = a->run();
  REQUIRE(s.outcome.ok());
  CHECK(s.stages_done == 5); // the sixth stage stops at 10 % of d
  CHECK(s.stop_reason == StopReason::settlement);
  CHECK(s.cutbacks == 0);
  auto last_of = [&](int stage) {
    Sample last{};
    for (const auto& x : samples)
      if (x.stage == stage) last = x;
    return last;
  };
  const Sample loaded = last_of(4), consolidated = last_of(5), failed = last_of(6);
  INFO("p beside the shaft: " << loaded.p_shaft << " kPa loaded, " << consolidated.p_shaft
                              << " consolidated");
  CHECK(loaded.p_shaft > 10.0);                        // undrained: the load went into the water
  CHECK(consolidated.p_shaft < 0.05 * loaded.p_shaft); // one year later it has drained away
  CHECK(consolidated.head > loaded.head + 1e-3);       // consolidation settles the pile (> 1 mm)
  double drained_largest = 0.0;
  for (const auto& x : samples)
    if (x.stage == 6) drained_largest = std::max(drained_largest, std::abs(x.p_shaft));
  CHECK(drained_largest < 0.05 * loaded.p_shaft); // drained: no pressure builds up
  CHECK(failed.head > 0.06);                      // the stop: 10 % of d = 60 mm
  REQUIRE(!s.load_settlement.empty());
  // The head load hands over from the working load (150 kN) to the drained stage's 750 kN.
  CHECK(s.load_settlement.back()[0] > 300.0);
  CHECK(s.load_settlement.back()[0] < 750.0);
}

TEST_CASE("groundwater: a water_level action lowers the table, the excess drains to the closed form",
          "[groundwater]") {
  // A 10 m column (linear elastic skeleton, quad8p4), water table at its top; the table is lowered
  // to y = 6 in a consolidation stage of T = 5 with the top drained. Drained at the end,
  // the effective stress is the geostatic one of the new level (gamma = 17 above it, buoyant
  // gamma_sat - gamma_w = 10 below), an increase of 7 (10 - y) above 6 m and 28 kPa below, and the
  // top settles by (int_6^10 7 (10 - y) dy + 28 x 6) / M = 224 / M.
  constexpr double gamma = 17.0, gamma_sat = 20.0, gw = 10.0, K0 = 0.5, level = 6.0;
  const double duration = 5.0 * H * H / cv();
  std::ostringstream s;
  s.precision(17);
  s << "[analysis]\nformulation = \"plane_strain\"\nsolver = \"newton\"\nautomatic = true\ngrowth = 1.3\n"
    << "fast_iterations = 3\nmax_increment = 0.05\n"
    << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n[[mesh.blocks]]\nname = \"soil\"\nx = [0.0, "
       "1.0]\n"
    << "y = [0.0, 10.0]\nnx = 1\nny = 10\n"
    << "[materials.soil]\nmodel = \"linear_elastic\"\nE = " << E << "\nnu = " << nu << "\n"
    << "[[domains]]\ncells = \"soil\"\nelement = \"quad8p4\"\nmaterial = \"soil\"\npermeability = " << k_perm
    << "\nporosity = " << n_por << "\nfluid_bulk_modulus = " << K_w << "\nunit_weight_water = " << gw << "\n"
    << "[[constraints]]\nnodes = \"left\"\nux = 0.0\n[[constraints]]\nnodes = \"right\"\nux = 0.0\n"
    << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
    << "[[stages]]\nname = \"geostatic\"\n[[stages.actions]]\ntype = \"geostatic\"\ngamma = " << gamma
    << "\ngamma_sat = " << gamma_sat << "\ngamma_w = " << gw << "\nK0 = " << K0 << "\nsurface = 10.0\n"
    << "water_level = 10.0\n"
    << "[[stages]]\nname = \"lower\"\ntype = \"consolidation\"\nduration = " << duration
    << "\nsteps = 10000\n"
    << "[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n"
    << "[[stages.actions]]\ntype = \"water_level\"\nlevel = " << level << "\n";
  std::vector<double> base_p;
  Analysis* analysis = nullptr;
  RunOptions o;
  o.on_step = [&](int, int, double, const StepReport&) {
    const Model& m = analysis->model();
    if (m.clock.stage == 2)
      base_p.push_back(m.u[m.dofs.dof(testing::node_at(m, 0.0, 0.0), m.dofs.field("p"))]);
  };
  auto a = build(s.str(), std::move(o));
  analysis = a.get();
  const RunSummary r = a->run();
  REQUIRE(r.outcome.ok());
  const Model& m = a->model();
  CHECK(m.water.level.at(0.0) == level);
  REQUIRE(!base_p.empty());
  // The instant (the first step, 1e-4 of the stage): the buoyancy lost between the levels, 7 kN/m3
  // over 4 m (gamma = 17 above the level instead of the buoyant 10), loads the column at once and
  // the sealed soil answers undrained: 28 kPa x (K_w/n) / (M + K_w/n) at the base.
  CHECK(base_p.front() == Approx(28.0 * fluid() / (oedometric() + fluid())).epsilon(0.01));
  // Drained: the series leaves 1.6e-4 kPa at T = 5; implicit Euler's steps of up to 0.25 in T
  // lag behind it (measured 1.7e-3 kPa): 0.01 kPa is 0.04 % of the initial excess.
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    if (const int d = m.dofs.dof(static_cast<int>(n), m.dofs.field("p")); d >= 0)
      CHECK(std::abs(m.u[d]) < 0.01);
  CHECK(top_settlement(m) == Approx(224.0 / oedometric()).epsilon(1e-3));
  const Domain& dm = m.domains[0];
  Eigen::MatrixXd x, xp;
  std::vector<int> nodes;
  for (std::size_t c = 0; c < dm.cells.size(); ++c) {
    m.cell_nodes(dm.cells[c], nodes, x);
    dm.element->point_coordinates(m.element_data(dm.cells[c], x), xp);
    for (Eigen::Index i = 0; i < xp.rows(); ++i) {
      const double y = xp(i, 1);
      const double sv = -(gamma * (10.0 - std::max(y, level)) + (gamma_sat - gw) * std::max(level - y, 0.0));
      CHECK(dm.states.committed(dm.first_point[c] + static_cast<std::size_t>(i)).stress()[1] ==
            Approx(sv).epsilon(1e-4));
    }
  }
}

TEST_CASE(
    "groundwater: water_level without a water table, or without its self-weight load, is one located line",
    "[groundwater]") {
  const std::string dry =
      column("plane_strain", 4,
             "[[stages]]\nname = \"lower\"\n[[stages.actions]]\ntype = \"water_level\"\nlevel "
             "= 6.0\nload = \"nothing\"\n");
  const std::string e = testing::build_error(dry, "groundwater.toml");
  CHECK_THAT(e, Catch::Contains("groundwater.toml:") &&
                    Catch::Contains("load = \"nothing\" is not an applied load"));
}

TEST_CASE(
    "groundwater: the global recorder's U, p_max and p_mean against Terzaghi's series, refused without p",
    "[groundwater]") {
  // Terzaghi's column (40 cells) to T = 0.2 in 200 equal steps; the recorder's last values are read
  // back through [[checks]] (whose own bounds are wide: the assertions below are the test).
  // U = 1 - p_mean / p0 is the average degree of consolidation, p_mean = p0 (1 - U), and p_max is
  // the base's pressure (the slowest point).
  const double T = 0.2, duration = T * H * H / cv();
  std::ostringstream more;
  more.precision(17);
  more
      << "[[stages]]\nname = \"consolidate\"\ntype = \"consolidation\"\nduration = " << duration
      << "\nsteps = 200\n[[stages.actions]]\ntype = \"drain\"\nnodes = \"soil.top\"\n"
      << "[[output.history]]\nname = \"c\"\nkind = \"global\"\nquantities = [\"U\", \"p_max\", \"p_mean\"]\n";
  for (const char* q : {"U", "p_max", "p_mean"})
    more << "[[checks]]\nrecorder = \"c\"\nquantity = \"" << q << "\"\nexpected = 1.0\nrtol = 1e3\n";
  auto a = build(column("plane_strain", 40, more.str()));
  const RunSummary s = a->run();
  REQUIRE(s.outcome.ok());
  REQUIRE(s.checks.size() == 3);
  CHECK(s.checks[0].value == Approx(terzaghi_U(T)).epsilon(0.01));
  CHECK(s.checks[1].value == Approx(terzaghi_p(H, T)).epsilon(0.01));
  CHECK(s.checks[2].value == Approx(p0() * (1.0 - terzaghi_U(T))).epsilon(0.01));
  CHECK(s.checks[1].unit == "kPa");

  // A model without porous elements has no excess pressure to record: one located line.
  const std::string dry = R"([analysis]
formulation = "plane_strain"
[mesh]
generator = "blocks"
[[mesh.blocks]]
name = "soil"
x = [0.0, 1.0]
y = [0.0, 1.0]
[materials.soil]
model = "linear_elastic"
E = 1000.0
nu = 0.3
[[domains]]
cells = "soil"
element = "quad"
material = "soil"
[[constraints]]
nodes = "bottom"
ux = 0.0
uy = 0.0
[[stages]]
name = "load"
[[stages.actions]]
type = "pressure"
edges = "soil.top"
p = 1.0
[[output.history]]
name = "c"
kind = "global"
quantities = ["time", "U"]
)";
  const std::string e = testing::build_error(dry, "dry.toml");
  CHECK_THAT(e,
             Catch::Contains("dry.toml:") && Catch::Contains("quantity \"U\" is the excess pore pressure"));
}

} // namespace test_groundwater
