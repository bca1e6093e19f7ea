// Back-analysis: reading the calibration file and its measured curves, one model evaluation, and
// the journal (framework/src/sweep/back_analysis.hpp). The optimizer and the statistics are in
// back_analysis_fit.cpp.
#include "sweep/back_analysis.hpp"

#include "csv_fields.hpp"
#include "files.hpp"
#include "scene/toml_check.hpp"
#include "sweep_study.hpp"
#include "sweep_toml.hpp"

#include <toml++/toml.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum::sweep {

struct BackAnalysis::Base {
  toml::table root;
};

namespace {

using namespace detail;
using io::location;

/// Reads the measured points of a data set: the header row names the columns, '#' lines and
/// blank lines are skipped, and so is a row whose x or y cell is empty (a gauge that did not
/// read). The abscissae must be strictly monotonic.
void read_data_file(DataSet& d, const toml::table& t, const std::string& ctx, std::string& text_out) {
  text_out = read_text_file(d.file, location(*t.get("file")), "data file", file_limits::csv);
  std::istringstream in(text_out);
  std::string raw;
  int line = 0, ix = -1, iy = -1;
  std::vector<std::string> fields, header;
  std::vector<int> starts;
  bool have_header = false;
  while (std::getline(in, raw)) {
    ++line;
    if (line == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3); // a UTF-8 byte-order mark
    const std::string s = csv::trim(raw);
    if (s.empty() || s[0] == '#') continue;
    csv::split_fields(raw, fields, starts);
    if (!have_header) {
      header = fields;
      have_header = true;
      for (std::size_t k = 0; k < fields.size(); ++k) {
        if (fields[k] == d.x_column) ix = static_cast<int>(k);
        if (fields[k] == d.y_column) iy = static_cast<int>(k);
      }
      for (const auto& [key, idx] : {std::pair{"x_column", ix}, std::pair{"y_column", iy}})
        if (idx < 0) {
          std::string list;
          for (const auto& h : header) list += (list.empty() ? "" : ", ") + h;
          throw Error(location(*t.get(key)), ctx + " " + key + " = \"" +
                                                 (std::string(key) == "x_column" ? d.x_column : d.y_column) +
                                                 "\" is not a column of " + d.file + " (line " +
                                                 std::to_string(line) + "); its columns: " + list);
        }
      continue;
    }
    double v[2] = {0, 0};
    bool empty = false;
    for (int c = 0; c < 2; ++c) {
      const auto k = static_cast<std::size_t>(c == 0 ? ix : iy);
      if (k >= fields.size() || fields[k].empty()) {
        empty = true;
        continue;
      }
      char* end = nullptr;
      v[c] = std::strtod(fields[k].c_str(), &end);
      if (*end || !std::isfinite(v[c]))
        throw Error(SourceLocation{d.file, line, starts[k]},
                    "'" + fields[k] + "' in column " + header[k] + " is not a finite number");
    }
    if (empty) continue;
    const std::size_t n = d.xs.size();
    if (n >= 1) {
      const double dir = n >= 2 ? d.xs[1] - d.xs[0] : v[0] - d.xs[0];
      if (!(dir != 0.0 && (v[0] - d.xs[n - 1]) * dir > 0.0))
        throw Error(SourceLocation{d.file, line, starts[static_cast<std::size_t>(ix)]},
                    d.x_column + " = " + fields[static_cast<std::size_t>(ix)] + " does not continue the " +
                        (n < 2 || dir > 0 ? "increasing" : "decreasing") + " order of line " +
                        std::to_string(d.lines[n - 1]) + " (" + format_number(d.xs[n - 1]) +
                        "); the measured abscissae must be strictly monotonic");
    }
    d.xs.push_back(v[0]);
    d.ys.push_back(v[1]);
    d.lines.push_back(line);
  }
  if (!have_header)
    throw Error(location(*t.get("file")), ctx + " data file " + d.file + " has no header row (column names)");
  if (d.xs.empty())
    throw Error(location(*t.get("file")),
                ctx + " data file " + d.file + " has no row with both " + d.x_column + " and " + d.y_column);
}

FitParameter read_fit_parameter(const toml::table& t, std::size_t i, const std::string& key,
                                toml::table& base_root, const std::string& base_path,
                                std::set<std::string>& names) {
  const std::string ctx = context_of("parameters", static_cast<int>(i));
  only_keys(t, {"name", "path", "paths", "scale", "start", "lower", "upper", "log"}, ctx);
  FitParameter f;
  Parameter& p = f.target;
  p.where = location(t);
  p.name = text(t, "name", ctx);
  if (!good_name(p.name) || !names.insert(p.name).second)
    throw Error(location(*t.get("name")),
                ctx + " name '" + p.name + "' must be new and made of letters, digits, '_', '-', '.'");
  read_paths(t, ctx, key, base_root, base_path, p);
  if (p.integer)
    throw Error(location(*t.get(t.get("path") ? "path" : "paths")),
                ctx + " the path names an integer of the " + key +
                    " file; a fitted parameter varies continuously (fit a number, or use scale = true)");
  f.lower = need_number(t, "lower", ctx, "the lower bound");
  f.upper = need_number(t, "upper", ctx, "the upper bound");
  f.start = need_number(t, "start", ctx, "the start value");
  if (const auto* l = t.get("log")) {
    if (!l->is_boolean()) throw Error(location(*l), ctx + " log must be true or false");
    f.log = l->as_boolean()->get();
  }
  if (!(f.lower < f.upper))
    throw Error(location(*t.get("lower")), ctx + " lower = " + format_number(f.lower) +
                                               " must be below upper = " + format_number(f.upper) +
                                               " (the bounds are reversed or equal)");
  if (!(f.start >= f.lower && f.start <= f.upper))
    throw Error(location(*t.get("start")), ctx + " start = " + format_number(f.start) +
                                               " is outside [lower, upper] = [" + format_number(f.lower) +
                                               ", " + format_number(f.upper) + "]");
  if (f.log && !(f.lower > 0.0))
    throw Error(location(*t.get("lower")), ctx + " log = true fits ln(" + p.name +
                                               "): lower must be > 0, not " + format_number(f.lower));
  return f;
}

DataSet read_data_set(const toml::table& t, std::size_t i, const fs::path& dir, const StudyColumns& columns,
                      bool point, std::set<std::string>& names, std::string& file_text) {
  const std::string ctx = context_of("data", static_cast<int>(i));
  only_keys(t, {"name", "file", "x_column", "y_column", "x", "y", "stage", "weight"}, ctx);
  DataSet d;
  d.name = text(t, "name", ctx);
  if (!good_name(d.name) || !names.insert(d.name).second)
    throw Error(location(*t.get("name")),
                ctx + " name '" + d.name + "' must be new and made of letters, digits, '_', '-', '.'");
  const std::string rel = text(t, "file", ctx);
  d.file = (fs::path(rel).is_absolute() ? fs::path(rel) : dir / rel).lexically_normal().string();
  d.x_column = text(t, "x_column", ctx);
  d.y_column = text(t, "y_column", ctx);
  d.x = text(t, "x", ctx, columns.allowed);
  d.y = text(t, "y", ctx, columns.allowed);
  const auto recorder_column = [](const std::string& c) { return c.find('.') != std::string::npos; };
  if (!point && recorder_column(d.x) != recorder_column(d.y))
    throw Error(location(*t.get("x")), ctx + " x = \"" + d.x + "\" and y = \"" + d.y +
                                           "\" must both be recorder columns or both the pile curve's: their "
                                           "rows are not the same steps");
  if (t.get("stage")) {
    if (point || !recorder_column(d.y))
      throw Error(location(*t.get("stage")),
                  ctx + " stage acts only on recorder columns (\"<recorder>.<column>\")");
    d.stage = stage_index(t, "stage", ctx, columns);
  }
  if (const auto w = number(t, "weight", ctx)) {
    if (!(*w > 0.0 && std::isfinite(*w)))
      throw Error(location(*t.get("weight")), ctx + " weight must be a finite number > 0");
    d.weight = *w;
  }
  read_data_file(d, t, ctx, file_text);
  return d;
}

FitSettings read_settings(const toml::table& c, const std::string& sc) {
  FitSettings s;
  s.central = text(c, "differences", sc, {"central", "forward"}, "central") == "central";
  const auto positive = [&](const char* k, double& v, double most) {
    if (const auto x = number(c, k, sc)) {
      if (!(*x > 0.0 && *x <= most))
        throw Error(location(*c.get(k)), sc + " " + k + " must be > 0 and at most " + format_number(most));
      v = *x;
    }
  };
  positive("step", s.step, 0.1);
  positive("tolerance", s.tolerance, 0.1);
  positive("determined", s.determined, 1e6);
  for (const char* k : {"max_iterations", "threads"}) {
    const auto* n = c.get(k);
    if (!n) continue;
    const long long most = std::string(k) == "threads" ? 256 : 10000;
    if (!n->is_integer() || n->as_integer()->get() < 1 || n->as_integer()->get() > most)
      throw Error(location(*n), sc + " " + k + " must be an integer from 1 to " + std::to_string(most));
    if (std::string(k) == "threads")
      s.threads = n->as_integer()->get();
    else
      s.max_iterations = static_cast<int>(n->as_integer()->get());
  }
  return s;
}

std::string hex_double(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%a", v);
  return b;
}

} // namespace

double FitParameter::to_z(double p) const { return log ? std::log(p) : p; }
double FitParameter::from_z(double z) const { return log ? std::exp(z) : z; }

bool Evaluation::usable() const {
  return !computed.empty() &&
         std::all_of(computed.begin(), computed.end(), [](double c) { return std::isfinite(c); });
}

BackAnalysis BackAnalysis::from_file(const std::string& path) {
  return from_string(read_text_file(path, SourceLocation{path, 0, 0}, "calibration file", file_limits::study),
                     path);
}

BackAnalysis BackAnalysis::from_string(const std::string& text_in, const std::string& path) {
  toml::table root = io::parse_with_includes(text_in, path);
  only_keys(root, {"calibration", "fixed", "parameters", "data"}, "calibration file:");
  BackAnalysis ba;
  ba.path_ = path;
  const auto* c = table_of(root, "calibration");
  if (!c)
    throw Error(
        SourceLocation{path, 1, 1},
        "a calibration file needs a [calibration] table (scene = \"FILE.toml\" or point = \"FILE.toml\")");
  const std::string sc = "[calibration]";
  only_keys(*c,
            {"scene", "point", "differences", "step", "max_iterations", "tolerance", "determined", "threads"},
            sc);
  const BaseFile bf = read_base_file(*c, sc, path);
  ba.point_ = bf.point;
  ba.base_path_ = bf.path;
  const std::string& key = bf.key;
  const std::string& base_text = bf.text;
  const fs::path dir = fs::path(path).parent_path();
  ba.settings_ = read_settings(*c, sc);
  auto base = std::make_shared<Base>();
  base->root = io::parse_with_includes(base_text, ba.base_path_);
  apply_fixed(root, base->root, ba.base_path_, ba.point_, ba.settings_.threads, *c);

  std::set<std::string> names;
  const auto ptables = tables_of(root, "parameters");
  if (ptables.empty())
    throw Error(SourceLocation{path, 1, 1},
                "a calibration needs at least one [[parameters]] entry (name, path, start, lower, upper)");
  for (std::size_t i = 0; i < ptables.size(); ++i)
    ba.params_.push_back(read_fit_parameter(*ptables[i], i, key, base->root, ba.base_path_, names));

  const StudyColumns columns =
      ba.point_ ? StudyColumns{point_columns(), {}} : scene_study_columns(base->root);
  const auto dtables = tables_of(root, "data");
  if (dtables.empty())
    throw Error(SourceLocation{path, 1, 1},
                "a calibration needs at least one [[data]] entry (name, file, x_column, y_column, x, y)");
  std::vector<std::string> texts = {text_in, base_text};
  std::set<std::string> data_names;
  for (std::size_t i = 0; i < dtables.size(); ++i) {
    std::string ft;
    ba.data_.push_back(read_data_set(*dtables[i], i, dir, columns, ba.point_, data_names, ft));
    texts.push_back(ft);
  }
  const std::size_t m = ba.points(), n = ba.params_.size();
  if (m <= n)
    throw Error(location(*ptables.back()),
                "the calibration fits " + std::to_string(n) + " parameter" + (n == 1 ? "" : "s") + " to " +
                    std::to_string(m) + " measured point" + (m == 1 ? "" : "s") +
                    ": it needs more points than parameters (their difference is what estimates the "
                    "scatter and the intervals)");
  ba.base_ = std::move(base);
  ba.hash_ = hash_of(texts);
  return ba;
}

std::size_t BackAnalysis::points() const {
  std::size_t m = 0;
  for (const auto& d : data_) m += d.xs.size();
  return m;
}

std::string BackAnalysis::scene_text(const std::vector<double>& p) const {
  toml::table root = base_->root;
  std::vector<Parameter> targets;
  for (const auto& f : params_) targets.push_back(f.target);
  apply_values(root, targets, p);
  std::ostringstream o;
  o << root << "\n";
  return o.str();
}

Evaluation BackAnalysis::evaluate(const std::vector<double>& p, const std::string& out_dir,
                                  std::vector<std::vector<std::array<double, 2>>>* curves) const {
  const auto t0 = std::chrono::steady_clock::now();
  Evaluation e;
  e.values = p;
  std::string values_text;
  for (std::size_t j = 0; j < p.size(); ++j)
    values_text += (j ? ", " : "") + params_[j].target.name + " = " + format_number(p[j]);
  const RunColumns rc = run_columns(scene_text(p), base_path_, point_, !out_dir.empty(), out_dir,
                                    "the scene with " + values_text + " (stratum calibrate --print-scene)");
  e.status = rc.status;
  e.reason = rc.reason;
  if (curves) curves->clear();
  for (const auto& d : data_) {
    const auto xy = curve_of(rc.cols, d.x, d.y, d.stage);
    for (double x : d.xs) e.computed.push_back(curve_at(xy, x));
    if (curves) curves->push_back(xy);
  }
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

Eigen::VectorXd BackAnalysis::residuals(const Evaluation& e) const {
  Eigen::VectorXd r(static_cast<Eigen::Index>(points()));
  Eigen::Index k = 0;
  for (const auto& d : data_)
    for (std::size_t i = 0; i < d.xs.size(); ++i, ++k)
      r[k] = d.weight * (e.computed.at(static_cast<std::size_t>(k)) - d.ys[i]);
  return r;
}

// ---------------------------------------------------------------- the journal

Journal::Journal(const std::string& path, const std::string& hash, std::size_t n_params, std::size_t n_points)
    : path_(path), n_params_(n_params), n_points_(n_points) {
  if (path.empty()) return;
  const std::string head = "# stratum calibrate journal " + hash;
  bool fresh = true;
  if (fs::exists(path)) {
    const std::string text =
        read_text_file(path, SourceLocation{}, "calibration journal", file_limits::journal);
    std::istringstream in(text);
    std::string line;
    std::size_t consumed = 0;
    bool first = true;
    while (std::getline(in, line)) {
      consumed += line.size() + 1;
      if (consumed > text.size()) break; // the last line has no newline: a run cut short while writing
      if (first) {
        if (line != head)
          throw Error(path +
                      ": this journal belongs to another calibration (or another version of its files): "
                      "give another --out, or remove the folder to start again");
        first = false;
        fresh = false;
        continue;
      }
      // p_1..p_n, status, seconds, c_1..c_m, reason
      Evaluation e;
      std::vector<std::string> f;
      std::size_t pos = 0;
      for (std::size_t k = 0; k < n_params_ + 2 + n_points_ && pos <= line.size(); ++k) {
        const auto comma = line.find(',', pos);
        f.push_back(line.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos));
        pos = comma == std::string::npos ? line.size() + 1 : comma + 1;
      }
      if (f.size() != n_params_ + 2 + n_points_) continue; // not a line of this journal: ignored
      for (std::size_t k = 0; k < n_params_; ++k) e.values.push_back(std::strtod(f[k].c_str(), nullptr));
      e.status = f[n_params_];
      e.seconds = std::strtod(f[n_params_ + 1].c_str(), nullptr);
      for (std::size_t k = 0; k < n_points_; ++k)
        e.computed.push_back(std::strtod(f[n_params_ + 2 + k].c_str(), nullptr));
      if (pos < line.size()) {
        std::string q = line.substr(pos);
        if (q.size() >= 2 && q.front() == '"' && q.back() == '"') q = q.substr(1, q.size() - 2);
        for (std::size_t k = 0; (k = q.find("\"\"", k)) != std::string::npos; ++k) q.erase(k, 1);
        e.reason = q;
      }
      e.from_journal = true;
      done_[e.values] = e;
    }
  }
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error(path + ": cannot write the calibration journal: " + std::strerror(errno));
  if (fresh) {
    if (::ftruncate(fd_, 0) != 0)
      throw Error(path + ": cannot write the calibration journal: " + std::strerror(errno));
    const std::string h = head + "\n";
    if (::write(fd_, h.data(), h.size()) != static_cast<ssize_t>(h.size()))
      throw Error(path + ": cannot write the calibration journal: " + std::strerror(errno));
  }
}

Journal::~Journal() {
  if (fd_ >= 0) ::close(fd_);
}

const Evaluation* Journal::find(const std::vector<double>& p) const {
  const auto it = done_.find(p);
  return it == done_.end() ? nullptr : &it->second;
}

void Journal::add(const Evaluation& e) {
  done_[e.values] = e;
  if (fd_ < 0) return;
  std::string line;
  for (double v : e.values) line += hex_double(v) + ",";
  line += e.status + "," + hex_double(e.seconds);
  for (double c : e.computed) line += "," + hex_double(c);
  std::string reason = e.reason;
  for (char& ch : reason)
    if (ch == '\n' || ch == '\r') ch = ' ';
  std::string q = "\"";
  for (char ch : reason) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  line += "," + q + "\"\n";
  // One write per line, then to the disk: a line is there whole or (cut short) ignored.
  if (::write(fd_, line.data(), line.size()) != static_cast<ssize_t>(line.size()) || ::fdatasync(fd_) != 0)
    throw Error(path_ + ": cannot write the calibration journal: " + std::strerror(errno));
}

BatchRunner journaled(Journal& journal, BatchRunner run) {
  return [&journal, run = std::move(run)](const std::vector<std::vector<double>>& batch) {
    std::vector<Evaluation> out(batch.size());
    std::vector<std::vector<double>> todo;
    std::vector<std::size_t> where;
    std::map<std::vector<double>, std::size_t> first; // identical points of one batch run once
    for (std::size_t k = 0; k < batch.size(); ++k) {
      if (const Evaluation* e = journal.find(batch[k])) {
        out[k] = *e;
        if (e->from_journal) journal.count_reuse(); // from an earlier calibration into this folder
        continue;
      }
      if (!first.count(batch[k])) {
        first[batch[k]] = todo.size();
        todo.push_back(batch[k]);
      }
      where.push_back(k);
    }
    if (!todo.empty()) {
      const std::vector<Evaluation> done = run(todo);
      for (const auto& e : done) journal.add(e);
      for (std::size_t k : where) out[k] = done[first[batch[k]]];
    }
    return out;
  };
}

} // namespace stratum::sweep
