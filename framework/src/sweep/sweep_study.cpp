// Parameter studies: reading the study file and its designs (framework/src/sweep/sweep.hpp).
#include "sweep_study.hpp"
#include "sweep/sweep.hpp"

#include "stratum/analysis.hpp"
#include "stratum/point_driver.hpp"
#include "sweep_toml.hpp"
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
namespace {

using namespace detail;
using io::location;

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

const std::vector<std::string> scene_columns = {"load", "settlement"};

} // namespace

const std::vector<std::string>& detail::point_columns() {
  static const std::vector<std::string> columns = {
      "step",   "eps_xx", "eps_yy", "eps_zz", "gamma_xy",  "gamma_yz", "gamma_zx", "sig_xx", "sig_yy",
      "sig_zz", "sig_xy", "sig_yz", "sig_zx", "eps_axial", "eps_vol",  "p",        "q"};
  return columns;
}

// ---------------------------------------------------------------- the study

Study Study::from_file(const std::string& path) {
  return from_string(slurp(path, SourceLocation{path, 0, 0}, "study file"), path);
}

Study Study::from_string(const std::string& text_in, const std::string& path) {
  toml::table root = io::parse_with_includes(text_in, path);
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
  base->root = io::parse_with_includes(base_text, st.base_path_);
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
  const auto& allowed_xy = st.point_ ? point_columns() : scene_columns;
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

} // namespace stratum::sweep
