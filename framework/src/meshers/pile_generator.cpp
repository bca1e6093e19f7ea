// The bored-pile mesher as a mesh generator: [mesh] generator = "axisymmetric_pile", its
// dimensions and cell counts in [mesh.pile] (stratum/mesh_io.hpp: PileMesh, generate_pile).
#include "meshers/builtin_generators.hpp"

#include "stratum/mesh_io.hpp"

#include <memory>

namespace stratum {

namespace {

// Each key once: its member of PileMesh, declared (with PileMesh's value as the default) and read
// through the same table.
struct Length {
  const char* name;
  double PileMesh::*member;
  const char* meaning;
};
constexpr Length lengths[] = {
    {"radius", &PileMesh::radius, "pile radius"},
    {"length", &PileMesh::length, "pile length below the ground surface y = 0"},
    {"near_radius", &PileMesh::near_radius, "outer radius of the near (nonlinear) zone"},
    {"near_depth", &PileMesh::near_depth, "depth of the near zone"},
    {"domain_radius", &PileMesh::domain_radius, "radius of the model"},
    {"domain_depth", &PileMesh::domain_depth, "depth of the model"},
};
struct Count {
  const char* name;
  int PileMesh::*member;
  const char* meaning;
};
constexpr Count counts[] = {
    {"n_pile", &PileMesh::n_pile, "cells across the pile radius"},
    {"n_shaft", &PileMesh::n_shaft, "cells along the pile"},
    {"n_near", &PileMesh::n_near, "cells across the near zone"},
    {"n_far", &PileMesh::n_far, "cells across the far zone"},
    {"n_below", &PileMesh::n_below, "cells from the pile base to near_depth"},
    {"n_deep", &PileMesh::n_deep, "cells from near_depth to domain_depth"},
};
constexpr Length grades[] = {
    {"grade_near", &PileMesh::grade_near, "outer/inner cell width in the near zone"},
    {"grade_far", &PileMesh::grade_far, "outer/inner cell width in the far zone"},
    {"grade_below", &PileMesh::grade_below, "lower/upper cell height below the base"},
    {"grade_deep", &PileMesh::grade_deep, "lower/upper cell height in the deep zone"},
};

Schema pile_schema() {
  const PileMesh d;
  Schema s;
  for (const auto& k : lengths) s.real(k.name, "m", k.meaning).greater_than(0).defaults_to(d.*k.member);
  for (const auto& k : counts)
    s.integer(k.name, "-", k.meaning).at_least(1).defaults_to(static_cast<long long>(d.*k.member));
  for (const auto& k : grades) s.real(k.name, "-", k.meaning).greater_than(0).defaults_to(d.*k.member);
  return s;
}

class PileGenerator final : public MeshGenerator {
public:
  explicit PileGenerator(const Params& p) {
    for (const auto& k : lengths) spec_.*k.member = p.real(k.name);
    for (const auto& k : counts) spec_.*k.member = static_cast<int>(p.integer(k.name));
    for (const auto& k : grades) spec_.*k.member = p.real(k.name);
    spec_.nodes_per_cell = 0;
  }
  Mesh generate(const MeshRequest& request) const override {
    if (request.formulation != Formulation::axisymmetric)
      throw Error("[mesh] generator = \"axisymmetric_pile\" needs [analysis] formulation = \"axisymmetric\"");
    PileMesh spec = spec_;
    spec.nodes_per_cell = request.nodes_per_cell;
    return generate_pile(spec);
  }

private:
  PileMesh spec_;
};

} // namespace

void register_builtin_mesh_generators(Registry& registry) {
  registry.add(Factory<MeshGenerator>{
      "axisymmetric_pile",
      "a bored pile in a cylinder of soil, graded near and far zones ([mesh.pile])",
      pile_schema(),
      [](const Params& p) -> std::unique_ptr<MeshGenerator> { return std::make_unique<PileGenerator>(p); },
      {}});
}

std::string generator_table(const std::string& generator) {
  return generator == "axisymmetric_pile" ? "pile" : generator;
}

} // namespace stratum
