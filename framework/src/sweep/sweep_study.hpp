// Parameter studies, internal: what the study reader (sweep_study.cpp) and a sample's run
// (sweep.cpp) share.
#pragma once

#include "sweep/sweep.hpp"

#include <toml++/toml.h>

#include <string>
#include <vector>

namespace stratum::sweep {

/// The base scene (or point file) as parsed, includes merged: each sample's text is this with
/// the sample's values set.
struct Study::Base {
  toml::table root;
};

namespace detail {

/// The settlement components of a pile a study may read (columns 2-8 of
/// curves/settlement_components.csv: mm and kN, or the scene's units; head_settlement is the area
/// mean over the head, the curve's `settlement` the mean of its nodes).
[[nodiscard]] const std::vector<std::string>& pile_component_columns();

/// The columns of a point run's CSV that a study may read (`point` outputs).
[[nodiscard]] const std::vector<std::string>& point_columns();

} // namespace detail

} // namespace stratum::sweep
