// Interface elements: the two-node contact element (contact2), the zero-thickness line
// interface (interface_line) and the thin-layer element (thin_layer). Header-only so that the
// tests run exactly the plugin's code; interface_elements.cpp only adds the factories.
// Equations and conventions: README.md in this folder; cell layouts: CellType in stratum/cell_type.hpp.
//
// Interface points store (in the framework's StateStore slot) the traction (shear, normal) in
// stress[0..1] and the jump (slip, opening) in strain[0..1]; the ContactLaw's history follows.
#pragma once

#include "quad/quad_element.hpp"

#include "stratum/contact_law.hpp"
#include "stratum/element.hpp"
#include "stratum/error.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <numbers>
#include <string>

namespace stratum::interfaces {

/// Calls the contact law at one point with the jump increment djump (local t, n axes) of the
/// step. The jump at t_n is the committed one (strain[0..1]), not one recomputed from the nodal
/// displacements: an interface placed into a deformed configuration (a pile cast in a bored hole
/// whose wall has moved) or kept across a reset of the displacements starts from the jump its
/// placement gave it. Writes the trial slot.
inline Outcome contact_point(const ContactLaw& law, StateStore& states, std::size_t p, const Vec2& djump,
                             int element, int point, Vec2& traction, Mat2& tangent) {
  const auto committed = states.committed(p);
  auto trial = states.trial(p);
  const Vec2 traction_n(committed.stress()[0], committed.stress()[1]);
  const Vec2 jump_n(committed.strain()[0], committed.strain()[1]);
  const Vec2 jump = jump_n + djump;
  ContactInput in{traction_n, jump_n, committed.history(), djump, PointContext{element, point}};
  ContactOutput out{traction, trial.history(), tangent};
  Outcome o = law.update(in, out);
  if (!o.ok()) return o;
  if (!traction.allFinite() || !tangent.allFinite())
    return Outcome::failure(Status::non_finite, "element " + std::to_string(element) + " point " +
                                                    std::to_string(point) + ": contact law returned NaN");
  trial.stress().setZero();
  trial.strain().setZero();
  trial.stress()[0] = traction[0], trial.stress()[1] = traction[1];
  trial.strain()[0] = jump[0], trial.strain()[1] = jump[1];
  return {};
}

/// Rotation to local axes: rows t and n = (t_y, -t_x).
inline Mat2 local_axes(const Vec2& t) {
  Mat2 R;
  R << t.x(), t.y(), t.y(), -t.x();
  return R;
}

inline Outcome missing_law(int id, const char* what) {
  return Outcome::failure(Status::material_failure,
                          "element " + std::to_string(id) + ": the " + what + " element needs a ContactLaw");
}

// ------------------------------------------------------------------------------- contact2

/// Two-node contact element (thesis (3.51)): cell slots 0 = node i (body 1), 1 = node j
/// (body 2), 2/3 = the body-1 neighbours before/after i along the interface (geometry only).
class Contact2 final : public Element {
public:
  explicit Contact2(Formulation f) : form_(f) {}

  [[nodiscard]] ElementCells cells() const override { return ElementCells::node_pairs; }

  [[nodiscard]] int num_points(unsigned /*shape*/) const override { return 1; }
  void check_shape(unsigned shape) const override {
    if (shape != 0x0Fu && shape != 0x1Fu && shape != 0x2Fu)
      throw Error("contact2 needs a node-pair cell (slots 0-3: node, partner, previous, next; 4 or 5 "
                  "marking a midside or corner node of 3-node edges); see "
                  "[[interfaces]] element = \"contact2\"");
  }
  void check_geometry(const ElementData& cell) const override {
    const Geometry g = geometry(cell);
    // A corner node of 3-node edges on the axis has a consistent weight of exactly zero.
    const bool axis_corner =
        (cell.shape & 0x20u) != 0 && form_ == Formulation::axisymmetric &&
        std::abs((*cell.x)(0, 0)) <= 1e-12 * (1.0 + (*cell.x).col(1).cwiseAbs().maxCoeff());
    if (!(g.area > 0.0) && !(axis_corner && g.area == 0.0 && g.R.allFinite()))
      throw Error("contact2 cell " + std::to_string(cell.id) + " has no tributary length (an isolated node)");
    if (((*cell.x).row(0) - (*cell.x).row(1)).norm() > 1e-9 * (1.0 + (*cell.x).row(0).norm()))
      throw Error("contact2 cell " + std::to_string(cell.id) + ": the two nodes are not coincident");
  }

  struct Geometry {
    Mat2 R;            ///< rows t, n
    double area = 0.0; ///< tributary length (x 2 pi r in axisymmetry)
  };
  [[nodiscard]] Geometry geometry(const ElementData& cell) const {
    const auto& X = *cell.x;
    const Vec2 xi = X.row(0).transpose(), xp = X.row(2).transpose(), xn = X.row(3).transpose();
    Geometry g;
    const Vec2 d = xn - xp;
    const double len = d.norm();
    if (!(len > 0.0)) return g;
    g.R = local_axes(d / len);
    // Tributary area: the integral of node i's shape function over the adjacent edge parts, with
    // 2 pi r in axisymmetry. 2-node edges (shape 0x0F): the linear function over half of each
    // neighbouring segment, l/2 or l pi (2 r_i + r_nb)/3. 3-node edges: a midside node (slot 4
    // present) gets the integral of 1 - s^2 over its edge from corner to corner, 2L/3 or
    // 2 pi L (r_a + r_b)/3; a corner (slot 5 present) that of s(s - 1)/2 over each edge it ends,
    // L/6 or pi L r_i/3 with L twice the distance to the midside neighbour (straight edges).
    const bool midside = (cell.shape & 0x10u) != 0, corner = (cell.shape & 0x20u) != 0;
    const bool axi = form_ == Formulation::axisymmetric;
    if (midside) {
      const double L = (xn - xp).norm();
      g.area = axi ? 2.0 * std::numbers::pi * L * (xp.x() + xn.x()) / 3.0 : 2.0 * L / 3.0;
      return g;
    }
    for (const Vec2& nb : {xp, xn}) {
      const double l = (nb - xi).norm();
      if (corner)
        g.area += axi ? std::numbers::pi * (2.0 * l) * xi.x() / 3.0 : 2.0 * l / 6.0;
      else
        g.area += axi ? l * std::numbers::pi * (2.0 * xi.x() + nb.x()) / 3.0 : 0.5 * l;
    }
    return g;
  }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    if (!law.contact) return missing_law(cell.id, "contact2");
    const Geometry g = geometry(cell);
    const Vec2 djump = g.R * ((u.segment<2>(2) - u_n.segment<2>(2)) - (u.segment<2>(0) - u_n.segment<2>(0)));
    Vec2 tr;
    Mat2 D;
    if (Outcome o = contact_point(*law.contact, states, first_point, djump, cell.id, 0, tr, D); !o.ok())
      return o;
    const auto nd = 2 * cell.x->rows();
    out.force.setZero(nd);
    const Vec2 f = g.area * (g.R.transpose() * tr);
    out.force.segment<2>(0) = -f;
    out.force.segment<2>(2) = f;
    if (want_tangent) {
      out.stiffness.setZero(nd, nd);
      const Mat2 k = g.area * (g.R.transpose() * D * g.R);
      out.stiffness.block<2, 2>(0, 0) = k;
      out.stiffness.block<2, 2>(2, 2) = k;
      out.stiffness.block<2, 2>(0, 2) = -k;
      out.stiffness.block<2, 2>(2, 0) = -k;
    }
    return {};
  }

  void body_force(const ElementData& cell, const Eigen::VectorXd& /*b*/, Eigen::VectorXd& f) const override {
    f.setZero(2 * cell.x->rows());
  }
  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    xp = cell.x->topRows(1);
  }
  void point_weights(const ElementData& /*cell*/, Eigen::VectorXd& w) const override { w.setOnes(1); }

private:
  Formulation form_;
};

// -------------------------------------------------------------------------- interface_line

enum class LineRule { gauss, newton_cotes };

/// Zero-thickness line interface: slots 0, 1 (and 4) on body 1 from a to b, slots 3, 2 (and 6)
/// their partners on body 2. 2 + 2 nodes: linear, 3 + 3 nodes: quadratic interpolation of the jump.
class InterfaceLine final : public Element {
public:
  InterfaceLine(Formulation f, LineRule rule) : form_(f), rule_(rule) {}

  [[nodiscard]] ElementCells cells() const override { return ElementCells::interface_lines; }

  [[nodiscard]] int num_points(unsigned shape) const override { return shape == 0x5Fu ? 3 : 2; }
  void check_shape(unsigned shape) const override {
    if (shape != 0x0Fu && shape != 0x5Fu)
      throw Error("interface_line needs a line-interface cell of 2 + 2 nodes (slots 0-3) or 3 + 3 nodes "
                  "(slots 0-3, 4, 6)");
  }
  void check_geometry(const ElementData& cell) const override {
    const auto& X = *cell.x;
    const bool quadratic = X.rows() == 6;
    const double len = (X.row(1) - X.row(0)).norm();
    if (!(len > 0.0)) throw Error("interface_line cell " + std::to_string(cell.id) + " has zero length");
    const auto far = [&](int a, int b) { return (X.row(a) - X.row(b)).norm() > 1e-9 * len; };
    if (far(0, 3) || far(1, 2) || (quadratic && far(4, 5)))
      throw Error("interface_line cell " + std::to_string(cell.id) +
                  ": the nodes of the two sides are not coincident (zero thickness expected)");
  }

  /// Points (xi) and weights on [-1, 1] of the rule for n nodes per side.
  void rule(int n, std::array<double, 3>& xi, std::array<double, 3>& w) const {
    if (rule_ == LineRule::gauss) {
      if (n == 2) {
        const double g = 1.0 / std::sqrt(3.0);
        xi = {-g, g, 0.0}, w = {1.0, 1.0, 0.0};
      } else {
        const double g = std::sqrt(0.6);
        xi = {-g, 0.0, g}, w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
      }
    } else if (n == 2) {
      xi = {-1.0, 1.0, 0.0}, w = {1.0, 1.0, 0.0}; // trapezoid: the points sit on the nodes
    } else {
      xi = {-1.0, 0.0, 1.0}, w = {1.0 / 3.0, 4.0 / 3.0, 1.0 / 3.0}; // Simpson
    }
  }

  static void shape_functions(int n, double s, std::array<double, 3>& N, std::array<double, 3>& dN) {
    if (n == 2) {
      N = {0.5 * (1 - s), 0.5 * (1 + s), 0.0};
      dN = {-0.5, 0.5, 0.0};
    } else {
      N = {0.5 * s * (s - 1), 0.5 * s * (s + 1), 1 - s * s};
      dN = {s - 0.5, s + 0.5, -2 * s};
    }
  }

  [[nodiscard]] double radial(double r) const {
    return form_ == Formulation::axisymmetric ? 2.0 * std::numbers::pi * r : 1.0;
  }

  /// Newton-Cotes weight of node k: the integral of N_k over the edge (with 2 pi r in axisymmetry),
  /// i.e. the row sum of the consistent matrix. In plane strain this is the trapezoid / Simpson
  /// rule; in axisymmetry it keeps nodal integration exact for a uniform traction.
  [[nodiscard]] double nodal_weight(const Eigen::MatrixXd& X, int n, int k) const {
    const std::array<int, 3> side1{0, 1, 4};
    const double g = std::sqrt(0.6);
    const std::array<double, 3> xg{-g, 0.0, g}, wg{5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    std::array<double, 3> N{}, dN{};
    double sum = 0.0;
    for (int q = 0; q < 3; ++q) {
      shape_functions(n, xg[q], N, dN);
      Vec2 x = Vec2::Zero(), dx = Vec2::Zero();
      for (int a = 0; a < n; ++a) {
        x += N[a] * X.row(side1[a]).transpose();
        dx += dN[a] * X.row(side1[a]).transpose();
      }
      sum += wg[q] * N[k] * dx.norm() * radial(x.x());
    }
    return sum;
  }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    if (!law.contact) return missing_law(cell.id, "interface_line");
    const auto& X = *cell.x;
    const int n = X.rows() == 6 ? 3 : 2;
    // Rows of body-1 nodes along a -> b and of their partners on body 2.
    const std::array<int, 3> side1{0, 1, 4}, side2{3, 2, 5};
    const std::array<int, 3> node_of_point{0, 2, 1}; // Simpson points -1, 0, 1 sit on a, mid, b
    const auto ndof = static_cast<Eigen::Index>(2 * X.rows());
    std::array<double, 3> xi{}, w{}, N{}, dN{};
    rule(n, xi, w);
    out.force.setZero(ndof);
    if (want_tangent) out.stiffness.setZero(ndof, ndof);
    Eigen::Matrix<double, 2, Eigen::Dynamic> B(2, ndof);
    const Eigen::VectorXd du = u - u_n;
    for (int q = 0; q < n; ++q) {
      shape_functions(n, xi[q], N, dN);
      Vec2 x = Vec2::Zero(), dx = Vec2::Zero();
      for (int k = 0; k < n; ++k) {
        x += N[k] * X.row(side1[k]).transpose();
        dx += dN[k] * X.row(side1[k]).transpose();
      }
      const double J = dx.norm();
      if (!(J > 0.0))
        return Outcome::failure(Status::material_failure,
                                "interface_line cell " + std::to_string(cell.id) + " has zero length");
      const Mat2 R = local_axes(dx / J);
      B.setZero();
      for (int k = 0; k < n; ++k) {
        B.middleCols<2>(2 * side1[k]) = -N[k] * R;
        B.middleCols<2>(2 * side2[k]) = N[k] * R;
      }
      const Vec2 djump = B * du;
      Vec2 tr;
      Mat2 D;
      if (Outcome o = contact_point(*law.contact, states, first_point + static_cast<std::size_t>(q), djump,
                                    cell.id, q, tr, D);
          !o.ok())
        return o;
      const double dA = rule_ == LineRule::gauss ? w[q] * J * radial(x.x())
                                                 : nodal_weight(X, n, n == 3 ? node_of_point[q] : q);
      out.force += dA * (B.transpose() * tr);
      if (want_tangent) out.stiffness += dA * (B.transpose() * D * B);
    }
    return {};
  }

  void body_force(const ElementData& cell, const Eigen::VectorXd& /*b*/, Eigen::VectorXd& f) const override {
    f.setZero(2 * cell.x->rows());
  }
  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    const auto& X = *cell.x;
    const int n = X.rows() == 6 ? 3 : 2;
    const std::array<int, 3> side1{0, 1, 4};
    std::array<double, 3> xi{}, w{}, N{}, dN{};
    rule(n, xi, w);
    xp.setZero(n, 2);
    for (int q = 0; q < n; ++q) {
      shape_functions(n, xi[q], N, dN);
      for (int k = 0; k < n; ++k) xp.row(q) += N[k] * X.row(side1[k]);
    }
  }
  void point_weights(const ElementData& cell, Eigen::VectorXd& wts) const override {
    const int n = cell.x->rows() == 6 ? 3 : 2;
    std::array<double, 3> xi{}, w{};
    rule(n, xi, w);
    wts.resize(n);
    for (int q = 0; q < n; ++q) wts[q] = 0.5 * w[q];
  }

private:
  Formulation form_;
  LineRule rule_;
};

// ------------------------------------------------------------------------------ thin_layer

/// Thin-layer element (Desai & Zaman 1984): an ordinary quadrilateral with any Material whose
/// thickness t (the shorter of the two mid-lines) over its length b (the longer) must lie in
/// [min_ratio, max_ratio], by default the thesis' 0.01-0.1.
class ThinLayer final : public Element {
public:
  ThinLayer(quad::Options o, double min_ratio, double max_ratio)
      : quad_(o), min_(min_ratio), max_(max_ratio) {}

  /// t / b of a cell from its corners.
  static double thickness_ratio(const Eigen::MatrixXd& X) {
    const Vec2 m01 = 0.5 * (X.row(0) + X.row(1)).transpose(), m23 = 0.5 * (X.row(2) + X.row(3)).transpose();
    const Vec2 m12 = 0.5 * (X.row(1) + X.row(2)).transpose(), m30 = 0.5 * (X.row(3) + X.row(0)).transpose();
    const double a = (m23 - m01).norm(), b = (m30 - m12).norm();
    return std::min(a, b) / std::max(a, b);
  }

  [[nodiscard]] int num_points(unsigned shape) const override { return quad_.num_points(shape); }
  void check_shape(unsigned shape) const override { quad_.check_shape(shape); }
  void check_geometry(const ElementData& cell) const override {
    const double r = thickness_ratio(*cell.x);
    if (r < min_ * (1 - 1e-9) || r > max_ * (1 + 1e-9)) {
      char buf[200];
      std::snprintf(
          buf, sizeof buf,
          "thin_layer cell %d has thickness ratio t/b = %.4g; allowed: %.4g to %.4g (Desai & Zaman: "
          "thinner layers are ill-conditioned, thicker ones are not an interface)",
          cell.id, r, min_, max_);
      throw Error(buf);
    }
  }
  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    return quad_.compute(cell, u, u_n, law, states, first_point, want_tangent, out);
  }
  void body_force(const ElementData& cell, const Eigen::VectorXd& b, Eigen::VectorXd& f) const override {
    quad_.body_force(cell, b, f);
  }
  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    quad_.point_coordinates(cell, xp);
  }
  void point_weights(const ElementData& cell, Eigen::VectorXd& w) const override {
    quad_.point_weights(cell, w);
  }

private:
  quad::QuadElement quad_;
  double min_, max_;
};

} // namespace stratum::interfaces
