// The integrators of the shared stress-integration library.
//
// One call advances (sigma_n, q_n) by a total strain increment de and returns
// the stress, the internal variables and a tangent. Which algorithm runs is a
// per-material choice read from the material's TOML table:
//
//   integrator = "closest_point"   # forward_euler | modified_euler | trapezoidal |
//                                  # midpoint | cutting_plane | closest_point
//   substeps = 10                  # forward_euler: equal sub-increments
//   stol = 1e-6                    # modified_euler: relative stress error per substep
//   ftol = 1e-9                    # yield tolerance, relative to model.stress_scale()
//   alpha = 0.5                    # trapezoidal / midpoint parameter in [0, 1]
//   max_iterations = 50            # local iterations (implicit schemes, drift correction)
//
// Tangents: closest_point returns the consistent (algorithmic) tangent; the
// other schemes return the continuum elastoplastic tangent at the final state
// (thesis (2.69)-(2.73)), which is what they can honestly offer.
//
// A failed local iteration is an Outcome with a message; nothing is thrown or printed.
#pragma once

#include "stratum/error.hpp"
#include "stratum/params.hpp"
#include "stratum/plasticity/model.hpp"

#include <span>
#include <string>

namespace stratum::plasticity {

enum class Scheme { forward_euler, modified_euler, trapezoidal, midpoint, cutting_plane, closest_point };

struct Settings {
  Scheme scheme = Scheme::closest_point;
  int substeps = 10;
  double stol = 1e-6;
  double ftol = 1e-9;
  double alpha = 0.5;
  int max_iterations = 50;
};

/// Work counters, for the work-precision benchmarks.
struct Counters {
  long yield_evaluations = 0;
  long substeps = 0;
  long iterations = 0;
};

/// Adds the integrator parameters above (with defaults) to a material's schema.
void add_integrator_parameters(Schema& schema, Scheme default_scheme = Scheme::closest_point);
/// Reads them back from validated parameters.
[[nodiscard]] Settings read_integrator_parameters(const Params& params);
[[nodiscard]] const char* to_string(Scheme s);

struct Result {
  Outcome outcome;
  bool plastic = false; ///< some plastic flow happened in this increment
};

/// Integrates the model over the strain increment de.
/// q has internal_size entries on entry (q_n) and exit (q_{n+1}). With want_tangent = false
/// (a residual-only evaluation, MaterialInput::want_tangent) a plastic step leaves `tangent` as
/// it is and skips its cost (the closest point's consistent tangent, the others' continuum one);
/// stress and q are the same either way.
[[nodiscard]] Result integrate(const Model& model, const Settings& settings, const Vec6& sigma_n,
                               const Vec6& de, Vec6& sigma, std::span<double> q, Mat6& tangent,
                               Counters* counters = nullptr, bool want_tangent = true);

/// The continuum elastoplastic tangent with the given active surfaces (thesis (2.69)-(2.73)).
[[nodiscard]] Mat6 continuum_tangent(const Model& model, const Vec6& sigma, std::span<const double> q,
                                     std::span<const int> active);

} // namespace stratum::plasticity
