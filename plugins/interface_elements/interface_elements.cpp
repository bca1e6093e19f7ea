// Plugin entry point of the interface elements contact2, interface_line and thin_layer.
// The elements live in interface_elements.hpp (shared with the tests).
#include "interface_elements.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

using namespace stratum;

Formulation formulation_of(const std::string& s) {
  return s == "plane_strain" ? Formulation::plane_strain : Formulation::axisymmetric;
}

void add_formulation(Schema& s) {
  s.text("formulation", {"axisymmetric", "plane_strain"},
         "axisymmetric (x = r; forces for the full circle, 2 pi r) or plane strain (unit thickness)")
      .defaults_to(std::string("axisymmetric"));
}

} // namespace

STRATUM_PLUGIN(registry) {
  {
    Factory<Element> f;
    f.name = "contact2";
    f.summary = "two-node contact element between coincident node pairs (thesis 3.51), any ContactLaw";
    add_formulation(f.schema);
    f.create = [](const Params& p) -> std::unique_ptr<Element> {
      return std::make_unique<interfaces::Contact2>(formulation_of(p.text("formulation")));
    };
    registry.add(std::move(f));
  }
  {
    Factory<Element> f;
    f.name = "interface_line";
    f.summary = "zero-thickness line interface on quad edges (2 + 2 or 3 + 3 nodes), any ContactLaw";
    add_formulation(f.schema);
    f.schema
        .text("integration", {"gauss", "newton_cotes"},
              "gauss (2 or 3 Gauss points) or newton_cotes (points on the nodes: trapezoid or Simpson)")
        .defaults_to(std::string("newton_cotes"));
    f.create = [](const Params& p) -> std::unique_ptr<Element> {
      return std::make_unique<interfaces::InterfaceLine>(formulation_of(p.text("formulation")),
                                                         p.text("integration") == "gauss"
                                                             ? interfaces::LineRule::gauss
                                                             : interfaces::LineRule::newton_cotes);
    };
    registry.add(std::move(f));
  }
  {
    Factory<Element> f;
    f.name = "thin_layer";
    f.summary = "thin-layer interface element (Desai & Zaman): a thin quadrilateral with any Material";
    add_formulation(f.schema);
    f.schema.integer("integration", "-", "number n of Gauss points per direction (n x n rule)")
        .at_least(2)
        .at_most(4)
        .defaults_to(2LL);
    f.schema.real("min_ratio", "-", "smallest allowed thickness ratio t/b")
        .greater_than(0.0)
        .defaults_to(0.01);
    f.schema.real("max_ratio", "-", "largest allowed thickness ratio t/b")
        .greater_than(0.0)
        .at_most(1.0)
        .defaults_to(0.1);
    f.create = [](const Params& p) -> std::unique_ptr<Element> {
      quad::Options o;
      o.formulation = formulation_of(p.text("formulation"));
      o.integration = static_cast<int>(p.integer("integration"));
      if (p.real("min_ratio") >= p.real("max_ratio"))
        throw Error(p.where("min_ratio"), p.context + " min_ratio must be below max_ratio");
      return std::make_unique<interfaces::ThinLayer>(o, p.real("min_ratio"), p.real("max_ratio"));
    };
    registry.add(std::move(f));
  }
}
