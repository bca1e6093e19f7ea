// Shape functions, Gauss rules and precomputed tables of the variable-node
// (4 to 8 nodes) isoparametric quadrilateral. Header-only so that tests can use
// the same code as the plugin. See README.md in this folder for the equations.
//
// Node slots (element.hpp): 0-3 corners counter-clockwise at natural coordinates
// (xi, eta) = (-1,-1), (1,-1), (1,1), (-1,1); slot 4 is the midside node of edge 0-1,
// 5 of edge 1-2, 6 of edge 2-3, 7 of edge 3-0. A shape mask has bits 0-3 set (corners
// are mandatory) and any subset of bits 4-7. Present nodes are numbered in slot order.
#pragma once

#include "stratum/error.hpp"

#include <Eigen/Core>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace stratum::quad {

inline constexpr int max_nodes = 8;
inline constexpr int max_rule = 4;                     ///< largest n of an n x n Gauss rule
inline constexpr int max_points = max_rule * max_rule; ///< largest number of integration points
inline constexpr unsigned corner_bits = 0x0Fu;
inline constexpr unsigned all_bits = 0xFFu;

using NodeVec = Eigen::Matrix<double, max_nodes, 1>;  ///< one value per present node (rest unused)
using NodeGrad = Eigen::Matrix<double, max_nodes, 2>; ///< d/dxi, d/deta per present node

/// Natural coordinates of the eight slots.
inline constexpr std::array<std::array<double, 2>, 8> slot_xi{
    {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}, {0.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}}};

/// The two corner slots of the edge that carries midside slot 4 + e.
inline constexpr std::array<std::array<int, 2>, 4> edge_corners{{{0, 1}, {1, 2}, {2, 3}, {3, 0}}};

/// True when the mask has all four corners and no bit above slot 7.
[[nodiscard]] inline bool valid_shape(unsigned shape) {
  return (shape & corner_bits) == corner_bits && (shape & ~all_bits) == 0u;
}

/// Number of present nodes of a mask.
[[nodiscard]] inline int node_count(unsigned shape) { return std::popcount(shape & all_bits); }

/// The midside part of a mask, 0..15 (bit e set when slot 4 + e is present).
[[nodiscard]] inline unsigned midside_bits(unsigned shape) { return (shape >> 4) & 0x0Fu; }

/// Throws stratum::Error unless the mask is a quadrilateral this family handles.
inline void require_valid_shape(unsigned shape) {
  if (valid_shape(shape)) return;
  if (shape == 0x07u || shape == 0x77u) // a triangle (stratum/mesh.hpp): say which element fits
    throw Error(std::string("quad element: the cell is a ") + (shape == 0x07u ? "3" : "6") +
                "-node triangle; use element = \"" + (shape == 0x07u ? "tri3" : "tri6") + "\" for triangles");
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%x", shape);
  throw Error(std::string("quad element: node mask ") + hex +
              " is not a 4- to 8-node quadrilateral (corner slots 0-3 must all be present, midside slots 4-7 "
              "are optional, there are no other slots)");
}

/// Shape functions and their natural derivatives of the present nodes of `shape` at
/// (xi, eta). Entries 0..node_count-1 of N and rows of dN are filled in slot order; the
/// rest are set to zero. Returns the node count. The mask must be valid.
///
/// Midside slot m (edge e = m - 4) contributes 1/2 (1 - xi^2)(1 -+ eta) or
/// 1/2 (1 -+ xi)(1 - eta^2); each corner starts from the bilinear function and subtracts
/// half of every present midside function of its two edges.
inline int shape_functions(unsigned shape, double xi, double eta, NodeVec& N, NodeGrad& dN) {
  std::array<double, 8> n{};
  std::array<double, 8> dx{};
  std::array<double, 8> de{};
  for (int c = 0; c < 4; ++c) {
    const double xc = slot_xi[c][0], ec = slot_xi[c][1];
    n[c] = 0.25 * (1.0 + xc * xi) * (1.0 + ec * eta);
    dx[c] = 0.25 * xc * (1.0 + ec * eta);
    de[c] = 0.25 * ec * (1.0 + xc * xi);
  }
  for (int e = 0; e < 4; ++e) {
    const int m = 4 + e;
    if ((shape & (1u << m)) == 0u) continue;
    const double xm = slot_xi[m][0], em = slot_xi[m][1];
    if (xm == 0.0) { // edge along xi (eta = em = +-1)
      n[m] = 0.5 * (1.0 - xi * xi) * (1.0 + em * eta);
      dx[m] = -xi * (1.0 + em * eta);
      de[m] = 0.5 * em * (1.0 - xi * xi);
    } else { // edge along eta (xi = xm = +-1)
      n[m] = 0.5 * (1.0 + xm * xi) * (1.0 - eta * eta);
      dx[m] = 0.5 * xm * (1.0 - eta * eta);
      de[m] = -eta * (1.0 + xm * xi);
    }
    for (int c : edge_corners[e]) {
      n[c] -= 0.5 * n[m];
      dx[c] -= 0.5 * dx[m];
      de[c] -= 0.5 * de[m];
    }
  }
  N.setZero();
  dN.setZero();
  int k = 0;
  for (int s = 0; s < 8; ++s) {
    if ((shape & (1u << s)) == 0u) continue;
    N(k) = n[s];
    dN(k, 0) = dx[s];
    dN(k, 1) = de[s];
    ++k;
  }
  return k;
}

/// A one-dimensional Gauss-Legendre rule on [-1, 1] with n = 1..4 points.
struct GaussRule1D {
  int n = 0;
  std::array<double, max_rule> x{};
  std::array<double, max_rule> w{};
};

/// Gauss-Legendre abscissae (ascending) and weights; throws stratum::Error for n outside 1..4.
[[nodiscard]] inline GaussRule1D gauss_legendre(int n) {
  GaussRule1D r;
  r.n = n;
  switch (n) {
  case 1:
    r.x = {0.0};
    r.w = {2.0};
    break;
  case 2: {
    const double a = 1.0 / std::sqrt(3.0);
    r.x = {-a, a};
    r.w = {1.0, 1.0};
    break;
  }
  case 3: {
    const double a = std::sqrt(0.6);
    r.x = {-a, 0.0, a};
    r.w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    break;
  }
  case 4: {
    const double s = 2.0 / 7.0 * std::sqrt(6.0 / 5.0);
    const double a = std::sqrt(3.0 / 7.0 - s), b = std::sqrt(3.0 / 7.0 + s);
    const double wa = (18.0 + std::sqrt(30.0)) / 36.0, wb = (18.0 - std::sqrt(30.0)) / 36.0;
    r.x = {-b, -a, a, b};
    r.w = {wb, wa, wa, wb};
    break;
  }
  default:
    throw Error("quad element: Gauss rule with " + std::to_string(n) +
                " points per direction is not available (1-4)");
  }
  return r;
}

/// One integration point of an n x n rule with the shape functions of one mask.
struct TablePoint {
  NodeVec N;      ///< shape functions of the present nodes
  NodeGrad dN;    ///< natural derivatives
  double weight;  ///< product of the 1D weights
  double xi, eta; ///< natural coordinates
};

/// An n x n Gauss rule with the shape functions of all 16 midside masks evaluated at its
/// points, built once and then only read. Point k = j * n + i sits at (x_i, x_j): xi runs
/// fastest.
class RuleTable {
public:
  RuleTable() = default;
  explicit RuleTable(int n) : n_(n) {
    const GaussRule1D g = gauss_legendre(n);
    for (unsigned m = 0; m < 16; ++m) {
      const unsigned shape = corner_bits | (m << 4);
      auto& pts = points_[m];
      pts.resize(static_cast<std::size_t>(n * n));
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          TablePoint& p = pts[static_cast<std::size_t>(j * n + i)];
          p.xi = g.x[static_cast<std::size_t>(i)];
          p.eta = g.x[static_cast<std::size_t>(j)];
          p.weight = g.w[static_cast<std::size_t>(i)] * g.w[static_cast<std::size_t>(j)];
          shape_functions(shape, p.xi, p.eta, p.N, p.dN);
        }
      }
    }
  }

  [[nodiscard]] int order() const { return n_; }
  [[nodiscard]] int size() const { return n_ * n_; }
  /// The points of a valid shape mask.
  [[nodiscard]] const std::vector<TablePoint>& points(unsigned shape) const {
    return points_[midside_bits(shape)];
  }

private:
  int n_ = 0;
  std::array<std::vector<TablePoint>, 16> points_;
};

/// Values at the points of the `full` rule of the tensor-product Lagrange polynomials
/// through the points of the `reduced` rule: P(k, l) = L_l(xi_k) L_l(eta_k), point
/// numbering as in RuleTable. Used to spread reduced-point values over the full rule.
[[nodiscard]] inline Eigen::MatrixXd lagrange_interpolation(int full, int reduced) {
  const GaussRule1D gf = gauss_legendre(full);
  const GaussRule1D gr = gauss_legendre(reduced);
  auto lag = [&](int l, double t) {
    double v = 1.0;
    for (int q = 0; q < reduced; ++q) {
      if (q == l) continue;
      v *= (t - gr.x[static_cast<std::size_t>(q)]) /
           (gr.x[static_cast<std::size_t>(l)] - gr.x[static_cast<std::size_t>(q)]);
    }
    return v;
  };
  Eigen::MatrixXd P(full * full, reduced * reduced);
  for (int j = 0; j < full; ++j)
    for (int i = 0; i < full; ++i)
      for (int lj = 0; lj < reduced; ++lj)
        for (int li = 0; li < reduced; ++li)
          P(j * full + i, lj * reduced + li) =
              lag(li, gf.x[static_cast<std::size_t>(i)]) * lag(lj, gf.x[static_cast<std::size_t>(j)]);
  return P;
}

} // namespace stratum::quad
