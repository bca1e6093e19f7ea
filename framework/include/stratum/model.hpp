// The assembled model of a scene: mesh, DOF map, element domains with their
// state stores, loads and constraints. Built by the scene reader, edited by
// stage actions, read by the assembler and the writers.
#pragma once

#include "stratum/element.hpp"
#include "stratum/fields.hpp"
#include "stratum/linear_solver.hpp"
#include "stratum/mesh.hpp"
#include "stratum/state_store.hpp"

#include <bit>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace stratum {

/// The unknowns of the model, numbered from the fields its elements declare (stratum/fields.hpp).
///
/// Layout: node by node (interleaved), and within a node the fields it carries in the model's
/// field order; the displacement components of the mesh's dimension are always fields 0..dim-1
/// ("ux", "uy"(, "uz")), so a model of displacement elements numbers "dim per node".
/// eq[d] >= 0 is the index of global DOF d among the free unknowns, eq[d] < 0 the prescribed
/// index (-1 - eq[d]).
struct DofMap {
  std::vector<Field> fields;            ///< the model's fields; a field's id is its index
  std::vector<int> node_first;          ///< per node, its first global DOF; size nodes + 1
  std::vector<std::uint32_t> node_mask; ///< per node, bit f set when it carries field f
  std::vector<int> eq;
  std::vector<int> prescribed; ///< global DOF of each prescribed index
  int free_count = 0;

  /// Global DOF of field `field` at `node`, -1 when the node does not carry it.
  [[nodiscard]] int dof(int node, int field) const {
    const std::uint32_t m = node_mask[static_cast<std::size_t>(node)];
    if (field < 0 || field >= 32 || !((m >> field) & 1u)) return -1;
    return node_first[static_cast<std::size_t>(node)] + std::popcount(m & ((1u << field) - 1u));
  }
  /// The id of the field called `name`, -1 when the model has none.
  [[nodiscard]] int field(std::string_view name) const;
  /// The names of the model's fields, comma-separated (for messages).
  [[nodiscard]] std::string field_list() const;
  /// Numbers the DOFs from per-node masks (node_mask set by the caller): fills node_first.
  void layout();
  /// `fixed[d]` marks prescribed global DOFs.
  void build(const std::vector<char>& fixed);
  [[nodiscard]] int total() const { return static_cast<int>(eq.size()); }
};

/// Cells of one element kind and one constitutive law, with the states of their points.
struct Domain {
  std::string name; ///< for messages and output
  int set_id = 0;   ///< written as cell data "set_id"
  const Element* element = nullptr;
  Constitutive law;
  std::vector<int> cells;               ///< global cell indices
  std::vector<std::size_t> first_point; ///< per cell, index of its first point in `states`; size cells + 1
  StateStore states;
  /// The pore water of a displacement domain: "drained", "undrained" (the material carries the
  /// excess pore pressure as its first history component, "p_excess"), "undrained_total" (total-
  /// stress parameters, no pore pressure computed) or "non_porous"; a porous element's domain is
  /// "drained" (its element carries p).
  std::string drainage = "drained";
};

/// A phreatic level: horizontal (one point: its y) or a polyline through points of strictly
/// increasing x, linear between them and horizontal beyond its ends (the reader requires the line
/// to span the mesh); no point: none (dry).
struct PhreaticLevel {
  std::vector<double> x, y; ///< m; x is unused for a horizontal level

  [[nodiscard]] static PhreaticLevel horizontal(double level) { return PhreaticLevel{{0.0}, {level}}; }
  [[nodiscard]] bool present() const { return !y.empty(); }
  [[nodiscard]] bool sloped() const {
    for (std::size_t i = 1; i < y.size(); ++i)
      if (y[i] != y[0]) return true;
    return false;
  }
  /// The level's y above x; -inf when there is none.
  [[nodiscard]] double at(double px) const {
    if (y.empty()) return -std::numeric_limits<double>::infinity();
    if (y.size() == 1 || !(px > x.front())) return y.front();
    if (!(px < x.back())) return y.back();
    const std::size_t i = segment(px);
    return y[i] + (y[i + 1] - y[i]) * (px - x[i]) / (x[i + 1] - x[i]);
  }
  /// dy/dx of the level above x: its segment's slope, 0 beyond the ends and when horizontal.
  [[nodiscard]] double slope(double px) const {
    if (y.size() < 2 || !(px > x.front()) || !(px < x.back())) return 0.0;
    const std::size_t i = segment(px);
    return (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
  }
  /// Checkpoints and loads keep it (framework/src/run/checkpoint.cpp).
  template <class Ar> void serialize(Ar& ar, unsigned /*version*/) { ar& x& y; }

private:
  /// The segment [x[i], x[i+1]] holding px, x.front() < px < x.back().
  [[nodiscard]] std::size_t segment(double px) const {
    std::size_t i = 0;
    while (i + 2 < x.size() && !(px < x[i + 1])) ++i;
    return i;
  }
};

/// The steady pore water of the model: hydrostatic below a phreatic level in every vertical
/// (PhreaticLevel; set by a `geostatic` action, moved by a `water_level` one). The unknown `p` of
/// porous elements is the excess over it.
struct Water {
  PhreaticLevel level;   ///< none: dry
  double gamma_w = 9.81; ///< unit weight of water, kN/m3
  [[nodiscard]] bool present() const { return level.present(); }
  /// The steady pore pressure at (x, y), compression positive (kPa).
  [[nodiscard]] double pressure(double x, double y) const {
    const double top = level.at(x);
    return y < top ? gamma_w * (top - y) : 0.0;
  }
};

struct Model {
  Formulation formulation = Formulation::axisymmetric;
  Water water;
  Mesh mesh;
  std::vector<Domain> domains;
  DofMap dofs;
  /// External load of the current stage: load_base + lambda * load_ref (full size, kN).
  Eigen::VectorXd load_base;
  Eigen::VectorXd load_ref;
  /// Prescribed displacement of the current stage: prescribed_base + lambda * prescribed (m).
  Eigen::VectorXd prescribed_base;
  Eigen::VectorXd prescribed;
  /// Prescribed inflow of the current stage: the volume per unit time (m3 per time unit) entering
  /// at each pore-pressure DOF (full size, empty or zero without one); a step of length dt adds dt
  /// times it to the continuity equations (StaticProblem), a static stage (dt = 0) nothing.
  Eigen::VectorXd inflow;
  Eigen::VectorXd u;         ///< full-size committed displacement (m)
  Eigen::VectorXd reactions; ///< full-size internal force at the last converged state (kN)
  double lambda = 0.0;       ///< committed load factor within the current stage
  /// The load step being evaluated (stratum/material.hpp, StepClock): the step driver sets the
  /// stage and increment, the stage's problem the times of each evaluation; element_data()
  /// hands it to the elements.
  StepClock clock;
  std::vector<char> active;      ///< per cell: 1 when the cell takes part (stages deactivate cells)
  std::vector<char> constrained; ///< per DOF: 1 when a constraint holds it

  /// Numbers the unknowns from the fields the domains' elements declare for their cells (every
  /// cell, active or not, so that the numbering does not change with the stages). Called once
  /// the domains and interfaces are built; throws Error when two elements declare a field of one
  /// name with different units.
  void layout_dofs();
  /// Rebuilds the free/prescribed split: constrained DOFs and DOFs no active cell uses are fixed.
  void rebuild_dofs();
  /// The global DOFs of a cell's local unknowns in the element's order (stratum/fields.hpp), -1
  /// for none; the domain's element declares them.
  void cell_dofs(const Domain& dm, int cell, std::vector<int>& dofs) const;
  /// What an element sees of a cell: its index, type, present slots and the coordinates x.
  [[nodiscard]] ElementData element_data(int cell, const Eigen::MatrixXd& x) const {
    const Cell& c = mesh.cells[static_cast<std::size_t>(cell)];
    return ElementData{cell, c.shape(), &x, c.type, clock};
  }
  /// The number of displacement components (2, or 3 when the model has field uz).
  [[nodiscard]] int dim() const { return dofs.field("uz") == field_uz ? 3 : 2; }
  [[nodiscard]] bool is_active(int cell) const { return active.empty() || active[cell] != 0; }

  /// Present nodes of a cell in slot order, and their coordinates.
  void cell_nodes(int cell, std::vector<int>& nodes, Eigen::MatrixXd& x) const;
  /// Full-size vector of unknowns from free unknowns and the prescribed values at load factor lambda.
  void expand(const Eigen::VectorXd& free, double lambda, Eigen::VectorXd& full) const;
  /// Free unknowns of a full-size vector.
  [[nodiscard]] Eigen::VectorXd restrict_free(const Eigen::VectorXd& full) const;
  /// True when the tangent is symmetric and may go to a symmetric (LDL^T, Cholesky) solver: every
  /// law says so and the model has no field besides the displacements (a u-p matrix is indefinite).
  [[nodiscard]] bool symmetric() const;
  /// The free unknowns (indices into the free vector) of field `field` at the nodes of the node
  /// set `set`; empty when the mesh has no such set or none of its nodes has a free one.
  [[nodiscard]] std::vector<Eigen::Index> node_set_free_dofs(const std::string& set, int field) const;
};

/// Assembles internal forces and the tangent over the free DOFs. The sparsity
/// pattern and the per-cell scatter indices are built once per model topology.
class WorkerPool;

class Assembler {
public:
  /// reuse_linear_stiffness: cells whose element reports constant_stiffness keep their stiffness
  /// from the first assembly with a tangent for the assembler's lifetime (one stage).
  /// threads: how many threads evaluate the cells (elements and materials are const, each
  /// cell writes only its own point states); their contributions are summed in cell order by
  /// one thread, so every number is the same whatever the count.
  explicit Assembler(const Model& model, bool reuse_linear_stiffness = true, int threads = 1);
  ~Assembler();
  Assembler(const Assembler&) = delete;
  Assembler& operator=(const Assembler&) = delete;

  /// The matrix with the fixed pattern (values zero) to be filled by assemble().
  [[nodiscard]] SparseMatrix make_matrix() const { return pattern_; }

  /// Evaluates every domain at the full-size trial displacement u (the committed one is
  /// model.u): internal force (full size) and, when k != nullptr, the free-free tangent
  /// (k must come from make_matrix()). Trial states are written.
  [[nodiscard]] Outcome assemble(Model& model, const Eigen::VectorXd& u, Eigen::VectorXd& f_int,
                                 SparseMatrix* k) const;

private:
  SparseMatrix pattern_;
  std::vector<std::vector<int>>
      scatter_; ///< per domain: concatenated per-cell (local DOFs)^2 value indices, -1 = skip
  std::vector<std::vector<std::size_t>> scatter_start_;
  /// Per domain whose element reports constant_stiffness: the cells' stiffness matrices
  /// (same layout as scatter_), computed at the first assembly with a tangent and reused for
  /// the rest of the stage; filled_ says which cells have one. A cache of values that are
  /// functions of the (fixed) geometry and material, owned by this stage's assembler.
  mutable std::vector<std::vector<double>> stiffness_;
  mutable std::vector<std::vector<char>> filled_;
  /// The active cells in summation order: (domain, index in the domain).
  std::vector<std::pair<std::size_t, std::size_t>> tasks_;
  /// Per domain: the concatenated global DOFs of each cell's local unknowns (Model::cell_dofs),
  /// and where each cell's list starts (size cells + 1).
  std::vector<std::vector<int>> dofs_;
  std::vector<std::vector<std::size_t>> dofs_start_;
  std::unique_ptr<WorkerPool> pool_;
  /// Scratch of one evaluation pass: per-thread gather buffers, and per cell of a chunk its
  /// nodes (gathered once, read again by the summation), result and outcome.
  struct Scratch {
    Eigen::MatrixXd x;
    Eigen::VectorXd ue, une;
  };
  mutable std::vector<Scratch> scratch_;
  mutable std::vector<std::vector<int>> nodes_;
  mutable std::vector<ElementResult> results_;
  mutable std::vector<Outcome> outcomes_;
};

/// Adds consistent nodal forces of a normal pressure p(x) (kPa, positive = pushing into the
/// body) on the edges of a two-dimensional model to out (full size, the model's DOF numbering).
/// Axisymmetric: weighted with 2 pi r.
void add_edge_pressure(const Model& model, const std::vector<Edge>& edges,
                       const std::function<double(const Eigen::Vector2d&)>& p, Eigen::VectorXd& out);
/// The same for a uniform pressure p.
void add_edge_pressure(const Model& model, const std::vector<Edge>& edges, double p, Eigen::VectorXd& out);

} // namespace stratum
