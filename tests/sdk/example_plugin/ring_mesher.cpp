// example_ring: a mesh generator (SDK example). A thick-walled ring, radii a..b and height h
// (axisymmetric: x = r, y = z), as one structured block of cells named "ring".
//
//   [mesh]
//   generator = "example_ring"
//   nodes_per_cell = 8
//   [mesh.example_ring]
//   inner_radius = 1.0
//   outer_radius = 2.0
//   height = 0.5
//
// Sets: cells "ring" (and "all"), edges "ring.left" (the inner wall), "ring.right",
// "ring.bottom", "ring.top", node sets of the same names and "bottom", "top" (from
// stratum::generate_blocks).
#include <stratum/mesh_generator.hpp>
#include <stratum/mesh_io.hpp>
#include <stratum/plugin.hpp>

#include <memory>
#include <string>

namespace example_ring {

class RingMesher final : public stratum::MeshGenerator {
public:
  explicit RingMesher(const stratum::Params& p) {
    ring_.name = "ring";
    ring_.x0 = p.real("inner_radius"), ring_.x1 = p.real("outer_radius");
    ring_.y0 = 0.0, ring_.y1 = p.real("height");
    ring_.nx = static_cast<int>(p.integer("n_radial")), ring_.ny = static_cast<int>(p.integer("n_axial"));
    // A check on several parameters at once: an unlocated Error is located at [mesh.example_ring].
    if (!(ring_.x1 > ring_.x0))
      throw stratum::Error(p.where("outer_radius"), p.context + " outer_radius must exceed inner_radius");
  }

  stratum::Mesh generate(const stratum::MeshRequest& request) const override {
    return stratum::generate_blocks({ring_}, request.nodes_per_cell);
  }

private:
  stratum::Block ring_;
};

stratum::Schema schema() {
  stratum::Schema s;
  s.real("inner_radius", "m", "radius of the inner wall").at_least(0.0);
  s.real("outer_radius", "m", "radius of the outer wall").greater_than(0.0);
  s.real("height", "m", "height of the ring").greater_than(0.0);
  s.integer("n_radial", "-", "cells across the wall").at_least(1).defaults_to(8LL);
  s.integer("n_axial", "-", "cells over the height").at_least(1).defaults_to(2LL);
  return s;
}

} // namespace example_ring

STRATUM_PLUGIN(registry) {
  registry.add(stratum::Factory<stratum::MeshGenerator>{
      "example_ring", // what scenes write as  [mesh] generator = "example_ring"
      "a thick-walled ring as one structured block (SDK example)",
      example_ring::schema(),
      [](const stratum::Params& p) -> std::unique_ptr<stratum::MeshGenerator> {
        return std::make_unique<example_ring::RingMesher>(p);
      },
      {}});
}
