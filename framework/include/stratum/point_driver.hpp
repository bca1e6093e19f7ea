// The material-point driver: one integration point of any material plugin
// driven along controlled stress/strain paths (`stratum point POINT.toml`).
//
// Every path is a mixed control problem: each of the six Voigt components is
// either strain-controlled (its increment is given) or stress-controlled (its
// target is given); the unknown strains are found per step by Newton with the
// material's tangent. Tension positive inside; the CSV adds compression-positive
// eps_axial, eps_vol, p and q (axial = y, radial = x and z).
#pragma once

#include "stratum/error.hpp"
#include "stratum/material.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/units.hpp"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace stratum {

/// One path segment as the driver runs it.
struct PointPath {
  std::string name; ///< e.g. "triaxial_drained", for messages and the CSV
  std::array<bool, 6> stress_controlled{};
  Vec6 increment =
      Vec6::Zero(); ///< over the whole segment: strain (controlled) or stress change (controlled)
  int steps = 1;
};

struct PointRow {
  int step = 0;
  int segment = 0;
  Vec6 strain = Vec6::Zero(), stress = Vec6::Zero();
};

struct PointRun {
  Outcome outcome;
  std::vector<PointRow> rows; ///< row 0 is the initial state
  Units units;                ///< the point file's [units]: the CSV labels stresses in them
};

class PointDriver {
public:
  /// Reads and validates a point file (throws Error with file:line:col).
  static std::unique_ptr<PointDriver> from_file(const std::string& path,
                                                std::vector<std::string> plugin_dirs = {});
  static std::unique_ptr<PointDriver> from_string(const std::string& text, const std::string& path,
                                                  std::vector<std::string> plugin_dirs = {});
  ~PointDriver();

  /// Runs every path; a material failure or a mixed-control failure ends the run with a status.
  [[nodiscard]] PointRun run() const;
  /// Writes rows as CSV atomically (temporary file, then rename). Throws Error on I/O failure.
  static void write_csv(const PointRun& run, const std::string& path);

  [[nodiscard]] const std::vector<PointPath>& paths() const;

  struct Impl;

private:
  explicit PointDriver(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

} // namespace stratum
