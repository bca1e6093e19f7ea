// The Material interface: a constitutive law of one integration point.
//
// A Material object holds parameters only; all history lives in the framework's
// StateStore. update() is const and pure: from the committed state and a strain
// increment it computes the trial stress, history and tangent. Numerical trouble
// is returned as an Outcome (never printed, never thrown); the step driver cuts
// the step back.
//
// Units: stress in kPa, strains dimensionless. Tension positive, Voigt order and
// engineering shear as in voigt.hpp.
#pragma once

#include "stratum/error.hpp"
#include "stratum/voigt.hpp"

#include <array>
#include <span>
#include <string>
#include <vector>

namespace stratum {

/// Where the analysis stands in time when a load step evaluates its points (docs/design.md,
/// "Time of a stage"). A static stage runs its load factor lambda from 0 to 1 in a pseudo-time
/// of 1: its step time is lambda, and the total time is the number of stages completed before it
/// plus the step time. The times are those of the start of the step being tried (lambda_n), so
/// that every evaluation of one step sees the same values; dtime is the trial load factor minus
/// lambda_n (0 in the evaluation of a stage's initial forces, negative where a path-following
/// solver unloads). A restart from a checkpoint continues the stage count, hence the total time.
struct StepClock {
  double step_time = 0.0;  ///< time within the stage at the start of the step (static: lambda_n)
  double total_time = 0.0; ///< time of the analysis at the start of the step
  double dtime = 0.0;      ///< time increment of the step (static: lambda - lambda_n)
  int stage = 0;           ///< stage number, 1-based (0: no staged analysis, e.g. a unit test)
  int increment = 0;       ///< load step within the stage, 1-based; a retried step keeps its number
  /// True in a consolidation stage: step_time and dtime are physical time (s) and transient fields
  /// (the pore pressure) flow over dtime. False in a static stage, whose time is its load factor
  /// and which takes no physical time: nothing flows in it (undrained).
  bool transient = false;
};

/// Where and when the point is: for messages, and for materials that depend on position, size or
/// time (e.g. the umat adapter's COORDS, CELENT, TIME, KSTEP, KINC).
struct PointContext {
  int element = -1;          ///< global element index
  int point = -1;            ///< integration point within the element
  StepClock clock{};         ///< the load step being evaluated (ElementData::clock)
  std::array<double, 3> x{}; ///< coordinates of the point (m; 2D: z = 0; axisymmetric: r, z, 0)
  double length = 0.0;       ///< characteristic length of the cell (m): sqrt(area) of a 2D cell,
                             ///< cbrt(volume) of a 3D one; 0 when the caller has no cell
};

/// Input of one update: the committed state at t_n and the total strain increment.
struct MaterialInput {
  const Vec6& stress_n;
  const Vec6& strain_n;
  std::span<const double> history_n;
  const Vec6& dstrain;
  PointContext where;
  /// False when the caller needs no tangent (a residual-only evaluation, e.g. a line-search
  /// trial): a material may then leave out.tangent as it is and skip computing it.
  bool want_tangent = true;
};

/// Output of one update; the caller provides the storage.
struct MaterialOutput {
  Vec6& stress;              ///< trial stress at t_{n+1}
  std::span<double> history; ///< trial history at t_{n+1} (write all of it)
  Mat6& tangent;             ///< d stress / d strain (consistent where the model has one)
};

class Material {
public:
  virtual ~Material() = default;

  /// Number of history doubles per point (besides stress and strain, which the framework keeps).
  [[nodiscard]] virtual int history_size() const { return 0; }
  /// Initial history of a virgin point at the given initial stress.
  virtual void init_history(const Vec6& /*stress*/, std::span<double> history) const {
    for (double& h : history) h = 0.0;
  }
  /// True when stress = D strain with a constant D: elements may then reuse their stiffness.
  [[nodiscard]] virtual bool is_linear() const { return false; }
  /// True when the tangent is symmetric (chooses Cholesky over LU).
  [[nodiscard]] virtual bool symmetric_tangent() const { return true; }

  /// What the committed state of a point is, for the output field "plastic": -1 when the model
  /// does not say (the default), 0 elastic (below yield or failure), >= 1 yielding or failed
  /// (a model may use several codes for its regimes; its README lists them).
  [[nodiscard]] virtual int point_status(const Vec6& /*stress*/, std::span<const double> /*history*/) const {
    return -1;
  }
  /// The names of the codes of point_status, index = code (e.g. {"elastic", "on the yield
  /// surface"}), written to the VTK field data so that a reader can label the regimes (and read
  /// by tools/plastic_zone.py for its legend). Empty (the default): the model names none.
  [[nodiscard]] virtual std::vector<std::string> status_names() const { return {}; }

  /// Branch decisions kept within a load step (docs/design.md, "Branch-consistent Newton"): a
  /// material that returns a history index here keeps its discrete decisions (e.g. loading or
  /// unloading) in that slot of its trial history. The framework guarantees that on entry to
  /// update() out.history holds what the previous evaluation of the point wrote, except that
  /// NonlinearProblem::renew_decisions() sets the slot to 0, which asks the material to decide
  /// afresh from the increment. -1 (the default): the material keeps nothing between evaluations.
  [[nodiscard]] virtual int decision_slot() const { return -1; }
  /// The local error estimate of the update that wrote this trial history (e.g. the difference
  /// of a second- and a first-order stress over the step, relative), for error-controlled load
  /// steps; 0 (the default) when the material has none.
  [[nodiscard]] virtual double step_error(std::span<const double> /*trial_history*/) const { return 0.0; }

  /// The constitutive update. Must fill out.stress, out.history and (when in.want_tangent)
  /// out.tangent.
  [[nodiscard]] virtual Outcome update(const MaterialInput& in, MaterialOutput& out) const = 0;

  /// Names of the first history components, written as integration-point output fields (one
  /// scalar each, beside "plastic"; NaN at the points of materials without that name); empty
  /// (the default) writes none. May be shorter than history_size(): the rest is not written.
  [[nodiscard]] virtual std::vector<std::string> history_names() const { return {}; }
};

} // namespace stratum
