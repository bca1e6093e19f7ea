// The framework's own mesh generators (stratum/mesh_generator.hpp), registered into every
// Analysis's registry before the scene is read. [mesh] generator = "blocks" and "gmsh" are
// read by scene/read_mesh.cpp itself (their tables are not one flat parameter table).
#pragma once

#include "stratum/registry.hpp"

#include <string>

namespace stratum {

/// axisymmetric_pile (the bored pile in its soil cylinder, [mesh.pile]).
void register_builtin_mesh_generators(Registry& registry);

/// The sub-table of [mesh] that holds a generator's parameters: [mesh.<generator>], except
/// [mesh.pile] for axisymmetric_pile (its name in scenes written before generators were a kind).
[[nodiscard]] std::string generator_table(const std::string& generator);

} // namespace stratum
