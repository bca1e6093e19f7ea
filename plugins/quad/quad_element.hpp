// The variable-node (4 to 8 nodes) isoparametric quadrilateral continuum element,
// axisymmetric or plane strain, with optional B-bar treatment of the volumetric strain.
// Header-only so that the tests can exercise exactly the code the plugin runs; quad.cpp
// only adds the factory. Equations and conventions: README.md in this folder.
//
// Axisymmetric forces and stiffnesses are for the full circle (integrated with
// 2 pi r detJ), consistent with the framework's pressure loads.
#pragma once

#include "quad_math.hpp"

#include "common/continuum_element.hpp"

#include "stratum/element.hpp"
#include "stratum/error.hpp"
#include "stratum/material_point.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>

namespace stratum::quad {

/// How the volumetric part of the strain is treated.
enum class Volumetric {
  full,      ///< standard displacement formulation, B at every point
  bbar,      ///< mean dilatation: volumetric strain averaged over the element (Hughes 1980)
  selective, ///< B-bar form of selective reduced integration: volumetric strain projected onto the
             ///< polynomials through the (n-1)x(n-1) Gauss points (Hughes 1980)
};

/// The parameters of the element kind.
struct Options {
  Formulation formulation = Formulation::axisymmetric;
  int integration = 3; ///< n of the n x n Gauss rule, 2..4
  Volumetric volumetric = Volumetric::full;
};

/// Largest number of points of the reduced (n-1)x(n-1) rule.
inline constexpr int max_reduced = (max_rule - 1) * (max_rule - 1);

namespace detail {

/// Calls f(std::integral_constant<int, n>{}) for n = 4..8 (the node count of a valid mask).
template <class F> decltype(auto) with_node_count(int n, F&& f) {
  switch (n) {
  case 4:
    return f(std::integral_constant<int, 4>{});
  case 5:
    return f(std::integral_constant<int, 5>{});
  case 6:
    return f(std::integral_constant<int, 6>{});
  case 7:
    return f(std::integral_constant<int, 7>{});
  default:
    return f(std::integral_constant<int, 8>{});
  }
}

/// Geometry of one integration point of a cell with NN nodes.
template <int NN> struct PointGeometry {
  Eigen::Matrix<double, NN, 1> N;    ///< shape functions
  Eigen::Matrix<double, NN, 2> dNdx; ///< derivatives by x (r) and y (z)
  double x = 0.0;                    ///< x coordinate (the radius r in axisymmetry)
  double detJ = 0.0;                 ///< Jacobian determinant of the map (xi, eta) -> (x, y)
  double dV = 0.0;                   ///< weight x detJ (x 2 pi r in axisymmetry)
};

/// Evaluates the geometry of a table point. Returns false (leaving dNdx unset) when the
/// Jacobian determinant or, in axisymmetry, the radius is not positive.
template <int NN>
bool evaluate(const TablePoint& p, const Eigen::Matrix<double, NN, 2>& X, bool axisymmetric,
              PointGeometry<NN>& g) {
  g.N = p.N.template head<NN>();
  const auto dN = p.dN.template topRows<NN>();
  const Mat2 J = dN.transpose() * X; // J(a, b) = d x_b / d xi_a
  g.detJ = J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0);
  g.x = g.N.dot(X.col(0));
  g.dV = p.weight * g.detJ;
  if (axisymmetric) g.dV *= 2.0 * std::numbers::pi * g.x;
  if (!(g.detJ > 0.0) || (axisymmetric && !(g.x > 0.0))) return false;
  Mat2 Jinv;
  Jinv << J(1, 1), -J(0, 1), -J(1, 0), J(0, 0);
  Jinv /= g.detJ;
  g.dNdx.noalias() = dN * Jinv.transpose();
  return true;
}

/// Volumetric strain operator of one point: eps_xx + eps_yy (+ eps_theta) = b u.
template <int NN>
Eigen::Matrix<double, 1, 2 * NN> volumetric_row(const PointGeometry<NN>& g, bool axisymmetric) {
  Eigen::Matrix<double, 1, 2 * NN> b;
  const double inv_r = axisymmetric ? 1.0 / g.x : 0.0;
  for (int k = 0; k < NN; ++k) {
    b(2 * k) = g.dNdx(k, 0) + g.N(k) * inv_r;
    b(2 * k + 1) = g.dNdx(k, 1);
  }
  return b;
}

/// Standard strain-displacement matrix, rows = Voigt components xx, yy, zz, xy
/// (axisymmetric: rr, zz, theta-theta, rz; plane strain: row zz is zero).
template <int NN>
void strain_matrix(const PointGeometry<NN>& g, bool axisymmetric, Eigen::Matrix<double, 4, 2 * NN>& B) {
  B.setZero();
  const double inv_r = axisymmetric ? 1.0 / g.x : 0.0;
  for (int k = 0; k < NN; ++k) {
    const double dx = g.dNdx(k, 0), dy = g.dNdx(k, 1);
    B(0, 2 * k) = dx;
    B(1, 2 * k + 1) = dy;
    B(2, 2 * k) = g.N(k) * inv_r;
    B(3, 2 * k) = dy;
    B(3, 2 * k + 1) = dx;
  }
}

/// K += B^T Dw B for the standard (sparse) B: column 2k of B is (dx, 0, h, dy), column
/// 2k+1 is (0, dy, 0, dx) with h = N/r in axisymmetry and 0 in plane strain.
template <int NN>
void add_sparse_btdb(const PointGeometry<NN>& g, bool axisymmetric, const Eigen::Matrix4d& Dw,
                     Eigen::Matrix<double, 2 * NN, 2 * NN, Eigen::RowMajor>& K) {
  const double inv_r = axisymmetric ? 1.0 / g.x : 0.0;
  Eigen::Matrix<double, 4, 2 * NN, Eigen::RowMajor> DB;
  for (int k = 0; k < NN; ++k) {
    const double dx = g.dNdx(k, 0), dy = g.dNdx(k, 1), h = g.N(k) * inv_r;
    DB.col(2 * k) = Dw.col(0) * dx + Dw.col(2) * h + Dw.col(3) * dy;
    DB.col(2 * k + 1) = Dw.col(1) * dy + Dw.col(3) * dx;
  }
  for (int k = 0; k < NN; ++k) {
    const double dx = g.dNdx(k, 0), dy = g.dNdx(k, 1), h = g.N(k) * inv_r;
    K.row(2 * k) += dx * DB.row(0) + h * DB.row(2) + dy * DB.row(3);
    K.row(2 * k + 1) += dy * DB.row(1) + dx * DB.row(3);
  }
}

/// B^T v for the standard (sparse) B and a 4-vector v.
template <int NN>
Eigen::Matrix<double, 2 * NN, 1> sparse_bt_times(const PointGeometry<NN>& g, bool axisymmetric,
                                                 const Eigen::Vector4d& v) {
  const double inv_r = axisymmetric ? 1.0 / g.x : 0.0;
  Eigen::Matrix<double, 2 * NN, 1> a;
  for (int k = 0; k < NN; ++k) {
    const double dx = g.dNdx(k, 0), dy = g.dNdx(k, 1), h = g.N(k) * inv_r;
    a(2 * k) = dx * v(0) + h * v(2) + dy * v(3);
    a(2 * k + 1) = dy * v(1) + dx * v(3);
  }
  return a;
}

inline std::string point_message(int element, const char* what, int point) {
  return "element " + std::to_string(element) + ": " + what + " at integration point " +
         std::to_string(point);
}

} // namespace detail

/// The quadrilateral element kind. Immutable after construction: the shape-function
/// tables of its rules are built in the constructor and only read afterwards, so one
/// object may be used from several threads at once.
class QuadElement final : public Element {
public:
  /// Throws stratum::Error when options.integration is not 2, 3 or 4.
  explicit QuadElement(Options options)
      : opt_(validated(options)), rule_(opt_.integration),
        interp_(lagrange_interpolation(opt_.integration,
                                       opt_.volumetric == Volumetric::selective ? opt_.integration - 1 : 1)) {
  }

  [[nodiscard]] const Options& options() const { return opt_; }
  [[nodiscard]] bool axisymmetric() const { return opt_.formulation == Formulation::axisymmetric; }

  [[nodiscard]] int num_points(unsigned /*shape*/) const override { return rule_.size(); }

  void check_shape(unsigned shape) const override { require_valid_shape(shape); }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    const int n = check_cell(cell);
    continuum::require_plane_displacements(cell, u, u_n, n, "quadrilateral");
    if (law.material == nullptr) return continuum::no_material(cell, "quad");
    return detail::with_node_count(n, [&](auto nn) {
      return compute_fixed<decltype(nn)::value>(cell, u, u_n, *law.material, states, first_point,
                                                want_tangent, out);
    });
  }

  [[nodiscard]] bool constant_stiffness(const Constitutive& law) const override {
    return continuum::constant_stiffness(law);
  }

  /// Consistent nodal forces N^T b integrated with the element's rule. Throws
  /// stratum::Error for a cell with a non-positive Jacobian (or radius) at a point.
  void body_force(const ElementData& cell, const Eigen::VectorXd& b, Eigen::VectorXd& f) const override {
    const int n = check_cell(cell);
    f.setZero(2 * n);
    each_point(cell, n, [&](int i, bool valid, const auto& g) {
      if (!valid) throw Error(detail::point_message(cell.id, bad_geometry(), i));
      for (int k = 0; k < g.N.size(); ++k) f.segment<2>(2 * k) += (g.N(k) * g.dV) * b;
    });
  }

  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    const int n = check_cell(cell);
    const auto& pts = rule_.points(cell.shape);
    // Two columns known at compile time: the product sums in the order it always has (the
    // coordinates, and the geostatic stresses computed from them, bit for bit).
    const Eigen::MatrixX2d X = *cell.x;
    xp.resize(rule_.size(), 2);
    for (int i = 0; i < rule_.size(); ++i)
      xp.row(i) = pts[static_cast<std::size_t>(i)].N.head(n).transpose() * X;
  }

  /// dV_i / sum dV (dV = w detJ, times 2 pi r in axisymmetry). Falls back to equal weights
  /// for a degenerate cell whose volume is not positive.
  void point_weights(const ElementData& cell, Eigen::VectorXd& w) const override {
    const int n = check_cell(cell);
    w.resize(rule_.size());
    each_point(cell, n, [&](int i, bool, const auto& g) { w(i) = g.dV; });
    continuum::normalize_weights(w);
  }

private:
  /// Calls visit(i, valid, g) with the geometry g of every integration point i of the cell (n
  /// nodes); valid is false where the Jacobian (or the radius) is not positive.
  template <class Visit> void each_point(const ElementData& cell, int n, Visit&& visit) const {
    detail::with_node_count(n, [&](auto nn) {
      constexpr int NN = decltype(nn)::value;
      const Eigen::Matrix<double, NN, 2> X = *cell.x;
      const auto& pts = rule_.points(cell.shape);
      detail::PointGeometry<NN> g;
      for (int i = 0; i < rule_.size(); ++i)
        visit(i, detail::evaluate<NN>(pts[static_cast<std::size_t>(i)], X, axisymmetric(), g), g);
    });
  }

  static Options validated(Options o) {
    if (o.integration < 2 || o.integration > max_rule)
      throw Error("quad element: integration must be 2, 3 or 4 (got " + std::to_string(o.integration) + ")");
    return o;
  }

  /// Validates the cell against the element and returns its node count.
  int check_cell(const ElementData& cell) const {
    require_valid_shape(cell.shape);
    const int n = node_count(cell.shape);
    if (cell.x == nullptr || cell.x->rows() != n)
      throw Error("element " + std::to_string(cell.id) + ": node mask has " + std::to_string(n) +
                  " nodes but the coordinate matrix has " + std::to_string(cell.x ? cell.x->rows() : 0) +
                  " rows");
    return n;
  }

  [[nodiscard]] const char* bad_geometry() const {
    return axisymmetric() ? "non-positive Jacobian determinant or radius"
                          : "non-positive Jacobian determinant";
  }

  template <int NN>
  Outcome compute_fixed(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                        const Material& material, StateStore& states, std::size_t first_point,
                        bool want_tangent, ElementResult& out) const {
    constexpr int ND = 2 * NN;
    using RowD = Eigen::Matrix<double, 1, ND>;
    using BMat = Eigen::Matrix<double, 4, ND>;
    const bool axi = axisymmetric();
    const Eigen::Matrix<double, NN, 2> X = *cell.x;
    const Eigen::Matrix<double, ND, 1> ue = u, une = u_n;
    const auto& pts = rule_.points(cell.shape);
    const int np = rule_.size();

    // Geometry of all points first: B-bar needs element-wide quantities.
    std::array<detail::PointGeometry<NN>, max_points> geo;
    for (int i = 0; i < np; ++i)
      if (!detail::evaluate<NN>(pts[static_cast<std::size_t>(i)], X, axi, geo[static_cast<std::size_t>(i)]))
        return Outcome::failure(Status::non_finite, detail::point_message(cell.id, bad_geometry(), i));

    // Volumetric rows b (eps_vol = b u) and their replacements b-bar.
    std::array<RowD, max_points> bbar;
    if (opt_.volumetric == Volumetric::bbar) {
      RowD sum = RowD::Zero();
      double volume = 0.0;
      for (int i = 0; i < np; ++i) {
        const auto& g = geo[static_cast<std::size_t>(i)];
        sum.noalias() += g.dV * detail::volumetric_row<NN>(g, axi);
        volume += g.dV;
      }
      sum /= volume;
      for (int i = 0; i < np; ++i) bbar[static_cast<std::size_t>(i)] = sum;
    } else if (opt_.volumetric == Volumetric::selective) {
      // Weighted L2 projection of the volumetric rows onto the polynomials spanned by the
      // Lagrange basis Phi through the (n-1)x(n-1) Gauss points:
      //   M = Phi^T W Phi, C = M^-1 Phi^T W Bv, B-bar_vol = Phi C   (W = diag(dV)).
      const int nr = static_cast<int>(interp_.cols());
      using Stack = Eigen::Matrix<double, Eigen::Dynamic, ND, 0, max_points, ND>;
      Stack Bv(np, ND);
      PhiT W(nr, np);
      for (int i = 0; i < np; ++i) {
        const auto& g = geo[static_cast<std::size_t>(i)];
        Bv.row(i) = detail::volumetric_row<NN>(g, axi);
        W.col(i) = g.dV * interp_.row(i).transpose();
      }
      const Gram M = W * interp_;
      const Eigen::Matrix<double, Eigen::Dynamic, ND, 0, max_reduced, ND> C = M.llt().solve(W * Bv);
      const Stack proj = interp_ * C;
      for (int i = 0; i < np; ++i) bbar[static_cast<std::size_t>(i)] = proj.row(i);
    }

    double area = 0.0; // in the plane, for the characteristic length of the points
    for (int i = 0; i < np; ++i) {
      const auto& g = geo[static_cast<std::size_t>(i)];
      area += axi ? g.dV / (2.0 * std::numbers::pi * g.x) : g.dV;
    }

    Eigen::Matrix<double, ND, 1> f = Eigen::Matrix<double, ND, 1>::Zero();
    Eigen::Matrix<double, ND, ND, Eigen::RowMajor> K; // row-major: add_sparse_btdb adds rows
    if (want_tangent) K.setZero();
    BMat B;
    Vec6 dstrain, stress;
    Mat6 tangent;

    const bool modified = opt_.volumetric != Volumetric::full;
    for (int i = 0; i < np; ++i) {
      const auto& g = geo[static_cast<std::size_t>(i)];
      detail::strain_matrix<NN>(g, axi, B);
      // B-bar = B + m c with m = (1, 1, 1, 0) and c = (b-bar - b) / 3.
      RowD c;
      if (modified) {
        c = (bbar[static_cast<std::size_t>(i)] - detail::volumetric_row<NN>(g, axi)) / 3.0;
        B.row(0) += c;
        B.row(1) += c;
        B.row(2) += c;
      }
      // The increment comes from the displacement change (stratum/material_point.hpp: the strain
      // is the committed one plus the increment, so a stage that resets displacements keeps it).
      dstrain.setZero();
      dstrain.head<4>().noalias() = B * (ue - une);
      if (Outcome r =
              update_material_point(material, states, first_point + static_cast<std::size_t>(i), dstrain,
                                    continuum::point_context(cell, i, (g.N.transpose() * X).eval(), area),
                                    want_tangent, stress, tangent);
          !r.ok())
        return r;

      f.noalias() += B.transpose() * (g.dV * stress.head<4>());
      if (want_tangent) {
        const Eigen::Matrix4d Dw = g.dV * tangent.topLeftCorner<4, 4>();
        detail::add_sparse_btdb<NN>(g, axi, Dw, K);
        if (modified) {
          // (B + m c)^T D (B + m c) = B^T D B + (B^T D m) c + c^T ((m^T D B) + (m^T D m) c)
          const Eigen::Vector4d Dm = Dw.leftCols<3>().rowwise().sum();
          const Eigen::RowVector4d mD = Dw.topRows<3>().colwise().sum();
          const double mDm = Dm.head<3>().sum();
          const auto a = detail::sparse_bt_times<NN>(g, axi, Dm);
          const auto b = detail::sparse_bt_times<NN>(g, axi, mD.transpose());
          K.noalias() += a * c;
          K.noalias() += c.transpose() * (b.transpose() + mDm * c);
        }
      }
    }
    return continuum::deliver(out, f, K, want_tangent);
  }

  using Phi = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, max_points, max_reduced>;
  using PhiT = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, max_reduced, max_points>;
  using Gram = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, max_reduced, max_reduced>;

  Options opt_;
  RuleTable rule_; ///< the n x n rule of all points
  /// Values at the rule's points of the Lagrange basis through the (n-1) x (n-1) Gauss
  /// points (selective variant; a single column of ones otherwise).
  Phi interp_;
};

} // namespace stratum::quad
