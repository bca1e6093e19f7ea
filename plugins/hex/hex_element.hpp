// The 8-node trilinear hexahedron of three-dimensional small-strain continua, with optional
// B-bar (mean dilatation) treatment of the volumetric strain. Header-only so that the tests run
// exactly the code of the plugin; hex.cpp adds the factory. Equations: README.md in this folder.
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
  int integration = 2; ///< n of the n x n x n Gauss rule, 1..3
  bool bbar = false;   ///< mean dilatation: the volumetric strain averaged over the cell (Hughes 1980)
};

/// The natural coordinates of the corners in VTK_HEXAHEDRON's order (stratum/cell_type.hpp).
inline constexpr std::array<std::array<double, 3>, 8> corner_xi{
    {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}};

using Mat83 = Eigen::Matrix<double, 8, 3>;
using Vec8 = Eigen::Matrix<double, 8, 1>;

/// One point of the rule: natural coordinates, weight, shape functions and their derivatives.
struct RulePoint {
  std::array<double, 3> xi{};
  double weight = 0.0;
  Vec8 N;
  Mat83 dN; ///< d N_a / d xi_b
};

/// Trilinear shape functions and their natural derivatives at xi.
inline void shape(const std::array<double, 3>& xi, Vec8& N, Mat83& dN) {
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
inline std::vector<RulePoint> gauss_rule(int n) {
  std::vector<double> g, w;
  if (n == 1) g = {0.0}, w = {2.0};
  if (n == 2) g = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)}, w = {1.0, 1.0};
  if (n == 3) g = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  std::vector<RulePoint> pts;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        RulePoint p;
        p.xi = {g[static_cast<std::size_t>(i)], g[static_cast<std::size_t>(j)],
                g[static_cast<std::size_t>(k)]};
        p.weight =
            w[static_cast<std::size_t>(i)] * w[static_cast<std::size_t>(j)] * w[static_cast<std::size_t>(k)];
        shape(p.xi, p.N, p.dN);
        pts.push_back(p);
      }
  return pts;
}

/// The 6 x 24 strain-displacement matrix (Voigt xx, yy, zz, xy, yz, zx; engineering shears) of
/// physical derivatives dNdx (8 x 3).
inline Eigen::Matrix<double, 6, 24> strain_matrix(const Mat83& dNdx) {
  Eigen::Matrix<double, 6, 24> B = Eigen::Matrix<double, 6, 24>::Zero();
  for (int a = 0; a < 8; ++a) {
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

class HexElement final : public Element {
public:
  explicit HexElement(Options o) : opt_(validated(o)), rule_(gauss_rule(opt_.integration)) {}

  [[nodiscard]] bool accepts(CellType type) const override { return type == CellType::hexahedron; }
  [[nodiscard]] int num_points(unsigned /*shape*/) const override { return static_cast<int>(rule_.size()); }
  void check_shape(unsigned shape) const override {
    if (shape != 0xFFu)
      throw Error("hex8 needs all 8 corner slots of a hexahedron (slots 0-7); the cell has mask " +
                  std::to_string(shape));
  }
  void check_geometry(const ElementData& cell) const override {
    const Mat83 X = coordinates(cell);
    for (std::size_t i = 0; i < rule_.size(); ++i) {
      const double d = (rule_[i].dN.transpose() * X).determinant();
      if (!(d > 0.0))
        throw Error("non-positive Jacobian determinant " + std::to_string(d) + " at integration point " +
                    std::to_string(i) + "; the corners must follow VTK_HEXAHEDRON's order");
    }
  }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    if (u.size() != 24 || u_n.size() != 24)
      throw Error("element " + std::to_string(cell.id) + ": hex8 expects 24 unknowns, got " +
                  std::to_string(u.size()));
    if (law.material == nullptr)
      return Outcome::failure(Status::material_failure,
                              "element " + std::to_string(cell.id) + ": the hex8 element needs a Material");
    const Mat83 X = coordinates(cell);
    const auto np = static_cast<int>(rule_.size());
    std::vector<Eigen::Matrix<double, 6, 24>> B(rule_.size());
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
      const Mat83 dNdx = p.dN * J.inverse().transpose();
      B[static_cast<std::size_t>(i)] = strain_matrix(dNdx);
      dV[static_cast<std::size_t>(i)] = p.weight * det;
    }
    if (opt_.bbar) {
      // B-bar = B + m (b_mean - b) / 3 with b the volumetric row (sum of the normal rows).
      Eigen::Matrix<double, 1, 24> mean = Eigen::Matrix<double, 1, 24>::Zero();
      double volume = 0.0;
      for (int i = 0; i < np; ++i) {
        const auto k = static_cast<std::size_t>(i);
        mean += dV[k] * B[k].topRows<3>().colwise().sum();
        volume += dV[k];
      }
      mean /= volume;
      for (auto& b : B) {
        const Eigen::Matrix<double, 1, 24> c = (mean - b.topRows<3>().colwise().sum()) / 3.0;
        for (int r = 0; r < 3; ++r) b.row(r) += c;
      }
    }
    Eigen::Matrix<double, 24, 1> f = Eigen::Matrix<double, 24, 1>::Zero();
    Eigen::Matrix<double, 24, 24> K;
    if (want_tangent) K.setZero();
    Vec6 stress;
    Mat6 tangent;
    const Eigen::Matrix<double, 24, 1> du = u - u_n;
    double volume = 0.0; // for the characteristic length of the points
    for (const double v : dV) volume += v;
    for (int i = 0; i < np; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const Vec6 dstrain = B[k] * du;
      if (Outcome r = update_material_point(
              *law.material, states, first_point + k, dstrain,
              continuum::point_context(cell, i, (rule_[k].N.transpose() * X).eval(), volume), want_tangent,
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
                  " components on a hexahedron (3 expected)");
    const Mat83 X = coordinates(cell);
    f.setZero(24);
    for (const auto& p : rule_) {
      const double dV = p.weight * (p.dN.transpose() * X).determinant();
      for (int a = 0; a < 8; ++a) f.segment<3>(3 * a) += (p.N(a) * dV) * b;
    }
  }

  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    const Mat83 X = coordinates(cell);
    xp.resize(static_cast<Eigen::Index>(rule_.size()), 3);
    for (std::size_t i = 0; i < rule_.size(); ++i)
      xp.row(static_cast<Eigen::Index>(i)) = rule_[i].N.transpose() * X;
  }

  void point_weights(const ElementData& cell, Eigen::VectorXd& w) const override {
    const Mat83 X = coordinates(cell);
    w.resize(static_cast<Eigen::Index>(rule_.size()));
    for (std::size_t i = 0; i < rule_.size(); ++i)
      w(static_cast<Eigen::Index>(i)) = rule_[i].weight * (rule_[i].dN.transpose() * X).determinant();
    continuum::normalize_weights(w);
  }

private:
  static Options validated(Options o) {
    if (o.integration < 1 || o.integration > 3)
      throw Error("hex8: integration must be 1, 2 or 3 (got " + std::to_string(o.integration) + ")");
    return o;
  }
  static Mat83 coordinates(const ElementData& cell) {
    if (cell.x == nullptr || cell.x->rows() != 8 || cell.x->cols() != 3)
      throw Error(
          "element " + std::to_string(cell.id) + ": hex8 needs 8 nodes with 3 coordinates each, got " +
          std::to_string(cell.x ? cell.x->rows() : 0) + " x " + std::to_string(cell.x ? cell.x->cols() : 0));
    return *cell.x;
  }

  Options opt_;
  std::vector<RulePoint> rule_;
};

} // namespace stratum::hex
