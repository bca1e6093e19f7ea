#include "stratum/model.hpp"

#include "worker_pool.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace stratum {

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

void Model::cell_nodes(int cell, std::vector<int>& nodes, Eigen::MatrixX2d& x) const {
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
  std::vector<char> fixed(constrained);
  fixed.resize(mesh.nodes.size() * DofMap::per_node, 0);
  std::vector<char> used(mesh.nodes.size(), 0);
  for (const auto& dm : domains)
    for (int c : dm.cells)
      if (is_active(c))
        for (int n : mesh.cells[c].nodes)
          if (n >= 0) used[n] = 1;
  for (std::size_t n = 0; n < used.size(); ++n)
    if (!used[n]) fixed[2 * n] = fixed[2 * n + 1] = 1;
  dofs.build(fixed);
}

bool Model::symmetric() const {
  for (const auto& dm : domains) {
    if (dm.law.material && !dm.law.material->symmetric_tangent()) return false;
    if (dm.law.contact && !dm.law.contact->symmetric_tangent()) return false;
  }
  return true;
}

Assembler::Assembler(const Model& model, bool reuse_linear_stiffness, int threads) {
  const int nf = model.dofs.free_count;
  const auto nnodes = model.mesh.nodes.size();
  // Node adjacency through cells of every domain, then the DOF pattern from it.
  std::vector<std::vector<int>> adj(nnodes);
  std::vector<int> nodes;
  for (const auto& dm : model.domains)
    for (int c : dm.cells) {
      if (!model.is_active(c)) continue;
      nodes.clear();
      for (int n : model.mesh.cells[c].nodes)
        if (n >= 0) nodes.push_back(n);
      for (int a : nodes)
        for (int b : nodes) adj[a].push_back(b);
    }
  for (auto& v : adj) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  // Column-major pattern: column j (free DOF of node b) holds rows of free DOFs of nodes adjacent to b.
  std::vector<int> col_node(nf), col_comp(nf);
  for (std::size_t n = 0; n < nnodes; ++n)
    for (int c = 0; c < DofMap::per_node; ++c) {
      const int e = model.dofs.eq[n * DofMap::per_node + c];
      if (e >= 0) col_node[e] = static_cast<int>(n), col_comp[e] = c;
    }
  std::vector<int> outer(nf + 1, 0);
  for (int j = 0; j < nf; ++j) {
    int count = 0;
    for (int a : adj[col_node[j]])
      for (int c = 0; c < DofMap::per_node; ++c) count += model.dofs.eq[a * DofMap::per_node + c] >= 0;
    outer[j + 1] = outer[j] + count;
  }
  std::vector<int> inner(outer[nf]);
  for (int j = 0; j < nf; ++j) {
    int k = outer[j];
    for (int a : adj[col_node[j]])
      for (int c = 0; c < DofMap::per_node; ++c) {
        const int e = model.dofs.eq[a * DofMap::per_node + c];
        if (e >= 0) inner[k++] = e;
      }
    std::sort(inner.begin() + outer[j], inner.begin() + outer[j + 1]);
  }
  pattern_.resize(nf, nf);
  pattern_.resizeNonZeros(outer[nf]);
  std::copy(outer.begin(), outer.end(), pattern_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), pattern_.innerIndexPtr());
  std::fill(pattern_.valuePtr(), pattern_.valuePtr() + outer[nf], 0.0);
  adj.clear();
  adj.shrink_to_fit();

  // Scatter indices: for each cell, (2n)^2 positions into the value array (column-major local order).
  scatter_.resize(model.domains.size());
  scatter_start_.resize(model.domains.size());
  stiffness_.resize(model.domains.size());
  filled_.resize(model.domains.size());
  std::vector<int> ldof;
  for (std::size_t di = 0; di < model.domains.size(); ++di) {
    const auto& dm = model.domains[di];
    auto& sc = scatter_[di];
    auto& st = scatter_start_[di];
    st.assign(dm.cells.size() + 1, 0);
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const int n = model.mesh.cells[dm.cells[ci]].count() * DofMap::per_node;
      st[ci + 1] = st[ci] + static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    }
    sc.assign(st.back(), -1);
    if (reuse_linear_stiffness && dm.element->constant_stiffness(dm.law)) {
      stiffness_[di].assign(st.back(), 0.0);
      filled_[di].assign(dm.cells.size(), 0);
    }
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      if (!model.is_active(dm.cells[ci])) continue;
      ldof.clear();
      for (int node : model.mesh.cells[dm.cells[ci]].nodes)
        if (node >= 0)
          for (int c = 0; c < DofMap::per_node; ++c)
            ldof.push_back(model.dofs.eq[node * DofMap::per_node + c]);
      const std::size_t n = ldof.size();
      int* out = sc.data() + st[ci];
      for (std::size_t b = 0; b < n; ++b) {
        const int col = ldof[b];
        for (std::size_t a = 0; a < n; ++a) {
          const int row = ldof[a];
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
      const auto nd = static_cast<Eigen::Index>(nodes.size() * DofMap::per_node);
      sc.ue.resize(nd);
      sc.une.resize(nd);
      for (std::size_t i = 0; i < nodes.size(); ++i)
        for (int c = 0; c < DofMap::per_node; ++c) {
          const auto g = static_cast<Eigen::Index>(nodes[i]) * DofMap::per_node + c;
          sc.ue[static_cast<Eigen::Index>(i) * DofMap::per_node + c] = u[g];
          sc.une[static_cast<Eigen::Index>(i) * DofMap::per_node + c] = model.u[g];
        }
      const ElementData data{cell, model.mesh.cells[cell].shape(), &sc.x};
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
      const std::vector<int>& nodes = nodes_[t];
      const auto nd = static_cast<std::size_t>(nodes.size() * DofMap::per_node);
      const std::size_t n2 = nd * nd;
      const std::size_t start = scatter_start_[di][ci];
      const bool cached = k && !filled_[di].empty() && filled_[di][ci];
      if (k && !cached && !filled_[di].empty()) {
        std::copy(res.stiffness.data(), res.stiffness.data() + n2, stiffness_[di].data() + start);
        filled_[di][ci] = 1;
      }
      for (std::size_t i = 0; i < nodes.size(); ++i)
        for (int c = 0; c < DofMap::per_node; ++c)
          f_int[static_cast<Eigen::Index>(nodes[i]) * DofMap::per_node + c] +=
              res.force[static_cast<Eigen::Index>(i) * DofMap::per_node + c];
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

void add_edge_pressure(const Mesh& mesh, const std::vector<Edge>& edges,
                       const std::function<double(const Eigen::Vector2d&)>& p, Formulation f,
                       Eigen::VectorXd& out) {
  // 4-point Gauss-Legendre on [-1, 1]: exact for the polynomial integrands of straight and
  // parabolic edges with the 2 pi r weight.
  constexpr double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
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
      const double weight = w[q] * (f == Formulation::axisymmetric ? 2 * std::numbers::pi * xq.x() : 1.0);
      const double pq = p(xq);
      for (int a = 0; a < n; ++a) {
        out[ids[a] * 2 + 0] += -pq * N[a] * nds.x() * weight;
        out[ids[a] * 2 + 1] += -pq * N[a] * nds.y() * weight;
      }
    }
  }
}

void add_edge_pressure(const Mesh& mesh, const std::vector<Edge>& edges, double p, Formulation f,
                       Eigen::VectorXd& out) {
  add_edge_pressure(
      mesh, edges, [p](const Eigen::Vector2d&) { return p; }, f, out);
}

} // namespace stratum
