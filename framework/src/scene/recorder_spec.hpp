// Recorders ([[output.history]]) and checks ([[checks]]) as a scene declares them: read and checked
// here; resolved against the model and sampled by output/recorders.hpp. Internal to the framework.
//
// A recorder samples named quantities after every converged step into one CSV per run,
// <out>/history/<name>.csv, with the columns stage, step, lambda and its quantities:
//
//   kind = "node"    at = [x, y]  one node (within 1e-6 of the mesh's size of `at`):
//                                 ux, uy (m), rx, ry (kN: the reaction, on constrained DOFs)
//   kind = "nodes"   set = "..."  a node or edge set: ux, uy (mean, m), rx, ry (sum of reactions, kN)
//                                 both node kinds also record the scene's other fields by name: "p"
//                                 (the mean over the nodes that carry it) and "p_reaction" (the sum
//                                 of its reactions), in the field's units
//   kind = "point"   at = [x, y]  the integration point of an active cell nearest to `at`
//                                 (chosen anew at each step: cells may be placed or removed):
//                                 x, y (m, where it is), sxx, syy, szz, sxy (kPa, tension positive),
//                                 exx, eyy, ezz, gxy (engineering shear), status (the model's
//                                 point_status: its own regime number, -1 where it has none)
//   kind = "global"               lambda, iterations (of the step), time (the analysis time: one
//                                 unit per static stage, the physical time of consolidation
//                                 stages); with porous elements p_max (the largest |p| at a node,
//                                 kPa), p_mean (the excess pressure's mean over the porous cells,
//                                 kPa) and U (the stage's degree of consolidation, 1 - p_mean /
//                                 p_mean at the end of the stage before); by default lambda,
//                                 iterations and time
//   kind = "interface" set = "..." an interface ([[interfaces]] name, by default its edge set's):
//                                 one row per interface point and step, ordered along it:
//                                 s (m, arc length along the interface from its end nearest
//                                 the set's first point; always the first column), x, y (m),
//                                 shear_traction, normal_traction (kPa, normal tension
//                                 positive), slip, opening (m: the jump u(body 2) - u(body 1)
//                                 along the tangent a -> b and the normal out of body 1),
//                                 status (0 stick, 1 slip, 2 open); a point that two
//                                 elements share (nodal integration) has a row for each
//
// A check compares the last recorded value of one recorder quantity with an expected value:
// it passes when |value - expected| <= atol + rtol |expected|. For an interface recorder the
// value is that of the point of the last step farthest from the expected one (the check holds
// at every point). The run prints each check and
// ends with exit status 5 when one fails (framework/cli/main.cpp).
#pragma once

#include "stratum/error.hpp"
#include "stratum/units.hpp"

#include <toml++/toml.h>

#include <string>
#include <vector>

namespace stratum {

/// The quantities a recorder of `kind` records (node, nodes, point, global, interface), in order.
[[nodiscard]] const std::vector<std::string>& recorder_quantities(const std::string& kind);
/// A point recorder records the first this many of its quantities unless told which (the rest,
/// the pore water's, when asked).
inline constexpr std::size_t point_dry_quantities = 11;

/// The unit of a recorder quantity in kN, m, kPa ("m", "kN", "kPa" or "-"); Units::label spells it
/// in a scene's units.
[[nodiscard]] std::string recorder_quantity_unit(const std::string& quantity);

/// The field a node recorder's field quantity names: "p" and "p_reaction" are both field "p".
[[nodiscard]] std::string recorder_field(const std::string& quantity);

/// One [[output.history]] table as read: checked, with its quantities resolved (they depend on
/// the kind only, not on the mesh). The names of nodes, sets and interfaces are resolved when the
/// scene is built (Recorder).
struct RecorderSpec {
  std::string context, name, kind, set;
  std::vector<std::string> quantities;
  /// Where each field quantity of a node recorder (a name that is not one of the kind's, e.g.
  /// "p") was written, in order: checked against the scene's fields when the model is built.
  std::vector<SourceLocation> quantity_at;
  double at[2] = {0.0, 0.0};
  SourceLocation where, set_at, at_at;
};

/// Reads and checks one [[output.history]] table; `ctx` names it in messages.
[[nodiscard]] RecorderSpec read_recorder(const toml::table& t, const std::string& ctx,
                                         const Units& units = {});

struct Check {
  std::string recorder, quantity;
  double expected = 0.0, rtol = 0.0, atol = 0.0;
  SourceLocation where;
};

/// Reads one [[checks]] table; the recorder and quantity must exist.
Check parse_check(const toml::table& t, const std::string& ctx, const std::vector<RecorderSpec>& recorders);

} // namespace stratum
