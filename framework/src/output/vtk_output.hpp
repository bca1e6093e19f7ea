// VTK XML output: one .vtu per output step (mesh, displacement, cell data), one
// .vtp point cloud of the integration points, and .pvd collections that
// ParaView opens as time series. Every file is written to a temporary name in
// the same directory and renamed, so a reader never sees a half-written file.
#pragma once

#include "stratum/mesh.hpp"

#include <Eigen/Core>

#include <future>
#include <string>
#include <utility>
#include <vector>

namespace stratum {

/// A named array: `components` values per tuple, tuples contiguous.
struct OutputArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
  /// Optional names of the components as ParaView shows them (e.g. "shear", "normal");
  /// empty: VTK's defaults (X, Y, Z / 0, 1, ...).
  std::vector<std::string> component_names = {};
};

/// What one output step contains.
struct OutputStep {
  /// The time ParaView shows: stage number - 1 + load factor. The writer keeps the series
  /// strictly increasing: a state written again at the same time (e.g. after
  /// reset_displacements) follows at the previous time + 1e-6.
  double time = 0.0;
  /// OutputArray data of the step (one value each, on the .vtu and the .vtp): e.g. stage_number, step,
  /// load_factor, head_load_kN; and text values, e.g. stage.
  std::vector<std::pair<std::string, double>> values = {};
  std::vector<std::pair<std::string, std::string>> texts = {};
  /// OutputArray data string arrays of several values (e.g. "domains": the domain names in order).
  std::vector<std::pair<std::string, std::vector<std::string>>> text_lists = {};
  const Mesh* mesh = nullptr;
  std::vector<int> cells;                ///< the cells to write (active cells)
  std::vector<OutputArray> point_fields; ///< one tuple per mesh node (e.g. "displacement", 3 comps)
  std::vector<OutputArray> cell_fields;  ///< one tuple per written cell (e.g. "stress", "set_id")
  Eigen::MatrixXd ip_coords;             ///< integration points (rows)
  std::vector<OutputArray> ip_fields;    ///< one tuple per integration point
};

/// Writes <dir>/<stem>_<k>.vtu and <dir>/<stem>_ip_<k>.vtp for k = 0, 1, ... and keeps
/// <dir>/<stem>.pvd and <dir>/<stem>_ip.pvd up to date after every step.
/// Cells: 4-node quads as VTK_QUAD, 8-node as VTK_QUADRATIC_QUAD, 5-7-node transition
/// quads as VTK_POLYGON through corners and midside nodes in boundary order; 3- and 6-node
/// triangles as VTK_TRIANGLE and VTK_QUADRATIC_TRIANGLE.
///
/// In the background mode write() checks the step, copies it (mesh included) and returns; the
/// files are written on a thread of the writer's own while the caller goes on, one step at a time
/// and in order. The next write() and finish() wait for that step and throw its Error, if any; the
/// destructor waits without throwing. The files are those of the foreground mode, byte for byte.
class VtkSeriesWriter {
public:
  VtkSeriesWriter(std::string directory, std::string stem, bool background = false);
  VtkSeriesWriter(const VtkSeriesWriter&) = delete;
  VtkSeriesWriter& operator=(const VtkSeriesWriter&) = delete;
  ~VtkSeriesWriter();
  /// Throws Error when the step is malformed or a file (of this step or, in the background mode,
  /// of the one before) cannot be written.
  void write(const OutputStep& step);
  /// Waits until every step given to write() is on disk; throws the Error of a failed one.
  void finish();
  [[nodiscard]] std::string pvd_path() const;
  /// Steps given to write() (in the background mode the last one may still be being written).
  [[nodiscard]] int steps_written() const { return static_cast<int>(times_.size()); }

private:
  /// Writes the files of step k = times.size() - 1 at time times[k] and the collections of
  /// steps 0..k.
  void write_files(const OutputStep& step, const std::vector<double>& times) const;
  std::string dir_, stem_;
  bool background_;
  std::vector<double> times_;
  std::future<void> pending_; ///< the background write of the last step
};

} // namespace stratum
