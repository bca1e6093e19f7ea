// The linear solid elements of three-dimensional small-strain continua: the 8-node trilinear
// hexahedron, the 4-node tetrahedron and the 6-node wedge, one class templated on the cell's
// shape functions and integration rules, with optional B-bar (mean dilatation) treatment of the
// volumetric strain. Header-only so that the tests run exactly the code of the plugin; hex.cpp
// adds the factories. Equations: README.md in this folder.
#pragma once

#include "common/continuum_element.hpp"
#include "stratum/element.hpp"
#include "stratum/error.hpp"
#include "stratum/material_point.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace stratum::hex {

struct Options {
  int integration =
      2; ///< the rule: hex8 n of n x n x n (1..3); tet4 1 or 4 points (1, 2); wedge6 1 or 6 (1, 2)
  bool bbar = false; ///< mean dilatation: the volumetric strain averaged over the cell (Hughes 1980)
};

/// One point of a rule: natural coordinates, weight, shape functions and their derivatives.
template <int N> struct RulePointN {
  std::array<double, 3> xi{};
  double weight = 0.0;
  Eigen::Matrix<double, N, 1> N_;
  Eigen::Matrix<double, N, 3> dN; ///< d N_a / d xi_b
};

/// The 8-node hexahedron, slots in VTK_HEXAHEDRON's order (stratum/cell_type.hpp).
struct Hex8 {
  static constexpr int nodes = 8;
  static constexpr unsigned mask = 0xFFu;
  static constexpr CellType type = CellType::hexahedron;
  static constexpr const char* name = "hex8";
  static constexpr const char* cell_name = "a hexahedron (slots 0-7)";
  static constexpr const char* order = "VTK_HEXAHEDRON's";
  /// The natural coordinates of the corners.
  static constexpr std::array<std::array<double, 3>, 8> corner_xi{
      {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}};
  static void shape(const std::array<double, 3>& xi, Eigen::Matrix<double, 8, 1>& N,
                    Eigen::Matrix<double, 8, 3>& dN) {
    for (int a = 0; a < 8; ++a) {
      const auto& c = corner_xi[static_cast<std::size_t>(a)];
      const double f0 = 1 + c[0] * xi[0], f1 = 1 + c[1] * xi[1], f2 = 1 + c[2] * xi[2];
      N(a) = 0.125 * f0 * f1 * f2;
      dN(a, 0) = 0.125 * c[0] * f1 * f2;
      dN(a, 1) = 0.125 * f0 * c[1] * f2;
      dN(a, 2) = 0.125 * f0 * f1 * c[2];
    }
  }
  /// The n x n x n Gauss-Legendre rule (n = 1, 2, 3), x fastest.
  static std::vector<std::pair<std::array<double, 3>, double>> rule(int n) {
    std::vector<double> g, w;
    if (n == 1) g = {0.0}, w = {2.0};
    if (n == 2) g = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)}, w = {1.0, 1.0};
    if (n == 3) g = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    std::vector<std::pair<std::array<double, 3>, double>> pts;
    for (std::size_t k = 0; k < g.size(); ++k)
      for (std::size_t j = 0; j < g.size(); ++j)
        for (std::size_t i = 0; i < g.size(); ++i) pts.push_back({{g[i], g[j], g[k]}, w[i] * w[j] * w[k]});
    return pts;
  }
  static constexpr int max_integration = 3;
};

/// The 4-node tetrahedron, corners 0-3 in VTK_TETRA's order: (x1 - x0) x (x2 - x0) . (x3 - x0) > 0;
/// natural coordinates 0 (0,0,0), 1 (1,0,0), 2 (0,1,0), 3 (0,0,1).
struct Tet4 {
  static constexpr int nodes = 4;
  static constexpr unsigned mask = 0x0Fu;
  static constexpr CellType type = CellType::tetrahedron;
  static constexpr const char* name = "tet4";
  static constexpr const char* cell_name = "a tetrahedron (slots 0-3)";
  static constexpr const char* order = "VTK_TETRA's";
  static void shape(const std::array<double, 3>& xi, Eigen::Matrix<double, 4, 1>& N,
                    Eigen::Matrix<double, 4, 3>& dN) {
    N << 1 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2];
    dN << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  }
  /// 1: the centroid (exact for the constant-strain stiffness); 2: the 4-point rule of degree 2.
  static std::vector<std::pair<std::array<double, 3>, double>> rule(int n) {
    if (n == 1) return {{{0.25, 0.25, 0.25}, 1.0 / 6.0}};
    const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0, b = (5.0 - std::sqrt(5.0)) / 20.0;
    return {
        {{b, b, b}, 1.0 / 24.0}, {{a, b, b}, 1.0 / 24.0}, {{b, a, b}, 1.0 / 24.0}, {{b, b, a}, 1.0 / 24.0}};
  }
  static constexpr int max_integration = 2;
};

/// The 6-node wedge: 0-2 the bottom triangle (zeta = -1), 3-5 the top triangle above them
/// (VTK_WEDGE's order); N_a = L_i(xi, eta) (1 -+ zeta) / 2, L = (1 - xi - eta, xi, eta).
struct Wedge6 {
  static constexpr int nodes = 6;
  static constexpr unsigned mask = 0x3Fu;
  static constexpr CellType type = CellType::wedge;
  static constexpr const char* name = "wedge6";
  static constexpr const char* cell_name = "a wedge (slots 0-5)";
  static constexpr const char* order = "VTK_WEDGE's";
  static void shape(const std::array<double, 3>& xi, Eigen::Matrix<double, 6, 1>& N,
                    Eigen::Matrix<double, 6, 3>& dN) {
    const double L[3] = {1 - xi[0] - xi[1], xi[0], xi[1]};
    const double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
    for (int h = 0; h < 2; ++h) {
      const double s = h == 0 ? -1.0 : 1.0, Z = 0.5 * (1 + s * xi[2]);
      for (int i = 0; i < 3; ++i) {
        const int a = 3 * h + i;
        N(a) = L[i] * Z;
        dN(a, 0) = dL[i][0] * Z;
        dN(a, 1) = dL[i][1] * Z;
        dN(a, 2) = L[i] * 0.5 * s;
      }
    }
  }
  /// 1: the centroid; 2: the 3-point triangle rule of degree 2 times 2-point Gauss in zeta.
  static std::vector<std::pair<std::array<double, 3>, double>> rule(int n) {
    if (n == 1) return {{{1.0 / 3.0, 1.0 / 3.0, 0.0}, 1.0}};
    const double g = 1 / std::sqrt(3.0);
    std::vector<std::pair<std::array<double, 3>, double>> pts;
    for (const double z : {-g, g})
      for (const auto& t : {std::array<double, 2>{1.0 / 6, 1.0 / 6}, std::array<double, 2>{2.0 / 3, 1.0 / 6},
                            std::array<double, 2>{1.0 / 6, 2.0 / 3}})
        pts.push_back({{t[0], t[1], z}, 1.0 / 6.0});
    return pts;
  }
  static constexpr int max_integration = 2;
};

/// The 6 x 3n strain-displacement matrix (Voigt xx, yy, zz, xy, yz, zx; engineering shears) of
/// physical derivatives dNdx (n x 3).
template <int N>
inline Eigen::Matrix<double, 6, 3 * N> strain_matrix(const Eigen::Matrix<double, N, 3>& dNdx) {
  Eigen::Matrix<double, 6, 3 * N> B = Eigen::Matrix<double, 6, 3 * N>::Zero();
  for (int a = 0; a < N; ++a) {
    const double dx = dNdx(a, 0), dy = dNdx(a, 1), dz = dNdx(a, 2);
    B(0, 3 * a) = dx;
    B(1, 3 * a + 1) = dy;
    B(2, 3 * a + 2) = dz;
    B(3, 3 * a) = dy, B(3, 3 * a + 1) = dx;
    B(4, 3 * a + 1) = dz, B(4, 3 * a + 2) = dy;
    B(5, 3 * a) = dz, B(5, 3 * a + 2) = dx;
  }
  return B;
}

template <class Shape> class SolidElement final : public Element {
public:
  static constexpr int n = Shape::nodes, nu = 3 * Shape::nodes;
  using MatN3 = Eigen::Matrix<double, n, 3>;
  using BMat = Eigen::Matrix<double, 6, nu>;

  explicit SolidElement(Options o) : opt_(validated(o)) {
    for (const auto& [xi, w] : Shape::rule(opt_.integration)) {
      RulePointN<n> p;
      p.xi = xi;
      p.weight = w;
      Shape::shape(xi, p.N_, p.dN);
      rule_.push_back(p);
    }
  }

  [[nodiscard]] bool accepts(CellType type) const override { return type == Shape::type; }
  [[nodiscard]] int num_points(unsigned /*shape*/) const override { return static_cast<int>(rule_.size()); }
  void check_shape(unsigned shape) const override {
    if (shape != Shape::mask)
      throw Error(std::string(Shape::name) + " needs all " + std::to_string(n) + " corner slots of " +
                  Shape::cell_name + "; the cell has mask " + std::to_string(shape));
  }
  void check_geometry(const ElementData& cell) const override {
    const MatN3 X = coordinates(cell);
    for (std::size_t i = 0; i < rule_.size(); ++i) {
      const double d = (rule_[i].dN.transpose() * X).determinant();
      if (!(d > 0.0))
        throw Error("non-positive Jacobian determinant " + std::to_string(d) + " at integration point " +
                    std::to_string(i) + "; the corners must follow " + Shape::order + " order");
    }
  }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    if (u.size() != nu || u_n.size() != nu)
      throw Error("element " + std::to_string(cell.id) + ": " + Shape::name + " expects " +
                  std::to_string(nu) + " unknowns, got " + std::to_string(u.size()));
    if (law.material == nullptr)
      return Outcome::failure(Status::material_failure, "element " + std::to_string(cell.id) + ": the " +
                                                            Shape::name + " element needs a Material");
    const MatN3 X = coordinates(cell);
    const auto np = static_cast<int>(rule_.size());
    std::vector<BMat> B(rule_.size());
    std::vector<double> dV(rule_.size());
    for (int i = 0; i < np; ++i) {
      const auto& p = rule_[static_cast<std::size_t>(i)];
      const Eigen::Matrix3d J = p.dN.transpose() * X; // J(a, b) = d x_b / d xi_a
      const double det = J.determinant();
      if (!(det > 0.0))
        return Outcome::failure(Status::non_finite,
                                "element " + std::to_string(cell.id) +
                                    ": non-positive Jacobian determinant at integration point " +
                                    std::to_string(i));
      const MatN3 dNdx = p.dN * J.inverse().transpose();
      B[static_cast<std::size_t>(i)] = strain_matrix<n>(dNdx);
      dV[static_cast<std::size_t>(i)] = p.weight * det;
    }
    if (opt_.bbar) {
      // B-bar = B + m (b_mean - b) / 3 with b the volumetric row (sum of the normal rows).
      Eigen::Matrix<double, 1, nu> mean = Eigen::Matrix<double, 1, nu>::Zero();
      double volume = 0.0;
      for (int i = 0; i < np; ++i) {
        const auto k = static_cast<std::size_t>(i);
        mean += dV[k] * B[k].template topRows<3>().colwise().sum();
        volume += dV[k];
      }
      mean /= volume;
      for (auto& b : B) {
        const Eigen::Matrix<double, 1, nu> c = (mean - b.template topRows<3>().colwise().sum()) / 3.0;
        for (int r = 0; r < 3; ++r) b.row(r) += c;
      }
    }
    Eigen::Matrix<double, nu, 1> f = Eigen::Matrix<double, nu, 1>::Zero();
    Eigen::Matrix<double, nu, nu> K;
    if (want_tangent) K.setZero();
    Vec6 stress;
    Mat6 tangent;
    const Eigen::Matrix<double, nu, 1> du = u - u_n;
    double volume = 0.0; // for the characteristic length of the points
    for (const double v : dV) volume += v;
    for (int i = 0; i < np; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const Vec6 dstrain = B[k] * du;
      if (Outcome r = update_material_point(
              *law.material, states, first_point + k, dstrain,
              continuum::point_context(cell, i, (rule_[k].N_.transpose() * X).eval(), volume), want_tangent,
              stress, tangent);
          !r.ok())
        return r;
      f.noalias() += B[k].transpose() * (dV[k] * stress);
      if (want_tangent) K.noalias() += B[k].transpose() * (dV[k] * tangent) * B[k];
    }
    return continuum::deliver(out, f, K, want_tangent);
  }

  [[nodiscard]] bool constant_stiffness(const Constitutive& law) const override {
    return continuum::constant_stiffness(law);
  }

  void body_force(const ElementData& cell, const Eigen::VectorXd& b, Eigen::VectorXd& f) const override {
    if (b.size() != 3)
      throw Error("element " + std::to_string(cell.id) + ": a body force of " + std::to_string(b.size()) +
                  " components on a three-dimensional cell (3 expected)");
    const MatN3 X = coordinates(cell);
    f.setZero(nu);
    for (const auto& p : rule_) {
      const double dV = p.weight * (p.dN.transpose() * X).determinant();
      for (int a = 0; a < n; ++a) f.template segment<3>(3 * a) += (p.N_(a) * dV) * b;
    }
  }

  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    const MatN3 X = coordinates(cell);
    xp.resize(static_cast<Eigen::Index>(rule_.size()), 3);
    for (std::size_t i = 0; i < rule_.size(); ++i)
      xp.row(static_cast<Eigen::Index>(i)) = rule_[i].N_.transpose() * X;
  }

  void point_weights(const ElementData& cell, Eigen::VectorXd& w) const override {
    const MatN3 X = coordinates(cell);
    w.resize(static_cast<Eigen::Index>(rule_.size()));
    for (std::size_t i = 0; i < rule_.size(); ++i)
      w(static_cast<Eigen::Index>(i)) = rule_[i].weight * (rule_[i].dN.transpose() * X).determinant();
    continuum::normalize_weights(w);
  }

private:
  static Options validated(Options o) {
    if (o.integration < 1 || o.integration > Shape::max_integration)
      throw Error(std::string(Shape::name) + ": integration must be 1 to " +
                  std::to_string(Shape::max_integration) + " (got " + std::to_string(o.integration) + ")");
    return o;
  }
  static MatN3 coordinates(const ElementData& cell) {
    if (cell.x == nullptr || cell.x->rows() != n || cell.x->cols() != 3)
      throw Error("element " + std::to_string(cell.id) + ": " + Shape::name + " needs " + std::to_string(n) +
                  " nodes with 3 coordinates each, got " + std::to_string(cell.x ? cell.x->rows() : 0) +
                  " x " + std::to_string(cell.x ? cell.x->cols() : 0));
    return *cell.x;
  }

  Options opt_;
  std::vector<RulePointN<n>> rule_;
};

using HexElement = SolidElement<Hex8>;
using TetElement = SolidElement<Tet4>;
using WedgeElement = SolidElement<Wedge6>;

} // namespace stratum::hex
