#include "scene/recorder_spec.hpp"

#include "scene/schemas.hpp"
#include "scene/tables.hpp"
#include "scene/toml_check.hpp"
#include "suggest.hpp"

#include <algorithm>
#include <cctype>

namespace stratum {

using io::location;

const std::vector<std::string>& recorder_quantities(const std::string& kind) {
  static const std::vector<std::string> node{"ux", "uy", "rx", "ry"};
  // A point's water quantities (p, p_excess, the effective and total normal stresses) follow
  // its first 11, recorded only when asked (read_recorder).
  static const std::vector<std::string> point{
      "x",      "y", "sxx",      "syy",     "szz",     "sxy",     "exx",       "eyy",       "ezz",      "gxy",
      "status", "p", "p_excess", "sxx_eff", "syy_eff", "szz_eff", "sxx_total", "syy_total", "szz_total"};
  static const std::vector<std::string> global{"lambda", "iterations", "time", "p_max", "p_mean", "U"};
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

} // namespace

std::string recorder_field(const std::string& q) {
  const std::string suffix = "_reaction";
  return q.size() > suffix.size() && q.compare(q.size() - suffix.size(), suffix.size(), suffix) == 0
             ? q.substr(0, q.size() - suffix.size())
             : q;
}

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
  scene::require_file_name(r.name, p.where("name"), ctx, "name");
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
                                    "\"]; allowed: " + name_list(names));
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
                                     "\" does not record; allowed: " + name_list(names));
      r.quantities.push_back(*v);
    }
  } else if (r.kind == "global") {
    r.quantities = {"lambda", "iterations", "time"}; // the excess pressure's, of porous models, when asked
  } else if (r.kind == "point") {
    r.quantities.assign(names.begin(), names.begin() + point_dry_quantities);
  } else {
    r.quantities = names;
  }
  // An interface's rows are points: where each is along the interface comes first, always.
  if (r.kind == "interface" && r.quantities.front() != "s") {
    r.quantities.erase(std::remove(r.quantities.begin(), r.quantities.end(), "s"), r.quantities.end());
    r.quantities.insert(r.quantities.begin(), "s");
  }
  io::require_read(p, keys.schema, ctx);
  return r;
}

std::string recorder_quantity_unit(const std::string& q) {
  if (q == "ux" || q == "uy" || q == "x" || q == "y" || q == "s" || q == "slip" || q == "opening") return "m";
  if (q == "rx" || q == "ry") return "kN";
  if (q == "sxx" || q == "syy" || q == "szz" || q == "sxy" || q == "shear_traction" || q == "normal_traction")
    return "kPa";
  if (q.starts_with("sxx_") || q.starts_with("syy_") || q.starts_with("szz_")) return "kPa";
  if (q == "p" || q == "p_steady" || q == "p_excess" || q == "p_max" || q == "p_mean") return "kPa";
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
                                         c.recorder + "\"; it records: " + name_list(it->quantities));
  io::require_read(p, scene::check_schema(), ctx);
  return c;
}

} // namespace stratum
