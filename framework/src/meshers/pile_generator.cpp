// The bored-pile mesher as a mesh generator: [mesh] generator = "axisymmetric_pile", its
// dimensions and cell counts in [mesh.pile] (stratum/mesh_io.hpp: PileMesh, generate_pile).
#include "meshers/builtin_generators.hpp"

#include "stratum/mesh_io.hpp"

#include <memory>

namespace stratum {

namespace {

Schema pile_schema() {
  const PileMesh d;
  Schema s;
  s.real("radius", "m", "pile radius").greater_than(0).defaults_to(d.radius);
  s.real("length", "m", "pile length below the ground surface y = 0").greater_than(0).defaults_to(d.length);
  s.real("near_radius", "m", "outer radius of the near (nonlinear) zone")
      .greater_than(0)
      .defaults_to(d.near_radius);
  s.real("near_depth", "m", "depth of the near zone").greater_than(0).defaults_to(d.near_depth);
  s.real("domain_radius", "m", "radius of the model").greater_than(0).defaults_to(d.domain_radius);
  s.real("domain_depth", "m", "depth of the model").greater_than(0).defaults_to(d.domain_depth);
  s.integer("n_pile", "-", "cells across the pile radius")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.n_pile));
  s.integer("n_shaft", "-", "cells along the pile")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.n_shaft));
  s.integer("n_near", "-", "cells across the near zone")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.n_near));
  s.integer("n_far", "-", "cells across the far zone")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.n_far));
  s.integer("n_below", "-", "cells from the pile base to near_depth")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.n_below));
  s.integer("n_deep", "-", "cells from near_depth to domain_depth")
      .at_least(1)
      .defaults_to(static_cast<long long>(d.n_deep));
  s.real("grade_near", "-", "outer/inner cell width in the near zone")
      .greater_than(0)
      .defaults_to(d.grade_near);
  s.real("grade_far", "-", "outer/inner cell width in the far zone").greater_than(0).defaults_to(d.grade_far);
  s.real("grade_below", "-", "lower/upper cell height below the base")
      .greater_than(0)
      .defaults_to(d.grade_below);
  s.real("grade_deep", "-", "lower/upper cell height in the deep zone")
      .greater_than(0)
      .defaults_to(d.grade_deep);
  return s;
}

class PileGenerator final : public MeshGenerator {
public:
  explicit PileGenerator(const Params& p) {
    spec_.radius = p.real("radius"), spec_.length = p.real("length");
    spec_.near_radius = p.real("near_radius"), spec_.near_depth = p.real("near_depth");
    spec_.domain_radius = p.real("domain_radius"), spec_.domain_depth = p.real("domain_depth");
    spec_.nodes_per_cell = 0;
    spec_.n_pile = static_cast<int>(p.integer("n_pile")),
    spec_.n_shaft = static_cast<int>(p.integer("n_shaft"));
    spec_.n_near = static_cast<int>(p.integer("n_near")), spec_.n_far = static_cast<int>(p.integer("n_far"));
    spec_.n_below = static_cast<int>(p.integer("n_below")),
    spec_.n_deep = static_cast<int>(p.integer("n_deep"));
    spec_.grade_near = p.real("grade_near"), spec_.grade_far = p.real("grade_far");
    spec_.grade_below = p.real("grade_below"), spec_.grade_deep = p.real("grade_deep");
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
