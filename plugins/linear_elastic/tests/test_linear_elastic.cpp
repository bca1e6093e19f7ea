// Tests of the linear elastic material (plugins/linear_elastic): isotropic and
// cross-anisotropic stiffness, the update, and rejection of inadmissible constants.
#include "linear_elastic/elastic_math.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <vector>

namespace test_linear_elastic {

namespace {

using stratum::Mat6;
using stratum::Vec6;
namespace le = stratum::linear_elastic;

Vec6 unit(int i, double v) {
  Vec6 e = Vec6::Zero();
  e(i) = v;
  return e;
}

} // namespace

TEST_CASE("linear_elastic: uniaxial strain gives the constrained modulus", "[point]") {
  for (double nu : {0.0, 0.2, 0.3, 0.45, 0.4999, -0.3}) {
    INFO("nu " << nu);
    const double E = 2.5e4;
    const Mat6 D = le::isotropic_stiffness(E, nu);
    const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    const double G = E / (2 * (1 + nu));
    const double eps = -1e-3;
    const Vec6 s = D * unit(stratum::voigt::yy, eps);
    CHECK(s(stratum::voigt::yy) == Approx(M * eps).epsilon(1e-14));
    CHECK(s(stratum::voigt::xx) == Approx(lambda * eps).epsilon(1e-14).margin(1e-15));
    CHECK(s(stratum::voigt::zz) == Approx(lambda * eps).epsilon(1e-14).margin(1e-15));
    CHECK(s.tail<3>().isZero());
    // engineering shear: tau = G gamma, for all three shear components
    for (int i = 3; i < 6; ++i) CHECK((D * unit(i, 2e-3))(i) == Approx(G * 2e-3).epsilon(1e-14));
    // uniaxial stress: inverse gives 1/E and -nu/E
    const Vec6 e = D.inverse() * unit(stratum::voigt::xx, 10.0);
    CHECK(e(0) == Approx(10.0 / E).epsilon(1e-10));
    CHECK(e(1) == Approx(-nu * 10.0 / E).epsilon(1e-8).margin(1e-16));
    CHECK(le::positive_definite(D));
  }
}

TEST_CASE("linear_elastic: update adds D times the strain increment to the committed stress", "[point]") {
  const le::LinearElastic mat(le::isotropic_stiffness(1.0e4, 0.25));
  CHECK(mat.is_linear());
  CHECK(mat.symmetric_tangent());
  CHECK(mat.history_size() == 0);
  Vec6 stress_n, strain_n, dstrain, stress;
  stress_n << -50, -100, -50, 5, 0, 0;
  strain_n << 1e-4, 2e-4, 0, 3e-4, 0, 0;
  dstrain << 1e-4, -3e-4, 2e-5, 1e-4, 2e-5, -1e-5;
  Mat6 tangent;
  stratum::MaterialOutput out{stress, {}, tangent};
  const stratum::Outcome o = mat.update(stratum::MaterialInput{stress_n, strain_n, {}, dstrain, {4, 2}}, out);
  REQUIRE(o.ok());
  const Mat6 D = le::isotropic_stiffness(1.0e4, 0.25);
  CHECK((stress - (stress_n + D * dstrain)).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((tangent - D).cwiseAbs().maxCoeff() == 0.0);
  // hand-checked entry: sigma_yy = -100 + lambda tr + 2 G deps_yy with lambda = G = 4000
  const double tr = 1e-4 - 3e-4 + 2e-5;
  CHECK(stress(1) == Approx(-100 + 4000 * tr + 8000 * -3e-4).epsilon(1e-13));
}

TEST_CASE("linear_elastic: cross-anisotropic reduces to isotropic for matching constants", "[point]") {
  const double E = 3.0e4, nu = 0.28;
  const Mat6 iso = le::isotropic_stiffness(E, nu);
  // all optional constants at their defaults
  le::Settings s;
  s.cross_anisotropic = true;
  s.E = E;
  s.nu = nu;
  const le::CrossAnisotropic c = le::resolve(s);
  CHECK(c.Ev == E);
  CHECK(c.nu_vh == nu);
  CHECK(c.Gvh == Approx(E / (2 * (1 + nu))).epsilon(1e-15));
  REQUIRE_FALSE(le::check(c).has_value());
  CHECK((le::cross_anisotropic_stiffness(c) - iso).cwiseAbs().maxCoeff() < 1e-12 * iso.maxCoeff());
  // the same constants given explicitly
  s.Ev = E;
  s.nu_vh = nu;
  s.Gvh = E / (2 * (1 + nu));
  CHECK((le::cross_anisotropic_stiffness(le::resolve(s)) - iso).cwiseAbs().maxCoeff() <
        1e-12 * iso.maxCoeff());
  // and a different Gvh is not isotropic any more
  s.Gvh *= 2;
  CHECK((le::cross_anisotropic_stiffness(le::resolve(s)) - iso).cwiseAbs().maxCoeff() >
        1e-3 * iso.maxCoeff());
}

TEST_CASE("linear_elastic: cross-anisotropic stiffness responds with its five constants", "[point]") {
  const le::CrossAnisotropic c{2.0e4, 5.0e4, 0.15, 0.3, 9.0e3};
  REQUIRE_FALSE(le::check(c).has_value());
  const Mat6 D = le::cross_anisotropic_stiffness(c);
  CHECK(le::positive_definite(D));
  const Mat6 S = D.inverse();
  const double sv = -100.0;
  // vertical (y) stress: eps_v = sv / Ev, eps_h = -nu_vh sv / Ev in both horizontal directions
  Vec6 e = S * unit(stratum::voigt::yy, sv);
  CHECK(e(1) == Approx(sv / c.Ev).epsilon(1e-10));
  CHECK(e(0) == Approx(-c.nu_vh * sv / c.Ev).epsilon(1e-10));
  CHECK(e(2) == Approx(-c.nu_vh * sv / c.Ev).epsilon(1e-10));
  // horizontal (x) stress: eps_x = s / Eh, eps_z = -nu_hh s / Eh, eps_y = -nu_hv s / Eh with nu_hv = nu_vh Eh
  // / Ev
  e = S * unit(stratum::voigt::xx, sv);
  CHECK(e(0) == Approx(sv / c.Eh).epsilon(1e-10));
  CHECK(e(2) == Approx(-c.nu_hh * sv / c.Eh).epsilon(1e-10));
  CHECK(e(1) == Approx(-(c.nu_vh * c.Eh / c.Ev) * sv / c.Eh).epsilon(1e-10));
  // shear moduli
  CHECK(D(stratum::voigt::xy, stratum::voigt::xy) == Approx(c.Gvh).epsilon(1e-14));
  CHECK(D(stratum::voigt::yz, stratum::voigt::yz) == Approx(c.Gvh).epsilon(1e-14));
  CHECK(D(stratum::voigt::zx, stratum::voigt::zx) == Approx(c.Eh / (2 * (1 + c.nu_hh))).epsilon(1e-14));
  // x and z are equivalent (isotropy in the horizontal plane)
  CHECK(D(0, 0) == Approx(D(2, 2)).epsilon(1e-14));
  CHECK(D(0, 1) == Approx(D(2, 1)).epsilon(1e-14));
  CHECK((D - D.transpose()).cwiseAbs().maxCoeff() < 1e-10);
}

TEST_CASE("linear_elastic: non-positive-definite constants are rejected", "[point]") {
  // |nu_vh| must stay below sqrt((1 - nu_hh) Ev / (2 Eh)) = sqrt(0.8 * 1e4 / 4e4) = 0.4472
  le::CrossAnisotropic c{2.0e4, 1.0e4, 0.2, 0.44, 5.0e3};
  CHECK_FALSE(le::check(c).has_value());
  CHECK(le::positive_definite(le::cross_anisotropic_stiffness(c)));
  c.nu_vh = 0.45;
  auto problem = le::check(c);
  REQUIRE(problem.has_value());
  CHECK(problem->parameter == "nu_vh");
  CHECK_THAT(problem->message, Catch::Contains("not positive definite") && Catch::Contains("0.447214"));
  CHECK_FALSE(le::positive_definite(le::cross_anisotropic_stiffness(c)));
  c.nu_vh = -0.45; // the sign does not help
  CHECK(le::check(c).has_value());

  c.nu_vh = 0.3;
  c.Gvh = -1.0;
  problem = le::check(c);
  REQUIRE(problem.has_value());
  CHECK(problem->parameter == "Gvh");
  c.Gvh = 5.0e3;
  c.nu_hh = 1.0;
  REQUIRE(le::check(c).has_value());
  CHECK(le::check(c)->parameter == "nu");

  // The material itself refuses a stiffness that is not positive definite.
  CHECK_THROWS_AS(le::LinearElastic(le::isotropic_stiffness(1.0e4, 0.6)), stratum::Error);
  CHECK_THROWS_AS(le::LinearElastic(le::isotropic_stiffness(-1.0e4, 0.3)), stratum::Error);
  Mat6 nonsym = le::isotropic_stiffness(1.0e4, 0.3);
  nonsym(0, 1) += 100.0;
  CHECK_THROWS_AS(le::LinearElastic(nonsym), stratum::Error);
  CHECK_NOTHROW(le::LinearElastic(le::isotropic_stiffness(1.0e4, 0.4999)));
}

} // namespace test_linear_elastic
