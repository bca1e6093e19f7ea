// Interface elements in whole scenes (verification.md section 4): C2 column on an interface
// layer, C1 rigid pile with shaft slip, mesh splitting, input errors.
#include "contact_scenes.hpp"
#include "scene_helpers.hpp"

#include "model/body_interfaces.hpp"
#include "stratum/mesh_io.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>

namespace test_contact_scenes {

using namespace stratum;
using namespace stratum::testing;

TEST_CASE("split_interface duplicates the nodes of an edge set and links them", "[contact]") {
  Block lower{"lower", 0, 2, 0, 1, 2, 1}, upper{"upper", 0, 2, 1, 2, 2, 1};
  for (int npc : {4, 8}) {
    for (auto kind : {InterfaceCells::node_pairs, InterfaceCells::line}) {
      Mesh m = generate_blocks({lower, upper}, npc);
      const auto nodes0 = m.nodes.size(), cells0 = m.cells.size();
      const auto edges = m.edge_sets.at("lower.top");
      const auto split = split_interface(m, "mid", edges, m.cell_sets.at("upper"), kind);
      const std::size_t on_line = npc == 4 ? 3 : 5;
      CHECK(split.side1.size() == on_line);
      CHECK(m.nodes.size() == nodes0 + on_line);
      CHECK(m.cells.size() == cells0 + (kind == InterfaceCells::line ? 2 : on_line));
      m.check();
      // The upper cells no longer touch the lower ones.
      for (int c : m.cell_sets.at("upper"))
        for (int n : m.cells[static_cast<std::size_t>(c)].nodes)
          for (int s : split.side1) CHECK(n != s);
      for (std::size_t i = 0; i < split.side1.size(); ++i)
        CHECK((m.nodes[static_cast<std::size_t>(split.side1[i])] -
               m.nodes[static_cast<std::size_t>(split.side2[i])])
                  .norm() == 0.0);
      CHECK_THROWS_WITH(split_interface(m, "mid", edges, {}, kind), Catch::Contains("already has a set"));
    }
  }
}

TEST_CASE("C2 column on an interface layer: w = q H / E_oed + q / k_n", "[contact]") {
  const double q = 100.0, H = 2.0, E = 2e4, nu = 0.3, kn = 5e4;
  const double Eoed = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const double expected = q * H / Eoed + q / kn;
  for (const char* form : {"plane_strain", "axisymmetric"})
    for (const char* kind : {"contact2", "interface_line", "interface_line_gauss", "thin_layer"})
      for (int npc : {4, 8}) {
        CAPTURE(form, kind, npc);
        ColumnSpec s;
        s.formulation = form, s.kind = kind, s.nodes_per_cell = npc;
        s.q = q, s.H = H, s.E = E, s.nu = nu, s.kn = kn;
        auto a = scene(column_scene(s));
        const auto run = a->run();
        REQUIRE(run.outcome.ok());
        const Model& m = a->model();
        const double w = -m.u[2 * node_at(m, 0.5, s.top()) + 1];
        CHECK(rel(w, expected) < 1e-9);
      }
}

TEST_CASE("C1 rigid pile with shaft slip: P(w) before slip, shaft capacity after", "[contact]") {
  for (const char* kind : {"contact2", "interface_line", "thin_layer"}) {
    CAPTURE(kind);
    PileSpec s;
    s.kind = kind;
    std::vector<std::pair<double, double>> curve; // (w, P)
    RunOptions o;
    o.plugin_dirs = {STRATUM_PLUGIN_DIR};
    o.write_output = false;
    Analysis* self = nullptr;
    o.on_step = [&](int, int, double lambda, const StepReport&) {
      curve.emplace_back(lambda * s.w_max(), pile_load(self->model(), s));
    };
    auto a = Analysis::from_string(pile_scene(s), "pile.toml", o);
    self = a.get();
    const auto run = a->run();
    CAPTURE(run.outcome.message);
    REQUIRE(run.outcome.ok());
    REQUIRE(curve.size() == static_cast<std::size_t>(s.steps));
    int before = 0;
    for (const auto& [w, P] : curve)
      if (w < 0.9 * s.w_slip()) {
        ++before;
        const double elastic = s.shaft_stiffness() * w;
        CAPTURE(w, P, elastic);
        CHECK(std::abs(P - elastic) <= 0.10 * elastic);
      }
    CHECK(before >= 3);
    const double capacity = s.shaft_capacity();
    CAPTURE(curve.back().second, capacity);
    CHECK(std::abs(curve.back().second - capacity) <= 0.01 * capacity);
  }
}

TEST_CASE("interface input errors are one located line", "[contact]") {
  ColumnSpec s;
  s.kind = "interface_line";
  std::string text = column_scene(s);
  auto replace = [](std::string t, const std::string& a, const std::string& b) {
    const auto pos = t.find(a);
    REQUIRE(pos != std::string::npos);
    return t.replace(pos, a.size(), b);
  };
  CHECK_THROWS_WITH(scene(replace(text, "law = \"iface\"", "law = \"nope\"")),
                    Catch::Contains("test.toml:") && Catch::Contains("law = \"nope\" is not defined"));
  CHECK_THROWS_WITH(scene(replace(text, "edges = \"soil.bottom\"", "edges = \"nope\"")),
                    Catch::Contains("is not an edge set"));
  CHECK_THROWS_WITH(scene(replace(text, "element = \"interface_line\"", "element = \"quad\"")),
                    Catch::Contains("element = \"quad\" works on area cells (give it in [[domains]]); "
                                    "allowed: an element whose cells are node pairs or interface lines"));
  // ... and an interface element in [[domains]] is refused the other way round.
  CHECK_THROWS_WITH(scene(replace(text, "element = \"quad\"", "element = \"contact2\"")),
                    Catch::Contains("element = \"contact2\" works on interface cells"));
  CHECK_THROWS_WITH(scene(replace(text, "model = \"coulomb_elastoplastic\"",
                                  "model = \"coulomb_elastoplastic\"\npsi = 45.0")),
                    Catch::Contains("psi"));
  ColumnSpec t;
  t.kind = "thin_layer";
  t.layer = 0.3; // t/b = 0.3
  CHECK_THROWS_WITH(scene(column_scene(t)),
                    Catch::Contains("thickness ratio t/b = 0.3") && Catch::Contains("allowed: 0.01 to 0.1"));
}

TEST_CASE("C3 conditioning sweep: k_n h / E from 1 to 1e8", "[contact]") {
  for (const char* kind : {"contact2", "interface_line", "interface_line_gauss", "thin_layer"}) {
    double cond_first = 0.0;
    for (double ratio : {1.0, 1e4, 1e8}) {
      CAPTURE(kind, ratio);
      const auto r = conditioning(kind, ratio, 4, STRATUM_PLUGIN_DIR);
      REQUIRE(r.ok);
      CHECK(r.iterations <= 2);
      // The uniform state is reproduced to round-off although cond(K) grows like k_n h / E:
      // a backward-stable direct solver loses nothing in this patch test.
      CHECK(r.error < 1e-10);
      CHECK(r.interface_error < 1e-8);
      if (ratio == 1.0) cond_first = r.cond;
      if (ratio == 1e8) CHECK(r.cond > 1e5 * cond_first);
    }
  }
  // contact2 on 8-node meshes: the consistent weights of 3-node edges (1/6, 2/3, 1/6) keep the
  // closure uniform, so the column is exact at any stiffness (lumping half-segments, 1/4, 1/2,
  // 1/4, gave 33 % error of q/k_n here).
  for (double ratio : {1.0, 1e4, 1e8}) {
    CAPTURE(ratio);
    const auto r = conditioning("contact2", ratio, 8, STRATUM_PLUGIN_DIR);
    REQUIRE(r.ok);
    CHECK(r.error < 1e-10);
    CHECK(r.interface_error < 1e-8);
  }
}

} // namespace test_contact_scenes
