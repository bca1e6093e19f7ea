#include "recorders.hpp"

#include "scene/schemas.hpp"
#include "stratum/body_interfaces.hpp"
#include "stratum/suggest.hpp"
#include "toml_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace stratum {

using io::location;

const std::vector<std::string>& recorder_quantities(const std::string& kind) {
  static const std::vector<std::string> node{"ux", "uy", "rx", "ry"};
  static const std::vector<std::string> point{"x",   "y",   "sxx", "syy", "szz",   "sxy",
                                              "exx", "eyy", "ezz", "gxy", "status"};
  static const std::vector<std::string> global{"lambda", "iterations", "time"};
  static const std::vector<std::string> iface{"s",    "x",       "y",     "shear_traction", "normal_traction",
                                              "slip", "opening", "status"};
  if (kind == "point") return point;
  if (kind == "global") return global;
  if (kind == "interface") return iface;
  return node; // node, nodes
}

namespace {

const std::vector<std::string>& allowed(const std::string& kind) { return recorder_quantities(kind); }

/// A name a field may have: a letter, then letters, digits and underscores.
bool is_field_name(const std::string& s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; });
}

/// The field of a node recorder's field quantity: "p" and "p_reaction" are both field "p".
std::string field_of(const std::string& q) {
  const std::string suffix = "_reaction";
  return q.size() > suffix.size() && q.compare(q.size() - suffix.size(), suffix.size(), suffix) == 0
             ? q.substr(0, q.size() - suffix.size())
             : q;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// The interface points in order along the interface, with s the arc length of the polyline
/// through them from the end nearest the first point in cell order (the set's first edge, or
/// for node pairs its lowest node). The order is found by walking from that end to the nearest
/// point not yet visited, which follows any chain whose points are closer to their neighbours
/// than to the points of another part of the chain.
std::vector<InterfacePoint> ordered_along(std::vector<InterfacePoint> pts) {
  if (pts.size() < 2) {
    for (auto& p : pts) p.s = 0.0;
    return pts;
  }
  const auto farthest = [&](const Vec2& from) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < pts.size(); ++i)
      if ((pts[i].x - from).norm() > (pts[best].x - from).norm()) best = i;
    return best;
  };
  const std::size_t end_a = farthest(pts.front().x), end_b = farthest(pts[end_a].x);
  const Vec2 first = pts.front().x;
  std::size_t at = (pts[end_b].x - first).norm() < (pts[end_a].x - first).norm() ? end_b : end_a;
  std::vector<InterfacePoint> out;
  std::vector<char> used(pts.size(), 0);
  double s = 0.0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (!out.empty()) s += (pts[at].x - out.back().x).norm();
    used[at] = 1;
    out.push_back(pts[at]);
    out.back().s = s;
    std::size_t next = pts.size();
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (!used[i] &&
          (next == pts.size() || (pts[i].x - pts[at].x).norm() < (pts[next].x - pts[at].x).norm()))
        next = i;
    at = next;
  }
  return out;
}

} // namespace

RecorderSpec read_recorder(const toml::table& t, const std::string& ctx, const Units& units) {
  const scene::TableKeys keys = scene::recorder_keys();
  const Params p = io::check_table(t, keys.schema, ctx, keys.other_names());
  RecorderSpec r;
  r.context = ctx;
  r.where = location(t);
  r.name = p.text("name");
  r.kind = p.text("kind");
  r.set = p.text("set");
  r.set_at = p.where("set");
  r.at_at = p.where("at");
  if (r.name.empty() || r.name.find_first_of("/\\ ") != std::string::npos || r.name[0] == '.')
    throw Error(p.where("name"), ctx + " name = \"" + r.name +
                                     "\" must be a plain file name (no '/', '\\', spaces or leading '.')");
  const auto& at = p.real_list("at");
  const bool needs_at = r.kind == "node" || r.kind == "point";
  if (needs_at && at.size() != 2)
    throw Error(at.empty() ? location(t) : p.where("at"),
                ctx + " kind = \"" + r.kind + "\" needs at = [x, y] (" + units.length() + ")");
  if (!needs_at && !at.empty())
    throw Error(p.where("at"), ctx + " at acts only for kind = \"node\" or \"point\"");
  if (r.kind == "nodes" && r.set.empty())
    throw Error(location(t), ctx + " kind = \"nodes\" needs set = \"<node or edge set>\"");
  if (r.kind == "interface" && r.set.empty())
    throw Error(location(t), ctx + " kind = \"interface\" needs set = \"<interface name>\"");
  if (r.kind != "nodes" && r.kind != "interface" && !r.set.empty())
    throw Error(p.where("set"), ctx + " set acts only for kind = \"nodes\" or \"interface\"");
  if (needs_at) r.at[0] = at[0], r.at[1] = at[1];
  // quantities: a list of names; by default all of the kind's.
  const auto& names = allowed(r.kind);
  if (const toml::node* q = t.get("quantities")) {
    const auto* arr = q->as_array();
    if (!arr || arr->empty())
      throw Error(location(*q), ctx + " quantities must be a non-empty list of names, e.g. [\"" + names[0] +
                                    "\"]; allowed: " + joined(names));
    const bool node_kind = r.kind == "node" || r.kind == "nodes";
    for (const auto& e : *arr) {
      const auto v = e.value<std::string>();
      // Node recorders also record the scene's other fields by name ("p", and its reaction
      // "p_reaction"); which fields there are is known once the domains are built (Recorder).
      if (v && node_kind && std::find(names.begin(), names.end(), *v) == names.end() && is_field_name(*v)) {
        r.quantities.push_back(*v);
        r.quantity_at.push_back(location(e));
        continue;
      }
      if (!v || std::find(names.begin(), names.end(), *v) == names.end())
        throw Error(location(e), ctx + " quantities contains " + io::show(e) + ", which kind = \"" + r.kind +
                                     "\" does not record; allowed: " + joined(names));
      r.quantities.push_back(*v);
    }
  } else {
    r.quantities = names;
  }
  // An interface's rows are points: where each is along the interface comes first, always.
  if (r.kind == "interface" && r.quantities.front() != "s") {
    r.quantities.erase(std::remove(r.quantities.begin(), r.quantities.end(), "s"), r.quantities.end());
    r.quantities.insert(r.quantities.begin(), "s");
  }
  return r;
}

Recorder::Recorder(const RecorderSpec& spec, const Model& model)
    : name_(spec.name), kind_(spec.kind), set_(spec.set), quantities_(spec.quantities) {
  const std::string& ctx = spec.context;
  at_[0] = spec.at[0], at_[1] = spec.at[1];
  if (kind_ == "nodes") {
    const auto it = model.mesh.node_sets.find(set_);
    if (it == model.mesh.node_sets.end())
      throw Error(spec.set_at,
                  ctx + " set = \"" + set_ +
                      "\" is not a node or edge set of the mesh; known: " + key_list(model.mesh.node_sets));
    nodes_ = it->second;
  } else if (kind_ == "interface") {
    std::vector<std::string> known;
    bool found = false;
    for (std::size_t d = 0; d < model.domains.size(); ++d) {
      const Domain& dm = model.domains[d];
      if (!dm.law.contact) continue;
      known.push_back(dm.name);
      if (dm.name == set_) domain_ = d, found = true;
    }
    if (!found)
      throw Error(spec.set_at, ctx + " set = \"" + set_ + "\" is not an interface of the scene; " +
                                   (known.empty() ? std::string("the scene has no [[interfaces]]")
                                                  : "known: " + joined(known) + did_you_mean(set_, known)));
  }
  if (kind_ == "node") {
    // The node must be at `at`: a recorder that silently moved to another node would record
    // another quantity than the one asked for.
    double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    double hi[2] = {-lo[0], -lo[1]};
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t n = 0; n < model.mesh.nodes.size(); ++n) {
      const auto& x = model.mesh.nodes[n];
      for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], x[k]), hi[k] = std::max(hi[k], x[k]);
      const double d = std::hypot(x[0] - at_[0], x[1] - at_[1]);
      if (d < best_d) best_d = d, best = static_cast<int>(n);
    }
    const double size = std::max(hi[0] - lo[0], hi[1] - lo[1]);
    if (best < 0 || best_d > 1e-6 * size) {
      std::ostringstream m;
      m << ctx << " no node at (" << at_[0] << ", " << at_[1] << ")";
      if (best >= 0)
        m << "; the nearest is node " << best << " at ("
          << model.mesh.nodes[static_cast<std::size_t>(best)][0] << ", "
          << model.mesh.nodes[static_cast<std::size_t>(best)][1] << ")";
      throw Error(spec.at_at, m.str());
    }
    nodes_ = {best};
  }
  // Field quantities of node recorders: each names a field of the scene's elements.
  std::size_t extra = 0;
  for (const auto& q : quantities_) {
    const auto& names = allowed(kind_);
    if (std::find(names.begin(), names.end(), q) != names.end()) continue;
    const SourceLocation at = extra < spec.quantity_at.size() ? spec.quantity_at[extra] : spec.where;
    ++extra;
    const int f = model.dofs.field(field_of(q));
    if (f < 0 || f < model.dim())
      throw Error(at, ctx + " quantities: \"" + q + "\" is not a quantity of kind = \"" + kind_ + "\" (" +
                          joined(names) + ") nor a field of the scene's elements or its reaction (fields: " +
                          model.dofs.field_list() + "; e.g. \"p\", \"p_reaction\")");
  }
}

std::vector<const RecorderRow*> Recorder::last_step() const {
  std::vector<const RecorderRow*> out;
  for (auto it = rows_.rbegin(); it != rows_.rend(); ++it) {
    if (it->stage != rows_.back().stage || it->step != rows_.back().step) break;
    out.insert(out.begin(), &*it);
  }
  return out;
}

int Recorder::column(const std::string& quantity) const {
  const auto it = std::find(quantities_.begin(), quantities_.end(), quantity);
  return it == quantities_.end() ? -1 : static_cast<int>(it - quantities_.begin());
}

void Recorder::sample(const Model& m, int stage, int step, double lambda, int iterations) {
  RecorderRow r{stage, step, lambda, {}};
  const auto reaction = [&](int d) {
    if (m.dofs.eq[static_cast<std::size_t>(d)] >= 0) return 0.0; // a free DOF carries no reaction
    return m.reactions[d] - m.load_base[d] - m.lambda * m.load_ref[d];
  };
  std::vector<double> v; // in the order of allowed(kind_)
  const auto& names = allowed(kind_);
  if (kind_ == "interface") {
    for (const auto& ip : ordered_along(interface_points(m, m.domains[domain_]))) {
      v = {ip.s,           ip.x[0],    ip.x[1],    ip.traction[0],
           ip.traction[1], ip.jump[0], ip.jump[1], static_cast<double>(static_cast<int>(ip.state))};
      RecorderRow row{stage, step, lambda, {}};
      for (const auto& q : quantities_)
        row.values.push_back(
            v[static_cast<std::size_t>(std::find(names.begin(), names.end(), q) - names.begin())]);
      rows_.push_back(std::move(row));
    }
    return;
  }
  if (kind_ == "node" || kind_ == "nodes") {
    double u[2] = {0, 0}, f[2] = {0, 0};
    for (int n : nodes_)
      for (int k = 0; k < 2; ++k)
        if (const int d = m.dofs.dof(n, field_ux + k); d >= 0) {
          u[k] += m.u[d];
          f[k] += reaction(d);
        }
    const double count = static_cast<double>(std::max<std::size_t>(nodes_.size(), 1));
    v = {u[0] / count, u[1] / count, f[0], f[1]};
  } else if (kind_ == "point") {
    double best = std::numeric_limits<double>::infinity();
    v.assign(11, std::numeric_limits<double>::quiet_NaN());
    std::vector<int> nodes;
    Eigen::MatrixXd x, xp;
    for (const auto& dm : m.domains)
      for (std::size_t ci = 0; ci < dm.cells.size(); ++ci) {
        const int c = dm.cells[ci];
        if (!m.is_active(c) || !dm.element) continue;
        m.cell_nodes(c, nodes, x);
        dm.element->point_coordinates(m.element_data(c, x), xp);
        for (Eigen::Index q = 0; q < xp.rows(); ++q) {
          const double d = std::hypot(xp(q, 0) - at_[0], xp(q, 1) - at_[1]);
          if (!(d < best)) continue;
          best = d;
          const auto slot = dm.states.committed(dm.first_point[ci] + static_cast<std::size_t>(q));
          const Vec6 s = slot.stress(), e = slot.strain();
          const double status =
              dm.law.material ? static_cast<double>(dm.law.material->point_status(s, slot.history())) : -1.0;
          v = {xp(q, 0), xp(q, 1), s[0], s[1], s[2], s[3], e[0], e[1], e[2], e[3], status};
        }
      }
  } else {
    v = {lambda, static_cast<double>(iterations), static_cast<double>(stage - 1) + lambda};
  }
  for (const auto& q : quantities_) {
    const auto it = std::find(names.begin(), names.end(), q);
    if (it != names.end()) {
      r.values.push_back(v[static_cast<std::size_t>(it - names.begin())]);
      continue;
    }
    // A field quantity (node recorders): the mean value over the nodes that carry the field, or
    // the sum of its reactions.
    const int f = m.dofs.field(field_of(q));
    const bool want_reaction = q != field_of(q);
    double sum = 0.0;
    int count = 0;
    for (int n : nodes_)
      if (const int d = m.dofs.dof(n, f); d >= 0) sum += want_reaction ? reaction(d) : m.u[d], ++count;
    r.values.push_back(want_reaction || count == 0 ? (count ? sum : std::numeric_limits<double>::quiet_NaN())
                                                   : sum / count);
  }
  rows_.push_back(std::move(r));
}

std::string Recorder::csv() const {
  std::ostringstream o;
  // Every row starts with stage, step and lambda: a `lambda` quantity (kind global) is that
  // column already and is not written twice.
  o << std::setprecision(12) << "stage,step,lambda";
  for (const auto& q : quantities_)
    if (q != "lambda") o << ',' << q;
  o << '\n';
  for (const auto& r : rows_) {
    o << r.stage << ',' << r.step << ',' << r.lambda;
    for (std::size_t i = 0; i < r.values.size() && i < quantities_.size(); ++i)
      if (quantities_[i] != "lambda") o << ',' << r.values[i];
    o << '\n';
  }
  return o.str();
}

std::string recorder_quantity_unit(const std::string& q) {
  if (q == "ux" || q == "uy" || q == "x" || q == "y" || q == "s" || q == "slip" || q == "opening") return "m";
  if (q == "rx" || q == "ry") return "kN";
  if (q == "sxx" || q == "syy" || q == "szz" || q == "sxy" || q == "shear_traction" || q == "normal_traction")
    return "kPa";
  return "-";
}

Check parse_check(const toml::table& t, const std::string& ctx, const std::vector<RecorderSpec>& recorders) {
  const Params p = io::check_table(t, scene::check_schema(), ctx);
  Check c{p.text("recorder"), p.text("quantity"), p.real("expected"),
          p.real("rtol"),     p.real("atol"),     location(t)};
  if (c.rtol == 0.0 && c.atol == 0.0)
    throw Error(location(t), ctx + " give rtol or atol (or both): a check of floating-point results needs a "
                                   "tolerance");
  const auto it = std::find_if(recorders.begin(), recorders.end(),
                               [&](const RecorderSpec& r) { return r.name == c.recorder; });
  if (it == recorders.end()) {
    std::string known;
    for (const auto& r : recorders) known += (known.empty() ? "" : ", ") + r.name;
    throw Error(p.where("recorder"), ctx + " recorder = \"" + c.recorder +
                                         "\" is not an [[output.history]] name" +
                                         (known.empty() ? "; the scene has none" : "; known: " + known));
  }
  if (std::find(it->quantities.begin(), it->quantities.end(), c.quantity) == it->quantities.end())
    throw Error(p.where("quantity"), ctx + " quantity = \"" + c.quantity + "\" is not recorded by \"" +
                                         c.recorder + "\"; it records: " + joined(it->quantities));
  return c;
}

std::vector<CheckResult> evaluate_checks(const std::vector<Check>& checks,
                                         const std::vector<Recorder>& recorders) {
  std::vector<CheckResult> out;
  for (const auto& c : checks) {
    const auto& r = *std::find_if(recorders.begin(), recorders.end(),
                                  [&](const Recorder& x) { return x.name() == c.recorder; });
    CheckResult res;
    res.label = c.recorder + "." + c.quantity;
    res.unit = recorder_quantity_unit(c.quantity);
    res.expected = c.expected;
    res.tolerance = c.atol + c.rtol * std::abs(c.expected);
    // The last step's value; for an interface the point farthest from the expected value, so
    // that the check holds at every point (NaN anywhere wins: it fails).
    res.value = std::numeric_limits<double>::quiet_NaN();
    double worst = -1.0;
    for (const RecorderRow* row : r.last_step()) {
      const double x = row->values[static_cast<std::size_t>(r.column(c.quantity))];
      const double d = std::isnan(x) ? std::numeric_limits<double>::infinity() : std::abs(x - c.expected);
      if (d > worst) worst = d, res.value = x;
    }
    res.pass = std::abs(res.value - res.expected) <= res.tolerance; // NaN fails
    out.push_back(res);
  }
  return out;
}

} // namespace stratum
