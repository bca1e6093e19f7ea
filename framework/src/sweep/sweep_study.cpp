// Parameter studies: reading the study file and its designs (framework/src/sweep/sweep.hpp).
#include "sweep_study.hpp"
#include "files.hpp"
#include "sweep/sweep.hpp"

#include "scene/recorder_spec.hpp"
#include "scene/toml_check.hpp"
#include "stratum/analysis.hpp"
#include "stratum/point_driver.hpp"
#include "sweep_toml.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <set>

namespace fs = std::filesystem;

namespace stratum::sweep {
namespace {

using namespace detail;
using io::location;

std::uint64_t fnv1a(std::uint64_t h, const std::string& s) {
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  h ^= 0xff; // a separator, so that ("ab", "c") and ("a", "bc") differ
  h *= 0x100000001b3ULL;
  return h;
}

const std::vector<std::string> scene_columns = {"load", "settlement"};

} // namespace

bool detail::good_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') return false;
  return true;
}

std::string detail::hash_of(const std::vector<std::string>& texts) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const auto& t : texts) h = fnv1a(h, t);
  char hex[20];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

const std::vector<std::string>& detail::pile_component_columns() {
  static const std::vector<std::string> columns = {"head_settlement", "pile_shortening", "base_settlement",
                                                   "shaft_slip_mean", "shaft_slip_top",  "shaft_load",
                                                   "base_load"};
  return columns;
}

const std::vector<std::string>& detail::point_columns() {
  static const std::vector<std::string> columns = {
      "step",   "eps_xx", "eps_yy", "eps_zz", "gamma_xy",  "gamma_yz", "gamma_zx", "sig_xx", "sig_yy",
      "sig_zz", "sig_xy", "sig_yz", "sig_zx", "eps_axial", "eps_vol",  "p",        "q"};
  return columns;
}

// ---------------------------------------------------------------- the study

namespace {

/// The [study] table as read: what the rest of the study file is checked against.
struct StudySettings {
  const toml::table* table = nullptr;
  bool point = false;
  std::string key;                  ///< "point" or "scene"
  std::string base_path, base_text; ///< the base file, relative to the study file's folder
  std::string design;               ///< as written
  Design kind = Design::one_at_a_time;
  bool sampled = false; ///< latin_hypercube or monte_carlo
  long long n_samples = 0, seed = 1, threads = 1;
  bool sample_output = false;
};

/// The most element-loop threads a sample may have: the bound of [analysis] threads.
constexpr long long max_threads = 256;

/// Checks samples, seed and threads of [study] (integers, only where the design uses them).
void check_counts(const toml::table& s, const std::string& sc, bool sampled, const std::string& design) {
  for (const char* k : {"samples", "seed", "threads"}) {
    const auto* n = s.get(k);
    if (!n) continue;
    if (!n->is_integer() || n->as_integer()->get() < (std::string(k) == "seed" ? 0 : 1))
      throw Error(location(*n),
                  sc + " " + k + " = " + io::show(*n) +
                      (std::string(k) == "seed" ? " must be an integer >= 0" : " must be an integer >= 1"));
    // The element-loop threads of each sample: [analysis] threads takes at most 256, and more than
    // the machine's cores only makes the samples slower.
    if (std::string(k) == "threads" && n->as_integer()->get() > max_threads)
      throw Error(location(*n), sc + " threads = " + io::show(*n) + " must be at most " +
                                    std::to_string(max_threads) +
                                    " (element-loop threads per sample; the processes are the parallelism)");
    if (!sampled && std::string(k) != "threads")
      throw Error(location(*n),
                  sc + " " + k + " is for the sampled designs (latin_hypercube, monte_carlo), not " + design);
  }
}

/// Reads [study]: the base file (read here), the design and the sample counts.
StudySettings read_study_table(const toml::table& root, const std::string& path) {
  StudySettings r;
  const auto* s = table_of(root, "study");
  if (!s)
    throw Error(SourceLocation{path, 1, 1}, "a study file needs a [study] table (scene or point, design)");
  r.table = s;
  const std::string sc = "[study]";
  only_keys(*s, {"scene", "point", "design", "samples", "seed", "sample_output", "threads"}, sc);
  BaseFile base = read_base_file(*s, sc, path);
  r.point = base.point;
  r.key = std::move(base.key);
  r.base_path = std::move(base.path);
  r.base_text = std::move(base.text);
  r.design = text(*s, "design", sc, {"one_at_a_time", "grid", "latin_hypercube", "monte_carlo"});
  r.kind = r.design == "one_at_a_time"     ? Design::one_at_a_time
           : r.design == "grid"            ? Design::grid
           : r.design == "latin_hypercube" ? Design::latin_hypercube
                                           : Design::monte_carlo;
  r.sampled = r.kind == Design::latin_hypercube || r.kind == Design::monte_carlo;
  check_counts(*s, sc, r.sampled, r.design);
  if (r.sampled) {
    if (!s->get("samples")) throw Error(location(*s), sc + " needs samples = N for design " + r.design);
    r.n_samples = s->get("samples")->as_integer()->get();
    if (r.n_samples > 10000000)
      throw Error(location(*s->get("samples")), sc + " samples must be at most 1e7");
    if (s->get("seed")) r.seed = s->get("seed")->as_integer()->get();
  }
  r.threads = s->get("threads") ? s->get("threads")->as_integer()->get() : 1;
  if (const auto* o = s->get("sample_output")) {
    if (!o->is_boolean()) throw Error(location(*o), sc + " sample_output must be true or false");
    r.sample_output = o->as_boolean()->get();
  }
  return r;
}

} // namespace

BaseFile detail::read_base_file(const toml::table& t, const std::string& ctx, const std::string& study_path) {
  if (t.get("scene") && t.get("point"))
    throw Error(location(*t.get("point")), ctx + " names both a scene and a point file; give one");
  if (!t.get("scene") && !t.get("point"))
    throw Error(location(t),
                ctx + " needs scene = \"FILE.toml\" (stratum run) or point = \"FILE.toml\" (stratum point)");
  BaseFile b;
  b.point = t.get("point") != nullptr;
  b.key = b.point ? "point" : "scene";
  const std::string rel = text(t, b.key, ctx);
  const fs::path dir = fs::path(study_path).parent_path();
  b.path = (fs::path(rel).is_absolute() ? fs::path(rel) : dir / rel).lexically_normal().string();
  b.text = read_text_file(b.path, location(*t.get(b.key)), b.key + " file",
                          b.point ? file_limits::point : file_limits::scene);
  return b;
}

void detail::apply_fixed(const toml::table& study_root, toml::table& base_root, const std::string& base_path,
                         bool point, long long threads, const toml::node& threads_where) {
  if (!point) {
    toml::value<int64_t> t(threads);
    if (!base_root.get("analysis")) base_root.insert("analysis", toml::table{});
    try {
      assign(base_root, "analysis.threads", t);
    } catch (const PathError& e) {
      throw Error(location(threads_where), "threads: " + e.message);
    }
  }
  if (const auto* f = table_of(study_root, "fixed")) {
    for (auto&& [k, v] : *f) {
      try {
        assign(base_root, std::string(k.str()), v);
      } catch (const PathError& e) {
        throw Error(location(k.source()),
                    "[fixed] '" + std::string(k.str()) + "': " + e.message + " (in " + base_path + ")");
      }
    }
  }
}

namespace {

/// The base file with the fixed settings (and one element-loop thread per sample) applied.
std::shared_ptr<Study::Base> read_base(const toml::table& root, const StudySettings& ss) {
  auto base = std::make_shared<Study::Base>();
  base->root = io::parse_with_includes(ss.base_text, ss.base_path);
  apply_fixed(root, base->root, ss.base_path, ss.point, ss.threads, *ss.table);
  return base;
}

} // namespace

void detail::read_paths(const toml::table& t, const std::string& ctx, const std::string& key,
                        toml::table& base_root, const std::string& base_path, Parameter& p) {
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
    throw Error(location(t), ctx + " needs path = \"table.key\" (or paths = [...]) in the " + key + " file");
  }
  if (const auto* sc2 = t.get("scale")) {
    if (!sc2->is_boolean()) throw Error(location(*sc2), ctx + " scale must be true or false");
    p.scale = sc2->as_boolean()->get();
  }
  // Every path must name numbers of the base file.
  p.integer = !p.scale;
  const toml::node* pn = t.get("path") ? t.get("path") : t.get("paths");
  for (std::size_t k = 0; k < p.paths.size(); ++k) {
    const toml::node* where = pn->is_array() ? pn->as_array()->get(k) : pn;
    try {
      for (auto* leaf : number_leaves(base_root, p.paths[k])) p.integer = p.integer && leaf->is_integer();
    } catch (const PathError& e) {
      throw Error(location(*where),
                  ctx + " path '" + p.paths[k] + "': " + e.message + " (in " + base_path + ")");
    }
  }
}

namespace {

/// A grid parameter's levels: values = [...], or levels equally spaced from low to high.
void read_grid_values(const toml::table& t, const std::string& ctx, Parameter& p) {
  if (t.get("values")) {
    if (t.get("low") || t.get("high") || t.get("levels"))
      throw Error(location(*t.get("values")), ctx + " give values = [...] or low, high and levels, not both");
    p.values = numbers(t, "values", ctx);
    return;
  }
  const double lo = need_number(t, "low", ctx, "or values = [...]"), hi = need_number(t, "high", ctx, "");
  const auto* lv = t.get("levels");
  if (!lv || !lv->is_integer() || lv->as_integer()->get() < 2 || lv->as_integer()->get() > 100000)
    throw Error(lv ? location(*lv) : location(t),
                ctx + " needs levels = an integer from 2 (with low and high)");
  const auto n = lv->as_integer()->get();
  for (long long k = 0; k < n; ++k)
    p.values.push_back(lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(n - 1));
}

/// A sampled parameter's distribution and its parameters.
void read_distribution(const toml::table& t, const std::string& ctx, Parameter& p) {
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
    return;
  }
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

/// The [[parameters]] entry i; its name goes into `names` (the samples.csv columns so far).
Parameter read_parameter(const toml::table& t, std::size_t i, const StudySettings& ss, toml::table& base_root,
                         std::set<std::string>& names) {
  const std::string ctx = context_of("parameters", static_cast<int>(i));
  std::vector<std::string> allowed = {"name", "path", "paths", "scale"};
  if (ss.kind == Design::one_at_a_time) allowed.insert(allowed.end(), {"low", "high"});
  if (ss.kind == Design::grid) allowed.insert(allowed.end(), {"values", "low", "high", "levels"});
  if (ss.sampled) allowed.insert(allowed.end(), {"distribution", "mean", "sd", "lower", "upper"});
  only_keys(t, allowed, ctx + " (design " + ss.design + ")");
  Parameter p;
  p.where = location(t);
  p.name = text(t, "name", ctx);
  if (!good_name(p.name) || !names.insert(p.name).second)
    throw Error(location(*t.get("name")),
                ctx + " name '" + p.name + "' must be new and made of letters, digits, '_', '-', '.'");
  read_paths(t, ctx, ss.key, base_root, ss.base_path, p);
  if (ss.kind == Design::one_at_a_time) {
    p.low = need_number(t, "low", ctx, "the low value of the one-at-a-time design");
    p.high = need_number(t, "high", ctx, "the high value");
  } else if (ss.kind == Design::grid) {
    read_grid_values(t, ctx, p);
  } else {
    read_distribution(t, ctx, p);
  }
  return p;
}

} // namespace

StudyColumns detail::scene_study_columns(const toml::table& base) {
  StudyColumns c;
  c.allowed = scene_columns;
  // The settlement components of a pile whose cells the scene names ([output] pile_cells), the
  // rows of curves/settlement_components.csv (pile_components.hpp), one per row of the curve.
  const toml::table* output = table_of(base, "output");
  if (output && output->get("pile_cells"))
    c.allowed.insert(c.allowed.end(), pile_component_columns().begin(), pile_component_columns().end());
  if (output)
    for (const toml::table* h : tables_of(*output, "history")) {
      const RecorderSpec r = read_recorder(*h, "[[output.history]]", Units{});
      if (r.kind == "interface") continue;
      for (const char* k : {"stage", "step", "lambda"}) c.allowed.push_back(r.name + "." + k);
      for (const auto& q : r.quantities)
        if (q != "lambda") c.allowed.push_back(r.name + "." + q);
    }
  for (const toml::table* st : tables_of(base, "stages"))
    if (const auto* n = st->get("name"); n && n->is_string()) c.stages.push_back(n->as_string()->get());
  return c;
}

int detail::stage_index(const toml::table& t, const std::string& key, const std::string& ctx,
                        const StudyColumns& columns) {
  const std::string name = text(t, key, ctx);
  const auto it = std::find(columns.stages.begin(), columns.stages.end(), name);
  if (it == columns.stages.end()) {
    std::string list;
    for (const auto& n : columns.stages) list += (list.empty() ? "" : ", ") + n;
    throw Error(location(*t.get(key)), ctx + " " + key + " = \"" + name +
                                           "\" is not a stage of the base scene; its stages: " +
                                           (list.empty() ? "(none named)" : list));
  }
  return static_cast<int>(it - columns.stages.begin()) + 1;
}

namespace {

/// The [[quantities]] entry i; its columns go into `names`.
Quantity read_quantity(const toml::table& t, std::size_t i, bool point, const StudyColumns& columns,
                       std::set<std::string>& names) {
  const std::string ctx = context_of("quantities", static_cast<int>(i));
  only_keys(t, {"name", "type", "x", "y", "at", "stage"}, ctx);
  const auto& allowed_xy = columns.allowed;
  Quantity q;
  q.name = text(t, "name", ctx);
  const std::vector<std::string> kinds =
      point ? std::vector<std::string>{"curve", "last", "max", "min", "steps"}
            : std::vector<std::string>{"curve", "last", "max", "min", "steps", "cutbacks", "iterations"};
  const std::string type = text(t, "type", ctx, kinds);
  q.kind = type == "curve"      ? Quantity::Kind::curve
           : type == "last"     ? Quantity::Kind::last
           : type == "max"      ? Quantity::Kind::max
           : type == "min"      ? Quantity::Kind::min
           : type == "steps"    ? Quantity::Kind::steps
           : type == "cutbacks" ? Quantity::Kind::cutbacks
                                : Quantity::Kind::iterations;
  const bool reads_y = q.kind == Quantity::Kind::curve || q.kind == Quantity::Kind::last ||
                       q.kind == Quantity::Kind::max || q.kind == Quantity::Kind::min;
  const auto recorder_column = [](const std::string& c) { return c.find('.') != std::string::npos; };
  if (reads_y) {
    if (q.kind == Quantity::Kind::curve) q.x = text(t, "x", ctx, allowed_xy);
    q.y = text(t, "y", ctx, allowed_xy);
    if (!q.x.empty() && recorder_column(q.x) != recorder_column(q.y))
      throw Error(location(*t.get("x")),
                  ctx + " x = \"" + q.x + "\" and y = \"" + q.y +
                      "\" must both be recorder columns or both the pile curve's (load, "
                      "settlement): their rows are not the same steps");
  } else {
    for (const char* k : {"x", "y", "at", "stage"})
      if (t.get(k))
        throw Error(location(*t.get(k)), ctx + " " + k + " is only for the types curve, last, max and min");
  }
  if (const toml::node* st = t.get("stage")) {
    if (!recorder_column(q.y) || (!q.x.empty() && !recorder_column(q.x)))
      throw Error(location(*st), ctx + " stage acts only on recorder columns (\"<recorder>.<column>\"); the "
                                       "pile curve's load and settlement are those of its loaded stages");
    q.stage = stage_index(t, "stage", ctx, columns);
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
  return q;
}

/// Appends a sample of values v (rounded where the parameter is an integer), numbered in order.
void push_sample(std::vector<Sample>& samples, const std::vector<Parameter>& params, std::vector<double> v,
                 std::string varied) {
  for (std::size_t j = 0; j < params.size(); ++j)
    if (params[j].integer) v[j] = static_cast<double>(std::llround(v[j]));
  Sample smp;
  smp.index = static_cast<int>(samples.size());
  smp.varied = std::move(varied);
  smp.values = std::move(v);
  samples.push_back(std::move(smp));
}

/// The one-at-a-time design: the base values, then each parameter at its low and its high value.
std::vector<Sample> one_at_a_time_samples(const std::vector<Parameter>& params, toml::table& base_root) {
  const std::size_t np = params.size();
  std::vector<Sample> samples;
  std::vector<double> b(np);
  for (std::size_t j = 0; j < np; ++j)
    b[j] = params[j].scale ? 1.0 : number_of(*number_leaves(base_root, params[j].paths[0])[0]);
  push_sample(samples, params, b, "base");
  for (std::size_t j = 0; j < np; ++j) {
    auto lo = b, hi = b;
    lo[j] = params[j].low;
    hi[j] = params[j].high;
    push_sample(samples, params, lo, params[j].name + ":low");
    push_sample(samples, params, hi, params[j].name + ":high");
  }
  return samples;
}

/// The grid design: every combination of the levels, the last parameter varying fastest.
std::vector<Sample> grid_samples(const std::vector<Parameter>& params, const std::string& path) {
  const std::size_t np = params.size();
  std::vector<Sample> samples;
  std::size_t total = 1;
  for (const auto& p : params) {
    total *= p.values.size();
    if (total > 10000000) throw Error(SourceLocation{path, 1, 1}, "the grid has more than 1e7 points");
  }
  for (std::size_t k = 0; k < total; ++k) {
    std::vector<double> v(np);
    std::size_t r = k;
    for (std::size_t j = np; j-- > 0;) { // the last parameter varies fastest
      v[j] = params[j].values[r % params[j].values.size()];
      r /= params[j].values.size();
    }
    push_sample(samples, params, v, "");
  }
  return samples;
}

/// The sampled designs: n samples, Monte Carlo or a Latin hypercube, from the seed.
std::vector<Sample> random_samples(const std::vector<Parameter>& params, Design design, long long n_samples,
                                   long long seed) {
  const std::size_t np = params.size();
  std::vector<Sample> samples;
  const auto n = static_cast<std::size_t>(n_samples);
  std::vector<std::vector<double>> u(n, std::vector<double>(np));
  Rng rng(static_cast<std::uint64_t>(seed));
  if (design == Design::monte_carlo) {
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
    for (std::size_t j = 0; j < np; ++j) v[j] = params[j].quantile(u[i][j]);
    push_sample(samples, params, v, "");
  }
  return samples;
}

} // namespace

Study Study::from_file(const std::string& path) {
  return from_string(read_text_file(path, SourceLocation{path, 0, 0}, "study file", file_limits::study),
                     path);
}

Study Study::from_string(const std::string& text_in, const std::string& path) {
  toml::table root = io::parse_with_includes(text_in, path);
  only_keys(root, {"study", "fixed", "parameters", "quantities"}, "study file:");
  Study st;
  st.path_ = path;
  const StudySettings ss = read_study_table(root, path);
  st.point_ = ss.point;
  st.base_path_ = ss.base_path;
  st.design_ = ss.kind;
  st.sample_output_ = ss.sample_output;
  auto base = read_base(root, ss);

  // Parameters.
  std::set<std::string> names = {"index", "varied", "status", "reason"};
  const auto ptables = tables_of(root, "parameters");
  if (ptables.empty())
    throw Error(SourceLocation{path, 1, 1},
                "a study needs at least one [[parameters]] entry (name, path, ...)");
  for (std::size_t i = 0; i < ptables.size(); ++i)
    st.params_.push_back(read_parameter(*ptables[i], i, ss, base->root, names));

  // Quantities.
  const StudyColumns columns =
      st.point_ ? StudyColumns{point_columns(), {}} : scene_study_columns(base->root);
  const auto qtables = tables_of(root, "quantities");
  for (std::size_t i = 0; i < qtables.size(); ++i)
    st.quantities_.push_back(read_quantity(*qtables[i], i, st.point_, columns, names));

  // The samples.
  if (st.design_ == Design::one_at_a_time)
    st.samples_ = one_at_a_time_samples(st.params_, base->root);
  else if (st.design_ == Design::grid)
    st.samples_ = grid_samples(st.params_, path);
  else
    st.samples_ = random_samples(st.params_, st.design_, ss.n_samples, ss.seed);
  st.base_ = std::move(base);
  st.hash_ = hash_of({text_in, ss.base_text, st.header()});
  return st;
}

} // namespace stratum::sweep
