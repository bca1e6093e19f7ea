#include "model/body_interfaces.hpp"

#include "model/domain_points.hpp"
#include "model/scene_interfaces.hpp"
#include "scene/scene.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

namespace stratum {

InterfaceSplit split_interface(Mesh& mesh, const std::string& name, const std::vector<Edge>& edges,
                               const std::vector<int>& body2_cells, InterfaceCells kind) {
  const std::string ctx = "interface '" + name + "'";
  if (edges.empty()) throw Error(ctx + ": the edge set is empty");
  if (mesh.cell_sets.count(name) || mesh.node_sets.count(name + ".side1") ||
      mesh.node_sets.count(name + ".side2"))
    throw Error(ctx + ": the mesh already has a set of this name");
  const auto nn = static_cast<int>(mesh.nodes.size());
  // Chains along the interface: next/prev of every node in the a -> (mid) -> b order.
  std::map<int, int> next, prev;
  std::set<int> nodes;
  for (const Edge& e : edges) {
    if (e.a < 0 || e.b < 0 || e.a >= nn || e.b >= nn || e.mid >= nn || e.a == e.b)
      throw Error(ctx + ": edge {" + std::to_string(e.a) + ", " + std::to_string(e.b) +
                  "} refers to a missing node");
    std::vector<int> seq{e.a};
    if (e.mid >= 0) seq.push_back(e.mid);
    seq.push_back(e.b);
    for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
      if (next.count(seq[k]) || prev.count(seq[k + 1]))
        throw Error(ctx + ": node " + std::to_string(seq[k]) +
                    " starts two edges; the edges must form non-branching chains a -> b");
      next[seq[k]] = seq[k + 1];
      prev[seq[k + 1]] = seq[k];
    }
    nodes.insert(seq.begin(), seq.end());
  }
  InterfaceSplit out;
  std::map<int, int> copy;
  for (int n : nodes) {
    const auto c = static_cast<int>(mesh.nodes.size());
    mesh.nodes.push_back(mesh.nodes[static_cast<std::size_t>(n)]);
    copy[n] = c;
    out.side1.push_back(n);
    out.side2.push_back(c);
  }
  for (int c : body2_cells) {
    if (c < 0 || static_cast<std::size_t>(c) >= mesh.cells.size())
      throw Error(ctx + ": body-2 cell " + std::to_string(c) + " does not exist");
    for (int& n : mesh.cells[static_cast<std::size_t>(c)].nodes)
      if (auto it = copy.find(n); it != copy.end()) n = it->second;
  }
  std::vector<Edge> side2_edges;
  for (const Edge& e : edges)
    side2_edges.push_back(Edge{copy[e.b], copy[e.a], e.mid >= 0 ? copy[e.mid] : -1});
  if (kind == InterfaceCells::line) {
    for (const Edge& e : edges) {
      Cell cell;
      cell.type = CellType::line_interface;
      cell.nodes[0] = e.a, cell.nodes[1] = e.b, cell.nodes[2] = copy[e.b], cell.nodes[3] = copy[e.a];
      if (e.mid >= 0) cell.nodes[4] = e.mid, cell.nodes[6] = copy[e.mid];
      out.cells.push_back(static_cast<int>(mesh.cells.size()));
      mesh.cells.push_back(cell);
    }
  } else {
    // On 3-node edges the pair also says whether its node is a midside node (slot 4) or a corner
    // (slot 5), both filled with the partner again: contact2 then uses the consistent weights of
    // quadratic edges (1/6, 2/3, 1/6) instead of lumping half-segments.
    std::set<int> mids;
    bool quadratic = false;
    for (const Edge& e : edges)
      if (e.mid >= 0) quadratic = true, mids.insert(e.mid);
    for (int n : nodes) {
      Cell cell;
      cell.type = CellType::node_pair;
      cell.nodes[0] = n, cell.nodes[1] = copy[n];
      cell.nodes[2] = prev.count(n) ? prev[n] : n;
      cell.nodes[3] = next.count(n) ? next[n] : n;
      if (quadratic) cell.nodes[mids.count(n) ? 4 : 5] = copy[n];
      out.cells.push_back(static_cast<int>(mesh.cells.size()));
      mesh.cells.push_back(cell);
    }
  }
  mesh.cell_sets[name] = out.cells;
  mesh.node_sets[name + ".side1"] = out.side1;
  mesh.add_edge_set(name + ".side2", std::move(side2_edges)); // also node set name.side2 (sorted)
  return out;
}

void build_scene_interfaces(const scene::Scene& sc, Model& model, SceneInterfaces& out) {
  for (const auto& law : sc.contact_laws) out.laws.push_back(law.plugin.create());
  for (const auto& f : sc.interfaces) {
    const std::string& ctx = f.context;
    auto es = model.mesh.edge_sets.find(f.edges);
    if (es == model.mesh.edge_sets.end())
      throw Error(f.edges_at, ctx + " edges = \"" + f.edges + "\" is not an edge set of the mesh; known: " +
                                  key_list(model.mesh.edge_sets, f.edges));
    std::vector<int> body2;
    if (!f.cells.empty()) {
      auto cs = model.mesh.cell_sets.find(f.cells);
      if (cs == model.mesh.cell_sets.end())
        throw Error(f.cells_at, ctx + " cells = \"" + f.cells + "\" is not a cell set of the mesh; known: " +
                                    key_list(model.mesh.cell_sets, f.cells));
      body2 = cs->second;
    }
    out.elements.push_back(f.plugin.create());
    // The element says which interface cells it works on (stratum/element.hpp).
    InterfaceCells kind = InterfaceCells::node_pairs;
    switch (out.elements.back()->cells()) {
    case ElementCells::node_pairs:
      kind = InterfaceCells::node_pairs;
      break;
    case ElementCells::interface_lines:
      kind = InterfaceCells::line;
      break;
    case ElementCells::area:
      throw Error(
          f.element_at,
          ctx + " element = \"" + f.element +
              "\" works on area cells (give it in [[domains]]); allowed: an element whose cells are "
              "node pairs or interface lines, e.g. contact2, interface_line (a thin_layer is a row of "
              "thin cells given as [[domains]] with a material)");
    }
    InterfaceSplit split;
    try {
      split = split_interface(model.mesh, f.name, es->second, body2, kind);
    } catch (const Error& e) {
      throw Error(f.at, ctx + ": " + e.message());
    }
    Domain dm;
    dm.name = f.name;
    dm.set_id = static_cast<int>(model.domains.size());
    dm.element = out.elements.back().get();
    dm.law.contact = out.laws[f.law_index].get();
    dm.cells = split.cells;
    const ContactLaw& law = *dm.law.contact;
    place_points(dm, model, law.history_size(), ctx, f.element_at,
                 [&](std::span<double> h) { law.init_history(h); });
    out.interfaces.push_back({f.name, model.domains.size(), f.csv});
    model.domains.push_back(std::move(dm));
  }
}

} // namespace stratum
