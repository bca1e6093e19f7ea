// Plugin entry point of the linear solid elements "hex8", "tet4" and "wedge6": the factories with
// their parameter schemas. The elements live in hex_element.hpp (shared with the tests).
#include "hex_element.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

/// The factory of SolidElement<Shape>: its rule (`integration`, 1..max) and the volumetric strain.
template <class Shape>
stratum::Factory<stratum::Element> solid_factory(const char* summary, const char* integration_help,
                                                 long long integration_default) {
  stratum::Factory<stratum::Element> f;
  f.name = Shape::name;
  f.summary = summary;
  f.schema.integer("integration", "-", integration_help)
      .at_least(1)
      .at_most(Shape::max_integration)
      .defaults_to(integration_default);
  f.schema
      .text(
          "volumetric", {"full", "bbar"},
          "volumetric strain: full (standard displacement form) or bbar (mean dilatation: averaged over the "
          "cell, against volumetric locking of nearly incompressible materials)")
      .defaults_to(std::string("full"));
  f.create = [](const stratum::Params& p) -> std::unique_ptr<stratum::Element> {
    stratum::hex::Options o;
    o.integration = static_cast<int>(p.integer("integration"));
    o.bbar = p.text("volumetric") == "bbar";
    return std::make_unique<stratum::hex::SolidElement<Shape>>(o);
  };
  return f;
}

} // namespace

STRATUM_PLUGIN(registry) {
  registry.add(solid_factory<stratum::hex::Hex8>(
      "8-node trilinear hexahedron of a three-dimensional continuum (small strain), optional B-bar",
      "number n of Gauss points per direction (n x n x n rule)", 2));
  registry.add(solid_factory<stratum::hex::Tet4>(
      "4-node linear tetrahedron of a three-dimensional continuum (constant strain), optional B-bar",
      "1: one point at the centroid (exact for the constant strain); 2: the 4-point rule of degree 2", 1));
  registry.add(solid_factory<stratum::hex::Wedge6>(
      "6-node wedge (triangular prism) of a three-dimensional continuum (small strain), optional B-bar",
      "1: one point at the centroid; 2: the 3-point triangle rule times 2-point Gauss across (6 points)", 2));
}
