// The variable-node (4 to 8 nodes) isoparametric quadrilateral continuum element,
// axisymmetric or plane strain, with optional B-bar treatment of the volumetric strain.
// Header-only so that the tests can exercise exactly the code the plugin runs; quad.cpp
// only adds the factory. Equations and conventions: README.md in this folder.
//
// Axisymmetric forces and stiffnesses are for the full circle (integrated with
// 2 pi r detJ), consistent with the framework's pressure loads.
#pragma once

#include "quad_math.hpp"

#include "stratum/element.hpp"
#include "stratum/error.hpp"

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
  selective, ///< B-bar form of selective reduced integration: volumetric strain from the (n-1)x(n-1) rule
};

/// The parameters of the element kind.
struct Options {
  Formulation formulation = Formulation::axisymmetric;
  int integration = 3; ///< n of the n x n Gauss rule, 2..4
  Volumetric volumetric = Volumetric::full;
};

namespace detail {

/// Calls f(std::integral_constant<int, n>{}) for n = 4..8 (the node count of a valid mask).
template <class F> decltype(auto) with_node_count(int n, F&& f) {
  switch (n) {
  case 4: return f(std::integral_constant<int, 4>{});
  case 5: return f(std::integral_constant<int, 5>{});
  case 6: return f(std::integral_constant<int, 6>{});
  case 7: return f(std::integral_constant<int, 7>{});
  default: return f(std::integral_constant<int, 8>{});
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
bool evaluate(const TablePoint& p, const Eigen::Matrix<double, NN, 2>& X, bool axisymmetric, PointGeometry<NN>& g) {
  g.N = p.N.template head<NN>();
  const auto dN = p.dN.template topRows<NN>();
  const Mat2 J = dN.transpose() * X; // J(a, b) = d x_b / d xi_a
  g.detJ = J.determinant();
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

inline std::string point_message(int element, const char* what, int point) {
  return "element " + std::to_string(element) + ": " + what + " at integration point " + std::to_string(point);
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
        reduced_(opt_.volumetric == Volumetric::selective ? opt_.integration - 1 : 1),
        interp_(lagrange_interpolation(opt_.integration, reduced_.order())) {}

  [[nodiscard]] const Options& options() const { return opt_; }
  [[nodiscard]] bool axisymmetric() const { return opt_.formulation == Formulation::axisymmetric; }

  [[nodiscard]] int num_points(unsigned /*shape*/) const override { return rule_.size(); }

  void check_shape(unsigned shape) const override { require_valid_shape(shape); }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    const int n = check_cell(cell);
    if (u.size() != 2 * n || u_n.size() != 2 * n)
      throw Error("element " + std::to_string(cell.id) + ": displacement vector of size " +
                  std::to_string(u.size()) + " for a " + std::to_string(n) + "-node quadrilateral");
    if (law.material == nullptr)
      return Outcome::failure(Status::material_failure, "element " + std::to_string(cell.id) +
                                                            ": the quad element needs a Material (none was given)");
    return detail::with_node_count(n, [&](auto nn) {
      return compute_fixed<decltype(nn)::value>(cell, u, u_n, *law.material, states, first_point, want_tangent, out);
    });
  }

  /// Consistent nodal forces N^T b integrated with the element's rule. Throws
  /// stratum::Error for a cell with a non-positive Jacobian (or radius) at a point.
  void body_force(const ElementData& cell, const Vec2& b, Eigen::VectorXd& f) const override {
    const int n = check_cell(cell);
    f.setZero(2 * n);
    detail::with_node_count(n, [&](auto nn) {
      constexpr int NN = decltype(nn)::value;
      const Eigen::Matrix<double, NN, 2> X = *cell.x;
      const auto& pts = rule_.points(cell.shape);
      detail::PointGeometry<NN> g;
      for (int i = 0; i < rule_.size(); ++i) {
        if (!detail::evaluate<NN>(pts[static_cast<std::size_t>(i)], X, axisymmetric(), g))
          throw Error(detail::point_message(cell.id, bad_geometry(), i));
        for (int k = 0; k < NN; ++k) f.segment<2>(2 * k) += (g.N(k) * g.dV) * b;
      }
    });
  }

  void point_coordinates(const ElementData& cell, Eigen::MatrixX2d& xp) const override {
    const int n = check_cell(cell);
    const auto& pts = rule_.points(cell.shape);
    xp.resize(rule_.size(), 2);
    for (int i = 0; i < rule_.size(); ++i)
      xp.row(i) = pts[static_cast<std::size_t>(i)].N.head(n).transpose() * (*cell.x);
  }

  /// dV_i / sum dV (dV = w detJ, times 2 pi r in axisymmetry). Falls back to equal weights
  /// for a degenerate cell whose volume is not positive.
  void point_weights(const ElementData& cell, Eigen::VectorXd& w) const override {
    const int n = check_cell(cell);
    w.resize(rule_.size());
    detail::with_node_count(n, [&](auto nn) {
      constexpr int NN = decltype(nn)::value;
      const Eigen::Matrix<double, NN, 2> X = *cell.x;
      const auto& pts = rule_.points(cell.shape);
      detail::PointGeometry<NN> g;
      for (int i = 0; i < rule_.size(); ++i) {
        detail::evaluate<NN>(pts[static_cast<std::size_t>(i)], X, axisymmetric(), g);
        w(i) = g.dV;
      }
    });
    const double total = w.sum();
    if (total > 0.0 && w.allFinite())
      w /= total;
    else
      w.setConstant(1.0 / static_cast<double>(rule_.size()));
  }

private:
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
                  " nodes but the coordinate matrix has " + std::to_string(cell.x ? cell.x->rows() : 0) + " rows");
    return n;
  }

  [[nodiscard]] const char* bad_geometry() const {
    return axisymmetric() ? "non-positive Jacobian determinant or radius" : "non-positive Jacobian determinant";
  }

  template <int NN>
  Outcome compute_fixed(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                        const Material& material, StateStore& states, std::size_t first_point, bool want_tangent,
                        ElementResult& out) const {
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
      const auto& rpts = reduced_.points(cell.shape);
      const int nr = reduced_.size();
      std::array<RowD, max_points> bred;
      detail::PointGeometry<NN> g;
      for (int l = 0; l < nr; ++l) {
        if (!detail::evaluate<NN>(rpts[static_cast<std::size_t>(l)], X, axi, g))
          return Outcome::failure(Status::non_finite,
                                  detail::point_message(cell.id, bad_geometry(), l) + " of the reduced rule");
        bred[static_cast<std::size_t>(l)] = detail::volumetric_row<NN>(g, axi);
      }
      for (int i = 0; i < np; ++i) {
        RowD& bi = bbar[static_cast<std::size_t>(i)];
        bi.setZero();
        for (int l = 0; l < nr; ++l) bi.noalias() += interp_(i, l) * bred[static_cast<std::size_t>(l)];
      }
    }

    Eigen::Matrix<double, ND, 1> f = Eigen::Matrix<double, ND, 1>::Zero();
    Eigen::Matrix<double, ND, ND> K;
    if (want_tangent) K.setZero();
    BMat B;
    Eigen::Matrix<double, 4, ND> DB;
    Vec6 strain = Vec6::Zero(), strain_n = Vec6::Zero(), dstrain, stress_n, stress;
    Mat6 tangent;

    for (int i = 0; i < np; ++i) {
      const auto& g = geo[static_cast<std::size_t>(i)];
      detail::strain_matrix<NN>(g, axi, B);
      if (opt_.volumetric != Volumetric::full) {
        const RowD corr = (bbar[static_cast<std::size_t>(i)] - detail::volumetric_row<NN>(g, axi)) / 3.0;
        B.row(0) += corr;
        B.row(1) += corr;
        B.row(2) += corr;
      }
      strain.head<4>().noalias() = B * ue;
      strain_n.head<4>().noalias() = B * une;
      dstrain = strain - strain_n;

      const std::size_t p = first_point + static_cast<std::size_t>(i);
      const auto committed = states.committed(p);
      const auto trial = states.trial(p);
      stress_n = committed.stress();
      const MaterialInput in{stress_n, strain_n, committed.history(), dstrain, PointContext{cell.id, i}};
      MaterialOutput mo{stress, trial.history(), tangent};
      Outcome r = material.update(in, mo);
      if (!r.ok()) return r;
      if (!stress.allFinite() || (want_tangent && !tangent.allFinite()))
        return Outcome::failure(Status::non_finite,
                                detail::point_message(cell.id, "the material returned a non-finite stress or tangent", i));
      trial.strain() = strain;
      trial.stress() = stress;

      f.noalias() += B.transpose() * (g.dV * stress.head<4>());
      if (want_tangent) {
        DB.noalias() = (g.dV * tangent.topLeftCorner<4, 4>()) * B;
        K.noalias() += B.transpose() * DB;
      }
    }
    out.force = f;
    if (want_tangent) out.stiffness = K;
    return Outcome::success();
  }

  Options opt_;
  RuleTable rule_;         ///< the n x n rule of all points
  RuleTable reduced_;      ///< (n-1) x (n-1) rule of the selective variant (1 x 1 otherwise, unused)
  Eigen::MatrixXd interp_; ///< Lagrange interpolation from reduced_ points to rule_ points
};

} // namespace stratum::quad
