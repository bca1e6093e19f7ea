// VTK XML output: one .vtu per output step (mesh, displacement, cell data), one
// .vtp point cloud of the integration points, and .pvd collections that
// ParaView opens as time series. Every file is written to a temporary name in
// the same directory and renamed, so a reader never sees a half-written file.
#pragma once

#include "stratum/mesh.hpp"

#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace stratum {

/// A named array: `components` values per tuple, tuples contiguous.
struct Field {
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
  /// Field data of the step (one value each, on the .vtu and the .vtp): e.g. stage_number, step,
  /// load_factor, head_load_kN; and text values, e.g. stage.
  std::vector<std::pair<std::string, double>> values = {};
  std::vector<std::pair<std::string, std::string>> texts = {};
  /// Field data string arrays of several values (e.g. "domains": the domain names in order).
  std::vector<std::pair<std::string, std::vector<std::string>>> text_lists = {};
  const Mesh* mesh = nullptr;
  std::vector<int> cells;          ///< the cells to write (active cells)
  std::vector<Field> point_fields; ///< one tuple per mesh node (e.g. "displacement", 3 comps)
  std::vector<Field> cell_fields;  ///< one tuple per written cell (e.g. "stress", "set_id")
  Eigen::MatrixX2d ip_coords;      ///< integration points (rows)
  std::vector<Field> ip_fields;    ///< one tuple per integration point
};

/// Writes <dir>/<stem>_<k>.vtu and <dir>/<stem>_ip_<k>.vtp for k = 0, 1, ... and keeps
/// <dir>/<stem>.pvd and <dir>/<stem>_ip.pvd up to date after every step.
/// Cells: 4-node quads as VTK_QUAD, 8-node as VTK_QUADRATIC_QUAD, 5-7-node transition
/// quads as VTK_POLYGON through corners and midside nodes in boundary order; 3- and 6-node
/// triangles as VTK_TRIANGLE and VTK_QUADRATIC_TRIANGLE.
class VtkSeriesWriter {
public:
  VtkSeriesWriter(std::string directory, std::string stem);
  /// Throws Error when a file cannot be written.
  void write(const OutputStep& step);
  [[nodiscard]] std::string pvd_path() const;
  [[nodiscard]] int steps_written() const { return static_cast<int>(times_.size()); }

private:
  std::string dir_, stem_;
  std::vector<double> times_;
};

} // namespace stratum
