// [units]: a scene declares its force and length units once (stratum/units.hpp). The same
// problem in kN, m and in N, mm gives the same numbers after conversion, defaults that plugins
// declare in kN, m, kPa convert, the labels of the results follow, bad units are located errors.
#include "output/pile_components.hpp"
#include "scene/toml_check.hpp"
#include "scene_helpers.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/point_driver.hpp"
#include "stratum/registry.hpp"
#include "stratum/units.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>
#include <unistd.h>
#include <vtkFieldData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace test_units {

namespace fs = std::filesystem;
using stratum::Error;
using stratum::Units;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string first_line(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  return line;
}

std::unique_ptr<stratum::Analysis> from_file(const std::string& relative) {
  stratum::RunOptions o;
  o.plugin_dirs = {STRATUM_PLUGIN_DIR};
  o.write_output = false;
  return stratum::Analysis::from_file(std::string(STRATUM_SOURCE_DIR) + "/" + relative, std::move(o));
}

/// The error message of building `toml` as a scene ("" when it builds).
std::string scene_error(const std::string& toml) {
  try {
    static_cast<void>(stratum::testing::scene(toml, stratum::testing::scene_path("units/square.toml")));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST_CASE("units: unit strings read as dimensions, convert and are spelt in the scene's units", "[units]") {
  const Units nmm("N", "mm");
  CHECK(nmm.stress() == "MPa");
  CHECK_FALSE(nmm.is_default());
  // 1 kPa = 1 kN/m2 = 1000 N / 1e6 mm2; 1 kN/m3 = 1000 N / 1e9 mm3; 1 m = 1000 mm.
  CHECK(*nmm.factor("kPa") == Approx(1e3 / 1e6).epsilon(1e-15));
  CHECK(*nmm.factor("kN/m3") == Approx(1e3 / 1e9).epsilon(1e-15));
  CHECK(*nmm.factor("m") == Approx(1e3).epsilon(1e-15));
  CHECK(*nmm.factor("kN") == Approx(1e3).epsilon(1e-15));
  CHECK(*nmm.factor("1/kPa") == Approx(1e6 / 1e3).epsilon(1e-15));
  CHECK(*nmm.factor("kPa/m") == Approx(1e3 / 1e9).epsilon(1e-15));
  CHECK(*nmm.factor("kN m") == Approx(1e3 * 1e3).epsilon(1e-15));
  CHECK(*nmm.factor("MPa") == Approx(1.0).epsilon(1e-15)); // a unit of another system converts too
  CHECK(*nmm.factor("deg") == 1.0);
  CHECK(*nmm.factor("-") == 1.0);
  CHECK_FALSE(nmm.factor("furlong").has_value());
  CHECK_FALSE(nmm.factor("- or kPa").has_value());

  CHECK(nmm.label("kPa") == "MPa");
  CHECK(nmm.label("kN/m3") == "N/mm3");
  CHECK(nmm.label("1/kPa") == "1/MPa");
  CHECK(nmm.label("kN m") == "N mm");
  CHECK(nmm.label("kPa/m") == "MPa/mm");
  CHECK(nmm.label("deg") == "deg");
  CHECK(nmm.column("load", "kN") == "load_N");
  CHECK(nmm.small_length() == "mm");
  CHECK(nmm.small_length_factor() == 1.0);

  // The named multiples of the pascal, and the spelt-out rest.
  CHECK(Units("kN", "m").stress() == "kPa");
  CHECK(Units("N", "m").stress() == "Pa");
  CHECK(Units("MN", "m").stress() == "MPa");
  CHECK(Units("kN", "mm").stress() == "GPa");
  const Units kncm("kN", "cm");
  CHECK(kncm.stress() == "kN/cm2");
  CHECK(*kncm.factor("kPa") == Approx(1.0 / 1e4).epsilon(1e-15));
  CHECK(kncm.label("1/kPa") == "1/(kN/cm2)");
  CHECK(kncm.column("p", "kPa") == "p_kN_per_cm2");
  CHECK(kncm.small_length() == "cm");

  // The default system leaves every label as it was.
  const Units d;
  CHECK(d.is_default());
  CHECK(d.column("load", "kN") == "load_kN");
  CHECK(d.label("kN/m3") == "kN/m3");
  CHECK(d.small_length() == "mm");
  CHECK(d.small_length_factor() == 1e3);

  REQUIRE_THROWS_AS(Units("kn", "m"), Error);
  try {
    static_cast<void>(Units("kn", "m"));
  } catch (const Error& e) {
    CHECK_THAT(e.what(), Catch::Contains("allowed: N, kN, MN") && Catch::Contains("did you mean 'kN'"));
  }
}

TEST_CASE("units: a time unit converts durations and permeabilities, nothing else", "[units][groundwater]") {
  const Units days("kN", "m", "day");
  CHECK_FALSE(days.is_default());
  CHECK(days.time() == "day");
  CHECK(*days.factor("s") == Approx(1.0 / 86400.0).epsilon(1e-15)); // a duration
  CHECK(*days.factor("m/s") == Approx(86400.0).epsilon(1e-15));     // a permeability: m/s to m/day
  CHECK(*days.factor("kPa") == 1.0);                                // force and length as they were
  CHECK(*days.factor("kN/m3") == 1.0);
  CHECK(*days.factor("s (wall clock)") == 1.0); // progress tables: the program's seconds
  CHECK(days.label("m/s") == "m/day");
  CHECK(days.label("s") == "day");
  CHECK(days.describe() == "kN, m, kPa, day");
  CHECK(*Units("N", "mm", "h").factor("m/s") == Approx(1e3 * 3600.0).epsilon(1e-15));
  CHECK(*Units("kN", "m", "min").factor("s") == Approx(1.0 / 60.0).epsilon(1e-15));
  CHECK(Units("kN", "m", "s").is_default());
  try {
    static_cast<void>(Units("kN", "m", "days"));
    FAIL("a time unit that is not allowed");
  } catch (const Error& e) {
    CHECK_THAT(e.what(), Catch::Contains("allowed: s, min, h, day") && Catch::Contains("did you mean 'day'"));
  }
}

TEST_CASE("units: Terzaghi's column with [units] time = \"day\" gives the run in seconds",
          "[units][groundwater]") {
  // inputs/verification/terzaghi.toml as it is (seconds, k in m/s) and with its duration and
  // permeability written in days: the same settlement and base pressure at the end, and the
  // global recorder's time in days.
  const std::string path = stratum::testing::source_path("inputs/verification/terzaghi.toml");
  const std::string full = stratum::testing::read_text(path);
  const std::string text = full.substr(0, full.find("\n[[checks]]")); // its checks are in seconds
  const std::string in_days = stratum::testing::replace_once(
      stratum::testing::replace_once(
          stratum::testing::replace_once(text, "permeability = 1.0e-8 ", "permeability = 8.64e-4 "),
          "duration = 1489350.6493506494", "duration = 17.23785473785474"),
      "[analysis]", "[units]\ntime = \"day\"\n\n[analysis]");
  auto run = [&](const std::string& toml) {
    stratum::RunOptions o;
    o.plugin_dirs = {STRATUM_PLUGIN_DIR};
    o.write_output = false;
    auto a = stratum::Analysis::from_string(toml, path, std::move(o));
    const stratum::RunSummary s = a->run();
    REQUIRE(s.outcome.ok());
    const stratum::Model& m = a->model();
    const int base = stratum::testing::node_at(m, 0.0, 0.0), top = stratum::testing::node_at(m, 0.0, 10.0);
    return std::array<double, 3>{m.u[m.dofs.dof(base, m.dofs.field("p"))],
                                 m.u[m.dofs.dof(top, stratum::field_uy)], m.clock.total_time};
  };
  const auto s = run(text), d = run(in_days);
  CHECK(d[0] == Approx(s[0]).epsilon(1e-9));
  CHECK(d[1] == Approx(s[1]).epsilon(1e-9));
  CHECK((d[2] - 1.0) * 86400.0 == Approx(s[2] - 1.0).epsilon(1e-9)); // the time within the stage, in days
  // A misspelt time unit is one located line.
  const std::string bad = stratum::testing::replace_once(in_days, "time = \"day\"", "time = \"days\"");
  CHECK_THAT(stratum::testing::build_error(bad, path),
             Catch::Contains("terzaghi.toml:") && Catch::Contains("did you mean 'day'"));
}

TEST_CASE("units: the Lamé cylinder in kN, m and in N, mm agrees after conversion and with the closed form",
          "[units]") {
  auto m_scene = from_file("inputs/verification/lame_axisymmetric.toml");
  auto mm_scene = from_file("inputs/verification/lame_axisymmetric_n_mm.toml");
  CHECK(mm_scene->units().describe() == "N, mm, MPa");
  REQUIRE(m_scene->run().outcome.ok());
  REQUIRE(mm_scene->run().outcome.ok());
  const auto& a = m_scene->model();
  const auto& b = mm_scene->model();
  REQUIRE(a.mesh.nodes.size() == b.mesh.nodes.size());
  // Lengths: 1 m = 1000 mm; stresses: 1 kPa = 1e-3 MPa; forces: 1 kN = 1000 N.
  double umax = 0.0, du = 0.0;
  for (std::size_t n = 0; n < a.mesh.nodes.size(); ++n) {
    CHECK(std::abs(b.mesh.nodes[n].x() - 1e3 * a.mesh.nodes[n].x()) <= 1e-9);
    for (int c = 0; c < 2; ++c) {
      const auto d = static_cast<Eigen::Index>(2 * n + static_cast<std::size_t>(c));
      umax = std::max(umax, std::abs(1e3 * a.u[d]));
      du = std::max(du, std::abs(b.u[d] - 1e3 * a.u[d]));
    }
  }
  CHECK(du <= 1e-10 * umax);
  double rmax = 0.0, dr = 0.0;
  for (Eigen::Index d = 0; d < a.reactions.size(); ++d) {
    rmax = std::max(rmax, std::abs(1e3 * a.reactions[d]));
    dr = std::max(dr, std::abs(b.reactions[d] - 1e3 * a.reactions[d]));
  }
  CHECK(dr <= 1e-10 * rmax);
  const auto& sa = a.domains[0].states;
  const auto& sb = b.domains[0].states;
  REQUIRE(sa.points() == sb.points());
  double smax = 0.0, ds = 0.0;
  for (std::size_t p = 0; p < sa.points(); ++p)
    for (int i = 0; i < 6; ++i) {
      smax = std::max(smax, std::abs(1e-3 * sa.committed(p).stress()[i]));
      ds = std::max(ds, std::abs(sb.committed(p).stress()[i] - 1e-3 * sa.committed(p).stress()[i]));
    }
  CHECK(ds <= 1e-10 * smax);
  // The closed form u(a) = (1 + nu) p a^2 / (E (b^2 - a^2)) [(1 - 2 nu) a + b^2 / a], in mm from
  // the N, mm data (quad8, 8 x 2 cells: within 1e-5).
  const double nu = 0.3, p = 0.001, E = 1.0, ra = 1000.0, rb = 2000.0;
  const double exact =
      (1 + nu) * p * ra * ra / (E * (rb * rb - ra * ra)) * ((1 - 2 * nu) * ra + rb * rb / ra);
  const int inner = stratum::testing::node_at(b, ra, 0.0);
  CHECK(stratum::testing::rel(b.u[2 * inner], exact) < 1e-5);
}

TEST_CASE("units: defaults declared in kN, m, kPa convert into the scene's units", "[units]") {
  stratum::PluginCatalog catalog({STRATUM_PLUGIN_DIR});
  stratum::Registry reg;
  catalog.require(reg, stratum::PluginKind::material, "duncan_chang");
  catalog.require(reg, stratum::PluginKind::material, "hardening_soil");
  catalog.require(reg, stratum::PluginKind::contact_law, "hyperbolic_interface");
  const Units nmm("N", "mm");
  const auto dc_table = toml::parse("K = 300.0\nn = 0.5\nR_f = 0.8\nphi = 30.0\nc = 0.01\nK_ur = 600.0\n");
  // p_a = 100 kPa = 100 kN/m2 = 100 * 1000 N / (1000 mm)^2 = 0.1 N/mm2.
  const double p_a = 100.0 * 1000.0 / (1000.0 * 1000.0);
  {
    const auto p =
        stratum::io::check_table(dc_table, reg.material("duncan_chang").schema, "[materials.s]", {}, nmm);
    CHECK(p.real("p_a") == Approx(p_a).epsilon(1e-14));
    CHECK(p.real_list("c").at(0) == 0.01); // a value the scene writes is in its units already
    CHECK(stratum::units_of(p) == nmm);
    const auto q = stratum::io::check_table(dc_table, reg.material("duncan_chang").schema, "[materials.s]");
    CHECK(q.real("p_a") == 100.0); // kN, m: as declared
    CHECK(stratum::units_of(q).is_default());
  }
  {
    const auto t = toml::parse("E50_ref = 20.0\nEoed_ref = 20.0\nEur_ref = 60.0\nphi = 30.0\n");
    const auto p =
        stratum::io::check_table(t, reg.material("hardening_soil").schema, "[materials.s]", {}, nmm);
    CHECK(p.real("p_ref") == Approx(p_a).epsilon(1e-14));
  }
  {
    // gamma_w = 9.81 kN/m3 = 9.81 * 1000 N / (1000 mm)^3; k_n = 1e6 kPa/m = 1e6 * 1000 N / (1000 mm)^3.
    const auto t = toml::parse("K_I = 1000.0\ndelta = 25.0\n");
    const auto& schema = reg.contact_law("hyperbolic_interface").schema;
    std::string why;
    try {
      const auto p = stratum::io::check_table(t, schema, "[contact_laws.i]", {}, nmm);
      CHECK(p.real("gamma_w") == Approx(9.81 * 1e3 / 1e9).epsilon(1e-14));
      CHECK(p.real("k_n") == Approx(1e6 * 1e3 / 1e9).epsilon(1e-14));
    } catch (const Error& e) {
      why = e.what();
    }
    CHECK(why == "");
  }
  {
    // "-1: none" flags (a negative default that is its own lower bound) stay flags: Mohr-Coulomb's
    // tension = -1 is "no cut-off" in any units, and -1 may still be written.
    catalog.require(reg, stratum::PluginKind::material, "mohr_coulomb");
    const auto& schema = reg.material("mohr_coulomb").schema;
    const auto p = stratum::io::check_table(toml::parse("E = 20.0\nc = 0.01\nphi = 30.0\n"), schema,
                                            "[materials.s]", {}, nmm);
    CHECK(p.real("tension") == -1.0);
    const auto q = stratum::io::check_table(toml::parse("E = 20.0\nc = 0.01\nphi = 30.0\ntension = -1.0\n"),
                                            schema, "[materials.s]", {}, nmm);
    CHECK(q.real("tension") == -1.0);
  }
  {
    // The range bounds convert too: sigma_n_floor-like bounds in kPa read in MPa.
    stratum::Schema s;
    s.real("p", "kPa", "a pressure").at_most(200.0).defaults_to(100.0);
    const auto ok = stratum::io::check_table(toml::parse("p = 0.15\n"), s, "[t]", {}, nmm);
    CHECK(ok.real("p") == 0.15);
    CHECK_THROWS_WITH(stratum::io::check_table(toml::parse("p = 150.0\n"), s, "[t]", {}, nmm),
                      Catch::Contains("is outside (-inf, 0.2]"));
    // A default whose unit cannot be read is refused rather than used unconverted.
    stratum::Schema odd;
    odd.real("w", "furlong", "a length in an odd unit").defaults_to(3.0);
    CHECK_THROWS_WITH(stratum::io::check_table(toml::parse(""), odd, "[t]", {}, nmm),
                      Catch::Contains("cannot be converted to [units] N, mm, MPa") &&
                          Catch::Contains("allowed: give w in the table"));
  }
}

TEST_CASE(
    "units: a bad unit, a stress that does not follow and a plugin that cannot follow are located errors",
    "[units]") {
  // tests/scenes/units/square.toml, read as text: each case appends a [units] table to it, so its
  // keys are on the lines after the file's last line n.
  const std::string square = stratum::testing::scene_path("units/square.toml");
  const std::string base = stratum::testing::read_text(square);
  const auto n = std::count(base.begin(), base.end(), '\n');
  const auto at = [&](long line, int column) {
    return square + ":" + std::to_string(n + line) + ":" + std::to_string(column) + " ";
  };
  const std::string bad_force = scene_error(base + "[units]\nforce = \"kn\"\n");
  CHECK_THAT(bad_force,
             Catch::StartsWith(at(2, 9) + "[units] force = \"kn\" is not allowed; allowed: one of: "
                                          "N, kN, MN; did you mean 'kN'?"));
  const std::string bad_length = scene_error(base + "[units]\nlength = \"inch\"\n");
  CHECK_THAT(bad_length, Catch::StartsWith(at(2, 10) + "[units] length = \"inch\" is not allowed; allowed: "
                                                       "one of: mm, cm, m"));
  const std::string bad_stress =
      scene_error(base + "[units]\nforce = \"N\"\nlength = \"mm\"\nstress = \"kPa\"\n");
  CHECK_THAT(bad_stress, Catch::StartsWith(at(4, 10) + "[units] stress = \"kPa\" does not follow") &&
                             Catch::Contains("allowed: MPa, N/mm2"));
  CHECK(scene_error(base + "[units]\nforce = \"N\"\nlength = \"mm\"\nstress = \"N/mm2\"\n") == "");
  const std::string bad_key = scene_error(base + "[units]\nlenght = \"mm\"\n");
  CHECK_THAT(bad_key, Catch::Contains("did you mean 'length'?"));
  // A UMAT is compiled code: in N, mm it is refused (located at the [units] declaration) unless
  // the user vouches for it with any_units = true.
  const std::string elastic = "model = \"linear_elastic\"\nE = 1.0";
  std::string umat = base + "[units]\nforce = \"N\"\nlength = \"mm\"\n";
  umat.replace(umat.find(elastic), elastic.size(), "model = \"umat\"\nlibrary = \"no_such_library.so\"");
  CHECK_THAT(scene_error(umat), Catch::StartsWith(at(2, 9) + "[materials.m] cannot compute in [units] N, "
                                                             "mm, MPa: a UMAT is compiled code"));
  std::string vouched = umat;
  vouched.replace(vouched.find("library ="), 0, "any_units = true\n");
  CHECK_THAT(scene_error(vouched), Catch::Contains("no_such_library.so") && !Catch::Contains("[units]"));
}

TEST_CASE("units: the labels of the results follow the scene's units", "[units][cli]") {
  // The pile's CSV headers.
  CHECK(stratum::PileComponents::header(Units()) ==
        "load_kN,head_mm,pile_shortening_mm,base_mm,shaft_slip_mean_mm,shaft_slip_top_mm,shaft_load_kN,"
        "base_load_kN");
  CHECK(stratum::PileComponents::header(Units("N", "mm")) ==
        "load_N,head_mm,pile_shortening_mm,base_mm,shaft_slip_mean_mm,shaft_slip_top_mm,shaft_load_N,"
        "base_load_N");
  CHECK(stratum::PileComponents::header(Units("MN", "cm")) ==
        "load_MN,head_cm,pile_shortening_cm,base_cm,shaft_slip_mean_cm,shaft_slip_top_cm,shaft_load_MN,"
        "base_load_MN");

  const fs::path dir = fs::temp_directory_path() / ("stratum_units_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The point driver's table: p and q in the point file's stress unit.
  const std::string point = R"([units]
force = "N"
length = "mm"
[material]
model = "linear_elastic"
E = 10.0
nu = 0.25
[initial]
p = 0.1
[[paths]]
type = "isotropic"
pressure = 0.05
steps = 2
)";
  {
    auto d = stratum::PointDriver::from_string(point, "point.toml", {STRATUM_PLUGIN_DIR});
    const auto run = d->run();
    REQUIRE(run.outcome.ok());
    stratum::PointDriver::write_csv(run, (dir / "nmm.csv").string());
    const std::string h = first_line(dir / "nmm.csv");
    CHECK_THAT(h, Catch::EndsWith(",eps_axial,eps_vol,p_MPa,q_MPa"));
    auto k = stratum::PointDriver::from_string(point.substr(point.find("[material]")), "point.toml",
                                               {STRATUM_PLUGIN_DIR});
    stratum::PointDriver::write_csv(k->run(), (dir / "knm.csv").string());
    CHECK_THAT(first_line(dir / "knm.csv"), Catch::EndsWith(",eps_axial,eps_vol,p_kPa,q_kPa"));
  }
  // A run in N, mm: the check lines name the unit, the VTK field data carries the units.
  const std::string scene =
      std::string(STRATUM_SOURCE_DIR) + "/inputs/verification/lame_axisymmetric_n_mm.toml";
  const fs::path out = dir / "run";
  const std::string cmd = std::string("STRATUM_PLUGIN_PATH= ") + STRATUM_EXE + " run " + scene + " --out " +
                          out.string() + " > " + (dir / "log").string() + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const std::string log = read_text(dir / "log");
  CHECK_THAT(log, Catch::Contains("check inner.ux [mm] = 1.9066") && Catch::Contains(": pass"));
  auto r = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  r->SetFileName((out / "lame_axisymmetric_n_mm_1.vtu").string().c_str());
  r->Update();
  vtkFieldData* fd = r->GetOutput()->GetFieldData();
  REQUIRE(fd != nullptr);
  auto* units = vtkStringArray::SafeDownCast(fd->GetAbstractArray("units"));
  REQUIRE(units != nullptr);
  CHECK(units->GetValue(0) == "N, mm, MPa");
  // No pile head in Lame's scene: no head load or settlement in its field data, in any unit.
  CHECK(fd->GetAbstractArray("head_load_N") == nullptr);
  CHECK(fd->GetAbstractArray("head_load_kN") == nullptr);
  CHECK(fd->GetAbstractArray("head_settlement_mm") == nullptr);
  CHECK(fd->GetAbstractArray("load_factor") != nullptr);
  fs::remove_all(dir);
}

namespace {

/// An elastic pile in elastic soil, loaded at its head, with lengths in units of `L` m, forces in
/// units of `F` kN (kN, m: 1, 1; N, mm: 1e-3, 1e-3): every number of the scene is converted here.
std::string elastic_pile(double L, double F, const std::string& units) {
  const double S = F / (L * L); // stress unit in kPa
  std::ostringstream t;
  t.precision(17);
  t << units << "[analysis]\nformulation = \"axisymmetric\"\n[convergence]\nforce_rtol = 1e-12\n";
  t << "[mesh]\ngenerator = \"axisymmetric_pile\"\n[mesh.pile]\nradius = " << 0.25 / L
    << "\nlength = " << 3.0 / L << "\nnear_radius = " << 2.0 / L << "\nnear_depth = " << 4.5 / L
    << "\ndomain_radius = " << 6.0 / L << "\ndomain_depth = " << 9.0 / L
    << "\nn_shaft = 4\nn_near = 3\nn_far = 2\nn_below = 2\nn_deep = 1\n";
  t << "[materials.soil]\nmodel = \"linear_elastic\"\nE = " << 20000.0 / S << "\nnu = 0.3\n";
  t << "[materials.concrete]\nmodel = \"linear_elastic\"\nE = " << 3e7 / S << "\nnu = 0.2\n";
  for (const char* set : {"bore", "near", "far"})
    t << "[[domains]]\ncells = \"" << set << "\"\nelement = \"quad\"\nmaterial = \"soil\"\n";
  t << "[[domains]]\ncells = \"pile\"\nelement = \"quad\"\nmaterial = \"concrete\"\n";
  t << "[[constraints]]\nnodes = \"axis\"\nux = 0.0\n[[constraints]]\nnodes = \"far_side\"\nux = 0.0\n";
  t << "[[constraints]]\nnodes = \"bottom\"\nux = 0.0\nuy = 0.0\n";
  t << "[output]\nvtk = false\npile_cells = \"pile\"\n";
  t << "[[stages]]\nname = \"loading\"\nsteps = 2\ncheckpoint = false\n[[stages.actions]]\ntype = \"load\"\n"
       "cells = \"pile\"\nforce = "
    << 100.0 / F << "\n";
  return t.str();
}

std::vector<std::vector<double>> rows_of(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) r.push_back(std::stod(cell));
    rows.push_back(r);
  }
  return rows;
}

} // namespace

TEST_CASE("units: an elastic pile in kN, m and in N, mm writes the same curves, labelled in its units",
          "[units][pile]") {
  const fs::path dir = fs::temp_directory_path() / ("stratum_units_pile_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  auto run = [&](const std::string& text, const std::string& name) {
    stratum::RunOptions o;
    o.plugin_dirs = {STRATUM_PLUGIN_DIR};
    o.out_dir = (dir / name).string();
    auto a = stratum::Analysis::from_string(text, name + ".toml", std::move(o));
    const auto r = a->run();
    INFO(r.outcome.message);
    REQUIRE(r.outcome.ok());
    return dir / name / "curves";
  };
  const fs::path m = run(elastic_pile(1.0, 1.0, ""), "kn_m");
  const fs::path mm = run(elastic_pile(1e-3, 1e-3, "[units]\nforce = \"N\"\nlength = \"mm\"\n"), "n_mm");
  CHECK(first_line(m / "load_settlement.csv") == "load_kN,settlement_mm");
  CHECK(first_line(mm / "load_settlement.csv") == "load_N,settlement_mm");
  CHECK(first_line(m / "axial_force.csv") == "load_kN,depth_m,axial_force_kN");
  CHECK(first_line(mm / "axial_force.csv") == "load_N,depth_mm,axial_force_N");
  CHECK(first_line(mm / "settlement_components.csv") ==
        "load_N,head_mm,pile_shortening_mm,base_mm,shaft_slip_mean_mm,shaft_slip_top_mm,shaft_load_N,base_"
        "load_N");
  // The same numbers after conversion: loads x 1000 (kN -> N), settlements in mm in both (m:
  // tabulated x 1000; mm: as computed), depths x 1000, axial forces x 1000.
  const auto a = rows_of(m / "load_settlement.csv"), b = rows_of(mm / "load_settlement.csv");
  REQUIRE(a.size() == 3);
  REQUIRE(b.size() == a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(std::abs(b[i][0] - 1e3 * a[i][0]) <= 1e-10 * 1e3 * 100.0);
    CHECK(std::abs(b[i][1] - a[i][1]) <= 1e-10 * std::abs(a.back()[1]));
  }
  CHECK(a.back()[1] > 0.1); // the pile settles (mm)
  const auto fa = rows_of(m / "axial_force.csv"), fb = rows_of(mm / "axial_force.csv");
  REQUIRE(fa.size() == fb.size());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    CHECK(std::abs(fb[i][1] - 1e3 * fa[i][1]) <= 1e-9);
    CHECK(std::abs(fb[i][2] - 1e3 * fa[i][2]) <= 1e-10 * 1e3 * 100.0);
  }
  fs::remove_all(dir);
}

TEST_CASE("an integer beyond 2^53 where a number is expected is a value, not an internal error", "[units]") {
  // Found by fuzz_scene (tests/fuzz/corpus/fuzz_scene/finding_integer_beyond_double.toml): toml++
  // gives no double for an integer it cannot hold exactly, and the reader asked for one anyway.
  stratum::Schema s;
  s.real("m", "-", "a number").greater_than(0.0).less_than(10.0);
  s.real_list("k", "-", "numbers").greater_than(0.0).less_than(10.0);
  CHECK_THROWS_WITH(stratum::io::check_table(toml::parse("m = 9223372036854775807\nk = 1.0"), s, "[t]"),
                    Catch::Contains("m = 9223372036854775807 is outside (0, 10)"));
  CHECK_THROWS_WITH(
      stratum::io::check_table(toml::parse("m = 1.0\nk = [1.0, 9223372036854775807]"), s, "[t]"),
      Catch::Contains("k contains 9223372036854775807, outside (0, 10)"));
  CHECK(stratum::io::number(*toml::parse("x = 9007199254740993")["x"].node()) == 9007199254740992.0);
}

} // namespace test_units
