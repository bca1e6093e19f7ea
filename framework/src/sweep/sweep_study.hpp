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

/// The columns of a point run's CSV that a study may read (`point` outputs).
[[nodiscard]] const std::vector<std::string>& point_columns();

} // namespace detail

} // namespace stratum::sweep
