// Parameter studies: the study file, the designs, one sample's run and its row (stratum/sweep.hpp).
#include "stratum/sweep.hpp"

#include "stratum/analysis.hpp"
#include "stratum/point_driver.hpp"
#include "toml_check.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum::sweep {

struct Study::Base {
  toml::table root;
};

namespace {

using io::location;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------- TOML paths of the base scene

struct Segment {
  std::string key;
  std::vector<std::size_t> index;
};

struct PathError {
  std::string message;
};

std::vector<Segment> parse_path(const std::string& path) {
  std::vector<Segment> segs;
  std::size_t i = 0;
  auto fail = [&](const std::string& what) {
    throw PathError{"'" + path + "' is not a path (" + what +
                    "); write keys joined by dots with optional [index], e.g. materials.soil.K[0]"};
  };
  while (true) {
    Segment s;
    while (i < path.size() &&
           (std::isalnum(static_cast<unsigned char>(path[i])) || path[i] == '_' || path[i] == '-'))
      s.key += path[i++];
    if (s.key.empty()) fail("an empty key at character " + std::to_string(i + 1));
    while (i < path.size() && path[i] == '[') {
      std::size_t j = ++i, n = 0;
      while (i < path.size() && std::isdigit(static_cast<unsigned char>(path[i])))
        n = 10 * n + static_cast<std::size_t>(path[i++] - '0');
      if (i == j || i >= path.size() || path[i] != ']')
        fail("a bad [index] at character " + std::to_string(j));
      ++i;
      s.index.push_back(n);
    }
    segs.push_back(std::move(s));
    if (i == path.size()) break;
    if (path[i] != '.') fail("'" + std::string(1, path[i]) + "' at character " + std::to_string(i + 1));
    ++i;
  }
  return segs;
}

std::string keys_of(const toml::table& t) {
  std::string k;
  for (auto&& [key, v] : t) k += (k.empty() ? "" : ", ") + std::string(key.str());
  return k.empty() ? "(none)" : k;
}

/// Follows one segment's key from `cur` (a table, or an array of tables addressed by `name`).
toml::node* step_key(toml::node& cur, const std::string& key, const std::string& done) {
  if (auto* t = cur.as_table()) {
    if (auto* n = t->get(key)) return n;
    throw PathError{"no key '" + key + "' in " + (done.empty() ? "the top level" : "[" + done + "]") +
                    "; keys: " + keys_of(*t)};
  }
  if (auto* a = cur.as_array(); a && a->is_array_of_tables()) {
    std::string names;
    for (auto& e : *a) {
      const auto* name = e.as_table()->get("name");
      if (name && name->is_string()) {
        if (name->as_string()->get() == key) return &e;
        names += (names.empty() ? "" : ", ") + name->as_string()->get();
      }
    }
    throw PathError{"no entry named '" + key + "' in [[" + done +
                    "]]; names: " + (names.empty() ? "(none: address entries by [index])" : names)};
  }
  throw PathError{"'" + done + "' is " + io::type_name(cur) + ", it has no key '" + key + "'"};
}

toml::node* step_index(toml::node& cur, std::size_t i, const std::string& done) {
  auto* a = cur.as_array();
  if (!a) throw PathError{"'" + done + "' is " + io::type_name(cur) + ", not an array"};
  if (i >= a->size())
    throw PathError{"index " + std::to_string(i) + " is beyond '" + done + "' (" + std::to_string(a->size()) +
                    " entries)"};
  return a->get(i);
}

/// The node a path names.
toml::node& walk(toml::table& root, const std::vector<Segment>& segs) {
  toml::node* cur = &root;
  std::string done;
  for (const auto& s : segs) {
    cur = step_key(*cur, s.key, done);
    done += (done.empty() ? "" : ".") + s.key;
    for (auto i : s.index) {
      cur = step_index(*cur, i, done);
      done += "[" + std::to_string(i) + "]";
    }
  }
  return *cur;
}

/// The numbers a parameter path names: one number, or every element of an array of numbers.
std::vector<toml::node*> number_leaves(toml::table& root, const std::string& path) {
  toml::node& n = walk(root, parse_path(path));
  if (n.is_number()) return {&n};
  if (auto* a = n.as_array(); a && !a->empty()) {
    std::vector<toml::node*> out;
    for (auto& e : *a) {
      if (!e.is_number()) break;
      out.push_back(&e);
    }
    if (out.size() == a->size()) return out;
  }
  throw PathError{"it is " + io::show(n) + " in the base file, not a number or an array of numbers"};
}

void set_number(toml::node& leaf, double v) {
  if (auto* i = leaf.as_integer())
    i->get() = std::llround(v);
  else
    leaf.as_floating_point()->get() = v;
}

double number_of(const toml::node& leaf) { return leaf.value<double>().value(); }

/// Sets a path to a copy of `value` (any TOML value); the last key may be new.
void assign(toml::table& root, const std::string& path, const toml::node& value) {
  auto segs = parse_path(path);
  Segment last = segs.back();
  segs.pop_back();
  toml::node* parent = segs.empty() ? static_cast<toml::node*>(&root) : &walk(root, segs);
  std::string done = path.substr(0, path.size() - last.key.size());
  if (!last.index.empty()) {
    parent = step_key(*parent, last.key, done);
    for (std::size_t k = 0; k + 1 < last.index.size(); ++k) parent = step_index(*parent, last.index[k], path);
    auto* a = parent->as_array();
    step_index(*parent, last.index.back(), path); // checks the range
    value.visit(
        [&](const auto& v) { a->replace(a->cbegin() + static_cast<std::ptrdiff_t>(last.index.back()), v); });
    return;
  }
  if (auto* a = parent->as_array(); a && a->is_array_of_tables()) { // a named entry replaced whole
    step_key(*parent, last.key, done);
    throw PathError{"'" + path + "' names a whole [[...]] entry; set its keys instead"};
  }
  auto* t = parent->as_table();
  if (!t) throw PathError{"'" + path + "': its parent is " + io::type_name(*parent) + ", not a table"};
  value.visit([&](const auto& v) { t->insert_or_assign(last.key, v); });
}

// ---------------------------------------------------------------- reading the study file

std::string context_of(const std::string& table, int index = -1) {
  return index < 0 ? "[" + table + "]" : "[[" + table + "]] " + std::to_string(index + 1);
}

void only_keys(const toml::table& t, const std::vector<std::string>& allowed, const std::string& ctx) {
  for (auto&& [key, v] : t) {
    if (std::find(allowed.begin(), allowed.end(), std::string(key.str())) != allowed.end()) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw Error(location(key.source()),
                ctx + " unknown key '" + std::string(key.str()) + "'; allowed: " + list);
  }
}

const toml::table* table_of(const toml::table& root, const std::string& key) {
  const auto* n = root.get(key);
  if (!n) return nullptr;
  if (!n->is_table()) throw Error(location(*n), "'" + key + "' must be a table [" + key + "]");
  return n->as_table();
}

std::vector<const toml::table*> tables_of(const toml::table& root, const std::string& key) {
  std::vector<const toml::table*> out;
  const auto* n = root.get(key);
  if (!n) return out;
  const auto* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    throw Error(location(*n), "'" + key + "' must be an array of tables [[" + key + "]]");
  for (const auto& e : *a) out.push_back(e.as_table());
  return out;
}

std::optional<double> number(const toml::table& t, const std::string& key, const std::string& ctx) {
  const auto* n = t.get(key);
  if (!n) return std::nullopt;
  if (!n->is_number() || !std::isfinite(n->value<double>().value()))
    throw Error(location(*n), ctx + " " + key + " = " + io::show(*n) + " must be a finite number");
  return n->value<double>().value();
}

double need_number(const toml::table& t, const std::string& key, const std::string& ctx,
                   const std::string& why) {
  auto v = number(t, key, ctx);
  if (!v) throw Error(location(t), ctx + " needs " + key + " (" + why + ")");
  return *v;
}

std::vector<double> numbers(const toml::table& t, const std::string& key, const std::string& ctx) {
  const auto* n = t.get(key);
  if (!n) return {};
  if (n->is_number()) return {*number(t, key, ctx)};
  const auto* a = n->as_array();
  std::vector<double> out;
  if (a)
    for (const auto& e : *a)
      if (e.is_number() && std::isfinite(e.value<double>().value())) out.push_back(e.value<double>().value());
  if (!a || a->empty() || out.size() != a->size())
    throw Error(location(*n),
                ctx + " " + key + " = " + io::show(*n) + " must be a number or a non-empty array of numbers");
  return out;
}

std::string text(const toml::table& t, const std::string& key, const std::string& ctx,
                 const std::vector<std::string>& choices = {}, std::string fallback = {}) {
  const auto* n = t.get(key);
  if (!n) {
    if (fallback.empty()) throw Error(location(t), ctx + " needs " + key);
    return fallback;
  }
  if (!n->is_string())
    throw Error(location(*n), ctx + " " + key + " = " + io::show(*n) + " must be a string");
  std::string v = n->as_string()->get();
  if (!choices.empty() && std::find(choices.begin(), choices.end(), v) == choices.end()) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    throw Error(location(*n), ctx + " " + key + " = \"" + v + "\" is not allowed; allowed: " + list);
  }
  return v;
}

bool good_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') return false;
  return true;
}

std::uint64_t fnv1a(std::uint64_t h, const std::string& s) {
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  h ^= 0xff; // a separator, so that ("ab", "c") and ("a", "bc") differ
  h *= 0x100000001b3ULL;
  return h;
}

std::string slurp(const std::string& path, const SourceLocation& where, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path)) throw Error(where, "cannot open " + what + " '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::vector<std::string> point_columns = {
    "step",   "eps_xx", "eps_yy", "eps_zz", "gamma_xy",  "gamma_yz", "gamma_zx", "sig_xx", "sig_yy",
    "sig_zz", "sig_xy", "sig_yz", "sig_zx", "eps_axial", "eps_vol",  "p",        "q"};
const std::vector<std::string> scene_columns = {"load", "settlement"};

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string csv_text(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

} // namespace

// ---------------------------------------------------------------- numbers

double Rng::uniform() { return (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53; }

std::uint64_t Rng::below(std::uint64_t n) {
  return static_cast<std::uint64_t>((static_cast<unsigned __int128>(engine_()) * n) >> 64);
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) return p == 0.0 ? -INFINITY : p == 1.0 ? INFINITY : nan;
  // P. J. Acklam's rational approximations (central region and tails), about 1e-9 relative.
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  const double p_low = 0.02425;
  double x;
  if (p < p_low || p > 1.0 - p_low) {
    const double q = std::sqrt(-2.0 * std::log(p < p_low ? p : 1.0 - p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    if (p > 1.0 - p_low) x = -x;
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  // One Halley step on Phi(x) - p (third-order convergence) brings it to rounding level.
  const double e = normal_cdf(x) - p;
  const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

double Parameter::quantile(double p) const {
  switch (distribution) {
  case Distribution::uniform:
    return lower + p * (upper - lower);
  case Distribution::normal:
    return mean + sd * normal_quantile(p);
  case Distribution::lognormal: {
    const double s2 = std::log1p((sd / mean) * (sd / mean));
    return std::exp(std::log(mean) - 0.5 * s2 + std::sqrt(s2) * normal_quantile(p));
  }
  case Distribution::truncated_normal: {
    const double fa = std::isfinite(lower) ? normal_cdf((lower - mean) / sd) : 0.0;
    const double fb = std::isfinite(upper) ? normal_cdf((upper - mean) / sd) : 1.0;
    return std::clamp(mean + sd * normal_quantile(fa + p * (fb - fa)), lower, upper);
  }
  }
  return nan;
}

double curve_at(const std::vector<std::array<double, 2>>& xy, double x0) {
  for (std::size_t i = 0; i + 1 < xy.size(); ++i) {
    const double xa = xy[i][0], xb = xy[i + 1][0];
    if ((x0 - xa) * (x0 - xb) > 0.0) continue;
    if (xa == xb) return xy[i][1];
    const double t = (x0 - xa) / (xb - xa);
    return xy[i][1] + t * (xy[i + 1][1] - xy[i][1]);
  }
  if (xy.size() == 1 && xy[0][0] == x0) return xy[0][1];
  return nan;
}

std::string format_number(double v) {
  if (std::isnan(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v + 0.0);
  return buf;
}

std::vector<std::string> Quantity::columns() const {
  if (kind != Kind::curve || !list) return {name};
  std::vector<std::string> c;
  for (double a : at) c.push_back(name + "@" + format_number(a));
  return c;
}

// ---------------------------------------------------------------- the study

Study Study::from_file(const std::string& path) {
  return from_string(slurp(path, SourceLocation{path, 0, 0}, "study file"), path);
}

Study Study::from_string(const std::string& text_in, const std::string& path) {
  toml::table root;
  try {
    root = toml::parse(text_in, path);
  } catch (const toml::parse_error& e) {
    throw Error(location(e.source()), "malformed TOML: " + std::string(e.description()));
  }
  only_keys(root, {"study", "fixed", "parameters", "quantities"}, "study file:");
  Study st;
  st.path_ = path;
  const auto* s = table_of(root, "study");
  if (!s)
    throw Error(SourceLocation{path, 1, 1}, "a study file needs a [study] table (scene or point, design)");
  const std::string sc = "[study]";
  only_keys(*s, {"scene", "point", "design", "samples", "seed", "sample_output", "threads"}, sc);
  if (s->get("scene") && s->get("point"))
    throw Error(location(*s->get("point")), sc + " names both a scene and a point file; give one");
  if (!s->get("scene") && !s->get("point"))
    throw Error(location(*s),
                sc + " needs scene = \"FILE.toml\" (stratum run) or point = \"FILE.toml\" (stratum point)");
  st.point_ = s->get("point") != nullptr;
  const std::string key = st.point_ ? "point" : "scene";
  const std::string base_rel = text(*s, key, sc);
  const fs::path dir = fs::path(path).parent_path();
  st.base_path_ =
      (fs::path(base_rel).is_absolute() ? fs::path(base_rel) : dir / base_rel).lexically_normal().string();
  const std::string base_text = slurp(st.base_path_, location(*s->get(key)), key + " file");
  const std::string design =
      text(*s, "design", sc, {"one_at_a_time", "grid", "latin_hypercube", "monte_carlo"});
  st.design_ = design == "one_at_a_time"     ? Design::one_at_a_time
               : design == "grid"            ? Design::grid
               : design == "latin_hypercube" ? Design::latin_hypercube
                                             : Design::monte_carlo;
  const bool sampled = st.design_ == Design::latin_hypercube || st.design_ == Design::monte_carlo;
  long long n_samples = 0, seed = 1;
  for (const char* k : {"samples", "seed", "threads"}) {
    const auto* n = s->get(k);
    if (!n) continue;
    if (!n->is_integer() || n->as_integer()->get() < (std::string(k) == "seed" ? 0 : 1))
      throw Error(location(*n),
                  sc + " " + k + " = " + io::show(*n) +
                      (std::string(k) == "seed" ? " must be an integer >= 0" : " must be an integer >= 1"));
    if (!sampled && std::string(k) != "threads")
      throw Error(location(*n),
                  sc + " " + k + " is for the sampled designs (latin_hypercube, monte_carlo), not " + design);
  }
  if (sampled) {
    if (!s->get("samples")) throw Error(location(*s), sc + " needs samples = N for design " + design);
    n_samples = s->get("samples")->as_integer()->get();
    if (n_samples > 10000000) throw Error(location(*s->get("samples")), sc + " samples must be at most 1e7");
    if (s->get("seed")) seed = s->get("seed")->as_integer()->get();
  }
  long long threads = s->get("threads") ? s->get("threads")->as_integer()->get() : 1;
  if (const auto* o = s->get("sample_output")) {
    if (!o->is_boolean()) throw Error(location(*o), sc + " sample_output must be true or false");
    st.sample_output_ = o->as_boolean()->get();
  }

  // The base file with the fixed settings (and one element-loop thread per sample) applied.
  auto base = std::make_shared<Base>();
  try {
    base->root = toml::parse(base_text, st.base_path_);
  } catch (const toml::parse_error& e) {
    throw Error(location(e.source()), "malformed TOML: " + std::string(e.description()));
  }
  if (!st.point_) {
    toml::value<int64_t> t(threads);
    if (!base->root.get("analysis")) base->root.insert("analysis", toml::table{});
    try {
      assign(base->root, "analysis.threads", t);
    } catch (const PathError& e) {
      throw Error(location(*s), sc + " threads: " + e.message);
    }
  }
  if (const auto* f = table_of(root, "fixed")) {
    for (auto&& [k, v] : *f) {
      try {
        assign(base->root, std::string(k.str()), v);
      } catch (const PathError& e) {
        throw Error(location(k.source()),
                    "[fixed] '" + std::string(k.str()) + "': " + e.message + " (in " + st.base_path_ + ")");
      }
    }
  }

  // Parameters.
  std::set<std::string> names = {"index", "varied", "status", "reason"};
  const auto ptables = tables_of(root, "parameters");
  if (ptables.empty())
    throw Error(SourceLocation{path, 1, 1},
                "a study needs at least one [[parameters]] entry (name, path, ...)");
  for (std::size_t i = 0; i < ptables.size(); ++i) {
    const auto& t = *ptables[i];
    const std::string ctx = context_of("parameters", static_cast<int>(i));
    std::vector<std::string> allowed = {"name", "path", "paths", "scale"};
    if (st.design_ == Design::one_at_a_time) allowed.insert(allowed.end(), {"low", "high"});
    if (st.design_ == Design::grid) allowed.insert(allowed.end(), {"values", "low", "high", "levels"});
    if (sampled) allowed.insert(allowed.end(), {"distribution", "mean", "sd", "lower", "upper"});
    only_keys(t, allowed, ctx + " (design " + design + ")");
    Parameter p;
    p.where = location(t);
    p.name = text(t, "name", ctx);
    if (!good_name(p.name) || !names.insert(p.name).second)
      throw Error(location(*t.get("name")),
                  ctx + " name '" + p.name + "' must be new and made of letters, digits, '_', '-', '.'");
    if (t.get("path") && t.get("paths"))
      throw Error(location(*t.get("paths")), ctx + " give path or paths, not both");
    if (t.get("path")) {
      p.paths.push_back(text(t, "path", ctx));
    } else if (const auto* n2 = t.get("paths")) {
      const auto* a = n2->as_array();
      if (!a || a->empty()) throw Error(location(*n2), ctx + " paths must be a non-empty array of strings");
      for (const auto& e : *a) {
        if (!e.is_string()) throw Error(location(e), ctx + " paths must be a non-empty array of strings");
        p.paths.push_back(e.as_string()->get());
      }
    } else {
      throw Error(location(t),
                  ctx + " needs path = \"table.key\" (or paths = [...]) in the " + key + " file");
    }
    if (const auto* sc2 = t.get("scale")) {
      if (!sc2->is_boolean()) throw Error(location(*sc2), ctx + " scale must be true or false");
      p.scale = sc2->as_boolean()->get();
    }
    // Every path must name numbers of the base file.
    p.integer = !p.scale;
    {
      const toml::node* pn = t.get("path") ? t.get("path") : t.get("paths");
      for (std::size_t k = 0; k < p.paths.size(); ++k) {
        const toml::node* where = pn->is_array() ? pn->as_array()->get(k) : pn;
        try {
          for (auto* leaf : number_leaves(base->root, p.paths[k]))
            p.integer = p.integer && leaf->is_integer();
        } catch (const PathError& e) {
          throw Error(location(*where),
                      ctx + " path '" + p.paths[k] + "': " + e.message + " (in " + st.base_path_ + ")");
        }
      }
    }
    if (st.design_ == Design::one_at_a_time) {
      p.low = need_number(t, "low", ctx, "the low value of the one-at-a-time design");
      p.high = need_number(t, "high", ctx, "the high value");
    } else if (st.design_ == Design::grid) {
      if (t.get("values")) {
        if (t.get("low") || t.get("high") || t.get("levels"))
          throw Error(location(*t.get("values")),
                      ctx + " give values = [...] or low, high and levels, not both");
        p.values = numbers(t, "values", ctx);
      } else {
        const double lo = need_number(t, "low", ctx, "or values = [...]"),
                     hi = need_number(t, "high", ctx, "");
        const auto* lv = t.get("levels");
        if (!lv || !lv->is_integer() || lv->as_integer()->get() < 2 || lv->as_integer()->get() > 100000)
          throw Error(lv ? location(*lv) : location(t),
                      ctx + " needs levels = an integer from 2 (with low and high)");
        const auto n = lv->as_integer()->get();
        for (long long k = 0; k < n; ++k)
          p.values.push_back(lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(n - 1));
      }
    } else {
      const std::string dist =
          text(t, "distribution", ctx, {"uniform", "normal", "lognormal", "truncated_normal"}, "uniform");
      const auto where = t.get("distribution") ? location(*t.get("distribution")) : location(t);
      auto forbid = [&](std::initializer_list<const char*> keys) {
        for (const char* k : keys)
          if (t.get(k))
            throw Error(location(*t.get(k)),
                        ctx + " " + k + " is not a parameter of the " + dist + " distribution");
      };
      if (dist == "uniform") {
        forbid({"mean", "sd"});
        p.distribution = Distribution::uniform;
        p.lower = need_number(t, "lower", ctx, "uniform distribution");
        p.upper = need_number(t, "upper", ctx, "uniform distribution");
        if (!(p.lower < p.upper)) throw Error(where, ctx + " needs lower < upper");
      } else {
        p.mean = need_number(t, "mean", ctx, dist + " distribution");
        p.sd = need_number(t, "sd", ctx, "standard deviation, " + dist + " distribution");
        if (!(p.sd > 0.0)) throw Error(location(*t.get("sd")), ctx + " sd must be > 0");
        if (dist == "normal" || dist == "lognormal") {
          forbid({"lower", "upper"});
          p.distribution = dist == "normal" ? Distribution::normal : Distribution::lognormal;
          if (dist == "lognormal" && !(p.mean > 0.0))
            throw Error(location(*t.get("mean")), ctx + " a lognormal mean must be > 0");
        } else {
          p.distribution = Distribution::truncated_normal;
          p.lower = number(t, "lower", ctx).value_or(-INFINITY);
          p.upper = number(t, "upper", ctx).value_or(INFINITY);
          if (!t.get("lower") && !t.get("upper"))
            throw Error(where, ctx + " a truncated_normal needs lower and/or upper");
          if (!(p.lower < p.upper)) throw Error(where, ctx + " needs lower < upper");
          if (normal_cdf((p.upper - p.mean) / p.sd) - normal_cdf((p.lower - p.mean) / p.sd) < 1e-9)
            throw Error(where, ctx + " [lower, upper] holds almost none of the normal distribution");
        }
      }
    }
    st.params_.push_back(std::move(p));
  }

  // Quantities.
  const auto& allowed_xy = st.point_ ? point_columns : scene_columns;
  std::string xy_list;
  for (const auto& c : allowed_xy) xy_list += (xy_list.empty() ? "" : ", ") + c;
  const auto qtables = tables_of(root, "quantities");
  for (std::size_t i = 0; i < qtables.size(); ++i) {
    const auto& t = *qtables[i];
    const std::string ctx = context_of("quantities", static_cast<int>(i));
    only_keys(t, {"name", "type", "x", "y", "at"}, ctx);
    Quantity q;
    q.name = text(t, "name", ctx);
    const std::vector<std::string> kinds =
        st.point_ ? std::vector<std::string>{"curve", "last", "steps"}
                  : std::vector<std::string>{"curve", "last", "steps", "cutbacks", "iterations"};
    const std::string type = text(t, "type", ctx, kinds);
    q.kind = type == "curve"      ? Quantity::Kind::curve
             : type == "last"     ? Quantity::Kind::last
             : type == "steps"    ? Quantity::Kind::steps
             : type == "cutbacks" ? Quantity::Kind::cutbacks
                                  : Quantity::Kind::iterations;
    if (q.kind == Quantity::Kind::curve || q.kind == Quantity::Kind::last) {
      if (q.kind == Quantity::Kind::curve) q.x = text(t, "x", ctx, allowed_xy);
      q.y = text(t, "y", ctx, allowed_xy);
    } else {
      for (const char* k : {"x", "y", "at"})
        if (t.get(k))
          throw Error(location(*t.get(k)), ctx + " " + k + " is only for the types curve and last");
    }
    if (q.kind == Quantity::Kind::curve) {
      if (!t.get("at"))
        throw Error(location(t), ctx + " needs at = the abscissa (or a list of them) of the curve");
      q.at = numbers(t, "at", ctx);
      q.list = t.get("at")->is_array();
    } else if (t.get("at")) {
      throw Error(location(*t.get("at")), ctx + " at is only for the type curve");
    }
    for (const auto& c : q.columns())
      if (!good_name(q.name) || !names.insert(c).second)
        throw Error(location(*t.get("name")),
                    ctx + " column '" + c + "' must be new and made of letters, digits, '_', '-', '.', '@'");
    st.quantities_.push_back(std::move(q));
  }

  // The samples.
  const std::size_t np = st.params_.size();
  auto push = [&](std::vector<double> v, std::string varied) {
    for (std::size_t j = 0; j < np; ++j)
      if (st.params_[j].integer) v[j] = static_cast<double>(std::llround(v[j]));
    Sample smp;
    smp.index = static_cast<int>(st.samples_.size());
    smp.varied = std::move(varied);
    smp.values = std::move(v);
    st.samples_.push_back(std::move(smp));
  };
  if (st.design_ == Design::one_at_a_time) {
    std::vector<double> b(np);
    for (std::size_t j = 0; j < np; ++j)
      b[j] = st.params_[j].scale ? 1.0 : number_of(*number_leaves(base->root, st.params_[j].paths[0])[0]);
    push(b, "base");
    for (std::size_t j = 0; j < np; ++j) {
      auto lo = b, hi = b;
      lo[j] = st.params_[j].low;
      hi[j] = st.params_[j].high;
      push(lo, st.params_[j].name + ":low");
      push(hi, st.params_[j].name + ":high");
    }
  } else if (st.design_ == Design::grid) {
    std::size_t total = 1;
    for (const auto& p : st.params_) {
      total *= p.values.size();
      if (total > 10000000) throw Error(SourceLocation{path, 1, 1}, "the grid has more than 1e7 points");
    }
    for (std::size_t k = 0; k < total; ++k) {
      std::vector<double> v(np);
      std::size_t r = k;
      for (std::size_t j = np; j-- > 0;) { // the last parameter varies fastest
        v[j] = st.params_[j].values[r % st.params_[j].values.size()];
        r /= st.params_[j].values.size();
      }
      push(v, "");
    }
  } else {
    const auto n = static_cast<std::size_t>(n_samples);
    std::vector<std::vector<double>> u(n, std::vector<double>(np));
    Rng rng(static_cast<std::uint64_t>(seed));
    if (st.design_ == Design::monte_carlo) {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < np; ++j) u[i][j] = rng.uniform();
    } else {
      for (std::size_t j = 0; j < np; ++j) {
        std::vector<std::size_t> perm(n);
        for (std::size_t i = 0; i < n; ++i) perm[i] = i;
        for (std::size_t i = n; i-- > 1;) std::swap(perm[i], perm[rng.below(i + 1)]); // Fisher-Yates
        for (std::size_t i = 0; i < n; ++i)
          u[i][j] = (static_cast<double>(perm[i]) + rng.uniform()) / static_cast<double>(n);
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<double> v(np);
      for (std::size_t j = 0; j < np; ++j) v[j] = st.params_[j].quantile(u[i][j]);
      push(v, "");
    }
  }
  st.base_ = std::move(base);
  std::uint64_t h = 0xcbf29ce484222325ULL;
  h = fnv1a(h, text_in);
  h = fnv1a(h, base_text);
  h = fnv1a(h, st.header());
  char hex[20];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  st.hash_ = hex;
  return st;
}

std::string Study::header() const {
  std::string h = "index";
  if (design_ == Design::one_at_a_time) h += ",varied";
  for (const auto& p : params_) h += "," + p.name;
  for (const auto& q : quantities_)
    for (const auto& c : q.columns()) h += "," + c;
  return h + ",status,reason";
}

std::string Study::scene_text(int index) const {
  toml::table root = base_->root;
  const Sample& smp = samples_.at(static_cast<std::size_t>(index));
  for (std::size_t j = 0; j < params_.size(); ++j) {
    const auto& p = params_[j];
    for (const auto& path : p.paths)
      for (auto* leaf : number_leaves(root, path))
        set_number(*leaf, p.scale ? number_of(*leaf) * smp.values[j] : smp.values[j]);
  }
  std::ostringstream o;
  o << root << "\n";
  return o.str();
}

SampleResult Study::run(int index, const std::string& out_dir) const {
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_seconds();
  const Sample& smp = samples_.at(static_cast<std::size_t>(index));
  std::string status = "failed", reason;
  std::map<std::string, std::vector<double>> cols;
  double steps = nan, cutbacks = nan, iterations = nan;
  const fs::path sample_dir = fs::path(out_dir) / "samples" / std::to_string(index);
  try {
    const std::string text = scene_text(index);
    if (point_) {
      const auto driver = PointDriver::from_string(text, base_path_);
      const PointRun r = driver->run();
      if (sample_output_) PointDriver::write_csv(r, (sample_dir / "point.csv").string());
      for (const auto& row : r.rows) {
        const auto& e = row.strain;
        const auto& s = row.stress;
        const double q = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                                          (s[2] - s[0]) * (s[2] - s[0])) +
                                   3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
        const double v[] = {static_cast<double>(row.step),
                            e[0],
                            e[1],
                            e[2],
                            e[3],
                            e[4],
                            e[5],
                            s[0],
                            s[1],
                            s[2],
                            s[3],
                            s[4],
                            s[5],
                            -e[1],
                            -(e[0] + e[1] + e[2]),
                            -(s[0] + s[1] + s[2]) / 3,
                            q};
        for (std::size_t k = 0; k < point_columns.size(); ++k) cols[point_columns[k]].push_back(v[k]);
      }
      steps = r.rows.empty() ? 0.0 : static_cast<double>(r.rows.size() - 1);
      status = r.outcome.ok() ? "converged" : "failed";
      if (!r.outcome.ok()) reason = std::string(to_string(r.outcome.status)) + ": " + r.outcome.message;
    } else {
      RunOptions o;
      o.write_output = sample_output_;
      o.out_dir = sample_dir.string();
      const auto analysis = Analysis::from_string(text, base_path_, o);
      const RunSummary s = analysis->run();
      for (const auto& r : s.load_settlement) {
        cols["load"].push_back(r[0]);
        cols["settlement"].push_back(r[1]);
      }
      steps = s.steps_done;
      cutbacks = s.cutbacks;
      iterations = 0.0;
      for (const auto& r : s.reports) iterations += r.iterations;
      if (!s.outcome.ok()) {
        reason = std::string(to_string(s.outcome.status)) + ": " + s.outcome.message;
      } else if (!s.stop_reason.empty()) {
        status = "stopped";
        reason = s.stop_reason + (s.stop_message.empty() ? "" : ": " + s.stop_message);
      } else {
        status = "converged";
      }
    }
  } catch (const Error& e) {
    // A place in the sample's scene names its line in the text --print-scene shows (not in the
    // base file, and not by the path the study was given by: the row must not depend on it).
    const auto& w = e.where();
    reason = w.file == base_path_ ? "line " + std::to_string(w.line) + ":" + std::to_string(w.column) +
                                        " of the sample's scene (stratum sweep --print-scene " +
                                        std::to_string(index) + "): " + e.message()
                                  : e.what();
  } catch (const std::exception& e) {
    reason = std::string("internal error: ") + e.what();
  }

  std::string row = std::to_string(index);
  if (design_ == Design::one_at_a_time) row += "," + smp.varied;
  for (double v : smp.values) row += "," + format_number(v);
  for (const auto& q : quantities_) {
    const auto& y = cols[q.y];
    switch (q.kind) {
    case Quantity::Kind::curve: {
      const auto& x = cols[q.x];
      std::vector<std::array<double, 2>> xy(x.size());
      for (std::size_t k = 0; k < x.size(); ++k) xy[k] = {x[k], y[k]};
      for (double a : q.at) row += "," + format_number(curve_at(xy, a));
      break;
    }
    case Quantity::Kind::last:
      row += "," + format_number(y.empty() ? nan : y.back());
      break;
    case Quantity::Kind::steps:
      row += "," + format_number(steps);
      break;
    case Quantity::Kind::cutbacks:
      row += "," + format_number(cutbacks);
      break;
    case Quantity::Kind::iterations:
      row += "," + format_number(iterations);
      break;
    }
  }
  row += "," + status + "," + (reason.empty() ? std::string() : csv_text(reason));
  SampleResult r;
  r.index = index;
  r.row = std::move(row);
  r.status = status;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_seconds = thread_cpu_seconds() - cpu0;
  return r;
}

} // namespace stratum::sweep
