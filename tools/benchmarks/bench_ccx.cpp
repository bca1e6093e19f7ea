// bench_ccx: Stratum and CalculiX (ccx) side by side on the same axisymmetric quad8 / CAX8
// meshes, and the ratio of their run times.
//
// Two problems, both axisymmetric slices with u_z = 0 on top and bottom (so plane strain in z):
//  * lame: the elastic Lamé cylinder of inputs/verification/lame_axisymmetric.toml
//    (a = 1, b = 2, height 0.5, E = 1000, nu = 0.3, p = 1), one linear step;
//  * hill: Hill's thick cylinder of inputs/verification/hill_cylinder.toml made axisymmetric
//    (a = 0.1, b = 0.2, height 0.05, E = 2.1e8, nu = 0.3, sigma_y = 2.4e5, perfectly plastic
//    von Mises), loaded in equal increments to 0.9 of the limit pressure Y ln(b/a);
//  * lame_ps: the same Lamé ring in plane strain, a quarter ring meshed in polar coordinates,
//    CPE8 in ccx: a plane element ccx expands without an angle about an axis;
//  * tresca: the same Hill cylinder with Tresca (Mohr-Coulomb at phi = 1e-4 deg, c = Y/2), the
//    material the closed form is exact for; Stratum only (ccx has no Tresca material).
// Both are meshed with nx x nx/2 square quad8 cells (3x3 Gauss, the full integration of
// ccx's CAX8). Stratum builds the scene from TOML text; the harness writes ccx's input
// from Stratum's own mesh (nodes, CAX8 connectivity, *BOUNDARY, *DLOAD on the element faces
// of r = a), runs `ccx` in a temporary directory under /tmp, parses its .dat file and
// compares displacements at every node and element-mean stresses against Stratum's, and
// both against the closed forms. Nothing of ccx is kept.
//
// Usage: bench_ccx [--max-dof N] [--hill-max-dof N] [--repeat K] [--hill-repeat K]
//                  [--no-write] [--keep] [--docs PATH] [--plugin-dir DIR] [--ccx PATH]
// README.md in this folder describes what is timed and the columns.
#include "cli.hpp"
#include "cylinder_series.hpp"
#include "docs_section.hpp"
#include "machine.hpp"
#include "stratum/analysis.hpp"
#include "stratum/linear_solver.hpp"
#include "stratum/model.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

using namespace stratum::bench; // median, fixed, size_for, seconds_since, ... (machine.hpp,
                                // cylinder_series.hpp)

constexpr const char* begin_marker = "<!-- bench_ccx:begin -->";
constexpr const char* end_marker = "<!-- bench_ccx:end -->";
constexpr double speed_target = 0.5;       ///< Stratum / ccx time at 1e5 DOF, elastic
constexpr double elastic_agreement = 1e-6; ///< relative difference of the displacements, elastic
constexpr double plastic_agreement = 1e-3; ///< relative difference of u(b), Hill, to ccx and closed form
constexpr double hill_load_fraction = 0.9; ///< of the limit pressure

enum class Problem { lame, lame_plane, hill };

/// The data of one problem (units kN, m, kPa).
struct Spec {
  Problem problem = Problem::lame;
  const char* name = "";
  double a = 0, b = 0, height = 0, young = 0, poisson = 0, sigma_y = 0, pressure = 0;
  int steps = 1;

  [[nodiscard]] bool plastic() const { return problem == Problem::hill; }
  /// Plane strain on a quarter ring (x = r cos theta, y = r sin theta) instead of axisymmetric.
  [[nodiscard]] bool plane() const { return problem == Problem::lame_plane; }
  /// Y = 2 sigma_y / sqrt(3): the plane-strain yield stress of Hill's solution.
  [[nodiscard]] double yield_y() const { return 2.0 * sigma_y / std::sqrt(3.0); }
  [[nodiscard]] double limit_pressure() const { return yield_y() * std::log(b / a); }
};

Spec lame_spec() {
  Spec s;
  s.problem = Problem::lame;
  s.name = "lame";
  s.a = 1.0;
  s.b = 2.0;
  s.height = 0.5;
  s.young = 1000.0;
  s.poisson = 0.3;
  s.pressure = 1.0;
  s.steps = 1;
  return s;
}

Spec lame_plane_spec() {
  Spec s = lame_spec();
  s.problem = Problem::lame_plane;
  s.name = "lame_ps";
  return s;
}

Spec hill_spec() {
  Spec s;
  s.problem = Problem::hill;
  s.name = "hill";
  s.a = 0.1;
  s.b = 0.2;
  s.height = 0.05;
  s.young = 2.1e8;
  s.poisson = 0.3;
  s.sigma_y = 2.4e5;
  s.pressure = hill_load_fraction * s.limit_pressure();
  s.steps = 10;
  return s;
}

/// Lamé: u(r) of the closed form (exact for the plane-strain ring).
double lame_u(const Spec& s, double r) {
  const double a = s.a, b = s.b, nu = s.poisson;
  return (1 + nu) * s.pressure * a * a / (s.young * (b * b - a * a)) * ((1 - 2 * nu) * r + b * b / r);
}

/// Hill: the plastic radius c of P = Y [ln(c/a) + (1 - c^2/b^2)/2] (bisection).
double hill_c(const Spec& s) {
  const double y = s.yield_y();
  double lo = s.a, hi = s.b;
  for (int i = 0; i < 200; ++i) {
    const double c = 0.5 * (lo + hi);
    const double p = y * (std::log(c / s.a) + 0.5 * (1 - c * c / (s.b * s.b)));
    (p < s.pressure ? lo : hi) = c;
  }
  return 0.5 * (lo + hi);
}

/// Hill: u(b) = Y c^2 (1 - nu^2) / (E b) (Tresca with Y; for von Mises an approximation).
double hill_u_b(const Spec& s) {
  const double c = hill_c(s);
  return s.yield_y() * c * c * (1 - s.poisson * s.poisson) / (s.young * s.b);
}

/// The closed-form reference of the problem: u(a) for Lamé, u(b) for Hill.
double exact_reference(const Spec& s) { return s.plastic() ? hill_u_b(s) : lame_u(s, s.a); }

struct Options {
  double max_dof = 1e5;
  double hill_max_dof = 1e5;
  int repeat = 3;
  int hill_repeat = 1;
  bool write = true;
  bool keep = false;
  std::string docs = std::string(STRATUM_SOURCE_DIR) + "/docs/benchmarks.md";
  std::string plugin_dir = STRATUM_PLUGIN_DIR;
  std::string ccx = "ccx";
};

/// Tresca as Mohr-Coulomb at phi -> 0: c = Y/2 and phi = psi = 1e-4 deg, which moves the strength
/// by at most sin(phi) |sigma_m| / c < 2e-6 of it here (|sigma_m| < P_lim < 1.4 c).
constexpr double tresca_phi = 1e-4;

/// The scene of a problem; `tresca` swaps the Hill cylinder's von Mises for Tresca (Stratum only).
std::string scene_text(const Spec& p, const Size& s, bool tresca = false) {
  std::ostringstream t;
  t.precision(17);
  t << "title = \"bench_ccx: " << p.name << " " << s.nx << " x " << s.ny << " quad8\"\n"
    << "[analysis]\nformulation = \"" << (p.plane() ? "plane_strain" : "axisymmetric")
    << "\"\nsolver = \"newton\"\nlinear_solver = \"auto\"\nthreads = "
       "1\nsteps = "
    << p.steps << "\nmax_cutbacks = 0\n"
    << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n"
    << (p.plane() ? "transform = \"polar\"\n" : "") << "[[mesh.blocks]]\nname = \"ring\"\nx = [" << p.a
    << ", " << p.b << "]\ny = [0.0, " << (p.plane() ? 90.0 : p.height) << "]\nnx = " << s.nx
    << "\nny = " << s.ny << "\n";
  if (p.plastic() && tresca)
    t << "[materials.steel]\nmodel = \"mohr_coulomb\"\nE = " << p.young << "\nnu = " << p.poisson
      << "\nc = " << 0.5 * p.yield_y() << "\nphi = " << tresca_phi << "\npsi = " << tresca_phi << "\n";
  else if (p.plastic())
    t << "[materials.steel]\nmodel = \"von_mises\"\nE = " << p.young << "\nnu = " << p.poisson
      << "\nsigma_y = " << p.sigma_y << "\nH = 0.0\nintegrator = \"closest_point\"\n";
  else
    t << "[materials.steel]\nmodel = \"linear_elastic\"\nE = " << p.young << "\nnu = " << p.poisson << "\n";
  t << "[[domains]]\ncells = \"ring\"\nelement = \"quad\"\nmaterial = \"steel\"\nintegration = 3\n"
    << "[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
    << "[[constraints]]\nnodes = \"top\"\n"
    << (p.plane() ? "ux" : "uy") << " = 0.0\n"
    << "[[loads]]\ntype = \"pressure\"\nedges = \"ring.left\"\np = " << p.pressure << "\n"
    << "[output]\nvtk = false\n";
  return t.str();
}

/// What both programs deliver: displacements of every node (r, z) and the mean stress
/// (r, z, theta, rz) over the integration points of every cell.
struct Results {
  std::vector<double> u;      ///< 2 per node
  std::vector<double> stress; ///< 4 per cell
};

/// Writes what ccx's .dat holds (*NODE PRINT U, *EL PRINT S): displacements of every node
/// and the stresses of every integration point, in the same format. Part of Stratum's timing.
void write_stratum_results(const stratum::Model& m, const fs::path& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw stratum::Error("bench_ccx: cannot write " + path.string());
  std::fprintf(f, "\n displacements (vx,vy,vz) for set NALL\n\n");
  const auto nodes = static_cast<int>(m.mesh.nodes.size());
  for (int n = 0; n < nodes; ++n)
    std::fprintf(f, "%10d %13.6E %13.6E %13.6E\n", n + 1, m.u[2 * n], m.u[2 * n + 1], 0.0);
  std::fprintf(f, "\n stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz) for set EALL\n\n");
  for (const auto& d : m.domains)
    for (std::size_t c = 0; c < d.cells.size(); ++c)
      for (std::size_t p = d.first_point[c]; p < d.first_point[c + 1]; ++p) {
        const auto s = d.states.committed(p).stress();
        std::fprintf(f, "%10d %3d %13.6E %13.6E %13.6E %13.6E %13.6E %13.6E\n", d.cells[c] + 1,
                     static_cast<int>(p - d.first_point[c]) + 1, s[0], s[1], s[2], s[3], s[5], s[4]);
      }
  if (std::fclose(f) != 0) throw stratum::Error("bench_ccx: cannot write " + path.string());
}

Results stratum_results(const stratum::Model& m) {
  Results r;
  r.u.assign(m.u.data(), m.u.data() + m.u.size());
  r.stress.assign(4 * m.mesh.cells.size(), 0.0);
  for (const auto& d : m.domains)
    for (std::size_t c = 0; c < d.cells.size(); ++c) {
      const std::size_t p0 = d.first_point[c], p1 = d.first_point[c + 1];
      for (std::size_t p = p0; p < p1; ++p) {
        const auto s = d.states.committed(p).stress();
        for (int k = 0; k < 4; ++k)
          r.stress[4 * static_cast<std::size_t>(d.cells[c]) + k] += s[k] / static_cast<double>(p1 - p0);
      }
    }
  return r;
}

/// ccx's element face (1-4, CAX8: face k joins corners k and k+1) holding a boundary edge.
std::vector<std::pair<int, int>> faces_of(const stratum::Mesh& mesh,
                                          const std::vector<stratum::Edge>& edges) {
  std::map<std::pair<int, int>, std::pair<int, int>> by_corners;
  for (std::size_t c = 0; c < mesh.cells.size(); ++c)
    for (int k = 0; k < 4; ++k)
      by_corners[{mesh.cells[c].nodes[k], mesh.cells[c].nodes[(k + 1) % 4]}] = {static_cast<int>(c), k + 1};
  std::vector<std::pair<int, int>> out;
  for (const auto& e : edges) {
    auto it = by_corners.find({e.a, e.b});
    if (it == by_corners.end()) it = by_corners.find({e.b, e.a});
    if (it == by_corners.end()) throw stratum::Error("bench_ccx: a loaded edge belongs to no cell");
    out.push_back(it->second);
  }
  return out;
}

const std::vector<int>& node_set(const stratum::Mesh& m, const std::string& name) {
  const auto it = m.node_sets.find(name);
  if (it == m.node_sets.end() || it->second.empty()) throw stratum::Error("bench_ccx: no node set " + name);
  return it->second;
}

/// A number as ccx reads it: its input fields hold at most 20 characters, so the 17 significant
/// digits that round-trip a double are shortened where a sign and an exponent need the room
/// (e.g. the 6e-17 that cos(90 deg) leaves in the polar map).
std::string ccx_number(double v) {
  char buf[64];
  for (int digits = 17; digits > 1; --digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strlen(buf) <= 20) break;
  }
  return buf;
}

/// The ccx input of the same problem on Stratum's mesh: CAX8 (ccx's corner and midside order
/// is Stratum's slot order), u_z = 0 on top and bottom, the pressure as *DLOAD on the faces of
/// r = a; *NODE PRINT U and *EL PRINT S of the last increment only. Plane strain (lame_ps): CPE8
/// (unit thickness, ccx's default), u_y = 0 at theta = 0 and u_x = 0 at theta = 90 deg.
void write_ccx_input(const stratum::Model& m, const Spec& p, const fs::path& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw stratum::Error("bench_ccx: cannot write " + path.string());
  std::fprintf(f, "** bench_ccx: %s, written from Stratum's mesh\n*NODE,NSET=NALL\n", p.name);
  for (std::size_t n = 0; n < m.mesh.nodes.size(); ++n)
    std::fprintf(f, "%zu,%s,%s\n", n + 1, ccx_number(m.mesh.nodes[n].x()).c_str(),
                 ccx_number(m.mesh.nodes[n].y()).c_str());
  std::fprintf(f, "*ELEMENT,TYPE=%s,ELSET=EALL\n", p.plane() ? "CPE8" : "CAX8");
  for (std::size_t c = 0; c < m.mesh.cells.size(); ++c) {
    const auto& nd = m.mesh.cells[c].nodes;
    if (m.mesh.cells[c].count() != 8) throw stratum::Error("bench_ccx: a cell is not a quad8");
    std::fprintf(f, "%zu,%d,%d,%d,%d,%d,%d,%d,%d\n", c + 1, nd[0] + 1, nd[1] + 1, nd[2] + 1, nd[3] + 1,
                 nd[4] + 1, nd[5] + 1, nd[6] + 1, nd[7] + 1);
  }
  if (p.plane()) {
    std::fprintf(f, "*NSET,NSET=NFIXY\n");
    for (int n : node_set(m.mesh, "bottom")) std::fprintf(f, "%d\n", n + 1);
    std::fprintf(f, "*NSET,NSET=NFIXX\n");
    for (int n : node_set(m.mesh, "top")) std::fprintf(f, "%d\n", n + 1);
    std::fprintf(f, "*BOUNDARY\nNFIXY,2,2\nNFIXX,1,1\n");
  } else {
    std::fprintf(f, "*NSET,NSET=NFIXZ\n");
    for (const char* set : {"bottom", "top"})
      for (int n : node_set(m.mesh, set)) std::fprintf(f, "%d\n", n + 1);
    std::fprintf(f, "*BOUNDARY\nNFIXZ,2,2\n");
  }
  std::fprintf(f, "*MATERIAL,NAME=STEEL\n*ELASTIC\n%.17g,%.17g\n", p.young, p.poisson);
  if (p.plastic()) std::fprintf(f, "*PLASTIC\n%.17g,0.0\n", p.sigma_y);
  std::fprintf(f, "*SOLID SECTION,ELSET=EALL,MATERIAL=STEEL\n");
  if (p.plastic())
    std::fprintf(f, "*STEP,INC=1000\n*STATIC,DIRECT\n%.17g,1.0\n", 1.0 / p.steps);
  else
    std::fprintf(f, "*STEP\n*STATIC\n");
  std::fprintf(f, "*DLOAD\n");
  const auto it = m.mesh.edge_sets.find("ring.left");
  if (it == m.mesh.edge_sets.end()) throw stratum::Error("bench_ccx: no edge set ring.left");
  for (const auto& [cell, face] : faces_of(m.mesh, it->second))
    std::fprintf(f, "%d,P%d,%.17g\n", cell + 1, face, p.pressure);
  std::fprintf(f,
               "*NODE PRINT,NSET=NALL,FREQUENCY=%d\nU\n*EL PRINT,ELSET=EALL,FREQUENCY=%d\nS\n*END "
               "STEP\n",
               p.steps, p.steps);
  if (std::fclose(f) != 0) throw stratum::Error("bench_ccx: cannot write " + path.string());
}

/// Reads the last displacement and stress blocks of ccx's .dat (stresses averaged per element).
Results read_ccx_dat(const fs::path& path, std::size_t nodes, std::size_t cells) {
  std::ifstream in(path);
  if (!in) throw stratum::Error("bench_ccx: ccx wrote no " + path.string());
  Results r;
  r.u.assign(2 * nodes, NAN);
  r.stress.assign(4 * cells, 0.0);
  std::vector<int> count(cells, 0);
  enum class Block { none, disp, stress } block = Block::none;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find("displacements (vx,vy,vz)") != std::string::npos) {
      block = Block::disp;
      continue;
    }
    if (line.find("stresses (elem, integ.pnt.") != std::string::npos) {
      block = Block::stress;
      std::fill(r.stress.begin(), r.stress.end(), 0.0);
      std::fill(count.begin(), count.end(), 0);
      continue;
    }
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream ls(line);
    if (block == Block::disp) {
      long n = 0;
      double x = 0, y = 0, z = 0;
      if (!(ls >> n >> x >> y >> z) || n < 1 || static_cast<std::size_t>(n) > nodes) {
        block = Block::none;
        continue;
      }
      r.u[2 * (n - 1)] = x;
      r.u[2 * (n - 1) + 1] = y;
    } else if (block == Block::stress) {
      long e = 0, ip = 0;
      double s[6];
      if (!(ls >> e >> ip >> s[0] >> s[1] >> s[2] >> s[3] >> s[4] >> s[5]) || e < 1 ||
          static_cast<std::size_t>(e) > cells) {
        block = Block::none;
        continue;
      }
      const auto c = static_cast<std::size_t>(e - 1);
      for (int k = 0; k < 4; ++k) r.stress[4 * c + k] += s[k];
      ++count[c];
    }
  }
  for (std::size_t c = 0; c < cells; ++c) {
    if (count[c] == 0) throw stratum::Error("bench_ccx: no stresses of element " + std::to_string(c + 1));
    for (int k = 0; k < 4; ++k) r.stress[4 * c + k] /= count[c];
  }
  for (double v : r.u)
    if (std::isnan(v)) throw stratum::Error("bench_ccx: the .dat misses displacements");
  return r;
}

/// Sum of ccx's Newton iterations over the increments (the ITRS column of the .sta file).
int ccx_iterations(const fs::path& sta) {
  std::ifstream in(sta);
  std::string line;
  int total = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    int step = 0, inc = 0, att = 0, itrs = 0;
    if (ls >> step >> inc >> att >> itrs) total += itrs;
  }
  return total;
}

/// The number after "number of equations" in ccx's log (the unknowns of its expanded 3D model).
long long ccx_equations(const fs::path& log) {
  std::ifstream in(log);
  std::string line;
  while (std::getline(in, line))
    if (line.find("number of equations") != std::string::npos) {
      long long n = 0;
      if (in >> n) return n;
    }
  return 0;
}

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

/// Runs ccx on <dir>/job.inp single-threaded; returns the wall time of the whole process.
double run_ccx(const Options& o, const fs::path& dir) {
  const std::string cmd = "cd " + quoted(dir.string()) +
                          " && OMP_NUM_THREADS=1 CCX_NPROC_EQUATION_SOLVER=1 CCX_NPROC_STIFFNESS=1 " +
                          quoted(o.ccx) + " -i job > ccx.log 2>&1";
  const auto t = Clock::now();
  const int status = std::system(cmd.c_str());
  const double wall = seconds_since(t);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw stratum::Error("bench_ccx: ccx failed (see " + (dir / "ccx.log").string() + ")");
  return wall;
}

/// The measurements of one repetition of one problem and size.
struct Sample {
  double build = 0, run = 0, write = 0; ///< Stratum: from_string, run(), writing the results
  double ccx = 0;                       ///< the whole ccx process
  double assembly = 0;  ///< Stratum's split, measured after run(): one assemble() with the tangent
  double factorize = 0; ///< analyze + factorize of that tangent with the "auto" linear solver
  int free = 0, iterations = 0, ccx_iterations = 0;
  long long ccx_equations = 0;
  // comparisons
  double du = 0;               ///< max over nodes |u_ccx - u_stratum| / max |u_stratum|
  double ds = 0;               ///< max over cells and components |s_ccx - s| / max |s|
  double u_a = 0, u_a_ccx = 0; ///< u_r at r = a (mean over the face's nodes)
  double u_b = 0, u_b_ccx = 0; ///< u_r at r = b
  [[nodiscard]] double stratum() const { return build + run + write; }
};

double mean_ur(const std::vector<double>& u, const std::vector<int>& nodes) {
  double s = 0;
  for (int n : nodes) s += u[2 * static_cast<std::size_t>(n)];
  return s / static_cast<double>(nodes.size());
}

/// Plane strain quarter ring: the mean radial displacement (u . x / |x|) over the nodes.
double mean_radial(const std::vector<double>& u, const stratum::Mesh& mesh, const std::vector<int>& nodes) {
  double s = 0;
  for (int n : nodes) {
    const auto k = static_cast<std::size_t>(n);
    const double x = mesh.nodes[k].x(), y = mesh.nodes[k].y();
    s += (u[2 * k] * x + u[2 * k + 1] * y) / std::hypot(x, y);
  }
  return s / static_cast<double>(nodes.size());
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

Sample measure(const Spec& p, const Size& s, const Options& o, const fs::path& dir) {
  Sample r;
  stratum::RunOptions ro;
  ro.plugin_dirs = {o.plugin_dir};
  ro.write_output = false;
  const std::string text = scene_text(p, s);
  // Stratum: TOML text -> solution -> results file.
  auto t = Clock::now();
  auto analysis = stratum::Analysis::from_string(text, "bench_ccx.toml", std::move(ro));
  r.build = seconds_since(t);
  t = Clock::now();
  const stratum::RunSummary summary = analysis->run();
  r.run = seconds_since(t);
  if (!summary.outcome.ok()) throw stratum::Error("bench_ccx: run() failed: " + summary.outcome.message);
  const stratum::Model& m = analysis->model();
  t = Clock::now();
  write_stratum_results(m, dir / "stratum.dat");
  r.write = seconds_since(t);
  r.free = m.dofs.free_count;
  for (const auto& rep : summary.reports) r.iterations += rep.iterations;
  const Results mine = stratum_results(m);

  // ccx on the same mesh.
  write_ccx_input(m, p, dir / "job.inp");
  r.ccx = run_ccx(o, dir);
  const Results theirs = read_ccx_dat(dir / "job.dat", m.mesh.nodes.size(), m.mesh.cells.size());
  r.ccx_iterations = p.plastic() ? ccx_iterations(dir / "job.sta") : 1;
  r.ccx_equations = ccx_equations(dir / "ccx.log");

  r.du = max_diff(theirs.u, mine.u) / max_abs(mine.u);
  r.ds = max_diff(theirs.stress, mine.stress) / max_abs(mine.stress);
  const auto& left = node_set(m.mesh, "ring.left");
  const auto& right = node_set(m.mesh, "ring.right");
  auto ur = [&](const std::vector<double>& u, const std::vector<int>& nodes) {
    return p.plane() ? mean_radial(u, m.mesh, nodes) : mean_ur(u, nodes);
  };
  r.u_a = ur(mine.u, left);
  r.u_a_ccx = ur(theirs.u, left);
  r.u_b = ur(mine.u, right);
  r.u_b_ccx = ur(theirs.u, right);
  // Stratum's split (not part of its time above): one assembly with the tangent at the converged
  // state and one analyze + factorize of it, the cost of a Newton iteration.
  {
    stratum::Model& mm = analysis->model();
    const stratum::Assembler assembler(mm);
    stratum::SparseMatrix k = assembler.make_matrix();
    Eigen::VectorXd f_int;
    t = Clock::now();
    if (auto out = assembler.assemble(mm, mm.u, f_int, &k); !out.ok())
      throw stratum::Error("bench_ccx: assembly failed: " + out.message);
    r.assembly = seconds_since(t);
    auto ls = stratum::make_linear_solver("auto", mm.symmetric(), r.free);
    t = Clock::now();
    if (auto out = ls->analyze(k); !out.ok()) throw stratum::Error("bench_ccx: " + out.message);
    if (auto out = ls->factorize(k); !out.ok()) throw stratum::Error("bench_ccx: " + out.message);
    r.factorize = seconds_since(t);
  }
  if (!o.keep)
    for (const char* f : {"job.inp", "job.dat", "job.frd", "job.sta", "job.cvg", "job.12d", "spooles.out",
                          "ccx.log", "stratum.dat"})
      fs::remove(dir / f);
  return r;
}

/// Hill's cylinder with Tresca, Stratum only: u(b) against the closed form that is exact for it.
struct TrescaRow {
  Size size;
  int free = 0, iterations = 0;
  double run = 0;     ///< from_string + run(), s
  double u_b = 0;     ///< mean u_r on r = b
  double u_b_vm = -1; ///< the von Mises run's u(b) on the same mesh (-1: not measured)
};

TrescaRow measure_tresca(const Size& s, const Options& o) {
  TrescaRow r;
  r.size = s;
  stratum::RunOptions ro;
  ro.plugin_dirs = {o.plugin_dir};
  ro.write_output = false;
  const auto t = Clock::now();
  auto analysis = stratum::Analysis::from_string(scene_text(hill_spec(), s, true), "bench_ccx_tresca.toml",
                                                 std::move(ro));
  const stratum::RunSummary summary = analysis->run();
  r.run = seconds_since(t);
  if (!summary.outcome.ok())
    throw stratum::Error("bench_ccx: Tresca run() failed: " + summary.outcome.message);
  const stratum::Model& m = analysis->model();
  r.free = m.dofs.free_count;
  for (const auto& rep : summary.reports) r.iterations += rep.iterations;
  r.u_b = mean_ur(std::vector<double>(m.u.data(), m.u.data() + m.u.size()), node_set(m.mesh, "ring.right"));
  return r;
}

/// One row: medians of the times over the repetitions, the results of the first (they do
/// not change between repetitions), the medians of the per-repetition ratios.
struct Row {
  Spec spec;
  Size size;
  int repeat = 0;
  Sample med;
  double ratio = 0; ///< median of Stratum / ccx over the repetitions
};

Row summarize(const Spec& p, const Size& s, const std::vector<Sample>& v) {
  Row row{p, s, static_cast<int>(v.size()), v.front(), 0};
  auto med = [&](auto f) {
    std::vector<double> x;
    for (const auto& e : v) x.push_back(f(e));
    return median(std::move(x));
  };
  row.med.build = med([](const Sample& e) { return e.build; });
  row.med.run = med([](const Sample& e) { return e.run; });
  row.med.write = med([](const Sample& e) { return e.write; });
  row.med.ccx = med([](const Sample& e) { return e.ccx; });
  row.med.assembly = med([](const Sample& e) { return e.assembly; });
  row.med.factorize = med([](const Sample& e) { return e.factorize; });
  row.ratio = med([](const Sample& e) { return e.stratum() / e.ccx; });
  return row;
}

double rel(double x, double ref) { return std::abs(x - ref) / std::abs(ref); }

/// Median Stratum time (s) of a row, from the medians of its parts.
double stratum_median(const Row& r) { return r.med.build + r.med.run + r.med.write; }

// ---- console

void print_header() {
  std::printf("%4s %9s %9s %9s | %7s %7s %7s %7s | %8s %6s | %5s %5s | %7s %7s | %8s %8s | %8s %8s %8s\n",
              "case", "free DOF", "ccx eqs", "mesh", "build", "run()", "write", "Stratum", "ccx", "ratio",
              "its", "ccx", "1 asm", "1 fact", "du", "dsigma", "ref err", "ccx err", "u(a) d");
  std::fflush(stdout);
}

void print_tresca(const TrescaRow& r) {
  std::printf("tresca %9d %5dx%-4d | %7.3f s | %3d its | u(b) %.6e, closed form %.6e, err %8.1e\n", r.free,
              r.size.nx, r.size.ny, r.run, r.iterations, r.u_b, hill_u_b(hill_spec()),
              rel(r.u_b, hill_u_b(hill_spec())));
  std::fflush(stdout);
}

void print_row(const Row& r) {
  const auto& m = r.med;
  const std::string mesh = std::to_string(r.size.nx) + "x" + std::to_string(r.size.ny);
  const double ref = exact_reference(r.spec);
  const double mine = r.spec.plastic() ? m.u_b : m.u_a, theirs = r.spec.plastic() ? m.u_b_ccx : m.u_a_ccx;
  std::printf("%4s %9d %9lld %9s | %7.3f %7.3f %7.3f %7.3f | %8.3f %6.3f | %5d %5d | %7.3f %7.3f | %8.1e "
              "%8.1e | %8.1e "
              "%8.1e %8.1e\n",
              r.spec.name, m.free, m.ccx_equations, mesh.c_str(), m.build, m.run, m.write, stratum_median(r),
              m.ccx, r.ratio, m.iterations, m.ccx_iterations, m.assembly, m.factorize, m.du, m.ds,
              rel(mine, ref), rel(theirs, ref), rel(m.u_a, m.u_a_ccx));
  std::fflush(stdout);
}

// ---- docs/benchmarks.md

/// The first line of `ccx -v` (its version), or "ccx".
std::string ccx_version(const Options& o) {
  const fs::path tmp = fs::temp_directory_path() / ("bench_ccx_version_" + std::to_string(getpid()));
  const std::string cmd = quoted(o.ccx) + " -v > " + quoted(tmp.string()) + " 2>&1";
  std::string version = "ccx";
  if (std::system(cmd.c_str()) != -1) {
    std::ifstream in(tmp);
    std::string line;
    while (std::getline(in, line))
      if (line.find("Version") != std::string::npos) {
        version = "ccx " + line.substr(line.find("Version") + 8);
        while (!version.empty() && std::isspace(static_cast<unsigned char>(version.back())))
          version.pop_back();
        break;
      }
  }
  fs::remove(tmp);
  return version;
}

/// True when `name` runs: an executable path, or found on PATH.
bool have_program(const std::string& name) {
  if (name.find('/') != std::string::npos) return access(name.c_str(), X_OK) == 0;
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string d;
  while (std::getline(dirs, d, ':'))
    if (!d.empty() && access((fs::path(d) / name).c_str(), X_OK) == 0) return true;
  return false;
}

const Row* find_row(const std::vector<Row>& rows, Problem p, double target) {
  for (const auto& r : rows)
    if (r.spec.problem == p && r.size.target == target) return &r;
  return nullptr;
}

std::string targets(const std::vector<Row>& rows, const std::vector<TrescaRow>& tresca) {
  std::ostringstream s;
  if (const Row* r = find_row(rows, Problem::lame, 1e5)) {
    const bool fast = r->ratio <= speed_target, equal = r->med.du <= elastic_agreement;
    s << "- Elastic, 1e5 DOF: Stratum at most half of ccx's time: **" << (fast ? "met" : "NOT met") << "** ("
      << fixed(stratum_median(*r), 2) << " s against " << fixed(r->med.ccx, 2) << " s, ratio "
      << fixed(r->ratio, 3) << "); displacements equal within 1e-6 relative: **"
      << (equal ? "met" : "NOT met") << "** (largest nodal difference " << sci(r->med.du)
      << " of the largest displacement).\n";
  } else {
    s << "- Elastic, 1e5 DOF: not measured in this run.\n";
  }
  const Row* ps = find_row(rows, Problem::lame_plane, 1e5);
  if (!ps) ps = find_row(rows, Problem::lame_plane, 1e4);
  if (ps)
    s << "- Elastic in plane strain (CPE8, no expansion angle in ccx), " << grouped(ps->med.free)
      << " DOF: displacements equal within 1e-6 relative: **"
      << (ps->med.du <= elastic_agreement ? "met" : "NOT met") << "** (largest nodal difference "
      << sci(ps->med.du) << "; Stratum / ccx time ratio " << fixed(ps->ratio, 3) << ").\n";
  const Row* h = find_row(rows, Problem::hill, 1e5);
  if (!h) h = find_row(rows, Problem::hill, 1e4);
  if (h) {
    const double ref = hill_u_b(h->spec);
    const bool near_ccx = rel(h->med.u_b, h->med.u_b_ccx) <= plastic_agreement &&
                          rel(h->med.u_a, h->med.u_a_ccx) <= plastic_agreement;
    const bool near_exact = rel(h->med.u_b, ref) <= plastic_agreement;
    s << "- Hill, " << grouped(h->med.free) << " DOF: within 1e-3 of ccx (u(a), u(b)): **"
      << (near_ccx ? "met" : "NOT met") << "** (" << sci(rel(h->med.u_a, h->med.u_a_ccx)) << ", "
      << sci(rel(h->med.u_b, h->med.u_b_ccx)) << "); u(b) within 1e-3 of the closed form: **"
      << (near_exact ? "met" : "NOT met") << "** (Stratum " << sci(rel(h->med.u_b, ref)) << ", ccx "
      << sci(rel(h->med.u_b_ccx, ref)) << ").\n";
  } else {
    s << "- Hill: not measured in this run.\n";
  }
  if (!tresca.empty()) {
    const TrescaRow& t = tresca.back();
    const double err = rel(t.u_b, hill_u_b(hill_spec()));
    s << "- Hill with Tresca, the material the closed form is exact for (Stratum only), " << grouped(t.free)
      << " DOF: u(b) within 1e-3 of the closed form: **" << (err <= plastic_agreement ? "met" : "NOT met")
      << "** (" << sci(err) << ").\n";
  }
  return s.str();
}

/// What the measured figures say about the targets that are not met (from the rows, no fixed claims).
std::string limits(const std::vector<Row>& rows, const std::vector<TrescaRow>& tresca) {
  std::ostringstream s;
  std::vector<const Row*> lame, hill;
  for (const auto& r : rows)
    if (r.spec.problem != Problem::lame_plane) (r.spec.plastic() ? hill : lame).push_back(&r);
  bool ccx_off = !lame.empty();
  for (const Row* r : lame) {
    const double mine = rel(r->med.u_a, exact_reference(r->spec)),
                 theirs = rel(r->med.u_a_ccx, exact_reference(r->spec));
    ccx_off = ccx_off && r->med.du > elastic_agreement && theirs > 10 * mine;
  }
  if (ccx_off) {
    s << "- The elastic difference is ccx's: against the closed form u(a), Stratum is off by ";
    for (std::size_t i = 0; i < lame.size(); ++i)
      s << (i ? ", " : "") << sci(rel(lame[i]->med.u_a, exact_reference(lame[i]->spec))) << " at "
        << grouped(lame[i]->med.free) << " DOF";
    s << ", ccx by ";
    for (std::size_t i = 0; i < lame.size(); ++i)
      s << (i ? ", " : "") << sci(rel(lame[i]->med.u_a_ccx, exact_reference(lame[i]->spec)));
    s << ".";
    const double first = rel(lame.front()->med.u_a_ccx, exact_reference(lame.front()->spec)),
                 last = rel(lame.back()->med.u_a_ccx, exact_reference(lame.back()->spec));
    if (lame.size() > 1 && last > 0.5 * first)
      s << " ccx's error does not shrink as the mesh is refined, which fits its CAX8 being expanded into 3D "
           "elements spanning a fixed angle about the axis (its manual: the expansion angle is fixed): a "
           "modelling offset of ccx, so no change of Stratum brings the two within 1e-6.";
    std::vector<const Row*> plane;
    for (const auto& r : rows)
      if (r.spec.plane()) plane.push_back(&r);
    if (!plane.empty()) {
      s << " On the same ring in plane strain (CPE8, which ccx expands by a thickness, not an angle) the "
           "largest nodal difference is ";
      for (std::size_t i = 0; i < plane.size(); ++i)
        s << (i ? ", " : "") << sci(plane[i]->med.du) << " at " << grouped(plane[i]->med.free) << " DOF";
      s << " and ccx's u(a) is off the closed form by ";
      for (std::size_t i = 0; i < plane.size(); ++i)
        s << (i ? ", " : "") << sci(rel(plane[i]->med.u_a_ccx, exact_reference(plane[i]->spec)));
      s << " (Stratum ";
      for (std::size_t i = 0; i < plane.size(); ++i)
        s << (i ? ", " : "") << sci(rel(plane[i]->med.u_a, exact_reference(plane[i]->spec)));
      s << ").";
    }
    s << "\n";
  }
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (i + 1 == rows.size() || rows[i].spec.problem != rows[i + 1].spec.problem) {
      const Row* r = &rows[i];
      const auto& m = r->med;
      s << "- Stratum's time on the largest " << r->spec.name << " mesh (" << grouped(m.free)
        << " DOF): build " << fixed(m.build, 3) << " s, run() " << fixed(m.run, 3) << " s, write "
        << fixed(m.write, 3) << " s; run() did " << m.iterations
        << " Newton iteration(s), and one assembly costs " << fixed(m.assembly, 3)
        << " s, one analyze + factorization " << fixed(m.factorize, 3) << " s, so the sparse factorization "
        << (m.factorize > m.assembly ? "dominates" : "does not dominate") << ". ccx did " << m.ccx_iterations
        << " iteration(s) in " << fixed(m.ccx, 2) << " s.\n";
    }
  if (!hill.empty()) {
    const Row* h = hill.back();
    const double ref = hill_u_b(h->spec);
    const double mine = rel(h->med.u_b, ref), theirs = rel(h->med.u_b_ccx, ref),
                 between = rel(h->med.u_b, h->med.u_b_ccx);
    if (mine > plastic_agreement && theirs > plastic_agreement && between < plastic_agreement)
      s << "- Hill's closed form is exact for Tresca (Y = 2 sigma_y/sqrt(3)); for von Mises with nu = 0.3 "
           "sigma_z is not the mean of sigma_r and sigma_theta, so the von Mises solution is only close to "
           "it. "
           "Both codes differ from the closed form u(b) by about the same amount (Stratum "
        << sci(mine) << ", ccx " << sci(theirs) << ") while they agree with each other to " << sci(between)
        << ": the 1e-3 target against this closed form cannot be met by a von Mises material with nu = 0.3, "
           "whichever code.";
    if (mine > plastic_agreement && !tresca.empty()) {
      const TrescaRow& t = tresca.back();
      s << " With Tresca on the same mesh and load (Stratum only) u(b) is off the closed form by "
        << sci(rel(t.u_b, ref)) << " at " << grouped(t.free)
        << " DOF: the von Mises offset is the material's, not the discretization's.";
    }
    s << "\n";
  }
  return s.str();
}

std::string section(const std::vector<Row>& rows, const std::vector<TrescaRow>& tresca, const Options& o,
                    const std::string& load, const std::string& version) {
  const Spec lame = lame_spec(), hill = hill_spec();
  std::ostringstream s;
  s << begin_marker << "\n"
    << "## Stratum and CalculiX side by side (axisymmetric quad8 / CAX8)\n\n"
    << "Generated by `build/release/bin/bench_ccx` (source `tools/benchmarks/bench_ccx.cpp`, columns "
       "explained "
       "in `tools/benchmarks/README.md`) on "
    << today_utc() << ": " << std::thread::hardware_concurrency() << " cores (" << cpu_model() << "), "
    << version << " (Debian `calculix-ccx`, SPOOLES, run with OMP_NUM_THREADS=1), Stratum with "
    << "OPENBLAS_NUM_THREADS=" << env_or("OPENBLAS_NUM_THREADS", "unset")
    << ", OMP_NUM_THREADS=" << env_or("OMP_NUM_THREADS", "unset") << "; load average " << load
    << " at the start. Elastic rows: median of " << o.repeat << ", Hill rows: median of " << o.hill_repeat
    << " (see *n*). The two programs run alternately in one process, so each ratio is measured under the "
       "same load; absolute times on these shared machines vary. Regenerate with "
       "`OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 build/release/bin/bench_ccx` (`--no-write` leaves this "
       "file "
       "alone).\n\n"
    << "Both solve the same mesh: nx x nx/2 square 8-node cells, Stratum's `quad` with 3x3 Gauss and ccx's "
       "CAX8 (full integration; ccx expands it internally into 3D C3D20 elements spanning a small angle, yet "
       "the equation count it prints equals Stratum's free DOF). u_z = 0 on top and bottom, the pressure on "
       "r = a (ccx: `*DLOAD` on the element faces). "
       "*lame*: a = 1, b = 2, height 0.5, E = 1000, nu = 0.3, p = 1, closed form u(a) = "
    << sci(lame_u(lame, lame.a), 6)
    << " m. *lame_ps*: the same ring in plane strain, a quarter ring of nx (radial) x nx/2 (angular) "
       "cells mapped to polar coordinates (midside nodes on the arcs; the same free DOF count), u_y = 0 at "
       "theta = 0 and u_x = 0 at theta = 90 deg, ccx's CPE8 (unit thickness); u(a) is the mean radial "
       "displacement of r = a, with the same closed form. *hill*: a = 0.1, b = 0.2, height 0.05, E = 2.1e8, "
       "nu = 0.3, "
    << "von Mises sigma_y = 2.4e5 perfectly plastic (ccx `*PLASTIC` with one point, small-strain since no "
       "NLGEOM), p = 0.9 P_lim = "
    << fixed(hill.pressure, 0) << " kPa in " << hill.steps
    << " equal increments (ccx `*STATIC,DIRECT`), each code with its default convergence test; closed form "
       "(Tresca with Y = 2 sigma_y/sqrt(3), plastic radius c = "
    << fixed(hill_c(hill), 5) << " m) u(b) = " << sci(hill_u_b(hill), 6)
    << " m, exact for Tresca and only close for von Mises with nu = 0.3.\n\n"
    << "Times in seconds, wall. *Stratum* = `Analysis::from_string` + `run()` + writing node displacements "
       "and integration-point stresses as ccx's `.dat` holds them; *ccx* = the whole ccx process (input "
       "read, its own output). *ratio* = Stratum / ccx (median of the per-repetition ratios). *Δu* = largest "
       "nodal displacement difference / largest displacement; *Δσ* = largest difference of the "
       "element-mean stresses (r, z, theta, rz) / largest one. *ref err* = relative error of u(a) (lame) or "
       "u(b) (hill) against the closed form, Stratum / ccx. *1 assembly*, *1 factorization*: Stratum's "
       "cost of one Newton iteration, measured after the run (one `assemble()` with the tangent; analyze + "
       "factorize with the `auto` linear solver), not part of its time.\n\n"
    << "| case | free DOF | ccx equations | mesh | n | build | run() | write | **Stratum** | **ccx** | "
       "**ratio** | iterations Stratum / ccx | 1 assembly | 1 factorization | Δu | Δσ | u(a) Stratum vs ccx "
       "| "
       "ref err Stratum / ccx |\n"
    << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    const auto& m = r.med;
    const double ref = exact_reference(r.spec);
    const double mine = r.spec.plastic() ? m.u_b : m.u_a, theirs = r.spec.plastic() ? m.u_b_ccx : m.u_a_ccx;
    s << "| " << r.spec.name << " | " << grouped(m.free) << " | " << grouped(m.ccx_equations) << " | "
      << r.size.nx << " x " << r.size.ny << " | " << r.repeat << " | " << fixed(m.build, 3) << " | "
      << fixed(m.run, 3) << " | " << fixed(m.write, 3) << " | **" << fixed(stratum_median(r), 3) << "** | **"
      << fixed(m.ccx, 2) << "** | **" << fixed(r.ratio, 3) << "** | " << m.iterations << " / "
      << m.ccx_iterations << " | " << fixed(m.assembly, 3) << " | " << fixed(m.factorize, 3) << " | "
      << sci(m.du) << " | " << sci(m.ds) << " | " << sci(rel(m.u_a, m.u_a_ccx)) << " | "
      << sci(rel(mine, ref)) << " / " << sci(rel(theirs, ref)) << " |\n";
  }
  if (!tresca.empty()) {
    s << "\n*tresca*: the same Hill cylinder, mesh and load with Tresca, the material the closed form is "
         "exact for: Stratum's `mohr_coulomb` (exact pyramid, closest-point return in principal stresses) "
         "with c = Y/2 = "
      << fixed(0.5 * hill_spec().yield_y(), 0) << " kPa and phi = psi = " << tresca_phi
      << " deg (the friction term moves the strength by less than 2e-6 of c here). ccx has no Tresca "
         "material, so this row is Stratum's alone; *von Mises* is the hill row's u(b) on the same mesh.\n\n"
      << "| case | free DOF | mesh | from_string + run() (s) | iterations | u(b) (m) | closed form (m) | "
         "error | "
         "von Mises u(b) / Tresca u(b) - 1 |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& t : tresca)
      s << "| tresca | " << grouped(t.free) << " | " << t.size.nx << " x " << t.size.ny << " | "
        << fixed(t.run, 3) << " | " << t.iterations << " | " << sci(t.u_b, 6) << " | "
        << sci(hill_u_b(hill_spec()), 6) << " | " << sci(rel(t.u_b, hill_u_b(hill_spec()))) << " | "
        << (t.u_b_vm > 0 ? sci(t.u_b_vm / t.u_b - 1.0) : std::string("-")) << " |\n";
  }
  s << "\nTargets:\n\n"
    << targets(rows, tresca) << "\nWhat limits them:\n\n"
    << limits(rows, tresca) << end_marker << "\n";
  return s.str();
}

} // namespace

int main(int argc, char** argv) {
  const std::string load = load_average();
  Options opt;
  const auto cli =
      stratum::bench::Cli("bench_ccx")
          .number("--max-dof", "largest elastic (Lame) size (default 1e5; sizes ~1e4, 1e5)", opt.max_dof,
                  true)
          .number("--hill-max-dof", "largest plastic (Hill) size (default 1e5; 0 skips Hill)",
                  opt.hill_max_dof, true)
          .count("--repeat", "repetitions of every elastic size, medians reported (default 3)", opt.repeat)
          .count("--hill-repeat", "repetitions of every Hill size (default 1: ccx needs minutes there)",
                 opt.hill_repeat)
          .flag("--no-write", "do not update the docs file", opt.write, false)
          .flag("--keep", "keep the ccx input and output in the temporary directory", opt.keep)
          .docs(opt.docs)
          .plugin_dir(opt.plugin_dir)
          .text("--ccx", "PATH", "the CalculiX program (default: ccx on PATH)", opt.ccx);
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  if (!have_program(opt.ccx)) {
    std::fprintf(stderr, "bench_ccx: CalculiX (%s) is not installed (Debian: apt-get install calculix-ccx)\n",
                 opt.ccx.c_str());
    return 3;
  }
  const std::string version = ccx_version(opt);
  std::string tmpl = (fs::temp_directory_path() / "bench_ccx.XXXXXX").string();
  if (!mkdtemp(tmpl.data())) {
    std::fprintf(stderr, "bench_ccx: cannot create a temporary directory\n");
    return 2;
  }
  const fs::path dir = tmpl;
  std::printf("bench_ccx: %s against Stratum, axisymmetric quad8 / CAX8; %u cores (%s), "
              "OPENBLAS_NUM_THREADS=%s, load %s; times in s, work in %s\n",
              version.c_str(), std::thread::hardware_concurrency(), cpu_model().c_str(),
              env_or("OPENBLAS_NUM_THREADS", "unset").c_str(), load.c_str(), dir.c_str());
  print_header();
  std::vector<Row> rows;
  std::vector<TrescaRow> tresca;
  try {
    for (const Spec& p : {lame_spec(), lame_plane_spec(), hill_spec()}) {
      const double max_dof = p.plastic() ? opt.hill_max_dof : opt.max_dof;
      const int repeat = p.plastic() ? opt.hill_repeat : opt.repeat;
      for (double target : {1e4, 1e5}) {
        if (target > max_dof) break;
        const Size s = size_for(target);
        std::vector<Sample> samples;
        for (int k = 0; k < repeat; ++k) samples.push_back(measure(p, s, opt, dir));
        rows.push_back(summarize(p, s, samples));
        print_row(rows.back());
      }
    }
    for (double target : {1e4, 1e5}) {
      if (target > opt.hill_max_dof) break;
      tresca.push_back(measure_tresca(size_for(target), opt));
      if (const Row* h = find_row(rows, Problem::hill, target)) tresca.back().u_b_vm = h->med.u_b;
      print_tresca(tresca.back());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    if (!opt.keep) fs::remove_all(dir);
    return 2;
  }
  if (!opt.keep) fs::remove_all(dir);
  std::printf("%s%s", targets(rows, tresca).c_str(), limits(rows, tresca).c_str());
  if (opt.write) {
    try {
      stratum::bench::replace_docs_section(opt.docs, begin_marker, end_marker,
                                           section(rows, tresca, opt, load, version));
      std::printf("wrote %s\n", opt.docs.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_ccx: %s\n", e.what());
      return 2;
    }
  }
  return 0;
}
