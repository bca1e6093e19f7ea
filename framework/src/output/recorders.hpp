// Recorders and checks at run time: a recorder resolved against the model samples its quantities
// after every accepted step; the checks are evaluated on the last rows at the end of the run.
// What each kind records: scene/recorder_spec.hpp. Internal to the framework.
#pragma once

#include "scene/recorder_spec.hpp"
#include "stratum/analysis.hpp"
#include "stratum/model.hpp"
#include "stratum/units.hpp"

#include <string>
#include <vector>

namespace stratum {

struct RecorderRow {
  int stage = 0, step = 0;
  double lambda = 0.0;
  std::vector<double> values;
};

class Recorder {
public:
  /// Resolves the spec against the model: the node (within 1e-6 of the mesh's size of `at`),
  /// the node set or the interface it names; throws a located Error when there is none.
  Recorder(const RecorderSpec& spec, const Model& model);

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::string& kind() const { return kind_; }
  [[nodiscard]] const std::vector<std::string>& quantities() const { return quantities_; }
  [[nodiscard]] const std::vector<RecorderRow>& rows() const { return rows_; }
  /// Index of a quantity, or -1.
  [[nodiscard]] int column(const std::string& quantity) const;
  /// The rows of the last recorded step (one, or one per point for an interface); empty if none.
  [[nodiscard]] std::vector<const RecorderRow*> last_step() const;

  /// Samples the model's converged state (reactions already updated); `time` is the analysis time
  /// it is reached at (one unit per static stage, the seconds of consolidation stages; the VTK time).
  void sample(const Model& model, int stage, int step, double lambda, int iterations, double time);
  /// The CSV text: stage,step,lambda,<quantities>, each quantity's column named with its unit in
  /// the scene's units as the curves are (recorder_column: uy_m, ry_kN_per_m, sxx_kPa; a
  /// dimensionless quantity keeps its name).
  [[nodiscard]] std::string csv(const Units& units, Formulation formulation) const;

private:
  std::string name_, kind_, set_;
  std::vector<std::string> quantities_;
  std::vector<int> nodes_; ///< node: the one node; nodes: the set
  std::size_t domain_ = 0; ///< interface: index of the interface's domain in Model::domains
  double at_[2] = {0.0, 0.0};
  bool wants_water_ = false; ///< point: a pore-water quantity is asked for (PointWater)
  std::vector<RecorderRow> rows_;
  /// global U: the stage of the last sample, the mean excess pressure then, and at the stage's start
  int last_stage_ = -1;
  double last_mean_ = std::numeric_limits<double>::quiet_NaN();
  double stage_start_mean_ = std::numeric_limits<double>::quiet_NaN();
};

/// A recorder quantity's CSV column: its name and its unit in the scene's units ("uy", m -> uy_m;
/// "ry" -> ry_kN in axisymmetry, where a reaction is the whole ring's, and ry_kN_per_m in plane
/// strain, per unit thickness); a dimensionless quantity (lambda, strains, status, iterations, U)
/// and the analysis time (a stage counter in static stages) keep their names.
[[nodiscard]] std::string recorder_column(const std::string& quantity, const Units& units,
                                          Formulation formulation);

/// The pore water at one integration point: the steady and the excess pore pressure (kPa,
/// compression positive) and the effective and total stress (tension positive; total = effective -
/// (p_steady + p_excess) m). NaN where the domain computes no pore pressure (drainage =
/// "undrained_total": its stress is total, its effective stress and excess unknown).
struct PointWater {
  double p_steady = 0.0, p_excess = 0.0;
  Vec6 effective = Vec6::Zero(), total = Vec6::Zero();
};

/// The pore water at the points of cell ci of a domain (point order) from the committed state:
/// a porous element interpolates its unknown p (Element::point_field), an undrained domain keeps
/// p in its history, a drained one has none; the steady pressure is Model::water's at the
/// point; a non-porous domain has no water (its stress is total); an interface's points carry a
/// total contact traction (pressures and effective stress NaN).
void point_water(const Model& m, const Domain& dm, std::size_t ci, std::vector<PointWater>& out);

/// Evaluates the checks on the recorders' last rows (a recorder without rows fails its checks).
std::vector<CheckResult> evaluate_checks(const std::vector<Check>& checks,
                                         const std::vector<Recorder>& recorders);

} // namespace stratum
