// Plugin entry point of the "hex8" element: the factory with its parameter schema. The element
// lives in hex_element.hpp (shared with the tests).
#include "hex_element.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Element> f;
  f.name = "hex8";
  f.summary = "8-node trilinear hexahedron of a three-dimensional continuum (small strain), optional B-bar";
  f.schema.integer("integration", "-", "number n of Gauss points per direction (n x n x n rule)")
      .at_least(1)
      .at_most(3)
      .defaults_to(2LL);
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
    return std::make_unique<stratum::hex::HexElement>(o);
  };
  registry.add(std::move(f));
}
