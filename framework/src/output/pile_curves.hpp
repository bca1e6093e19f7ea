// The pile curves' quantities: a node set's mean settlement and a pile's axial force profile.
#pragma once

#include "stratum/model.hpp"

#include <array>
#include <vector>

namespace stratum {

/// Mean downward displacement of a node set (m).
[[nodiscard]] double mean_settlement(const Model& m, const std::vector<int>& nodes);

/// Axial force N(y) (kN, compression positive) of the active cells of a set, from the stress
/// sigma_yy at the integration points: for each cell, the points of one row (equal y) give the
/// weighted mean of sigma_yy times the cell's cross-section area (axisymmetric: the ring). Exact
/// for rectangular cells; rows at the same level from different cells are added. Levels are
/// rounded to 1 / per_unit length units: a micrometre (1e6 per m, 1e3 per mm; Units::length_in_m).
[[nodiscard]] std::vector<std::array<double, 2>> axial_profile(const Model& m, const std::vector<int>& cells,
                                                               double per_unit = 1e6);

} // namespace stratum
