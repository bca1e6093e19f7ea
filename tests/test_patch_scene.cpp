// Patch tests through the whole pipeline: a distorted 2x2 Gmsh mesh (4- and
// 8-node), loaded by a uniform pressure on one face with symmetry supports, must
// give the uniform stress state and the linear displacement field exactly.
#include "scene_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace stratum;

namespace {
std::string patch_scene(const std::string& msh, const std::string& formulation,
                        const std::string& volumetric) {
  return "[analysis]\nformulation = \"" + formulation + "\"\n[mesh]\ngenerator = \"gmsh\"\nfile = \"" +
         std::string(STRATUM_TEST_DATA_DIR) + "/" + msh +
         "\"\n[materials.m]\nmodel = \"linear_elastic\"\nE = 200.0\nnu = 0.3\n"
         "[[domains]]\ncells = \"patch\"\nelement = \"quad\"\nmaterial = \"m\"\nvolumetric = \"" +
         volumetric +
         "\"\n[[constraints]]\nnodes = \"left\"\nux = 0.0\n[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
         "[[loads]]\ntype = \"pressure\"\nedges = \"right\"\np = 10.0\n";
}
} // namespace

TEST_CASE("patch: distorted Gmsh meshes reproduce uniform stress exactly", "[patch]") {
  const double E = 200, nu = 0.3, p = 10;
  for (const std::string msh : {"patch_quad4.msh", "patch_quad8.msh"})
    for (const std::string form : {"plane_strain", "axisymmetric"})
      for (const std::string vol : {"full", "bbar", "selective"}) {
        auto an = stratum::testing::scene(patch_scene(msh, form, vol));
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
