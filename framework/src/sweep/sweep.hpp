// Parameter studies (`stratum sweep STUDY.toml`): a study file names a base scene (or a
// point file), the parameters to vary as TOML paths of it, a design and the quantities to
// read from each run. This part knows nothing of MPI: it turns a study into numbered samples,
// runs one sample in-process and formats its row of samples.csv. The distribution over
// processes (manager and workers), the journal and the progress line are in
// framework/cli/sweep.cpp. Format and examples: docs/sweep.md.
#pragma once

#include "stratum/error.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace stratum::sweep {

enum class Design { one_at_a_time, grid, latin_hypercube, monte_carlo };
enum class Distribution { uniform, normal, lognormal, truncated_normal };

/// One varied quantity of the study: one value, set at one or more TOML paths of the base scene
/// (or, with scale = true, multiplying the base value found there).
struct Parameter {
  std::string name;
  std::vector<std::string> paths;
  bool scale = false;           ///< the value is a factor on the base values
  bool integer = false;         ///< every path holds an integer (set mode): values are rounded
  double low = 0.0, high = 0.0; ///< one_at_a_time
  std::vector<double> values;   ///< grid levels
  Distribution distribution = Distribution::uniform;
  double mean = 0.0, sd = 0.0, lower = 0.0, upper = 0.0; ///< sampled designs
  SourceLocation where;

  /// The value with probability p of not being exceeded (0 < p < 1).
  [[nodiscard]] double quantile(double p) const;
};

/// What is read from each run. Columns: one per abscissa of `at` (name, or name@at when `at`
/// is a list), one for the other kinds.
struct Quantity {
  enum class Kind { curve, last, max, min, steps, cutbacks, iterations };
  std::string name;
  Kind kind = Kind::curve;
  /// curve columns: "load", "settlement" (the pile curve), "<recorder>.<column>" (a recorder of
  /// the base scene: stage, step, lambda or one of its quantities); point files: their CSV columns
  std::string x, y;
  int stage = 0;          ///< > 0: only the rows of this stage (1-based; recorder columns only)
  std::vector<double> at; ///< abscissae for kind curve
  bool list = false;      ///< `at` was written as an array: one column per value, named name@value
  [[nodiscard]] std::vector<std::string> columns() const;
};

struct Sample {
  int index = 0;
  std::string varied;         ///< one_at_a_time: "base", "NAME:low", "NAME:high"; else ""
  std::vector<double> values; ///< one per parameter, as written to samples.csv
};

/// The outcome of one sample: its samples.csv row and what the manager counts.
struct SampleResult {
  int index = 0;
  std::string row;          ///< one CSV line without the newline
  std::string status;       ///< converged, stopped or failed
  double seconds = 0.0;     ///< wall time of the sample
  double cpu_seconds = 0.0; ///< CPU time of the thread that ran it (the element loop on one thread)
};

class Study {
public:
  /// Reads and checks a study file; a problem throws Error with file:line:col.
  static Study from_file(const std::string& path);
  static Study from_string(const std::string& text, const std::string& path);

  [[nodiscard]] const std::vector<Sample>& samples() const { return samples_; }
  [[nodiscard]] const std::vector<Parameter>& parameters() const { return params_; }
  [[nodiscard]] Design design() const { return design_; }
  /// The header line of samples.csv (without the newline).
  [[nodiscard]] std::string header() const;
  /// FNV-1a 64 of the study text, the base file's text and the header, in hex: a journal
  /// written under another hash belongs to another study.
  [[nodiscard]] std::string hash() const { return hash_; }
  [[nodiscard]] const std::string& base_path() const { return base_path_; }
  [[nodiscard]] bool point_base() const { return point_; }
  [[nodiscard]] bool sample_output() const { return sample_output_; }

  /// The base text with sample `index`'s values set (TOML as toml++ writes it).
  [[nodiscard]] std::string scene_text(int index) const;
  /// Runs sample `index` in this process. Never throws for trouble of the sample itself (bad
  /// values, no convergence): that is the row's status and reason. `out_dir` is the study's
  /// output folder (per-sample output goes to out_dir/samples/<index> when asked for).
  [[nodiscard]] SampleResult run(int index, const std::string& out_dir) const;

  struct Base;

private:
  Study() = default;
  std::string path_, base_path_, hash_;
  bool point_ = false, sample_output_ = false;
  Design design_ = Design::one_at_a_time;
  std::vector<Parameter> params_;
  std::vector<Quantity> quantities_;
  std::vector<Sample> samples_;
  std::shared_ptr<const Base> base_; ///< the parsed base scene with the fixed settings applied
};

/// The random numbers of the sampled designs: std::mt19937_64 (its sequence is fixed by the C++
/// standard) and our own transforms, so that a seed gives the same samples with any library.
class Rng {
public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  /// Uniform on the open interval (0, 1): (k + 0.5) / 2^53 from the top 53 bits.
  double uniform();
  /// Uniform integer in [0, n) by the multiply-high method.
  std::uint64_t below(std::uint64_t n);

private:
  std::mt19937_64 engine_;
};

/// Standard normal distribution function and its inverse (Acklam's rational approximation
/// refined by one Halley step on erfc: relative error near 1e-15).
[[nodiscard]] double normal_cdf(double x);
[[nodiscard]] double normal_quantile(double p);

/// The y of a curve at abscissa x0: linear interpolation on the first segment whose x range
/// contains x0; NaN when none does (the run stopped before reaching it).
[[nodiscard]] double curve_at(const std::vector<std::array<double, 2>>& xy, double x0);

/// "%.10g", "" for NaN, no "-0".
[[nodiscard]] std::string format_number(double v);

} // namespace stratum::sweep
