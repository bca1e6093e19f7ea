#include "stratum/model.hpp"

#include "worker_pool.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace stratum {

int DofMap::field(std::string_view name) const {
  for (std::size_t f = 0; f < fields.size(); ++f)
    if (fields[f].name == name) return static_cast<int>(f);
  return -1;
}

std::string DofMap::field_list() const {
  std::string s;
  for (const Field& f : fields) s += (s.empty() ? "" : ", ") + f.name;
  return s;
}

void DofMap::layout() {
  node_first.assign(node_mask.size() + 1, 0);
  for (std::size_t n = 0; n < node_mask.size(); ++n)
    node_first[n + 1] = node_first[n] + std::popcount(node_mask[n]);
  eq.assign(static_cast<std::size_t>(node_first.back()), 0);
  prescribed.clear();
  free_count = 0;
}

void DofMap::build(const std::vector<char>& fixed) {
  eq.assign(fixed.size(), 0);
  prescribed.clear();
  free_count = 0;
  for (std::size_t d = 0; d < fixed.size(); ++d) {
    if (fixed[d]) {
      eq[d] = -1 - static_cast<int>(prescribed.size());
      prescribed.push_back(static_cast<int>(d));
    } else {
      eq[d] = free_count++;
    }
  }
}

namespace {

/// The model's id of each of an element's fields, adding the fields the model has not seen.
void field_ids(DofMap& dofs, const std::vector<Field>& fields, const std::string& domain,
               std::vector<int>& ids) {
  ids.clear();
  for (const Field& f : fields) {
    int id = dofs.field(f.name);
    if (id < 0) {
      if (dofs.fields.size() >= 32)
        throw Error("domain \"" + domain + "\": more than 32 fields (" + dofs.field_list() + ")");
      id = static_cast<int>(dofs.fields.size());
      dofs.fields.push_back(f);
    } else if (!(dofs.fields[static_cast<std::size_t>(id)] == f)) {
      const Field& g = dofs.fields[static_cast<std::size_t>(id)];
      throw Error("domain \"" + domain + "\": its element declares field \"" + f.name + "\" in " + f.unit +
                  " (reaction " + f.reaction_unit + "), another domain's in " + g.unit + " (reaction " +
                  g.reaction_unit + "); a field has one unit");
    }
    ids.push_back(id);
  }
}

} // namespace

void Model::layout_dofs() {
  int dim = 2;
  for (const Cell& c : mesh.cells) dim = std::max(dim, cell_dimension(c.type));
  dofs.fields = displacement_fields(dim);
  dofs.node_mask.assign(mesh.nodes.size(), 0u);
  std::vector<int> ids;
  for (const auto& dm : domains)
    for (int c : dm.cells) {
      const Cell& cell = mesh.cells[static_cast<std::size_t>(c)];
      const NodeFields nf = dm.element->node_fields(cell.type, cell.shape());
      field_ids(dofs, nf.fields, dm.name, ids);
      std::size_t i = 0;
      for (int n : cell.nodes) {
        if (n < 0) continue;
        const std::uint32_t carried = nf.at(i++);
        for (std::size_t k = 0; k < ids.size(); ++k)
          if ((carried >> k) & 1u) dofs.node_mask[static_cast<std::size_t>(n)] |= 1u << ids[k];
      }
    }
  dofs.layout();
}

void Model::cell_dofs(const Domain& dm, int cell, std::vector<int>& out) const {
  const Cell& c = mesh.cells[static_cast<std::size_t>(cell)];
  const NodeFields nf = dm.element->node_fields(c.type, c.shape());
  // The model's id of each of the element's fields, looked up once (layout_dofs added them all).
  std::array<int, 32> id{};
  for (std::size_t k = 0; k < nf.fields.size() && k < id.size(); ++k) id[k] = dofs.field(nf.fields[k].name);
  out.clear();
  std::size_t i = 0;
  for (int n : c.nodes) {
    if (n < 0) continue;
    const std::uint32_t carried = nf.at(i++);
    for (std::size_t k = 0; k < nf.fields.size() && k < id.size(); ++k)
      if ((carried >> k) & 1u) out.push_back(dofs.dof(n, id[k]));
  }
}

void Model::cell_nodes(int cell, std::vector<int>& nodes, Eigen::MatrixXd& x) const {
  nodes.clear();
  for (int n : mesh.cells[cell].nodes)
    if (n >= 0) nodes.push_back(n);
  x.resize(static_cast<Eigen::Index>(nodes.size()), 2);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    x.row(static_cast<Eigen::Index>(i)) = mesh.nodes[nodes[i]].transpose();
}

void Model::expand(const Eigen::VectorXd& free, double lam, Eigen::VectorXd& full) const {
  full.resize(dofs.total());
  for (int d = 0; d < dofs.total(); ++d) {
    const int e = dofs.eq[d];
    full[d] = e >= 0 ? free[e] : prescribed_base[d] + lam * prescribed[d];
  }
}

Eigen::VectorXd Model::restrict_free(const Eigen::VectorXd& full) const {
  Eigen::VectorXd v(dofs.free_count);
  for (int d = 0; d < dofs.total(); ++d)
    if (dofs.eq[d] >= 0) v[dofs.eq[d]] = full[d];
  return v;
}

void Model::rebuild_dofs() {
  const auto total = static_cast<std::size_t>(dofs.node_first.empty() ? 0 : dofs.node_first.back());
  std::vector<char> fixed(constrained);
  fixed.resize(total, 0);
  std::vector<char> used(total, 0);
  std::vector<int> ld;
  for (const auto& dm : domains)
    for (int c : dm.cells)
      if (is_active(c)) {
        cell_dofs(dm, c, ld);
        for (int d : ld)
          if (d >= 0) used[static_cast<std::size_t>(d)] = 1;
      }
  for (std::size_t d = 0; d < total; ++d)
    if (!used[d]) fixed[d] = 1;
  dofs.build(fixed);
}

std::vector<Eigen::Index> Model::node_set_free_dofs(const std::string& set, int field) const {
  std::vector<Eigen::Index> v;
  const auto it = mesh.node_sets.find(set);
  if (it == mesh.node_sets.end() || field < 0 || field >= static_cast<int>(dofs.fields.size())) return v;
  for (int n : it->second)
    if (const int d = dofs.dof(n, field); d >= 0)
      if (const int e = dofs.eq[static_cast<std::size_t>(d)]; e >= 0) v.push_back(e);
  return v;
}

bool Model::symmetric() const {
  // Fields besides the displacements (a pore pressure) make a saddle-point matrix: symmetric but
  // indefinite, with zero or tiny diagonal entries where a fluid is (nearly) incompressible. The
  // LDL^T and Cholesky factorizations do not pivot, so such a model takes the LU solvers.
  if (static_cast<int>(dofs.fields.size()) > dim()) return false;
  for (const auto& dm : domains) {
    if (dm.law.material && !dm.law.material->symmetric_tangent()) return false;
    if (dm.law.contact && !dm.law.contact->symmetric_tangent()) return false;
  }
  return true;
}

Assembler::Assembler(const Model& model, bool reuse_linear_stiffness, int threads) {
  const int nf = model.dofs.free_count;
  // Each cell's global DOFs, then the pattern: column j holds the free rows of every active cell
  // that has free DOF j.
  dofs_.resize(model.domains.size());
  dofs_start_.resize(model.domains.size());
  std::vector<int> ld;
  for (std::size_t di = 0; di < model.domains.size(); ++di) {
    const auto& dm = model.domains[di];
    dofs_start_[di].assign(dm.cells.size() + 1, 0);
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      model.cell_dofs(dm, dm.cells[ci], ld);
      dofs_[di].insert(dofs_[di].end(), ld.begin(), ld.end());
      dofs_start_[di][ci + 1] = dofs_[di].size();
    }
  }
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(nf));
  std::vector<int> free;
  for (std::size_t di = 0; di < model.domains.size(); ++di)
    for (std::size_t ci = 0; ci < model.domains[di].cells.size(); ++ci) {
      if (!model.is_active(model.domains[di].cells[ci])) continue;
      free.clear();
      for (std::size_t k = dofs_start_[di][ci]; k < dofs_start_[di][ci + 1]; ++k)
        if (const int d = dofs_[di][k]; d >= 0 && model.dofs.eq[static_cast<std::size_t>(d)] >= 0)
          free.push_back(model.dofs.eq[static_cast<std::size_t>(d)]);
      for (int j : free)
        rows[static_cast<std::size_t>(j)].insert(rows[static_cast<std::size_t>(j)].end(), free.begin(),
                                                 free.end());
    }
  std::vector<int> outer(nf + 1, 0);
  for (int j = 0; j < nf; ++j) {
    auto& v = rows[static_cast<std::size_t>(j)];
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    outer[j + 1] = outer[j] + static_cast<int>(v.size());
  }
  std::vector<int> inner;
  inner.reserve(static_cast<std::size_t>(outer[nf]));
  for (auto& v : rows) {
    inner.insert(inner.end(), v.begin(), v.end());
    std::vector<int>().swap(v);
  }
  pattern_.resize(nf, nf);
  pattern_.resizeNonZeros(outer[nf]);
  std::copy(outer.begin(), outer.end(), pattern_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), pattern_.innerIndexPtr());
  std::fill(pattern_.valuePtr(), pattern_.valuePtr() + outer[nf], 0.0);

  // Scatter indices: for each cell, n^2 positions (n local DOFs) into the value array
  // (column-major local order).
  scatter_.resize(model.domains.size());
  scatter_start_.resize(model.domains.size());
  stiffness_.resize(model.domains.size());
  filled_.resize(model.domains.size());
  for (std::size_t di = 0; di < model.domains.size(); ++di) {
    const auto& dm = model.domains[di];
    auto& sc = scatter_[di];
    auto& st = scatter_start_[di];
    st.assign(dm.cells.size() + 1, 0);
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const std::size_t n = dofs_start_[di][ci + 1] - dofs_start_[di][ci];
      st[ci + 1] = st[ci] + n * n;
    }
    sc.assign(st.back(), -1);
    if (reuse_linear_stiffness && dm.element->constant_stiffness(dm.law)) {
      stiffness_[di].assign(st.back(), 0.0);
      filled_[di].assign(dm.cells.size(), 0);
    }
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      if (!model.is_active(dm.cells[ci])) continue;
      const int* g = dofs_[di].data() + dofs_start_[di][ci];
      const std::size_t n = dofs_start_[di][ci + 1] - dofs_start_[di][ci];
      auto eq = [&](std::size_t a) { return g[a] >= 0 ? model.dofs.eq[static_cast<std::size_t>(g[a])] : -1; };
      int* out = sc.data() + st[ci];
      for (std::size_t b = 0; b < n; ++b) {
        const int col = eq(b);
        for (std::size_t a = 0; a < n; ++a) {
          const int row = eq(a);
          int pos = -1;
          if (row >= 0 && col >= 0) {
            const int* begin = inner.data() + outer[col];
            const int* end = inner.data() + outer[col + 1];
            pos = static_cast<int>(std::lower_bound(begin, end, row) - inner.data());
          }
          out[b * n + a] = pos;
        }
      }
    }
  }
  for (std::size_t di = 0; di < model.domains.size(); ++di)
    for (std::size_t ci = 0; ci < model.domains[di].cells.size(); ++ci)
      if (model.is_active(model.domains[di].cells[ci])) tasks_.emplace_back(di, ci);
  threads = std::clamp(threads, 1, std::max(1, static_cast<int>(tasks_.size() / 16)));
  if (threads > 1) pool_ = std::make_unique<WorkerPool>(threads);
  scratch_.resize(static_cast<std::size_t>(threads));
}

Assembler::~Assembler() = default;

Outcome Assembler::assemble(Model& model, const Eigen::VectorXd& u, Eigen::VectorXd& f_int,
                            SparseMatrix* k) const {
  f_int.setZero(model.dofs.total());
  double* values = nullptr;
  if (k) {
    values = k->valuePtr();
    std::fill(values, values + k->nonZeros(), 0.0);
  }
  // Inactive cells keep their committed state through the commit swap.
  for (auto& dm : model.domains)
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci)
      if (!model.is_active(dm.cells[ci])) dm.states.hold(dm.first_point[ci], dm.first_point[ci + 1]);

  // Cells are evaluated in chunks, in parallel when there is a pool (each cell writes only its
  // own point states and result slot); each chunk is then summed by this thread in cell order,
  // so the sums, and every number downstream, do not depend on the thread count.
  const std::size_t chunk = pool_ ? std::min<std::size_t>(tasks_.size(), 256) : 1;
  if (results_.size() < chunk) {
    nodes_.resize(chunk);
    results_.resize(chunk);
    outcomes_.resize(chunk);
  }
  auto evaluate = [&](std::size_t first, std::size_t begin, std::size_t end, int worker) {
    Scratch& sc = scratch_[static_cast<std::size_t>(worker)];
    for (std::size_t t = begin; t < end; ++t) {
      const auto [di, ci] = tasks_[first + t];
      auto& dm = model.domains[di];
      const int cell = dm.cells[ci];
      std::vector<int>& nodes = nodes_[t];
      model.cell_nodes(cell, nodes, sc.x);
      const int* g = dofs_[di].data() + dofs_start_[di][ci];
      const auto nd = static_cast<Eigen::Index>(dofs_start_[di][ci + 1] - dofs_start_[di][ci]);
      sc.ue.resize(nd);
      sc.une.resize(nd);
      for (Eigen::Index i = 0; i < nd; ++i) {
        sc.ue[i] = u[g[i]];
        sc.une[i] = model.u[g[i]];
      }
      const ElementData data = model.element_data(cell, sc.x);
      const bool cached = k && !filled_[di].empty() && filled_[di][ci];
      outcomes_[t] = dm.element->compute(data, sc.ue, sc.une, dm.law, dm.states, dm.first_point[ci],
                                         k && !cached, results_[t]);
    }
  };
  for (std::size_t first = 0; first < tasks_.size(); first += chunk) {
    const std::size_t n = std::min(chunk, tasks_.size() - first);
    if (pool_)
      pool_->run(n, 4, [&](std::size_t b, std::size_t e, int w) { evaluate(first, b, e, w); });
    else
      evaluate(first, 0, n, 0);
    for (std::size_t t = 0; t < n; ++t) {
      if (!outcomes_[t].ok()) return outcomes_[t]; // the first failing cell in cell order
      const auto [di, ci] = tasks_[first + t];
      const ElementResult& res = results_[t];
      const int* g = dofs_[di].data() + dofs_start_[di][ci];
      const std::size_t nd = dofs_start_[di][ci + 1] - dofs_start_[di][ci];
      const std::size_t n2 = nd * nd;
      const std::size_t start = scatter_start_[di][ci];
      const bool cached = k && !filled_[di].empty() && filled_[di][ci];
      if (k && !cached && !filled_[di].empty()) {
        std::copy(res.stiffness.data(), res.stiffness.data() + n2, stiffness_[di].data() + start);
        filled_[di][ci] = 1;
      }
      for (std::size_t i = 0; i < nd; ++i) f_int[g[i]] += res.force[static_cast<Eigen::Index>(i)];
      if (k) {
        const int* pos = scatter_[di].data() + start;
        // column-major, matches the scatter order
        const double* ke = cached ? stiffness_[di].data() + start : res.stiffness.data();
        for (std::size_t e = 0; e < n2; ++e)
          if (pos[e] >= 0) values[pos[e]] += ke[e];
      }
    }
  }
  if (!f_int.allFinite()) return Outcome::failure(Status::non_finite, "internal force contains NaN or Inf");
  return {};
}

void add_edge_pressure(const Model& model, const std::vector<Edge>& edges,
                       const std::function<double(const Eigen::Vector2d&)>& p, Eigen::VectorXd& out) {
  // 4-point Gauss-Legendre on [-1, 1]: exact for the polynomial integrands of straight and
  // parabolic edges with the 2 pi r weight.
  constexpr double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  const Mesh& mesh = model.mesh;
  for (const Edge& e : edges) {
    const int ids[3] = {e.a, e.b, e.mid};
    const int n = e.mid >= 0 ? 3 : 2;
    for (int q = 0; q < 4; ++q) {
      const double s = g[q];
      double N[3], dN[3];
      if (n == 2) {
        N[0] = 0.5 * (1 - s), N[1] = 0.5 * (1 + s);
        dN[0] = -0.5, dN[1] = 0.5;
      } else {
        N[0] = 0.5 * s * (s - 1), N[1] = 0.5 * s * (s + 1), N[2] = 1 - s * s;
        dN[0] = s - 0.5, dN[1] = s + 0.5, dN[2] = -2 * s;
      }
      Eigen::Vector2d xq = Eigen::Vector2d::Zero(), t = Eigen::Vector2d::Zero();
      for (int a = 0; a < n; ++a) {
        xq += N[a] * mesh.nodes[ids[a]];
        t += dN[a] * mesh.nodes[ids[a]];
      }
      // Outward normal times the line Jacobian: (t_y, -t_x); the pressure acts along -normal.
      const Eigen::Vector2d nds(t.y(), -t.x());
      const double weight =
          w[q] * (model.formulation == Formulation::axisymmetric ? 2 * std::numbers::pi * xq.x() : 1.0);
      const double pq = p(xq);
      for (int a = 0; a < n; ++a) {
        const int dx = model.dofs.dof(ids[a], field_ux), dy = model.dofs.dof(ids[a], field_uy);
        if (dx >= 0) out[dx] += -pq * N[a] * nds.x() * weight;
        if (dy >= 0) out[dy] += -pq * N[a] * nds.y() * weight;
      }
    }
  }
}

void add_edge_pressure(const Model& model, const std::vector<Edge>& edges, double p, Eigen::VectorXd& out) {
  add_edge_pressure(
      model, edges, [p](const Eigen::Vector2d&) { return p; }, out);
}

} // namespace stratum
