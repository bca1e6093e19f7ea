// Closed-form verification of the linear core (catalogue E1, E2 in
// ../shared/docs/verification.md). References are computed from the formulas;
// the worked case of the catalogue guards the formula itself.
#include "quad/quad_math.hpp"
#include "scene_helpers.hpp"

#include <catch2/catch.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace test_verification {

using namespace stratum;
using stratum::testing::node_at;
using stratum::testing::rel;
using stratum::testing::scene;

namespace {

// E1: Lamé cylinder a = 1, b = 2, p = 1, E = 1000 (tension positive).
struct Lame {
  double a = 1, b = 2, p = 1, E = 1000, nu = 0.3;
  [[nodiscard]] double u(double r) const {
    return (1 + nu) * p * a * a / (E * (b * b - a * a)) * ((1 - 2 * nu) * r + b * b / r);
  }
  [[nodiscard]] double A() const { return p * a * a / (b * b - a * a); }
  [[nodiscard]] double sigma_r(double r) const { return A() * (1 - b * b / (r * r)); }
  [[nodiscard]] double sigma_theta(double r) const { return A() * (1 + b * b / (r * r)); }
};

struct LameRun {
  std::string formulation = "axisymmetric";
  int nodes_per_cell = 8, nx = 8, ny = 2, integration = 3;
  double grade_x = 1.0; ///< last/first radial cell size (< 1: finer at the inner face)
  std::string volumetric = "full";
  double nu = 0.3;
};

std::string lame_toml(const LameRun& c) {
  std::ostringstream t;
  const bool axi = c.formulation == "axisymmetric";
  t << "[analysis]\nformulation = \"" << c.formulation << "\"\n";
  t << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = " << c.nodes_per_cell << "\n";
  // Plane strain: a quarter ring through the polar map (x = r, y = angle in degrees).
  if (!axi) t << "transform = \"polar\"\n";
  t << "[[mesh.blocks]]\nname = \"ring\"\nx = [1.0, 2.0]\ny = [0.0, " << (axi ? 0.5 : 90.0)
    << "]\nnx = " << c.nx << "\nny = " << c.ny << "\ngrade_x = " << c.grade_x << "\n";
  t << "[materials.m]\nmodel = \"linear_elastic\"\nE = 1000.0\nnu = " << c.nu << "\n";
  t << "[[domains]]\ncells = \"ring\"\nelement = \"quad\"\nmaterial = \"m\"\nintegration = " << c.integration
    << "\nvolumetric = \"" << c.volumetric << "\"\n";
  if (axi) {
    t << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n[[constraints]]\nnodes = \"top\"\nuy = 0.0\n";
  } else {
    // After the polar map, "bottom" (angle 0) lies on the x axis and "top" (90 degrees) on the y axis.
    t << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n[[constraints]]\nnodes = \"top\"\nux = 0.0\n";
  }
  t << "[[loads]]\ntype = \"pressure\"\nedges = \"ring.left\"\np = 1.0\n";
  return t.str();
}

/// L2 norm of the radial displacement error over the domain (area measure), with 4x4 Gauss.
double l2_error(const Model& m, const Lame& ex) {
  const auto g = quad::gauss_legendre(4);
  double err2 = 0;
  std::vector<int> nodes;
  Eigen::MatrixXd x;
  for (std::size_t c = 0; c < m.mesh.cells.size(); ++c) {
    m.cell_nodes(static_cast<int>(c), nodes, x);
    const unsigned shape = m.mesh.cells[c].shape();
    for (int i = 0; i < g.n; ++i)
      for (int j = 0; j < g.n; ++j) {
        quad::NodeVec N;
        quad::NodeGrad dN;
        quad::shape_functions(shape, g.x[i], g.x[j], N, dN);
        Eigen::Vector2d xq = Eigen::Vector2d::Zero(), uq = Eigen::Vector2d::Zero();
        Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
        for (std::size_t a = 0; a < nodes.size(); ++a) {
          const auto ai = static_cast<Eigen::Index>(a);
          xq += N[ai] * x.row(ai).transpose();
          J += x.row(ai).transpose() * dN.row(ai);
          uq += N[ai] * Eigen::Vector2d(m.u[2 * nodes[a]], m.u[2 * nodes[a] + 1]);
        }
        const double r = xq.norm();
        const Eigen::Vector2d ue = ex.u(r) * xq / r; // radial in both idealisations (axisym: xq.y irrelevant)
        Eigen::Vector2d e = uq - ue;
        if (m.formulation == Formulation::axisymmetric) e = Eigen::Vector2d(uq.x() - ex.u(xq.x()), uq.y());
        err2 += e.squaredNorm() * g.w[i] * g.w[j] * J.determinant();
      }
  }
  return std::sqrt(err2);
}

double u_at_inner(const Model& m) {
  const int n = node_at(m, 1.0, 0.0);
  return m.u[2 * n]; // radial at (1, 0) in both idealisations
}

} // namespace

TEST_CASE("E1 worked case guards the Lamé formula", "[verification]") {
  Lame ex;
  CHECK(ex.u(1.0) == Approx(1.906667e-3).epsilon(1e-6));
  CHECK(ex.u(2.0) == Approx(1.213333e-3).epsilon(1e-6));
  CHECK(ex.sigma_theta(1.0) == Approx(1.666667).epsilon(1e-6));
  CHECK(ex.sigma_theta(2.0) == Approx(0.666667).epsilon(1e-6));
}

TEST_CASE("Lamé cylinder quad8: u(a) and sigma_theta(a) within 1e-3", "[verification]") {
  for (const std::string form : {"axisymmetric", "plane_strain"}) {
    LameRun c;
    c.formulation = form;
    // Stresses at 3x3 Gauss points of quad8 converge as h^2 and oscillate about the exact
    // field within a cell; 32 cells across the wall put sigma_theta(a), extrapolated from
    // the inner cells, well inside 1e-3 (8 cells: 0.3 %).
    c.nx = 32;
    if (form == "plane_strain") c.ny = 16;
    auto an = scene(lame_toml(c));
    const auto s = an->run();
    REQUIRE(s.outcome.ok());
    REQUIRE(s.reports.size() == 1);
    CHECK(s.reports[0].iterations == 1); // a linear scene: one Newton iteration
    const Model& m = an->model();
    Lame ex;
    INFO(form << ": u(a) = " << u_at_inner(m));
    CHECK(rel(u_at_inner(m), ex.u(1.0)) < 1e-3);
    CHECK(rel(u_at_inner(m), 1.906667e-3) < 1e-3);
    // sigma_theta at every integration point against the closed form at its radius, and
    // sigma_theta(a) extrapolated from the three Gauss radii of the cells on the inner face.
    double worst = 0;
    std::vector<int> nodes;
    Eigen::MatrixXd x, xp;
    const auto& dm = m.domains.at(0);
    std::vector<std::pair<double, double>> inner; // (r, sigma_theta) of points in cells touching r = a
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      m.cell_nodes(dm.cells[ci], nodes, x);
      const double rmin = (form == "axisymmetric" ? x.col(0) : x.rowwise().norm().eval()).minCoeff();
      dm.element->point_coordinates(ElementData{dm.cells[ci], m.mesh.cells[dm.cells[ci]].shape(), &x}, xp);
      for (Eigen::Index p = 0; p < xp.rows(); ++p) {
        const auto st = dm.states.committed(dm.first_point[ci] + static_cast<std::size_t>(p)).stress();
        const double r = form == "axisymmetric" ? xp(p, 0) : xp.row(p).norm();
        double sth;
        if (form == "axisymmetric") {
          sth = st[voigt::zz];
        } else {
          const Eigen::Vector2d t(-xp(p, 1) / r, xp(p, 0) / r); // hoop direction
          sth = t.x() * t.x() * st[voigt::xx] + t.y() * t.y() * st[voigt::yy] +
                2 * t.x() * t.y() * st[voigt::xy];
        }
        worst = std::max(worst, std::abs(sth - ex.sigma_theta(r)) / ex.sigma_theta(1.0));
        if (rmin < 1.0 + 1e-9) inner.emplace_back(r, sth);
      }
    }
    // The 3x3 rule puts the inner cells' points on three radii: average each third.
    std::sort(inner.begin(), inner.end());
    double r_in[3] = {0, 0, 0}, s_in[3] = {0, 0, 0};
    const std::size_t third = inner.size() / 3;
    REQUIRE(third * 3 == inner.size());
    for (std::size_t i = 0; i < inner.size(); ++i) {
      r_in[i / third] += inner[i].first / static_cast<double>(third);
      s_in[i / third] += inner[i].second / static_cast<double>(third);
    }
    // Lagrange extrapolation to r = a through the three Gauss radii.
    double s_a = 0;
    for (int k = 0; k < 3; ++k) {
      double l = 1;
      for (int j = 0; j < 3; ++j)
        if (j != k) l *= (1.0 - r_in[j]) / (r_in[k] - r_in[j]);
      s_a += l * s_in[k];
    }
    INFO(form << ": sigma_theta(a) = " << s_a << ", worst point error " << worst);
    CHECK(worst < 1e-3);
    CHECK(rel(s_a, ex.sigma_theta(1.0)) < 1e-3);
    CHECK(rel(s_a, 1.666667) < 1e-3);
  }
}

TEST_CASE("Lamé h-convergence: L2 displacement error rates", "[verification]") {
  Lame ex;
  for (int npc : {4, 8}) {
    std::vector<double> h, e;
    for (int nx : {2, 4, 8, 16}) {
      LameRun c;
      c.nodes_per_cell = npc;
      c.nx = nx;
      c.ny = 1;
      c.integration = npc == 4 ? 2 : 3;
      auto an = scene(lame_toml(c));
      REQUIRE(an->run().outcome.ok());
      h.push_back(1.0 / nx);
      e.push_back(l2_error(an->model(), ex));
    }
    const double rate = std::log(e[2] / e[3]) / std::log(h[2] / h[3]);
    INFO("quad" << npc << " errors " << e[0] << " " << e[1] << " " << e[2] << " " << e[3] << ", rate "
                << rate);
    CHECK(rate >= (npc == 8 ? 2.8 : 1.8));
    CHECK(e[3] < e[2]);
  }
}

TEST_CASE("Nearly incompressible Lamé (nu = 0.4999): locking and its cures", "[verification]") {
  Lame ex;
  ex.nu = 0.4999;
  auto u_err = [&](int npc, const std::string& vol, const std::string& form) {
    LameRun c;
    c.formulation = form;
    c.nu = 0.4999;
    c.nodes_per_cell = npc;
    c.nx = 8;
    c.ny = form == "axisymmetric" ? 2 : 8;
    c.integration = npc == 4 ? 2 : 3;
    c.volumetric = vol;
    auto an = scene(lame_toml(c));
    REQUIRE(an->run().outcome.ok());
    return rel(u_at_inner(an->model()), ex.u(1.0));
  };
  for (const std::string form : {"axisymmetric", "plane_strain"}) {
    const double locked = u_err(4, "full", form);
    const double bbar = u_err(4, "bbar", form);
    const double selective = u_err(4, "selective", form);
    const double q8 = u_err(8, "full", form);
    INFO(form << ": quad4 full " << locked << ", quad4 bbar " << bbar << ", quad4 selective " << selective
              << ", quad8 " << q8);
    CHECK(locked > 0.10); // plain full-integration quad4 locks: far too stiff
    CHECK(bbar < 0.01);
    CHECK(selective < 0.01);
    CHECK(q8 < 0.01);
  }
}

TEST_CASE("E2 circular load on an elastic half-space: centre settlement", "[verification]") {
  // q = 100 kPa on radius a = 1 m, E = 10 MPa, nu = 0.3. The half-space is truncated at
  // 100 a (depth and radius); Boussinesq's far field puts the truncation error near 1 %.
  const double q = 100, a = 1, E = 1e4, nu = 0.3;
  const double w0 = 2 * q * a * (1 - nu * nu) / E;
  CHECK(w0 == Approx(0.0182).epsilon(1e-12));
  RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  auto an =
      Analysis::from_file(std::string(STRATUM_SOURCE_DIR) + "/inputs/verification/circular_load.toml", o);
  REQUIRE(an->run().outcome.ok());
  const Model& m = an->model();
  const double w = -m.u[2 * node_at(m, 0.0, 0.0) + 1];
  const double w_edge = -m.u[2 * node_at(m, 1.0, 0.0) + 1];
  INFO("w(0) = " << w << " exact " << w0 << "; w(a) = " << w_edge << " exact " << 2 / std::numbers::pi * w0);
  CHECK(rel(w, w0) < 0.03);
  CHECK(rel(w_edge, 2 / std::numbers::pi * w0) < 0.03);
  // The pressure resultant equals q pi a^2 (2 pi r weighting of the edge load).
  double fy = 0;
  for (int n = 0; n < static_cast<int>(m.mesh.nodes.size()); ++n) fy += m.load_ref[2 * n + 1];
  CHECK(-fy == Approx(q * std::numbers::pi * a * a).epsilon(1e-12));
}

} // namespace test_verification
