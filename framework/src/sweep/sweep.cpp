// Parameter studies: one sample's scene text, its run and its row (framework/src/sweep/sweep.hpp);
// the study file is read by sweep_study.cpp.
#include "sweep/sweep.hpp"
#include "sweep_study.hpp"

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
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <numbers>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum::sweep {
namespace {

using namespace detail;
using io::location;

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

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

/// The samples.csv cells of one quantity (each with its leading comma), read from a run's
/// columns (`cols`: the pile curve's, the recorders' "<name>.<column>", a point file's) and
/// counts.
std::string quantity_cells(const Quantity& q, const Columns& cols, double steps, double cutbacks,
                           double iterations) {
  std::string cells;
  const std::vector<double> y = column_rows(cols, q.y, q.stage);
  switch (q.kind) {
  case Quantity::Kind::curve: {
    const auto xy = curve_of(cols, q.x, q.y, q.stage);
    for (double a : q.at) cells += "," + format_number(curve_at(xy, a));
    break;
  }
  case Quantity::Kind::last:
    cells += "," + format_number(y.empty() ? not_a_number : y.back());
    break;
  case Quantity::Kind::max:
  case Quantity::Kind::min: {
    double v = not_a_number;
    for (double e : y)
      if (std::isfinite(e) && !(q.kind == Quantity::Kind::max ? v >= e : v <= e)) v = e;
    cells += "," + format_number(v);
    break;
  }
  case Quantity::Kind::steps:
    cells += "," + format_number(steps);
    break;
  case Quantity::Kind::cutbacks:
    cells += "," + format_number(cutbacks);
    break;
  case Quantity::Kind::iterations:
    cells += "," + format_number(iterations);
    break;
  }
  return cells;
}

} // namespace

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
  apply_values(root, params_, samples_.at(static_cast<std::size_t>(index)).values);
  std::ostringstream o;
  o << root << "\n";
  return o.str();
}

void detail::apply_values(toml::table& root, const std::vector<Parameter>& params,
                          const std::vector<double>& values) {
  for (std::size_t j = 0; j < params.size(); ++j) {
    const auto& p = params[j];
    for (const auto& path : p.paths)
      for (auto* leaf : number_leaves(root, path))
        set_number(*leaf, p.scale ? number_of(*leaf) * values[j] : values[j]);
  }
}

std::vector<double> detail::column_rows(const Columns& cols, const std::string& column, int stage) {
  const auto it = cols.find(column);
  if (it == cols.end()) return {};
  if (stage <= 0) return it->second;
  const auto st = cols.find(column.substr(0, column.find('.')) + ".stage");
  if (st == cols.end()) return {};
  std::vector<double> kept;
  for (std::size_t k = 0; k < it->second.size() && k < st->second.size(); ++k)
    if (st->second[k] == stage) kept.push_back(it->second[k]);
  return kept;
}

std::vector<std::array<double, 2>> detail::curve_of(const Columns& cols, const std::string& x,
                                                    const std::string& y, int stage) {
  const std::vector<double> xs = column_rows(cols, x, stage), ys = column_rows(cols, y, stage);
  // Recorders sample every accepted step: two of them have as many rows. A curve of columns of
  // unequal length (the pile curve against a recorder) has none.
  std::vector<std::array<double, 2>> xy(xs.size() == ys.size() ? xs.size() : 0);
  for (std::size_t k = 0; k < xy.size(); ++k) xy[k] = {xs[k], ys[k]};
  return xy;
}

RunColumns detail::run_columns(const std::string& text, const std::string& base_path, bool point,
                               bool write_output, const std::string& out_dir, const std::string& hint) {
  RunColumns rc;
  auto& cols = rc.cols;
  try {
    if (point) {
      const auto driver = PointDriver::from_string(text, base_path);
      const PointRun r = driver->run();
      if (write_output) PointDriver::write_csv(r, (fs::path(out_dir) / "point.csv").string());
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
        for (std::size_t k = 0; k < point_columns().size(); ++k) cols[point_columns()[k]].push_back(v[k]);
      }
      rc.steps = r.rows.empty() ? 0.0 : static_cast<double>(r.rows.size() - 1);
      rc.status = r.outcome.ok() ? "converged" : "failed";
      if (!r.outcome.ok()) rc.reason = std::string(to_string(r.outcome.status)) + ": " + r.outcome.message;
    } else {
      RunOptions o;
      o.write_output = write_output;
      o.out_dir = out_dir;
      const auto analysis = Analysis::from_string(text, base_path, o);
      const RunSummary s = analysis->run();
      for (const auto& r : s.load_settlement) {
        cols["load"].push_back(r[0]);
        cols["settlement"].push_back(r[1]);
      }
      // Each row of the curve has its components when the scene names the pile's cells.
      if (s.settlement_components.size() == s.load_settlement.size())
        for (const auto& r : s.settlement_components)
          for (std::size_t k = 0; k < pile_component_columns().size(); ++k)
            cols[pile_component_columns()[k]].push_back(r[k + 1]);
      for (const RecordedTable& t : analysis->recorded())
        for (std::size_t c = 0; c < t.columns.size(); ++c) {
          auto& v = cols[t.name + "." + t.columns[c]];
          for (const auto& row : t.rows) v.push_back(c < row.size() ? row[c] : not_a_number);
        }
      rc.steps = s.steps_done;
      rc.cutbacks = s.cutbacks;
      rc.iterations = 0.0;
      for (const auto& r : s.reports) rc.iterations += r.iterations;
      if (!s.outcome.ok()) {
        rc.reason = std::string(to_string(s.outcome.status)) + ": " + s.outcome.message;
      } else if (s.stop_reason != StopReason::none) {
        rc.status = "stopped";
        rc.reason = stop_reason_name(s.stop_reason) + (s.stop_message.empty() ? "" : ": " + s.stop_message);
      } else {
        rc.status = "converged";
      }
    }
  } catch (const Error& e) {
    // A place in the run's scene names its line in the text that `hint` shows (not in the base
    // file, and not by the path the study was given by: the result must not depend on it).
    const auto& w = e.where();
    rc.reason = w.file == base_path ? "line " + std::to_string(w.line) + ":" + std::to_string(w.column) +
                                          " of " + hint + ": " + e.message()
                                    : e.what();
  } catch (const std::bad_alloc&) {
    // The run's model did not fit in the memory the process may have (ulimit -v): a failed run,
    // not a defect; the others may be smaller.
    rc.reason = "out of memory: the process could allocate no more for this run's model";
  } catch (const std::exception& e) {
    rc.reason = std::string("internal error: ") + e.what();
  }
  return rc;
}

SampleResult Study::run(int index, const std::string& out_dir) const {
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_seconds();
  const Sample& smp = samples_.at(static_cast<std::size_t>(index));
  const fs::path sample_dir = fs::path(out_dir) / "samples" / std::to_string(index);
  std::string text;
  RunColumns rc;
  try {
    text = scene_text(index);
  } catch (const Error& e) {
    rc.reason = e.what();
  }
  if (!text.empty())
    rc = run_columns(text, base_path_, point_, sample_output_, sample_dir.string(),
                     "the sample's scene (stratum sweep --print-scene " + std::to_string(index) + ")");

  std::string row = std::to_string(index);
  if (design_ == Design::one_at_a_time) row += "," + smp.varied;
  for (double v : smp.values) row += "," + format_number(v);
  for (const auto& q : quantities_) row += quantity_cells(q, rc.cols, rc.steps, rc.cutbacks, rc.iterations);
  row += "," + rc.status + "," + (rc.reason.empty() ? std::string() : csv_text(rc.reason));
  SampleResult r;
  r.index = index;
  r.row = std::move(row);
  r.status = rc.status;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_seconds = thread_cpu_seconds() - cpu0;
  return r;
}

} // namespace stratum::sweep
