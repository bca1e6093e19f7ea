// The numerical stability harness shared by tools/benchmarks/bench_stability.cpp and
// tests/test_stability.cpp: scene variants as TOML text, one `stratum run` child process
// per run (with a time limit), and the classification of its outcome from the exit
// status, the messages and every output file it wrote.
//
// Outcomes:
//   converged     exit 0, every stage reached load factor 1, all outputs finite
//   stopped       exit 0 with the "stopped:" line of a stage with until_failure or
//                 stop_settlement (the documented end of loading to failure: a collapse or
//                 the settlement limit)
//   numerical     exit 4 with the "stopped: numerical failure" line: an until_failure stage
//                 whose step did not converge while the structure was still stiff (a defect
//                 of the solver settings or the solver, counted as such; not a crash)
//   failed        exit 2 with one "stratum: ..." line on stderr (a clean numerical failure)
//   input_error   exit 1 (the variant is not a valid scene: a harness bug)
//   crash         a signal, or an exit status other than 0, 1, 2, 4 (e.g. 3, internal error)
//   timeout       still running after the time limit (killed)
//   nan_inf       some output (VTK arrays, CSV files, the printed table) holds NaN or Inf
//   silent        exit 0 but not a converged end state (a stage short of load factor 1
//                 without a stop line, no diagnostics), or exit 2 without a clear message
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace stratum::bench::stability {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- TOML text editing

/// Position of the line following the header line `header` (e.g. "[analysis]"), or npos.
inline std::size_t table_body(const std::string& text, const std::string& header) {
  std::size_t at = 0;
  while ((at = text.find(header, at)) != std::string::npos) {
    const bool line_start = at == 0 || text[at - 1] == '\n';
    const auto eol = text.find('\n', at);
    if (line_start) return eol == std::string::npos ? text.size() : eol + 1;
    at += header.size();
  }
  return std::string::npos;
}

/// End of the table whose body starts at `body`: the next line starting with '['.
inline std::size_t table_end(const std::string& text, std::size_t body) {
  std::size_t at = body;
  while (at < text.size()) {
    if (text[at] == '[') return at;
    const auto eol = text.find('\n', at);
    if (eol == std::string::npos) return text.size();
    at = eol + 1;
  }
  return text.size();
}

/// Line [begin, end) in [body, stop) that sets `key`, or npos.
inline std::pair<std::size_t, std::size_t> find_key(const std::string& text, std::size_t body,
                                                    std::size_t stop, const std::string& key) {
  std::size_t at = body;
  while (at < stop) {
    auto eol = text.find('\n', at);
    if (eol == std::string::npos) eol = text.size();
    std::size_t k = at;
    while (k < eol && (text[k] == ' ' || text[k] == '\t')) ++k;
    if (text.compare(k, key.size(), key) == 0) {
      std::size_t j = k + key.size();
      while (j < eol && (text[j] == ' ' || text[j] == '\t')) ++j;
      if (j < eol && text[j] == '=') return {at, eol == text.size() ? eol : eol + 1};
    }
    at = eol + 1;
  }
  return {std::string::npos, std::string::npos};
}

/// Sets `key = value` (value is TOML text) in the table starting at `body`.
inline std::string set_at(std::string text, std::size_t body, const std::string& key,
                          const std::string& value) {
  const auto stop = table_end(text, body);
  const auto [b, e] = find_key(text, body, stop, key);
  const std::string line = key + " = " + value + "\n";
  if (b == std::string::npos) return text.insert(body, line);
  return text.replace(b, e - b, line);
}

/// Sets `key = value` in the table `header` (appended at the end when the table is missing).
inline std::string set_key(std::string text, const std::string& header, const std::string& key,
                           const std::string& value) {
  auto body = table_body(text, header);
  if (body == std::string::npos) {
    if (!text.empty() && text.back() != '\n') text += '\n';
    text += header + "\n";
    body = text.size();
  }
  return set_at(std::move(text), body, key, value);
}

/// Removes `key` from the table `header` (no-op when absent).
inline std::string remove_key(std::string text, const std::string& header, const std::string& key) {
  const auto body = table_body(text, header);
  if (body == std::string::npos) return text;
  const auto [b, e] = find_key(text, body, table_end(text, body), key);
  if (b != std::string::npos) text.erase(b, e - b);
  return text;
}

/// Removes the whole table `header` (its header line and body).
inline std::string remove_table(std::string text, const std::string& header) {
  const auto body = table_body(text, header);
  if (body == std::string::npos) return text;
  const auto start = text.rfind(header, body - 1);
  return text.erase(start, table_end(text, body) - start);
}

/// Number of [[stages]] of a scene.
inline int count_stages(const std::string& text) {
  int n = 0;
  std::size_t at = 0;
  while ((at = text.find("[[stages]]", at)) != std::string::npos) {
    if (at == 0 || text[at - 1] == '\n') ++n;
    at += 10;
  }
  return n;
}

/// Sets the number of load steps: `steps` of [analysis] for a single-stage scene, of the
/// last [[stages]] table for a staged one (the loading stage).
inline std::string set_steps(const std::string& text, int steps) {
  if (count_stages(text) == 0) return set_key(text, "[analysis]", "steps", std::to_string(steps));
  const auto at = text.rfind("\n[[stages]]\n");
  if (at == std::string::npos) throw std::runtime_error("set_steps: no [[stages]] table");
  return set_at(text, at + 12, "steps", std::to_string(steps));
}

/// Selects the global solver; the scene's [solver] table is kept for the Newton family
/// (its options, e.g. line_search, apply to them) and dropped for the others.
inline std::string set_solver(std::string text, const std::string& solver) {
  if (solver != "newton" && solver != "modified_newton" && solver != "initial_stiffness")
    text = remove_table(std::move(text), "[solver]");
  return set_key(std::move(text), "[analysis]", "solver", "\"" + solver + "\"");
}

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// ---------------------------------------------------------------- scenes and variants

struct Scene {
  std::string name;        ///< "strip_footing", "strip_footing nu=0.499", ...
  std::string text;        ///< the TOML of the scene
  std::string integ_table; ///< material table whose integrator is varied ("" : none)
  std::string integ_key;   ///< "integrator" or "update" (Duncan-Chang)
  std::vector<std::string> integrators;
};

inline const std::vector<std::string>& plasticity_integrators() {
  static const std::vector<std::string> v{"forward_euler", "modified_euler", "trapezoidal",
                                          "midpoint",      "cutting_plane",  "closest_point"};
  return v;
}

/// A scene of inputs/ by its path relative to the source tree.
/// The text without its [[checks]] tables (each up to the next table header).
inline std::string strip_checks(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  bool skip = false;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] == '[') skip = line.rfind("[[checks]]", 0) == 0;
    if (!skip) out += line + "\n";
  }
  return out;
}

/// The scene's top-level `include = [...]` entries as absolute paths (relative ones are
/// relative to the scene's folder), so that the text runs from any folder; `included` (if given)
/// receives those paths.
inline std::string absolute_includes(const std::string& text, const fs::path& scene_dir,
                                     std::vector<fs::path>* included = nullptr) {
  // The top-level key: a line `include = "a.toml"` or `include = [ "a.toml", ... ]` (comments allowed).
  std::size_t at = 0;
  for (;;) {
    const bool line_start = at == 0 || text[at - 1] == '\n';
    if (line_start && text.compare(at, 7, "include") == 0) {
      const auto eq = text.find_first_not_of(" \t", at + 7);
      if (eq != std::string::npos && text[eq] == '=') break;
    }
    at = text.find("include", at + 1);
    if (at == std::string::npos) return text;
  }
  std::size_t i = text.find_first_not_of(" \t", text.find('=', at) + 1);
  if (i == std::string::npos) return text;
  const bool list = text[i] == '[';
  std::string out = text.substr(0, i);
  // Rewrite every quoted entry until the value ends: after the one string, or at the list's `]`.
  while (i < text.size()) {
    const char ch = text[i];
    if (ch == '#') { // a comment inside the list: copied to its line's end
      const auto eol = text.find('\n', i);
      out += text.substr(i, eol == std::string::npos ? std::string::npos : eol - i);
      if (eol == std::string::npos) return out;
      i = eol;
      continue;
    }
    if (ch == '"') {
      const auto e = text.find('"', i + 1);
      if (e == std::string::npos) return text; // malformed: left to the scene reader
      const std::string entry = text.substr(i + 1, e - i - 1);
      const fs::path p(entry);
      const fs::path file = p.is_absolute() ? p : (scene_dir / p).lexically_normal();
      out += '"' + file.string() + '"';
      if (included) included->push_back(file);
      i = e + 1;
      if (!list) break;
      continue;
    }
    out += ch;
    ++i;
    if (list && ch == ']') break;
  }
  return out + text.substr(i);
}

inline Scene input_scene(const fs::path& source_dir, const std::string& rel) {
  Scene s;
  s.name = fs::path(rel).stem().string();
  // The scene's [[checks]] state the closed form of the scene as written: a variant (other
  // steps, nu = 0.499) is not that scene, and the matrix tests stability, not accuracy.
  std::vector<fs::path> included;
  s.text = absolute_includes(strip_checks(read_text(source_dir / rel)), (source_dir / rel).parent_path(),
                             &included);
  if (s.text.empty()) throw std::runtime_error("cannot read " + (source_dir / rel).string());
  // The models of the scene and of the material files it includes (inputs/materials/).
  std::string models = s.text;
  for (const auto& f : included) models += "\n" + read_text(f);
  if (models.find("model = \"von_mises\"") != std::string::npos) {
    s.integ_table = s.name == "hill_cylinder" ? "[materials.steel]" : "[materials.clay]";
    s.integ_key = "integrator";
    s.integrators = plasticity_integrators();
  } else if (models.find("model = \"duncan_chang\"") != std::string::npos) {
    s.integ_table = "[materials.loess]";
    s.integ_key = "update";
    s.integrators = {"explicit", "incremental"};
  } else if (models.find("model = \"cap_sandler\"") != std::string::npos) {
    s.integ_table = "[materials.loess]";
    s.integ_key = "integrator";
    s.integrators = {"closest_point", "sandler_rubin"};
  }
  return s;
}

/// The variant of `base` with `key = value` in `table`, named "<base> <label>".
inline Scene variant(const Scene& base, const std::string& label, const std::string& table,
                     const std::string& key, const std::string& value) {
  Scene s = base;
  s.name = base.name + " " + label;
  s.text = set_key(base.text, table, key, value);
  return s;
}

/// Strip footing with a Mohr-Coulomb soil of friction angle 1 degree (c = 100 kPa).
inline Scene strip_footing_mohr_coulomb(const Scene& strip) {
  Scene s = strip;
  s.name = "strip_footing mohr_coulomb phi=1";
  s.text = remove_key(strip.text, "[materials.clay]", "sigma_y");
  s.text = set_key(s.text, "[materials.clay]", "model", "\"mohr_coulomb\"");
  s.text = set_key(s.text, "[materials.clay]", "c", "100.0");
  s.text = set_key(s.text, "[materials.clay]", "phi", "1.0");
  s.text = set_key(s.text, "[materials.clay]", "form", "\"rounded\""); // the integrators apply to it
  return s;
}

/// A triaxial sample (axisymmetric, 2 x 4 quad8 cells, r <= 0.05 m, h = 0.1 m) with a
/// proportional load: lateral pressure p3 and axial pressure p1 at load factor 1.
inline std::string sample_scene(const std::string& title, const std::string& material, double p3, double p1) {
  std::ostringstream t;
  t.precision(12);
  t << "title = \"" << title
    << "\"\n[analysis]\nformulation = \"axisymmetric\"\nsteps = 10\nmax_cutbacks = 4\n"
    << "[convergence]\nforce_rtol = 1e-8\nmax_iterations = 40\n"
    << "[mesh]\ngenerator = \"blocks\"\nnodes_per_cell = 8\n[[mesh.blocks]]\nname = \"sample\"\n"
    << "x = [0.0, 0.05]\ny = [0.0, 0.1]\nnx = 2\nny = 4\n"
    << material << "[[domains]]\ncells = \"all\"\nelement = \"quad\"\nmaterial = \"soil\"\n"
    << "[[constraints]]\nnodes = \"left\"\nux = 0.0\n[[constraints]]\nnodes = \"bottom\"\nuy = 0.0\n"
    << "[[loads]]\ntype = \"pressure\"\nedges = \"sample.right\"\np = " << p3 << "\n"
    << "[[loads]]\ntype = \"pressure\"\nedges = \"sample.top\"\np = " << p1 << "\n"
    << "[output]\nvtk = true\nintegration_points = true\n";
  return t.str();
}

/// Duncan-Chang near failure: the loess set (a) of inputs/point, sigma_3 = 50 kPa and the
/// deviator at `level` times the failure deviator (2 c cos phi + 2 sigma_3 sin phi)/(1 - sin phi).
inline Scene duncan_chang_near_failure(double level) {
  const double pi = 3.14159265358979323846;
  const double s3 = 50.0, c = 10.0, phi = 26.0 * pi / 180.0;
  const double qf = (2 * c * std::cos(phi) + 2 * s3 * std::sin(phi)) / (1 - std::sin(phi));
  Scene s;
  std::ostringstream lbl;
  lbl << "duncan_chang sample q/q_f=" << level;
  s.name = lbl.str();
  const std::string mat =
      "[materials.soil]\nmodel = \"duncan_chang\"\nform = \"E_nu\"\nupdate = \"incremental\"\n"
      "K = 500.0\nn = 0.82\nR_f = 0.80\nphi = 26.0\nc = 10.0\nK_ur = 800.0\nG = 0.18\n"
      "F = 0.22\nd = 20.0\n";
  s.text = sample_scene(s.name, mat, s3, s3 + level * qf);
  s.integ_table = "[materials.soil]";
  s.integ_key = "update";
  s.integrators = {"explicit", "incremental"};
  return s;
}

/// Cap model with its cap at the apex of the envelope (Z = 0: the cap starts at J1 = 0)
/// under a small confinement, so the stress path runs through the cap-envelope corner.
inline Scene cap_near_apex() {
  Scene s;
  s.name = "cap_sandler sample, cap at the apex";
  const std::string mat =
      "[materials.soil]\nmodel = \"cap_sandler\"\nE = 18000.0\nnu = 0.30\nT_CUT = 30.0\n"
      "A = 190.0\nB = 0.0015\nC = 110.0\nD = 0.00023\nR = 2.50\nW = 0.06\nF_CUT = 364.34\n"
      "Z = 0.0\nintegrator = \"closest_point\"\n";
  s.text = sample_scene(s.name, mat, 2.0, 130.0);
  s.integ_table = "[materials.soil]";
  s.integ_key = "integrator";
  s.integrators = {"closest_point", "sandler_rubin"};
  return s;
}

/// The scene text of one run.
inline std::string run_text(const Scene& s, const std::string& solver, const std::string& integrator,
                            int steps) {
  std::string t = set_steps(s.text, steps);
  t = set_solver(std::move(t), solver);
  if (!integrator.empty() && !s.integ_table.empty())
    t = set_key(std::move(t), s.integ_table, s.integ_key, "\"" + integrator + "\"");
  return t;
}

// ---------------------------------------------------------------- running and classifying

enum class Kind { converged, stopped, numerical, failed, input_error, crash, timeout, nan_inf, silent };

inline const char* to_string(Kind k) {
  switch (k) {
  case Kind::converged:
    return "converged";
  case Kind::stopped:
    return "stopped";
  case Kind::numerical:
    return "numerical";
  case Kind::failed:
    return "failed";
  case Kind::input_error:
    return "input_error";
  case Kind::crash:
    return "crash";
  case Kind::timeout:
    return "timeout";
  case Kind::nan_inf:
    return "nan_inf";
  case Kind::silent:
    return "silent";
  }
  return "?";
}

/// A bug of the framework or the harness (everything but converged, stopped, numerical, failed).
/// A numerical stop is a defect of the solver or its settings, counted apart (not a bug of the
/// framework: the run said what happened and wrote what it had).
inline bool is_bug(Kind k) {
  return k != Kind::converged && k != Kind::stopped && k != Kind::numerical && k != Kind::failed;
}

struct Outcome {
  Kind kind = Kind::crash;
  int exit_code = -1;
  int signal = 0;
  double seconds = 0;
  std::string message;   ///< the failure line, or what makes the run a bug
  int files_checked = 0; ///< output files scanned for NaN/Inf
  long values_checked = 0;
};

/// A token that parses completely as a non-finite number ("nan", "-inf", "NaN", ...).
inline bool non_finite_token(const std::string& tok) {
  if (tok.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(tok.c_str(), &end);
  return end == tok.c_str() + tok.size() && !std::isfinite(v);
}

/// First non-finite token of a text (CSV, console output), or "".
/// Quoted text (the message column of diagnostics.csv, e.g. "residual is NaN or Inf") is words,
/// not values, and is skipped.
inline std::string scan_text(const std::string& text, long& values) {
  std::string tok;
  bool quoted = false;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    const char ch = i < text.size() ? text[i] : '\n';
    if (ch == '"') quoted = !quoted;
    if (quoted && ch != '"') continue;
    if (ch == ',' || ch == ';' || ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r' || ch == '"' ||
        ch == '(' || ch == ')' || ch == '=' || ch == '[' || ch == ']') {
      if (!tok.empty()) {
        ++values;
        if (non_finite_token(tok)) return tok;
      }
      tok.clear();
    } else {
      tok += ch;
    }
  }
  return {};
}

/// Name of the first array of `ds` (points included) with a non-finite value, or "".
/// A named history variable (docs/design.md, "Output") is NaN at every point of a domain whose
/// material has no component of that name: with a point array `domain`, an array that is NaN at
/// all points of some domains and finite at all points of the others is complete, not a failure.
inline std::string scan_dataset(vtkDataSet* ds, long& values) {
  vtkDataArray* domain = ds->GetPointData() ? ds->GetPointData()->GetArray("domain") : nullptr;
  auto scan = [&](vtkDataArray* a) -> bool {
    if (!a) return false;
    const vtkIdType n = a->GetNumberOfTuples() * a->GetNumberOfComponents();
    values += n;
    const bool per_domain = domain && a != domain && a->GetNumberOfTuples() == domain->GetNumberOfTuples();
    std::map<long long, std::pair<bool, bool>> seen; // domain -> (a finite value, a NaN)
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
      for (int c = 0; c < a->GetNumberOfComponents(); ++c) {
        const double v = a->GetComponent(i, c);
        if (std::isfinite(v)) {
          if (per_domain) seen[static_cast<long long>(domain->GetComponent(i, 0))].first = true;
          continue;
        }
        if (!per_domain || !std::isnan(v)) return true;
        seen[static_cast<long long>(domain->GetComponent(i, 0))].second = true;
      }
    for (const auto& [d, fin_nan] : seen)
      if (fin_nan.first && fin_nan.second) return true; // a NaN among a domain's values
    return false;
  };
  if (auto* ps = vtkPointSet::SafeDownCast(ds); ps && ps->GetPoints() && scan(ps->GetPoints()->GetData()))
    return "points";
  for (auto* data :
       {static_cast<vtkFieldData*>(ds->GetPointData()), static_cast<vtkFieldData*>(ds->GetCellData())})
    for (int i = 0; i < data->GetNumberOfArrays(); ++i)
      if (scan(data->GetArray(i))) return data->GetArrayName(i) ? data->GetArrayName(i) : "array";
  return {};
}

/// Scans every .vtu, .vtp and .csv file under `dir`; returns "<file>: <what>" of the first
/// non-finite value, or "".
inline std::string scan_outputs(const fs::path& dir, Outcome& o) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return {};
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    const auto ext = e.path().extension().string();
    std::string bad;
    if (ext == ".vtu") {
      vtkNew<vtkXMLUnstructuredGridReader> r;
      r->SetFileName(e.path().c_str());
      r->Update();
      if (!r->GetOutput() || r->GetErrorCode() != 0) return e.path().filename().string() + ": unreadable";
      bad = scan_dataset(r->GetOutput(), o.values_checked);
    } else if (ext == ".vtp") {
      vtkNew<vtkXMLPolyDataReader> r;
      r->SetFileName(e.path().c_str());
      r->Update();
      if (!r->GetOutput() || r->GetErrorCode() != 0) return e.path().filename().string() + ": unreadable";
      bad = scan_dataset(r->GetOutput(), o.values_checked);
    } else if (e.path().filename() == "diagnostics.csv") {
      // A rejected attempt (accepted = 0) may record the NaN/Inf residual that made the step
      // driver cut it back: that is the status flowing back, not a result. Accepted rows are
      // results and must be finite.
      std::istringstream in(read_text(e.path()));
      std::string kept, line;
      while (std::getline(in, line)) {
        const auto c1 = line.find(','), c2 = c1 == std::string::npos ? c1 : line.find(',', c1 + 1);
        if (c2 == std::string::npos || line.compare(c2 + 1, 2, "0,") != 0) kept += line + "\n";
      }
      bad = scan_text(kept, o.values_checked);
    } else if (ext == ".csv") {
      bad = scan_text(read_text(e.path()), o.values_checked);
    } else {
      continue;
    }
    ++o.files_checked;
    if (!bad.empty()) return e.path().filename().string() + ": " + bad;
  }
  return {};
}

/// Checks diagnostics.csv of a run that exited with 0: every stage with steps ends at load
/// factor 1, except the last one when the run printed a stop line. Returns "" or the problem.
inline std::string check_diagnostics(const fs::path& csv, bool stopped) {
  const std::string text = read_text(csv);
  if (text.empty()) return "no diagnostics.csv";
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);     // header
  std::map<int, double> last; // stage -> load factor of its last accepted step
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string stage, step, accepted, lambda_n, lambda;
    std::getline(l, stage, ',');
    std::getline(l, step, ',');
    std::getline(l, accepted, ',');
    std::getline(l, lambda_n, ',');
    std::getline(l, lambda, ',');
    if (accepted == "1") last[std::stoi(stage)] = std::strtod(lambda.c_str(), nullptr);
  }
  if (last.empty()) return "no accepted step in diagnostics.csv";
  const int final_stage = last.rbegin()->first;
  for (const auto& [stage, lambda] : last) {
    if (stopped && stage == final_stage) continue;
    if (!(std::abs(lambda - 1.0) < 1e-9)) {
      std::ostringstream m;
      m << "stage " << stage << " ended at load factor " << lambda << " without a failure or stop message";
      return m.str();
    }
  }
  return {};
}

/// Runs `stratum run scene.toml --out DIR/out` in DIR (created afresh) with a time limit,
/// then classifies it.
inline Outcome run_case(const fs::path& stratum_exe, const std::string& text, const fs::path& dir,
                        double timeout) {
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  const fs::path scene = dir / "scene.toml", out = dir / "out", so = dir / "stdout.txt",
                 se = dir / "stderr.txt";
  {
    std::ofstream f(scene, std::ios::binary);
    f << text;
  }
  Outcome o;
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    setpgid(0, 0);
    const int fo = open(so.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int fe = open(se.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fo < 0 || fe < 0) _exit(127);
    dup2(fo, STDOUT_FILENO);
    dup2(fe, STDERR_FILENO);
    setenv("OPENBLAS_NUM_THREADS", "1", 1);
    const std::string exe = stratum_exe.string(), sc = scene.string(), od = out.string();
    const char* argv[] = {exe.c_str(), "run", sc.c_str(), "--out", od.c_str(), nullptr};
    execv(exe.c_str(), const_cast<char* const*>(argv));
    _exit(127);
  }
  int status = 0;
  bool timed_out = false;
  for (;;) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout) {
      kill(-pid, SIGKILL);
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string out_text = read_text(so);
  // Progress lines (printed every few seconds when stderr is not a terminal) are not messages.
  std::string err_text;
  {
    std::istringstream all(read_text(se));
    for (std::string line; std::getline(all, line);)
      if (line.rfind("progress: ", 0) != 0) err_text += line + "\n";
  }
  std::string err_line = err_text;
  while (!err_line.empty() && (err_line.back() == '\n' || err_line.back() == '\r')) err_line.pop_back();
  if (const auto cr = err_line.rfind('\r'); cr != std::string::npos) err_line = err_line.substr(cr + 1);
  if (timed_out) {
    o.kind = Kind::timeout;
    o.message = "killed after " + std::to_string(static_cast<int>(timeout)) + " s";
    return o;
  }
  if (WIFSIGNALED(status)) {
    o.kind = Kind::crash;
    o.signal = WTERMSIG(status);
    o.message = std::string("signal ") + std::to_string(o.signal) + " (" + strsignal(o.signal) + ")";
    if (!err_line.empty()) o.message += ": " + err_line.substr(0, 300);
    return o;
  }
  o.exit_code = WEXITSTATUS(status);
  // NaN/Inf anywhere in what was written or printed, whatever the exit status.
  std::string bad = scan_outputs(out, o);
  if (bad.empty()) {
    const std::string t = scan_text(out_text, o.values_checked);
    if (!t.empty()) bad = "stdout: " + t;
  }
  const bool one_line =
      !err_line.empty() && err_line.find('\n') == std::string::npos && err_line.rfind("stratum: ", 0) == 0;
  if (o.exit_code == 0 || o.exit_code == 4) {
    const bool stopped = out_text.find("\nstopped: ") != std::string::npos;
    const bool numerical = out_text.find("\nstopped: numerical failure") != std::string::npos;
    if (numerical != (o.exit_code == 4)) {
      o.kind = Kind::silent;
      o.message = "exit " + std::to_string(o.exit_code) + (numerical ? " with" : " without") +
                  " the 'stopped: numerical failure' line";
      return o;
    }
    if (!bad.empty()) {
      o.kind = Kind::nan_inf;
      o.message = bad;
      return o;
    }
    if (out_text.rfind("done: ", 0) != 0) {
      o.kind = Kind::silent;
      o.message = "exit 0 without the 'done:' line";
      return o;
    }
    if (const auto d = check_diagnostics(out / "diagnostics.csv", stopped); !d.empty()) {
      o.kind = Kind::silent;
      o.message = d;
      return o;
    }
    o.kind = numerical ? Kind::numerical : stopped ? Kind::stopped : Kind::converged;
    if (stopped) {
      const auto at = out_text.find("\nstopped: ");
      o.message = out_text.substr(at + 1, out_text.find('\n', at + 1) - at - 1);
    }
    return o;
  }
  if (o.exit_code == 1) {
    o.kind = Kind::input_error;
    o.message = err_line;
    return o;
  }
  if (o.exit_code == 2) {
    if (!bad.empty()) {
      o.kind = Kind::nan_inf;
      o.message = bad + " (after: " + err_line + ")";
    } else if (!one_line) {
      o.kind = Kind::silent;
      o.message = "exit 2 without one clear message line: '" + err_text.substr(0, 300) + "'";
    } else {
      o.kind = Kind::failed;
      o.message = err_line;
    }
    return o;
  }
  o.kind = Kind::crash;
  o.message = "exit status " + std::to_string(o.exit_code) + ": " + err_line.substr(0, 300);
  return o;
}

} // namespace stratum::bench::stability
