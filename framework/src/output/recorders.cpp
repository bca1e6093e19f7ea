#include "output/recorders.hpp"

#include "output/interface_output.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace stratum {

namespace {

/// The excess pore pressure of the model: the largest |p| at a node, and its mean over the active
/// cells that carry p (each cell's mean of its p nodes times its volume, the sum of its points'
/// weights; exact for p linear on triangles and bilinear on parallelograms in plane strain).
std::pair<double, double> excess_pressure(const Model& m) {
  const int f = m.dofs.field("p");
  double largest = 0.0, integral = 0.0, volume = 0.0;
  if (f < 0) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  for (std::size_t n = 0; n + 1 < m.dofs.node_first.size(); ++n)
    if (const int d = m.dofs.dof(static_cast<int>(n), f); d >= 0)
      largest = std::max(largest, std::abs(m.u[d]));
  std::vector<int> nodes;
  Eigen::MatrixXd x;
  Eigen::VectorXd w;
  for (const auto& dm : m.domains)
    for (int c : dm.cells) {
      if (!m.is_active(c) || !dm.element) continue;
      m.cell_nodes(c, nodes, x);
      double sum = 0.0;
      int count = 0;
      for (int n : nodes)
        if (const int d = m.dofs.dof(n, f); d >= 0) sum += m.u[d], ++count;
      if (count == 0) continue;
      dm.element->point_weights(m.element_data(c, x), w);
      integral += sum / count * w.sum();
      volume += w.sum();
    }
  return {largest, volume > 0.0 ? integral / volume : std::numeric_limits<double>::quiet_NaN()};
}

const std::vector<std::string>& allowed(const std::string& kind) { return recorder_quantities(kind); }

/// The index of the field called `name` among an element's fields of a cell, -1 when none.
int local_field(const Element& e, const Cell& c, const std::string& name) {
  const auto fields = e.node_fields(c.type, c.shape()).fields;
  for (std::size_t f = 0; f < fields.size(); ++f)
    if (fields[f].name == name) return static_cast<int>(f);
  return -1;
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

void point_water(const Model& m, const Domain& dm, std::size_t ci, std::vector<PointWater>& out) {
  const int c = dm.cells[ci];
  const std::size_t first = dm.first_point[ci], count = dm.first_point[ci + 1] - first;
  out.assign(count, PointWater{});
  std::vector<int> nodes, dofs;
  Eigen::MatrixXd x, xp;
  m.cell_nodes(c, nodes, x);
  const ElementData data = m.element_data(c, x);
  Eigen::VectorXd excess = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(count));
  if (dm.element) {
    dm.element->point_coordinates(data, xp);
    if (const int f = local_field(*dm.element, m.mesh.cells[static_cast<std::size_t>(c)], "p"); f >= 0) {
      m.cell_dofs(dm, c, dofs);
      Eigen::VectorXd ue(static_cast<Eigen::Index>(dofs.size()));
      for (std::size_t i = 0; i < dofs.size(); ++i)
        ue[static_cast<Eigen::Index>(i)] = dofs[i] >= 0 ? m.u[dofs[i]] : 0.0;
      Eigen::VectorXd v;
      if (dm.element->point_field(data, ue, f, v) && v.size() == excess.size()) excess = v;
    }
  }
  const bool undrained = dm.drainage == "undrained", total_only = dm.drainage == "undrained_total";
  const bool non_porous = dm.drainage == "non_porous";
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  // An interface's points carry a contact traction, total (the laws know no pore pressure).
  if (!is_solid(m.mesh.cells[static_cast<std::size_t>(c)].type)) {
    for (std::size_t q = 0; q < count; ++q) {
      PointWater& w = out[q];
      w.p_steady = w.p_excess = nan;
      w.effective.setConstant(nan);
      w.total = dm.states.committed(first + q).stress();
    }
    return;
  }
  for (std::size_t q = 0; q < count; ++q) {
    const auto slot = dm.states.committed(first + q);
    PointWater& w = out[q];
    const Eigen::Index r = static_cast<Eigen::Index>(q);
    w.p_steady = non_porous || xp.rows() <= r ? 0.0 : m.water.pressure(xp(r, 0), xp(r, 1));
    w.p_excess = undrained ? slot.history()[0] : (total_only ? nan : (non_porous ? 0.0 : excess[r]));
    // The stored stress: effective (drained, porous elements), effective less the excess (an
    // undrained domain's material), total (undrained_total: with the geostatic effective stress
    // it started from; non-porous).
    w.effective = slot.stress();
    if (undrained) w.effective.head<3>().array() += w.p_excess;
    w.total = w.effective;
    w.total.head<3>().array() -= w.p_steady + (total_only ? 0.0 : w.p_excess);
    if (total_only) w.effective.setConstant(nan);
  }
}

Recorder::Recorder(const RecorderSpec& spec, const Model& model)
    : name_(spec.name), kind_(spec.kind), set_(spec.set), quantities_(spec.quantities) {
  const std::string& ctx = spec.context;
  at_[0] = spec.at[0], at_[1] = spec.at[1];
  if (kind_ == "point") {
    const auto& names = allowed(kind_);
    wants_water_ = std::any_of(quantities_.begin(), quantities_.end(), [&](const std::string& q) {
      return std::find(names.begin(), names.end(), q) - names.begin() >=
             static_cast<std::ptrdiff_t>(point_dry_quantities);
    });
  }
  if (kind_ == "global" && model.dofs.field("p") < 0)
    for (std::size_t i = 0; i < quantities_.size(); ++i)
      if (quantities_[i] == "p_max" || quantities_[i] == "p_mean" || quantities_[i] == "U")
        throw Error(spec.where,
                    ctx + " quantity \"" + quantities_[i] +
                        "\" is the excess pore pressure of porous elements (quad8p4, tri6p3), and this "
                        "model has none; allowed here: lambda, iterations, time");
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
      throw Error(spec.set_at,
                  ctx + " set = \"" + set_ + "\" is not an interface of the scene; " +
                      (known.empty() ? std::string("the scene has no [[interfaces]]")
                                     : "known: " + name_list(known) + did_you_mean(set_, known)));
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
      m.precision(10); // enough digits for the nearest node's position to be copied into the scene
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
    const int f = model.dofs.field(recorder_field(q));
    if (f < 0 || f < model.dim())
      throw Error(at, ctx + " quantities: \"" + q + "\" is not a quantity of kind = \"" + kind_ + "\" (" +
                          name_list(names) +
                          ") nor a field of the scene's elements or its reaction (fields: " +
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

void Recorder::sample(const Model& m, int stage, int step, double lambda, int iterations, double time) {
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
    v.assign(names.size(), std::numeric_limits<double>::quiet_NaN());
    std::vector<int> nodes;
    Eigen::MatrixXd x, xp;
    const Domain* at_domain = nullptr;
    std::size_t at_cell = 0;
    Eigen::Index at_point = 0;
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
          at_domain = &dm, at_cell = ci, at_point = q;
        }
      }
    // The pore water of the nearest point, when asked for any of it.
    v.resize(names.size(), std::numeric_limits<double>::quiet_NaN());
    if (wants_water_ && at_domain) {
      std::vector<PointWater> water;
      point_water(m, *at_domain, at_cell, water);
      const PointWater& w = water[static_cast<std::size_t>(at_point)];
      const double p = w.p_steady + w.p_excess;
      const std::vector<double> extra{p,          w.p_excess, w.effective[0], w.effective[1], w.effective[2],
                                      w.total[0], w.total[1], w.total[2]};
      std::copy(extra.begin(), extra.end(), v.begin() + static_cast<std::ptrdiff_t>(point_dry_quantities));
    }
  } else {
    const auto [largest, mean] = excess_pressure(m);
    // U of the stage: its start is the state of the previous sample (the end of the stage before).
    if (stage != last_stage_) stage_start_mean_ = std::isfinite(last_mean_) ? last_mean_ : mean;
    last_stage_ = stage, last_mean_ = mean;
    const double U =
        stage_start_mean_ != 0.0 ? 1.0 - mean / stage_start_mean_ : std::numeric_limits<double>::quiet_NaN();
    v = {lambda, static_cast<double>(iterations), time, largest, mean, U};
  }
  for (const auto& q : quantities_) {
    const auto it = std::find(names.begin(), names.end(), q);
    if (it != names.end()) {
      r.values.push_back(v[static_cast<std::size_t>(it - names.begin())]);
      continue;
    }
    // A field quantity (node recorders): the mean value over the nodes that carry the field, or
    // the sum of its reactions.
    const int f = m.dofs.field(recorder_field(q));
    const bool want_reaction = q != recorder_field(q);
    double sum = 0.0;
    int count = 0;
    for (int n : nodes_)
      if (const int d = m.dofs.dof(n, f); d >= 0) sum += want_reaction ? reaction(d) : m.u[d], ++count;
    r.values.push_back(want_reaction || count == 0 ? (count ? sum : std::numeric_limits<double>::quiet_NaN())
                                                   : sum / count);
  }
  rows_.push_back(std::move(r));
}

std::string recorder_column(const std::string& quantity, const Units& units, Formulation formulation) {
  std::string unit = recorder_quantity_unit(quantity);
  if (unit == "-") return quantity;
  if ((quantity == "rx" || quantity == "ry") && formulation == Formulation::plane_strain) unit = "kN/m";
  return units.column(quantity, unit);
}

std::string Recorder::csv(const Units& units, Formulation formulation) const {
  std::ostringstream o;
  // Every row starts with stage, step and lambda: a `lambda` quantity (kind global) is that
  // column already and is not written twice.
  o << std::setprecision(12) << "stage,step,lambda";
  for (const auto& q : quantities_)
    if (q != "lambda") o << ',' << recorder_column(q, units, formulation);
  o << '\n';
  for (const auto& r : rows_) {
    o << r.stage << ',' << r.step << ',' << r.lambda;
    for (std::size_t i = 0; i < r.values.size() && i < quantities_.size(); ++i)
      if (quantities_[i] != "lambda") o << ',' << r.values[i];
    o << '\n';
  }
  return o.str();
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
