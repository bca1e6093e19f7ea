// Tests of the u-p elements quad8p4 and tri6p3 (plugins/biot), one cell at a time:
//  * the tangent against central differences of the force (both cell types, plane strain and
//    axisymmetry, a static step and a consolidation step, with a nonlinear skeleton), relative
//    1e-6 of the largest entry;
//  * the coupling block is -integral B^T m N_p dV: for a rigid-body translation it vanishes, for a
//    uniform expansion e the continuity row sums to -e times the cell's volume;
//  * the flow: a linear pressure field p = g x in a rectangle with dt gives the nodal flows
//    dt (k / gamma_w) g times the side's area on the two sides and nothing at the corners'
//    sum (conservation), and no flow in a static step (undrained);
//  * the local order: ux, uy, p at the corners, ux, uy at the midside nodes.
#include "biot/biot_element.hpp"
#include "linear_elastic/elastic_math.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <numbers>

namespace test_biot_element {

using namespace stratum;
using stratum::biot::BiotElement;
using stratum::biot::Options;

namespace {

/// A small nonlinear material with an exact tangent (stiffening with the volumetric strain).
class Nonlinear final : public Material {
public:
  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    const Vec6 e = in.strain_n + in.dstrain;
    out.stress = in.stress_n + sigma(e) - sigma(in.strain_n);
    out.tangent = D_;
    out.tangent.topLeftCorner<3, 3>().array() += 2.0 * 3e4 * e.head<3>().sum();
    return Outcome::success();
  }

private:
  [[nodiscard]] Vec6 sigma(const Vec6& e) const {
    Vec6 s = D_ * e;
    const double tr = e.head<3>().sum();
    s.head<3>().array() += 3e4 * tr * tr;
    return s;
  }
  Mat6 D_ = linear_elastic::isotropic_stiffness(2e4, 0.3);
};

class Elastic final : public Material {
public:
  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput& out) const override {
    out.stress = in.stress_n + D_ * in.dstrain;
    out.tangent = D_;
    return Outcome::success();
  }
  [[nodiscard]] bool is_linear() const override { return true; }

private:
  Mat6 D_ = linear_elastic::isotropic_stiffness(1e4, 0.25);
};

/// A distorted 8-node quadrilateral (curved edge 1-2) and a 6-node triangle, away from the axis.
Eigen::MatrixXd quad_nodes() {
  Eigen::MatrixXd X(8, 2);
  X << 1.0, 0.0, 2.2, 0.1, 2.0, 1.3, 0.9, 1.0, 1.6, 0.02, 2.15, 0.7, 1.45, 1.2, 0.95, 0.5;
  return X;
}
Eigen::MatrixXd tri_nodes() {
  Eigen::MatrixXd X(6, 2);
  X << 1.0, 0.0, 2.0, 0.2, 1.2, 1.1, 1.5, 0.1, 1.62, 0.68, 1.1, 0.55;
  return X;
}

Options options(CellType cell, Formulation f) {
  Options o;
  o.cell = cell;
  o.formulation = f;
  o.integration = cell == CellType::quadrilateral ? 3 : 6;
  o.water.kx = 2e-3;
  o.water.ky = 5e-4;
  o.water.porosity = 0.35;
  o.water.fluid_bulk_modulus = 1e5;
  o.water.unit_weight_water = 9.81;
  return o;
}

ElementData cell_of(const Eigen::MatrixXd& X, CellType type, bool transient, double dt) {
  ElementData c;
  c.id = 7;
  c.type = type;
  c.shape = type == CellType::quadrilateral ? 0xFFu : 0x77u;
  c.x = &X;
  c.clock.transient = transient;
  c.clock.dtime = dt;
  return c;
}

} // namespace

TEST_CASE("biot: the tangent of the u-p cells matches central differences", "[biot]") {
  const Nonlinear material;
  for (CellType type : {CellType::quadrilateral, CellType::triangle})
    for (Formulation f : {Formulation::plane_strain, Formulation::axisymmetric})
      for (bool transient : {false, true}) {
        const BiotElement el(options(type, f));
        const Eigen::MatrixXd X = type == CellType::quadrilateral ? quad_nodes() : tri_nodes();
        const ElementData cell = cell_of(X, type, transient, 3.0);
        const int n = el.local_size();
        Eigen::VectorXd u_n = Eigen::VectorXd::Zero(n), u(n);
        for (int i = 0; i < n; ++i) u(i) = 1e-3 * std::sin(1.0 + 2.3 * i);
        for (int i = 0; i < el.pressure_nodes(); ++i)
          u(el.p_index(i)) = 40.0 * std::cos(0.7 * i), u_n(el.p_index(i)) = 5.0;
        StateStore states(static_cast<std::size_t>(el.num_points(cell.shape)), 0);
        ElementResult r;
        REQUIRE(el.compute(cell, u, u_n, Constitutive{&material, nullptr}, states, 0, true, r).ok());
        Eigen::MatrixXd K_fd(n, n);
        for (int j = 0; j < n; ++j) {
          const double h = j % 3 == 2 && j < 3 * el.pressure_nodes() ? 1e-3 : 1e-8;
          Eigen::VectorXd up = u, um = u;
          up(j) += h;
          um(j) -= h;
          ElementResult rp, rm;
          REQUIRE(el.compute(cell, up, u_n, Constitutive{&material, nullptr}, states, 0, false, rp).ok());
          REQUIRE(el.compute(cell, um, u_n, Constitutive{&material, nullptr}, states, 0, false, rm).ok());
          K_fd.col(j) = (rp.force - rm.force) / (2.0 * h);
        }
        INFO("cell " << (type == CellType::quadrilateral ? "quad8p4" : "tri6p3") << ", "
                     << (f == Formulation::axisymmetric ? "axisymmetric" : "plane strain")
                     << (transient ? ", consolidation step" : ", static step"));
        // Each block against its own scale: the coupling and flow entries are many orders below
        // the stiffness ones.
        const int np = el.pressure_nodes();
        Eigen::VectorXi is_p = Eigen::VectorXi::Zero(n);
        for (int i = 0; i < np; ++i) is_p(el.p_index(i)) = 1;
        for (int rp = 0; rp < 2; ++rp)
          for (int cp = 0; cp < 2; ++cp) {
            double scale = 0.0, err = 0.0;
            for (int i = 0; i < n; ++i)
              for (int j = 0; j < n; ++j)
                if (is_p(i) == rp && is_p(j) == cp) {
                  scale = std::max(scale, std::abs(r.stiffness(i, j)));
                  err = std::max(err, std::abs(r.stiffness(i, j) - K_fd(i, j)));
                }
            INFO("block " << rp << cp << ": largest entry " << scale << ", largest difference " << err);
            CHECK(err <= 1e-6 * scale);
          }
        // Symmetric when the skeleton's tangent is: the coupling blocks are each other's transpose.
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            if (is_p(i) != is_p(j)) CHECK(r.stiffness(i, j) == Approx(r.stiffness(j, i)).margin(1e-14));
      }
}

TEST_CASE("biot: the local order and the coupling of a uniform expansion", "[biot]") {
  const Elastic material;
  const BiotElement el(options(CellType::quadrilateral, Formulation::plane_strain));
  // ux, uy, p at corners 0..3 (indices 0..11), then ux, uy at midside 4..7 (12..19).
  CHECK(el.local_size() == 20);
  CHECK(el.u_index(0, 0) == 0);
  CHECK(el.p_index(3) == 11);
  CHECK(el.u_index(4, 1) == 13);
  const NodeFields nf = el.node_fields(CellType::quadrilateral, 0xFFu);
  REQUIRE(nf.fields.size() == 3);
  CHECK(nf.fields[2].name == "p");
  CHECK(nf.at(0) == 0b111u);
  CHECK(nf.at(7) == 0b011u);

  const Eigen::MatrixXd X = quad_nodes();
  const ElementData cell = cell_of(X, CellType::quadrilateral, false, 0.0);
  double area = 0.0; // of the curved cell: the Gauss rule of the 8-node map is exact for it
  {
    StateStore states(9, 0);
    ElementResult r;
    Eigen::VectorXd u = Eigen::VectorXd::Zero(20);
    const double e = 1e-4; // u = e x: uniform expansion, volumetric strain 2 e (plane strain)
    for (int i = 0; i < 8; ++i) {
      u(el.u_index(i, 0)) = e * X(i, 0);
      u(el.u_index(i, 1)) = e * X(i, 1);
    }
    REQUIRE(
        el.compute(cell, u, Eigen::VectorXd::Zero(20), Constitutive{&material, nullptr}, states, 0, true, r)
            .ok());
    // Sum of the continuity rows = -(volumetric strain) x (volume); the volume from the coupling
    // block of a unit pressure: sum_j K_up(., j) . u / (2 e) = -volume as well.
    double continuity = 0.0;
    for (int i = 0; i < 4; ++i) continuity += r.force(el.p_index(i));
    Eigen::VectorXd ones_p = Eigen::VectorXd::Zero(20);
    for (int i = 0; i < 4; ++i) ones_p(el.p_index(i)) = 1.0;
    area = -(u.transpose() * r.stiffness * ones_p)(0) / (2.0 * e);
    CHECK(area > 1.0);
    CHECK(continuity == Approx(-2.0 * e * area).epsilon(1e-12));
    // A rigid translation: no volume change, no continuity residual.
    Eigen::VectorXd t = Eigen::VectorXd::Zero(20);
    for (int i = 0; i < 8; ++i) t(el.u_index(i, 0)) = 0.3, t(el.u_index(i, 1)) = -0.1;
    REQUIRE(
        el.compute(cell, t, Eigen::VectorXd::Zero(20), Constitutive{&material, nullptr}, states, 0, false, r)
            .ok());
    for (int i = 0; i < 4; ++i) CHECK(r.force(el.p_index(i)) == Approx(0.0).margin(1e-15));
  }
}

TEST_CASE("biot: Darcy flow of a linear pressure through a rectangle", "[biot]") {
  const Elastic material;
  Options o = options(CellType::quadrilateral, Formulation::plane_strain);
  o.water.fluid_bulk_modulus = 0.0; // incompressible: the continuity rows hold the flow alone
  const BiotElement el(o);
  Eigen::MatrixXd X(8, 2);
  const double a = 2.0, b = 0.5;
  X << 0, 0, a, 0, a, b, 0, b, a / 2, 0, a, b / 2, a / 2, b, 0, b / 2;
  const double dt = 10.0, g = 3.0; // p = g x: the water flows towards -x, v = -(k / gamma_w) g
  Eigen::VectorXd u = Eigen::VectorXd::Zero(20);
  for (int i = 0; i < 4; ++i) u(el.p_index(i)) = g * X(i, 0);
  StateStore states(9, 0);
  ElementResult r;
  for (bool transient : {true, false}) {
    const ElementData cell = cell_of(X, CellType::quadrilateral, transient, dt);
    REQUIRE(el.compute(cell, u, u, Constitutive{&material, nullptr}, states, 0, true, r).ok());
    // The nodal volumes -dt grad N . (k/gamma_w) grad p: on the side x = 0 the water leaves
    // (+dt k g / gamma_w per unit area, split between its two corners), on x = a it enters.
    const double flow = transient ? dt * o.water.kx / o.water.unit_weight_water * g * b : 0.0;
    CHECK(r.force(el.p_index(0)) == Approx(flow / 2).margin(1e-18));
    CHECK(r.force(el.p_index(3)) == Approx(flow / 2).margin(1e-18));
    CHECK(r.force(el.p_index(1)) == Approx(-flow / 2).margin(1e-18));
    CHECK(r.force(el.p_index(2)) == Approx(-flow / 2).margin(1e-18));
  }
}

TEST_CASE("biot: the pressure at the integration points interpolates the corners exactly", "[biot]") {
  // p = 3 + 2 x - 5 y at the corners of straight-sided cells (midside nodes at the middles): the
  // pressure interpolation reproduces it at every point (Element::point_field), field 2 only.
  Eigen::MatrixXd Q(8, 2), T(6, 2);
  Q << 1.0, 0.0, 2.5, 0.2, 2.2, 1.4, 0.8, 1.0, 1.75, 0.1, 2.35, 0.8, 1.5, 1.2, 0.9, 0.5;
  T << 1.0, 0.0, 2.0, 0.4, 1.2, 1.1, 1.5, 0.2, 1.6, 0.75, 1.1, 0.55;
  for (const CellType type : {CellType::quadrilateral, CellType::triangle}) {
    const BiotElement el(options(type, Formulation::axisymmetric));
    const Eigen::MatrixXd& X = type == CellType::quadrilateral ? Q : T;
    const ElementData cell = cell_of(X, type, false, 0.0);
    Eigen::VectorXd u = Eigen::VectorXd::Constant(el.local_size(), 0.123); // displacements: anything
    for (int i = 0; i < el.pressure_nodes(); ++i) u(el.p_index(i)) = 3.0 + 2.0 * X(i, 0) - 5.0 * X(i, 1);
    Eigen::VectorXd v;
    Eigen::MatrixXd xp;
    REQUIRE(el.point_field(cell, u, 2, v));
    el.point_coordinates(cell, xp);
    REQUIRE(v.size() == xp.rows());
    for (Eigen::Index q = 0; q < v.size(); ++q)
      CHECK(v(q) == Approx(3.0 + 2.0 * xp(q, 0) - 5.0 * xp(q, 1)).epsilon(1e-13));
    CHECK_FALSE(el.point_field(cell, u, 0, v)); // a displacement is not interpolated at the points
  }
}

TEST_CASE("biot: a cell of the wrong shape is refused with the pair it needs", "[biot]") {
  const BiotElement quad(options(CellType::quadrilateral, Formulation::plane_strain));
  CHECK_THROWS_WITH(quad.check_shape(0x0Fu), Catch::Contains("8-node quadrilateral"));
  const BiotElement tri(options(CellType::triangle, Formulation::plane_strain));
  CHECK_THROWS_WITH(tri.check_shape(0x07u), Catch::Contains("6-node triangle"));
  CHECK_FALSE(quad.accepts(CellType::triangle));
  CHECK(tri.accepts(CellType::triangle));
}

} // namespace test_biot_element
