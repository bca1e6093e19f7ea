// Tests of the interface elements of plugins/interface_elements (the plugin's own classes):
// - interface_line, linear contact law D (constant, also with shear-normal coupling): the stiffness
//   equals the closed form K = int B^T D B dA = [[M, -M], [-M, M]] (x) R^T D R with the shape-function
//   matrix M_ab = int N_a N_b dA: plane strain 2 + 2 nodes L/6 [[2, 1], [1, 2]] (Gauss) and
//   L/2 I (Newton-Cotes); 3 + 3 nodes L/30 [[4, -1, 2], [-1, 4, 2], [2, 2, 16]] (Gauss) and
//   L diag(1/6, 1/6, 2/3) (Simpson); axisymmetric 2 + 2 nodes 2 pi L/12 [[3 r_a + r_b, r_a + r_b],
//   [r_a + r_b, r_a + 3 r_b]] (Gauss) and its row sums (Newton-Cotes) (1e-12 relative);
// - the local axes: slip along the body-1 edge a -> b, opening along n = (t_y, -t_x) (exact);
// - force equilibrium: the forces on the two sides are equal and opposite pair by pair, and a
//   uniform jump gives the resultant int dA R^T D R jump on body 2 (1e-12);
// - the tangent of a nonlinear, non-symmetric law against central differences of the element
//   force, both rules, both interpolations, plane strain and axisymmetric, on an inclined edge
//   (1e-6 relative);
// - contact2: the tributary area (the integral of the node's linear shape function over its two
//   segments, l/2 each in plane strain, int N_i 2 pi r ds in axisymmetry), the blocks
//   [[K, -K], [-K, K]], K = A R^T D R (1e-12), and the same nodal force as interface_line with
//   Newton-Cotes under a uniform jump;
// - the element reports a missing contact law as a status.
#include "interface_elements/interface_elements.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <numbers>
#include <vector>

namespace test_interface_elements {

using namespace stratum;
using stratum::interfaces::Contact2;
using stratum::interfaces::InterfaceLine;
using stratum::interfaces::LineRule;

namespace {

constexpr double pi = std::numbers::pi;

/// A linear law t = D jump (D constant, not necessarily diagonal).
class LinearLaw final : public ContactLaw {
public:
  explicit LinearLaw(const Mat2& D) : D_(D) {}
  [[nodiscard]] bool symmetric_tangent() const override { return D_(0, 1) == D_(1, 0); }
  [[nodiscard]] Outcome update(const ContactInput& in, ContactOutput& out) const override {
    out.traction = D_ * (in.jump_n + in.djump);
    out.tangent = D_;
    return {};
  }

private:
  Mat2 D_;
};

/// A smooth nonlinear, non-symmetric law with its exact tangent:
/// t = D j + beta |j|^2 j + kappa (j_n^2, 0).
class CubicLaw final : public ContactLaw {
public:
  CubicLaw(const Mat2& D, double beta, double kappa) : D_(D), beta_(beta), kappa_(kappa) {}
  [[nodiscard]] bool symmetric_tangent() const override { return false; }
  [[nodiscard]] Outcome update(const ContactInput& in, ContactOutput& out) const override {
    const Vec2 j = in.jump_n + in.djump;
    out.traction = D_ * j + beta_ * j.squaredNorm() * j + Vec2(kappa_ * j[1] * j[1], 0.0);
    out.tangent = D_ + beta_ * j.squaredNorm() * Mat2::Identity() + 2.0 * beta_ * j * j.transpose();
    out.tangent(0, 1) += 2.0 * kappa_ * j[1];
    return {};
  }

private:
  Mat2 D_;
  double beta_, kappa_;
};

/// Rows: slots 0 (a), 1 (b) of body 1, 2 (partner of b), 3 (partner of a), then 4 (mid of body 1)
/// and 6 (its partner) for the quadratic cell. The edge from a to b, straight.
Eigen::MatrixXd line_cell(const Vec2& a, const Vec2& b, bool quadratic) {
  Eigen::MatrixXd X(quadratic ? 6 : 4, 2);
  X.row(0) = a.transpose();
  X.row(1) = b.transpose();
  X.row(2) = b.transpose();
  X.row(3) = a.transpose();
  if (quadratic) {
    X.row(4) = (0.5 * (a + b)).transpose();
    X.row(5) = (0.5 * (a + b)).transpose();
  }
  return X;
}

struct Evaluated {
  Outcome o;
  ElementResult r;
};
Evaluated evaluate(const Element& el, unsigned shape, const Eigen::MatrixXd& X, const ContactLaw* law,
                   const Eigen::VectorXd& u) {
  StateStore states(static_cast<std::size_t>(el.num_points(shape)), law ? law->history_size() : 0);
  ElementData cell{7, shape, &X};
  Evaluated e;
  e.o =
      el.compute(cell, u, Eigen::VectorXd::Zero(u.size()), Constitutive{nullptr, law}, states, 0, true, e.r);
  return e;
}

/// Rotation rows t, n = (t_y, -t_x) of the edge a -> b.
Mat2 axes(const Vec2& a, const Vec2& b) {
  const Vec2 t = (b - a).normalized();
  Mat2 R;
  R << t.x(), t.y(), t.y(), -t.x();
  return R;
}

/// The closed-form stiffness [[M, -M], [-M, M]] (x) R^T D R in the element's DOF order, from the
/// shape-function matrix M over the body-1 nodes in the order a, b (, mid).
Eigen::MatrixXd closed_form(const Eigen::MatrixXd& M, const Mat2& RtDR) {
  const int n = static_cast<int>(M.rows());
  // Row of the body-1 node k and of its partner on body 2.
  const std::vector<int> side1 = n == 2 ? std::vector<int>{0, 1} : std::vector<int>{0, 1, 4};
  const std::vector<int> side2 = n == 2 ? std::vector<int>{3, 2} : std::vector<int>{3, 2, 5};
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(4 * n, 4 * n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const Mat2 k = M(a, b) * RtDR;
      K.block<2, 2>(2 * side1[a], 2 * side1[b]) += k;
      K.block<2, 2>(2 * side2[a], 2 * side2[b]) += k;
      K.block<2, 2>(2 * side1[a], 2 * side2[b]) -= k;
      K.block<2, 2>(2 * side2[a], 2 * side1[b]) -= k;
    }
  return K;
}

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

} // namespace

TEST_CASE("interface_line: stiffness equals int B^T D B dA in closed form", "[plugins][interface_elements]") {
  Mat2 D;
  D << 2.0e4, 3.0e3, 1.0e3, 1.0e5; // kPa/m, with shear-normal coupling (not symmetric)
  const LinearLaw law(D);
  const Vec2 a(0.3, 1.1), b(1.9, 2.3); // inclined, L = 2
  const double L = (b - a).norm();
  REQUIRE(L == Approx(2.0).epsilon(1e-14));
  const Mat2 R = axes(a, b);
  const Mat2 RtDR = R.transpose() * D * R;
  SECTION("plane strain, 2 + 2 nodes") {
    Eigen::MatrixXd Mg(2, 2), Mn(2, 2);
    Mg << 2, 1, 1, 2;
    Mg *= L / 6.0;
    Mn << L / 2, 0, 0, L / 2;
    const Eigen::MatrixXd X = line_cell(a, b, false);
    for (const auto& [rule, M] : {std::pair{LineRule::gauss, Mg}, std::pair{LineRule::newton_cotes, Mn}}) {
      const InterfaceLine el(Formulation::plane_strain, rule);
      const auto e = evaluate(el, 0x0Fu, X, &law, Eigen::VectorXd::Zero(8));
      REQUIRE(e.o.ok());
      CHECK(rel(e.r.stiffness, closed_form(M, RtDR)) < 1e-12);
    }
  }
  SECTION("plane strain, 3 + 3 nodes") {
    Eigen::MatrixXd Mg(3, 3), Mn = Eigen::MatrixXd::Zero(3, 3);
    Mg << 4, -1, 2, -1, 4, 2, 2, 2, 16;
    Mg *= L / 30.0;
    Mn.diagonal() << L / 6, L / 6, 2 * L / 3;
    const Eigen::MatrixXd X = line_cell(a, b, true);
    for (const auto& [rule, M] : {std::pair{LineRule::gauss, Mg}, std::pair{LineRule::newton_cotes, Mn}}) {
      const InterfaceLine el(Formulation::plane_strain, rule);
      const auto e = evaluate(el, 0x5Fu, X, &law, Eigen::VectorXd::Zero(12));
      REQUIRE(e.o.ok());
      CHECK(rel(e.r.stiffness, closed_form(M, RtDR)) < 1e-12);
    }
  }
  SECTION("axisymmetric, 2 + 2 nodes: the 2 pi r weight") {
    const double ra = a.x(), rb = b.x();
    Eigen::MatrixXd Mg(2, 2), Mn = Eigen::MatrixXd::Zero(2, 2);
    Mg << 3 * ra + rb, ra + rb, ra + rb, ra + 3 * rb;
    Mg *= 2 * pi * L / 12.0;
    Mn.diagonal() = Mg.rowwise().sum(); // Newton-Cotes: the row sums int N_k 2 pi r ds
    CHECK(Mn(0, 0) == Approx(pi * L * (2 * ra + rb) / 3.0).epsilon(1e-14)); // README's l pi (2 r_i + r_nb)/3
    const Eigen::MatrixXd X = line_cell(a, b, false);
    for (const auto& [rule, M] : {std::pair{LineRule::gauss, Mg}, std::pair{LineRule::newton_cotes, Mn}}) {
      const InterfaceLine el(Formulation::axisymmetric, rule);
      const auto e = evaluate(el, 0x0Fu, X, &law, Eigen::VectorXd::Zero(8));
      REQUIRE(e.o.ok());
      CHECK(rel(e.r.stiffness, closed_form(M, RtDR)) < 1e-12);
    }
  }
}

TEST_CASE("interface_line: local axes, force equilibrium and the resultant of a uniform jump",
          "[plugins][interface_elements]") {
  Mat2 D;
  D << 2.0e4, 0.0, 0.0, 1.0e5;
  const LinearLaw law(D);
  SECTION("axes: slip along a -> b, opening along (t_y, -t_x)") {
    // Horizontal edge a = (0, 0) -> b = (2, 0): t = (1, 0), n = (0, -1). Body 2 moved by (1, -2) mm
    // relative to body 1: slip 1 mm, opening 2 mm; tractions 20 kPa shear, 200 kPa tension.
    const Eigen::MatrixXd X = line_cell(Vec2(0, 0), Vec2(2, 0), false);
    const InterfaceLine el(Formulation::plane_strain, LineRule::gauss);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(8);
    for (int k : {2, 3}) u.segment<2>(2 * k) = Vec2(1e-3, -2e-3);
    StateStore states(2, 0);
    ElementData cell{0, 0x0Fu, &X};
    ElementResult r;
    REQUIRE(
        el.compute(cell, u, Eigen::VectorXd::Zero(8), Constitutive{nullptr, &law}, states, 0, true, r).ok());
    for (std::size_t p = 0; p < 2; ++p) {
      CHECK(states.trial(p).strain()[0] == Approx(1e-3).epsilon(1e-14));
      CHECK(states.trial(p).strain()[1] == Approx(2e-3).epsilon(1e-14));
      CHECK(states.trial(p).stress()[0] == Approx(20.0).epsilon(1e-14));
      CHECK(states.trial(p).stress()[1] == Approx(200.0).epsilon(1e-14));
    }
    // Resultant on body 2: L R^T t = 2 m (20, -200) kN/m.
    CHECK(r.force[4] + r.force[6] == Approx(40.0).epsilon(1e-14));
    CHECK(r.force[5] + r.force[7] == Approx(-400.0).epsilon(1e-14));
  }
  SECTION("equal and opposite forces; the resultant int dA R^T D R jump") {
    const Vec2 a(1.0, 0.5), b(1.6, -0.3); // inclined, L = 1, at r = 1-1.6 in axisymmetry
    const Mat2 R = axes(a, b);
    const Vec2 delta(2e-4, -5e-4); // body 2 relative to body 1, global
    for (const bool quadratic : {false, true})
      for (const auto form : {Formulation::plane_strain, Formulation::axisymmetric})
        for (const auto rule : {LineRule::gauss, LineRule::newton_cotes}) {
          const Eigen::MatrixXd X = line_cell(a, b, quadratic);
          const InterfaceLine el(form, rule);
          const int rows = static_cast<int>(X.rows());
          Eigen::VectorXd u = Eigen::VectorXd::Zero(2 * rows);
          for (int k = 0; k < rows; ++k) u.segment<2>(2 * k) = Vec2(0.1 * k, -0.05 * k); // any body-1 motion
          const std::vector<int> s1 = quadratic ? std::vector<int>{0, 1, 4} : std::vector<int>{0, 1};
          const std::vector<int> s2 = quadratic ? std::vector<int>{3, 2, 5} : std::vector<int>{3, 2};
          for (std::size_t k = 0; k < s1.size(); ++k)
            u.segment<2>(2 * s2[k]) = u.segment<2>(2 * s1[k]) + delta;
          const auto e = evaluate(el, quadratic ? 0x5Fu : 0x0Fu, X, &law, u);
          REQUIRE(e.o.ok());
          INFO("quadratic " << quadratic << ", axisymmetric " << (form == Formulation::axisymmetric)
                            << ", gauss " << (rule == LineRule::gauss));
          Vec2 on2 = Vec2::Zero();
          for (std::size_t k = 0; k < s1.size(); ++k) {
            CHECK((e.r.force.segment<2>(2 * s1[k]) + e.r.force.segment<2>(2 * s2[k])).norm() <
                  1e-12 * e.r.force.norm());
            on2 += e.r.force.segment<2>(2 * s2[k]);
          }
          // The area: L, or 2 pi r_mid L in axisymmetry (r linear along the edge).
          const double area = form == Formulation::axisymmetric ? 2 * pi * 0.5 * (a.x() + b.x()) : 1.0;
          const Vec2 expect = area * (R.transpose() * D * R * delta);
          CHECK((on2 - expect).norm() < 1e-12 * expect.norm());
          // Nodal shares of a uniform traction in plane strain: L/2 each, or L (1/6, 1/6, 2/3).
          if (form == Formulation::plane_strain) {
            const std::vector<double> share =
                quadratic ? std::vector<double>{1.0 / 6, 1.0 / 6, 2.0 / 3} : std::vector<double>{0.5, 0.5};
            for (std::size_t k = 0; k < s1.size(); ++k)
              CHECK((e.r.force.segment<2>(2 * s2[k]) - share[k] * expect).norm() < 1e-12 * expect.norm());
          }
        }
  }
}

TEST_CASE("interface_line: tangent against central differences of the force",
          "[plugins][interface_elements]") {
  Mat2 D;
  D << 2.0e4, 3.0e3, 1.0e3, 1.0e5;
  const CubicLaw law(D, 4.0e9, 2.0e8); // the cubic terms comparable to D at jumps of ~1 mm
  const Vec2 a(0.7, 0.2), b(1.5, 1.4);
  for (const bool quadratic : {false, true})
    for (const auto form : {Formulation::plane_strain, Formulation::axisymmetric})
      for (const auto rule : {LineRule::gauss, LineRule::newton_cotes}) {
        const Eigen::MatrixXd X = line_cell(a, b, quadratic);
        const InterfaceLine el(form, rule);
        const unsigned shape = quadratic ? 0x5Fu : 0x0Fu;
        const int ndof = 2 * static_cast<int>(X.rows());
        Eigen::VectorXd u(ndof);
        for (int i = 0; i < ndof; ++i) u[i] = 1e-3 * std::sin(1.7 * i + 0.3); // jumps of ~1 mm, all signs
        const auto base = evaluate(el, shape, X, &law, u);
        REQUIRE(base.o.ok());
        Eigen::MatrixXd fd(ndof, ndof);
        const double h = 1e-8;
        for (int j = 0; j < ndof; ++j) {
          Eigen::VectorXd up = u, um = u;
          up[j] += h;
          um[j] -= h;
          fd.col(j) =
              (evaluate(el, shape, X, &law, up).r.force - evaluate(el, shape, X, &law, um).r.force) / (2 * h);
        }
        INFO("quadratic " << quadratic << ", axisymmetric " << (form == Formulation::axisymmetric)
                          << ", gauss " << (rule == LineRule::gauss));
        CHECK(rel(base.r.stiffness, fd) < 1e-6);
        CHECK((base.r.stiffness - base.r.stiffness.transpose()).norm() > 1e-3 * base.r.stiffness.norm());
      }
}

TEST_CASE("contact2: tributary area, blocks and agreement with interface_line",
          "[plugins][interface_elements]") {
  Mat2 D;
  D << 2.0e4, 0.0, 0.0, 1.0e5;
  const LinearLaw law(D);
  // Node i at (1, 0) between prev (0, 0) and next (3, 0); its partner j coincident.
  Eigen::MatrixXd X(4, 2);
  X << 1, 0, 1, 0, 0, 0, 3, 0;
  const Mat2 R = axes(Vec2(0, 0), Vec2(3, 0));
  // int N_i dA over the two segments: plane strain 1/2 + 2/2 = 1.5; axisymmetric
  // int_0^1 s 2 pi s ds + int_0^2 (1 - s/2) 2 pi (1 + s) ds = 2 pi/3 + 10 pi/3 = 4 pi.
  for (const auto& [form, area] :
       {std::pair{Formulation::plane_strain, 1.5}, std::pair{Formulation::axisymmetric, 4 * pi}}) {
    const Contact2 el(form);
    REQUIRE(el.num_points(0x0Fu) == 1);
    CHECK(el.geometry(ElementData{0, 0x0Fu, &X}).area == Approx(area).epsilon(1e-14));
    const Eigen::Vector<double, 8> zero = Eigen::Vector<double, 8>::Zero();
    const auto e = evaluate(el, 0x0Fu, X, &law, zero);
    REQUIRE(e.o.ok());
    const Mat2 K = area * R.transpose() * D * R;
    CHECK(rel(e.r.stiffness.block<2, 2>(0, 0), K) < 1e-12);
    CHECK(rel(e.r.stiffness.block<2, 2>(2, 2), K) < 1e-12);
    CHECK(rel(e.r.stiffness.block<2, 2>(0, 2), -K) < 1e-12);
    CHECK(rel(e.r.stiffness.block<2, 2>(2, 0), -K) < 1e-12);
    CHECK(e.r.stiffness.bottomRightCorner<4, 4>().norm() == 0.0); // the neighbours carry nothing
    // A uniform jump: contact2's force on j equals the sum of the Newton-Cotes shares of node i's
    // partner in the two interface_line elements on either side of it.
    const Vec2 delta(3e-4, 1e-4);
    Eigen::Vector<double, 8> u = zero;
    u.segment<2>(2) = delta;
    const auto c = evaluate(el, 0x0Fu, X, &law, u);
    const InterfaceLine line(form, LineRule::newton_cotes);
    Vec2 sum = Vec2::Zero();
    for (const auto& [p, q] : {std::pair{Vec2(0, 0), Vec2(1, 0)}, std::pair{Vec2(1, 0), Vec2(3, 0)}}) {
      const Eigen::MatrixXd Y = line_cell(p, q, false);
      Eigen::VectorXd v = Eigen::VectorXd::Zero(8);
      v.segment<2>(4) = delta, v.segment<2>(6) = delta;
      const auto li = evaluate(line, 0x0Fu, Y, &law, v);
      sum += p.x() == 1.0 ? li.r.force.segment<2>(6) : li.r.force.segment<2>(4); // the partner of (1, 0)
    }
    CHECK((c.r.force.segment<2>(2) - sum).norm() < 1e-12 * sum.norm());
    CHECK((c.r.force.segment<2>(0) + c.r.force.segment<2>(2)).norm() == 0.0);
  }
}

TEST_CASE("interface elements: a missing contact law is a status", "[plugins][interface_elements]") {
  const Eigen::MatrixXd X = line_cell(Vec2(0, 0), Vec2(1, 0), false);
  const InterfaceLine el(Formulation::plane_strain, LineRule::gauss);
  Evaluated e;
  REQUIRE_NOTHROW(e = evaluate(el, 0x0Fu, X, nullptr, Eigen::VectorXd::Zero(8)));
  CHECK(e.o.status == Status::material_failure);
  CHECK(e.o.message.find("needs a ContactLaw") != std::string::npos);
}

} // namespace test_interface_elements
