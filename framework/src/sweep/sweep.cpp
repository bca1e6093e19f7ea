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
std::string quantity_cells(const Quantity& q, std::map<std::string, std::vector<double>>& cols, double steps,
                           double cutbacks, double iterations) {
  std::string cells;
  // The rows the quantity reads: all, or those of its stage (by the stage column of y's recorder).
  const auto rows_of = [&](const std::string& column) {
    std::vector<double> v = cols[column];
    if (q.stage <= 0) return v;
    const auto& stage = cols[column.substr(0, column.find('.')) + ".stage"];
    std::vector<double> kept;
    for (std::size_t k = 0; k < v.size() && k < stage.size(); ++k)
      if (stage[k] == q.stage) kept.push_back(v[k]);
    return kept;
  };
  const std::vector<double> y = rows_of(q.y);
  switch (q.kind) {
  case Quantity::Kind::curve: {
    const std::vector<double> x = rows_of(q.x);
    // Recorders sample every accepted step: two of them have as many rows. A curve of columns
    // of unequal length (the pile curve against a recorder) has none.
    std::vector<std::array<double, 2>> xy(x.size() == y.size() ? x.size() : 0);
    for (std::size_t k = 0; k < xy.size(); ++k) xy[k] = {x[k], y[k]};
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
  double steps = not_a_number, cutbacks = not_a_number, iterations = not_a_number;
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
        for (std::size_t k = 0; k < point_columns().size(); ++k) cols[point_columns()[k]].push_back(v[k]);
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
      steps = s.steps_done;
      cutbacks = s.cutbacks;
      iterations = 0.0;
      for (const auto& r : s.reports) iterations += r.iterations;
      if (!s.outcome.ok()) {
        reason = std::string(to_string(s.outcome.status)) + ": " + s.outcome.message;
      } else if (s.stop_reason != StopReason::none) {
        status = "stopped";
        reason = stop_reason_name(s.stop_reason) + (s.stop_message.empty() ? "" : ": " + s.stop_message);
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
  } catch (const std::bad_alloc&) {
    // The sample's model did not fit in the memory the process may have (ulimit -v): a failed
    // sample, not a defect; the others may be smaller.
    reason = "out of memory: the process could allocate no more for this sample's model";
  } catch (const std::exception& e) {
    reason = std::string("internal error: ") + e.what();
  }

  std::string row = std::to_string(index);
  if (design_ == Design::one_at_a_time) row += "," + smp.varied;
  for (double v : smp.values) row += "," + format_number(v);
  for (const auto& q : quantities_) row += quantity_cells(q, cols, steps, cutbacks, iterations);
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
