// What every command of the CLI guards against (internal to framework/cli): running out of
// memory, and an output path that would overwrite one of the command's input files.
#pragma once

#include "stratum/error.hpp"

#include <sys/resource.h>

#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace stratum::cli {

/// A std::bad_alloc, with what the program was doing when it came; main() prints it as one
/// line and exits 2 (README.md, "Exit codes").
class OutOfMemory : public std::exception {
public:
  explicit OutOfMemory(std::string phase) : phase_(std::move(phase)) {}
  [[nodiscard]] const char* what() const noexcept override { return phase_.c_str(); }
  [[nodiscard]] const std::string& phase() const { return phase_; }

private:
  std::string phase_;
};

/// Runs `f`; a std::bad_alloc in it becomes OutOfMemory(phase) ("reading the scene ...").
template <class F> decltype(auto) in_phase(const std::string& phase, F&& f) {
  try {
    return std::forward<F>(f)();
  } catch (const std::bad_alloc&) {
    throw OutOfMemory(phase);
  }
}

/// The line main() prints for an OutOfMemory: the phase, and the address-space limit that was
/// reached (ulimit -v, common on clusters), or that there was none.
inline std::string out_of_memory_line(const std::string& phase) {
  std::string limit =
      "no address-space limit is set (ulimit -v unlimited): the machine's memory is exhausted";
  rlimit r{};
  if (::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    limit = "limit: ulimit -v " + std::to_string(r.rlim_cur / 1024) + " kB";
  return "out of memory while " + phase + ": the process could allocate no more (" + limit +
         "); raise the limit, or make the model smaller (a coarser mesh)";
}

/// Refuses an output path that is, or would overwrite, one of the command's input files:
/// `out` itself, or (for an output folder) the files `written` inside it. `option` names it
/// ("--out"). Paths that do not exist cannot be an input.
inline void refuse_output_over_inputs(const std::string& option, const std::string& out,
                                      const std::vector<std::string>& inputs,
                                      const std::vector<std::string>& written = {}) {
  namespace fs = std::filesystem;
  std::vector<fs::path> outs{fs::path(out)};
  for (const auto& w : written) outs.push_back(fs::path(out) / w);
  for (const auto& o : outs)
    for (const auto& in : inputs) {
      std::error_code ec;
      if (!in.empty() && fs::equivalent(o, in, ec) && !ec)
        throw Error(option + " '" + out + "'" +
                    (o == fs::path(out) ? "" : " (its " + o.filename().string() + ")") +
                    " is the input file '" + in + "' of this command, which the output would overwrite; " +
                    "give " + option + " another path");
    }
}

/// Refuses an output path below a regular file ("--out results.csv/x"), which no folder can be
/// made for, before anything runs.
inline void refuse_output_below_file(const std::string& option, const std::string& out) {
  namespace fs = std::filesystem;
  for (fs::path p = fs::path(out).parent_path(); !p.empty(); p = p.parent_path()) {
    std::error_code ec;
    const auto st = fs::status(p, ec);
    if (fs::exists(st)) {
      if (!fs::is_directory(st))
        throw Error(option + " '" + out + "': '" + p.string() +
                    "' is a file, not a folder, so nothing can be written below it; give " + option +
                    " a path in a folder");
      return;
    }
    if (p == p.parent_path()) return;
  }
}

} // namespace stratum::cli
