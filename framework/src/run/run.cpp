// Analysis::run: the stages in order, restart from a checkpoint, a checkpoint after each stage.
#include "output/output_folder.hpp"
#include "output/vtk_output.hpp"
#include "run/analysis_impl.hpp"
#include "run/checkpoint.hpp"
#include "run/timing.hpp"
#include "stratum/enum_names.hpp"

#include <filesystem>
#include <new>
#include <optional>

namespace fs = std::filesystem;

namespace stratum {

const char* stop_reason_name(StopReason reason) {
  static constexpr std::array<const char*, 5> names{"", "collapse", "numerical", "settlement", "interrupted"};
  return enum_name(reason, names, "");
}

namespace {

/// The state after stage k that a checkpoint keeps: the scene's parts that shaped it, the
/// unknowns and reactions, the active cells and constraints, the loads, the committed points,
/// the time and the water table.
Checkpoint snapshot(SceneModel& sm, const std::vector<LoadSpec>& loads, double time, std::size_t k) {
  const Model& m = sm.model;
  Checkpoint c;
  c.fingerprint = sm.fingerprint;
  sm.add_library_parts();
  for (const auto& p : sm.parts)
    if (p.stage <= static_cast<int>(k)) {
      c.part_names.push_back(p.name);
      c.part_digests.push_back(p.digest);
      c.part_stages.push_back(p.stage);
    }
  c.stages_done = static_cast<int>(k + 1);
  c.stage_name = sm.stages[k].name;
  c.u.assign(m.u.data(), m.u.data() + m.u.size());
  c.reactions.assign(m.reactions.data(), m.reactions.data() + m.reactions.size());
  c.active = m.active;
  c.constrained = m.constrained;
  c.loads = loads;
  for (const auto& dm : m.domains) c.states.push_back(dm.states.committed_data());
  c.time = time;
  c.water_level = m.water.level, c.gamma_w = m.water.gamma_w;
  return c;
}

/// The model, the applied loads and the time from a checkpoint already checked against the scene.
void restore(const Checkpoint& c, Model& m, std::vector<LoadSpec>& loads, double& time) {
  m.u = Eigen::Map<const Eigen::VectorXd>(c.u.data(), static_cast<Eigen::Index>(c.u.size()));
  m.reactions =
      Eigen::Map<const Eigen::VectorXd>(c.reactions.data(), static_cast<Eigen::Index>(c.reactions.size()));
  m.active = c.active;
  m.constrained = c.constrained;
  loads = c.loads;
  for (std::size_t d = 0; d < m.domains.size(); ++d) m.domains[d].states.restore(c.states[d]);
  time = c.time;
  m.water = Water{c.water_level, c.gamma_w};
}

} // namespace

RunSummary Analysis::run() {
  const auto t_run = std::chrono::steady_clock::now();
  Impl& s = *impl_;
  SceneModel& sm = s.sm;
  Model& m = sm.model;
  RunSummary summary;
  summary.out_dir =
      s.options.out_dir.empty() ? (fs::path("out") / fs::path(s.path).stem()).string() : s.options.out_dir;
  s.out_dir = summary.out_dir;
  std::size_t first = 0;
  if (!s.options.restart_from.empty()) {
    const std::string& path = s.options.restart_from;
    Checkpoint c = read_checkpoint(path);
    if (c.fingerprint != sm.fingerprint)
      throw Error(path + ": the checkpoint belongs to another scene (it has \"" + c.fingerprint +
                  "\", this scene has \"" + sm.fingerprint + "\")");
    std::vector<FingerprintPart> saved;
    for (std::size_t i = 0; i < c.part_names.size() && i < c.part_digests.size() && i < c.part_stages.size();
         ++i)
      saved.push_back({c.part_names[i], c.part_digests[i], c.part_stages[i], {}});
    SourceLocation where;
    sm.add_library_parts();
    if (const std::string why = fingerprint_mismatch(saved, sm.parts, c.stages_done, &where); !why.empty())
      throw Error(where, "--restart-from " + path + ": " + why);
    if (c.states.size() != m.domains.size() || c.u.size() != static_cast<std::size_t>(m.u.size()))
      throw Error(path + ": the checkpoint does not match the scene's model size");
    // What the completed stages' actions left that the checkpoint does not keep (a domain's
    // material), then the checkpoint's values.
    for (int k = 0; k < c.stages_done && static_cast<std::size_t>(k) < sm.stages.size(); ++k)
      for (const auto& a : sm.stages[static_cast<std::size_t>(k)].actions) a->resume(m);
    for (std::size_t d = 0; d < m.domains.size(); ++d)
      if (c.states[d].size() != m.domains[d].states.committed_data().size())
        throw Error(path + ": the checkpoint's states of domain \"" + m.domains[d].name +
                    "\" do not match its material's history (" + std::to_string(c.states[d].size()) +
                    " values, the scene's model has " +
                    std::to_string(m.domains[d].states.committed_data().size()) + ")");
    restore(c, m, s.loads, s.state.time);
    first = static_cast<std::size_t>(c.stages_done);
    summary.stages_done = c.stages_done;
  }

  // The folder is this run's while it writes; what an earlier run left there moves aside (after
  // a checkpoint in it was read above), so that no file of two runs mixes.
  std::optional<OutputFolder> folder;
  if (s.options.write_output) {
    folder.emplace(summary.out_dir);
    folder->move_aside_previous(fs::path(s.path).stem().string(), static_cast<int>(first));
  }
  // A result file that cannot be written (disk full, file size limit) or memory that runs out
  // ends the run with an exception; summary.toml still says how far it got, when it can be
  // written, and every file written before stays whole (each is written atomically).
  try {
    std::unique_ptr<VtkSeriesWriter> writer;
    if (s.options.write_output && sm.settings.vtk) {
      // With more than one thread allowed, the VTK files are written on a thread of the writer's
      // own while the next steps are solved (the sparse LU is serial, so a core is often free);
      // the files are the same. [analysis] threads = 1 keeps everything on one thread.
      writer = std::make_unique<VtkSeriesWriter>(summary.out_dir, fs::path(s.path).stem().string(),
                                                 sm.settings.threads > 1);
      timed(summary.times.output, [&] { write_step(*writer, s.view()); });
    }
    s.state.axial_rows.clear();
    s.state.shaft_rows.clear();
    // The recorders' first row: the state the run starts from (step 0 of its first stage).
    for (auto& r : s.recorders) r.sample(m, static_cast<int>(first) + 1, 0, 0.0, 0, s.state.time);
    for (std::size_t k = first; k < sm.stages.size(); ++k) {
      const bool go_on = s.run_stage(k, summary, writer.get());
      if (!summary.outcome.ok()) break;
      if (go_on && k + 1 < sm.stages.size())
        timed(summary.times.output, [&] { s.update_tables(summary, {}); });
      summary.stages_done = static_cast<int>(k + 1);
      if (sm.stages[k].checkpoint && s.options.write_output && go_on) {
        const auto t_ckpt = std::chrono::steady_clock::now();
        const Checkpoint c = snapshot(sm, s.loads, s.state.time, k);
        const auto path = (fs::path(summary.out_dir) / "checkpoints" /
                           (std::to_string(k + 1) + "_" + sm.stages[k].name + ".ckpt"))
                              .string();
        write_checkpoint(path, c);
        summary.checkpoints.push_back(path);
        summary.times.checkpoint += seconds_since(t_ckpt);
      }
      if (!go_on) {
        if (summary.stop_reason != StopReason::none) summary.stages_done = static_cast<int>(k); // ended early
        break;
      }
    }
    if (writer) {
      timed(summary.times.output, [&] { writer->finish(); });
      summary.pvd = writer->pvd_path();
    }
    const auto t_out = std::chrono::steady_clock::now();
    s.update_tables(summary, {});
    summary.checks = evaluate_checks(s.checks, s.recorders);
    if (s.options.write_output) write_summary(summary, s.path, sm.stages.size());
    summary.times.output += seconds_since(t_out);
  } catch (const std::exception& e) {
    if (folder) {
      try {
        const bool oom = dynamic_cast<const std::bad_alloc*>(&e) != nullptr;
        write_summary(summary, s.path, sm.stages.size(),
                      oom ? std::string("out of memory: the process could allocate no more")
                          : std::string(e.what()));
      } catch (...) { // the summary is a courtesy here: the error that ended the run is what counts
      }
    }
    throw;
  }
  summary.times.total = seconds_since(t_run);
  return summary;
}

} // namespace stratum
