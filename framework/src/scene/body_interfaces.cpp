#include "stratum/body_interfaces.hpp"

#include "scene/domain_points.hpp"
#include "scene/plugin_table.hpp"
#include "scene/scene.hpp"
#include "scene/schemas.hpp"
#include "scene_interfaces.hpp"
#include "toml_check.hpp"

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

std::vector<InterfacePoint> interface_points(const Model& model, const Domain& dm) {
  std::vector<InterfacePoint> pts;
  if (!dm.law.contact) return pts;
  std::vector<int> nodes;
  Eigen::MatrixXd x, xp;
  for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
    const int c = dm.cells[ci];
    if (!model.is_active(c)) continue; // output skips cells removed or not yet placed
    model.cell_nodes(c, nodes, x);
    dm.element->point_coordinates(model.element_data(c, x), xp);
    for (std::size_t p = dm.first_point[ci]; p < dm.first_point[ci + 1]; ++p) {
      const auto slot = dm.states.committed(p);
      InterfacePoint ip;
      ip.x = xp.row(static_cast<Eigen::Index>(p - dm.first_point[ci])).transpose();
      ip.traction = Vec2(slot.stress()[0], slot.stress()[1]);
      ip.jump = Vec2(slot.strain()[0], slot.strain()[1]);
      ip.state = dm.law.contact->state(ip.traction, slot.history());
      ip.cell = c;
      pts.push_back(ip);
    }
  }
  if (!pts.empty())
    for (auto& p : pts) p.s = (p.x - pts.front().x).norm();
  return pts;
}

void write_interface_csv(const std::vector<InterfacePoint>& points, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw Error("cannot write interface CSV file '" + path + "'");
  out << "s,x,y,shear_traction,normal_traction,slip,opening,status\n";
  static const char* names[] = {"stick", "slip", "open"};
  char buf[256];
  for (const auto& p : points) {
    std::snprintf(buf, sizeof buf, "%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,", p.s, p.x.x(), p.x.y(),
                  p.traction[0], p.traction[1], p.jump[0], p.jump[1]);
    out << buf << names[static_cast<int>(p.state)] << '\n';
  }
  if (!out) throw Error("cannot write interface CSV file '" + path + "'");
}

void append_interface_fields(const Model& model, std::vector<OutputArray>& ip_fields) {
  OutputArray tr{"interface_traction", 2, {}, {"shear", "normal"}},
      jump{"interface_jump", 2, {}, {"slip", "opening"}}, status{"interface_status", 1, {}};
  for (const auto& dm : model.domains) {
    if (!dm.law.contact) {
      std::size_t n = 0;
      for (std::size_t ci = 0; ci < dm.cells.size(); ++ci)
        if (model.is_active(dm.cells[ci])) n += dm.first_point[ci + 1] - dm.first_point[ci];
      tr.values.insert(tr.values.end(), 2 * n, 0.0);
      jump.values.insert(jump.values.end(), 2 * n, 0.0);
      status.values.insert(status.values.end(), n, -1.0);
      continue;
    }
    for (const auto& p : interface_points(model, dm)) {
      tr.values.insert(tr.values.end(), {p.traction[0], p.traction[1]});
      jump.values.insert(jump.values.end(), {p.jump[0], p.jump[1]});
      status.values.push_back(static_cast<double>(static_cast<int>(p.state)));
    }
  }
  ip_fields.push_back(std::move(tr));
  ip_fields.push_back(std::move(jump));
  ip_fields.push_back(std::move(status));
}

// ---------------------------------------------------------------- scene input

namespace {

using io::check_table;
using io::location;
using io::require_string;

template <class Map> std::string names_of(const Map& m, std::string_view name = {}) {
  std::string s;
  for (const auto& [k, v] : m) s += (s.empty() ? "" : ", ") + k;
  return (s.empty() ? "(none)" : s) + (name.empty() ? "" : did_you_mean(name, m));
}

} // namespace

void scene::read_interfaces(const toml::table& root, PluginCatalog& catalog, Registry& registry, Scene& sc) {
  // [contact_laws.<name>]
  std::map<std::string, std::size_t> law_by_name;
  if (const toml::node* n = root.get("contact_laws")) {
    const auto* laws = n->as_table();
    if (!laws) throw Error(location(*n), "contact_laws must be a table of [contact_laws.<name>] tables");
    const Schema law_keys = scene::contact_law_schema();
    for (auto&& [key, value] : *laws) {
      const std::string name(key.str());
      const std::string ctx = "[contact_laws." + name + "]";
      const auto* t = value.as_table();
      if (!t) throw Error(location(value), ctx + " must be a table");
      const std::string model_name = require_string(*t, "model", ctx);
      sc.contact_laws.push_back(
          {name, scene::plugin_table<ContactLaw>(catalog, registry, model_name, location(*t->get("model")),
                                                 ctx + " model = \"" + model_name + "\"", *t, ctx,
                                                 scene::key_names(law_keys), sc.units)});
      law_by_name[name] = sc.contact_laws.size() - 1;
    }
  }

  // [[interfaces]]
  const toml::node* list = root.get("interfaces");
  if (!list) return;
  const auto* arr = list->as_array();
  if (!arr) throw Error(location(*list), "interfaces must be an array of tables [[interfaces]]");
  int index = 0;
  const Schema interface_keys = scene::interface_schema();
  for (const auto& entry : *arr) {
    ++index;
    const auto* t = entry.as_table();
    if (!t) throw Error(location(entry), "interfaces entries must be tables [[interfaces]]");
    InterfaceSpec f;
    f.context = "[[interfaces]] #" + std::to_string(index);
    const std::string& ctx = f.context;
    f.at = location(*t);
    f.edges = require_string(*t, "edges", ctx);
    f.element = require_string(*t, "element", ctx);
    const std::string law = require_string(*t, "law", ctx);
    f.edges_at = location(*t->get("edges"));
    f.element_at = location(*t->get("element"));
    f.name = f.edges;
    if (const auto* v = t->get("name")) {
      if (!v->is_string()) throw Error(location(*v), ctx + " name must be a string");
      f.name = v->as_string()->get();
    }
    if (const auto* v = t->get("cells")) {
      if (!v->is_string()) throw Error(location(*v), ctx + " cells must be a string (a cell set)");
      f.cells = v->as_string()->get();
      f.cells_at = location(*v);
    }
    if (const auto* v = t->get("csv")) {
      if (!v->is_boolean()) throw Error(location(*v), ctx + " csv must be true or false");
      f.csv = v->as_boolean()->get();
    }
    auto lw = law_by_name.find(law);
    if (lw == law_by_name.end())
      throw Error(location(*t->get("law")),
                  ctx + " law = \"" + law +
                      "\" is not defined; defined [contact_laws]: " + names_of(law_by_name, law));
    f.law_index = lw->second;
    f.plugin = scene::plugin_table<Element>(catalog, registry, f.element, f.element_at,
                                            ctx + " element = \"" + f.element + "\"", *t, ctx,
                                            scene::key_names(interface_keys), sc.units);
    scene::follow_formulation(f.plugin.factory->schema, *t, f.plugin.params, sc.settings.formulation, ctx);
    sc.interfaces.push_back(std::move(f));
  }
}

void build_scene_interfaces(const scene::Scene& sc, Model& model, SceneInterfaces& out) {
  for (const auto& law : sc.contact_laws) out.laws.push_back(law.plugin.create());
  for (const auto& f : sc.interfaces) {
    const std::string& ctx = f.context;
    auto es = model.mesh.edge_sets.find(f.edges);
    if (es == model.mesh.edge_sets.end())
      throw Error(f.edges_at, ctx + " edges = \"" + f.edges + "\" is not an edge set of the mesh; known: " +
                                  names_of(model.mesh.edge_sets, f.edges));
    std::vector<int> body2;
    if (!f.cells.empty()) {
      auto cs = model.mesh.cell_sets.find(f.cells);
      if (cs == model.mesh.cell_sets.end())
        throw Error(f.cells_at, ctx + " cells = \"" + f.cells + "\" is not a cell set of the mesh; known: " +
                                    names_of(model.mesh.cell_sets, f.cells));
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
