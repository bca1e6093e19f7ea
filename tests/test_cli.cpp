// The program as a user runs it: bad input gives one line with file:line:col,
// what is wrong and what is allowed, and a non-zero exit code.
#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace test_cli {

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string out, err;
};

fs::path scratch() {
  static const fs::path dir = fs::temp_directory_path() / ("stratum_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

/// Runs stratum with the build tree's plugins; captures stdout and stderr separately.
Result stratum(const std::string& args, const std::string& env = "") {
  const fs::path out = scratch() / "stdout.txt", err = scratch() / "stderr.txt";
  const std::string cmd = "cd " + scratch().string() + " && " + env + " STRATUM_PLUGIN_PATH= " + STRATUM_EXE +
                          " " + args + " >" + out.string() + " 2>" + err.string();
  Result r;
  const int status = std::system(cmd.c_str());
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::string write_scene(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p.string();
}

// tests/scenes/cli/ring.toml; the tests write it (or a variant with one line replaced) to the scratch
// folder, and the located errors count the lines of that file.
const std::string good = [] {
  std::ifstream in(fs::path(STRATUM_SOURCE_DIR) / "tests" / "scenes" / "cli" / "ring.toml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}();

/// The scene with one line replaced.
std::string edit(const std::string& from, const std::string& to) {
  std::string s = good;
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

void expect_one_line_error(const Result& r, const std::string& location, const std::string& text) {
  INFO("stderr: " << r.err);
  CHECK(r.code != 0);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.rfind("stratum: " + location, 0) == 0);
  CHECK(r.err.find(text) != std::string::npos);
}

} // namespace

TEST_CASE("cli: --version and plugins listing", "[cli]") {
  auto v = stratum("--version");
  CHECK(v.code == 0);
  CHECK(v.out.rfind("stratum 0.", 0) == 0);

  auto p = stratum("plugins --describe");
  INFO(p.err);
  REQUIRE(p.code == 0);
  CHECK(p.out.find("element quad:") != std::string::npos);
  CHECK(p.out.find("material linear_elastic:") != std::string::npos);
  CHECK(p.out.find("solver newton:") != std::string::npos);
  // Parameters with unit, range and default are listed.
  CHECK(std::regex_search(p.out, std::regex(R"(\n  nu +number +- +\(-1, 0\.5\))")));
  CHECK(std::regex_search(p.out, std::regex(R"(\n  E +number +kPa +\(0, inf\), required)")));
  CHECK(std::regex_search(p.out, std::regex(R"(\n  integration +integer +- +\[2, 4\], default 3)")));

  auto d = stratum("plugins --describe quad");
  CHECK(d.code == 0);
  CHECK(d.out.find("library: ") != std::string::npos);
  CHECK(d.out.find("volumetric") != std::string::npos);
  // The unknowns an element's nodes carry, by field name and unit, per cell type it takes.
  CHECK(d.out.find("\n    quadrilateral: ux [m; reaction kN], uy [m; reaction kN]\n") != std::string::npos);
  CHECK(d.out.find("hexahedron") == std::string::npos);
  const auto hex = stratum("plugins --describe hex8");
  CHECK(hex.out.find("\n    hexahedron: ux [m; reaction kN], uy [m; reaction kN], uz [m; reaction kN]\n") !=
        std::string::npos);
  // A default the plugin computes is described as such (997ba04 printed F_CUT "default 1").
  auto cap = stratum("plugins --describe cap_sandler");
  CHECK(std::regex_search(
      cap.out, std::regex(R"(\n  F_CUT +number +kPa +\(0, inf\), default ln\(A/C\)/B, computed)")));
  auto hs = stratum("plugins --describe hardening_soil");
  CHECK(std::regex_search(hs.out, std::regex(R"(\n  K0_nc +number +- +\(0, 1\), default 1 - sin phi)")));
  // A name that is two plugins shows both: the duncan_chang material and its calibration target.
  auto dc = stratum("plugins --describe duncan_chang");
  CHECK(dc.code == 0);
  CHECK(dc.out.rfind("material duncan_chang: ", 0) == 0);
  CHECK(dc.out.find("\n\ncalibration duncan_chang: ") != std::string::npos);
  CHECK(std::regex_search(dc.out, std::regex(R"(\n  form +string)")));
  auto u = stratum("plugins --describe nosuch");
  expect_one_line_error(u, "", "unknown plugin 'nosuch'; known: ");
  CHECK(u.err.find("did you mean") == std::string::npos); // nothing is near "nosuch"
  auto m = stratum("plugins --describe linear_elastik");
  expect_one_line_error(m, "", "unknown plugin 'linear_elastik'; known: ");
  CHECK(m.err.find("; did you mean 'linear_elastic'?") != std::string::npos);
}

TEST_CASE("cli: the short plugin list has one line per plugin, --all the full listing", "[cli]") {
  const auto full = stratum("plugins --describe");
  REQUIRE(full.code == 0);
  CHECK(stratum("plugins --all").out == full.out);
  // In the full listing every plugin starts a line at column 0 ("kind name: summary"); its
  // parameters are indented.
  int plugins = 0;
  std::istringstream in(full.out);
  for (std::string l; std::getline(in, l);) plugins += !l.empty() && l[0] != ' ';
  REQUIRE(plugins > 10);
  const auto s = stratum("plugins");
  INFO(s.err);
  REQUIRE(s.code == 0);
  CHECK(lines(s.out) == plugins);
  CHECK(std::regex_search(s.out, std::regex(R"((^|\n)material +linear_elastic +\S)")));
  CHECK(std::regex_search(s.out, std::regex(R"((^|\n)element +quad +\S)")));
  CHECK(std::regex_search(s.out, std::regex(R"((^|\n)solver +newton +\S)")));
  expect_one_line_error(stratum("plugins --frobnicate"), "", "plugins: unexpected argument '--frobnicate'");
}

TEST_CASE("cli: --help on every subcommand prints usage, options and exit status and exits 0", "[cli]") {
  for (const std::string cmd : {"run", "check", "point", "fit", "sweep", "plugins", "describe"}) {
    for (const auto& form : {cmd + " --help", cmd + " -h", "help " + cmd}) {
      const auto h = stratum(form);
      INFO(form << "\nstdout: " << h.out << "\nstderr: " << h.err);
      CHECK(h.code == 0);
      CHECK(h.err.empty());
      CHECK(h.out.rfind("usage: stratum " + cmd, 0) == 0);
      CHECK(h.out.find("exit status: 0 ") != std::string::npos);
      CHECK(h.out.find("--help") != std::string::npos);
    }
  }
  // Also after other arguments, and the top-level usage names the per-command help.
  CHECK(stratum("point some.toml --help").code == 0);
  const auto top = stratum("--help");
  CHECK(top.code == 0);
  CHECK(top.out.find("stratum COMMAND --help") != std::string::npos);
  expect_one_line_error(stratum("help frobnicate"), "", "help: unknown command 'frobnicate'");
  expect_one_line_error(stratum("rnu x.toml"), "", "unknown command 'rnu'");
  CHECK(stratum("rnu x.toml").err.find("did you mean 'run'?") != std::string::npos);
}

TEST_CASE("cli: did you mean: misspelt keys, plugins and sets", "[cli]") {
  // nu written nuu: one edit away from nu.
  const auto p1 = write_scene("dym_nuu.toml", edit("nu = 0.3", "nuu = 0.3"));
  expect_one_line_error(stratum("check " + p1), p1 + ":23:1 ",
                        "[materials.soil] unknown key 'nuu'; allowed: model, ");
  CHECK(stratum("check " + p1).err.find("; did you mean 'nu'?\n") != std::string::npos);
  // A key with nothing near gets no suggestion.
  const auto p2 = write_scene("dym_none.toml", edit("nu = 0.3", "nu = 0.3\nporosity = 0.4"));
  const auto r2 = stratum("check " + p2);
  expect_one_line_error(r2, p2 + ":24:1 ", "unknown key 'porosity'");
  CHECK(r2.err.find("did you mean") == std::string::npos);
  // sigma_y written sigma_yy in a von Mises material.
  const auto p3 =
      write_scene("dym_sigma.toml", edit("model = \"linear_elastic\"\nE = 1000.0\nnu = 0.3",
                                         "model = \"von_mises\"\nE = 1000.0\nnu = 0.3\nsigma_yy = 50.0"));
  const auto r3 = stratum("check " + p3);
  expect_one_line_error(r3, p3 + ":24:1 ", "unknown key 'sigma_yy'");
  CHECK(r3.err.find("; did you mean 'sigma_y'?") != std::string::npos);
  // A misspelt plugin name.
  const auto p4 =
      write_scene("dym_plugin.toml", edit("model = \"linear_elastic\"", "model = \"linear_elastc\""));
  const auto r4 = stratum("check " + p4);
  expect_one_line_error(r4, p4 + ":21:9 ", "unknown material 'linear_elastc'; known: ");
  CHECK(r4.err.find("; did you mean 'linear_elastic'?") != std::string::npos);
  // A misspelt set name and a misspelt top-level table.
  const auto p5 = write_scene("dym_set.toml", edit("edges = \"ring.left\"", "edges = \"ring.lfet\""));
  const auto r5 = stratum("check " + p5);
  expect_one_line_error(r5, p5 + ":36:9 ", "edges = \"ring.lfet\" is not an edge set of the mesh; known: ");
  CHECK(r5.err.find("; did you mean 'ring.left'?") != std::string::npos);
  const auto p6 = write_scene(
      "dym_top.toml", edit("[[constraints]]\nnodes = \"bottom\"", "[[constraint]]\nnodes = \"bottom\""));
  const auto r6 = stratum("check " + p6);
  expect_one_line_error(r6, p6 + ":", "unknown key 'constraint' at the top level");
  CHECK(r6.err.find("; did you mean 'constraints'?") != std::string::npos);
  // A misspelt option.
  const auto r7 = stratum("run " + p1 + " --quite");
  expect_one_line_error(r7, "", "unknown option '--quite'");
  CHECK(r7.err.find("did you mean '--quiet'?") != std::string::npos);
}

TEST_CASE("cli: --quiet prints nothing on a good run, progress lines when stderr is not a terminal",
          "[cli]") {
  const auto path = write_scene("quiet.toml", good);
  const auto q = stratum("run " + path + " --quiet --out " + (scratch() / "quiet").string());
  INFO(q.err);
  CHECK(q.code == 0);
  CHECK(q.out.empty());
  CHECK(q.err.empty());
  CHECK(fs::exists(scratch() / "quiet" / "quiet.pvd"));
  const auto c = stratum("check " + path + " --quiet");
  CHECK(c.code == 0);
  CHECK(c.out.empty());
  CHECK(c.err.empty());
  // stderr is a file here: with --progress-every 0 a line per step, with the stage (a scene
  // without stages runs one stage named "load"), step, load factor, iterations and elapsed time;
  // stdout keeps its summary.
  const auto p = stratum("run " + path + " --progress-every 0 --out " + (scratch() / "progress").string());
  INFO(p.err);
  CHECK(p.code == 0);
  CHECK(p.out.find("done: ") != std::string::npos);
  CHECK(std::regex_search(
      p.err,
      std::regex(
          R"(^progress: stage 1/1 "load"  step 1/\d+  load factor [0-9.]+  iterations \d+  elapsed [0-9.]+ s)")));
  CHECK(p.err.find("\r") == std::string::npos);
  expect_one_line_error(stratum("run " + path + " --progress-every soon"), "",
                        "--progress-every needs a number of seconds >= 0");
  expect_one_line_error(stratum("run " + path + " --quiet --verbose"), "", "--verbose and --quiet exclude");
}

TEST_CASE("cli: check and run a good scene", "[cli]") {
  const auto path = write_scene("good.toml", good);
  auto c = stratum("check " + path);
  INFO(c.err);
  CHECK(c.code == 0);
  CHECK(c.out.find(": ok (") != std::string::npos);
  CHECK(c.out.find("3 plugin libraries") != std::string::npos);
  auto r = stratum("run " + path + " --out " + (scratch() / "out").string());
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(r.out.find("results: ") != std::string::npos);
  CHECK(fs::exists(scratch() / "out" / "good.pvd"));
  CHECK(fs::exists(scratch() / "out" / "good_1.vtu"));
}

TEST_CASE("cli: unknown key", "[cli]") {
  const auto path = write_scene("unknown_key.toml", edit("nu = 0.3", "nu = 0.3\nmu = 0.2"));
  expect_one_line_error(stratum("check " + path), path + ":24:1 ",
                        "[materials.soil] unknown key 'mu'; allowed: model, ");
}

TEST_CASE("cli: [output] pile_head is no longer a key: the pile head is the load action's", "[cli]") {
  // pile_head was declared and documented but never read (the head the curves follow is the set the
  // `load` action loads or pushes down), so `pile_head = "no_such_set"` was accepted; it is refused now
  // like any unknown key, located, with the keys [output] has.
  const auto path = write_scene("pile_head.toml", good + "[output]\npile_head = \"no_such_set\"\n");
  REQUIRE(lines(good) == 37);
  const auto r = stratum("check " + path);
  expect_one_line_error(r, path + ":39:1 ",
                        "[output] unknown key 'pile_head'; allowed: history, vtk, integration_points, every, "
                        "pile_cells, tables_every");
}

TEST_CASE("cli: a key that the scene sets but that has no effect is refused, located", "[cli]") {
  // `file` belongs to a Gmsh mesh; in a scene of generated blocks nothing reads it (the schema of
  // [mesh] declares it, so the key check alone accepted it and the run ignored it).
  const std::string text = edit("nodes_per_cell = 8\n", "nodes_per_cell = 8\nfile = \"left_over.msh\"\n");
  const auto path = write_scene("no_effect.toml", text);
  const auto line = std::to_string(1 + std::count(text.begin(), text.begin() + text.find("file = "), '\n'));
  expect_one_line_error(stratum("check " + path), path + ":" + line + ":8 ",
                        "[mesh] file has no effect in this scene (the reader of the table does not use it "
                        "here); remove it");
}

TEST_CASE("cli: wrong type", "[cli]") {
  const auto path = write_scene("wrong_type.toml", edit("E = 1000.0", "E = \"stiff\""));
  expect_one_line_error(stratum("check " + path), path + ":22:5 ",
                        "[materials.soil] E = \"stiff\" has the wrong type: expected a number, got a string");
}

TEST_CASE("cli: nu out of range", "[cli]") {
  const auto path = write_scene("nu_range.toml", edit("nu = 0.3", "nu = 0.7"));
  expect_one_line_error(stratum("run " + path), path + ":23:6 ", "[materials.soil] nu = 0.7 is outside (");
}

TEST_CASE("cli: unknown plugin name lists the known names", "[cli]") {
  const auto path =
      write_scene("unknown_plugin.toml", edit("model = \"linear_elastic\"", "model = \"elastik\""));
  const auto r = stratum("check " + path);
  expect_one_line_error(r, path + ":21:9 ", "model = \"elastik\": unknown material 'elastik'; known: ");
  CHECK(r.err.find("linear_elastic") != std::string::npos);
}

TEST_CASE("cli: missing file", "[cli]") {
  expect_one_line_error(stratum("run /nonexistent/scene.toml"), "/nonexistent/scene.toml ",
                        "cannot open scene file '/nonexistent/scene.toml'");
}

TEST_CASE("cli: malformed TOML", "[cli]") {
  const auto path = write_scene("malformed.toml", edit("nx = 4", "nx = = 4"));
  expect_one_line_error(stratum("check " + path), path + ":18:", "malformed TOML: ");
}

TEST_CASE("cli: bad references and usage errors", "[cli]") {
  auto p1 = write_scene("bad_set.toml", edit("edges = \"ring.left\"", "edges = \"ring.inner\""));
  expect_one_line_error(stratum("check " + p1), p1 + ":36:9 ",
                        "edges = \"ring.inner\" is not an edge set of the mesh; known: ");
  auto p2 =
      write_scene("bad_choice.toml", edit("element = \"quad\"", "element = \"quad\"\nvolumetric = \"soft\""));
  expect_one_line_error(stratum("check " + p2), p2 + ":27:14 ",
                        "volumetric = \"soft\" is not allowed; allowed: one of: full, bbar, selective");
  expect_one_line_error(stratum("frobnicate"), "", "unknown command 'frobnicate'");
  expect_one_line_error(stratum("run"), "", "no scene file given");
}

TEST_CASE("cli: stratum point runs the examples and writes CSV, malformed point files fail in one line",
          "[cli]") {
  for (const std::string ex : {"elastic_paths", "mcc_undrained", "drained_triaxial_mcc"}) {
    const auto csv = (scratch() / (ex + ".csv")).string();
    auto r =
        stratum("point " + std::string(STRATUM_SOURCE_DIR) + "/inputs/point/" + ex + ".toml --out " + csv);
    INFO(ex << ": " << r.err);
    CHECK(r.code == 0);
    CHECK(r.out.find("results: " + csv) != std::string::npos);
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    CHECK(header.rfind("step,path,eps_xx", 0) == 0);
  }
  const auto bad = write_scene("bad_point.toml", "[material]\nmodel = \"linear_elastic\"\nE = -5.0\n"
                                                 "[[paths]]\ntype = \"oedometer\"\naxial_strain = -0.01\n");
  expect_one_line_error(stratum("point " + bad), bad + ":3:5 ", "[material] E = -5 is outside (0, inf)");
  expect_one_line_error(stratum("point /nonexistent/p.toml"), "/nonexistent/p.toml ",
                        "cannot open point file '/nonexistent/p.toml'");
  // --out that is a symlink or a device is refused and left as it was (997ba04 replaced both).
  const fs::path target = scratch() / "target.csv", link = scratch() / "link.csv";
  fs::remove(link);
  std::ofstream(target) << "kept\n";
  fs::create_symlink(target, link);
  const std::string ex = std::string(STRATUM_SOURCE_DIR) + "/inputs/point/elastic_paths.toml";
  auto r = stratum("point " + ex + " --out " + link.string());
  CHECK(r.code == 1);
  CHECK(r.err.find("exists and is not a regular file") != std::string::npos);
  CHECK(fs::is_symlink(link));
  auto d = stratum("point " + ex + " --out /dev/null");
  CHECK(d.code == 1);
  CHECK(fs::is_character_file("/dev/null"));
}

TEST_CASE("cli: SIGINT and SIGTERM end a run at its next step, write what was computed and exit 130 / 143",
          "[cli]") {
  // On 997ba04 a signal ended the run without a word, and diagnostics.csv and the curves, written
  // at the end, were lost. The Hardening Soil pile takes tens of seconds: interrupted after 2 s.
  for (const auto& [sig, code] : {std::pair<std::string, int>{"INT", 130}, {"TERM", 143}}) {
    const std::string name = sig; // clang 14: no structured binding in the lambda-free INFO below
    INFO("SIG" << name);
    const fs::path out = scratch() / ("interrupted_" + name);
    fs::remove_all(out);
    const fs::path err = scratch() / ("interrupted_" + name + ".err");
    const std::string cmd = "cd " + scratch().string() + " && timeout --preserve-status -s " + name +
                            " 2 env STRATUM_PLUGIN_PATH= " + STRATUM_EXE + " run " + STRATUM_SOURCE_DIR +
                            "/inputs/loess_pile/hardening_soil.toml --out " + out.string() +
                            " >/dev/null 2>" + err.string();
    const int status = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == code);
    std::ifstream e(err);
    std::stringstream text;
    text << e.rdbuf();
    INFO(text.str());
    CHECK(text.str().find("stratum: interrupted by SIG" + name + " in stage ") != std::string::npos);
    CHECK(fs::exists(out / "diagnostics.csv"));
    CHECK(fs::exists(out / "hardening_soil.pvd"));
    CHECK_FALSE(fs::exists(out / "diagnostics.csv.tmp"));
  }
}

TEST_CASE("cli: SIGINT ends a run of many cheap steps within its stage, with its curve and summary written",
          "[cli]") {
  // The same path as the case above on a scene whose steps take milliseconds (the elastic pile in
  // 4000 steps): the sanitizer build runs this one (tools/ci_sanitize), where a step of the
  // Hardening Soil pile takes many seconds.
  std::ifstream in(fs::path(STRATUM_SOURCE_DIR) / "inputs" / "examples" / "elastic_pile.toml");
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const auto at = text.find("steps = 8");
  REQUIRE(at != std::string::npos);
  text.replace(at, 9, "steps = 4000");
  const std::string scene = write_scene("long_elastic_pile.toml", text);
  const fs::path out = scratch() / "interrupted_long";
  fs::remove_all(out);
  const fs::path err = scratch() / "interrupted_long.err";
  const std::string cmd = "cd " + scratch().string() +
                          " && timeout --preserve-status -s INT 1 env STRATUM_PLUGIN_PATH= " + STRATUM_EXE +
                          " run " + scene + " --out " + out.string() + " >/dev/null 2>" + err.string();
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  std::ifstream e(err);
  std::stringstream msg;
  msg << e.rdbuf();
  INFO(msg.str());
  CHECK(msg.str().find("stratum: interrupted by SIGINT in stage ") != std::string::npos);
  const auto summary = toml::parse_file((out / "summary.toml").string());
  CHECK(summary["ended"].value_or(std::string()) == "stopped");
  CHECK(summary["stop_reason"].value_or(std::string()) == "interrupted");
  const auto steps = summary["steps_done"].value_or(int64_t{0});
  CHECK(steps >= 1);
  CHECK(steps < 4000);
  // The curve holds the start and every converged step.
  std::ifstream curve(out / "curves" / "load_settlement.csv");
  int lines = 0;
  for (std::string line; std::getline(curve, line);) ++lines;
  CHECK(lines == 1 + 1 + steps);
  CHECK(fs::exists(out / "diagnostics.csv"));
  CHECK_FALSE(fs::exists(out / "diagnostics.csv.tmp"));
}

TEST_CASE("an until_failure stage tells a collapse (exit 0) from a numerical stop (exit 4)",
          "[cli][stages]") {
  // Found on 997ba04: both ended with exit 0 and the same "stopped:" line. Hill's cylinder loaded
  // to 1.2 P_lim: with Newton and enough iterations the run stops as a collapse just below the
  // closed-form limit P_lim = (2 / sqrt 3) sigma_y ln 2 (the mesh is coarse: within 3 %).
  const std::string text = [] {
    std::ifstream in(fs::path(STRATUM_SOURCE_DIR) / "tests" / "scenes" / "cli" / "hill_to_collapse.toml");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }();
  REQUIRE(text.find("max_iterations = 30") != std::string::npos);
  const double p_lim = 2.0 / std::sqrt(3.0) * 2.4e5 * std::log(2.0), p_target = 230511.6;
  const auto collapse = stratum("run " + write_scene("hill_collapse.toml", text) + " --out hill_collapse");
  INFO(collapse.out << collapse.err);
  CHECK(collapse.code == 0);
  CHECK(collapse.out.find("\nstopped: collapse: ") != std::string::npos);
  // The last converged load factor, from diagnostics.csv (stage, step, accepted, lambda_n, lambda, ...).
  double last = 0.0;
  {
    std::ifstream d(scratch() / "hill_collapse" / "diagnostics.csv");
    std::string line;
    std::getline(d, line);
    const std::string head = line;
    while (std::getline(d, line)) {
      std::vector<std::string> f;
      std::stringstream ls(line);
      for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
      if (f.size() > 4 && f[2] == "1") last = std::stod(f[4]);
    }
    REQUIRE(head.rfind("stage,step,accepted,lambda_n,lambda", 0) == 0);
  }
  WARN("collapse at " << last * p_target / p_lim << " P_lim");
  CHECK(last * p_target / p_lim > 0.97);
  CHECK(last * p_target / p_lim < 1.0 + 1e-3);
  // The same scene with two iterations per step: the first plastic steps fail while the cylinder
  // is still nearly elastic (first yield at 0.54 P_lim): a numerical stop, exit 4, its own line.
  std::string two = text;
  two.replace(two.find("max_iterations = 30"), 19, "max_iterations = 2");
  two.replace(two.find("max_cutbacks = 8"), 16, "max_cutbacks = 1");
  const auto numerical = stratum("run " + write_scene("hill_numerical.toml", two) + " --out hill_numerical");
  INFO(numerical.out << numerical.err);
  CHECK(numerical.code == 4);
  CHECK(numerical.out.find("\nstopped: numerical failure: ") != std::string::npos);
  CHECK(numerical.out.find("this is not a collapse load") != std::string::npos);
  // A numerical stop keeps what was computed: the diagnostics are written.
  CHECK(fs::exists(scratch() / "hill_numerical" / "diagnostics.csv"));
  // summary.toml beside the results says how each run ended (output/write_summary.cpp).
  {
    const auto c = toml::parse_file((scratch() / "hill_collapse" / "summary.toml").string());
    CHECK(c["ended"].value_or(std::string()) == "stopped");
    CHECK(c["stop_reason"].value_or(std::string()) == "collapse");
    CHECK(c["status"].value_or(std::string()) == "ok");
    CHECK(c["stiffness_ratio"].value_or(1.0) < 0.1); // below the stage's collapse_stiffness
    const auto n = toml::parse_file((scratch() / "hill_numerical" / "summary.toml").string());
    CHECK(n["ended"].value_or(std::string()) == "stopped");
    CHECK(n["stop_reason"].value_or(std::string()) == "numerical");
    CHECK(n["stop_message"].value_or(std::string()).find("did not converge") != std::string::npos);
  }
  // Outside an until_failure stage the same failure ends the run as failed: exit 4, and the
  // summary names the status and the failed step.
  std::string failing = two;
  failing.replace(failing.find("until_failure = true"), 20, "until_failure = false");
  const auto failed = stratum("run " + write_scene("hill_failed.toml", failing) + " --out hill_failed");
  INFO(failed.out << failed.err);
  CHECK(failed.code != 0);
  const auto f = toml::parse_file((scratch() / "hill_failed" / "summary.toml").string());
  CHECK(f["ended"].value_or(std::string()) == "failed");
  CHECK(f["status"].value_or(std::string()) == "not converged");
  CHECK(f["message"].value_or(std::string()).find("stage") != std::string::npos);
  CHECK(f["stages_done"].value_or(-1) == 0);
}

TEST_CASE("recorders write the quantities asked for, and a scene's [[checks]] decide the exit status",
          "[cli][recorders]") {
  // The Lamé scene records u_r at r = a and r = b and checks them against the closed form
  // u(r) = (1 + nu) p a^2 / (E (b^2 - a^2)) [(1 - 2 nu) r + b^2 / r] (E1 of the catalogue).
  std::string text;
  {
    std::ifstream in(fs::path(STRATUM_SOURCE_DIR) / "inputs" / "verification" / "lame_axisymmetric.toml");
    std::stringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  const auto u = [](double r) { return 1.3 * 1.0 / (1000.0 * 3.0) * (0.4 * r + 4.0 / r); };
  const auto ok = stratum("run " + write_scene("lame_checks.toml", text) + " --out lame_checks");
  INFO(ok.out << ok.err);
  CHECK(ok.code == 0);
  CHECK(ok.out.find("check inner.ux = ") != std::string::npos);
  CHECK(ok.out.find(": pass\n") != std::string::npos);
  // history/inner.csv: stage,step,lambda,ux_m (each quantity with its unit); its last row against
  // the closed form.
  {
    std::ifstream csv(scratch() / "lame_checks" / "history" / "inner.csv");
    std::string line, last;
    std::getline(csv, line);
    CHECK(line == "stage,step,lambda,ux_m");
    int rows = 0;
    while (std::getline(csv, line)) last = line, ++rows;
    CHECK(rows == 2); // the start (step 0) and the one load step
    const double ux = std::stod(last.substr(last.rfind(',') + 1));
    CHECK(std::abs(ux - u(1.0)) < 1e-3 * u(1.0));
  }
  // summary.toml: the run completed, and its check with the value the closed form gives.
  {
    const auto sm = toml::parse_file((scratch() / "lame_checks" / "summary.toml").string());
    CHECK(sm["ended"].value_or(std::string()) == "completed");
    CHECK(sm["stop_reason"].value_or(std::string("x")).empty());
    CHECK(sm["steps_done"].value_or(0) == 1);
    const auto* checks = sm["checks"].as_array();
    REQUIRE(checks);
    bool inner = false;
    for (const auto& c : *checks) {
      const auto& t = *c.as_table();
      if (t["label"].value_or(std::string()) != "inner.ux") continue;
      inner = true;
      CHECK(t["pass"].value_or(false));
      CHECK(std::abs(t["value"].value_or(0.0) - u(1.0)) < 1e-3 * u(1.0));
    }
    CHECK(inner);
  }
  // A wrong expected value fails its check: exit status 5, the FAIL line, one line on stderr.
  std::string bad = text;
  bad.replace(bad.find("expected = 1.2133333e-3"), 23, "expected = 1.3e-3");
  const auto fail = stratum("run " + write_scene("lame_bad.toml", bad) + " --out lame_bad");
  CHECK(fail.code == 5);
  CHECK(fail.out.find("check outer.ux = ") != std::string::npos);
  CHECK(fail.out.find(": FAIL\n") != std::string::npos);
  CHECK(fail.err.find("a check failed") != std::string::npos);
  // Located errors: a node recorder where no node is, a check of a quantity not recorded.
  std::string nonode = text;
  nonode.replace(nonode.find("at = [2.0, 0.0]"), 15, "at = [1.9, 0.1]");
  const auto e1 = stratum("check " + write_scene("lame_nonode.toml", nonode));
  CHECK(e1.code == 1);
  CHECK(e1.err.find("lame_nonode.toml:") != std::string::npos);
  CHECK(e1.err.find("[[output.history]] #2 no node at (1.9, 0.1); the nearest is node") != std::string::npos);
  std::string noq = text;
  noq.replace(noq.rfind("quantity = \"ux\""), 15, "quantity = \"uy\"");
  const auto e2 = stratum("check " + write_scene("lame_noq.toml", noq));
  CHECK(e2.code == 1);
  CHECK(e2.err.find("[[checks]] #2 quantity = \"uy\" is not recorded by \"outer\"; it records: ux") !=
        std::string::npos);
}

TEST_CASE("cli: stratum describe lists the scene's sections and describes each from the reader's schemas",
          "[cli][describe]") {
  const auto list = stratum("describe");
  INFO(list.err);
  CHECK(list.code == 0);
  for (const char* line :
       {"analysis        [analysis]", "mesh.blocks     [[mesh.blocks]]", "stages.actions  [[stages.actions]]",
        "output.history  [[output.history]]", "checks          [[checks]]", "include         include = ..."})
    CHECK(list.out.find(std::string("\n") + line) != std::string::npos);
  // One section in full: type, unit, allowed, default or required, and the meaning below.
  const auto a = stratum("describe analysis");
  CHECK(a.code == 0);
  CHECK(a.out.rfind("[analysis]: ", 0) == 0);
  CHECK(a.out.find("\n  max_cutbacks       integer  -       [0, 30], default 4\n      how many times a "
                   "failed step may be halved") != std::string::npos);
  // The stage actions, each with its own keys; brackets are allowed around the name.
  const auto sa = stratum("describe '[[stages.actions]]'");
  CHECK(sa.code == 0);
  CHECK(sa.out.find("[[stages.actions]] type = \"geostatic\": ") != std::string::npos);
  CHECK(sa.out.find("\n  K0                 number   -       (0, inf), required\n") != std::string::npos);
  CHECK(sa.out.find("[[stages.actions]] type = \"load\": ") != std::string::npos);
  // [[stages]] inherits its defaults from [analysis] and [output]; recorders list each kind.
  CHECK(stratum("describe stages").out.find("\n  max_cutbacks       integer  -       [0, 30], default 4") !=
        std::string::npos);
  CHECK(stratum("describe output.history").out.find("kind = \"node\" records: ux, uy, rx, ry") !=
        std::string::npos);
  CHECK(stratum("describe mesh.generators").out.find("generator = \"axisymmetric_pile\": [mesh.pile]") !=
        std::string::npos);
  // The sets a generator defines come from a mesh it generates (the pile mesher's shaft zone).
  CHECK(stratum("describe mesh.generators").out.find(", near_shaft, pile, ") != std::string::npos);
  CHECK(stratum("describe solver").out.find("[solver] solver = \"newton\": ") != std::string::npos);
  // Unknown sections: the known ones and a suggestion.
  const auto bad = stratum("describe stagse");
  expect_one_line_error(bad, "",
                        "describe: unknown section 'stagse'; known: scene, include, units, analysis");
  CHECK(bad.err.find("did you mean 'stages'?") != std::string::npos);
  expect_one_line_error(stratum("describe --markdwon"), "", "describe: unknown option '--markdwon'");
}

TEST_CASE("cli: check warns about cells that no [[domains]] entry covers", "[cli][describe]") {
  // A second block "cap" (4 cells) that no domain names: it stays out of the model (on 997ba04
  // check said ok and the run failed with a Newton message).
  const auto p =
      write_scene("no_domain.toml",
                  edit("nx = 4\nny = 1\n", "nx = 4\nny = 1\n[[mesh.blocks]]\nname = \"cap\"\nx = [1.0, 2.0]\n"
                                           "y = [0.5, 1.0]\nnx = 4\nny = 1\n"));
  const auto r = stratum("check " + p);
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(r.err == "stratum: warning: " + p +
                     ":30:1 4 of 8 cells belong to no [[domains]] entry (cells 4, 5, 6, 7); cell sets "
                     "without a domain: cap; they stay out of the model for the whole run (a cavity); "
                     "give them a [[domains]] entry (cells, element, material) if they are to carry load\n");
  CHECK(r.out.find(": ok (") != std::string::npos);
  // The same scene with the cap in a domain is good.
  std::string fixed =
      edit("nx = 4\nny = 1\n", "nx = 4\nny = 1\n[[mesh.blocks]]\nname = \"cap\"\nx = [1.0, 2.0]\n"
                               "y = [0.5, 1.0]\nnx = 4\nny = 1\n");
  fixed += "[[domains]]\ncells = \"cap\"\nelement = \"quad\"\nmaterial = \"soil\"\n";
  const auto ok = stratum("check " + write_scene("cap_domain.toml", fixed));
  INFO(ok.err);
  CHECK(ok.code == 0);
}

TEST_CASE("cli: a load on an empty set is an error located at the set's key", "[cli][describe]") {
  // patch_quad4.msh with three physical groups that hold no element: an edge, a node and a cell set.
  std::ifstream in(std::string(STRATUM_TEST_DATA_DIR) + "/patch_quad4.msh");
  std::stringstream msh;
  msh << in.rdbuf();
  std::string text = msh.str();
  const std::string names = "$PhysicalNames\n5\n";
  REQUIRE(text.find(names) != std::string::npos);
  text.replace(text.find(names), names.size(),
               "$PhysicalNames\n8\n1 6 \"no_edges\"\n0 7 \"no_nodes\"\n2 8 \"no_cells\"\n");
  std::ofstream(scratch() / "empty_sets.msh") << text;
  const std::string head = "[mesh]\ngenerator = \"gmsh\"\nfile = \"empty_sets.msh\"\n"
                           "[materials.soil]\nmodel = \"linear_elastic\"\nE = 1000.0\nnu = 0.3\n"
                           "[[domains]]\ncells = \"patch\"\nelement = \"quad\"\nmaterial = \"soil\"\n"
                           "[[constraints]]\nnodes = \"bottom\"\nux = 0.0\nuy = 0.0\n";
  const auto p1 = write_scene("empty_edges.toml",
                              head + "[[loads]]\ntype = \"pressure\"\nedges = \"no_edges\"\np = 1.0\n");
  expect_one_line_error(stratum("check " + p1), p1 + ":18:9 ",
                        "[[loads]] type = \"pressure\" edges = \"no_edges\" is an empty edge set: the load "
                        "would act on nothing");
  const auto p2 =
      write_scene("empty_nodes.toml", head + "[[loads]]\ntype = \"force\"\nnodes = \"no_nodes\"\nfy = 1.0\n");
  expect_one_line_error(stratum("check " + p2), p2 + ":18:9 ",
                        "nodes = \"no_nodes\" is an empty node set: the load would act on nothing");
  const auto p3 = write_scene("empty_cells.toml",
                              head + "[[stages]]\nname = \"push\"\n[[stages.actions]]\ntype = \"load\"\n"
                                     "cells = \"no_cells\"\nforce = 10.0\n");
  expect_one_line_error(stratum("check " + p3), p3 + ":20:9 ",
                        "[[stages]] #1 [[stages.actions]] #1 type = \"load\" cells = \"no_cells\" is an "
                        "empty cell set");
  // The same mesh loaded on a set with members: good, and a warning names the physical groups
  // that the scene never names (only Gmsh's: generated meshes define many unused sets).
  const auto p4 =
      write_scene("named_sets.toml", head + "[[loads]]\ntype = \"pressure\"\nedges = \"right\"\np = 1.0\n");
  const auto r4 = stratum("check " + p4);
  INFO(r4.err);
  CHECK(r4.code == 0);
  CHECK(r4.err == "stratum: warning: " + p4 +
                      ":3:8 [mesh] file = \"empty_sets.msh\": 5 physical groups that the scene never "
                      "names: left, no_cells, no_edges, no_nodes, top (harmless if left over; otherwise "
                      "check the set names)\n");
  CHECK(stratum("check --quiet " + p4).err.empty());
}

TEST_CASE("cli: every key a table accepts is in its stratum describe section", "[cli][describe]") {
  // An unknown key makes the reader list the keys it accepts; each must be described.
  const struct {
    const char* section;
    std::string scene;
  } cases[] = {
      {"analysis", edit("formulation = \"axisymmetric\"\n", "formulation = \"axisymmetric\"\nzzz = 1\n")},
      {"output", good + "[output]\nzzz = 1\n"},
      {"constraints", edit("nodes = \"bottom\"\n", "nodes = \"bottom\"\nzzz = 1\n")},
      {"mesh", edit("nodes_per_cell = 8\n", "nodes_per_cell = 8\nzzz = 1\n")},
      {"mesh.blocks", edit("nx = 4\n", "nx = 4\nzzz = 1\n")},
  };
  for (const auto& c : cases) {
    const auto r = stratum("check " + write_scene("keys.toml", c.scene));
    INFO(c.section << ": " << r.err);
    REQUIRE(r.code == 1);
    const auto at = r.err.find("; allowed: ");
    REQUIRE(at != std::string::npos);
    std::string list = r.err.substr(at + 11);
    list = list.substr(0, list.find_first_of(";\n"));
    const auto d = stratum(std::string("describe ") + c.section);
    REQUIRE(d.code == 0);
    int keys = 0;
    for (std::size_t from = 0; from < list.size();) {
      const auto comma = std::min(list.find(", ", from), list.size());
      const std::string key = list.substr(from, comma - from);
      INFO("key " << key);
      CHECK(d.out.find("\n  " + key + " ") != std::string::npos);
      ++keys;
      from = comma + 2;
    }
    CHECK(keys >= 2);
  }
}

} // namespace test_cli
