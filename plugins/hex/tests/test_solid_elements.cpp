// Tests of the 4-node tetrahedron and the 6-node wedge (plugins/hex, issue 36, item 1) against
// closed forms, as the hexahedron's:
//  * constant-strain patch tests on distorted meshes (a 3 x 3 x 3 box of hexahedra, every node
//    moved, each hexahedron cut into 6 tetrahedra or 2 wedges): the free nodes take the linear
//    field u = A x + c exactly, every point has its constant stress and the internal forces
//    balance at the free nodes (1e-10), with each rule and with B-bar;
//  * one cell's stiffness has exactly the 6 rigid-body zero modes (none spurious with the full
//    rule), and the tangent of a nonlinear material matches central differences;
//  * the self-weight of a distorted cell: its nodal forces add up to gamma times its volume
//    (the volume from the divergence theorem over the cell's faces) and their moment about the
//    origin to that of the weight at the centroid;
//  * cells that are not full, or turned inside out, are refused with their reason.
#include "hex/hex_element.hpp"
#include "hex/tests/solid_test_support.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <array>
#include <cmath>
#include <vector>

namespace test_solid_elements {

namespace {

using stratum::CellType;
using stratum::Constitutive;
using stratum::ElementData;
using stratum::ElementResult;
using stratum::Mat6;
using stratum::Outcome;
using stratum::StateStore;
using stratum::Vec6;
namespace hx = stratum::hex;
using hx::testing::distort;
using hx::testing::Elastic;
using hx::testing::Nonlinear;
using hx::testing::solve;

template <int N> struct Mesh3 {
  std::vector<Eigen::Vector3d> x;
  std::vector<std::array<int, N>> cells;
};

/// The nodes of a box of hexahedra (x fastest) and each hexahedron's 8 corners in VTK order.
std::pair<std::vector<Eigen::Vector3d>, std::vector<std::array<int, 8>>>
box(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs) {
  std::vector<Eigen::Vector3d> x;
  std::vector<std::array<int, 8>> hexes;
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size());
  for (double z : zs)
    for (double y : ys)
      for (double xx : xs) x.emplace_back(xx, y, z);
  auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k + 1 < static_cast<int>(zs.size()); ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                         id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  return {x, hexes};
}

double signed_volume(const std::vector<Eigen::Vector3d>& x, const std::array<int, 4>& t) {
  const auto& p = x;
  return (p[static_cast<std::size_t>(t[1])] - p[static_cast<std::size_t>(t[0])])
             .cross(p[static_cast<std::size_t>(t[2])] - p[static_cast<std::size_t>(t[0])])
             .dot(p[static_cast<std::size_t>(t[3])] - p[static_cast<std::size_t>(t[0])]) /
         6.0;
}

/// Each hexahedron cut into 6 tetrahedra around its diagonal 0-6, each turned to VTK_TETRA's
/// orientation (positive volume).
Mesh3<4> tets(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs,
              double distortion) {
  auto [x, hexes] = box(xs, ys, zs);
  distort(x, distortion);
  Mesh3<4> m;
  m.x = x;
  constexpr int cut[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                             {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  for (const auto& h : hexes)
    for (const auto& c : cut) {
      std::array<int, 4> t{h[static_cast<std::size_t>(c[0])], h[static_cast<std::size_t>(c[1])],
                           h[static_cast<std::size_t>(c[2])], h[static_cast<std::size_t>(c[3])]};
      if (signed_volume(m.x, t) < 0) std::swap(t[1], t[2]);
      m.cells.push_back(t);
    }
  return m;
}

/// Each hexahedron cut into 2 wedges along the diagonal 0-2 of its bottom and 4-6 of its top face.
Mesh3<6> wedges(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs,
                double distortion) {
  auto [x, hexes] = box(xs, ys, zs);
  distort(x, distortion);
  Mesh3<6> m;
  m.x = x;
  for (const auto& h : hexes) {
    m.cells.push_back({h[0], h[1], h[2], h[4], h[5], h[6]});
    m.cells.push_back({h[0], h[2], h[3], h[4], h[6], h[7]});
  }
  return m;
}

template <int N> Eigen::MatrixXd cell_x(const Mesh3<N>& m, std::size_t c) {
  Eigen::MatrixXd X(N, 3);
  for (int a = 0; a < N; ++a)
    X.row(a) = m.x[static_cast<std::size_t>(m.cells[c][static_cast<std::size_t>(a)])].transpose();
  return X;
}

template <class Shape> ElementData data(const Eigen::MatrixXd& X, int id = 0) {
  return ElementData{id, Shape::mask, &X, Shape::type};
}

struct Assembled {
  Eigen::SparseMatrix<double> K;
  Eigen::VectorXd f;
  std::vector<Vec6> stress;
};

template <class Shape>
Assembled assemble(const hx::SolidElement<Shape>& el, const stratum::Material& mat,
                   const Mesh3<Shape::nodes>& m, const Eigen::VectorXd& u) {
  constexpr int n = Shape::nodes, nu = 3 * Shape::nodes;
  const auto nd = static_cast<Eigen::Index>(3 * m.x.size());
  std::vector<Eigen::Triplet<double>> t;
  Assembled a;
  a.f = Eigen::VectorXd::Zero(nd);
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    const Eigen::MatrixXd X = cell_x(m, c);
    Eigen::VectorXd ue(nu);
    for (int p = 0; p < n; ++p)
      for (int k = 0; k < 3; ++k) ue(3 * p + k) = u(3 * m.cells[c][static_cast<std::size_t>(p)] + k);
    StateStore states(static_cast<std::size_t>(el.num_points(Shape::mask)), mat.history_size());
    ElementResult r;
    const ElementData cell = data<Shape>(X, static_cast<int>(c));
    REQUIRE_NOTHROW(el.check_geometry(cell));
    REQUIRE(el.compute(cell, ue, Eigen::VectorXd::Zero(nu), Constitutive{&mat, nullptr}, states, 0, true, r)
                .ok());
    for (int i = 0; i < nu; ++i) {
      const int gi = 3 * m.cells[c][static_cast<std::size_t>(i / 3)] + i % 3;
      a.f(gi) += r.force(i);
      for (int j = 0; j < nu; ++j)
        t.emplace_back(gi, 3 * m.cells[c][static_cast<std::size_t>(j / 3)] + j % 3, r.stiffness(i, j));
    }
    for (std::size_t p = 0; p < states.points(); ++p) a.stress.push_back(states.trial(p).stress());
  }
  a.K.resize(nd, nd);
  a.K.setFromTriplets(t.begin(), t.end());
  return a;
}

/// The patch test on a 3 x 3 x 3 box (4 x 4 x 4 nodes, 8 of them inside and free).
template <class Shape> void patch_test(const Mesh3<Shape::nodes>& m, const hx::Options& o) {
  const Elastic mat(3e4, 0.3);
  Eigen::Matrix3d A;
  A << 1e-3, 2e-4, -3e-4, -1e-4, -5e-4, 4e-4, 2.5e-4, 1.5e-4, 7e-4;
  const Eigen::Vector3d c(1e-3, -2e-3, 5e-4);
  const Eigen::Matrix3d e = 0.5 * (A + A.transpose());
  Vec6 eps;
  eps << e(0, 0), e(1, 1), e(2, 2), 2 * e(0, 1), 2 * e(1, 2), 2 * e(2, 0);
  const Vec6 sigma = mat.D() * eps;
  const hx::SolidElement<Shape> el(o);
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
  double ferr = 0.0;
  for (std::size_t d = 0; d < fixed.size(); ++d)
    if (!fixed[d]) ferr = std::max(ferr, std::abs(s.f(static_cast<Eigen::Index>(d))));
  CHECK(ferr < 1e-10 * sigma.cwiseAbs().maxCoeff());
}

/// Zero modes of one cell's stiffness, and the nonlinear tangent against central differences.
template <class Shape> void one_cell(const Eigen::MatrixXd& X, int integration, int expected_zero_modes) {
  constexpr int nu = 3 * Shape::nodes;
  const ElementData cell = data<Shape>(X);
  {
    const Elastic mat(1e4, 0.25);
    const hx::SolidElement<Shape> el(hx::Options{integration, false});
    StateStore st(static_cast<std::size_t>(el.num_points(Shape::mask)), 0);
    ElementResult r;
    REQUIRE(el.compute(cell, Eigen::VectorXd::Zero(nu), Eigen::VectorXd::Zero(nu),
                       Constitutive{&mat, nullptr}, st, 0, true, r)
                .ok());
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(r.stiffness).eigenvalues();
    int zeros = 0;
    for (Eigen::Index i = 0; i < ev.size(); ++i) zeros += std::abs(ev(i)) < 1e-9 * ev.maxCoeff();
    CHECK(zeros == expected_zero_modes);
  }
  const Nonlinear mat;
  for (bool bbar : {false, true}) {
    const hx::SolidElement<Shape> el(hx::Options{integration, bbar});
    Eigen::VectorXd u(nu);
    for (int i = 0; i < nu; ++i) u(i) = 2e-3 * std::sin(1.3 * i + 0.2);
    auto force = [&](const Eigen::VectorXd& v, Eigen::MatrixXd* K) {
      StateStore st(static_cast<std::size_t>(el.num_points(Shape::mask)), 0);
      ElementResult r;
      REQUIRE(
          el.compute(cell, v, Eigen::VectorXd::Zero(nu), Constitutive{&mat, nullptr}, st, 0, K != nullptr, r)
              .ok());
      if (K) *K = r.stiffness;
      return Eigen::VectorXd(r.force);
    };
    Eigen::MatrixXd K, Kfd(nu, nu);
    force(u, &K);
    const double h = 1e-7;
    for (int j = 0; j < nu; ++j) {
      Eigen::VectorXd up = u, um = u;
      up(j) += h, um(j) -= h;
      Kfd.col(j) = (force(up, nullptr) - force(um, nullptr)) / (2 * h);
    }
    CAPTURE(bbar);
    CHECK((K - Kfd).cwiseAbs().maxCoeff() < 1e-6 * K.cwiseAbs().maxCoeff());
  }
}

Eigen::Vector3d row3(const Eigen::MatrixXd& X, int i) { return X.row(i).transpose(); }

/// The volume of a polyhedron from its triangulated boundary (divergence theorem), faces outward.
double volume_of(const Eigen::MatrixXd& X, const std::vector<std::array<int, 3>>& faces) {
  double v = 0.0;
  for (const auto& f : faces) v += row3(X, f[0]).dot(row3(X, f[1]).cross(row3(X, f[2]))) / 6.0;
  return v;
}

} // namespace

TEST_CASE("tet4: constant-strain patch tests on distorted meshes are exact",
          "[plugins][hex][element][patch]") {
  const auto m = tets({0, 0.3, 0.7, 1.0}, {0, 0.4, 0.6, 1.0}, {0, 0.25, 0.65, 1.0}, 0.05);
  REQUIRE(m.cells.size() == 27 * 6);
  for (const auto& [integration, bbar] : {std::pair{1, false}, std::pair{2, false}, std::pair{1, true}}) {
    CAPTURE(integration, bbar);
    patch_test<hx::Tet4>(m, hx::Options{integration, bbar});
  }
}

TEST_CASE("wedge6: constant-strain patch tests on distorted meshes are exact",
          "[plugins][hex][element][patch]") {
  const auto m = wedges({0, 0.3, 0.7, 1.0}, {0, 0.4, 0.6, 1.0}, {0, 0.25, 0.65, 1.0}, 0.05);
  REQUIRE(m.cells.size() == 27 * 2);
  for (const auto& [integration, bbar] : {std::pair{2, false}, std::pair{2, true}}) {
    CAPTURE(integration, bbar);
    patch_test<hx::Wedge6>(m, hx::Options{integration, bbar});
  }
}

TEST_CASE("tet4 and wedge6: six rigid-body modes and a tangent that matches differences",
          "[plugins][hex][element]") {
  const auto t = tets({0, 1.2}, {0, 0.8}, {0, 1.0}, 0.1);
  const auto w = wedges({0, 1.2}, {0, 0.8}, {0, 1.0}, 0.1);
  one_cell<hx::Tet4>(cell_x(t, 0), 1, 6);
  one_cell<hx::Tet4>(cell_x(t, 3), 2, 6);
  one_cell<hx::Wedge6>(cell_x(w, 0), 2, 6);
  one_cell<hx::Wedge6>(cell_x(w, 1), 1, 12); // one point: 6 spurious modes besides the 6 rigid ones
}

TEST_CASE("tet4 and wedge6: the self-weight of a distorted cell is gamma times its volume, at its centroid",
          "[plugins][hex][element]") {
  Eigen::VectorXd b(3);
  b << 0.0, 0.0, -18.0;
  // A distorted tetrahedron: volume (x1 - x0) x (x2 - x0) . (x3 - x0) / 6, centroid the corners' mean.
  Eigen::MatrixXd T(4, 3);
  T << 0.1, -0.05, 0.02, 1.3, 0.1, -0.1, 0.2, 0.9, 0.05, -0.1, 0.15, 1.1;
  const double vt =
      (row3(T, 1) - row3(T, 0)).cross(row3(T, 2) - row3(T, 0)).dot(row3(T, 3) - row3(T, 0)) / 6.0;
  REQUIRE(vt > 0);
  for (int integration : {1, 2}) {
    const hx::TetElement el(hx::Options{integration, false});
    Eigen::VectorXd f;
    el.body_force(data<hx::Tet4>(T), b, f);
    double fz = 0.0;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) {
      fz += f(3 * a + 2);
      moment += row3(T, a).cross(Eigen::Vector3d(f.segment<3>(3 * a)));
    }
    CHECK(fz == Approx(-18.0 * vt).epsilon(1e-12));
    const Eigen::Vector3d centroid = T.colwise().mean().transpose();
    const Eigen::Vector3d weight = b * vt;
    CHECK((moment - centroid.cross(weight)).norm() < 1e-12 * 18.0 * vt);
  }
  // A wedge with a twisted top: its volume from the boundary (the quadrilateral sides split into
  // triangles along a diagonal are not planar: the bilinear side bulges, so the volume of the
  // trilinear cell is checked against a fine sum of the element's own rule instead: two rules agree).
  Eigen::MatrixXd W(6, 3);
  W << 0, 0, 0, 1.1, 0.05, 0.02, 0.1, 0.9, -0.03, 0.02, -0.04, 1.0, 1.05, 0.1, 1.1, 0.12, 0.95, 0.9;
  const hx::WedgeElement w1(hx::Options{1, false}), w2(hx::Options{2, false});
  Eigen::VectorXd f1, f2;
  w1.body_force(data<hx::Wedge6>(W), b, f1);
  w2.body_force(data<hx::Wedge6>(W), b, f2);
  double s1 = 0.0, s2 = 0.0;
  for (int a = 0; a < 6; ++a) s1 += f1(3 * a + 2), s2 += f2(3 * a + 2);
  // det J of the wedge is quadratic in (xi, eta) times linear in zeta at most: the 6-point rule
  // integrates the volume exactly, and so does the centroid rule when the top is parallel to the
  // bottom; here it is not, so only the 6-point value is exact. Exact volume: the boundary with the
  // two triangles and the three bilinear sides (each bilinear quadrilateral's signed volume against
  // the origin is exact with its two diagonal splits averaged).
  const std::vector<std::array<int, 3>> tri_faces{{0, 2, 1}, {3, 4, 5}};
  double v = volume_of(W, tri_faces);
  for (const auto& q : std::vector<std::array<int, 4>>{{0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}}) {
    const double split1 = volume_of(W, {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}});
    const double split2 = volume_of(W, {{q[0], q[1], q[3]}, {q[1], q[2], q[3]}});
    v += 0.5 * (split1 + split2);
  }
  CHECK(s2 == Approx(-18.0 * v).epsilon(1e-12));
  CHECK(s1 == Approx(s2).epsilon(0.05)); // the centroid rule: close, not exact, on a twisted cell
}

TEST_CASE("tet4 and wedge6: refuse cells that are not full or that are turned inside out",
          "[plugins][hex][element]") {
  const hx::TetElement tet(hx::Options{1, false});
  CHECK(tet.accepts(CellType::tetrahedron));
  CHECK_FALSE(tet.accepts(CellType::hexahedron));
  CHECK_THROWS_WITH(tet.check_shape(0x07u),
                    Catch::Contains("tet4 needs all 4 corner slots of a tetrahedron"));
  Eigen::MatrixXd T(4, 3);
  T << 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1; // corners 1 and 2 swapped: negative volume
  CHECK_THROWS_WITH(tet.check_geometry(data<hx::Tet4>(T)),
                    Catch::Contains("non-positive Jacobian") && Catch::Contains("VTK_TETRA's order"));
  const hx::WedgeElement wedge(hx::Options{2, false});
  CHECK(wedge.accepts(CellType::wedge));
  CHECK_THROWS_WITH(wedge.check_shape(0x1Fu), Catch::Contains("wedge6 needs all 6 corner slots of a wedge"));
  Eigen::MatrixXd W(6, 3);
  W << 0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0; // top and bottom exchanged
  CHECK_THROWS_WITH(wedge.check_geometry(data<hx::Wedge6>(W)), Catch::Contains("VTK_WEDGE's order"));
  CHECK_THROWS_WITH(hx::WedgeElement(hx::Options{3, false}),
                    Catch::Contains("wedge6: integration must be 1 to 2"));
}

} // namespace test_solid_elements
