// Mixed displacement - pore pressure (u-p) elements of a saturated porous medium (Biot's
// consolidation with incompressible grains and a compressible pore fluid), Taylor-Hood pairs:
// the 8-node quadrilateral with bilinear pressure on its corners (quad8p4) and the 6-node
// triangle with linear pressure on its corners (tri6p3), plane strain or axisymmetric.
// Header-only so that the tests run the code of the plugin; biot.cpp only adds the factories.
// Equations, sign conventions and the choice of the pairs: README.md in this folder.
//
// The pressure unknown p is the excess pore pressure (compression positive, kPa) over the steady
// hydrostatic state; the material's stress is the effective stress (tension positive), and the
// total stress carried by the cell is sigma' - p m, m = (1, 1, 1, 0).
#pragma once

#include "quad/quad_math.hpp"
#include "tri/tri_element.hpp"

#include "common/continuum_element.hpp"

#include "stratum/element.hpp"
#include "stratum/error.hpp"
#include "stratum/material_point.hpp"

#include <Eigen/Core>

#include <array>
#include <numbers>
#include <string>
#include <vector>

namespace stratum::biot {

/// The hydraulic parameters of a domain (framework units: kN, m, kPa, s).
struct Hydraulics {
  double kx = 0.0;                   ///< permeability along x (r), m/s
  double ky = 0.0;                   ///< permeability along y (z), m/s
  double porosity = 0.3;             ///< n, -
  double fluid_bulk_modulus = 2.2e6; ///< K_w, kPa (water about 2.2 GPa)
  double unit_weight_water = 9.81;   ///< gamma_w, kN/m3
  /// Storage per unit volume and unit pressure, n / K_w (1/kPa); 0 for an incompressible fluid.
  [[nodiscard]] double storage() const {
    return fluid_bulk_modulus > 0.0 ? porosity / fluid_bulk_modulus : 0.0;
  }
};

struct Options {
  CellType cell = CellType::quadrilateral; ///< quadrilateral: quad8p4; triangle: tri6p3
  Formulation formulation = Formulation::axisymmetric;
  int integration = 3; ///< quadrilateral: n of the n x n Gauss rule (2..4); triangle: 3 or 6 points
  Hydraulics water;
};

/// The shape functions of both interpolations at one point of the reference cell.
struct RefPoint {
  Eigen::VectorXd Nu;  ///< displacement shape functions (8 or 6 nodes, slot order)
  Eigen::MatrixXd dNu; ///< their derivatives by (xi, eta)
  Eigen::VectorXd Np;  ///< pressure shape functions (the 4 or 3 corners)
  Eigen::MatrixXd dNp;
  double weight = 0.0;
};

/// The u-p element kind; immutable after construction (safe to share between threads).
class BiotElement final : public Element {
public:
  explicit BiotElement(Options o) : opt_(validated(o)) {
    if (opt_.cell == CellType::quadrilateral) {
      const quad::RuleTable rule(opt_.integration);
      for (const quad::TablePoint& t : rule.points(quad::all_bits)) {
        quad::NodeVec N4;
        quad::NodeGrad dN4;
        quad::shape_functions(quad::corner_bits, t.xi, t.eta, N4, dN4);
        table_.push_back({t.N, t.dN, N4.head<4>(), dN4.topRows<4>(), t.weight});
      }
    } else {
      for (const tri::RulePoint& p : tri::triangle_rule(opt_.integration)) {
        RefPoint r;
        r.weight = p.weight;
        tri::shape_functions(6, p.xi, p.eta, r.Nu, r.dNu);
        tri::shape_functions(3, p.xi, p.eta, r.Np, r.dNp);
        table_.push_back(std::move(r));
      }
    }
  }

  [[nodiscard]] const Options& options() const { return opt_; }
  [[nodiscard]] bool axisymmetric() const { return opt_.formulation == Formulation::axisymmetric; }
  [[nodiscard]] std::string name() const {
    return opt_.cell == CellType::quadrilateral ? "quad8p4" : "tri6p3";
  }
  [[nodiscard]] unsigned required_shape() const {
    return opt_.cell == CellType::quadrilateral ? quad::all_bits : tri::tri6_shape;
  }
  [[nodiscard]] int displacement_nodes() const { return opt_.cell == CellType::quadrilateral ? 8 : 6; }
  [[nodiscard]] int pressure_nodes() const { return opt_.cell == CellType::quadrilateral ? 4 : 3; }

  [[nodiscard]] bool accepts(CellType type) const override { return type == opt_.cell; }

  /// ux, uy at every node; p at the corners (the first 4 or 3 present nodes in slot order).
  [[nodiscard]] NodeFields node_fields(CellType /*type*/, unsigned /*shape*/) const override {
    NodeFields f;
    f.fields = {{"ux", "m", "kN"}, {"uy", "m", "kN"}, {"p", "kPa", "m3"}};
    for (int i = 0; i < displacement_nodes(); ++i)
      f.carried.push_back(i < pressure_nodes() ? 0b111u : 0b011u);
    return f;
  }

  [[nodiscard]] int num_points(unsigned /*shape*/) const override { return static_cast<int>(table_.size()); }

  void check_shape(unsigned shape) const override {
    if (shape == required_shape()) return;
    throw Error(name() + " element: the cell is " + tri::describe_shape(shape) + "; the element needs " +
                (opt_.cell == CellType::quadrilateral
                     ? "an 8-node quadrilateral (nodes_per_cell = 8): Taylor-Hood pairs quadratic "
                       "displacements with linear pressures"
                     : "a 6-node triangle: Taylor-Hood pairs quadratic displacements with linear pressures"));
  }

  /// Local index of displacement component c of node i, and of the pressure of corner i.
  [[nodiscard]] int u_index(int i, int c) const {
    return i < pressure_nodes() ? 3 * i + c : 3 * pressure_nodes() + 2 * (i - pressure_nodes()) + c;
  }
  [[nodiscard]] int p_index(int i) const { return 3 * i + 2; }
  [[nodiscard]] int local_size() const { return 2 * displacement_nodes() + pressure_nodes(); }

  [[nodiscard]] Outcome compute(const ElementData& cell, const Eigen::VectorXd& u, const Eigen::VectorXd& u_n,
                                const Constitutive& law, StateStore& states, std::size_t first_point,
                                bool want_tangent, ElementResult& out) const override {
    check_cell(cell);
    const int nu = displacement_nodes(), np = pressure_nodes(), nl = local_size();
    if (u.size() != nl || u_n.size() != nl)
      throw Error("element " + std::to_string(cell.id) + ": " + std::to_string(u.size()) +
                  " unknowns for a " + name() + " cell, which has " + std::to_string(nl));
    if (law.material == nullptr) return continuum::no_material(cell, name());
    const bool axi = axisymmetric();
    // A static stage takes no time: nothing flows (undrained). A consolidation stage's step does.
    const double dt = cell.clock.transient ? cell.clock.dtime : 0.0;
    const double S = opt_.water.storage();
    const double cx = opt_.water.kx / opt_.water.unit_weight_water;
    const double cy = opt_.water.ky / opt_.water.unit_weight_water;

    Eigen::VectorXd du(2 * nu), p(np), dp(np);
    for (int i = 0; i < nu; ++i)
      for (int c = 0; c < 2; ++c) du(2 * i + c) = u(u_index(i, c)) - u_n(u_index(i, c));
    for (int i = 0; i < np; ++i) p(i) = u(p_index(i)), dp(i) = p(i) - u_n(p_index(i));

    const Eigen::MatrixXd& X = *cell.x;
    double area = 0.0;
    std::vector<Geometry> geo(table_.size());
    for (std::size_t q = 0; q < table_.size(); ++q) {
      if (!evaluate(table_[q], X, geo[q]))
        return Outcome::failure(Status::non_finite, "element " + std::to_string(cell.id) + ": " +
                                                        bad_geometry() + " at integration point " +
                                                        std::to_string(q));
      area += axi ? geo[q].dV / (2.0 * std::numbers::pi * geo[q].x) : geo[q].dV;
    }

    Eigen::VectorXd fu = Eigen::VectorXd::Zero(2 * nu), fp = Eigen::VectorXd::Zero(np);
    Eigen::MatrixXd Kuu, Kup, Kpp;
    if (want_tangent) {
      Kuu.setZero(2 * nu, 2 * nu);
      Kup.setZero(2 * nu, np);
      Kpp.setZero(np, np);
    }
    Eigen::MatrixXd B(4, 2 * nu);
    Vec6 dstrain, stress;
    Mat6 tangent;
    for (std::size_t q = 0; q < table_.size(); ++q) {
      const Geometry& g = geo[q];
      strain_matrix(g, axi, B);
      const Eigen::RowVectorXd mB = B.topRows<3>().colwise().sum(); // volumetric strain row
      dstrain.setZero();
      dstrain.head<4>() = B * du;
      const int point = static_cast<int>(q);
      const Eigen::VectorXd xq = X.transpose() * g.Nu;
      if (Outcome r = update_material_point(*law.material, states, first_point + q, dstrain,
                                            continuum::point_context(cell, point, xq, area), want_tangent,
                                            stress, tangent);
          !r.ok())
        return r;
      const double pq = g.Np.dot(p);
      Eigen::Vector4d total = stress.head<4>();
      total.head<3>().array() -= pq;
      fu.noalias() += B.transpose() * (g.dV * total);
      // Continuity over the step, as a volume (m3) per pressure node, with the sign that makes
      // the tangent symmetric: -(N_p (m^T B du + S dp) + dt grad N_p . (k / gamma_w) grad p) dV.
      const Eigen::Vector2d grad_p = g.dNp.transpose() * p;
      const Eigen::Vector2d flux(cx * grad_p(0), cy * grad_p(1)); // minus the Darcy velocity
      fp.noalias() -= g.dV * (g.Np * (mB.dot(du) + S * g.Np.dot(dp)) + dt * (g.dNp * flux));
      if (want_tangent) {
        Kuu.noalias() += B.transpose() * (g.dV * tangent.topLeftCorner<4, 4>()) * B;
        Kup.noalias() -= g.dV * mB.transpose() * g.Np.transpose();
        Eigen::MatrixXd kg = g.dNp;
        kg.col(0) *= cx;
        kg.col(1) *= cy;
        Kpp.noalias() -= g.dV * (S * g.Np * g.Np.transpose() + dt * kg * g.dNp.transpose());
      }
    }
    out.force.resize(nl);
    for (int i = 0; i < nu; ++i)
      for (int c = 0; c < 2; ++c) out.force(u_index(i, c)) = fu(2 * i + c);
    for (int i = 0; i < np; ++i) out.force(p_index(i)) = fp(i);
    if (want_tangent) {
      out.stiffness.resize(nl, nl);
      for (int i = 0; i < nu; ++i)
        for (int c = 0; c < 2; ++c) {
          const int r = u_index(i, c);
          for (int j = 0; j < nu; ++j)
            for (int d = 0; d < 2; ++d) out.stiffness(r, u_index(j, d)) = Kuu(2 * i + c, 2 * j + d);
          for (int j = 0; j < np; ++j) {
            out.stiffness(r, p_index(j)) = Kup(2 * i + c, j);
            out.stiffness(p_index(j), r) = Kup(2 * i + c, j);
          }
        }
      for (int i = 0; i < np; ++i)
        for (int j = 0; j < np; ++j) out.stiffness(p_index(i), p_index(j)) = Kpp(i, j);
    }
    return Outcome::success();
  }

  /// Consistent nodal forces of a body force b (kN/m3) on the displacements; zero on p.
  void body_force(const ElementData& cell, const Eigen::VectorXd& b, Eigen::VectorXd& f) const override {
    check_cell(cell);
    f.setZero(local_size());
    Geometry g;
    for (std::size_t q = 0; q < table_.size(); ++q) {
      if (!evaluate(table_[q], *cell.x, g))
        throw Error("element " + std::to_string(cell.id) + ": " + bad_geometry() + " at integration point " +
                    std::to_string(q));
      for (int i = 0; i < displacement_nodes(); ++i)
        for (int c = 0; c < 2; ++c) f(u_index(i, c)) += g.Nu(i) * g.dV * b(c);
    }
  }

  void point_coordinates(const ElementData& cell, Eigen::MatrixXd& xp) const override {
    check_cell(cell);
    xp.resize(static_cast<Eigen::Index>(table_.size()), 2);
    for (std::size_t q = 0; q < table_.size(); ++q)
      xp.row(static_cast<Eigen::Index>(q)) = table_[q].Nu.transpose() * *cell.x;
  }

  /// The excess pore pressure (field 2, "p") at the points: N_p . p of the corners.
  [[nodiscard]] bool point_field(const ElementData& cell, const Eigen::VectorXd& u, int field,
                                 Eigen::VectorXd& values) const override {
    check_cell(cell);
    if (field != 2 || u.size() != local_size()) return false;
    values.resize(static_cast<Eigen::Index>(table_.size()));
    for (std::size_t q = 0; q < table_.size(); ++q) {
      double p = 0.0;
      for (int i = 0; i < pressure_nodes(); ++i) p += table_[q].Np(i) * u(p_index(i));
      values(static_cast<Eigen::Index>(q)) = p;
    }
    return true;
  }

  void point_weights(const ElementData& cell, Eigen::VectorXd& w) const override {
    check_cell(cell);
    w.resize(static_cast<Eigen::Index>(table_.size()));
    Geometry g;
    for (std::size_t q = 0; q < table_.size(); ++q)
      w(static_cast<Eigen::Index>(q)) = evaluate(table_[q], *cell.x, g) ? g.dV : 0.0;
    continuum::normalize_weights(w);
  }

private:
  struct Geometry {
    Eigen::VectorXd Nu, Np;
    Eigen::MatrixXd dNu, dNp; ///< derivatives by x (r) and y (z)
    double x = 0.0, dV = 0.0;
  };

  static Options validated(Options o) {
    if (o.cell != CellType::quadrilateral && o.cell != CellType::triangle)
      throw Error("u-p element: a quadrilateral or a triangle");
    if (o.cell == CellType::quadrilateral && (o.integration < 2 || o.integration > quad::max_rule))
      throw Error("quad8p4 element: integration must be 2, 3 or 4 (got " + std::to_string(o.integration) +
                  ")");
    if (o.cell == CellType::triangle && o.integration != 3 && o.integration != 6)
      throw Error("tri6p3 element: integration must be 3 or 6 points (got " + std::to_string(o.integration) +
                  ")");
    return o;
  }

  void check_cell(const ElementData& cell) const {
    check_shape(cell.shape);
    if (cell.x == nullptr || cell.x->rows() != displacement_nodes() || cell.x->cols() != 2)
      throw Error("element " + std::to_string(cell.id) + ": a " + name() + " cell needs " +
                  std::to_string(displacement_nodes()) + " nodes with 2 coordinates");
  }

  [[nodiscard]] std::string bad_geometry() const {
    return axisymmetric() ? "non-positive Jacobian determinant or radius"
                          : "non-positive Jacobian determinant";
  }

  /// The point's shape functions by x and y, its radius and its volume; false where the map
  /// folds (or the radius is not positive in axisymmetry).
  bool evaluate(const RefPoint& r, const Eigen::MatrixXd& X, Geometry& g) const {
    const Eigen::Matrix2d J = r.dNu.transpose() * X; // J(a, b) = d x_b / d xi_a
    const double det = J.determinant();
    g.Nu = r.Nu;
    g.Np = r.Np;
    g.x = r.Nu.dot(X.col(0));
    g.dV = r.weight * det * (axisymmetric() ? 2.0 * std::numbers::pi * g.x : 1.0);
    if (!(det > 0.0) || (axisymmetric() && !(g.x > 0.0))) return false;
    const Eigen::Matrix2d Jinv_t = J.inverse().transpose();
    g.dNu = r.dNu * Jinv_t;
    // The pressure interpolation is subparametric: its corners span the same (straight-sided or
    // curved) map as the displacements, so its gradient uses the displacement map's Jacobian.
    g.dNp = r.dNp * Jinv_t;
    return true;
  }

  /// Rows xx, yy, zz (hoop in axisymmetry), xy of the strain of the displacement nodes.
  void strain_matrix(const Geometry& g, bool axi, Eigen::MatrixXd& B) const {
    B.setZero();
    for (int k = 0; k < displacement_nodes(); ++k) {
      const double dx = g.dNu(k, 0), dy = g.dNu(k, 1);
      B(0, 2 * k) = dx;
      B(1, 2 * k + 1) = dy;
      if (axi) B(2, 2 * k) = g.Nu(k) / g.x;
      B(3, 2 * k) = dy;
      B(3, 2 * k + 1) = dx;
    }
  }

  Options opt_;
  std::vector<RefPoint> table_;
};

} // namespace stratum::biot
