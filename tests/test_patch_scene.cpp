// Patch tests through the whole pipeline: a distorted 2x2 Gmsh mesh (4- and
// 8-node), loaded by a uniform pressure on one face with symmetry supports, must
// give the uniform stress state and the linear displacement field exactly.
#include "scene_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>

namespace test_patch_scene {

using namespace stratum;

namespace {
const std::string patch_path = stratum::testing::scene_path("patch/patch.toml");

/// patch/patch.toml on the Gmsh mesh `msh` (tests/data/), in `formulation`, with `volumetric`.
std::string patch_scene(const std::string& msh, const std::string& formulation,
                        const std::string& volumetric) {
  using stratum::testing::replace_once;
  std::string t = stratum::testing::read_text(patch_path);
  t = replace_once(t, "patch_quad4.msh", msh);
  t = replace_once(t, "formulation = \"plane_strain\"", "formulation = \"" + formulation + "\"");
  return replace_once(t, "volumetric = \"full\"", "volumetric = \"" + volumetric + "\"");
}
} // namespace

TEST_CASE("patch: distorted Gmsh meshes reproduce uniform stress exactly", "[patch]") {
  const double E = 200, nu = 0.3, p = 10;
  for (const std::string msh : {"patch_quad4.msh", "patch_quad8.msh"})
    for (const std::string form : {"plane_strain", "axisymmetric"})
      for (const std::string vol : {"full", "bbar", "selective"}) {
        auto an = stratum::testing::scene(patch_scene(msh, form, vol), patch_path);
        REQUIRE(an->run().outcome.ok());
        const Model& m = an->model();
        // Exact fields (tension positive).
        Vec6 s_exact = Vec6::Zero();
        double ex, ey; // u_x = ex x, u_y = ey y
        if (form == "plane_strain") {
          s_exact[0] = -p, s_exact[2] = -nu * p;
          ex = -p * (1 - nu * nu) / E, ey = nu * (1 + nu) * p / E;
        } else {
          s_exact[0] = -p, s_exact[2] = -p; // sigma_r = sigma_theta = -p, sigma_z = 0
          ex = -p * (1 - nu) / E, ey = 2 * nu * p / E;
        }
        double u_err = 0, s_err = 0;
        for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n) {
          u_err = std::max(u_err, std::abs(m.u[2 * static_cast<Eigen::Index>(n)] - ex * m.mesh.nodes[n].x()));
          u_err =
              std::max(u_err, std::abs(m.u[2 * static_cast<Eigen::Index>(n) + 1] - ey * m.mesh.nodes[n].y()));
        }
        const auto& st = m.domains.at(0).states;
        for (std::size_t q = 0; q < st.points(); ++q)
          s_err = std::max(s_err, (st.committed(q).stress() - s_exact).norm());
        INFO(msh << " " << form << " " << vol << ": max |u - u_exact| = " << u_err
                 << ", max |s - s_exact| = " << s_err);
        CHECK(u_err <= 1e-10 * std::abs(ex));
        CHECK(s_err <= 1e-10 * p);
      }
}

} // namespace test_patch_scene
