// [[domains]] and [[constraints]] built against the mesh: the plugin objects of each domain, its
// integration points with their first state, and the DOF map with the constrained unknowns.
#include "model/scene_model.hpp"
#include "model/undrained_material.hpp"

#include "model/domain_points.hpp"
#include "suggest.hpp"

#include <map>

namespace stratum {

namespace {

/// A located line when cells of the mesh belong to no [[domains]] entry (owner < 0): the count,
/// the first cell indices and the cell sets that lie wholly outside every domain; "" when none.
std::string domain_cover(const Mesh& mesh, const std::vector<int>& owner, const SourceLocation& at) {
  std::vector<int> lost;
  for (std::size_t c = 0; c < owner.size(); ++c)
    if (owner[c] < 0) lost.push_back(static_cast<int>(c));
  if (lost.empty()) return {};
  std::string cells;
  for (std::size_t i = 0; i < lost.size() && i < 10; ++i) cells += (i ? ", " : "") + std::to_string(lost[i]);
  if (lost.size() > 10) cells += ", ...";
  std::string sets; // the sets none of whose cells has a domain: what the user would add
  for (const auto& [name, members] : mesh.cell_sets) {
    if (members.empty() || name == "all") continue;
    bool none = true;
    for (int c : members) none = none && owner[static_cast<std::size_t>(c)] < 0;
    if (none) sets += (sets.empty() ? "" : ", ") + name;
  }
  return at.str() + " " + std::to_string(lost.size()) + " of " + std::to_string(owner.size()) +
         " cells belong to no [[domains]] entry (cells " + cells + ")" +
         (sets.empty() ? std::string() : "; cell sets without a domain: " + sets) +
         "; they stay out of the model for the whole run (a cavity); give them a [[domains]] entry "
         "(cells, element, material) if they are to carry load";
}

} // namespace

namespace {

/// The material of a domain whose element takes none: holds no history and refuses every update.
class NoMaterial final : public Material {
public:
  [[nodiscard]] Outcome update(const MaterialInput& in, MaterialOutput&) const override {
    return Outcome::failure(Status::material_failure, "element " + std::to_string(in.where.element) +
                                                          " called the material of a domain that has none");
  }
  [[nodiscard]] bool is_linear() const override { return true; }
};

} // namespace

void SceneModel::build_domains(const scene::Scene& sc) {
  if (sc.domains.empty()) throw Error(sc.at, "scene has no [[domains]]: nothing to analyse");
  for (const auto& m : sc.materials) {
    materials.push_back(m.plugin.create());
    material_by_name[m.name] = materials.back().get();
  }
  std::vector<int> owner(model.mesh.cells.size(), -1);
  for (std::size_t i = 0; i < sc.domains.size(); ++i) {
    const scene::DomainSpec& d = sc.domains[i];
    const std::string& ctx = d.context;
    auto cs = model.mesh.cell_sets.find(d.cells);
    if (cs == model.mesh.cell_sets.end())
      throw Error(d.cells_at, ctx + " cells = \"" + d.cells + "\" is not a cell set of the mesh; known: " +
                                  key_list(model.mesh.cell_sets, d.cells));
    elements.push_back(d.plugin.create());
    if (elements.back()->cells() != ElementCells::area)
      throw Error(d.element_at,
                  ctx + " element = \"" + d.element +
                      "\" works on interface cells (node pairs or lines), which an [[interfaces]] entry "
                      "creates along an edge set; allowed here: an element of area cells, e.g. quad, tri");
    Domain dm;
    dm.name = d.cells;
    dm.set_id = static_cast<int>(i);
    dm.element = elements.back().get();
    if (elements.back()->needs_material() && d.material.empty())
      throw Error(d.element_at,
                  ctx + " element = \"" + d.element +
                      "\" needs a material: add material = \"<name of a [materials.<name>] table>\"");
    if (!elements.back()->needs_material() && !d.material.empty())
      throw Error(d.material_at, ctx + " element = \"" + d.element +
                                     "\" takes no material; remove material = \"" + d.material + "\"");
    if (d.material.empty()) {
      // The element takes none: a placeholder that no element may call (history size 0).
      materials.push_back(std::make_unique<NoMaterial>());
      dm.law.material = materials.back().get();
    } else {
      dm.law.material = materials[d.material_index].get();
    }
    dm.cells = cs->second;
    dm.drainage = d.drainage;
    if (d.drainage != "drained" && !dm.cells.empty()) {
      const Cell& first = model.mesh.cells[static_cast<std::size_t>(dm.cells.front())];
      for (const Field& f : elements.back()->node_fields(first.type, first.shape()).fields)
        if (f.unit != "m")
          throw Error(d.drainage_at, ctx + " drainage = \"" + d.drainage + "\": element = \"" + d.element +
                                         "\" carries the pore pressure " + f.name +
                                         " itself (a static stage loads it undrained, a consolidation stage "
                                         "lets it drain); remove drainage, or use a displacement element");
    }
    if (d.drainage == "undrained") {
      materials.push_back(std::make_unique<UndrainedMaterial>(*dm.law.material, d.fluid_stiffness));
      dm.law.material = materials.back().get();
    }
    for (const int cell : dm.cells) {
      if (owner[cell] >= 0)
        throw Error(d.cells_at, ctx + " cell " + std::to_string(cell) + " already belongs to [[domains]] #" +
                                    std::to_string(owner[cell] + 1));
      owner[cell] = static_cast<int>(i);
    }
    const Material& material = *dm.law.material;
    place_points(dm, model, material.history_size(), ctx, d.element_at,
                 [&](std::span<double> h) { material.init_history(Vec6::Zero(), h); });
    model.domains.push_back(std::move(dm));
  }
  // A cell that no domain covers has no element and no material: it stays out of the model for
  // the whole run (found on 997ba04: `check` said ok, then the run failed with a Newton message).
  // A warning, not an error: leaving cells of a generated mesh out is a way to model a cavity
  // (the pile mesher's pile cells in a soil-only analysis).
  if (auto w = domain_cover(model.mesh, owner, sc.domains_at); !w.empty()) warnings.push_back(std::move(w));
}

void SceneModel::build_constraints(const scene::Scene& sc) {
  // The unknowns the domains' elements declare (every domain and interface is built by now).
  model.layout_dofs();
  const auto ndof = static_cast<Eigen::Index>(model.dofs.total());
  std::vector<char> fixed(static_cast<std::size_t>(ndof), 0);
  model.prescribed = Eigen::VectorXd::Zero(ndof);
  for (const auto& c : sc.constraints) {
    auto ns = model.mesh.node_sets.find(c.nodes);
    if (ns == model.mesh.node_sets.end())
      throw Error(c.nodes_at,
                  "[[constraints]] nodes = \"" + c.nodes +
                      "\" is not a node set of the mesh; known: " + key_list(model.mesh.node_sets, c.nodes));
    for (std::size_t k = 0; k < 2; ++k) {
      if (!c.value[k]) continue;
      const double v = *c.value[k];
      for (int n : ns->second) {
        const int dof = model.dofs.dof(n, field_ux + static_cast<int>(k));
        if (dof < 0) continue; // a node no element gives this unknown
        const auto d = static_cast<std::size_t>(dof);
        if (fixed[d] && model.prescribed[static_cast<Eigen::Index>(d)] != v)
          throw Error(c.value_at[k], "[[constraints]] " + std::string(k == 0 ? "ux" : "uy") + " on node " +
                                         std::to_string(n) + " contradicts an earlier constraint");
        fixed[d] = 1;
        model.prescribed[static_cast<Eigen::Index>(d)] = v;
      }
    }
  }
  for (const auto& c : sc.constraints) {
    if (c.field.empty()) continue;
    const int f = model.dofs.field(c.field);
    if (f < 0)
      throw Error(c.field_at,
                  "[[constraints]] field = \"" + c.field +
                      "\" is not a field of the scene's elements; the scene has: " + model.dofs.field_list());
    int carried = 0;
    for (int n : model.mesh.node_sets.at(c.nodes)) {
      const int dof = model.dofs.dof(n, f);
      if (dof < 0) continue;
      ++carried;
      const auto d = static_cast<std::size_t>(dof);
      if (fixed[d] && model.prescribed[dof] != c.field_value)
        throw Error(c.field_value_at, "[[constraints]] " + c.field + " on node " + std::to_string(n) +
                                          " contradicts an earlier constraint");
      fixed[d] = 1;
      model.prescribed[dof] = c.field_value;
    }
    if (carried == 0)
      throw Error(c.field_at,
                  "[[constraints]] field = \"" + c.field + "\": no node of \"" + c.nodes + "\" carries it");
  }
  // Nodes that no active cell uses carry no stiffness: rebuild_dofs() fixes them too.
  model.constrained = fixed;
  model.active.assign(model.mesh.cells.size(), 1);
  model.rebuild_dofs();
  model.u = Eigen::VectorXd::Zero(ndof);
  model.reactions = Eigen::VectorXd::Zero(ndof);
}

} // namespace stratum
