// <out>/summary.toml: how the run ended, in a file beside its results (the same facts the
// `stratum run` lines print), so that a folder of results says whether its curve ends at a
// collapse, a settlement limit, a numerical failure or the end of the load programme.
#include "analysis_impl.hpp"
#include "stratum/files.hpp"

#include <toml++/toml.h>

#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

std::string summary_toml(const RunSummary& summary, const std::string& scene, std::size_t stages) {
  toml::table t;
  t.insert("program", std::string("stratum ") + STRATUM_VERSION);
  t.insert("scene", scene);
  // ended: "completed" (every stage ran to its end), "stopped" (a stage ended the run early, as
  // its rules allow: stop_reason says why) or "failed" (a step found no equilibrium after its
  // cut-backs outside an until_failure stage: status and message say where).
  const char* ended = !summary.outcome.ok()         ? "failed"
                      : summary.stop_reason.empty() ? "completed"
                                                    : "stopped";
  t.insert("ended", ended);
  t.insert("status", to_string(summary.outcome.status));
  t.insert("message", summary.outcome.message);
  t.insert("stop_reason", summary.stop_reason);
  t.insert("stop_message", summary.stop_message);
  if (summary.stop_reason == "collapse" || summary.stop_reason == "numerical")
    t.insert("stiffness_ratio", summary.stiffness_ratio);
  t.insert("stages", static_cast<std::int64_t>(stages));
  t.insert("stages_done", static_cast<std::int64_t>(summary.stages_done));
  t.insert("steps_done", static_cast<std::int64_t>(summary.steps_done));
  t.insert("cutbacks", static_cast<std::int64_t>(summary.cutbacks));
  if (!summary.load_settlement.empty()) {
    // The last converged level of the pile head: load (kN) and settlement (mm, as in the curve).
    t.insert("head_load", summary.load_settlement.back()[0]);
    t.insert("head_settlement", summary.load_settlement.back()[1]);
  }
  toml::table counts;
  counts.insert("assemblies", static_cast<std::int64_t>(summary.times.assemblies));
  counts.insert("factorizations", static_cast<std::int64_t>(summary.times.factorizations));
  counts.insert("solves", static_cast<std::int64_t>(summary.times.solves));
  t.insert("work", std::move(counts));
  toml::array checks;
  for (const auto& c : summary.checks) {
    toml::table ct;
    ct.insert("label", c.label);
    ct.insert("value", c.value);
    ct.insert("expected", c.expected);
    ct.insert("tolerance", c.tolerance);
    ct.insert("pass", c.pass);
    checks.push_back(std::move(ct));
  }
  if (!checks.empty()) t.insert("checks", std::move(checks));
  std::ostringstream o;
  o << "# How the run of " << scene << " ended (written at its end; README.md, \"Exit codes\").\n"
    << toml::toml_formatter(t) << "\n";
  return o.str();
}

void Analysis::Impl::write_summary(const RunSummary& summary) const {
  write_file_atomically((fs::path(summary.out_dir) / "summary.toml").string(),
                        summary_toml(summary, path, stages.size()));
}

} // namespace stratum
