// Tests of the triangle elements (plugins/tri): the triangle Gauss rules, the shape functions,
// the stiffness null space and tangent of one cell, the cell-topology check, and through the
// whole pipeline on Gmsh meshes the patch test (3- and 6-node, mixed with quadrangles; both
// kinematics) and the Lamé thick cylinder against its closed form (catalogue E1).
#include "linear_elastic/elastic_math.hpp"
#include "scene_helpers.hpp"
#include "tri/tri_element.hpp"

#include "stratum/mesh_io.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <vtkCellType.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>
#include <vector>

namespace test_tri_element {

using namespace stratum;
using stratum::testing::node_at;
using stratum::testing::rel;
using stratum::testing::scene;

namespace {

/// sigma(eps) = D eps + alpha tr(eps)^2 m: nonlinear, with an exact tangent.
class TriTestMaterial final : public Material {
public:
  TriTestMaterial(double E, double nu, double alpha)
      : D_(linear_elastic::isotropic_stiffness(E, nu)), alpha_(alpha) {}
  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    const Vec6 eps = in.strain_n + in.dstrain;
    out.stress = in.stress_n + sigma(eps) - sigma(in.strain_n);
    out.tangent = D_;
    out.tangent.topLeftCorner<3, 3>().array() += 2.0 * alpha_ * eps.head<3>().sum();
    return Outcome::success();
  }
  [[nodiscard]] bool is_linear() const override { return alpha_ == 0.0; }

private:
  [[nodiscard]] Vec6 sigma(const Vec6& e) const {
    Vec6 s = D_ * e;
    s.head<3>().array() += alpha_ * e.head<3>().sum() * e.head<3>().sum();
    return s;
  }
  Mat6 D_;
  double alpha_;
};

/// A curved 6-node triangle away from the axis (midside nodes moved off the chords) or its
/// 3-node corners.
Eigen::MatrixXd curved_cell(int nodes) {
  Eigen::MatrixXd X(6, 2);
  X << 0.5, 0.2, 1.6, 0.35, 0.9, 1.3, // corners 0, 1, 2 counter-clockwise
      1.05, 0.22,                     // midside 0-1, moved off the chord
      1.28, 0.88,                     // midside 1-2
      0.66, 0.72;                     // midside 2-0
  return nodes == 6 ? X : Eigen::MatrixXd(X.topRows(3));
}

ElementResult evaluate(const tri::TriElement& el, const Eigen::MatrixXd& X, const Eigen::VectorXd& u,
                       const Material& mat, StateStore* keep = nullptr) {
  StateStore local(static_cast<std::size_t>(el.num_points(el.required_shape())), mat.history_size());
  StateStore& states = keep ? *keep : local;
  ElementResult r;
  const Outcome o = el.compute(ElementData{7, el.required_shape(), &X}, u, Eigen::VectorXd::Zero(u.size()),
                               Constitutive{&mat, nullptr}, states, 0, true, r);
  REQUIRE(o.ok());
  return r;
}

double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST_CASE("tri: the triangle rules integrate monomials exactly up to their degree", "[tri]") {
  // Integral of xi^i eta^j over the reference triangle = i! j! / (i + j + 2)!.
  for (const auto& [points, degree] : {std::pair{1, 1}, std::pair{3, 2}, std::pair{6, 4}}) {
    const auto rule = tri::triangle_rule(points);
    REQUIRE(static_cast<int>(rule.size()) == points);
    for (int i = 0; i <= degree; ++i)
      for (int j = 0; i + j <= degree; ++j) {
        double q = 0;
        for (const auto& p : rule) q += p.weight * std::pow(p.xi, i) * std::pow(p.eta, j);
        const double exact = factorial(i) * factorial(j) / factorial(i + j + 2);
        INFO(points << "-point rule, xi^" << i << " eta^" << j);
        CHECK(std::abs(q - exact) <= 1e-14);
      }
  }
  // ... and not beyond (guards against a rule of the wrong degree passing by accident).
  double q3 = 0;
  for (const auto& p : tri::triangle_rule(3)) q3 += p.weight * std::pow(p.xi, 3);
  CHECK(std::abs(q3 - 6.0 / 120.0) > 5e-4); // 66/1296 against 1/20
  CHECK_THROWS_AS(tri::triangle_rule(4), Error);
}

TEST_CASE("tri: shape functions interpolate, sum to one and have the right derivatives", "[tri]") {
  const std::vector<std::array<double, 2>> at{{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  for (int n : {3, 6}) {
    Eigen::VectorXd N;
    Eigen::MatrixXd dN;
    for (int k = 0; k < n; ++k) { // Kronecker delta at the nodes (slot order)
      tri::shape_functions(n, at[static_cast<std::size_t>(k)][0], at[static_cast<std::size_t>(k)][1], N, dN);
      for (int i = 0; i < n; ++i) CHECK(N(i) == Approx(i == k ? 1.0 : 0.0).margin(1e-15));
    }
    const double xi = 0.23, eta = 0.41, h = 1e-6;
    tri::shape_functions(n, xi, eta, N, dN);
    CHECK(N.sum() == Approx(1.0).epsilon(1e-15));
    CHECK(dN.colwise().sum().norm() <= 1e-14);
    Eigen::VectorXd Np, Nm;
    Eigen::MatrixXd d;
    tri::shape_functions(n, xi + h, eta, Np, d);
    tri::shape_functions(n, xi - h, eta, Nm, d);
    CHECK((dN.col(0) - (Np - Nm) / (2 * h)).norm() <= 1e-8);
    tri::shape_functions(n, xi, eta + h, Np, d);
    tri::shape_functions(n, xi, eta - h, Nm, d);
    CHECK((dN.col(1) - (Np - Nm) / (2 * h)).norm() <= 1e-8);
  }
}

TEST_CASE("tri: a linear displacement gives the exact constant strain at every point", "[tri]") {
  // u_x = a0 + a1 x + a2 y, u_y = b0 + b1 x + b2 y on a curved 6-node cell (isoparametric
  // completeness) and on a 3-node cell.
  const double a0 = 1e-3, a1 = 2e-3, a2 = -1e-3, b0 = -2e-3, b1 = 5e-4, b2 = 3e-3;
  const TriTestMaterial mat(1000, 0.3, 0.0);
  for (int n : {3, 6})
    for (const auto form : {Formulation::plane_strain, Formulation::axisymmetric})
      for (int rule : {1, 3, 6}) {
        if (n == 6 && rule == 1) continue;
        const tri::TriElement el({form, n, rule});
        const Eigen::MatrixXd X = curved_cell(n);
        Eigen::VectorXd u(2 * n);
        for (int k = 0; k < n; ++k) {
          u(2 * k) = a0 + a1 * X(k, 0) + a2 * X(k, 1);
          u(2 * k + 1) = b0 + b1 * X(k, 0) + b2 * X(k, 1);
        }
        StateStore states(static_cast<std::size_t>(el.num_points(el.required_shape())), 0);
        evaluate(el, X, u, mat, &states);
        Eigen::MatrixXd xp;
        el.point_coordinates(ElementData{7, el.required_shape(), &X}, xp);
        for (std::size_t p = 0; p < states.points(); ++p) {
          const double x = xp(static_cast<Eigen::Index>(p), 0), y = xp(static_cast<Eigen::Index>(p), 1);
          Vec6 e = Vec6::Zero();
          e << a1, b2, form == Formulation::axisymmetric ? (a0 + a1 * x + a2 * y) / x : 0.0, a2 + b1, 0, 0;
          INFO(n << " nodes, " << rule << " points, point " << p);
          CHECK((states.trial(p).strain() - e).norm() <= 1e-13);
        }
      }
}

TEST_CASE("tri: stiffness null space, symmetry and the finite-difference tangent", "[tri]") {
  const TriTestMaterial lin(1000, 0.3, 0.0), nonlin(1000, 0.3, 4e4);
  for (int n : {3, 6})
    for (const auto form : {Formulation::plane_strain, Formulation::axisymmetric})
      for (int rule : {1, 3, 6}) {
        if (n == 6 && rule == 1) continue;
        INFO(n << " nodes, " << rule << " points, "
               << (form == Formulation::axisymmetric ? "axisym" : "plane"));
        const tri::TriElement el({form, n, rule});
        const Eigen::MatrixXd X = curved_cell(n);
        const Eigen::MatrixXd K = evaluate(el, X, Eigen::VectorXd::Zero(2 * n), lin).stiffness;
        CHECK((K - K.transpose()).norm() <= 1e-12 * K.norm());
        // Zero modes: rigid translations and rotation in plane strain (3); in axisymmetry only
        // the axial translation (1). A 3-node cell with one point has no spurious mode either.
        const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
        int zeros = 0;
        for (Eigen::Index i = 0; i < ev.size(); ++i) zeros += std::abs(ev(i)) < 1e-10 * ev.maxCoeff();
        // The 1-point 3-node cell in axisymmetry has one more: the rotation about its centroid
        // (zero u_r there, so no hoop strain at the only point); neighbours with other centroids
        // restrain it in a mesh, and the default rule (3 points) has none.
        const int expected = (form == Formulation::plane_strain ? 3 : 1) +
                             (form == Formulation::axisymmetric && n == 3 && rule == 1 ? 1 : 0);
        // tri6 with 3 points in axisymmetry: 12 dof, 3 points x 4 strains = 12 >= 11: still no spurious mode.
        CHECK(zeros == expected);

        // Tangent against central differences of the internal force (nonlinear material).
        Eigen::VectorXd u(2 * n);
        for (int k = 0; k < 2 * n; ++k) u(k) = 1e-3 * std::sin(1.7 * k + 0.3);
        const ElementResult r = evaluate(el, X, u, nonlin);
        Eigen::MatrixXd Kfd(2 * n, 2 * n);
        const double h = 1e-7;
        for (int j = 0; j < 2 * n; ++j) {
          Eigen::VectorXd up = u, um = u;
          up(j) += h, um(j) -= h;
          Kfd.col(j) = (evaluate(el, X, up, nonlin).force - evaluate(el, X, um, nonlin).force) / (2 * h);
        }
        CHECK((r.stiffness - Kfd).norm() <= 1e-6 * r.stiffness.norm());
      }
}

TEST_CASE("tri: body force totals the weight of the cell", "[tri]") {
  // Plane strain: sum of nodal forces = area x b; the area of the curved cell from the 6-point rule
  // equals the shoelace area of the 6-node boundary polygon plus the parabolic segments (checked
  // here with the straight-sided 3-node cell, whose area is exact).
  const tri::TriElement el({Formulation::plane_strain, 3, 1});
  const Eigen::MatrixXd X = curved_cell(3);
  const double area =
      0.5 * ((X(1, 0) - X(0, 0)) * (X(2, 1) - X(0, 1)) - (X(2, 0) - X(0, 0)) * (X(1, 1) - X(0, 1)));
  Eigen::VectorXd f;
  el.body_force(ElementData{0, tri::tri3_shape, &X}, Vec2(0, -20), f);
  double fy = 0;
  for (int k = 0; k < 3; ++k) {
    CHECK(f(2 * k + 1) == Approx(-20 * area / 3).epsilon(1e-14)); // one third per corner
    fy += f(2 * k + 1);
  }
  CHECK(fy == Approx(-20 * area).epsilon(1e-14));
}

TEST_CASE("tri: a cell of the wrong topology is refused with a hint", "[tri]") {
  const tri::TriElement t6({Formulation::axisymmetric, 6, 6}), t3({Formulation::axisymmetric, 3, 1});
  CHECK_NOTHROW(t6.check_shape(tri::tri6_shape));
  CHECK(error_of([&] { t6.check_shape(tri::tri3_shape); }) ==
        "tri6 element: the cell is a 3-node triangle, but tri6 needs a 6-node triangle (Gmsh: gmsh -2 -order "
        "2); "
        "use element = \"tri3\" for these cells");
  CHECK(error_of([&] { t3.check_shape(0xFFu); }) ==
        "tri3 element: the cell is an 8-node quadrilateral, but tri3 needs a 3-node triangle; use element = "
        "\"quad\" for quadrilaterals");
  // A clockwise cell has a negative Jacobian: located by check_geometry.
  Eigen::MatrixXd X = curved_cell(3);
  X.row(1).swap(X.row(2));
  CHECK(error_of([&] {
          t3.check_geometry(ElementData{5, tri::tri3_shape, &X});
        }).starts_with("element 5: non-positive Jacobian determinant or radius at integration point 0"));
}

// ---------------------------------------------------------------------------------------
// Through the pipeline, on Gmsh meshes (tests/data/patch.geo, patch_mixed.geo).

namespace {

/// plugins/tri/tests/scenes/<name>: this plugin's test scenes.
std::string tri_scene(const std::string& name) {
  return stratum::testing::source_path("plugins/tri/tests/scenes/" + name);
}

/// tri_scene("patch.toml") on the Gmsh mesh `msh` (tests/data/) in formulation `form`, with `domains`.
std::string patch_scene(const std::string& msh, const std::string& form, const std::string& domains) {
  using stratum::testing::replace_once;
  std::string t = stratum::testing::read_text(tri_scene("patch.toml"));
  t = replace_once(t, "patch_tri6.msh", msh);
  t = replace_once(t, "formulation = \"plane_strain\"", "formulation = \"" + form + "\"");
  return t + domains;
}

std::string domain(const std::string& cells, const std::string& element, const std::string& extra = "") {
  return "[[domains]]\ncells = \"" + cells + "\"\nelement = \"" + element + "\"\nmaterial = \"m\"\n" + extra;
}

} // namespace

TEST_CASE("tri: patch test on unstructured Gmsh triangles, exact to round-off", "[tri][patch]") {
  const double E = 200, nu = 0.3, p = 10;
  struct Case {
    std::string msh, domains;
  };
  const std::vector<Case> cases{
      {"patch_tri6.msh", domain("patch", "tri6")},
      {"patch_tri6.msh", domain("patch", "tri6", "integration = 3\n")},
      {"patch_tri3.msh", domain("patch", "tri3")},
      {"patch_tri3.msh", domain("patch", "tri3", "integration = 3\n")},
      {"patch_mixed.msh", domain("patch.quadrangles", "quad") + domain("patch.triangles", "tri6")},
  };
  for (const Case& c : cases)
    for (const std::string form : {"plane_strain", "axisymmetric"}) {
      auto an = scene(patch_scene(c.msh, form, c.domains), tri_scene("patch.toml"));
      REQUIRE(an->run().outcome.ok());
      const Model& m = an->model();
      Vec6 s_exact = Vec6::Zero();
      double ex, ey; // u_x = ex x, u_y = ey y
      if (form == "plane_strain") {
        s_exact[0] = -p, s_exact[2] = -nu * p;
        ex = -p * (1 - nu * nu) / E, ey = nu * (1 + nu) * p / E;
      } else {
        s_exact[0] = -p, s_exact[2] = -p; // sigma_r = sigma_theta = -p, sigma_z = 0
        ex = -p * (1 - nu) / E, ey = 2 * nu * p / E;
      }
      double u_err = 0, s_err = 0;
      for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
        u_err = std::max(u_err, std::abs(m.u[2 * static_cast<Eigen::Index>(n)] - ex * m.mesh.nodes[n].x()));
        u_err =
            std::max(u_err, std::abs(m.u[2 * static_cast<Eigen::Index>(n) + 1] - ey * m.mesh.nodes[n].y()));
      }
      std::size_t points = 0;
      for (const auto& dm : m.domains)
        for (std::size_t q = 0; q < dm.states.points(); ++q, ++points)
          s_err = std::max(s_err, (dm.states.committed(q).stress() - s_exact).norm());
      INFO(c.msh << " " << form << " " << c.domains << "max |u - u_exact| = " << u_err
                 << ", max |s - s_exact| = " << s_err);
      CHECK(m.mesh.cells.size() >= 20u); // an unstructured mesh, not one cell
      CHECK(points > 0u);
      CHECK(u_err <= 1e-10 * std::abs(ex));
      CHECK(s_err <= 1e-10 * p);
    }
}

TEST_CASE("tri: Gmsh reader maps 3- and 6-node triangles and splits a mixed group", "[tri][mesh]") {
  const Mesh t6 = read_gmsh(std::string(STRATUM_TEST_DATA_DIR) + "/patch_tri6.msh");
  REQUIRE_NOTHROW(t6.check());
  for (const Cell& c : t6.cells) CHECK(c.shape() == tri::tri6_shape);
  // Every midside node is the midpoint of its edge (straight-sided cells): slot 4 + k on k -> k+1.
  for (const Cell& c : t6.cells)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d mid =
          0.5 * (t6.nodes[static_cast<std::size_t>(c.nodes[static_cast<std::size_t>(k)])] +
                 t6.nodes[static_cast<std::size_t>(c.nodes[static_cast<std::size_t>((k + 1) % 3)])]);
      CHECK((t6.nodes[static_cast<std::size_t>(c.nodes[static_cast<std::size_t>(4 + k)])] - mid).norm() <=
            1e-12);
    }
  // Edges of the "right" curve lie on x = 1, run upwards (counter-clockwise) and carry a midside node.
  for (const Edge& e : t6.edge_sets.at("right")) {
    CHECK(t6.nodes[static_cast<std::size_t>(e.a)].x() == Approx(1.0));
    CHECK(t6.nodes[static_cast<std::size_t>(e.b)].y() > t6.nodes[static_cast<std::size_t>(e.a)].y());
    CHECK(e.mid >= 0);
  }
  const Mesh t3 = read_gmsh(std::string(STRATUM_TEST_DATA_DIR) + "/patch_tri3.msh");
  for (const Cell& c : t3.cells) CHECK(c.shape() == tri::tri3_shape);

  const Mesh mixed = read_gmsh(std::string(STRATUM_TEST_DATA_DIR) + "/patch_mixed.msh");
  REQUIRE_NOTHROW(mixed.check());
  const auto& q = mixed.cell_sets.at("patch.quadrangles");
  const auto& t = mixed.cell_sets.at("patch.triangles");
  CHECK(q.size() == 6u); // the transfinite 2 x 3 half
  CHECK(q.size() + t.size() == mixed.cell_sets.at("patch").size());
  for (int c : q) CHECK(mixed.cells[static_cast<std::size_t>(c)].shape() == 0xFFu);
  for (int c : t) CHECK(mixed.cells[static_cast<std::size_t>(c)].shape() == tri::tri6_shape);
  CHECK(mixed.cell_sets.count("all.triangles") == 1u);
}

TEST_CASE("tri: an element that does not fit the cells is a located error", "[tri]") {
  const auto message = [](const std::string& toml) {
    try {
      (void)scene(toml, tri_scene("patch.toml"));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // quad on triangles; tri6 on 3-node triangles. Both point at the element key of the [[domains]]
  // appended to patch.toml (line 30 col 11).
  const std::string at = tri_scene("patch.toml") + ":30:11";
  const std::string quad = message(patch_scene("patch_tri6.msh", "plane_strain", domain("patch", "quad")));
  CHECK(quad.starts_with(at));
  CHECK(quad.find("6-node triangle") != std::string::npos);
  CHECK(quad.find("tri6") != std::string::npos);
  const std::string t6 = message(patch_scene("patch_tri3.msh", "plane_strain", domain("patch", "tri6")));
  CHECK(t6.starts_with(at));
  CHECK(t6.find("the cell is a 3-node triangle, but tri6 needs a 6-node triangle") != std::string::npos);
}

// ---------------------------------------------------------------------------------------
// E1 Lamé cylinder a = 1, b = 2, p = 1 kPa, E = 1000 kPa, nu = 0.3 on Gmsh 6-node triangles.

namespace {
struct LameExact {
  double a = 1, b = 2, p = 1, E = 1000, nu = 0.3;
  [[nodiscard]] double u(double r) const {
    return (1 + nu) * p * a * a / (E * (b * b - a * a)) * ((1 - 2 * nu) * r + b * b / r);
  }
  [[nodiscard]] double sigma_theta(double r) const {
    return p * a * a / (b * b - a * a) * (1 + b * b / (r * r));
  }
};
} // namespace

TEST_CASE("tri: Lamé cylinder, axisymmetric, the scene inputs/verification/lame_tri6.toml",
          "[tri][verification]") {
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  auto an = Analysis::from_file(std::string(STRATUM_SOURCE_DIR) + "/inputs/verification/lame_tri6.toml", o);
  const RunSummary summary = an->run();
  REQUIRE(summary.outcome.ok());
  // The scene's own [[checks]] (u(a), u(b) against the closed form) pass.
  CHECK(summary.checks.size() == 2);
  for (const auto& c : summary.checks) {
    INFO(c.label << " = " << c.value << ", expected " << c.expected << " +- " << c.tolerance);
    CHECK(c.pass);
  }
  const Model& m = an->model();
  const LameExact ex;
  // The mesh (h = 0.125, about 100 6-node triangles across the 1 x 0.5 m wall): quadratic
  // displacements converge as h^3, so the nodal error is well below the 2e-4 / 5e-4 asked.
  CHECK(m.mesh.cells.size() >= 50u);
  CHECK(rel(m.u[2 * node_at(m, 1.0, 0.0)], ex.u(1.0)) < 2e-4);
  CHECK(rel(m.u[2 * node_at(m, 2.0, 0.5)], ex.u(2.0)) < 2e-4);
  double worst = 0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
    const double r = m.mesh.nodes[n].x();
    // u_z = 0 is exact but only approximated inside an unstructured mesh: it counts as error.
    const Eigen::Vector2d e(m.u[2 * static_cast<Eigen::Index>(n)] - ex.u(r),
                            m.u[2 * static_cast<Eigen::Index>(n) + 1]);
    worst = std::max(worst, e.norm() / ex.u(1.0));
  }
  INFO("max |u - u_exact| / u(a) = " << worst);
  CHECK(worst < 5e-4);
  // Hoop stress at the integration points nearest the inner face (within 0.05 m): the field
  // varies as 1/r^2, so compare with the closed form at each point's own radius.
  const auto& dm = m.domains.at(0);
  Eigen::MatrixXd xp;
  std::vector<int> nodes;
  Eigen::MatrixXd x;
  double s_err = 0;
  int near = 0;
  for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
    m.cell_nodes(dm.cells[ci], nodes, x);
    dm.element->point_coordinates(
        ElementData{dm.cells[ci], m.mesh.cells[static_cast<std::size_t>(dm.cells[ci])].shape(), &x}, xp);
    for (Eigen::Index i = 0; i < xp.rows(); ++i) {
      const double r = xp(i, 0);
      if (r > 1.05) continue;
      ++near;
      const double s = dm.states.committed(dm.first_point[ci] + static_cast<std::size_t>(i)).stress()[2];
      s_err = std::max(s_err, std::abs(s - ex.sigma_theta(r)) / ex.sigma_theta(1.0));
    }
  }
  INFO("max relative error of sigma_theta within 0.05 m of r = a: " << s_err);
  CHECK(near > 10);
  CHECK(s_err < 5e-3);
}

TEST_CASE("tri: Lamé cylinder, plane strain quarter ring with curved 6-node triangles",
          "[tri][verification]") {
  auto an = stratum::testing::scene_file(tri_scene("lame_ring_plane_strain.toml"));
  REQUIRE(an->run().outcome.ok());
  const Model& m = an->model();
  const LameExact ex;
  double worst = 0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
    const Eigen::Vector2d xn = m.mesh.nodes[n];
    const Eigen::Vector2d un(m.u[2 * static_cast<Eigen::Index>(n)],
                             m.u[2 * static_cast<Eigen::Index>(n) + 1]);
    const double r = xn.norm();
    worst = std::max(worst, (un - ex.u(r) * xn / r).norm() / ex.u(1.0));
  }
  INFO("max |u - u_exact| / u(a) = " << worst);
  // h = 0.15 with the arcs' midside nodes on the circles: the geometry error of the boundary
  // is O(h^3) as well; 1e-3 of u(a) leaves room for it.
  CHECK(worst < 1e-3);
  CHECK(rel(m.u[2 * node_at(m, 1.0, 0.0)], ex.u(1.0)) < 1e-3);
}

TEST_CASE("tri: 6-node triangles are written as VTK quadratic triangles and read back", "[tri][output]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("stratum_tri_vtk_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.out_dir = dir.string();
  auto an = Analysis::from_file(std::string(STRATUM_SOURCE_DIR) + "/inputs/verification/lame_tri6.toml", o);
  REQUIRE(an->run().outcome.ok());
  const Model& m = an->model();
  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName((dir / "lame_tri6_1.vtu").string().c_str());
  r->Update();
  vtkUnstructuredGrid* g = r->GetOutput();
  REQUIRE(g != nullptr);
  REQUIRE(g->GetNumberOfCells() == static_cast<vtkIdType>(m.mesh.cells.size()));
  REQUIRE(g->GetNumberOfPoints() == static_cast<vtkIdType>(m.mesh.nodes.size()));
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
    CHECK(g->GetCellType(c) == VTK_QUADRATIC_TRIANGLE);
    // VTK's order is the cell's: corners 0 1 2, then the midside nodes of 0-1, 1-2, 2-0.
    const auto& n = m.mesh.cells[static_cast<std::size_t>(c)].nodes;
    vtkIdType count = 0;
    const vtkIdType* ids = nullptr;
    g->GetCellPoints(c, count, ids);
    REQUIRE(count == 6);
    const std::array<int, 6> slots{0, 1, 2, 4, 5, 6};
    for (int k = 0; k < 6; ++k)
      CHECK(ids[k] == n[static_cast<std::size_t>(slots[static_cast<std::size_t>(k)])]);
  }
  fs::remove_all(dir);
}

TEST_CASE("tri: a stage load on the top of triangle cells is the uniform patch state", "[tri][patch]") {
  // A stage action type = "load" with cells = "patch" (as on a pile head) finds the top edges of
  // the cells themselves (stage::load_edges): for triangles any edge on the top. Plane strain,
  // a force of 10 kN on the unit-wide top, i.e. p = 10 kPa on y = 1:
  // sigma_yy = -p, sigma_zz = -nu p, u_y = -p (1 - nu^2) / E y, u_x = nu (1 + nu) p / E x.
  const double E = 200, nu = 0.3, p = 10;
  std::string toml = patch_scene("patch_tri6.msh", "plane_strain", domain("patch", "tri6"));
  const std::string edge_load = "[[loads]]\ntype = \"pressure\"\nedges = \"right\"\np = 10.0\n";
  REQUIRE(toml.find(edge_load) != std::string::npos);
  toml.replace(toml.find(edge_load), edge_load.size(),
               "[[stages]]\nname = \"top\"\nsteps = 1\n[[stages.actions]]\ntype = \"load\"\ncells = "
               "\"patch\"\nforce = 10.0\n");
  auto an = scene(toml, tri_scene("patch.toml"));
  REQUIRE(an->run().outcome.ok());
  const Model& m = an->model();
  double u_err = 0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
    u_err = std::max(
        u_err, std::abs(m.u[2 * static_cast<Eigen::Index>(n)] - nu * (1 + nu) * p / E * m.mesh.nodes[n].x()));
    u_err = std::max(u_err, std::abs(m.u[2 * static_cast<Eigen::Index>(n) + 1] +
                                     p * (1 - nu * nu) / E * m.mesh.nodes[n].y()));
  }
  Vec6 s_exact = Vec6::Zero();
  s_exact[1] = -p, s_exact[2] = -nu * p;
  double s_err = 0;
  const auto& st = m.domains.at(0).states;
  for (std::size_t q = 0; q < st.points(); ++q)
    s_err = std::max(s_err, (st.committed(q).stress() - s_exact).norm());
  INFO("max |u - u_exact| = " << u_err << ", max |s - s_exact| = " << s_err);
  CHECK(u_err <= 1e-10 * p / E);
  CHECK(s_err <= 1e-10 * p);
}

TEST_CASE("tri: the Gmsh reader turns a clockwise 6-node triangle around, midside nodes with their edges",
          "[tri][mesh]") {
  namespace fs = std::filesystem;
  const fs::path path = fs::temp_directory_path() / ("stratum_tri_cw_" + std::to_string(::getpid()) + ".msh");
  {
    // Corners (0,0) (0,1) (1,0): clockwise. Midside tags 4 (edge 1-2), 5 (2-3), 6 (3-1) in Gmsh order.
    std::ofstream out(path);
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 6 1 6\n2 1 0 6\n1\n2\n3\n4\n5\n6\n"
           "0 0 0\n0 1 0\n1 0 0\n0 0.5 0\n0.5 0.5 0\n0.5 0 0\n$EndNodes\n"
           "$Elements\n1 1 1 1\n2 1 9 1\n1 1 2 3 4 5 6\n$EndElements\n";
  }
  const Mesh m = read_gmsh(path.string());
  fs::remove(path);
  REQUIRE(m.cells.size() == 1u);
  const auto& n = m.cells[0].nodes;
  // Corners 0 2 1 (counter-clockwise); edge 0-2 carries (0.5, 0), 2-1 carries (0.5, 0.5), 1-0 (0, 0.5).
  CHECK(n == std::array<int, 8>{0, 2, 1, -1, 5, 4, 3, -1});
  REQUIRE_NOTHROW(m.check());
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d mid =
        0.5 * (m.nodes[static_cast<std::size_t>(n[static_cast<std::size_t>(k)])] +
               m.nodes[static_cast<std::size_t>(n[static_cast<std::size_t>((k + 1) % 3)])]);
    CHECK((m.nodes[static_cast<std::size_t>(n[static_cast<std::size_t>(4 + k)])] - mid).norm() == 0.0);
  }
}

TEST_CASE("tri: Hill thick cylinder with Tresca (phi = 0) on curved 6-node triangles",
          "[tri][verification][tresca]") {
  // Catalogue P1 on the Gmsh quarter ring a = 1, b = 2 m (lame_ring_plane_strain.msh, h = 0.15 m),
  // Tresca with c = 100 kPa (Y = 2c), E = 1e5 kPa, nu = 0.3, plane strain. The closed form (exact
  // for Tresca while sigma_z stays the intermediate stress): elastic up to p0 = (Y/2)(1 - a^2/b^2),
  // then the plastic radius r_c from p = Y (ln(r_c/a) + (1 - r_c^2/b^2)/2) and
  // u_b = Y r_c^2 (1 - nu^2) / (E b). The 6-node triangles have no volumetric treatment, and the
  // isochoric plastic flow stiffens them as the limit nears; 2e-3 up to 0.9 P_lim allows for that
  // on this mesh (the quad8 scene with selective integration is checked to 1e-3).
  const double a = 1, b = 2, c = 100, E = 1e5, nu = 0.3, Y = 2 * c, p_lim = Y * std::log(b / a);
  auto u_b = [&](double P) {
    if (P <= 0.5 * Y * (1 - a * a / (b * b))) return 2 * P * b * (1 - nu * nu) / (E * (b * b / (a * a) - 1));
    double lo = a, hi = b;
    for (int i = 0; i < 200; ++i) {
      const double rc = 0.5 * (lo + hi);
      (Y * (std::log(rc / a) + 0.5 * (1 - rc * rc / (b * b))) < P ? lo : hi) = rc;
    }
    const double rc = 0.5 * (lo + hi);
    return Y * rc * rc * (1 - nu * nu) / (E * b);
  };
  for (double frac : {0.5, 0.75, 0.9}) {
    const double P = frac * p_lim;
    // tri_scene("hill_ring_tresca.toml") holds 0.5 P_lim; the pressure as std::to_string writes it.
    const std::string text =
        stratum::testing::replace_once(stratum::testing::read_text(tri_scene("hill_ring_tresca.toml")),
                                       "p = 69.314718\n", "p = " + std::to_string(P) + "\n");
    auto an = scene(text, tri_scene("hill_ring_tresca.toml"));
    const auto s = an->run();
    INFO(s.outcome.message);
    REQUIRE(s.outcome.ok());
    const double ub = an->model().u[2 * node_at(an->model(), b, 0.0)];
    INFO(frac << " P_lim: u_b = " << ub << ", closed form " << u_b(P) << ", relative error "
              << std::abs(ub - u_b(P)) / u_b(P));
    CHECK(std::abs(ub - u_b(P)) / u_b(P) < 2e-3);
  }
}

} // namespace test_tri_element
