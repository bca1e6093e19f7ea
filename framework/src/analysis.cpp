#include "stratum/analysis.hpp"

#include "stratum/mesh_io.hpp"
#include "stratum/step_control.hpp"
#include "stratum/vtk_output.hpp"
#include "toml_check.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

namespace {

using io::check_table;
using io::location;
using io::require_string;
using io::show;

/// Static equilibrium of the model: R(u, lambda) = lambda F_ref - F_int(u).
class StaticProblem final : public NonlinearProblem {
public:
  StaticProblem(Model& m, const Assembler& a, LinearSolver& ls) : m_(m), a_(a), ls_(ls) {
    ref_ = m.restrict_free(m.load_ref);
  }
  Eigen::Index size() const override { return m_.dofs.free_count; }
  Outcome evaluate(const Eigen::VectorXd& u, double lambda, Eigen::VectorXd& r, SparseMatrix* k) override {
    m_.expand(u, lambda, full_);
    Outcome o = a_.assemble(m_, full_, fint_, k);
    if (!o.ok()) return o;
    r.resize(size());
    for (int d = 0; d < m_.dofs.total(); ++d)
      if (const int e = m_.dofs.eq[d]; e >= 0) r[e] = lambda * m_.load_ref[d] - fint_[d];
    return {};
  }
  SparseMatrix make_tangent() const override { return a_.make_matrix(); }
  const Eigen::VectorXd& reference_load() const override { return ref_; }
  LinearSolver& linear_solver() override { return ls_; }
  double force_scale(double lambda) const override {
    return std::max(std::abs(lambda) * m_.load_ref.norm(), fint_.size() ? fint_.norm() : 0.0);
  }
  std::vector<Eigen::Index> node_set_dofs(const std::string& set, int component) const override {
    std::vector<Eigen::Index> v;
    auto it = m_.mesh.node_sets.find(set);
    if (it == m_.mesh.node_sets.end() || component < 0 || component > 1) return v;
    for (int n : it->second)
      if (const int e = m_.dofs.eq[static_cast<std::size_t>(2 * n + component)]; e >= 0) v.push_back(e);
    return v;
  }
  const Eigen::VectorXd& internal_force() const { return fint_; }

private:
  Model& m_;
  const Assembler& a_;
  LinearSolver& ls_;
  Eigen::VectorXd ref_, full_, fint_;
};

/// Tangent (Euler) predictor for a step from lambda_n to lambda: u += K_n^-1 dR/dlambda (lambda -
/// lambda_n), with dR/dlambda (which carries the prescribed-displacement increment through the
/// elements) by a one-sided difference at the converged state. Leaves u unchanged when any part
/// fails; Newton then starts from u_n as without a predictor.
void predict(NonlinearProblem& problem, LinearSolver& ls, double lambda_n, double lambda,
             Eigen::VectorXd& u) {
  SparseMatrix k = problem.make_tangent();
  Eigen::VectorXd r0, r1, du;
  constexpr double eps = 1e-6;
  if (!problem.evaluate(u, lambda_n, r0, &k).ok()) return;
  if (!problem.evaluate(u, lambda_n + eps * (lambda - lambda_n), r1, nullptr).ok()) return;
  if (!ls.factorize(k).ok() || !ls.solve((r1 - r0) / eps, du).ok() || !du.allFinite()) return;
  u += du;
}

Schema analysis_schema() {
  Schema s;
  s.text("formulation", {"axisymmetric", "plane_strain"}, "2D idealisation of the whole scene")
      .defaults_to(std::string("axisymmetric"));
  s.text("solver", {}, "solver plugin that solves each load step; its parameters go in [solver]")
      .defaults_to(std::string("newton"));
  s.text("linear_solver", linear_solver_names(), "sparse direct solver; auto = by size and symmetry")
      .defaults_to(std::string("auto"));
  s.integer("steps", "-", "number of equal load increments from load factor 0 to 1")
      .at_least(1)
      .defaults_to(1LL);
  s.integer("max_cutbacks", "-", "how many times a failed step may be halved before the run stops")
      .at_least(0)
      .at_most(30)
      .defaults_to(4LL);
  // Step control (stratum/step_control.hpp).
  StepSettings d;
  s.real_list("increments", "-", "explicit load-factor increments (the last one repeats); replaces steps")
      .defaults_to(std::vector<double>{});
  s.boolean("automatic", "grow the increment after fast convergence").defaults_to(false);
  s.integer("fast_iterations", "-", "a step converged in at most this many iterations counts as fast")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.fast_iterations));
  s.real("growth", "-", "increment (arc length) factor after a fast step").at_least(1).defaults_to(d.growth);
  s.real("max_increment", "-", "largest grown load increment; 0: the whole range")
      .at_least(0)
      .defaults_to(0.0);
  s.real("arc_length", "-", "path-following solvers: first step size; 0: from the first increment")
      .at_least(0)
      .defaults_to(0.0);
  s.real("max_arc_length", "-", "path-following solvers: largest grown step size; 0: unbounded")
      .at_least(0)
      .defaults_to(0.0);
  s.integer("max_steps", "-", "accepted steps at most (path following stops there, load control fails)")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.max_steps));
  return s;
}

Schema convergence_schema() {
  Schema s;
  Convergence c;
  s.real("force_rtol", "-", "residual force relative to the force scale")
      .greater_than(0)
      .defaults_to(c.force_rtol);
  s.real("force_atol", "kN", "absolute residual force bound").at_least(0).defaults_to(c.force_atol);
  s.real("disp_rtol", "-", "displacement correction relative to the step's displacement")
      .at_least(0)
      .defaults_to(c.disp_rtol);
  s.real("disp_atol", "m", "absolute displacement correction bound").at_least(0).defaults_to(c.disp_atol);
  s.real("energy_rtol", "-", "energy criterion (4.21) of the thesis; 0 disables it")
      .at_least(0)
      .defaults_to(0.0);
  s.real("energy_atol", "kN m", "absolute bound of the energy criterion").at_least(0).defaults_to(0.0);
  s.boolean("displacement_test", "also require the displacement-correction test").defaults_to(false);
  s.integer("max_iterations", "-", "iterations per step before it counts as failed")
      .at_least(1)
      .defaults_to(static_cast<long long>(c.max_iterations));
  return s;
}

Schema mesh_schema() {
  Schema s;
  s.text("generator", {"blocks", "gmsh"}, "structured graded blocks, or a Gmsh file");
  s.text("file", {}, "Gmsh .msh 4.1 ASCII file, relative to the scene file").defaults_to(std::string());
  s.integer("nodes_per_cell", "-", "4 (bilinear) or 8 (serendipity) for generated blocks")
      .at_least(4)
      .at_most(8)
      .defaults_to(8LL);
  s.text("transform", {"none", "polar"},
         "polar maps generated (x, y) to (x cos y, x sin y) with y in degrees: rings and sectors")
      .defaults_to(std::string("none"));
  return s;
}

Schema block_schema() {
  Schema s;
  s.text("name", {}, "cell set name of the block; its edges become <name>.left/right/bottom/top");
  s.real_list("x", "m", "[x0, x1] extent (axisymmetric: radius)");
  s.real_list("y", "m", "[y0, y1] extent (axisymmetric: height)");
  s.integer("nx", "-", "cells along x").at_least(1).defaults_to(1LL);
  s.integer("ny", "-", "cells along y").at_least(1).defaults_to(1LL);
  s.real("grade_x", "-", "last/first cell size along x").greater_than(0).defaults_to(1.0);
  s.real("grade_y", "-", "last/first cell size along y").greater_than(0).defaults_to(1.0);
  return s;
}

Schema output_schema() {
  Schema s;
  s.boolean("vtk", "write .vtu/.pvd files").defaults_to(true);
  s.boolean("integration_points", "write the integration-point cloud (.vtp)").defaults_to(true);
  s.integer("every", "-", "write every n-th step (the last step is always written)")
      .at_least(1)
      .defaults_to(1LL);
  return s;
}

const toml::table& table_at(const toml::table& root, std::string_view key, const std::string& ctx) {
  const toml::node* n = root.get(key);
  if (!n) throw Error(location(root), ctx + " missing required table [" + std::string(key) + "]");
  if (!n->is_table())
    throw Error(location(*n), ctx + " " + std::string(key) + " must be a table, got " + io::type_name(*n));
  return *n->as_table();
}

const toml::table empty_table;

const toml::table& optional_table(const toml::table& root, std::string_view key) {
  const toml::node* n = root.get(key);
  if (!n) return empty_table;
  if (!n->is_table())
    throw Error(location(*n), std::string(key) + " must be a table, got " + io::type_name(*n));
  return *n->as_table();
}

/// Array of tables [[key]] (absent = empty).
std::vector<const toml::table*> table_list(const toml::table& root, std::string_view key) {
  std::vector<const toml::table*> v;
  const toml::node* n = root.get(key);
  if (!n) return v;
  const auto* a = n->as_array();
  if (!a)
    throw Error(location(*n), std::string(key) + " must be an array of tables [[" + std::string(key) + "]]");
  for (const auto& e : *a) {
    if (!e.is_table())
      throw Error(location(e), std::string(key) + " entries must be tables [[" + std::string(key) + "]]");
    v.push_back(e.as_table());
  }
  return v;
}

template <class Map> std::string key_list(const Map& m) {
  std::string s;
  for (const auto& [k, v] : m) s += (s.empty() ? "" : ", ") + k;
  return s.empty() ? "(none)" : s;
}

} // namespace

struct Analysis::Impl {
  std::string path, title;
  RunOptions options;
  std::unique_ptr<PluginCatalog> catalog;
  Registry registry;
  std::vector<std::unique_ptr<Material>> materials;
  std::vector<std::unique_ptr<Element>> elements;
  std::unique_ptr<Solver> solver;
  Model model;
  std::string linear_solver = "auto";
  StepSettings stepping;
  Convergence convergence;
  bool vtk = true, ip_output = true;
  int every = 1;

  void build(const toml::table& root);
  void write_step(VtkSeriesWriter& w, double time) const;
};

void Analysis::Impl::build(const toml::table& root) {
  // ---- top level
  static const std::vector<std::string_view> top_keys{"title", "analysis",  "convergence", "solver",
                                                      "mesh",  "materials", "domains",     "constraints",
                                                      "loads", "output",    "plugins"};
  for (auto&& [key, value] : root) {
    const std::string k(key.str());
    if (std::find(top_keys.begin(), top_keys.end(), k) == top_keys.end()) {
      std::string allowed;
      for (auto t : top_keys) allowed += (allowed.empty() ? "" : ", ") + std::string(t);
      throw Error(location(key.source()), "unknown key '" + k + "' at the top level; allowed: " + allowed);
    }
  }
  if (const auto* t = root.get("title")) {
    if (!t->is_string()) throw Error(location(*t), "title must be a string");
    title = t->as_string()->get();
  }

  // ---- plugins: search path
  std::vector<std::string> dirs =
      options.plugin_dirs.empty() ? PluginCatalog::default_directories() : options.plugin_dirs;
  {
    const auto& pt = optional_table(root, "plugins");
    for (auto&& [key, value] : pt) {
      if (key.str() != "path")
        throw Error(location(key.source()),
                    "[plugins] unknown key '" + std::string(key.str()) + "'; allowed: path");
      const auto* a = value.as_array();
      if (!a) throw Error(location(value), "[plugins] path must be an array of directory strings");
      std::vector<std::string> extra;
      for (const auto& e : *a) {
        if (!e.is_string()) throw Error(location(e), "[plugins] path entries must be strings");
        fs::path d = e.as_string()->get();
        if (d.is_relative()) d = fs::path(path).parent_path() / d;
        extra.push_back(d.string());
      }
      dirs.insert(dirs.begin(), extra.begin(), extra.end());
    }
  }
  catalog = std::make_unique<PluginCatalog>(dirs);

  // ---- analysis, convergence, output
  const auto ap = check_table(optional_table(root, "analysis"), analysis_schema(), "[analysis]");
  model.formulation =
      ap.text("formulation") == "axisymmetric" ? Formulation::axisymmetric : Formulation::plane_strain;
  linear_solver = ap.text("linear_solver");
  stepping.steps = static_cast<int>(ap.integer("steps"));
  stepping.max_cutbacks = static_cast<int>(ap.integer("max_cutbacks"));
  stepping.increments = ap.real_list("increments");
  for (double v : stepping.increments)
    if (!(v > 0)) throw Error(ap.where("increments"), "[analysis] increments must all be > 0");
  stepping.automatic = ap.flag("automatic");
  stepping.fast_iterations = static_cast<int>(ap.integer("fast_iterations"));
  stepping.growth = ap.real("growth");
  stepping.max_increment = ap.real("max_increment");
  stepping.arc_length = ap.real("arc_length");
  stepping.max_arc_length = ap.real("max_arc_length");
  stepping.max_steps = static_cast<int>(ap.integer("max_steps"));
  const auto cp = check_table(optional_table(root, "convergence"), convergence_schema(), "[convergence]");
  convergence.force_rtol = cp.real("force_rtol");
  convergence.force_atol = cp.real("force_atol");
  convergence.disp_rtol = cp.real("disp_rtol");
  convergence.disp_atol = cp.real("disp_atol");
  convergence.energy_rtol = cp.real("energy_rtol");
  convergence.energy_atol = cp.real("energy_atol");
  convergence.displacement_test = cp.flag("displacement_test");
  convergence.max_iterations = static_cast<int>(cp.integer("max_iterations"));
  const auto op = check_table(optional_table(root, "output"), output_schema(), "[output]");
  vtk = op.flag("vtk");
  ip_output = op.flag("integration_points");
  every = static_cast<int>(op.integer("every"));

  // ---- solver plugin
  {
    const std::string name = ap.text("solver");
    try {
      catalog->require(registry, PluginKind::solver, name);
    } catch (const Error& e) {
      throw Error(ap.where("solver").known() ? ap.where("solver") : location(root),
                  "[analysis] solver = \"" + name + "\": " + e.message());
    }
    const auto& f = registry.solver(name);
    solver = f.create(check_table(optional_table(root, "solver"), f.schema, "[solver]"));
  }

  // ---- mesh
  {
    const auto& mt = table_at(root, "mesh", "scene");
    const auto mp = check_table(mt, mesh_schema(), "[mesh]", {"blocks"});
    if (mp.text("generator") == "blocks") {
      const int npc = static_cast<int>(mp.integer("nodes_per_cell"));
      if (npc != 4 && npc != 8)
        throw Error(mp.where("nodes_per_cell"),
                    "[mesh] nodes_per_cell = " + std::to_string(npc) + " is not allowed; allowed: 4 or 8");
      std::vector<Block> blocks;
      const auto list = table_list(mt, "blocks");
      if (list.empty())
        throw Error(location(mt), "[mesh] generator = \"blocks\" needs at least one [[mesh.blocks]]");
      for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string ctx = "[[mesh.blocks]] #" + std::to_string(i + 1);
        const auto bp = check_table(*list[i], block_schema(), ctx);
        Block b;
        b.name = bp.text("name");
        for (const char* xy : {"x", "y"}) {
          const auto& v = bp.real_list(xy);
          if (v.size() != 2 || !(v[1] > v[0]))
            throw Error(bp.where(xy), ctx + " " + xy + " must be [min, max] with max > min");
        }
        b.x0 = bp.real_list("x")[0], b.x1 = bp.real_list("x")[1];
        b.y0 = bp.real_list("y")[0], b.y1 = bp.real_list("y")[1];
        b.nx = static_cast<int>(bp.integer("nx")), b.ny = static_cast<int>(bp.integer("ny"));
        b.grade_x = bp.real("grade_x"), b.grade_y = bp.real("grade_y");
        blocks.push_back(b);
      }
      model.mesh = generate_blocks(blocks, npc);
      if (mp.text("transform") == "polar")
        for (auto& x : model.mesh.nodes) {
          const double r = x.x(), t = x.y() * std::numbers::pi / 180.0;
          x = Eigen::Vector2d(r * std::cos(t), r * std::sin(t));
        }
    } else {
      if (mt.get("blocks"))
        throw Error(location(*mt.get("blocks")), "[mesh] blocks are only used with generator = \"blocks\"");
      if (mp.text("file").empty())
        throw Error(location(mt), "[mesh] generator = \"gmsh\" needs file = \"...\"");
      fs::path f = mp.text("file");
      if (f.is_relative()) f = fs::path(path).parent_path() / f;
      model.mesh = read_gmsh(f.string());
    }
    model.mesh.check();
    if (model.formulation == Formulation::axisymmetric)
      for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n)
        if (model.mesh.nodes[n].x() < -1e-12)
          throw Error(location(mt), "[mesh] node " + std::to_string(n) + " has a negative radius x = " +
                                        std::to_string(model.mesh.nodes[n].x()) +
                                        " in an axisymmetric scene");
  }

  // ---- materials
  std::map<std::string, const Material*> material_by_name;
  {
    const auto& mats = optional_table(root, "materials");
    for (auto&& [key, value] : mats) {
      const std::string name(key.str());
      const std::string ctx = "[materials." + name + "]";
      const auto* t = value.as_table();
      if (!t) throw Error(location(value), ctx + " must be a table");
      const std::string model_name = require_string(*t, "model", ctx);
      try {
        catalog->require(registry, PluginKind::material, model_name);
      } catch (const Error& e) {
        throw Error(location(*t->get("model")), ctx + " model = \"" + model_name + "\": " + e.message());
      }
      const auto& f = registry.material(model_name);
      materials.push_back(f.create(check_table(*t, f.schema, ctx, {"model"})));
      material_by_name[name] = materials.back().get();
    }
  }

  // ---- domains
  const auto domain_list = table_list(root, "domains");
  if (domain_list.empty()) throw Error(location(root), "scene has no [[domains]]: nothing to analyse");
  std::vector<int> owner(model.mesh.cells.size(), -1);
  for (std::size_t i = 0; i < domain_list.size(); ++i) {
    const auto& t = *domain_list[i];
    const std::string ctx = "[[domains]] #" + std::to_string(i + 1);
    const std::string cells = require_string(t, "cells", ctx);
    const std::string element = require_string(t, "element", ctx);
    const std::string material = require_string(t, "material", ctx);
    auto cs = model.mesh.cell_sets.find(cells);
    if (cs == model.mesh.cell_sets.end())
      throw Error(location(*t.get("cells")),
                  ctx + " cells = \"" + cells +
                      "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
    auto mat = material_by_name.find(material);
    if (mat == material_by_name.end())
      throw Error(location(*t.get("material")),
                  ctx + " material = \"" + material +
                      "\" is not defined; defined: " + key_list(material_by_name));
    try {
      catalog->require(registry, PluginKind::element, element);
    } catch (const Error& e) {
      throw Error(location(*t.get("element")), ctx + " element = \"" + element + "\": " + e.message());
    }
    const auto& f = registry.element(element);
    // The element's formulation follows [analysis] unless the domain states it (then they must agree).
    const std::string form = model.formulation == Formulation::axisymmetric ? "axisymmetric" : "plane_strain";
    auto ep = check_table(t, f.schema, ctx, {"cells", "element", "material"});
    if (f.schema.find("formulation")) {
      if (const auto* fv = t.get("formulation"); fv && ep.text("formulation") != form)
        throw Error(location(*fv), ctx + " formulation = " + show(*fv) +
                                       " contradicts [analysis] formulation = \"" + form + "\"");
      ep.set("formulation", form, ep.where("formulation"));
    }
    elements.push_back(f.create(ep));
    Domain dm;
    dm.name = cells;
    dm.set_id = static_cast<int>(i);
    dm.element = elements.back().get();
    dm.law.material = mat->second;
    dm.cells = cs->second;
    dm.first_point.assign(dm.cells.size() + 1, 0);
    for (std::size_t c = 0; c < dm.cells.size(); ++c) {
      const int cell = dm.cells[c];
      if (owner[cell] >= 0)
        throw Error(location(*t.get("cells")), ctx + " cell " + std::to_string(cell) +
                                                   " already belongs to [[domains]] #" +
                                                   std::to_string(owner[cell] + 1));
      owner[cell] = static_cast<int>(i);
      const unsigned shape = model.mesh.cells[cell].shape();
      try {
        dm.element->check_shape(shape);
      } catch (const Error& e) {
        throw Error(location(*t.get("element")), ctx + " cell " + std::to_string(cell) + ": " + e.message());
      }
      dm.first_point[c + 1] = dm.first_point[c] + static_cast<std::size_t>(dm.element->num_points(shape));
    }
    dm.states = StateStore(dm.first_point.back(), dm.law.material->history_size());
    for (std::size_t p = 0; p < dm.states.points(); ++p) {
      auto slot = dm.states.committed_for_init(p);
      dm.law.material->init_history(Vec6::Zero(), slot.history());
    }
    dm.states.revert();
    model.domains.push_back(std::move(dm));
  }

  // ---- constraints
  const auto ndof = static_cast<Eigen::Index>(model.mesh.nodes.size() * DofMap::per_node);
  std::vector<char> fixed(static_cast<std::size_t>(ndof), 0);
  model.prescribed = Eigen::VectorXd::Zero(ndof);
  for (const auto* t : table_list(root, "constraints")) {
    const std::string ctx = "[[constraints]] at line " + std::to_string(location(*t).line);
    const std::string set = require_string(*t, "nodes", ctx);
    auto ns = model.mesh.node_sets.find(set);
    if (ns == model.mesh.node_sets.end())
      throw Error(location(*t->get("nodes")),
                  "[[constraints]] nodes = \"" + set +
                      "\" is not a node set of the mesh; known: " + key_list(model.mesh.node_sets));
    Schema s;
    s.real("ux", "m", "prescribed x (radial) displacement at load factor 1").defaults_to(0.0);
    s.real("uy", "m", "prescribed y (vertical) displacement at load factor 1").defaults_to(0.0);
    const auto p = check_table(*t, s, "[[constraints]]", {"nodes"});
    bool any = false;
    for (int c = 0; c < 2; ++c) {
      const char* k = c == 0 ? "ux" : "uy";
      if (!t->get(k)) continue;
      any = true;
      for (int n : ns->second) {
        const auto d = static_cast<std::size_t>(n) * 2 + static_cast<std::size_t>(c);
        if (fixed[d] && model.prescribed[static_cast<Eigen::Index>(d)] != p.real(k))
          throw Error(p.where(k), "[[constraints]] " + std::string(k) + " on node " + std::to_string(n) +
                                      " contradicts an earlier constraint");
        fixed[d] = 1;
        model.prescribed[static_cast<Eigen::Index>(d)] = p.real(k);
      }
    }
    if (!any)
      throw Error(location(*t),
                  "[[constraints]] nodes = \"" + set + "\" constrains nothing; give ux and/or uy");
  }
  // Nodes that no domain uses carry no stiffness: fix them.
  std::vector<char> used(model.mesh.nodes.size(), 0);
  for (const auto& dm : model.domains)
    for (int c : dm.cells)
      for (int n : model.mesh.cells[c].nodes)
        if (n >= 0) used[n] = 1;
  for (std::size_t n = 0; n < used.size(); ++n)
    if (!used[n]) fixed[2 * n] = fixed[2 * n + 1] = 1;
  model.dofs.build(fixed);
  model.u = Eigen::VectorXd::Zero(ndof);
  model.reactions = Eigen::VectorXd::Zero(ndof);

  // ---- loads (at load factor 1)
  model.load_ref = Eigen::VectorXd::Zero(ndof);
  for (const auto* t : table_list(root, "loads")) {
    const std::string type = require_string(*t, "type", "[[loads]]");
    if (type == "pressure") {
      Schema s;
      s.text("edges", {}, "edge set");
      s.real("p", "kPa", "normal pressure, positive pushing into the body");
      const auto p = check_table(*t, s, "[[loads]] type = \"pressure\"", {"type"});
      auto es = model.mesh.edge_sets.find(p.text("edges"));
      if (es == model.mesh.edge_sets.end())
        throw Error(p.where("edges"),
                    "[[loads]] edges = \"" + p.text("edges") +
                        "\" is not an edge set of the mesh; known: " + key_list(model.mesh.edge_sets));
      add_edge_pressure(model.mesh, es->second, p.real("p"), model.formulation, model.load_ref);
    } else if (type == "force") {
      Schema s;
      s.text("nodes", {}, "node set");
      s.real("fx", "kN", "force per node along x (axisymmetric: total over the circle)").defaults_to(0.0);
      s.real("fy", "kN", "force per node along y (axisymmetric: total over the circle)").defaults_to(0.0);
      const auto p = check_table(*t, s, "[[loads]] type = \"force\"", {"type"});
      auto ns = model.mesh.node_sets.find(p.text("nodes"));
      if (ns == model.mesh.node_sets.end())
        throw Error(p.where("nodes"),
                    "[[loads]] nodes = \"" + p.text("nodes") +
                        "\" is not a node set of the mesh; known: " + key_list(model.mesh.node_sets));
      for (int n : ns->second) {
        model.load_ref[2 * n] += p.real("fx");
        model.load_ref[2 * n + 1] += p.real("fy");
      }
    } else if (type == "gravity") {
      Schema s;
      s.text("cells", {}, "cell set").defaults_to(std::string("all"));
      s.real("gamma", "kN/m3", "unit weight, acting downwards (-y)").at_least(0);
      const auto p = check_table(*t, s, "[[loads]] type = \"gravity\"", {"type"});
      auto cs = model.mesh.cell_sets.find(p.text("cells"));
      if (cs == model.mesh.cell_sets.end())
        throw Error(p.where("cells").known() ? p.where("cells") : location(*t),
                    "[[loads]] cells = \"" + p.text("cells") +
                        "\" is not a cell set of the mesh; known: " + key_list(model.mesh.cell_sets));
      std::set<int> in_set(cs->second.begin(), cs->second.end());
      const Vec2 b(0.0, -p.real("gamma"));
      std::vector<int> nodes;
      Eigen::MatrixX2d x;
      Eigen::VectorXd fe;
      for (const auto& dm : model.domains)
        for (int c : dm.cells) {
          if (!in_set.count(c)) continue;
          model.cell_nodes(c, nodes, x);
          dm.element->body_force(ElementData{c, model.mesh.cells[c].shape(), &x}, b, fe);
          for (std::size_t a = 0; a < nodes.size(); ++a)
            for (int k = 0; k < 2; ++k)
              model.load_ref[2 * nodes[a] + k] += fe[static_cast<Eigen::Index>(2 * a) + k];
        }
    } else {
      throw Error(location(*t->get("type")),
                  "[[loads]] type = \"" + type +
                      "\" is not allowed; allowed: one of: pressure, force, gravity");
    }
  }
}

void Analysis::Impl::write_step(VtkSeriesWriter& w, double time) const {
  const Model& m = model;
  OutputStep out;
  out.time = time;
  out.mesh = &m.mesh;
  Field disp{"displacement", 3, std::vector<double>(m.mesh.nodes.size() * 3, 0.0)};
  Field reac{"reaction", 3, std::vector<double>(m.mesh.nodes.size() * 3, 0.0)};
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    for (int c = 0; c < 2; ++c) {
      const auto d = static_cast<Eigen::Index>(2 * n + static_cast<std::size_t>(c));
      disp.values[3 * n + static_cast<std::size_t>(c)] = m.u[d];
      if (m.dofs.eq[static_cast<std::size_t>(d)] < 0)
        reac.values[3 * n + static_cast<std::size_t>(c)] = m.reactions[d] - m.lambda * m.load_ref[d];
    }
  out.point_fields = {std::move(disp), std::move(reac)};
  Field stress{"stress", 6, {}}, set_id{"set_id", 1, {}};
  Field ip_stress{"stress", 6, {}}, ip_strain{"strain", 6, {}};
  std::size_t total_points = 0;
  for (const auto& dm : m.domains) total_points += dm.states.points();
  out.ip_coords.resize(static_cast<Eigen::Index>(ip_output ? total_points : 0), 2);
  Eigen::Index row = 0;
  std::vector<int> nodes;
  Eigen::MatrixX2d x, xp;
  Eigen::VectorXd wts;
  for (const auto& dm : m.domains)
    for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
      const int c = dm.cells[ci];
      out.cells.push_back(c);
      m.cell_nodes(c, nodes, x);
      ElementData data{c, m.mesh.cells[c].shape(), &x};
      dm.element->point_weights(data, wts);
      Vec6 avg = Vec6::Zero();
      for (std::size_t p = dm.first_point[ci]; p < dm.first_point[ci + 1]; ++p) {
        const auto slot = dm.states.committed(p);
        avg += wts[static_cast<Eigen::Index>(p - dm.first_point[ci])] * slot.stress();
        if (ip_output) {
          for (int k = 0; k < 6; ++k) {
            ip_stress.values.push_back(slot.stress()[k]);
            ip_strain.values.push_back(slot.strain()[k]);
          }
        }
      }
      for (int k = 0; k < 6; ++k) stress.values.push_back(avg[k]);
      set_id.values.push_back(dm.set_id);
      if (ip_output) {
        dm.element->point_coordinates(data, xp);
        out.ip_coords.middleRows(row, xp.rows()) = xp;
        row += xp.rows();
      }
    }
  out.cell_fields = {std::move(stress), std::move(set_id)};
  if (ip_output) out.ip_fields = {std::move(ip_stress), std::move(ip_strain)};
  w.write(out);
}

Analysis::Analysis(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Analysis::~Analysis() = default;

std::unique_ptr<Analysis> Analysis::from_string(const std::string& text, const std::string& path,
                                                RunOptions options) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw Error(io::location(e.source()), "malformed TOML: " + std::string(e.description()));
  }
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->options = std::move(options);
  impl->build(root);
  return std::unique_ptr<Analysis>(new Analysis(std::move(impl)));
}

std::unique_ptr<Analysis> Analysis::from_file(const std::string& path, RunOptions options) {
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path))
    throw Error(SourceLocation{path, 0, 0}, "cannot open scene file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return from_string(ss.str(), path, std::move(options));
}

const Model& Analysis::model() const { return impl_->model; }
Model& Analysis::model() { return impl_->model; }
std::vector<std::string> Analysis::opened_libraries() const { return impl_->catalog->opened(); }
std::string Analysis::title() const { return impl_->title; }

RunSummary Analysis::run() {
  Impl& s = *impl_;
  Model& m = s.model;
  RunSummary summary;
  const Assembler assembler(m);
  auto ls = make_linear_solver(s.linear_solver, m.symmetric(), m.dofs.free_count);
  SparseMatrix k = assembler.make_matrix();
  if (auto o = ls->analyze(k); !o.ok()) {
    summary.outcome = o;
    return summary;
  }
  StaticProblem problem(m, assembler, *ls);

  std::unique_ptr<VtkSeriesWriter> writer;
  if (s.options.write_output && s.vtk) {
    summary.out_dir = s.options.out_dir.empty() ? (fs::path("results") / fs::path(s.path).stem()).string()
                                                : s.options.out_dir;
    writer = std::make_unique<VtkSeriesWriter>(summary.out_dir, fs::path(s.path).stem().string());
    s.write_step(*writer, 0.0);
  }

  Eigen::VectorXd u = m.restrict_free(m.u);
  StepSettings settings = s.stepping;
  settings.lambda_start = m.lambda;
  settings.convergence = s.convergence;
  const int nominal_steps =
      settings.increments.empty() ? settings.steps : static_cast<int>(settings.increments.size());
  StepCallbacks cb;
  cb.commit = [&] {
    for (auto& dm : m.domains) dm.states.commit();
  };
  cb.revert = [&] {
    for (auto& dm : m.domains) dm.states.revert();
  };
  // Prescribed displacements jump at the start of a step; without a predictor the first
  // iterate puts the whole jump into the cells next to the prescribed nodes.
  if (m.prescribed.size() > 0 && m.prescribed.cwiseAbs().maxCoeff() > 0.0)
    cb.predict = [&](NonlinearProblem& p, double l0, double l1, Eigen::VectorXd& x) {
      predict(p, *ls, l0, l1, x);
    };
  int step = 0;
  cb.accepted = [&](const StepRecord& rec, const StepReport& rep, const Eigen::VectorXd& x) {
    m.lambda = rec.lambda;
    m.expand(x, m.lambda, m.u);
    m.reactions = problem.internal_force();
    step = rec.step;
    if (s.options.on_step) s.options.on_step(step, nominal_steps, m.lambda, rep);
    if (s.options.on_record) s.options.on_record(rec);
    if (writer && step % s.every == 0) s.write_step(*writer, m.lambda);
  };
  StageResult stage = run_stage(problem, *s.solver, settings, cb, u);
  summary.outcome = stage.outcome;
  summary.cutbacks = stage.cutbacks;
  summary.reports = std::move(stage.reports);
  summary.records = std::move(stage.records);
  if (writer && step > 0 && step % s.every != 0) s.write_step(*writer, m.lambda); // the last step
  if (!summary.out_dir.empty())
    write_step_records((fs::path(summary.out_dir) / "diagnostics.csv").string(), summary.records);
  summary.steps_done = step;
  if (writer) summary.pvd = writer->pvd_path();
  return summary;
}

} // namespace stratum
