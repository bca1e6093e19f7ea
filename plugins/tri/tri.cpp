// Plugin entry point of the triangle elements "tri6" and "tri3": the factories with their
// parameter schemas. The element itself lives in tri_element.hpp (shared with the tests).
#include "tri_element.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

void add(stratum::Registry& registry, int nodes) {
  stratum::Factory<stratum::Element> f;
  f.name = nodes == 6 ? "tri6" : "tri3";
  f.summary = nodes == 6
                  ? "isoparametric 6-node (quadratic) triangle, axisymmetric (full circle, 2 pi r) or "
                    "plane strain; for Gmsh meshes made with -order 2"
                  : "3-node constant-strain triangle, axisymmetric (full circle, 2 pi r) or plane strain";
  f.schema
      .text("formulation", {"axisymmetric", "plane_strain"},
            "axisymmetric (x = r, y = z; forces for the full circle) or plane strain (unit thickness)")
      .defaults_to(std::string("axisymmetric"));
  if (nodes == 6)
    f.schema
        .integer(
            "integration", "-",
            "points of the triangle Gauss rule: 3 (degree 2, exact for the plane-strain stiffness of a "
            "straight-sided cell) or 6 (degree 4, for the 1/r and r terms of axisymmetry and curved sides)")
        .at_least(3)
        .at_most(6)
        .defaults_to(6LL);
  else
    f.schema
        .integer(
            "integration", "-",
            "points of the triangle Gauss rule: 3 (degree 2) or 1 (the centroid: exact in plane strain; in "
            "axisymmetry it leaves each cell a zero-energy rotation about its centroid)")
        .at_least(1)
        .at_most(3)
        .defaults_to(3LL);
  f.create = [nodes](const stratum::Params& p) -> std::unique_ptr<stratum::Element> {
    stratum::tri::Options o;
    o.formulation = p.text("formulation") == "plane_strain" ? stratum::Formulation::plane_strain
                                                            : stratum::Formulation::axisymmetric;
    o.nodes = nodes;
    o.integration = static_cast<int>(p.integer("integration"));
    if (o.integration != 1 && o.integration != 3 && o.integration != 6)
      throw stratum::Error(p.where("integration"),
                           std::string(nodes == 6 ? "tri6" : "tri3") +
                               ": integration = " + std::to_string(o.integration) +
                               " is not a triangle rule; allowed: " + (nodes == 6 ? "3 or 6" : "1 or 3"));
    return std::make_unique<stratum::tri::TriElement>(o);
  };
  registry.add(std::move(f));
}

} // namespace

STRATUM_PLUGIN(registry) {
  add(registry, 6);
  add(registry, 3);
}
