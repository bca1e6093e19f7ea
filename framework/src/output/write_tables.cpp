// diagnostics.csv, the recorders' histories and the pile curves (curves/*.csv).
#include "files.hpp"
#include "output/pile_components.hpp"
#include "output/recorders.hpp"
#include "output/run_view.hpp"

#include <filesystem>
#include <iomanip>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum {

/// diagnostics.csv and the curves, each replaced atomically: at the end of every stage, every few
/// seconds during a stage (so that a long run's tables grow while it runs and a kill loses at
/// most the last seconds), and at the end. `live`: the accepted steps of the running stage (its
/// failed attempts join at the stage's end).
void write_tables(const RunView& run, const RunSummary& summary, const std::vector<Recorder>& recorders,
                  const std::vector<StepRecord>& live) {
  const Model& m = run.model;
  const auto& axial_rows = run.state.axial_rows;
  const auto& shaft_rows = run.state.shaft_rows;
  for (const auto& r : recorders)
    write_file_atomically((fs::path(summary.out_dir) / "history" / (r.name() + ".csv")).string(),
                          r.csv(run.units, m.formulation));
  if (live.empty()) {
    write_step_records((fs::path(summary.out_dir) / "diagnostics.csv").string(), summary.records);
  } else {
    std::vector<StepRecord> all = summary.records;
    all.insert(all.end(), live.begin(), live.end());
    write_step_records((fs::path(summary.out_dir) / "diagnostics.csv").string(), all);
  }
  if (!summary.load_settlement.empty()) {
    std::ostringstream ls, af;
    const Units& u = run.units;
    const std::string load = u.column("load", "kN"), depth = u.column("depth", "m");
    ls << std::setprecision(10) << load << ',' << "settlement_" << u.small_length() << '\n';
    for (const auto& r : summary.load_settlement) ls << r[0] << ',' << r[1] << '\n';
    write_file_atomically((fs::path(summary.out_dir) / "curves" / "load_settlement.csv").string(), ls.str());
    if (!axial_rows.empty()) {
      af << std::setprecision(10) << load << ',' << depth << ',' << u.column("axial_force", "kN") << '\n';
      double top = -std::numeric_limits<double>::infinity();
      for (int c : m.mesh.cell_sets.at(run.settings.pile_cells))
        for (int n : m.mesh.cells[static_cast<std::size_t>(c)].nodes)
          if (n >= 0) top = std::max(top, m.mesh.nodes[static_cast<std::size_t>(n)].y());
      for (const auto& r : axial_rows) af << r[0] << ',' << top - r[1] << ',' << r[2] << '\n';
      write_file_atomically((fs::path(summary.out_dir) / "curves" / "axial_force.csv").string(), af.str());
      if (!shaft_rows.empty()) {
        std::ostringstream st;
        st << std::setprecision(10) << load << ',' << depth << ',' << u.column("shear_traction", "kPa") << ','
           << u.column("normal_traction", "kPa") << ",slip_" << u.small_length() << ",status\n";
        static const char* names[] = {"stick", "slip", "open"};
        for (const auto& r : shaft_rows)
          st << r[0] << ',' << top - r[1] << ',' << r[2] << ',' << r[3] << ',' << r[4] << ','
             << names[static_cast<int>(r[5])] << '\n';
        write_file_atomically((fs::path(summary.out_dir) / "curves" / "shaft_traction.csv").string(),
                              st.str());
      }
    }
    if (!summary.settlement_components.empty()) {
      std::ostringstream sc;
      sc << std::setprecision(10) << PileComponents::header(u) << '\n';
      for (const auto& r : summary.settlement_components)
        for (std::size_t i = 0; i < r.size(); ++i) sc << r[i] << (i + 1 < r.size() ? ',' : '\n');
      write_file_atomically((fs::path(summary.out_dir) / "curves" / "settlement_components.csv").string(),
                            sc.str());
    }
  }
}

} // namespace stratum
