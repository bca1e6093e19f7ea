// Tests of the variable-node quadrilateral element (plugins/quad): shape functions,
// Gauss rules, stiffness null space, consistent tangent, patch tests, body forces,
// volumetric locking and failure reporting.
#include "linear_elastic/elastic_math.hpp"
#include "quad/quad_element.hpp"
#include "quad/quad_math.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace test_quad_element {

namespace {

using stratum::Constitutive;
using stratum::ElementData;
using stratum::ElementResult;
using stratum::Formulation;
using stratum::Mat6;
using stratum::Outcome;
using stratum::StateStore;
using stratum::Status;
using stratum::Vec2;
using stratum::Vec6;
using stratum::quad::Options;
using stratum::quad::QuadElement;
using stratum::quad::Volumetric;

constexpr double pi = std::numbers::pi;

/// The 16 masks of the family: corners plus every subset of midside slots.
std::vector<unsigned> all_masks() {
  std::vector<unsigned> m;
  for (unsigned s = 0; s < 16; ++s) m.push_back(0x0Fu | (s << 4));
  return m;
}

/// Present slots of a mask, in slot order.
std::vector<int> slots_of(unsigned shape) {
  std::vector<int> s;
  for (int k = 0; k < 8; ++k)
    if (shape & (1u << k)) s.push_back(k);
  return s;
}

/// Coordinates of a cell of the given mask mapped from the distorted quadrilateral with
/// corners P (midside nodes on the bilinear image, then moved by `bulge` along y).
Eigen::MatrixXd cell_coordinates(unsigned shape, const std::array<Vec2, 4>& P, double bulge = 0.0) {
  const auto slots = slots_of(shape);
  Eigen::MatrixXd X(static_cast<Eigen::Index>(slots.size()), 2);
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const double xi = stratum::quad::slot_xi[static_cast<std::size_t>(slots[k])][0];
    const double eta = stratum::quad::slot_xi[static_cast<std::size_t>(slots[k])][1];
    Vec2 x = 0.25 * ((1 - xi) * (1 - eta) * P[0] + (1 + xi) * (1 - eta) * P[1] + (1 + xi) * (1 + eta) * P[2] +
                     (1 - xi) * (1 + eta) * P[3]);
    if (slots[k] >= 4) x.y() += bulge * (slots[k] % 2 == 0 ? 1.0 : -1.0);
    X.row(static_cast<Eigen::Index>(k)) = x.transpose();
  }
  return X;
}

const std::array<Vec2, 4> distorted{Vec2(0.30, 0.10), Vec2(1.40, 0.00), Vec2(1.20, 0.90), Vec2(0.20, 1.10)};

/// A small nonlinear, non-symmetric test material with an exact tangent:
/// sigma(eps) = D eps + alpha tr(eps)^2 m + kappa gamma_xy e_xx.
class QuadTestMaterial final : public stratum::Material {
public:
  QuadTestMaterial(double E, double nu, double alpha, double kappa)
      : D_(stratum::linear_elastic::isotropic_stiffness(E, nu)), alpha_(alpha), kappa_(kappa) {}
  [[nodiscard]] Outcome update(const stratum::MaterialInput& in,
                               stratum::MaterialOutput& out) const override {
    const Vec6 eps = in.strain_n + in.dstrain;
    out.stress = in.stress_n + sigma(eps) - sigma(in.strain_n);
    const double tr = eps.head<3>().sum();
    out.tangent = D_;
    out.tangent.topLeftCorner<3, 3>().array() += 2.0 * alpha_ * tr;
    out.tangent(0, 3) += kappa_;
    return Outcome::success();
  }
  [[nodiscard]] bool symmetric_tangent() const override { return false; }

private:
  [[nodiscard]] Vec6 sigma(const Vec6& e) const {
    Vec6 s = D_ * e;
    const double tr = e.head<3>().sum();
    s.head<3>().array() += alpha_ * tr * tr;
    s(0) += kappa_ * e(3);
    return s;
  }
  Mat6 D_;
  double alpha_, kappa_;
};

/// A material that always fails, to check that the element hands the failure back.
class QuadFailingMaterial final : public stratum::Material {
public:
  [[nodiscard]] Outcome update(const stratum::MaterialInput& in, stratum::MaterialOutput&) const override {
    return Outcome::failure(Status::material_failure, "return mapping failed at element " +
                                                          std::to_string(in.where.element) + " point " +
                                                          std::to_string(in.where.point));
  }
};

/// Internal force and stiffness of one cell at displacement u (u_n = 0, virgin states).
ElementResult evaluate_cell(const QuadElement& el, unsigned shape, const Eigen::MatrixXd& X,
                            const Eigen::VectorXd& u, const stratum::Material& mat) {
  StateStore states(static_cast<std::size_t>(el.num_points(shape)), mat.history_size());
  ElementData cell{3, shape, &X};
  ElementResult r;
  const Outcome o =
      el.compute(cell, u, Eigen::VectorXd::Zero(u.size()), Constitutive{&mat, nullptr}, states, 0, true, r);
  REQUIRE(o.ok());
  return r;
}

/// Number of eigenvalues of the symmetric part of K whose magnitude is below tol times
/// the largest one, and the next magnitude relative to the largest (the gap). The
/// singular values of a symmetric matrix are the magnitudes of its eigenvalues.
std::pair<int, double> count_zero_modes(const Eigen::MatrixXd& K, double tol) {
  const Eigen::MatrixXd Ks = 0.5 * (K + K.transpose());
  const Eigen::VectorXd sv =
      Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::NoQRPreconditioner>(Ks).singularValues(); // descending
  const double lmax = sv(0);
  int zeros = 0;
  for (Eigen::Index i = 0; i < sv.size(); ++i)
    if (sv(i) < tol * lmax) ++zeros;
  const double next = zeros < sv.size() ? sv(sv.size() - 1 - zeros) / lmax : 0.0;
  return {zeros, next};
}

// ---------------------------------------------------------------------------------------
// A tiny mesh + dense assembler for patch and locking tests.

struct TestMesh {
  std::vector<Vec2> nodes;
  std::vector<unsigned> shapes;
  std::vector<std::vector<int>> cells; ///< present nodes in slot order
  std::vector<bool> boundary;          ///< node lies on the outer boundary of the patch
};

/// Builds a mesh from 4-node cells (corners counter-clockwise). Edges for which
/// has_mid(edge number) is true get a midside node at the edge midpoint moved normal to
/// the edge by curve * (edge length) * (+-1 alternating), which curves the edge.
template <class Pred>
TestMesh add_midside_nodes(std::vector<Vec2> corners, const std::vector<std::array<int, 4>>& quads,
                           Pred has_mid, double curve) {
  TestMesh m;
  m.nodes = std::move(corners);
  std::map<std::pair<int, int>, int> edge_count;
  for (const auto& q : quads)
    for (int e = 0; e < 4; ++e)
      ++edge_count[std::minmax(q[static_cast<std::size_t>(e)], q[static_cast<std::size_t>((e + 1) % 4)])];
  m.boundary.assign(m.nodes.size(), false);
  for (const auto& [edge, count] : edge_count)
    if (count == 1)
      m.boundary[static_cast<std::size_t>(edge.first)] = m.boundary[static_cast<std::size_t>(edge.second)] =
          true;

  std::map<std::pair<int, int>, int> mid_node;
  int edge_number = 0;
  for (const auto& [edge, count] : edge_count) {
    if (has_mid(edge_number)) {
      const Vec2 a = m.nodes[static_cast<std::size_t>(edge.first)],
                 b = m.nodes[static_cast<std::size_t>(edge.second)];
      const Vec2 t = b - a;
      const Vec2 normal(-t.y(), t.x());
      const double sign = edge_number % 2 == 0 ? 1.0 : -1.0;
      m.nodes.push_back(0.5 * (a + b) + sign * curve * normal);
      m.boundary.push_back(count == 1);
      mid_node[edge] = static_cast<int>(m.nodes.size()) - 1;
    }
    ++edge_number;
  }
  for (const auto& q : quads) {
    unsigned shape = 0x0F;
    std::vector<int> nodes(q.begin(), q.end());
    for (int e = 0; e < 4; ++e) {
      const auto it = mid_node.find(
          std::minmax(q[static_cast<std::size_t>(e)], q[static_cast<std::size_t>((e + 1) % 4)]));
      if (it != mid_node.end()) {
        shape |= 1u << (4 + e);
        nodes.push_back(it->second);
      }
    }
    m.shapes.push_back(shape);
    m.cells.push_back(nodes);
  }
  return m;
}

/// The 5-element distorted patch of MacNeal & Harder (0.24 x 0.12), shifted by x0.
template <class Pred> TestMesh macneal_harder_patch(double x0, Pred has_mid, double curve) {
  std::vector<Vec2> c{Vec2(0.0, 0.0),   Vec2(0.24, 0.0),  Vec2(0.24, 0.12), Vec2(0.0, 0.12),
                      Vec2(0.04, 0.02), Vec2(0.18, 0.03), Vec2(0.16, 0.08), Vec2(0.08, 0.08)};
  for (Vec2& p : c) p.x() += x0;
  const std::vector<std::array<int, 4>> q{
      {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}};
  return add_midside_nodes(c, q, has_mid, curve);
}

struct Assembly {
  Eigen::MatrixXd K;
  Eigen::VectorXd f;
};

Eigen::MatrixXd coordinates_of(const TestMesh& m, std::size_t e) {
  const auto& nodes = m.cells[e];
  Eigen::MatrixXd X(static_cast<Eigen::Index>(nodes.size()), 2);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    X.row(static_cast<Eigen::Index>(k)) = m.nodes[static_cast<std::size_t>(nodes[k])].transpose();
  return X;
}

/// Dense internal force and stiffness at u; states get every cell's points in order.
Assembly assemble(const QuadElement& el, const TestMesh& m, const stratum::Material& mat,
                  const Eigen::VectorXd& u, StateStore& states) {
  const auto ndof = static_cast<Eigen::Index>(2 * m.nodes.size());
  Assembly a{Eigen::MatrixXd::Zero(ndof, ndof), Eigen::VectorXd::Zero(ndof)};
  std::size_t first = 0;
  for (std::size_t e = 0; e < m.cells.size(); ++e) {
    const auto& nodes = m.cells[e];
    const Eigen::MatrixXd X = coordinates_of(m, e);
    const auto n = static_cast<Eigen::Index>(nodes.size());
    Eigen::VectorXd ue(2 * n);
    for (Eigen::Index k = 0; k < n; ++k)
      ue.segment<2>(2 * k) = u.segment<2>(2 * nodes[static_cast<std::size_t>(k)]);
    ElementData cell{static_cast<int>(e), m.shapes[e], &X};
    ElementResult r;
    const Outcome o = el.compute(cell, ue, Eigen::VectorXd::Zero(2 * n), Constitutive{&mat, nullptr}, states,
                                 first, true, r);
    REQUIRE(o.ok());
    for (Eigen::Index i = 0; i < 2 * n; ++i) {
      const Eigen::Index gi = 2 * nodes[static_cast<std::size_t>(i / 2)] + i % 2;
      a.f(gi) += r.force(i);
      for (Eigen::Index j = 0; j < 2 * n; ++j)
        a.K(gi, 2 * nodes[static_cast<std::size_t>(j / 2)] + j % 2) += r.stiffness(i, j);
    }
    first += static_cast<std::size_t>(el.num_points(m.shapes[e]));
  }
  return a;
}

std::size_t total_points(const QuadElement& el, const TestMesh& m) {
  std::size_t n = 0;
  for (unsigned s : m.shapes) n += static_cast<std::size_t>(el.num_points(s));
  return n;
}

/// Solves K u = f_ext for the free DOFs with u prescribed on the others.
Eigen::VectorXd solve_free(const Eigen::MatrixXd& K, const Eigen::VectorXd& f_ext,
                           const std::vector<bool>& fixed, Eigen::VectorXd u) {
  std::vector<Eigen::Index> free;
  for (std::size_t i = 0; i < fixed.size(); ++i)
    if (!fixed[i]) free.push_back(static_cast<Eigen::Index>(i));
  const auto nf = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd Kff(nf, nf);
  Eigen::VectorXd rhs(nf);
  for (Eigen::Index i = 0; i < nf; ++i) {
    rhs(i) = f_ext(free[static_cast<std::size_t>(i)]) - K.row(free[static_cast<std::size_t>(i)]).dot(u);
    for (Eigen::Index j = 0; j < nf; ++j)
      Kff(i, j) = K(free[static_cast<std::size_t>(i)], free[static_cast<std::size_t>(j)]);
  }
  // u holds zeros at the free DOFs, so K u above only involves the prescribed values.
  const Eigen::VectorXd uf = Kff.fullPivLu().solve(rhs);
  for (Eigen::Index i = 0; i < nf; ++i) u(free[static_cast<std::size_t>(i)]) = uf(i);
  return u;
}

struct PatchResult {
  double displacement_error = 0.0; ///< max |u - u_exact| at free nodes / max |u_exact|
  double stress_error = 0.0;       ///< max |sigma - sigma_exact| over points / max |sigma_exact|
  double strain_error = 0.0;       ///< same for the stored strain
  double residual = 0.0;           ///< max |f_int| at free DOFs / max |f_int|
};

/// Patch test: boundary nodes get the exact field, interior nodes are solved for.
template <class Field>
PatchResult run_patch(const QuadElement& el, const TestMesh& m, const stratum::Material& mat, Field exact,
                      const Vec6& strain_exact) {
  const auto ndof = static_cast<Eigen::Index>(2 * m.nodes.size());
  Eigen::VectorXd u_exact(ndof), u0 = Eigen::VectorXd::Zero(ndof);
  std::vector<bool> fixed(static_cast<std::size_t>(ndof), false);
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    u_exact.segment<2>(2 * static_cast<Eigen::Index>(i)) = exact(m.nodes[i]);
    if (m.boundary[i]) {
      fixed[2 * i] = fixed[2 * i + 1] = true;
      u0.segment<2>(2 * static_cast<Eigen::Index>(i)) = u_exact.segment<2>(2 * static_cast<Eigen::Index>(i));
    }
  }
  StateStore states(total_points(el, m), mat.history_size());
  const Assembly a0 = assemble(el, m, mat, Eigen::VectorXd::Zero(ndof), states);
  const Eigen::VectorXd u = solve_free(a0.K, Eigen::VectorXd::Zero(ndof), fixed, u0);
  const Assembly a = assemble(el, m, mat, u, states);

  PatchResult res;
  double umax = 0.0, fmax = a.f.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ndof; ++i) {
    umax = std::max(umax, std::abs(u_exact(i)));
    if (!fixed[static_cast<std::size_t>(i)]) {
      res.displacement_error = std::max(res.displacement_error, std::abs(u(i) - u_exact(i)));
      res.residual = std::max(res.residual, std::abs(a.f(i)));
    }
  }
  res.displacement_error /= umax;
  res.residual /= fmax;

  Vec6 stress_exact;
  Mat6 tangent;
  stratum::MaterialOutput mo{stress_exact, {}, tangent};
  const Vec6 zero = Vec6::Zero();
  REQUIRE(mat.update(stratum::MaterialInput{zero, zero, {}, strain_exact, {}}, mo).ok());
  for (std::size_t p = 0; p < states.points(); ++p) {
    res.stress_error =
        std::max(res.stress_error, (states.trial(p).stress() - stress_exact).cwiseAbs().maxCoeff());
    res.strain_error =
        std::max(res.strain_error, (states.trial(p).strain() - strain_exact).cwiseAbs().maxCoeff());
  }
  res.stress_error /= stress_exact.cwiseAbs().maxCoeff();
  res.strain_error /= strain_exact.cwiseAbs().maxCoeff();
  return res;
}

} // namespace

// =======================================================================================

TEST_CASE("quad: shape functions interpolate nodes and sum to one for all 16 masks", "[element]") {
  using namespace stratum::quad;
  const std::vector<Vec2> probes{Vec2(0.0, 0.0), Vec2(0.31, -0.77), Vec2(-0.9, 0.45), Vec2(0.99, 0.99),
                                 Vec2(-0.2, 0.6)};
  for (unsigned shape : all_masks()) {
    INFO("mask 0x" << std::hex << shape);
    const auto slots = slots_of(shape);
    const int n = static_cast<int>(slots.size());
    NodeVec N;
    NodeGrad dN;
    // Kronecker property at the nodes.
    for (int j = 0; j < n; ++j) {
      const auto& xj = slot_xi[static_cast<std::size_t>(slots[static_cast<std::size_t>(j)])];
      REQUIRE(shape_functions(shape, xj[0], xj[1], N, dN) == n);
      for (int i = 0; i < n; ++i) CHECK(N(i) == Approx(i == j ? 1.0 : 0.0).margin(1e-14));
    }
    // Partition of unity and reproduction of 1, xi, eta and xi*eta at interior points.
    for (const Vec2& p : probes) {
      shape_functions(shape, p.x(), p.y(), N, dN);
      double s = 0, sx = 0, se = 0, sxe = 0;
      Vec2 ds = Vec2::Zero();
      for (int i = 0; i < n; ++i) {
        const auto& xi = slot_xi[static_cast<std::size_t>(slots[static_cast<std::size_t>(i)])];
        s += N(i);
        sx += N(i) * xi[0];
        se += N(i) * xi[1];
        sxe += N(i) * xi[0] * xi[1];
        ds += dN.row(i).transpose();
      }
      CHECK(s == Approx(1.0).margin(1e-14));
      CHECK(sx == Approx(p.x()).margin(1e-14));
      CHECK(se == Approx(p.y()).margin(1e-14));
      CHECK(sxe == Approx(p.x() * p.y()).margin(1e-14));
      CHECK(ds.norm() < 1e-14);
      for (int i = n; i < max_nodes; ++i) CHECK(N(i) == 0.0);
    }
  }
}

TEST_CASE("quad: shape function derivatives match central differences", "[element]") {
  using namespace stratum::quad;
  const double h = 1e-6;
  for (unsigned shape : all_masks()) {
    INFO("mask 0x" << std::hex << shape);
    for (const Vec2& p : {Vec2(0.13, -0.42), Vec2(-0.66, 0.81), Vec2(0.5, 0.5)}) {
      NodeVec N, Np, Nm;
      NodeGrad dN, scratch;
      shape_functions(shape, p.x(), p.y(), N, dN);
      shape_functions(shape, p.x() + h, p.y(), Np, scratch);
      shape_functions(shape, p.x() - h, p.y(), Nm, scratch);
      const NodeVec dx = (Np - Nm) / (2 * h);
      shape_functions(shape, p.x(), p.y() + h, Np, scratch);
      shape_functions(shape, p.x(), p.y() - h, Nm, scratch);
      const NodeVec de = (Np - Nm) / (2 * h);
      CHECK((dx - dN.col(0)).cwiseAbs().maxCoeff() < 1e-9);
      CHECK((de - dN.col(1)).cwiseAbs().maxCoeff() < 1e-9);
    }
  }
}

TEST_CASE("quad: Gauss rules integrate polynomials of degree 2n-1 exactly", "[element]") {
  using namespace stratum::quad;
  for (int n = 1; n <= 4; ++n) {
    const GaussRule1D g = gauss_legendre(n);
    for (int d = 0; d <= 2 * n - 1; ++d) {
      double q = 0;
      for (int i = 0; i < n; ++i)
        q += g.w[static_cast<std::size_t>(i)] * std::pow(g.x[static_cast<std::size_t>(i)], d);
      const double exact = d % 2 == 1 ? 0.0 : 2.0 / (d + 1);
      CHECK(q == Approx(exact).margin(1e-14));
    }
    // and not degree 2n (so the check above can tell rules apart)
    double q = 0;
    for (int i = 0; i < n; ++i)
      q += g.w[static_cast<std::size_t>(i)] * std::pow(g.x[static_cast<std::size_t>(i)], 2 * n);
    CHECK(std::abs(q - 2.0 / (2 * n + 1)) > 1e-3);
  }
  CHECK_THROWS_AS(gauss_legendre(5), stratum::Error);
  // The reduced-to-full Lagrange interpolation reproduces constants and is exact at coinciding points.
  const Eigen::MatrixXd P = lagrange_interpolation(3, 2);
  CHECK((P.rowwise().sum() - Eigen::VectorXd::Ones(9)).cwiseAbs().maxCoeff() < 1e-14);
  const Eigen::MatrixXd P1 = lagrange_interpolation(2, 1);
  CHECK((P1 - Eigen::MatrixXd::Ones(4, 1)).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("quad: shape masks are validated and points counted", "[element]") {
  const QuadElement el(Options{Formulation::plane_strain, 3, Volumetric::full});
  for (unsigned shape : all_masks()) {
    CHECK_NOTHROW(el.check_shape(shape));
    CHECK(el.num_points(shape) == 9);
  }
  CHECK_THROWS_AS(el.check_shape(0x0Eu), stratum::Error); // corner 0 missing
  CHECK_THROWS_AS(el.check_shape(0x1F7u), stratum::Error);
  CHECK_THROWS_AS(el.check_shape(0x10Fu), stratum::Error); // slot 8 does not exist
  CHECK_THROWS_WITH(el.check_shape(0x0Bu), Catch::Contains("corner slots 0-3"));
  // A triangle (slot 3 empty, stratum/mesh.hpp) is named, with the element that fits it.
  CHECK_THROWS_WITH(el.check_shape(0x07u),
                    "quad element: the cell is a 3-node triangle; use element = \"tri3\" for triangles");
  CHECK_THROWS_WITH(el.check_shape(0x77u),
                    "quad element: the cell is a 6-node triangle; use element = \"tri6\" for triangles");
  CHECK_THROWS_AS(QuadElement(Options{Formulation::plane_strain, 5, Volumetric::full}), stratum::Error);
  CHECK_THROWS_AS(QuadElement(Options{Formulation::plane_strain, 1, Volumetric::full}), stratum::Error);
  CHECK(QuadElement(Options{Formulation::axisymmetric, 2, Volumetric::selective}).num_points(0xFF) == 4);
  CHECK(QuadElement(Options{Formulation::axisymmetric, 4, Volumetric::bbar}).num_points(0x0F) == 16);
}

TEST_CASE("quad: stiffness has exactly the rigid-body zero-energy modes", "[element]") {
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(1000.0, 0.3));
  struct Case {
    unsigned shape;
    int rule;
    Volumetric vol;
  };
  const std::vector<Case> cases{
      {0x0F, 2, Volumetric::full},      {0x0F, 3, Volumetric::full},      {0xFF, 3, Volumetric::full},
      {0x3F, 3, Volumetric::full},      {0x0F, 2, Volumetric::bbar},      {0xFF, 3, Volumetric::bbar},
      {0x0F, 2, Volumetric::selective}, {0xFF, 3, Volumetric::selective}, {0x5F, 4, Volumetric::selective}};
  for (const Case& c : cases) {
    for (double bulge : {0.0, 0.05}) {
      INFO("mask 0x" << std::hex << c.shape << std::dec << " rule " << c.rule << " volumetric "
                     << static_cast<int>(c.vol) << " bulge " << bulge);
      const Eigen::MatrixXd X = cell_coordinates(c.shape, distorted, bulge);
      const Eigen::VectorXd u0 = Eigen::VectorXd::Zero(2 * X.rows());
      {
        const QuadElement el(Options{Formulation::plane_strain, c.rule, c.vol});
        const auto [zeros, gap] = count_zero_modes(evaluate_cell(el, c.shape, X, u0, mat).stiffness, 1e-10);
        CHECK(zeros == 3);
        CHECK(gap > 1e-4);
      }
      // Mean dilatation of elements with midside nodes in axisymmetry has an extra mode
      // (see the next test case), so those are checked there.
      if (!(c.vol == Volumetric::bbar && c.shape != 0x0Fu)) {
        const QuadElement el(Options{Formulation::axisymmetric, c.rule, c.vol});
        const ElementResult r = evaluate_cell(el, c.shape, X, u0, mat);
        const auto [zeros, gap] = count_zero_modes(r.stiffness, 1e-10);
        CHECK(zeros == 1);
        CHECK(gap > 1e-4);
        // the zero mode is the vertical translation
        Eigen::VectorXd t = Eigen::VectorXd::Zero(u0.size());
        for (Eigen::Index k = 0; k < X.rows(); ++k) t(2 * k + 1) = 1.0;
        CHECK((r.stiffness * t).norm() < 1e-10 * r.stiffness.norm());
      }
    }
  }
  // Control: an 8-node quad with 2x2 Gauss points has one spurious mode, which the count must see.
  const QuadElement reduced(Options{Formulation::plane_strain, 2, Volumetric::full});
  const Eigen::MatrixXd X8 = cell_coordinates(0xFF, distorted);
  CHECK(count_zero_modes(evaluate_cell(reduced, 0xFF, X8, Eigen::VectorXd::Zero(16), mat).stiffness, 1e-10)
            .first == 4);
}

TEST_CASE("quad: axisymmetric mean dilatation of 8-node cells has one conformal zero-energy mode",
          "[element]") {
  // dev(eps) = 0 for u = (2 r z, z^2 - r^2) (a conformal Killing field); adding c (r, z)
  // with c = -2 zbar (zbar = volume-weighted mean height) makes the mean dilatation zero.
  // Mean dilatation cannot see this field; the selective variant (pressure in Q1) can.
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(1000.0, 0.3));
  const std::array<Vec2, 4> rect{Vec2(1.0, 0.0), Vec2(2.0, 0.0), Vec2(2.0, 1.0), Vec2(1.0, 1.0)};
  const Eigen::MatrixXd X = cell_coordinates(0xFF, rect);
  const double zbar = 0.5; // symmetric in z
  Eigen::VectorXd w(16);
  for (Eigen::Index k = 0; k < 8; ++k) {
    const double r = X(k, 0), z = X(k, 1);
    w(2 * k) = 2 * r * z - 2 * zbar * r;
    w(2 * k + 1) = z * z - r * r - 2 * zbar * z;
  }
  const Eigen::VectorXd u0 = Eigen::VectorXd::Zero(16);
  const QuadElement bbar(Options{Formulation::axisymmetric, 3, Volumetric::bbar});
  const Eigen::MatrixXd Kb = evaluate_cell(bbar, 0xFF, X, u0, mat).stiffness;
  CHECK(count_zero_modes(Kb, 1e-10).first == 2);
  CHECK((Kb * w).norm() < 1e-10 * Kb.norm() * w.norm());
  const QuadElement sel(Options{Formulation::axisymmetric, 3, Volumetric::selective});
  const Eigen::MatrixXd Ks = evaluate_cell(sel, 0xFF, X, u0, mat).stiffness;
  CHECK(count_zero_modes(Ks, 1e-10).first == 1);
  CHECK(w.dot(Ks * w) > 1e-3 * Ks.norm() * w.squaredNorm());
  // In a mesh the mode does not survive: a 2 x 2 patch of such cells has only the translation.
  std::vector<Vec2> corners;
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 2; ++i) corners.emplace_back(1.0 + 0.5 * i, 0.5 * j);
  std::vector<std::array<int, 4>> quads;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) quads.push_back({3 * j + i, 3 * j + i + 1, 3 * j + i + 4, 3 * j + i + 3});
  const TestMesh m = add_midside_nodes(
      corners, quads, [](int) { return true; }, 0.0);
  StateStore states(total_points(bbar, m), 0);
  const Assembly a =
      assemble(bbar, m, mat, Eigen::VectorXd::Zero(static_cast<Eigen::Index>(2 * m.nodes.size())), states);
  CHECK(count_zero_modes(a.K, 1e-10).first == 1);
}

TEST_CASE("quad: tangent equals the central-difference derivative of the internal force", "[element]") {
  const QuadTestMaterial mat(1000.0, 0.35, 4.0e4, 250.0);
  for (Formulation form : {Formulation::plane_strain, Formulation::axisymmetric}) {
    for (Volumetric vol : {Volumetric::full, Volumetric::bbar, Volumetric::selective}) {
      for (unsigned shape : {0x0Fu, 0xFFu, 0x6Fu, 0x1Fu}) {
        for (int rule : {2, 3}) {
          INFO("formulation " << static_cast<int>(form) << " volumetric " << static_cast<int>(vol)
                              << " mask 0x" << std::hex << shape << std::dec << " rule " << rule);
          const QuadElement el(Options{form, rule, vol});
          const Eigen::MatrixXd X = cell_coordinates(shape, distorted, 0.04);
          const auto nd = 2 * X.rows();
          Eigen::VectorXd u(nd);
          for (Eigen::Index i = 0; i < nd; ++i) u(i) = 1e-3 * std::sin(1.7 * static_cast<double>(i) + 0.3);
          const ElementResult r = evaluate_cell(el, shape, X, u, mat);
          const double h = 1e-6;
          Eigen::MatrixXd Kfd(nd, nd);
          for (Eigen::Index j = 0; j < nd; ++j) {
            Eigen::VectorXd up = u, um = u;
            up(j) += h;
            um(j) -= h;
            Kfd.col(j) =
                (evaluate_cell(el, shape, X, up, mat).force - evaluate_cell(el, shape, X, um, mat).force) /
                (2 * h);
          }
          CHECK((r.stiffness - Kfd).cwiseAbs().maxCoeff() < 1e-7 * r.stiffness.cwiseAbs().maxCoeff());
          // the material is non-symmetric, so the tangent must be too
          CHECK((r.stiffness - r.stiffness.transpose()).cwiseAbs().maxCoeff() >
                1e-4 * r.stiffness.cwiseAbs().maxCoeff());
        }
      }
    }
  }
}

TEST_CASE("quad: element passes committed stress and the strain increment to the material", "[element]") {
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(500.0, 0.25));
  const Mat6& D = mat.stiffness();
  for (Volumetric vol : {Volumetric::full, Volumetric::bbar}) {
    const QuadElement el(Options{Formulation::axisymmetric, 2, vol});
    const unsigned shape = 0x0F;
    const Eigen::MatrixXd X = cell_coordinates(shape, distorted);
    Eigen::VectorXd u(8), un(8);
    for (int i = 0; i < 8; ++i) {
      u(i) = 1e-3 * std::cos(0.9 * i);
      un(i) = 0.4e-3 * std::sin(1.3 * i + 0.2);
    }
    const std::size_t first = 3;
    StateStore states(first + 4 + 2, 0);
    Vec6 s0;
    s0 << -10.0, -20.0, -10.0, 1.0, 0.0, 0.0;
    for (std::size_t p = 0; p < states.points(); ++p) states.committed_for_init(p).stress() = s0;
    ElementData cell{11, shape, &X};
    ElementResult r;
    REQUIRE(el.compute(cell, u, un, Constitutive{&mat, nullptr}, states, first, false, r).ok());
    ElementResult rn;
    StateStore scratch(4, 0);
    REQUIRE(el.compute(cell, un, Eigen::VectorXd::Zero(8), Constitutive{&mat, nullptr}, scratch, 0, false, rn)
                .ok());
    ElementResult ru;
    StateStore scratch_u(4, 0);
    REQUIRE(
        el.compute(cell, u, Eigen::VectorXd::Zero(8), Constitutive{&mat, nullptr}, scratch_u, 0, false, ru)
            .ok());
    for (int i = 0; i < 4; ++i) {
      const auto ii = static_cast<std::size_t>(i);
      const auto p = states.trial(first + ii);
      // The trial strain is the committed strain plus B (u - u_n); the committed strain is kept
      // (here zero), not recomputed from u_n, so a displacement reset cannot change it.
      const Vec6 committed_strain = states.committed(first + ii).strain();
      const Vec6 increment = scratch_u.trial(ii).strain() - scratch.trial(ii).strain(); // B u - B u_n
      CHECK((p.strain() - (committed_strain + increment)).cwiseAbs().maxCoeff() < 1e-15);
      CHECK((p.stress() - (s0 + D * increment)).cwiseAbs().maxCoeff() < 1e-12);
      CHECK(p.strain().tail<2>().isZero());
    }
    // slots outside the cell's range are untouched
    CHECK(states.trial(0).stress().isZero());
    CHECK(states.trial(first + 4).stress().isZero());
    CHECK(r.force.size() == 8);
    CHECK(r.stiffness.size() == 0); // not requested
  }
}

TEST_CASE("quad: B-bar strains keep the deviator and replace the volumetric strain", "[element]") {
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(1000.0, 0.3));
  auto deviator = [](const Vec6& e) {
    Vec6 d = e;
    d.head<3>().array() -= e.head<3>().sum() / 3.0;
    return d;
  };
  for (Formulation form : {Formulation::plane_strain, Formulation::axisymmetric}) {
    for (unsigned shape : {0x0Fu, 0xFFu, 0x9Fu}) {
      for (int rule : {2, 3}) {
        INFO("formulation " << static_cast<int>(form) << " mask 0x" << std::hex << shape << std::dec
                            << " rule " << rule);
        const Eigen::MatrixXd X = cell_coordinates(shape, distorted, 0.04);
        Eigen::VectorXd u(2 * X.rows());
        for (Eigen::Index i = 0; i < u.size(); ++i)
          u(i) = 1e-3 * std::cos(2.1 * static_cast<double>(i) + 0.5);
        const Eigen::VectorXd un = Eigen::VectorXd::Zero(u.size());
        const int np = rule * rule;
        auto strains = [&](Volumetric vol) {
          const QuadElement el(Options{form, rule, vol});
          StateStore states(static_cast<std::size_t>(np), 0);
          ElementResult r;
          REQUIRE(
              el.compute(ElementData{0, shape, &X}, u, un, Constitutive{&mat, nullptr}, states, 0, false, r)
                  .ok());
          std::vector<Vec6> e;
          for (int i = 0; i < np; ++i) e.push_back(states.trial(static_cast<std::size_t>(i)).strain());
          return e;
        };
        const auto full = strains(Volumetric::full), bbar = strains(Volumetric::bbar),
                   sel = strains(Volumetric::selective);
        Eigen::VectorXd w;
        QuadElement(Options{form, rule, Volumetric::full}).point_weights(ElementData{0, shape, &X}, w);
        double mean = 0;
        for (int i = 0; i < np; ++i) mean += w(i) * full[static_cast<std::size_t>(i)].head<3>().sum();
        const Eigen::MatrixXd phi = stratum::quad::lagrange_interpolation(rule, rule - 1);
        Eigen::VectorXd moment = Eigen::VectorXd::Zero(phi.cols());
        bool varies = false;
        for (int i = 0; i < np; ++i) {
          const auto k = static_cast<std::size_t>(i);
          CHECK((deviator(bbar[k]) - deviator(full[k])).cwiseAbs().maxCoeff() < 1e-15);
          CHECK((deviator(sel[k]) - deviator(full[k])).cwiseAbs().maxCoeff() < 1e-15);
          CHECK(bbar[k].head<3>().sum() == Approx(mean).epsilon(1e-12));
          moment += w(i) * (sel[k].head<3>().sum() - full[k].head<3>().sum()) * phi.row(i).transpose();
          varies = varies || std::abs(full[k].head<3>().sum() - mean) > 1e-3 * std::abs(mean);
        }
        CHECK(varies); // the test field really has a non-uniform dilatation
        // selective: the volumetric strain is the weighted projection onto the reduced-point polynomials
        CHECK(moment.cwiseAbs().maxCoeff() < 1e-15);
      }
    }
  }
}

TEST_CASE("quad: plane-strain patch tests with distorted 4-, 8- and mixed-node meshes", "[patch]") {
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(1.0e4, 0.3));
  // u = 1e-3 (1 + 2x + 3y), v = 1e-3 (-1 + 4x - 5y)
  auto field = [](const Vec2& x) {
    return Vec2(1e-3 * (1 + 2 * x.x() + 3 * x.y()), 1e-3 * (-1 + 4 * x.x() - 5 * x.y()));
  };
  Vec6 strain;
  strain << 2e-3, -5e-3, 0.0, 7e-3, 0.0, 0.0;
  struct MeshCase {
    const char* name;
    TestMesh mesh;
  };
  const std::vector<MeshCase> meshes{
      {"quad4", macneal_harder_patch(
                    0.0, [](int) { return false; }, 0.0)},
      {"quad8 curved", macneal_harder_patch(
                           0.0, [](int) { return true; }, 0.04)},
      {"mixed transition", macneal_harder_patch(
                               0.0, [](int e) { return e % 3 != 1; }, 0.03)},
  };
  for (const auto& mc : meshes) {
    for (Volumetric vol : {Volumetric::full, Volumetric::bbar, Volumetric::selective}) {
      for (int rule : {2, 3}) {
        INFO(mc.name << " volumetric " << static_cast<int>(vol) << " rule " << rule);
        const QuadElement el(Options{Formulation::plane_strain, rule, vol});
        const PatchResult r = run_patch(el, mc.mesh, mat, field, strain);
        CHECK(r.displacement_error < 1e-10);
        CHECK(r.strain_error < 1e-10);
        CHECK(r.stress_error < 1e-10);
        CHECK(r.residual < 1e-10);
      }
    }
  }
  // the mixed mesh really contains transition elements
  const TestMesh mixed = macneal_harder_patch(
      0.0, [](int e) { return e % 3 != 1; }, 0.03);
  int transition = 0;
  for (unsigned s : mixed.shapes) transition += (s != 0x0Fu && s != 0xFFu) ? 1 : 0;
  CHECK(transition >= 3);
}

TEST_CASE("quad: axisymmetric patch tests with u_r = a r, u_z = b z + c", "[patch]") {
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(1.0e4, 0.3));
  const double a = 2e-3, b = -3e-3, c = 5e-4;
  auto field = [&](const Vec2& x) { return Vec2(a * x.x(), b * x.y() + c); };
  Vec6 strain;
  strain << a, b, a, 0.0, 0.0, 0.0;
  // With curved edges the integrands (r times polynomials) are of higher degree than in
  // plane strain and the 2x2 rule is not exact, so curved meshes are tested with 3x3 and
  // 4x4, straight-edged ones with every rule.
  for (double x0 : {0.0, 0.05}) {
    struct MeshCase {
      const char* name;
      TestMesh mesh;
      int first_rule;
    };
    const std::vector<MeshCase> meshes{
        {"quad4",
         macneal_harder_patch(
             x0, [](int) { return false; }, 0.0),
         2},
        {"quad8 straight",
         macneal_harder_patch(
             x0, [](int) { return true; }, 0.0),
         2},
        {"mixed straight",
         macneal_harder_patch(
             x0, [](int e) { return e % 3 != 0; }, 0.0),
         2},
        {"quad8 curved",
         macneal_harder_patch(
             x0, [](int) { return true; }, 0.04),
         3},
        {"mixed curved",
         macneal_harder_patch(
             x0, [](int e) { return e % 3 != 0; }, 0.03),
         3},
    };
    for (const auto& [name, mesh, first_rule] : meshes) {
      for (Volumetric vol : {Volumetric::full, Volumetric::bbar, Volumetric::selective}) {
        for (int rule = first_rule; rule <= 4; ++rule) {
          INFO(name << " x0 " << x0 << " volumetric " << static_cast<int>(vol) << " rule " << rule);
          const QuadElement el(Options{Formulation::axisymmetric, rule, vol});
          const PatchResult r = run_patch(el, mesh, mat, field, strain);
          CHECK(r.displacement_error < 1e-10);
          CHECK(r.strain_error < 1e-10);
          CHECK(r.stress_error < 1e-10);
          CHECK(r.residual < 1e-10);
        }
      }
    }
  }
}

TEST_CASE("quad: consistent body forces sum to the weight of the cell", "[element]") {
  const Vec2 b(0.7, -19.0);
  for (unsigned shape : {0x0Fu, 0xFFu, 0x5Fu, 0x8Fu, 0xEFu}) {
    const Eigen::MatrixXd X = cell_coordinates(shape, distorted); // straight edges: exact area
    // polygon area, int x dA and int x^2 dA (shoelace-type formulas)
    double A = 0, Ix = 0, Ixx = 0;
    for (int i = 0; i < 4; ++i) {
      const Vec2 p = distorted[static_cast<std::size_t>(i)],
                 q = distorted[static_cast<std::size_t>((i + 1) % 4)];
      const double cr = p.x() * q.y() - q.x() * p.y();
      A += cr / 2;
      Ix += (p.x() + q.x()) * cr / 6;
      Ixx += (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) * cr / 12;
    }
    for (int rule : {2, 3, 4}) {
      INFO("mask 0x" << std::hex << shape << std::dec << " rule " << rule);
      ElementData cell{1, shape, &X};
      Eigen::VectorXd f;
      Eigen::VectorXd w;
      Eigen::MatrixXd xp;
      {
        const QuadElement el(Options{Formulation::plane_strain, rule, Volumetric::full});
        el.body_force(cell, b, f);
        REQUIRE(f.size() == 2 * X.rows());
        CHECK(f(Eigen::seq(0, Eigen::last, 2)).sum() == Approx(b.x() * A).epsilon(1e-12));
        CHECK(f(Eigen::seq(1, Eigen::last, 2)).sum() == Approx(b.y() * A).epsilon(1e-12));
        el.point_weights(cell, w);
        el.point_coordinates(cell, xp);
        CHECK(w.size() == rule * rule);
        CHECK(w.sum() == Approx(1.0).epsilon(1e-14));
        CHECK(w.dot(xp.col(0)) == Approx(Ix / A).epsilon(1e-12)); // centroid
      }
      {
        const QuadElement el(Options{Formulation::axisymmetric, rule, Volumetric::bbar});
        el.body_force(cell, b, f);
        const double V = 2 * pi * Ix;
        CHECK(f(Eigen::seq(0, Eigen::last, 2)).sum() == Approx(b.x() * V).epsilon(1e-12));
        CHECK(f(Eigen::seq(1, Eigen::last, 2)).sum() == Approx(b.y() * V).epsilon(1e-12));
        el.point_weights(cell, w);
        CHECK(w.sum() == Approx(1.0).epsilon(1e-14));
        el.point_coordinates(cell, xp);
        CHECK(w.dot(xp.col(0)) == Approx(Ixx / Ix).epsilon(1e-12)); // volume-weighted mean radius
      }
    }
  }
  // corner nodes of a square quad4 get a quarter each
  Eigen::MatrixXd sq(4, 2);
  sq << 0, 0, 2, 0, 2, 2, 0, 2;
  const QuadElement el(Options{Formulation::plane_strain, 2, Volumetric::full});
  Eigen::VectorXd f;
  el.body_force(ElementData{0, 0x0F, &sq}, Vec2(0.0, -10.0), f);
  for (int k = 0; k < 4; ++k) CHECK(f(2 * k + 1) == Approx(-10.0).epsilon(1e-14));
}

TEST_CASE("quad: B-bar and selective integration remove volumetric locking of quad4", "[element]") {
  // Thick cylinder a = 1, b = 2 under internal pressure p = 1, axisymmetric with u_z = 0
  // (plane strain in the r-theta plane): u(r) = (1+nu) p a^2 / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r).
  const double a = 1.0, bo = 2.0, h = 0.1, p = 1.0, E = 1000.0, nu = 0.4999;
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(E, nu));
  const double exact = (1 + nu) * p * a * a / (E * (bo * bo - a * a)) * ((1 - 2 * nu) * a + bo * bo / a);
  auto radial_displacement = [&](bool quad8, Volumetric vol, int rule) {
    const int ne = 8;
    std::vector<Vec2> corners;
    for (int i = 0; i <= ne; ++i) {
      const double r = a + (bo - a) * i / ne;
      corners.emplace_back(r, 0.0);
      corners.emplace_back(r, h);
    }
    std::vector<std::array<int, 4>> quads;
    for (int i = 0; i < ne; ++i) quads.push_back({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
    const TestMesh m = add_midside_nodes(
        corners, quads, [&](int) { return quad8; }, 0.0);
    const QuadElement el(Options{Formulation::axisymmetric, rule, vol});
    const auto ndof = static_cast<Eigen::Index>(2 * m.nodes.size());
    StateStore states(total_points(el, m), 0);
    const Assembly A = assemble(el, m, mat, Eigen::VectorXd::Zero(ndof), states);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(ndof);
    std::vector<bool> fixed(static_cast<std::size_t>(ndof), false);
    std::vector<Eigen::Index> inner;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
      fixed[2 * i + 1] = true;
      if (std::abs(m.nodes[i].x() - a) < 1e-12) inner.push_back(static_cast<Eigen::Index>(i));
    }
    // consistent pressure load on the inner face (total 2 pi a h p)
    const double total = 2 * pi * a * h * p;
    for (Eigen::Index i : inner) {
      const double y = m.nodes[static_cast<std::size_t>(i)].y();
      const bool end = std::abs(y) < 1e-12 || std::abs(y - h) < 1e-12;
      f(2 * i) = quad8 ? total * (end ? 1.0 / 6.0 : 4.0 / 6.0) : total / 2;
    }
    const Eigen::VectorXd u = solve_free(A.K, f, fixed, Eigen::VectorXd::Zero(ndof));
    double ua = 0;
    for (Eigen::Index i : inner) ua += u(2 * i) / static_cast<double>(inner.size());
    return ua;
  };
  const double full4 = radial_displacement(false, Volumetric::full, 2);
  const double bbar4 = radial_displacement(false, Volumetric::bbar, 2);
  const double sel4 = radial_displacement(false, Volumetric::selective, 2);
  const double full8 = radial_displacement(true, Volumetric::full, 3);
  const double bbar8 = radial_displacement(true, Volumetric::bbar, 3);
  const double sel8 = radial_displacement(true, Volumetric::selective, 3);
  INFO("exact " << exact << " quad4 full " << full4 << " bbar " << bbar4 << " selective " << sel4
                << " quad8 full " << full8 << " bbar " << bbar8 << " selective " << sel8);
  CHECK(full4 < 0.5 * exact); // locked
  CHECK(bbar4 == Approx(exact).epsilon(0.01));
  CHECK(sel4 == Approx(exact).epsilon(0.01));
  CHECK(bbar8 == Approx(exact).epsilon(0.005));
  CHECK(sel8 == Approx(exact).epsilon(0.005));
}

TEST_CASE("quad: failures are reported as outcomes naming the element and point", "[element]") {
  const stratum::linear_elastic::LinearElastic mat(stratum::linear_elastic::isotropic_stiffness(1000.0, 0.3));
  const QuadElement el(Options{Formulation::axisymmetric, 2, Volumetric::full});
  StateStore states(4, 0);
  ElementResult r;
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(8);

  SECTION("inverted cell") {
    Eigen::MatrixXd X(4, 2);
    X << 1, 0, 1, 1, 2, 1, 2, 0; // clockwise
    const Outcome o =
        el.compute(ElementData{7, 0x0F, &X}, u, u, Constitutive{&mat, nullptr}, states, 0, true, r);
    CHECK(o.status == Status::non_finite);
    CHECK_THAT(o.message,
               Catch::Contains("element 7") && Catch::Contains("Jacobian") && Catch::Contains("point 0"));
    Eigen::VectorXd f;
    CHECK_THROWS_WITH(el.body_force(ElementData{7, 0x0F, &X}, Vec2(0, -1), f), Catch::Contains("element 7"));
  }
  SECTION("cell across the axis in axisymmetry") {
    Eigen::MatrixXd X(4, 2);
    X << -1, 0, 1, 0, 1, 1, -1, 1;
    const Outcome o =
        el.compute(ElementData{8, 0x0F, &X}, u, u, Constitutive{&mat, nullptr}, states, 0, true, r);
    CHECK(o.status == Status::non_finite);
    CHECK_THAT(o.message, Catch::Contains("element 8") && Catch::Contains("radius"));
  }
  SECTION("missing material") {
    Eigen::MatrixXd X(4, 2);
    X << 1, 0, 2, 0, 2, 1, 1, 1;
    const Outcome o = el.compute(ElementData{9, 0x0F, &X}, u, u, Constitutive{}, states, 0, true, r);
    CHECK_FALSE(o.ok());
    CHECK_THAT(o.message, Catch::Contains("element 9") && Catch::Contains("Material"));
  }
  SECTION("material failure is handed back unchanged") {
    Eigen::MatrixXd X(4, 2);
    X << 1, 0, 2, 0, 2, 1, 1, 1;
    const QuadFailingMaterial bad;
    const Outcome o =
        el.compute(ElementData{10, 0x0F, &X}, u, u, Constitutive{&bad, nullptr}, states, 0, true, r);
    CHECK(o.status == Status::material_failure);
    CHECK(o.message == "return mapping failed at element 10 point 0");
  }
  SECTION("non-finite displacement") {
    Eigen::MatrixXd X(4, 2);
    X << 1, 0, 2, 0, 2, 1, 1, 1;
    Eigen::VectorXd bad = u;
    bad(3) = std::nan("");
    const Outcome o =
        el.compute(ElementData{12, 0x0F, &X}, bad, u, Constitutive{&mat, nullptr}, states, 0, true, r);
    CHECK(o.status == Status::non_finite);
    CHECK_THAT(o.message, Catch::Contains("element 12") && Catch::Contains("point"));
  }
  SECTION("mismatched coordinates") {
    Eigen::MatrixXd X(5, 2);
    X.setZero();
    CHECK_THROWS_AS(
        el.compute(ElementData{13, 0x0F, &X}, u, u, Constitutive{&mat, nullptr}, states, 0, true, r),
        stratum::Error);
  }
}

} // namespace test_quad_element
