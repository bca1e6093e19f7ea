// Mesh generators: [mesh] generator = "<name>" builds the scene's mesh from the parameters in
// [mesh.<name>] (the bored-pile mesher, built in, reads [mesh.pile]). The framework's own
// generators and those of plugins are registered alike:
//
//   registry.add(stratum::Factory<stratum::MeshGenerator>{"my_mesher", "one line", schema, create});
//
// `generator = "blocks"` and `"gmsh"` are read by the scene reader itself.
#pragma once

#include "stratum/element.hpp"
#include "stratum/mesh.hpp"

namespace stratum {

/// What the scene says besides the generator's own table.
struct MeshRequest {
  Formulation formulation = Formulation::axisymmetric; ///< [analysis] formulation
  int nodes_per_cell = 8;                              ///< [mesh] nodes_per_cell: 4 or 8
};

class MeshGenerator {
public:
  virtual ~MeshGenerator() = default;
  /// The mesh with its named cell, edge and node sets (checked by Mesh::check afterwards).
  /// Throw Error on a bad combination; an unlocated one is located at the generator's table.
  [[nodiscard]] virtual Mesh generate(const MeshRequest& request) const = 0;
};

} // namespace stratum
