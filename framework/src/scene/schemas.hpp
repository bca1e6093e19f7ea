// The schemas of the scene's own tables: [analysis], [convergence], [mesh], [[mesh.blocks]],
// [output]. A plugin's table is checked against the schema its factory declares.
#pragma once

#include "stratum/params.hpp"

namespace stratum::scene {

[[nodiscard]] Schema analysis_schema();
[[nodiscard]] Schema convergence_schema();
[[nodiscard]] Schema mesh_schema();
[[nodiscard]] Schema block_schema();
[[nodiscard]] Schema output_schema();

} // namespace stratum::scene
