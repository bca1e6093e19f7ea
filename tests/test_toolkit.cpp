// The toolkit for model authors: parameters declared once and bound to their members
// (stratum/parameters.hpp), and the shared stiffness, projector and principal-stress helpers,
// checked against their definitions.
#include "stratum/elasticity.hpp"
#include "stratum/parameters.hpp"
#include "stratum/plasticity/invariants.hpp"
#include "stratum/stress.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace test_toolkit {

using namespace stratum;

namespace {

enum class Shape { round, sharp };
struct Inner {
  double ocr = 1.0;
};
struct Input {
  double E = 0.0, nu = 0.0, c = 0.0, phi = 0.0, psi = 0.0;
  int substeps = 0;
  bool flag = false;
  Shape shape = Shape::round;
  std::vector<double> levels;
  Inner inner;
};

Declared<Input> declaration() {
  Declared<Input> d;
  declare_isotropic_elastic(d, &Input::E, &Input::nu);
  declare_strength(d, &Input::c, &Input::phi, &Input::psi);
  d.integer(&Input::substeps, "substeps", "-", "substeps").at_least(1).defaults_to(4LL);
  d.flag(&Input::flag, "flag", "a switch").defaults_to(false);
  d.choice(&Input::shape, "shape", {{"round", Shape::round}, {"sharp", Shape::sharp}}, "the shape")
      .defaults_to(std::string("round"));
  d.real_list(&Input::levels, "levels", "kPa", "levels").defaults_to(std::vector<double>{});
  d.real(nested(&Input::inner, &Inner::ocr), "ocr", "-", "overconsolidation ratio")
      .at_least(1.0)
      .defaults_to(1.0);
  d.check([](const Input& in, const Params& p) -> std::optional<Problem> {
    if (in.flag && !p.where("levels").known()) return Problem{"flag", "flag = true needs levels"};
    return std::nullopt;
  });
  return d;
}

SourceLocation at(int line) { return {"s.toml", line, 5}; }

Params valid() {
  Params p;
  p.context = "[materials.soil]";
  p.set("E", 1000.0, at(2));
  p.set("nu", 0.25, at(3));
  p.set("c", 5.0, at(4));
  p.set("phi", 30.0, at(5));
  p.set("psi", 10.0, at(6));
  p.set("substeps", 7LL, at(7));
  p.set("flag", false);
  p.set("shape", std::string("sharp"), at(8));
  p.set("levels", std::vector<double>{50.0, 100.0}, at(9));
  p.set("ocr", 2.0, at(10));
  return p;
}

} // namespace

TEST_CASE("toolkit: one declaration gives the schema and fills every bound member", "[plugins][toolkit]") {
  const auto d = declaration();
  std::vector<std::string> names;
  for (const auto& s : d.schema().specs()) names.push_back(s.name);
  CHECK(names ==
        std::vector<std::string>{"E", "nu", "c", "phi", "psi", "substeps", "flag", "shape", "levels", "ocr"});
  CHECK(d.schema().find("psi")->allowed() == "[0, 90)");
  CHECK(d.schema().find("shape")->choices == std::vector<std::string>{"round", "sharp"});

  const Input in = d.read(valid());
  CHECK(in.E == 1000.0);
  CHECK(in.nu == 0.25);
  CHECK(in.c == 5.0);
  CHECK(in.phi == 30.0);
  CHECK(in.psi == 10.0);
  CHECK(in.substeps == 7);
  CHECK_FALSE(in.flag);
  CHECK(in.shape == Shape::sharp);
  CHECK(in.levels == std::vector<double>{50.0, 100.0});
  CHECK(in.inner.ocr == 2.0);
}

TEST_CASE("toolkit: a failed check is an Error located at the parameter it blames", "[plugins][toolkit]") {
  const auto d = declaration();
  Params p = valid();
  p.set("psi", 35.0, at(6));
  try {
    (void)d.read(p);
    FAIL("psi > phi was accepted");
  } catch (const Error& e) {
    CHECK(e.where().line == 6);
    CHECK(std::string(e.what()) == "s.toml:6:5 [materials.soil] the dilatancy angle psi = 35 must not exceed "
                                   "the friction angle phi = 30");
  }
  p = valid();
  p.set("flag", true, at(11));
  p.set("levels", std::vector<double>{}); // a default: no location
  CHECK_THROWS_WITH(d.read(p), "s.toml:11:5 [materials.soil] flag = true needs levels");
}

TEST_CASE("toolkit: history names carry their unit", "[output][toolkit]") {
  CHECK(history_names({{"p_c", "kPa"}, {"eps_v_p", "-"}}) ==
        std::vector<std::string>{"p_c [kPa]", "eps_v_p [-]"});
}

TEST_CASE("toolkit: K-G stiffness, projectors and principal stresses", "[toolkit]") {
  const double E = 1000.0, nu = 0.3;
  const double K = bulk_modulus(E, nu), G = shear_modulus(E, nu);
  CHECK(K == Approx(E / (3.0 * (1.0 - 2.0 * nu))));
  CHECK(G == Approx(E / (2.0 * (1.0 + nu))));
  // The two isotropic forms are one stiffness, and the compliance is its inverse.
  CHECK((stiffness_kg(K, G) - isotropic_stiffness(E, nu)).cwiseAbs().maxCoeff() < 1e-12 * E);
  CHECK((isotropic_compliance(E, nu) * isotropic_stiffness(E, nu) - Mat6::Identity()).cwiseAbs().maxCoeff() <
        1e-12);

  Vec6 s;
  s << -30.0, -10.0, -20.0, 4.0, 0.0, 0.0;
  CHECK((plasticity::deviatoric_projector() * s - plasticity::deviator(s)).cwiseAbs().maxCoeff() < 1e-12);
  // d J2 / d sigma = to_strain_like(deviator); its derivative is the strain-like projector.
  const Mat6 P = plasticity::deviatoric_projector_strain_like();
  for (int j = 0; j < 6; ++j) {
    Vec6 ds = Vec6::Zero();
    ds[j] = 1e-6;
    const Vec6 fd = (plasticity::to_strain_like(plasticity::deviator(s + ds)) -
                     plasticity::to_strain_like(plasticity::deviator(s - ds))) /
                    2e-6;
    CHECK((fd - P.col(j)).cwiseAbs().maxCoeff() < 1e-8);
  }

  // In-plane principal values: m -/+ sqrt(h^2 + t^2) with m = -20, h = -10, t = 4; s_zz = -20.
  const double r = std::sqrt(100.0 + 16.0);
  const Eigen::Vector3d v = principal_tension(s);
  CHECK(v[0] == Approx(-20.0 - r));
  CHECK(v[1] == Approx(-20.0));
  CHECK(v[2] == Approx(-20.0 + r));
  const Principal pc = principal_compression(s);
  CHECK(pc.s1 == Approx(20.0 + r));
  CHECK(pc.s3 == Approx(20.0 - r));
  // The 3D path (eigen-solver) agrees with the closed form once a tiny out-of-plane shear is added.
  Vec6 s3 = s;
  s3[4] = 1e-9;
  CHECK((principal_tension(s3) - v).cwiseAbs().maxCoeff() < 1e-8);
}

} // namespace test_toolkit
