// Plugin entry point of the u-p elements quad8p4 and tri6p3: their factories and the schema of
// a domain's hydraulic parameters. The elements live in biot_element.hpp (shared with the tests).
#include "biot_element.hpp"

#include "stratum/plugin.hpp"

#include <memory>
#include <string>

namespace {

stratum::Schema schema(stratum::CellType cell) {
  stratum::Schema s;
  s.text("formulation", {"axisymmetric", "plane_strain"},
         "axisymmetric (x = r, y = z; forces and flows for the full circle) or plane strain (unit thickness)")
      .defaults_to(std::string("axisymmetric"));
  if (cell == stratum::CellType::quadrilateral)
    s.integer("integration", "-", "number n of Gauss points per direction (n x n rule)")
        .at_least(2)
        .at_most(4)
        .defaults_to(3LL);
  else
    s.integer("integration", "-", "points of the triangle rule: 3 (degree 2) or 6 (degree 4)")
        .at_least(3)
        .at_most(6)
        .defaults_to(6LL);
  s.real("permeability", "m/s", "Darcy permeability k (hydraulic conductivity) of the soil; 0: impermeable")
      .at_least(0.0);
  s.real(
       "permeability_y", "m/s",
       "permeability along y (z in axisymmetry) when it differs from `permeability`, which then acts along x")
      .at_least(-1.0)
      .defaults_to(-1.0);
  s.real("porosity", "-", "porosity n of the soil (volume of the pores over the total volume)")
      .greater_than(0.0)
      .less_than(1.0);
  s.real(
       "fluid_bulk_modulus", "kPa",
       "bulk modulus K_w of the pore fluid (water: 2.2e6 kPa; air in the water lowers it); 0: incompressible")
      .at_least(0.0)
      .defaults_to(2.2e6);
  s.real("unit_weight_water", "kN/m3",
         "unit weight gamma_w of the pore fluid (Darcy: v = -(k / gamma_w) grad p)")
      .greater_than(0.0)
      .defaults_to(9.81);
  return s;
}

stratum::Factory<stratum::Element> factory(stratum::CellType cell) {
  stratum::Factory<stratum::Element> f;
  const bool quad = cell == stratum::CellType::quadrilateral;
  f.name = quad ? "quad8p4" : "tri6p3";
  f.summary =
      quad ? "saturated porous quadrilateral (Biot, u-p): quadratic displacements on 8 nodes, bilinear "
             "excess pore pressure on the 4 corners (Taylor-Hood)"
           : "saturated porous triangle (Biot, u-p): quadratic displacements on 6 nodes, linear excess pore "
             "pressure on the 3 corners (Taylor-Hood)";
  f.schema = schema(cell);
  f.create = [cell](const stratum::Params& p) -> std::unique_ptr<stratum::Element> {
    stratum::biot::Options o;
    o.cell = cell;
    o.formulation = p.text("formulation") == "plane_strain" ? stratum::Formulation::plane_strain
                                                            : stratum::Formulation::axisymmetric;
    o.integration = static_cast<int>(p.integer("integration"));
    if (cell == stratum::CellType::triangle && o.integration != 3 && o.integration != 6)
      throw stratum::Error(p.where("integration"), "tri6p3 integration must be 3 or 6 points (got " +
                                                       std::to_string(o.integration) + ")");
    o.water.kx = p.real("permeability");
    o.water.ky = p.real("permeability_y") >= 0.0 ? p.real("permeability_y") : o.water.kx;
    o.water.porosity = p.real("porosity");
    o.water.fluid_bulk_modulus = p.real("fluid_bulk_modulus");
    o.water.unit_weight_water = p.real("unit_weight_water");
    return std::make_unique<stratum::biot::BiotElement>(o);
  };
  return f;
}

} // namespace

STRATUM_PLUGIN(registry) {
  registry.add(factory(stratum::CellType::quadrilateral));
  registry.add(factory(stratum::CellType::triangle));
}
