// Back-analysis (`stratum calibrate STUDY.toml`): fits parameters of a scene (or a point file) to
// measured curves by weighted nonlinear least squares, and says how well the data determine them.
// This part knows nothing of MPI: it reads the calibration file, runs one model evaluation in this
// process, keeps the journal, drives the optimizer (Ceres' Levenberg-Marquardt) through a batch
// runner that the program gives (one process, or MPI ranks: framework/cli/calibrate.cpp), and
// computes the statistics at the optimum. Method and formats: docs/calibrate.md.
#pragma once

#include "sweep/sweep.hpp"

#include <Eigen/Dense>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace stratum::sweep {

/// A fitted parameter: where it goes in the base file (as a study's parameter), its start and
/// bounds, and whether it is fitted in log space (z = ln p).
struct FitParameter {
  Parameter target; ///< name, paths, scale, where
  double start = 0.0, lower = 0.0, upper = 0.0;
  bool log = false;
  [[nodiscard]] double to_z(double p) const;
  [[nodiscard]] double from_z(double z) const;
};

/// One measured curve and the computed curve it is compared with.
struct DataSet {
  std::string name;
  std::string file;               ///< as resolved (relative to the calibration file)
  std::string x_column, y_column; ///< the CSV's columns
  std::string x, y;               ///< the run's columns (as a study quantity's x and y)
  int stage = 0;                  ///< > 0: only the rows of this stage (recorder columns)
  double weight = 1.0;            ///< residual = weight (computed - measured)
  std::vector<double> xs, ys;     ///< the measured points
  std::vector<int> lines;         ///< the CSV line of each point
};

/// The optimizer's settings ([calibration] table).
struct FitSettings {
  bool central = true;     ///< central differences for the Jacobian (else forward)
  double step = 1e-3;      ///< difference step in z: step * max(|z|, 1) (log: step)
  int max_iterations = 50; ///< Levenberg-Marquardt iterations
  double tolerance = 1e-8; ///< relative change of the cost, of the parameters
  double determined = 1.0; ///< a combination with a larger standard error (relative) is not determined
  long long threads = 1;   ///< element-loop threads per run
};

/// One model run at parameter values p: the computed values at every measured abscissa.
struct Evaluation {
  std::vector<double> values;    ///< p, one per parameter
  std::vector<double> computed;  ///< per data point (all data sets in order); NaN where not reached
  std::string status = "failed"; ///< converged, stopped, failed (of the run)
  std::string reason;
  double seconds = 0.0;
  bool from_journal = false;
  /// Every data point has a computed value.
  [[nodiscard]] bool usable() const;
};

/// Runs a batch of parameter vectors (p, not z) and returns their evaluations in order.
using BatchRunner = std::function<std::vector<Evaluation>(const std::vector<std::vector<double>>&)>;

class BackAnalysis {
public:
  /// Reads and checks a calibration file (every problem a located Error), with its data files.
  static BackAnalysis from_file(const std::string& path);
  static BackAnalysis from_string(const std::string& text, const std::string& path);

  [[nodiscard]] const std::vector<FitParameter>& parameters() const { return params_; }
  [[nodiscard]] const std::vector<DataSet>& data() const { return data_; }
  [[nodiscard]] const FitSettings& settings() const { return settings_; }
  [[nodiscard]] std::size_t points() const; ///< measured points of all data sets
  [[nodiscard]] const std::string& hash() const { return hash_; }
  [[nodiscard]] const std::string& base_path() const { return base_path_; }
  [[nodiscard]] const std::string& path() const { return path_; }

  /// The base text with the values p set.
  [[nodiscard]] std::string scene_text(const std::vector<double>& p) const;
  /// Runs the model at p in this process (never throws for trouble of the run). With a
  /// non-empty out_dir the run writes its files there, and `curves` gets each data set's whole
  /// computed curve.
  [[nodiscard]] Evaluation evaluate(const std::vector<double>& p, const std::string& out_dir = {},
                                    std::vector<std::vector<std::array<double, 2>>>* curves = nullptr) const;
  /// The weighted residuals weight (computed - measured) of an evaluation.
  [[nodiscard]] Eigen::VectorXd residuals(const Evaluation& e) const;

  struct Base;

private:
  BackAnalysis() = default;
  std::string path_, base_path_, hash_;
  bool point_ = false;
  std::vector<FitParameter> params_;
  std::vector<DataSet> data_;
  FitSettings settings_;
  std::shared_ptr<const Base> base_;
};

/// The evaluations of a calibration, kept in DIR/journal.csv: one line per finished run,
/// appended and flushed as it finishes, so that a calibration started again into the same folder
/// takes its finished runs from there (the optimizer asks for the same points again: it is
/// deterministic). Values are written exactly (hexadecimal floating point).
class Journal {
public:
  /// Opens (or starts) the journal of the calibration with this hash; a journal of another
  /// calibration is an Error. An empty path keeps the journal in memory only.
  Journal(const std::string& path, const std::string& hash, std::size_t n_params, std::size_t n_points);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;
  /// The evaluation at exactly these values, if the journal has it.
  [[nodiscard]] const Evaluation* find(const std::vector<double>& p) const;
  /// Records a finished evaluation (appended to the file).
  void add(const Evaluation& e);
  [[nodiscard]] std::size_t size() const { return done_.size(); }
  [[nodiscard]] std::size_t reused() const { return reused_; }
  void count_reuse() { ++reused_; }

private:
  std::string path_;
  std::size_t n_params_ = 0, n_points_ = 0, reused_ = 0;
  std::map<std::vector<double>, Evaluation> done_;
  int fd_ = -1;
};

/// A batch runner that takes what the journal has, runs the rest with `run`, and journals them.
[[nodiscard]] BatchRunner journaled(Journal& journal, BatchRunner run);

/// The optimizer could not go on (the program's exit status 2, not a bad input).
class FitFailed : public Error {
public:
  using Error::Error;
};

/// The result of a calibration.
struct FitResult {
  std::vector<double> start, best; ///< p
  double cost = 0.0;               ///< 0.5 |r|^2 at the best point
  double start_cost = 0.0;
  int iterations = 0;      ///< optimizer iterations
  int runs = 0;            ///< model evaluations asked for (journal included)
  std::string termination; ///< the optimizer's reason for stopping
  bool converged = false;
  Evaluation best_eval;
  Eigen::VectorXd residuals;          ///< weighted, at the best point
  Eigen::MatrixXd jacobian;           ///< d r / d z at the best point (points x parameters)
  int dof = 0;                        ///< points - parameters
  double sigma = 0.0;                 ///< sqrt(|r|^2 / dof): the residuals' estimated standard deviation
  double t95 = 0.0;                   ///< Student's t quantile 0.975 for dof
  std::vector<double> se_z;           ///< standard error of z (inf when not determined)
  std::vector<double> low95, high95;  ///< 95 % interval of p
  std::vector<bool> determined;       ///< the parameter's interval is finite and within the settings' limit
  std::vector<bool> at_bound;         ///< the best value sits on a bound
  Eigen::MatrixXd correlation;        ///< NaN where a parameter is not determined
  Eigen::VectorXd singular;           ///< of the Jacobian scaled to relative changes, descending
  Eigen::MatrixXd directions;         ///< their right singular vectors (columns)
  std::vector<double> combination_se; ///< standard error along each direction (relative)
  std::vector<std::string> notes;     ///< findings in words (what is not determined, bounds)
};

/// Progress of a calibration: called after each optimizer iteration (iteration, cost, runs).
using FitProgress = std::function<void(int, double, int)>;

/// Runs the optimizer from the start values, then the statistics at its best point.
/// Throws Error when the start point's run does not give every data point.
[[nodiscard]] FitResult calibrate(const BackAnalysis& ba, const BatchRunner& run,
                                  const FitProgress& progress = {});

/// The result folder's text files: parameters.csv, correlation.csv, singular_values.csv,
/// jacobian.csv, residuals.csv and report.md (a human summary), by name.
[[nodiscard]] std::map<std::string, std::string> report_files(const BackAnalysis& ba, const FitResult& r);

} // namespace stratum::sweep
