// The isoparametric 3- and 6-node triangles, axisymmetric or plane strain.
// Header-only so that the tests run exactly the code of the plugin; tri.cpp only adds the
// factories. Equations, quadrature and conventions: README.md in this folder.
//
// Node slots (stratum/element.hpp, a triangle is the quadrilateral family with corner 3 and
// midside 7 absent): corners 0, 1, 2 counter-clockwise; midside 4 on edge 0-1, 5 on 1-2,
// 6 on 2-0. Shape masks: 0x07 (3 nodes), 0x77 (6 nodes).
//
// Axisymmetric forces and stiffnesses are for the full circle (integrated with 2 pi r detJ),
// as in the quad element and the framework's pressure loads.
#pragma once

#include "common/continuum_element.hpp"
#include "stratum/element.hpp"
#include "stratum/error.hpp"
#include "stratum/material_point.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <bit>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

namespace stratum::tri {

inline constexpr unsigned tri3_shape = 0x07u; ///< corners 0, 1, 2
inline constexpr unsigned tri6_shape = 0x77u; ///< corners and midside slots 4, 5, 6
inline constexpr int max_points = 6;

/// The parameters of the element kind.
struct Options {
  Formulation formulation = Formulation::axisymmetric;
  int nodes = 6;       ///< 3 or 6: the cell topology the element needs
  int integration = 6; ///< points of the triangle rule: 1 (3-node only), 3 or 6
};

/// One point of a rule on the reference triangle (0,0), (1,0), (0,1), whose area is 1/2.
struct RulePoint {
  double xi = 0.0, eta = 0.0, weight = 0.0;
};

/// Symmetric Gauss rules on the reference triangle:
///  * 1 point, the centroid (degree 1);
///  * 3 points at (1/6, 1/6), (2/3, 1/6), (1/6, 2/3), weights 1/6 (degree 2);
///  * 6 points in two orbits (Strang and Fix; Dunavant 1985, degree 4).
/// Throws stratum::Error for another count.
[[nodiscard]] inline std::vector<RulePoint> triangle_rule(int points) {
  switch (points) {
  case 1:
    return {{1.0 / 3.0, 1.0 / 3.0, 0.5}};
  case 3: {
    const double a = 1.0 / 6.0, b = 2.0 / 3.0, w = 1.0 / 6.0;
    return {{a, a, w}, {b, a, w}, {a, b, w}};
  }
  case 6: {
    const double a = 0.445948490915965, wa = 0.5 * 0.223381589678011;
    const double b = 0.091576213509771, wb = 0.5 * 0.109951743655322;
    return {{a, a, wa}, {1.0 - 2.0 * a, a, wa}, {a, 1.0 - 2.0 * a, wa},
            {b, b, wb}, {1.0 - 2.0 * b, b, wb}, {b, 1.0 - 2.0 * b, wb}};
  }
  default:
    throw Error("tri element: integration must be 1, 3 or 6 points (got " + std::to_string(points) + ")");
  }
}

/// Shape functions (present nodes in slot order) and their derivatives by (xi, eta).
/// With the area coordinates L0 = 1 - xi - eta, L1 = xi, L2 = eta:
///  3 nodes: N_i = L_i;
///  6 nodes: corners N_i = L_i (2 L_i - 1), midside 4 N_4 = 4 L0 L1, N_5 = 4 L1 L2, N_6 = 4 L2 L0.
inline void shape_functions(int nodes, double xi, double eta, Eigen::VectorXd& N, Eigen::MatrixXd& dN) {
  const std::array<double, 3> L{1.0 - xi - eta, xi, eta};
  const std::array<std::array<double, 2>, 3> dL{{{-1.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}}};
  N.resize(nodes);
  dN.resize(nodes, 2);
  if (nodes == 3) {
    for (int i = 0; i < 3; ++i) {
      N(i) = L[i];
      dN(i, 0) = dL[i][0];
      dN(i, 1) = dL[i][1];
    }
    return;
  }
  for (int i = 0; i < 3; ++i) {
    N(i) = L[i] * (2.0 * L[i] - 1.0);
    for (int d = 0; d < 2; ++d) dN(i, d) = (4.0 * L[i] - 1.0) * dL[i][d];
  }
  for (int e = 0; e < 3; ++e) { // midside e + 3 (slot 4 + e) on edge e -> e + 1
    const int i = e, j = (e + 1) % 3;
    N(3 + e) = 4.0 * L[i] * L[j];
    for (int d = 0; d < 2; ++d) dN(3 + e, d) = 4.0 * (dL[i][d] * L[j] + L[i] * dL[j][d]);
  }
}

/// Describes a shape mask for messages: "a 6-node triangle", "an 8-node quadrilateral", ...
[[nodiscard]] inline std::string describe_shape(unsigned shape) {
  const int n = std::popcount(shape & 0xFFu);
  const bool triangle = (shape & 0x88u) == 0u && (shape & 0x07u) == 0x07u;
  const std::string count = std::to_string(n) + "-node ";
  return (n == 8 ? "an " : "a ") + count + (triangle ? "triangle" : "quadrilateral");
}

/// The triangle element kind. Immutable after construction (tables built in the constructor
/// and only read afterwards), so one object may be used from several threads at once.
class TriElement final : public Element {
public:
  /// Throws stratum::Error for a node count other than 3 or 6, or a rule that does not fit.
  explicit TriElement(Options options) : opt_(validated(options)) {
    for (const RulePoint& p : triangle_rule(opt_.integration)) {
      Table t;
      t.weight = p.weight;
      shape_functions(opt_.nodes, p.xi, p.eta, t.N, t.dN);
      table_.push_back(std::move(t));
    }
  }

  [[nodiscard]] const Options& options() const { return opt_; }
  [[nodiscard]] bool axisymmetric() const { return opt_.formulation == Formulation::axisymmetric; }
  [[nodiscard]] unsigned required_shape() const { return opt_.nodes == 3 ? tri3_shape : tri6_shape; }
  [[nodiscard]] std::string name() const { return opt_.nodes == 3 ? "tri3" : "tri6"; }

  [[nodiscard]] int num_points(unsigned /*shape*/) const override { return static_cast<int>(table_.size()); }

  /// The cell topology the element needs: exactly its own node count, as a triangle.
  void check_shape(unsigned shape) const override {
    if (shape == required_shape()) return;
    std::string hint;
    if (shape == tri3_shape || shape == tri6_shape)
      hint = "; use element = \"" + std::string(shape == tri3_shape ? "tri3" : "tri6") + "\" for these cells";
    else if ((shape & 0x0Fu) == 0x0Fu)
      hint = "; use element = \"quad\" for quadrilaterals";
    throw Error(name() + " element: the cell is " + describe_shape(shape) + ", but " + name() + " needs " +
                describe_shape(required_shape()) + (opt_.nodes == 6 ? " (Gmsh: gmsh -2 -order 2)" : "") +
                hint);
  }

  /// Every integration point must have a positive Jacobian (and, in axisymmetry, radius).
  void check_geometry(const ElementData& cell) const override {
    const Eigen::MatrixXd& X = *cell.x;
    for (std::size_t i = 0; i < table_.size(); ++i) {
      Point g;
      if (!evaluate(table_[i], X, g))
        throw Error(point_message(cell.id, bad_geometry(), static_cast<int>(i)) +
                    " (corners must be counter-clockwise, midside nodes near the middle of their edges)");
    }
  }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    const int n = check_cell(cell);
    continuum::require_plane_displacements(cell, u, u_n, n, "triangle");
    if (law.material == nullptr) return continuum::no_material(cell, name());
    const Material& material = *law.material;
    const bool axi = axisymmetric();
    const Eigen::MatrixXd& X = *cell.x;
    const Eigen::VectorXd du = u - u_n;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * n);
    Eigen::MatrixXd K;
    if (want_tangent) K.setZero(2 * n, 2 * n);
    Eigen::MatrixXd B(4, 2 * n);
    Vec6 dstrain, stress;
    Mat6 tangent;
    Point g;
    // The characteristic length of the points: from the area of the corner triangle.
    const double area =
        0.5 * ((X(1, 0) - X(0, 0)) * (X(2, 1) - X(0, 1)) - (X(2, 0) - X(0, 0)) * (X(1, 1) - X(0, 1)));
    for (std::size_t i = 0; i < table_.size(); ++i) {
      const int ip = static_cast<int>(i);
      if (!evaluate(table_[i], X, g))
        return Outcome::failure(Status::non_finite, point_message(cell.id, bad_geometry(), ip));
      strain_matrix(g, axi, B);
      // As in quad: the increment from the displacement change (stratum/material_point.hpp).
      dstrain.setZero();
      dstrain.head<4>().noalias() = B * du;
      if (Outcome r =
              update_material_point(material, states, first_point + i, dstrain,
                                    continuum::point_context(cell, ip, (g.N->transpose() * X).eval(), area),
                                    want_tangent, stress, tangent);
          !r.ok())
        return r;
      f.noalias() += B.transpose() * (g.dV * stress.head<4>());
      if (want_tangent) {
        const Eigen::Matrix4d Dw = g.dV * tangent.topLeftCorner<4, 4>();
        K.noalias() += B.transpose() * (Dw * B);
      }
    }
    return continuum::deliver(out, f, K, want_tangent);
  }

  [[nodiscard]] bool constant_stiffness(const Constitutive& law) const override {
    return continuum::constant_stiffness(law);
  }

  /// Consistent nodal forces N^T b integrated with the element's rule.
  void body_force(const ElementData& cell, const Eigen::VectorXd& b, Eigen::VectorXd& f) const override {
    const int n = check_cell(cell);
    f.setZero(2 * n);
    Point g;
    for (std::size_t i = 0; i < table_.size(); ++i) {
      if (!evaluate(table_[i], *cell.x, g))
        throw Error(point_message(cell.id, bad_geometry(), static_cast<int>(i)));
      for (int k = 0; k < n; ++k) f.segment<2>(2 * k) += (table_[i].N(k) * g.dV) * b;
    }
  }

  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    check_cell(cell);
    const Eigen::MatrixX2d X = *cell.x; // two columns known at compile time, as the quad's
    xp.resize(static_cast<Eigen::Index>(table_.size()), 2);
    for (std::size_t i = 0; i < table_.size(); ++i)
      xp.row(static_cast<Eigen::Index>(i)) = table_[i].N.transpose() * X;
  }

  /// dV_i / sum dV; equal weights for a degenerate cell.
  void point_weights(const ElementData& cell, Eigen::VectorXd& w) const override {
    check_cell(cell);
    w.resize(static_cast<Eigen::Index>(table_.size()));
    Point g;
    for (std::size_t i = 0; i < table_.size(); ++i) {
      evaluate(table_[i], *cell.x, g);
      w(static_cast<Eigen::Index>(i)) = g.dV;
    }
    continuum::normalize_weights(w);
  }

private:
  struct Table {
    Eigen::VectorXd N;
    Eigen::MatrixXd dN; ///< d/dxi, d/deta
    double weight = 0.0;
  };
  struct Point {
    Eigen::MatrixXd dNdx;
    const Eigen::VectorXd* N = nullptr;
    double x = 0.0, detJ = 0.0, dV = 0.0;
  };

  static Options validated(Options o) {
    if (o.nodes != 3 && o.nodes != 6)
      throw Error("tri element: nodes must be 3 or 6 (got " + std::to_string(o.nodes) + ")");
    if (o.integration != 1 && o.integration != 3 && o.integration != 6)
      throw Error("tri element: integration must be 1, 3 or 6 points (got " + std::to_string(o.integration) +
                  ")");
    if (o.nodes == 6 && o.integration == 1)
      throw Error(
          "tri6 element: the 1-point rule leaves the 6-node triangle with zero-energy modes; use 3 or 6");
    return o;
  }

  int check_cell(const ElementData& cell) const {
    check_shape(cell.shape);
    if (cell.x == nullptr || cell.x->rows() != opt_.nodes)
      throw Error("element " + std::to_string(cell.id) + ": a " + std::to_string(opt_.nodes) +
                  "-node triangle with a coordinate matrix of " +
                  std::to_string(cell.x ? cell.x->rows() : 0) + " rows");
    return opt_.nodes;
  }

  [[nodiscard]] const char* bad_geometry() const {
    return axisymmetric() ? "non-positive Jacobian determinant or radius"
                          : "non-positive Jacobian determinant";
  }

  static std::string point_message(int element, const char* what, int point) {
    return "element " + std::to_string(element) + ": " + what + " at integration point " +
           std::to_string(point);
  }

  /// Geometry at one point; false when detJ (or, in axisymmetry, the radius) is not positive.
  bool evaluate(const Table& t, const Eigen::MatrixXd& X, Point& g) const {
    const Eigen::Matrix2d J = t.dN.transpose() * X; // J(a, b) = d x_b / d xi_a
    g.N = &t.N;
    g.detJ = J.determinant();
    g.x = t.N.dot(X.col(0));
    g.dV = t.weight * g.detJ;
    if (axisymmetric()) g.dV *= 2.0 * std::numbers::pi * g.x;
    if (!(g.detJ > 0.0) || (axisymmetric() && !(g.x > 0.0))) return false;
    g.dNdx.noalias() = t.dN * J.inverse().transpose();
    return true;
  }

  /// Rows: Voigt xx, yy, zz (theta-theta in axisymmetry, zero in plane strain), xy (engineering).
  static void strain_matrix(const Point& g, bool axi, Eigen::MatrixXd& B) {
    B.setZero();
    const double inv_r = axi ? 1.0 / g.x : 0.0;
    for (Eigen::Index k = 0; k < g.dNdx.rows(); ++k) {
      const double dx = g.dNdx(k, 0), dy = g.dNdx(k, 1);
      B(0, 2 * k) = dx;
      B(1, 2 * k + 1) = dy;
      B(2, 2 * k) = (*g.N)(k)*inv_r;
      B(3, 2 * k) = dy;
      B(3, 2 * k + 1) = dx;
    }
  }

  Options opt_;
  std::vector<Table> table_;
};

} // namespace stratum::tri
