// stratum: the command-line front end.
//
//   stratum run SCENE.toml [--out DIR] [--restart-from CHECKPOINT] [--verbose | --quiet]
//               [--progress-every SECONDS]
//   stratum check SCENE.toml [--quiet]
//   stratum point POINT.toml [--out FILE.csv]
//   stratum plugins [--describe [NAME] | --all | --paths]
//   stratum describe [SECTION | --markdown]
//   stratum fit TARGET CSV... [-o FILE]   (framework/cli/fit.cpp)
//   stratum sweep STUDY.toml [--out DIR]  (framework/cli/sweep.cpp; also under mpirun)
//   stratum --version
//   stratum COMMAND --help, stratum help COMMAND
//
// Errors are one line on stderr and a non-zero exit code.
#include "calibrate.hpp"
#include "files.hpp"
#include "fit.hpp"
#include "guards.hpp"
#include "info.hpp"
#include "point_command.hpp"
#include "run_command.hpp"
#include "scene/reference.hpp"
#include "stratum/plugin.hpp"
#include "stratum/plugin_loader.hpp"
#include "suggest.hpp"
#include "sweep.hpp"

#include <csignal>

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

namespace {

/// A file-size limit (ulimit -f) kills a process that writes past it with SIGXFSZ, before it can
/// say anything. Ignored, the write fails with EFBIG instead and the writers report it (which
/// file, which limit) as a WriteError. Set once at start-up, for the life of the process.
void ignore_file_size_signal() {
  struct sigaction sa {};
  sa.sa_handler = SIG_IGN;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGXFSZ, &sa, nullptr);
}

using namespace stratum;

constexpr const char* usage =
    "usage: stratum run SCENE.toml [--out DIR] [--restart-from CHECKPOINT] [--verbose | --quiet]\n"
    "                  [--progress-every SECONDS]\n"
    "       stratum check SCENE.toml [--quiet]\n"
    "       stratum point POINT.toml [--out FILE.csv]\n"
    "       stratum plugins [--describe [NAME] | --all | --paths]\n"
    "       stratum describe [SECTION | --markdown]   the scene format: sections and their keys\n"
    "       stratum fit TARGET CSV... [-o FILE.toml]\n"
    "       stratum sweep STUDY.toml [--out DIR] [--print-scene INDEX]   (also under mpirun -n N)\n"
    "       stratum calibrate STUDY.toml [--out DIR] [--print-scene]   (also under mpirun -n N)\n"
    "       stratum --version\n"
    "       stratum COMMAND --help   (or stratum help COMMAND): the command's options and exit status\n"
    "exit status: 0 done (a collapse or a settlement limit of the last stage included), 1 bad input,\n"
    "  2 a stage failed, a result file could not be written (disk full, ulimit -f) or memory ran out\n"
    "  (ulimit -v), 3 internal error, 4 an until_failure stage stopped by a numerical failure\n"
    "  (not a collapse), 5 a [[checks]] entry failed, 130/143 interrupted by SIGINT/SIGTERM\n";

/// The --help text of a subcommand; empty for an unknown one.
std::string help_of(const std::string& cmd) {
  if (cmd == "run") return stratum::cli::run_help();
  if (cmd == "check") return stratum::cli::check_help();
  if (cmd == "point") return stratum::cli::point_help();
  if (cmd == "plugins") return stratum::cli::plugins_help();
  if (cmd == "describe") return stratum::cli::describe_help();
  if (cmd == "fit") return stratum::cli::fit_help(); // lists the targets the plugins declare
  if (cmd == "sweep") return stratum::cli::sweep_help();
  if (cmd == "calibrate") return stratum::cli::calibrate_help();
  return {};
}

constexpr const char* commands[] = {"run",       "check",   "point",    "fit",  "sweep",
                                    "calibrate", "plugins", "describe", "help", "--version"};

} // namespace

int main(int argc, char** argv) {
  ignore_file_size_signal();
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty()) {
      std::cerr << usage;
      return 1;
    }
    const std::string cmd = args[0];
    std::vector<std::string> rest(args.begin() + 1, args.end());
    // `stratum COMMAND --help` (anywhere among its arguments) and `stratum help COMMAND`.
    const bool help = std::find(rest.begin(), rest.end(), "--help") != rest.end() ||
                      std::find(rest.begin(), rest.end(), "-h") != rest.end();
    if (help && !help_of(cmd).empty()) {
      std::cout << help_of(cmd);
      return 0;
    }
    if ((cmd == "help" || cmd == "--help" || cmd == "-h") && !rest.empty()) {
      if (help_of(rest[0]).empty())
        throw Error("help: unknown command '" + rest[0] +
                    "'; allowed: run, check, point, fit, sweep, calibrate, plugins, describe" +
                    did_you_mean(rest[0], commands));
      std::cout << help_of(rest[0]);
      return 0;
    }
    if (cmd == "--version" || cmd == "version") {
      std::cout << "stratum " << STRATUM_VERSION << " (plugin ABI " << STRATUM_PLUGIN_ABI_VERSION << ")\n";
      return 0;
    }
    if (cmd == "run") return stratum::cli::run(rest, false);
    if (cmd == "check") return stratum::cli::run(rest, true);
    if (cmd == "plugins") return stratum::cli::plugins(rest);
    if (cmd == "describe") return stratum::cli::describe_scene(rest);
    if (cmd == "point") return stratum::cli::point(rest);
    if (cmd == "fit") return stratum::cli::fit(rest);
    if (cmd == "sweep") return stratum::cli::sweep(rest);
    if (cmd == "calibrate") return stratum::cli::calibrate(rest);
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::cout << usage;
      return 0;
    }
    throw Error("unknown command '" + cmd +
                "'; allowed: run, check, point, fit, sweep, calibrate, plugins, describe, help, --version" +
                did_you_mean(cmd, commands));
  } catch (const stratum::WriteError& e) {
    // A result file could not be written (disk full, file size limit): the run failed, its input
    // did not; what was written before stays.
    std::cerr << "stratum: " << e.what() << "\n";
    return 2;
  } catch (const stratum::Error& e) {
    std::cerr << "stratum: " << e.what() << "\n";
    return 1;
  } catch (const stratum::cli::OutOfMemory& e) {
    std::cerr << "stratum: " << stratum::cli::out_of_memory_line(e.phase()) << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "stratum: " << stratum::cli::out_of_memory_line("starting") << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "stratum: internal error: " << e.what() << "\n";
    return 3;
  }
}
