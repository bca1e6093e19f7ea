// Scene texts of the contact verification cases (C1, C2), shared by the tests and by the
// conditioning benchmark (tools/benchmarks/contact_conditioning.cpp).
#pragma once

#include "stratum/analysis.hpp"
#include "stratum/model.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace stratum::testing {

/// C2: a soil column of height H on an interface (or a thin layer) on a rigid base, under a
/// uniform pressure q, laterally confined: w = q H / E_oed + q / k_n.
struct ColumnSpec {
  std::string formulation = "plane_strain";
  std::string kind = "interface_line"; ///< contact2, interface_line, interface_line_gauss, thin_layer
  int nodes_per_cell = 4;
  double q = 100.0, H = 2.0, E = 2e4, nu = 0.3, kn = 5e4;
  double b = 1.0;      ///< column width (one cell)
  double layer = 0.05; ///< thin layer thickness t
  int ny = 4;
  [[nodiscard]] bool thin() const { return kind == "thin_layer"; }
  [[nodiscard]] double top() const { return H + (thin() ? layer : 0.0); }
  [[nodiscard]] double e_oed(double E_, double nu_) const {
    return E_ * (1 - nu_) / ((1 + nu_) * (1 - 2 * nu_));
  }
  [[nodiscard]] double expected() const { return q * H / e_oed(E, nu) + q / kn; }
};

inline std::string column_scene(const ColumnSpec& s) {
  std::ostringstream t;
  t.precision(17);
  const double y0 = s.thin() ? s.layer : 0.0;
  t << "title = \"C2 column on an interface layer\"\n[analysis]\nformulation = \"" << s.formulation
    << "\"\nsteps = 1\n[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = " << s.nodes_per_cell
    << "\n[[mesh.blocks]]\nname = \"soil\"\nx = [0.0, " << s.b << "]\ny = [" << y0 << ", " << y0 + s.H
    << "]\nny = " << s.ny << "\n";
  if (s.thin())
    t << "[[mesh.blocks]]\nname = \"layer\"\nx = [0.0, " << s.b << "]\ny = [0.0, " << s.layer << "]\n";
  t << "[materials.soil]\nmodel = \"linear_elastic\"\nE = " << s.E << "\nnu = " << s.nu << "\n";
  t << "[[domains]]\ncells = \"soil\"\nelement = \"quad\"\nmaterial = \"soil\"\n";
  if (s.thin()) {
    // E_oed of the layer / t = k_n.
    const double nu = s.nu;
    const double El = s.kn * s.layer * (1 + nu) * (1 - 2 * nu) / (1 - nu);
    t << "[materials.layer]\nmodel = \"linear_elastic\"\nE = " << El << "\nnu = " << nu << "\n";
    t << "[[domains]]\ncells = \"layer\"\nelement = \"thin_layer\"\nmaterial = \"layer\"\n";
    t << "[[constraints]]\nnodes = \"layer.bottom\"\nux = 0.0\nuy = 0.0\n";
  } else {
    t << "[contact_laws.iface]\nmodel = \"coulomb_elastoplastic\"\nk_s = " << s.kn << "\nk_n = " << s.kn
      << "\nc = 1e6\n";
    const bool gauss = s.kind == "interface_line_gauss";
    t << "[[interfaces]]\nname = \"base\"\nedges = \"soil.bottom\"\nelement = \""
      << (gauss ? std::string("interface_line") : s.kind) << "\"\nlaw = \"iface\"\n";
    if (gauss) t << "integration = \"gauss\"\n";
    t << "[[constraints]]\nnodes = \"base.side2\"\nux = 0.0\nuy = 0.0\n";
  }
  t << "[[constraints]]\nnodes = \"left\"\nux = 0.0\n[[constraints]]\nnodes = \"right\"\nux = 0.0\n";
  t << "[[loads]]\ntype = \"pressure\"\nedges = \"soil.top\"\np = " << s.q << "\n";
  return t.str();
}

/// C1: a rigid pile shaft (radius r0, length L) pushed down by w in an elastic soil annulus
/// r0..rm with u = 0 at rm and no radial displacement at the top and bottom. Before slip the
/// soil deforms in simple shear (concentric cylinders: tau r = const), P = 2 pi L G w / zeta
/// with zeta = ln(rm / r0) (Randolph & Wroth) plus the interface compliance; the shaft slips at
/// tau_max and P stays at 2 pi r0 L tau_max.
struct PileSpec {
  std::string kind = "contact2"; ///< contact2, interface_line, thin_layer
  double r0 = 0.5, rm = 5.0, L = 1.0, E = 1e4, nu = 0.3, tau_max = 20.0, k_s = 1e6;
  double layer = 0.004; ///< thin layer thickness (t/b = 0.02 with b = L / ny)
  int nx = 8, ny = 5, steps = 12;
  [[nodiscard]] bool thin() const { return kind == "thin_layer"; }
  [[nodiscard]] double G() const { return E / (2 * (1 + nu)); }
  [[nodiscard]] double zeta() const { return std::log(rm / r0); }
  [[nodiscard]] double w_slip() const { return tau_max * (r0 * zeta() / G() + 1.0 / k_s); }
  [[nodiscard]] double w_max() const { return 3.0 * w_slip(); }
  /// Randolph & Wroth shaft stiffness P / w (no base).
  [[nodiscard]] double shaft_stiffness() const { return 2 * std::numbers::pi * L * G() / zeta(); }
  /// 2 pi r L tau_max at the interface radius (the mid-surface of a thin layer).
  [[nodiscard]] double shaft_capacity() const {
    return 2 * std::numbers::pi * (r0 + (thin() ? 0.5 * layer : 0.0)) * L * tau_max;
  }
  [[nodiscard]] std::string pile_nodes() const { return thin() ? "layer.left" : "shaft.side2"; }
};

inline std::string pile_scene(const PileSpec& s) {
  std::ostringstream t;
  t.precision(17);
  const double rs = s.thin() ? s.r0 + s.layer : s.r0;
  t << "title = \"C1 rigid pile with shaft slip\"\n[analysis]\nformulation = \"axisymmetric\"\nsteps = "
    << s.steps << "\n[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n";
  t << "[[mesh.blocks]]\nname = \"soil\"\nx = [" << rs << ", " << s.rm << "]\ny = [0.0, " << s.L
    << "]\nnx = " << s.nx << "\nny = " << s.ny << "\ngrade_x = 6.0\n";
  if (s.thin())
    t << "[[mesh.blocks]]\nname = \"layer\"\nx = [" << s.r0 << ", " << rs << "]\ny = [0.0, " << s.L
      << "]\nny = " << s.ny << "\n";
  t << "[materials.soil]\nmodel = \"linear_elastic\"\nE = " << s.E << "\nnu = " << s.nu << "\n";
  t << "[[domains]]\ncells = \"soil\"\nelement = \"quad\"\nmaterial = \"soil\"\n";
  if (s.thin()) {
    const double El = 2 * (1 + s.nu) * s.k_s * s.layer; // G_layer / t = k_s
    t << "[materials.layer]\nmodel = \"von_mises\"\nE = " << El << "\nnu = " << s.nu
      << "\nsigma_y = " << std::sqrt(3.0) * s.tau_max << "\n";
    t << "[[domains]]\ncells = \"layer\"\nelement = \"thin_layer\"\nmaterial = \"layer\"\n";
  } else {
    t << "[contact_laws.shaft]\nmodel = \"coulomb_elastoplastic\"\nk_s = " << s.k_s << "\nk_n = " << s.k_s
      << "\nc = " << s.tau_max << "\nsigma_t = 1000.0\n"; // adhesive: sigma_n = 0 here, no flip to open
    t << "[[interfaces]]\nname = \"shaft\"\nedges = \"soil.left\"\nelement = \"" << s.kind
      << "\"\nlaw = \"shaft\"\ncsv = false\n";
  }
  t << "[[constraints]]\nnodes = \"" << s.pile_nodes() << "\"\nux = 0.0\nuy = " << -s.w_max() << "\n";
  t << "[[constraints]]\nnodes = \"top\"\nux = 0.0\n[[constraints]]\nnodes = \"bottom\"\nux = 0.0\n";
  t << "[[constraints]]\nnodes = \"right\"\nux = 0.0\nuy = 0.0\n";
  return t.str();
}

/// The load on the pile: the vertical internal force on its nodes (kN, full circle).
inline double pile_load(const Model& m, const PileSpec& s) {
  double P = 0.0;
  for (int n : m.mesh.node_sets.at(s.pile_nodes())) P += m.reactions[2 * n + 1];
  return std::abs(P);
}

/// One row of the C3 conditioning sweep: the C2 column with k_n = ratio E / h (h = cell height).
struct ConditioningRow {
  std::string kind;
  double ratio = 0.0;           ///< k_n h / E
  double cond = 0.0;            ///< 2-norm condition number of the free-free tangent at the solution
  int iterations = 0;           ///< Newton iterations (linear solves) of the load step
  double error = 0.0;           ///< |w - w_exact| / w_exact at the top
  double interface_error = 0.0; ///< error of the interface closure relative to q / k_n
  bool ok = false;
};

inline ConditioningRow conditioning(const std::string& kind, double ratio, int nodes_per_cell,
                                    const std::string& plugin_dir) {
  ColumnSpec s;
  s.kind = kind;
  s.nodes_per_cell = nodes_per_cell;
  s.kn = ratio * s.E / (s.H / s.ny);
  RunOptions o;
  o.plugin_dirs = {plugin_dir};
  o.write_output = false;
  auto a = Analysis::from_string(column_scene(s), "c3.toml", o);
  const auto run = a->run();
  ConditioningRow row;
  row.kind = kind;
  row.ratio = ratio;
  row.ok = run.outcome.ok();
  for (const auto& r : run.reports) row.iterations += r.iterations;
  Model& m = a->model();
  // Top displacement (any top node: the state is uniform) and the interface closure.
  double top = 0.0, bottom = 0.0;
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
    if (std::abs(m.mesh.nodes[n].y() - s.top()) < 1e-12) top = -m.u[static_cast<Eigen::Index>(2 * n + 1)];
    if (s.thin() && std::abs(m.mesh.nodes[n].y() - s.layer) < 1e-12)
      bottom = -m.u[static_cast<Eigen::Index>(2 * n + 1)];
  }
  if (!s.thin()) bottom = -m.u[2 * m.mesh.node_sets.at("base.side1").front() + 1];
  row.error = std::abs(top - s.expected()) / s.expected();
  row.interface_error = std::abs(bottom - s.q / s.kn) / (s.q / s.kn);
  const Assembler asm_(m);
  SparseMatrix k = asm_.make_matrix();
  Eigen::VectorXd f;
  if (asm_.assemble(m, m.u, f, &k).ok()) {
    const Eigen::MatrixXd K(k);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (K + K.transpose()),
                                                            Eigen::EigenvaluesOnly);
    const auto& ev = es.eigenvalues();
    row.cond = ev.cwiseAbs().maxCoeff() / ev.cwiseAbs().minCoeff();
  }
  for (auto& dm : m.domains) dm.states.revert();
  return row;
}

} // namespace stratum::testing
