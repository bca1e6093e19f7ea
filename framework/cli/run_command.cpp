// `stratum run` and `stratum check`: the arguments, the progress line, the run, and what is
// printed after it (steps and times, why a stage stopped, the load-settlement table, the checks).
#include "run_command.hpp"

#include "files.hpp"
#include "guards.hpp"
#include "stratum/analysis.hpp"
#include "suggest.hpp"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string_view>

namespace stratum::cli {

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

constexpr const char* run_help_text =
    "usage: stratum run SCENE.toml [--out DIR] [--restart-from CHECKPOINT] [--verbose | --quiet]\n"
    "                  [--progress-every SECONDS]\n"
    "\n"
    "Reads the scene, runs its stages and writes the results (.vtu/.vtp/.pvd, curves, diagnostics,\n"
    "checkpoints) under DIR; prints the steps done, the time split and, for a pile, the\n"
    "load-settlement table.\n"
    "\n"
    "options:\n"
    "  --out DIR                  output folder (default out/<scene name>); an earlier run's files\n"
    "                             move to DIR/previous_run/\n"
    "  --restart-from CHECKPOINT  continue from a stage checkpoint of the same scene\n"
    "  --verbose                  one line per accepted step on stderr (iterations, cut-backs, rate,\n"
    "                             order, time, residuals)\n"
    "  --quiet                    no progress and no summary; errors only (stderr)\n"
    "  --progress-every SECONDS   when stderr is not a terminal, a progress line (stage, step, load\n"
    "                             factor, iterations, elapsed time, estimate for the stage) at most every\n"
    "                             SECONDS (default 5; 0: every step); on a terminal one line is\n"
    "                             rewritten in place\n"
    "  -h, --help                 this text\n"
    "\n"
    "exit status: 0 done (a collapse or a settlement limit of the last stage included), 1 bad input\n"
    "  (one located line on stderr), 2 a stage failed, a result file could not be written (disk full,\n"
    "  file size limit) or memory ran out (what was written before is kept, summary.toml says how\n"
    "  far the run got), 3 internal error, 4 an until_failure stage stopped by a numerical failure\n"
    "  (not a collapse), 5 a [[checks]] entry failed, 130/143 interrupted by SIGINT/SIGTERM (what\n"
    "  was computed is written)\n";

constexpr const char* check_help_text =
    "usage: stratum check SCENE.toml [--quiet]\n"
    "\n"
    "Reads the scene, builds the mesh and the model and opens the plugins it names, without\n"
    "solving; prints the size of the model. Refused (exit 1): loads on empty sets and every\n"
    "error a run would report before its first step. Warned (stderr, exit 0): cells that no\n"
    "[[domains]] entry covers (they stay out of the model: a cavity, or a forgotten domain) and\n"
    "physical groups of a Gmsh mesh that the scene never names.\n"
    "\n"
    "options:\n"
    "  --quiet      print nothing when the scene is good\n"
    "  -h, --help   this text\n"
    "\n"
    "exit status: 0 the scene is good, 1 bad input (one located line on stderr), 2 out of memory\n"
    "  (ulimit -v), 3 internal error\n";

/// The progress of a run on stderr: on a terminal one line rewritten in place after every step;
/// otherwise (a batch job, a log file) one line at most every `every` seconds.
class RunProgress {
public:
  RunProgress(bool tty, double every) : tty_(tty), every_(every) {}
  /// A stage starts (RunOptions::on_stage).
  void stage(const std::string& name, int number, int count) {
    stage_start_ = Clock::now();
    stage_ = "stage " + std::to_string(number) + "/" + std::to_string(count) + " \"" + name + "\"  ";
  }
  void step(int step, int steps, double lambda, int iterations) {
    const auto now = Clock::now();
    if (!tty_ && seconds(last_shown_, now) < every_) return; // the first after `every` s
    last_shown_ = now;
    shown_ = true;
    std::ostringstream o;
    o << stage_ << "step " << step << "/" << steps << "  load factor " << std::fixed << std::setprecision(4)
      << lambda << "  iterations " << iterations << "  elapsed " << duration(seconds(start_, now));
    // The load factor goes from 0 to 1 over a stage: the time per unit of it so far gives the rest.
    if (lambda > 0.0 && lambda < 1.0)
      o << "  about " << duration(seconds(stage_start_, now) * (1.0 - lambda) / lambda)
        << " left in the stage";
    if (tty_)
      std::cerr << "\r" << o.str() << "\033[K" << std::flush;
    else
      std::cerr << "progress: " << o.str() << "\n" << std::flush;
  }
  void end() const {
    if (tty_ && shown_) std::cerr << "\n";
  }
  /// The stage running now ("stage 2/3 \"load\""), or "before its first stage".
  [[nodiscard]] std::string stage_text() const {
    if (stage_.empty()) return "before its first stage";
    return stage_.substr(0, stage_.find_last_not_of(' ') + 1);
  }

private:
  using Clock = std::chrono::steady_clock;
  static double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  }
  static std::string duration(double s) {
    std::ostringstream o;
    if (s < 60.0)
      o << std::fixed << std::setprecision(s < 10.0 ? 1 : 0) << s << " s";
    else if (s < 3600.0)
      o << static_cast<int>(s / 60.0) << " min " << static_cast<int>(s) % 60 << " s";
    else
      o << static_cast<int>(s / 3600.0) << " h " << static_cast<int>(s / 60.0) % 60 << " min";
    return o.str();
  }
  bool tty_;
  double every_;
  bool shown_ = false;
  std::string stage_; ///< "stage 2/3 \"load\"  ", empty before the first stage starts
  Clock::time_point start_ = Clock::now(), stage_start_ = start_, last_shown_ = start_;
};

/// Sends std::cout nowhere while it lives (--quiet); errors go to std::cerr and stay.
class MuteStdout {
public:
  explicit MuteStdout(bool mute) : old_(mute ? std::cout.rdbuf(&null_) : nullptr) {}
  ~MuteStdout() {
    if (old_) std::cout.rdbuf(old_);
  }
  MuteStdout(const MuteStdout&) = delete;
  MuteStdout& operator=(const MuteStdout&) = delete;

private:
  struct Null : std::streambuf {
    int overflow(int c) override { return traits_type::not_eof(c); }
  } null_;
  std::streambuf* old_;
};

/// The options of `stratum run` and `stratum check` as given.
struct RunArgs {
  std::string scene, out, restart;
  bool verbose = false, quiet = false;
  double progress_every = 5.0;
};

/// Reads the arguments of `stratum run` (or of `stratum check`: only --quiet).
RunArgs parse_run_args(const std::vector<std::string>& args, bool check_only) {
  RunArgs a;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out" && !check_only) {
      if (i + 1 >= args.size()) throw Error("--out needs a directory");
      a.out = args[++i];
    } else if (args[i] == "--restart-from" && !check_only) {
      if (i + 1 >= args.size()) throw Error("--restart-from needs a checkpoint file");
      a.restart = args[++i];
    } else if (args[i] == "--verbose" && !check_only) {
      a.verbose = true;
    } else if (args[i] == "--quiet") {
      a.quiet = true;
    } else if (args[i] == "--progress-every" && !check_only) {
      char* end = nullptr;
      if (i + 1 >= args.size() || (a.progress_every = std::strtod(args[++i].c_str(), &end), *end) ||
          !(a.progress_every >= 0.0))
        throw Error("--progress-every needs a number of seconds >= 0");
    } else if (!args[i].empty() && args[i][0] == '-') {
      const std::vector<std::string_view> allowed =
          check_only ? std::vector<std::string_view>{"--quiet"}
                     : std::vector<std::string_view>{"--out", "--restart-from", "--verbose", "--quiet",
                                                     "--progress-every"};
      throw Error("unknown option '" + args[i] + "'; allowed: " +
                  (check_only ? "--quiet"
                              : "--out DIR, --restart-from CHECKPOINT, --verbose, --quiet, --progress-every "
                                "SECONDS") +
                  did_you_mean(args[i], allowed) + " (see stratum " + (check_only ? "check" : "run") +
                  " --help)");
    } else if (a.scene.empty()) {
      a.scene = args[i];
    } else {
      throw Error("more than one scene file given ('" + a.scene + "', '" + args[i] + "')");
    }
  }
  if (a.scene.empty()) throw Error("no scene file given (see stratum --help)");
  if (a.verbose && a.quiet) throw Error("--verbose and --quiet exclude each other");
  return a;
}

/// The run's options: output folder, restart, and the callbacks that print progress (to
/// `progress`) or every step's diagnostics (--verbose), and poll the stop signals.
RunOptions run_options(const RunArgs& a, RunProgress& progress) {
  RunOptions opts;
  opts.out_dir = a.out;
  opts.restart_from = a.restart;
  opts.on_record = [verbose = a.verbose](const StepRecord& r) {
    if (!verbose) return;
    std::cerr << "step " << r.step << " lambda " << r.lambda << " iterations " << r.iterations
              << " cut-backs " << r.cutbacks << " rate " << r.contraction << " order " << r.order << " time "
              << r.seconds << " s |R|:";
    for (double x : r.residual_norms) std::cerr << " " << x;
    std::cerr << "\n";
  };
  opts.interrupted = [] { return stop_signal != 0; };
  opts.on_stage = [&progress](const std::string& name, int number, int count) {
    progress.stage(name, number, count);
  };
  opts.on_step = [&progress, verbose = a.verbose, quiet = a.quiet](int step, int steps, double lambda,
                                                                   const StepReport& rep) {
    if (!verbose && !quiet) progress.step(step, steps, lambda, rep.iterations); // --verbose: on_record
  };
  return opts;
}

/// `stratum check`: the warnings and the one line that says the scene is fine.
int report_check(const Analysis& analysis, const std::string& scene, bool quiet) {
  if (!quiet) // --quiet: errors only
    for (const auto& w : analysis.warnings()) std::cerr << "stratum: warning: " << w << "\n";
  const auto& m = analysis.model();
  std::cout << scene << ": ok (" << m.mesh.nodes.size() << " nodes, " << m.mesh.cells.size() << " cells, "
            << m.dofs.free_count << " unknowns of fields " << m.dofs.field_list() << ", "
            << analysis.opened_libraries().size() << " plugin libraries"
            << (analysis.units().is_default() ? "" : ", units " + analysis.units().describe()) << ")\n";
  return 0;
}

/// A failed run: its status and message on stderr; exit status 2.
int report_failure(const RunSummary& s, const std::string& scene) {
  std::cerr << "stratum: " << scene << ": " << to_string(s.outcome.status) << ": " << s.outcome.message;
  // A singular stiffness before any step has converged is a model that can move without
  // resistance; later it is the structure's own loss of stiffness (see until_failure).
  if (s.outcome.status == Status::singular && s.steps_done == 0)
    std::cerr << " (before any step converged: a part of the model may be free to move as a rigid body; "
                 "check the constraints)";
  std::cerr << "\n";
  return 2;
}

/// The `done:` line and where the time went.
void print_done(const RunSummary& s) {
  std::cout << "done: " << s.steps_done << " steps";
  if (s.cutbacks) std::cout << " (" << s.cutbacks << " cut-backs)";
  std::cout << "\n";
  const RunTimes& t = s.times;
  std::cout << std::fixed << std::setprecision(3) << "time: " << t.total << " s: assembly and stress update "
            << t.assembly << " s (" << t.assemblies << "), linear solver "
            << t.analyze + t.factorize + t.solve << " s (analyze " << t.analyze << " x" << t.analyses
            << ", factorize " << t.factorize << " x" << t.factorizations << ", solve " << t.solve << " x"
            << t.solves << "), output " << t.output << " s, checkpoints " << t.checkpoint << " s\n"
            << std::defaultfloat;
}

/// Why a stage ended the run early (collapse, numerical failure, settlement limit).
void print_stop(const RunSummary& s) {
  if (s.stop_reason == StopReason::collapse || s.stop_reason == StopReason::numerical) {
    std::ostringstream ratio;
    ratio << std::setprecision(3) << s.stiffness_ratio;
    std::ostringstream attempt;
    attempt << std::setprecision(3) << s.attempt_stiffness_ratio;
    if (s.stop_reason == StopReason::collapse && s.stiffness_ratio >= s.collapse_stiffness)
      // The accepted steps were stiff up to the stop (a plateau reached by force control): the
      // failed attempt's iterations are the evidence.
      std::cout
          << "stopped: collapse: a load step found no equilibrium after its cut-backs, and the "
             "structure gave way under the load: the last attempt, at the smallest increment, "
             "went along the load as if its stiffness were "
          << attempt.str() << " of the stage's first step's (the accepted steps stayed at least "
          << ratio.str()
          << "); the table ends at the last converged level, less than that increment below the limit load\n";
    else if (s.stop_reason == StopReason::collapse)
      std::cout << "stopped: collapse: a load step found no equilibrium after its cut-backs, and the "
                   "structure had lost its stiffness (over the last tenth of the load, down to "
                << ratio.str()
                << " of the stage's first step's); the table ends at the last converged level\n";
    else
      std::cout << "stopped: numerical failure: a load step did not converge after its cut-backs "
                   "although the structure was still stiff (over the last tenth of the load, at least "
                << ratio.str()
                << " of the stage's first step's stiffness): this is not a collapse load; the table ends at "
                   "the last converged level (see diagnostics.csv)\n";
    // The failed step's message (its residual may be NaN) is a diagnostic, not a result: stderr.
    std::cerr << "stratum: the step that stopped the run"
              << (s.stop_reason == StopReason::collapse ? " at the collapse: " : ": ") << s.stop_message
              << "\n";
  } else if (s.stop_reason == StopReason::settlement)
    std::cout << "stopped: the settlement limit of the stage is exceeded\n";
}

/// The pile head's load-settlement table, when the run recorded one.
void print_load_settlement(const RunSummary& s, const Units& u) {
  if (s.load_settlement.empty()) return;
  std::cout << "\n  load (" << u.force() << ")   settlement (" << u.small_length() << ")\n";
  for (const auto& r : s.load_settlement)
    std::cout << "  " << std::setw(9) << std::fixed << std::setprecision(1) << r[0] << "   " << std::setw(15)
              << std::setprecision(3) << r[1] << "\n";
  std::cout << std::defaultfloat << "\n";
}

/// The scene's [[checks]]: one line each; a failed check is exit status 5.
int report_checks(const RunSummary& s, const Units& u, const std::string& scene) {
  bool checks_pass = true;
  std::string failed;
  for (const auto& c : s.checks) {
    if (!c.pass) failed += (failed.empty() ? "" : ", ") + c.label;
    // In other units than kN, m the line names the quantity's unit (stratum/units.hpp).
    const std::string unit = u.is_default() ? "" : " [" + u.label(c.unit) + "]";
    std::cout << "check " << c.label << unit << " = " << std::setprecision(10) << c.value << ", expected "
              << c.expected << " +- " << std::setprecision(3) << c.tolerance << ": "
              << (c.pass ? "pass" : "FAIL") << "\n"
              << std::defaultfloat;
    checks_pass = checks_pass && c.pass;
  }
  if (!checks_pass)
    std::cerr << "stratum: " << scene << ": a check failed: " << failed << " (the check lines on stdout)\n";
  return checks_pass ? 0 : 5;
}

} // namespace

int run(const std::vector<std::string>& args, bool check_only) {
  const RunArgs a = parse_run_args(args, check_only);
  const MuteStdout mute(a.quiet);
  const bool tty = isatty(STDERR_FILENO) != 0;
  RunProgress progress(tty, a.progress_every);
  if (!check_only) {
    cli::refuse_output_over_inputs("--out", a.out, {a.scene, a.restart});
    cli::refuse_output_below_file("--out", a.out);
  }
  auto analysis = cli::in_phase("reading " + a.scene + " and building its model",
                                [&] { return Analysis::from_file(a.scene, run_options(a, progress)); });
  if (check_only) return report_check(*analysis, a.scene, a.quiet);
  catch_stop_signals();
  RunSummary s;
  try {
    s = analysis->run();
  } catch (const std::bad_alloc&) {
    throw cli::OutOfMemory("running " + a.scene + " (" + progress.stage_text() + ")");
  } catch (const WriteError& e) {
    throw WriteError(a.scene + ": " + e.message() + "; the run stopped there (" + progress.stage_text() +
                     "), the files written before are whole and kept, and summary.toml says how far it got");
  }
  progress.end();
  if (!s.outcome.ok()) return report_failure(s, a.scene);
  print_done(s);
  print_stop(s);
  print_load_settlement(s, analysis->units());
  for (const auto& c : s.checkpoints) std::cout << "checkpoint: " << c << "\n";
  if (!s.pvd.empty()) std::cout << "results: " << s.pvd << "\n";
  if (s.stop_reason == StopReason::interrupted) {
    const int signo = stop_signal;
    std::cerr << "stratum: interrupted by " << (signo == SIGTERM ? "SIGTERM" : "SIGINT") << " in stage "
              << s.stages_done + 1 << " after " << s.steps_done << " steps"
              << "; the results computed so far are written to " << s.out_dir << "\n";
    return 128 + signo;
  }
  // A numerical stop is not a result: its own exit status, so that scripts and studies can tell it
  // from a collapse (0) and from a failed stage (2).
  if (s.stop_reason == StopReason::numerical) return 4;
  return report_checks(s, analysis->units(), a.scene);
}

std::string run_help() { return run_help_text; }
std::string check_help() { return check_help_text; }

} // namespace stratum::cli
