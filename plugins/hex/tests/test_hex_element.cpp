// Tests of the 8-node hexahedron (plugins/hex) against closed forms:
//  * constant-strain patch tests on distorted meshes (every node moved, positive Jacobians): the
//    free nodes take the linear field exactly and every point has its constant stress (1e-10);
//  * the rigid-body null space of one cell (6 zero modes) and the tangent against differences;
//  * a column under its own weight with nu = 0 on unevenly spaced layers: the nodal settlements
//    of linear elements are exact for this one-dimensional problem, u_z = -gamma/E (H z - z^2/2)
//    (1e-10);
//  * Lame's thick cylinder in plane strain, a quarter ring one cell thick: the radial
//    displacement u_r = (1 + nu) a^2 p / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r) within 0.3 % on
//    12 x 16 cells, and the error falls like h^2 when the mesh is refined (ratio above 3).
#include "hex/hex_element.hpp"
#include "hex/tests/solid_test_support.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace test_hex_element {

namespace {

using stratum::CellType;
using stratum::Constitutive;
using stratum::ElementData;
using stratum::ElementResult;
using stratum::Mat6;
using stratum::Outcome;
using stratum::StateStore;
using stratum::Vec6;
using stratum::hex::HexElement;
using stratum::hex::Options;
using stratum::hex::testing::Elastic;
using stratum::hex::testing::Nonlinear;
using stratum::hex::testing::solve;

struct Mesh3 {
  std::vector<Eigen::Vector3d> x;
  std::vector<std::array<int, 8>> cells;
};

/// nx x ny x nz cells on the box [0, L]^3 with coordinates from the given 1D node positions.
Mesh3 box(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs) {
  Mesh3 m;
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size());
  for (double z : zs)
    for (double y : ys)
      for (double x : xs) m.x.emplace_back(x, y, z);
  auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k + 1 < static_cast<int>(zs.size()); ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        m.cells.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                           id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1),
                           id(i, j + 1, k + 1)});
  return m;
}

Eigen::MatrixXd cell_x(const Mesh3& m, std::size_t c) {
  Eigen::MatrixXd X(8, 3);
  for (int a = 0; a < 8; ++a)
    X.row(a) = m.x[static_cast<std::size_t>(m.cells[c][static_cast<std::size_t>(a)])].transpose();
  return X;
}

/// Global stiffness (3 unknowns per node, the element's declared order) and the stress at every
/// point for the displacement u (u_n = 0).
struct Assembled {
  Eigen::SparseMatrix<double> K;
  Eigen::VectorXd f;
  std::vector<Vec6> stress;
};

Assembled assemble(const HexElement& el, const stratum::Material& mat, const Mesh3& m,
                   const Eigen::VectorXd& u) {
  const auto nd = static_cast<Eigen::Index>(3 * m.x.size());
  std::vector<Eigen::Triplet<double>> t;
  Assembled a;
  a.f = Eigen::VectorXd::Zero(nd);
  // The element declares ux, uy, uz at every node: local DOF 3 a + c.
  const auto nf = el.node_fields(CellType::hexahedron, 0xFFu);
  REQUIRE(nf.fields.size() == 3);
  REQUIRE(nf.fields[2].name == "uz");
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    const Eigen::MatrixXd X = cell_x(m, c);
    Eigen::VectorXd ue(24);
    for (int p = 0; p < 8; ++p)
      for (int k = 0; k < 3; ++k) ue(3 * p + k) = u(3 * m.cells[c][static_cast<std::size_t>(p)] + k);
    StateStore states(static_cast<std::size_t>(el.num_points(0xFFu)), mat.history_size());
    ElementResult r;
    const ElementData cell{static_cast<int>(c), 0xFFu, &X, CellType::hexahedron};
    REQUIRE_NOTHROW(el.check_geometry(cell));
    REQUIRE(el.compute(cell, ue, Eigen::VectorXd::Zero(24), Constitutive{&mat, nullptr}, states, 0, true, r)
                .ok());
    for (int i = 0; i < 24; ++i) {
      const int gi = 3 * m.cells[c][static_cast<std::size_t>(i / 3)] + i % 3;
      a.f(gi) += r.force(i);
      for (int j = 0; j < 24; ++j)
        t.emplace_back(gi, 3 * m.cells[c][static_cast<std::size_t>(j / 3)] + j % 3, r.stiffness(i, j));
    }
    for (std::size_t p = 0; p < states.points(); ++p) a.stress.push_back(states.trial(p).stress());
  }
  a.K.resize(nd, nd);
  a.K.setFromTriplets(t.begin(), t.end());
  return a;
}

/// Every node moved by up to `amount` x spacing in each direction (a fixed pseudo-random field).
void distort(Mesh3& m, double amount) { stratum::hex::testing::distort(m.x, amount); }

} // namespace

TEST_CASE("hex8: constant-strain patch tests on distorted meshes are exact",
          "[plugins][hex][element][patch]") {
  const Elastic mat(3e4, 0.3);
  // u = A x + c, a general (unsymmetric) gradient with a rigid rotation part.
  Eigen::Matrix3d A;
  A << 1e-3, 2e-4, -3e-4, -1e-4, -5e-4, 4e-4, 2.5e-4, 1.5e-4, 7e-4;
  const Eigen::Vector3d c(1e-3, -2e-3, 5e-4);
  const Eigen::Matrix3d e = 0.5 * (A + A.transpose());
  Vec6 eps;
  eps << e(0, 0), e(1, 1), e(2, 2), 2 * e(0, 1), 2 * e(1, 2), 2 * e(2, 0);
  const Vec6 sigma = mat.D() * eps;
  for (const auto& [integration, bbar] : {std::pair{2, false}, std::pair{3, false}, std::pair{2, true}}) {
    CAPTURE(integration, bbar);
    const HexElement el(Options{integration, bbar});
    Mesh3 m = box({0, 0.3, 0.7, 1.0}, {0, 0.4, 0.6, 1.0}, {0, 0.25, 0.65, 1.0});
    distort(m, 0.06);
    const std::size_t nn = m.x.size();
    std::vector<char> fixed(3 * nn, 0);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * nn));
    int free_nodes = 0;
    for (std::size_t n = 0; n < nn; ++n) {
      const std::size_t i = n % 4, j = (n / 4) % 4, k = n / 16;
      const bool boundary = i == 0 || i == 3 || j == 0 || j == 3 || k == 0 || k == 3;
      free_nodes += !boundary;
      if (!boundary) continue;
      u.segment<3>(static_cast<Eigen::Index>(3 * n)) = A * m.x[n] + c;
      for (int d = 0; d < 3; ++d) fixed[3 * n + static_cast<std::size_t>(d)] = 1;
    }
    REQUIRE(free_nodes == 8);
    const Assembled k0 = assemble(el, mat, m, Eigen::VectorXd::Zero(u.size()));
    const Eigen::VectorXd us = solve(k0.K, Eigen::VectorXd::Zero(u.size()), fixed, u);
    double err = 0.0;
    for (std::size_t n = 0; n < nn; ++n)
      err = std::max(
          err, (us.segment<3>(static_cast<Eigen::Index>(3 * n)) - (A * m.x[n] + c)).cwiseAbs().maxCoeff());
    CHECK(err < 1e-10 * A.cwiseAbs().maxCoeff());
    const Assembled s = assemble(el, mat, m, us);
    double serr = 0.0;
    for (const Vec6& p : s.stress) serr = std::max(serr, (p - sigma).cwiseAbs().maxCoeff());
    CHECK(serr < 1e-10 * sigma.cwiseAbs().maxCoeff());
    // The internal forces balance at the free nodes (no body force).
    double ferr = 0.0;
    for (std::size_t d = 0; d < fixed.size(); ++d)
      if (!fixed[d]) ferr = std::max(ferr, std::abs(s.f(static_cast<Eigen::Index>(d))));
    CHECK(ferr < 1e-10 * sigma.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("hex8: six rigid-body modes and a tangent that matches differences", "[plugins][hex][element]") {
  Mesh3 m = box({0, 1.2}, {0, 0.8}, {0, 1.0});
  distort(m, 0.1);
  const Eigen::MatrixXd X = cell_x(m, 0);
  const ElementData cell{0, 0xFFu, &X, CellType::hexahedron};
  {
    const Elastic mat(1e4, 0.25);
    const HexElement el(Options{2, false});
    StateStore st(8, 0);
    ElementResult r;
    REQUIRE(el.compute(cell, Eigen::VectorXd::Zero(24), Eigen::VectorXd::Zero(24),
                       Constitutive{&mat, nullptr}, st, 0, true, r)
                .ok());
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(r.stiffness).eigenvalues();
    int zeros = 0;
    for (Eigen::Index i = 0; i < ev.size(); ++i) zeros += std::abs(ev(i)) < 1e-9 * ev.maxCoeff();
    CHECK(zeros == 6);
    CHECK(ev(6) > 1e-4 * ev.maxCoeff()); // no spurious mode with the full 2x2x2 rule
  }
  const Nonlinear mat;
  for (bool bbar : {false, true}) {
    const HexElement el(Options{2, bbar});
    Eigen::VectorXd u(24);
    for (int i = 0; i < 24; ++i) u(i) = 2e-3 * std::sin(1.3 * i + 0.2);
    auto force = [&](const Eigen::VectorXd& v, Eigen::MatrixXd* K) {
      StateStore st(8, 0);
      ElementResult r;
      REQUIRE(
          el.compute(cell, v, Eigen::VectorXd::Zero(24), Constitutive{&mat, nullptr}, st, 0, K != nullptr, r)
              .ok());
      if (K) *K = r.stiffness;
      return Eigen::VectorXd(r.force);
    };
    Eigen::MatrixXd K, Kfd(24, 24);
    force(u, &K);
    const double h = 1e-7;
    for (int j = 0; j < 24; ++j) {
      Eigen::VectorXd up = u, um = u;
      up(j) += h, um(j) -= h;
      Kfd.col(j) = (force(up, nullptr) - force(um, nullptr)) / (2 * h);
    }
    CAPTURE(bbar);
    CHECK((K - Kfd).cwiseAbs().maxCoeff() < 1e-6 * K.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("hex8: a column under its own weight (nu = 0) has exact nodal settlements",
          "[plugins][hex][element]") {
  const double E = 2e4, gamma = 18.0, H = 10.0;
  const Elastic mat(E, 0.0);
  const HexElement el(Options{2, false});
  const std::vector<double> zs{0.0, 0.7, 2.0, 3.1, 5.0, 6.4, 8.5, 10.0}; // uneven layers
  const Mesh3 m = box({0, 1.0}, {0, 1.0}, zs);
  const std::size_t nn = m.x.size();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * nn));
  Eigen::VectorXd b(3);
  b << 0.0, 0.0, -gamma;
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    const Eigen::MatrixXd X = cell_x(m, c);
    Eigen::VectorXd fe;
    el.body_force(ElementData{static_cast<int>(c), 0xFFu, &X, CellType::hexahedron}, b, fe);
    for (int i = 0; i < 24; ++i) f(3 * m.cells[c][static_cast<std::size_t>(i / 3)] + i % 3) += fe(i);
  }
  CHECK(f.sum() == Approx(-gamma * H).epsilon(1e-12)); // the weight of the unit-section column
  // Base fixed vertically; ux = 0 on x = 0 and uy = 0 on y = 0 remove the rigid modes.
  std::vector<char> fixed(3 * nn, 0);
  for (std::size_t n = 0; n < nn; ++n) {
    if (m.x[n].z() == 0.0) fixed[3 * n + 2] = 1;
    if (m.x[n].x() == 0.0) fixed[3 * n] = 1;
    if (m.x[n].y() == 0.0) fixed[3 * n + 1] = 1;
  }
  const Assembled k = assemble(el, mat, m, Eigen::VectorXd::Zero(f.size()));
  const Eigen::VectorXd u = solve(k.K, f, fixed, Eigen::VectorXd::Zero(f.size()));
  double err = 0.0, top = 0.0;
  for (std::size_t n = 0; n < nn; ++n) {
    const double z = m.x[n].z();
    const double exact = -gamma / E * (H * z - 0.5 * z * z);
    err = std::max(err, std::abs(u(static_cast<Eigen::Index>(3 * n + 2)) - exact));
    top = std::max(top, std::abs(exact));
    err = std::max({err, std::abs(u(static_cast<Eigen::Index>(3 * n))),
                    std::abs(u(static_cast<Eigen::Index>(3 * n + 1)))});
  }
  CHECK(err < 1e-10 * top);
}

namespace {

/// Lame's plane-strain cylinder on a quarter ring of nr x nt cells, one cell thick (uz = 0 on
/// both faces): the largest error of u_r at the nodes, relative to u_r(a).
double lame_error(int nr, int nt) {
  const double a = 1.0, b = 2.0, p = 100.0, E = 1e4, nu = 0.3, t = 0.1;
  const Elastic mat(E, nu);
  const HexElement el(Options{2, false});
  Mesh3 m;
  auto id = [&](int i, int j, int k) { return i + (nr + 1) * (j + (nt + 1) * k); };
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= nt; ++j)
      for (int i = 0; i <= nr; ++i) {
        const double r = a + (b - a) * i / nr, th = 0.5 * std::numbers::pi * j / nt;
        m.x.emplace_back(r * std::cos(th), r * std::sin(th), t * k);
      }
  for (int j = 0; j < nt; ++j)
    for (int i = 0; i < nr; ++i)
      m.cells.push_back({id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0), id(i, j, 1),
                         id(i + 1, j, 1), id(i + 1, j + 1, 1), id(i, j + 1, 1)});
  const std::size_t nn = m.x.size();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * nn));
  // The inner pressure on the facets i = 0: p times the outward facet area vector, shared equally
  // by the four corners of each planar facet (exact for a uniform pressure on a planar face).
  for (int j = 0; j < nt; ++j) {
    const int q[4] = {id(0, j, 0), id(0, j + 1, 0), id(0, j + 1, 1), id(0, j, 1)};
    const Eigen::Vector3d d1 = m.x[static_cast<std::size_t>(q[2])] - m.x[static_cast<std::size_t>(q[0])];
    const Eigen::Vector3d d2 = m.x[static_cast<std::size_t>(q[3])] - m.x[static_cast<std::size_t>(q[1])];
    Eigen::Vector3d area = 0.5 * d1.cross(d2); // points away from the axis for this ordering
    if (area.dot(m.x[static_cast<std::size_t>(q[0])]) < 0) area = -area;
    for (int v : q) f.segment<3>(3 * v) += 0.25 * p * area;
  }
  std::vector<char> fixed(3 * nn, 0);
  for (std::size_t n = 0; n < nn; ++n) {
    fixed[3 * n + 2] = 1; // plane strain
    const std::size_t j = (n / static_cast<std::size_t>(nr + 1)) % static_cast<std::size_t>(nt + 1);
    if (j == 0) fixed[3 * n + 1] = 1;                        // uy = 0 on y = 0
    if (j == static_cast<std::size_t>(nt)) fixed[3 * n] = 1; // ux = 0 on x = 0
  }
  Eigen::VectorXd u0 = Eigen::VectorXd::Zero(f.size());
  const Assembled k = assemble(el, mat, m, u0);
  const Eigen::VectorXd u = solve(k.K, f, fixed, u0);
  auto exact = [&](double r) {
    return (1 + nu) * a * a * p / (E * (b * b - a * a)) * ((1 - 2 * nu) * r + b * b / r);
  };
  double err = 0.0;
  for (std::size_t n = 0; n < nn; ++n) {
    const Eigen::Vector3d x = m.x[n];
    const double r = std::hypot(x.x(), x.y());
    const double ur =
        (u(static_cast<Eigen::Index>(3 * n)) * x.x() + u(static_cast<Eigen::Index>(3 * n + 1)) * x.y()) / r;
    err = std::max(err, std::abs(ur - exact(r)));
  }
  return err / exact(a);
}

} // namespace

TEST_CASE("hex8: Lame's thick cylinder in plane strain converges at second order",
          "[plugins][hex][element][verification]") {
  const double coarse = lame_error(6, 8), fine = lame_error(12, 16);
  CAPTURE(coarse, fine);
  CHECK(fine < 3e-3);
  CHECK(coarse / fine > 3.0);
}

TEST_CASE("hex8: refuses cells that are not full hexahedra", "[plugins][hex][element]") {
  const HexElement el(Options{2, false});
  CHECK(el.accepts(CellType::hexahedron));
  CHECK_FALSE(el.accepts(CellType::quadrilateral));
  CHECK_THROWS_AS(el.check_shape(0x7Fu), stratum::Error);
  Mesh3 m = box({0, 1}, {0, 1}, {0, 1});
  std::swap(m.cells[0][0], m.cells[0][1]); // an inverted cell
  const Eigen::MatrixXd X = cell_x(m, 0);
  CHECK_THROWS_WITH(el.check_geometry(ElementData{0, 0xFFu, &X, CellType::hexahedron}),
                    Catch::Contains("non-positive Jacobian"));
  CHECK_THROWS_AS(HexElement(Options{4, false}), stratum::Error);
}

} // namespace test_hex_element
