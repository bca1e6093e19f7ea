// <out>/summary.toml: how the run ended, in a file beside its results (the same facts the
// `stratum run` lines print), so that a folder of results says whether its curve ends at a
// collapse, a settlement limit, a numerical failure or the end of the load programme.
#include "files.hpp"
#include "output/run_view.hpp"
#include "stratum/analysis.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

namespace {

/// One `key = value` line, the value written by toml++ (quoting and escapes, nan and inf).
template <class T> void line(std::ostringstream& o, const char* key, T value) {
  o << key << " = " << toml::toml_formatter(toml::value<T>(std::move(value))) << "\n";
}

} // namespace

std::string summary_toml(const RunSummary& summary, const std::string& scene, std::size_t stages,
                         const std::string& error) {
  // Written key by key, so that the file reads in this order (a toml::table would sort them).
  std::ostringstream o;
  o << "# How the run of " << scene << " ended (written at its end; README.md, \"Exit codes\").\n";
  line(o, "program", std::string("stratum ") + STRATUM_VERSION);
  line(o, "scene", scene);
  // ended: "completed" (every stage ran to its end), "stopped" (a stage ended the run early, as
  // its rules allow: stop_reason says why) or "failed" (a step found no equilibrium after its
  // cut-backs outside an until_failure stage: status and message say where).
  // With `error`: "failed", status "error" (a file that could not be written, no memory left).
  const char* ended = !summary.outcome.ok() || !error.empty()   ? "failed"
                      : summary.stop_reason == StopReason::none ? "completed"
                                                                : "stopped";
  line(o, "ended", std::string(ended));
  line(o, "stop_reason", std::string(stop_reason_name(summary.stop_reason)));
  line(o, "stop_message", summary.stop_message);
  if (summary.stop_reason == StopReason::collapse || summary.stop_reason == StopReason::numerical) {
    line(o, "stiffness_ratio", summary.stiffness_ratio);
    // The last attempt's evidence, where it gives any (docs/design.md, "How a stage ends").
    if (std::isfinite(summary.attempt_stiffness_ratio))
      line(o, "attempt_stiffness_ratio", summary.attempt_stiffness_ratio);
  }
  line(o, "status", error.empty() ? std::string(to_string(summary.outcome.status)) : std::string("error"));
  line(o, "message", error.empty() ? summary.outcome.message : error);
  line(o, "stages", static_cast<std::int64_t>(stages));
  line(o, "stages_done", static_cast<std::int64_t>(summary.stages_done));
  line(o, "steps_done", static_cast<std::int64_t>(summary.steps_done));
  line(o, "cutbacks", static_cast<std::int64_t>(summary.cutbacks));
  if (!summary.load_settlement.empty()) {
    // The last converged level of the pile head: load (kN) and settlement (mm, as in the curve).
    line(o, "head_load", summary.load_settlement.back()[0]);
    line(o, "head_settlement", summary.load_settlement.back()[1]);
  }
  o << "\n[work]\n";
  line(o, "assemblies", static_cast<std::int64_t>(summary.times.assemblies));
  line(o, "factorizations", static_cast<std::int64_t>(summary.times.factorizations));
  line(o, "solves", static_cast<std::int64_t>(summary.times.solves));
  for (const auto& c : summary.checks) {
    o << "\n[[checks]]\n";
    line(o, "label", c.label);
    line(o, "value", c.value);
    line(o, "expected", c.expected);
    line(o, "tolerance", c.tolerance);
    line(o, "pass", c.pass);
  }
  return o.str();
}

void write_summary(const RunSummary& summary, const std::string& scene, std::size_t stages,
                   const std::string& error) {
  write_file_atomically((fs::path(summary.out_dir) / "summary.toml").string(),
                        summary_toml(summary, scene, stages, error));
}

} // namespace stratum
