// The cell types of stratum/cell_type.hpp and the fields of stratum/fields.hpp: the dimension,
// the continuum/interface split and the corner slots of every type (against the slot numberings
// the header documents), and the default displacement fields an element declares.
#include "stratum/cell_type.hpp"
#include "stratum/element.hpp"
#include "stratum/fields.hpp"

#include <catch2/catch.hpp>

#include <bit>

namespace test_cell_type {

using stratum::CellType;

TEST_CASE("cell types: dimension, kind and corner slots", "[mesh]") {
  struct Row {
    CellType type;
    int dim;
    bool solid;
    int corners;
    const char* name;
  };
  // Corners: quadrilateral 0-3, triangle 0-2, hexahedron 0-7, tetrahedron 0-3, wedge 0-5,
  // node pair 0-1, line interface 0-3.
  for (const Row& r :
       {Row{CellType::quadrilateral, 2, true, 4, "quadrilateral"},
        Row{CellType::triangle, 2, true, 3, "triangle"}, Row{CellType::hexahedron, 3, true, 8, "hexahedron"},
        Row{CellType::tetrahedron, 3, true, 4, "tetrahedron"}, Row{CellType::wedge, 3, true, 6, "wedge"},
        Row{CellType::node_pair, 2, false, 2, "node_pair"},
        Row{CellType::line_interface, 2, false, 4, "line_interface"}}) {
    CAPTURE(r.name);
    CHECK(stratum::cell_dimension(r.type) == r.dim);
    CHECK(stratum::is_solid(r.type) == r.solid);
    const unsigned corners = stratum::corner_slots(r.type);
    CHECK(std::popcount(corners) == r.corners);
    CHECK(corners == (1u << r.corners) - 1u); // the corners are the first slots of every type
    CHECK(std::string(stratum::to_string(r.type)) == r.name);
  }
}

TEST_CASE("fields: an element's default unknowns are the displacement of its cell's dimension", "[mesh]") {
  const auto two = stratum::displacement_fields(2), three = stratum::displacement_fields(3);
  REQUIRE(two.size() == 2);
  REQUIRE(three.size() == 3);
  CHECK(three[stratum::field_uz].name == "uz");
  CHECK(two[stratum::field_ux] == stratum::Field{"ux", "m", "kN"});
  CHECK(two[stratum::field_uy] == stratum::Field{"uy", "m", "kN"});
  const stratum::NodeFields all{three, {}};
  CHECK(all.at(5) == 0x7u); // empty `carried`: every node carries every field
  const stratum::NodeFields some{three, {0x7u, 0x1u}};
  CHECK(some.at(1) == 0x1u);
}

} // namespace test_cell_type
