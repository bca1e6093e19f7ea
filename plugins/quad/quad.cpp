// Plugin entry point of the "quad" element: the factory with its parameter schema.
// The element itself lives in quad_element.hpp (shared with the tests).
#include "quad_element.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

stratum::Formulation formulation_of(const std::string& s) {
  return s == "plane_strain" ? stratum::Formulation::plane_strain : stratum::Formulation::axisymmetric;
}

stratum::quad::Volumetric volumetric_of(const std::string& s) {
  if (s == "bbar") return stratum::quad::Volumetric::bbar;
  if (s == "selective") return stratum::quad::Volumetric::selective;
  return stratum::quad::Volumetric::full;
}

} // namespace

STRATUM_PLUGIN(registry) {
  stratum::Factory<stratum::Element> f;
  f.name = "quad";
  f.summary = "isoparametric 4- to 8-node quadrilateral, axisymmetric (full circle, 2 pi r) or plane strain";
  f.schema
      .text("formulation", {"axisymmetric", "plane_strain"},
            "axisymmetric (x = r, y = z; forces for the full circle) or plane strain (unit thickness)")
      .defaults_to(std::string("axisymmetric"));
  f.schema.integer("integration", "-", "number n of Gauss points per direction (n x n rule)")
      .at_least(2)
      .at_most(4)
      .defaults_to(3LL);
  f.schema
      .text("volumetric", {"full", "bbar", "selective"},
            "volumetric strain: full (standard displacement form), bbar (mean dilatation: averaged over the "
            "cell) or selective (projected onto the polynomials through the (n-1)x(n-1) Gauss points, the "
            "B-bar form of selective reduced integration)")
      .defaults_to(std::string("full"));
  f.create = [](const stratum::Params& p) -> std::unique_ptr<stratum::Element> {
    stratum::quad::Options o;
    o.formulation = formulation_of(p.text("formulation"));
    o.integration = static_cast<int>(p.integer("integration"));
    o.volumetric = volumetric_of(p.text("volumetric"));
    return std::make_unique<stratum::quad::QuadElement>(o);
  };
  registry.add(std::move(f));
}
