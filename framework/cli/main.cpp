// stratum: the command-line front end.
//
//   stratum run SCENE.toml [--out DIR] [--restart-from CHECKPOINT] [--verbose]
//   stratum check SCENE.toml
//   stratum plugins [--describe NAME]
//   stratum fit TARGET CSV... [-o FILE]   (framework/cli/fit.cpp)
//   stratum sweep STUDY.toml [--out DIR]  (framework/cli/sweep.cpp; also under mpirun)
//   stratum --version
//
// Errors are one line on stderr and a non-zero exit code.
#include "fit.hpp"
#include "stratum/analysis.hpp"
#include "stratum/plugin.hpp"
#include "stratum/plugin_loader.hpp"
#include "stratum/point_driver.hpp"
#include "sweep.hpp"

#include <unistd.h>

#include <csignal>

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// The signal that asked the run to end (0: none). The one mutable global of the program: a
/// signal handler can only reach a sig_atomic_t; the run polls it after every accepted step.
volatile std::sig_atomic_t stop_signal = 0;

extern "C" void on_stop_signal(int signo) { stop_signal = signo; }

void catch_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

using namespace stratum;

constexpr const char* usage =
    "usage: stratum run SCENE.toml [--out DIR] [--restart-from CHECKPOINT] [--verbose]\n"
    "       stratum check SCENE.toml\n"
    "       stratum point POINT.toml [--out FILE.csv]\n"
    "       stratum plugins [--describe NAME]\n"
    "       stratum fit TARGET CSV... [-o FILE.toml]\n"
    "       stratum sweep STUDY.toml [--out DIR] [--print-scene INDEX]   (also under mpirun -n N)\n"
    "       stratum --version\n"
    "exit status: 0 done (a collapse or a settlement limit of the last stage included), 1 bad input,\n"
    "  2 a stage failed, 3 internal error, 4 an until_failure stage stopped by a numerical failure\n"
    "  (not a collapse), 5 a [[checks]] entry failed, 130/143 interrupted by SIGINT/SIGTERM\n";

constexpr PluginKind kinds[] = {PluginKind::element, PluginKind::material, PluginKind::contact_law,
                                PluginKind::solver};

void describe(const Registry& reg, PluginKind kind, const std::string& name, bool full) {
  std::string summary, library;
  const Schema& s = reg.schema(kind, name, &summary, &library);
  std::cout << to_string(kind) << " " << name << ": " << summary << "\n";
  if (full) std::cout << "  library: " << library << "\n";
  for (const auto& p : s.specs()) {
    std::cout << "  " << std::left << std::setw(18) << p.name << " " << std::setw(8) << to_string(p.type)
              << " " << std::setw(7) << (p.unit.empty() ? "-" : p.unit) << " " << p.allowed();
    if (p.fallback) {
      std::ostringstream d;
      std::visit(
          [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::vector<double>>) {
              d << "[";
              for (std::size_t i = 0; i < v.size(); ++i) d << (i ? ", " : "") << v[i];
              d << "]";
            } else if constexpr (std::is_same_v<T, bool>) {
              d << (v ? "true" : "false");
            } else if constexpr (std::is_same_v<T, std::string>) {
              d << '"' << v << '"';
            } else {
              d << v;
            }
          },
          *p.fallback);
      std::cout << ", default " << d.str();
    } else {
      std::cout << ", required";
    }
    std::cout << "\n      " << p.meaning << "\n";
  }
}

int plugins(const std::vector<std::string>& args) {
  PluginCatalog catalog(PluginCatalog::default_directories());
  Registry reg;
  catalog.require_all(reg);
  if (args.size() >= 2 && args[0] == "--describe") {
    for (PluginKind k : kinds)
      if (reg.has(k, args[1])) {
        describe(reg, k, args[1], true);
        return 0;
      }
    std::string known;
    for (PluginKind k : kinds)
      for (const auto& n : reg.names(k)) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown plugin '" + args[1] + "'; known: " + known);
  }
  if (!args.empty()) throw Error("plugins: unexpected argument '" + args[0] + "'; allowed: --describe NAME");
  for (PluginKind k : kinds)
    for (const auto& n : reg.names(k)) describe(reg, k, n, false);
  return 0;
}

int point(const std::vector<std::string>& args) {
  std::string file, out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out") {
      if (i + 1 >= args.size()) throw Error("--out needs a file name");
      out = args[++i];
    } else if (!args[i].empty() && args[i][0] == '-') {
      throw Error("unknown option '" + args[i] + "'; allowed: --out FILE.csv");
    } else if (file.empty()) {
      file = args[i];
    } else {
      throw Error("more than one point file given ('" + file + "', '" + args[i] + "')");
    }
  }
  if (file.empty()) throw Error("no point file given (see stratum --help)");
  if (out.empty())
    out = (std::filesystem::path("out") / (std::filesystem::path(file).stem().string() + ".csv")).string();
  // The CSV is written to a temporary file and renamed over the target: a symlink or a device
  // there would be replaced by a regular file (as root, /dev/full was), so only a regular file
  // or a new name is taken.
  if (std::error_code ec; std::filesystem::exists(std::filesystem::symlink_status(out, ec)) &&
                          !std::filesystem::is_regular_file(std::filesystem::symlink_status(out, ec)))
    throw Error("--out '" + out +
                "' exists and is not a regular file (a symlink, folder or device); give a new "
                "or a regular file name");
  const auto driver = PointDriver::from_file(file);
  const PointRun r = driver->run();
  PointDriver::write_csv(r, out); // what was computed is kept, also after a failure
  if (!r.outcome.ok()) {
    std::cerr << "stratum: " << file << ": " << to_string(r.outcome.status) << ": " << r.outcome.message
              << "\n";
    return 2;
  }
  std::cout << "done: " << r.rows.size() - 1 << " steps\nresults: " << out << "\n";
  return 0;
}

int run(const std::vector<std::string>& args, bool check_only) {
  std::string scene, out, restart;
  bool verbose = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out" && !check_only) {
      if (i + 1 >= args.size()) throw Error("--out needs a directory");
      out = args[++i];
    } else if (args[i] == "--restart-from" && !check_only) {
      if (i + 1 >= args.size()) throw Error("--restart-from needs a checkpoint file");
      restart = args[++i];
    } else if (args[i] == "--verbose" && !check_only) {
      verbose = true;
    } else if (!args[i].empty() && args[i][0] == '-') {
      throw Error("unknown option '" + args[i] +
                  "'; allowed: --out DIR, --restart-from CHECKPOINT, --verbose (see stratum --help)");
    } else if (scene.empty()) {
      scene = args[i];
    } else {
      throw Error("more than one scene file given ('" + scene + "', '" + args[i] + "')");
    }
  }
  if (scene.empty()) throw Error("no scene file given (see stratum --help)");
  RunOptions opts;
  opts.out_dir = out;
  opts.restart_from = restart;
  const bool tty = isatty(STDERR_FILENO) != 0;
  opts.on_record = [&](const StepRecord& r) {
    if (!verbose) return;
    std::cerr << "step " << r.step << " lambda " << r.lambda << " iterations " << r.iterations
              << " cut-backs " << r.cutbacks << " rate " << r.contraction << " order " << r.order << " time "
              << r.seconds << " s |R|:";
    for (double x : r.residual_norms) std::cerr << " " << x;
    std::cerr << "\n";
  };
  opts.interrupted = [] { return stop_signal != 0; };
  opts.on_step = [&](int step, int steps, double lambda, const StepReport& rep) {
    if (verbose) {
      return; // on_record prints the full line
    } else if (tty) {
      std::cerr << "\rstep " << step << "/" << steps << "  load factor " << std::fixed << std::setprecision(4)
                << lambda << "  iterations " << rep.iterations << std::defaultfloat << std::flush;
    }
  };
  auto analysis = Analysis::from_file(scene, opts);
  if (check_only) {
    const auto& m = analysis->model();
    std::cout << scene << ": ok (" << m.mesh.nodes.size() << " nodes, " << m.mesh.cells.size() << " cells, "
              << m.dofs.free_count << " unknowns, " << analysis->opened_libraries().size()
              << " plugin libraries)\n";
    return 0;
  }
  catch_stop_signals();
  const RunSummary s = analysis->run();
  if (tty && !verbose) std::cerr << "\n";
  if (!s.outcome.ok()) {
    std::cerr << "stratum: " << scene << ": " << to_string(s.outcome.status) << ": " << s.outcome.message
              << "\n";
    return 2;
  }
  std::cout << "done: " << s.steps_done << " steps";
  if (s.cutbacks) std::cout << " (" << s.cutbacks << " cut-backs)";
  std::cout << "\n";
  {
    const RunTimes& t = s.times;
    std::cout << std::fixed << std::setprecision(3) << "time: " << t.total
              << " s: assembly and stress update " << t.assembly << " s (" << t.assemblies
              << "), linear solver " << t.analyze + t.factorize + t.solve << " s (analyze " << t.analyze
              << " x" << t.analyses << ", factorize " << t.factorize << " x" << t.factorizations << ", solve "
              << t.solve << " x" << t.solves << "), output " << t.output << " s, checkpoints " << t.checkpoint
              << " s\n"
              << std::defaultfloat;
  }
  if (s.stop_reason == "collapse" || s.stop_reason == "numerical") {
    std::ostringstream ratio;
    ratio << std::setprecision(3) << s.stiffness_ratio;
    if (s.stop_reason == "collapse")
      std::cout << "stopped: collapse: a load step found no equilibrium after its cut-backs, and the "
                   "structure had lost its stiffness (the last converged step's is "
                << ratio.str() << " of the stage's first); the table ends at the last converged level\n";
    else
      std::cout << "stopped: numerical failure: a load step did not converge after its cut-backs "
                   "although the structure was still stiff (the last converged step's stiffness is "
                << ratio.str()
                << " of the stage's first): this is not a collapse load; the table ends at the last "
                   "converged level (see diagnostics.csv)\n";
    // The failed step's message (its residual may be NaN) is a diagnostic, not a result: stderr.
    std::cerr << "stratum: the step that stopped the run: " << s.stop_message << "\n";
  } else if (s.stop_reason == "settlement")
    std::cout << "stopped: the settlement limit of the stage is exceeded\n";

  if (!s.load_settlement.empty()) {
    std::cout << "\n  load (kN)   settlement (mm)\n";
    for (const auto& r : s.load_settlement)
      std::cout << "  " << std::setw(9) << std::fixed << std::setprecision(1) << r[0] << "   "
                << std::setw(15) << std::setprecision(3) << r[1] << "\n";
    std::cout << std::defaultfloat << "\n";
  }
  for (const auto& c : s.checkpoints) std::cout << "checkpoint: " << c << "\n";
  if (!s.pvd.empty()) std::cout << "results: " << s.pvd << "\n";
  if (s.stop_reason == "interrupted") {
    const int signo = stop_signal;
    std::cerr << "stratum: interrupted by " << (signo == SIGTERM ? "SIGTERM" : "SIGINT") << " in stage "
              << s.stages_done + 1 << " after " << s.steps_done << " steps"
              << "; the results computed so far are written to " << s.out_dir << "\n";
    return 128 + signo;
  }
  // A numerical stop is not a result: its own exit status, so that scripts and studies can tell it
  // from a collapse (0) and from a failed stage (2).
  if (s.stop_reason == "numerical") return 4;
  // The scene's [[checks]]: one line each; a failed check is exit status 5.
  bool checks_pass = true;
  for (const auto& c : s.checks) {
    std::cout << "check " << c.label << " = " << std::setprecision(10) << c.value << ", expected "
              << c.expected << " +- " << std::setprecision(3) << c.tolerance << ": "
              << (c.pass ? "pass" : "FAIL") << "\n"
              << std::defaultfloat;
    checks_pass = checks_pass && c.pass;
  }
  if (!checks_pass) std::cerr << "stratum: " << scene << ": a check failed (see the check lines above)\n";
  return checks_pass ? 0 : 5;
}

} // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty()) {
      std::cerr << usage;
      return 1;
    }
    const std::string cmd = args[0];
    std::vector<std::string> rest(args.begin() + 1, args.end());
    if (cmd == "--version" || cmd == "version") {
      std::cout << "stratum " << STRATUM_VERSION << " (plugin ABI " << STRATUM_PLUGIN_ABI_VERSION << ")\n";
      return 0;
    }
    if (cmd == "run") return run(rest, false);
    if (cmd == "check") return run(rest, true);
    if (cmd == "plugins") return plugins(rest);
    if (cmd == "point") return point(rest);
    if (cmd == "fit") return stratum::cli::fit(rest);
    if (cmd == "sweep") return stratum::cli::sweep(rest);
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::cout << usage;
      return 0;
    }
    throw Error("unknown command '" + cmd + "'; allowed: run, check, point, fit, sweep, plugins, --version");
  } catch (const stratum::Error& e) {
    std::cerr << "stratum: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "stratum: internal error: " << e.what() << "\n";
    return 3;
  }
}
