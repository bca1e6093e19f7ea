// [mesh] built: the generator run or the file read, then the mesh checked against the scene.
#include "model/scene_model.hpp"

#include "meshers/builtin_generators.hpp"
#include "stratum/mesh_io.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <numeric>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

// A Gmsh file's physical groups are names the user chose; one that no string of the scene names
// is likely a misspelling elsewhere (or a group left over). Generated meshes are not looked at:
// their generators define many sets a scene does not need (the pile mesher some forty).
void SceneModel::unused_physical_groups(const std::set<std::string>& named, const SourceLocation& at,
                                        const std::string& file) {
  std::set<std::string> unused;
  for (const auto* sets : {&model.mesh.cell_sets, &model.mesh.node_sets})
    for (const auto& [name, v] : *sets)
      if (name != "all" && !named.count(name)) unused.insert(name);
  for (const auto& [name, v] : model.mesh.edge_sets)
    if (!named.count(name)) unused.insert(name);
  if (unused.empty()) return;
  std::string list;
  for (const auto& n : unused) list += (list.empty() ? "" : ", ") + n;
  std::ostringstream o;
  o << at.str() << " [mesh] file = \"" << file << "\": " << unused.size() << " physical group"
    << (unused.size() == 1 ? "" : "s") << " that the scene never names: " << list
    << " (harmless if left over; otherwise check the set names)";
  warnings.push_back(o.str());
}

namespace {

/// Joins the nodes that a mapping put at one place (the seam of a polar ring): cells, node and
/// edge sets then refer to the first of them. A cell two of whose own nodes meet (a ring that
/// starts at radius 0) is refused.
void join_coincident_nodes(Mesh& mesh, const SourceLocation& at) {
  const std::size_t nn = mesh.nodes.size();
  if (nn == 0) return;
  Eigen::Vector2d lo = mesh.nodes[0], hi = mesh.nodes[0];
  for (const auto& x : mesh.nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double tol = 1e-9 * std::max((hi - lo).norm(), 1e-300);
  std::vector<int> order(nn);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return mesh.nodes[static_cast<std::size_t>(a)].x() < mesh.nodes[static_cast<std::size_t>(b)].x();
  });
  std::vector<int> to(nn);
  std::iota(to.begin(), to.end(), 0);
  bool any = false;
  for (std::size_t i = 0; i < nn; ++i) {
    const auto a = static_cast<std::size_t>(order[i]);
    for (std::size_t j = i + 1; j < nn; ++j) {
      const auto b = static_cast<std::size_t>(order[j]);
      if (mesh.nodes[b].x() - mesh.nodes[a].x() > tol) break;
      if ((mesh.nodes[b] - mesh.nodes[a]).norm() <= tol &&
          to[std::max(a, b)] == static_cast<int>(std::max(a, b))) {
        to[std::max(a, b)] = to[std::min(a, b)];
        any = true;
      }
    }
  }
  if (!any) return;
  std::vector<int> index(nn, -1);
  std::vector<Eigen::Vector2d> kept;
  for (std::size_t n = 0; n < nn; ++n)
    if (to[n] == static_cast<int>(n)) index[n] = static_cast<int>(kept.size()), kept.push_back(mesh.nodes[n]);
  const auto map = [&](int n) {
    return n < 0 ? n : index[static_cast<std::size_t>(to[static_cast<std::size_t>(n)])];
  };
  for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
    auto& nodes = mesh.cells[c].nodes;
    for (int& n : nodes) n = map(n);
    std::vector<int> corners;
    for (int n : nodes)
      if (n >= 0) corners.push_back(n);
    std::sort(corners.begin(), corners.end());
    if (std::adjacent_find(corners.begin(), corners.end()) != corners.end())
      throw Error(at,
                  "[mesh] transform = \"polar\": cell " + std::to_string(c) +
                      " collapses (two of its nodes map to one point, as at radius 0); start the ring at a "
                      "radius > 0");
  }
  for (auto& [name, set] : mesh.node_sets) {
    for (int& n : set) n = map(n);
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
  }
  for (auto& [name, edges] : mesh.edge_sets)
    for (Edge& e : edges) e.a = map(e.a), e.b = map(e.b), e.mid = map(e.mid);
  mesh.nodes = std::move(kept);
}

} // namespace

void SceneModel::build_mesh(const scene::Scene& sc) {
  const scene::MeshSpec& spec = sc.mesh;
  switch (spec.source) {
  case scene::MeshSpec::Source::blocks:
    try {
      model.mesh = generate_blocks(spec.blocks, spec.nodes_per_cell);
    } catch (const Error& e) {
      if (e.where().known()) throw;
      // The generator names the block; locate the first block table that carries that name.
      SourceLocation at = spec.at;
      for (std::size_t i = 0; i < spec.blocks.size(); ++i)
        if (e.message().find("'" + spec.blocks[i].name + "'") != std::string::npos) {
          at = spec.block_at[i];
          if (e.message().find("used more than once") == std::string::npos) break;
        }
      throw Error(at, "[mesh] " + e.message());
    }
    if (spec.polar) {
      for (auto& x : model.mesh.nodes) {
        const double r = x.x(), t = x.y() * std::numbers::pi / 180.0;
        x = Eigen::Vector2d(r * std::cos(t), r * std::sin(t));
      }
      // A ring over 360 degrees meets itself: its seam's nodes are one.
      join_coincident_nodes(model.mesh, spec.at);
    }
    break;
  case scene::MeshSpec::Source::generator: {
    const auto mesher = spec.mesher.create();
    try {
      model.mesh = mesher->generate(MeshRequest{model.formulation, spec.nodes_per_cell});
    } catch (const Error& e) {
      if (e.where().known()) throw;
      throw Error(spec.generator_table_at, e.message());
    }
    break;
  }
  case scene::MeshSpec::Source::gmsh: {
    const fs::path f = spec.file_path;
    std::error_code ec;
    if (!fs::is_regular_file(f, ec))
      throw Error(spec.file_at,
                  "[mesh] file = \"" + spec.file + "\": " +
                      (fs::exists(f, ec) ? "is not a regular file (a folder, a FIFO or a device)"
                                         : "no such file ('" + f.string() + "')") +
                      "; give a Gmsh .msh 4.1 ASCII file");
    model.mesh = read_gmsh(f.string());
    unused_physical_groups(sc.strings, spec.file_at, spec.file);
    break;
  }
  }
  model.mesh.check();
  if (!settings.pile_cells.empty() && !model.mesh.cell_sets.count(settings.pile_cells))
    throw Error(sc.settings.pile_cells_at,
                "[output] pile_cells = \"" + settings.pile_cells +
                    "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
  if (model.formulation == Formulation::axisymmetric)
    for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n)
      if (model.mesh.nodes[n].x() < -1e-12)
        throw Error(spec.at, "[mesh] node " + std::to_string(n) + " has a negative radius x = " +
                                 std::to_string(model.mesh.nodes[n].x()) + " in an axisymmetric scene");
}

} // namespace stratum
