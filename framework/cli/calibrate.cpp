// `stratum calibrate STUDY.toml [--out DIR] [--print-scene]`: fits a scene's parameters to
// measured curves (framework/src/sweep/back_analysis.hpp, docs/calibrate.md), on one process or
// on N under mpirun/srun. Rank 0 runs the optimizer; each batch of model runs it asks for (the
// points of a difference Jacobian) is dealt round-robin to the ranks, rank 0 included, so a
// Jacobian of n parameters takes about 2n/N run times. The result depends only on the study: every
// run is deterministic and the optimizer asks for the same points whatever the rank count.
// Rank 0 is the only writer of the output folder:
//   DIR/journal.csv  every finished run, appended and flushed: a calibration started again into
//                    the same folder (after an interruption) takes its runs from there;
//   DIR/parameters.csv, correlation.csv, singular_values.csv, jacobian.csv, residuals.csv,
//   DIR/report.md    the result (written at the end, each atomically);
//   DIR/fitted_<data>.csv  each data set's whole computed curve at the best values;
//   DIR/best/        the run at the best values, with the scene's own output.
#include "calibrate.hpp"
#include "guards.hpp"
#include "sweep_manager.hpp"

#include "files.hpp"
#include "output/output_folder.hpp"
#include "sweep/back_analysis.hpp"

#include "mpi.hpp"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

namespace fs = std::filesystem;

namespace stratum::cli {

namespace {

using sweep::BackAnalysis;
using sweep::Evaluation;

constexpr int tag_stop = 3;

[[maybe_unused]] std::string pack(const Evaluation& e) {
  std::ostringstream o;
  char b[40];
  o << e.status << "\n";
  std::snprintf(b, sizeof b, "%a", e.seconds);
  o << b << "\n";
  for (std::size_t k = 0; k < e.computed.size(); ++k) {
    std::snprintf(b, sizeof b, "%a", e.computed[k]);
    o << (k ? "," : "") << b;
  }
  o << "\n" << e.reason;
  return o.str();
}

[[maybe_unused]] Evaluation unpack(const std::string& s, const std::vector<double>& values) {
  Evaluation e;
  e.values = values;
  std::istringstream in(s);
  std::string line;
  std::getline(in, e.status);
  std::getline(in, line);
  e.seconds = std::strtod(line.c_str(), nullptr);
  std::getline(in, line);
  std::size_t pos = 0;
  while (pos <= line.size() && !line.empty()) {
    const auto comma = line.find(',', pos);
    e.computed.push_back(std::strtod(line.substr(pos, comma - pos).c_str(), nullptr));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  std::getline(in, e.reason, '\0');
  return e;
}

#ifdef STRATUM_HAVE_MPI
/// Ranks 1..N-1: run the values rank 0 sends until it says stop.
int worker(const BackAnalysis& ba) {
  const auto n = static_cast<int>(ba.parameters().size());
  std::vector<double> p(static_cast<std::size_t>(n));
  while (true) {
    MPI_Status st;
    MPI_Recv(p.data(), n, MPI_DOUBLE, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
    if (st.MPI_TAG == tag_stop) return 0;
    const std::string s = pack(ba.evaluate(p));
    MPI_Send(s.data(), static_cast<int>(s.size()), MPI_CHAR, 0, tag_result, MPI_COMM_WORLD);
  }
}
#endif

/// Rank 0's runner: item k of a batch goes to rank k mod N; rank 0 runs its own, then collects.
sweep::BatchRunner rank_runner(const BackAnalysis& ba, [[maybe_unused]] const MpiSession& mpi) {
  return [&ba, &mpi](const std::vector<std::vector<double>>& batch) {
    std::vector<Evaluation> out(batch.size());
    const auto size = static_cast<std::size_t>(mpi.size());
#ifdef STRATUM_HAVE_MPI
    for (std::size_t k = 0; k < batch.size(); ++k)
      if (k % size != 0)
        MPI_Send(batch[k].data(), static_cast<int>(batch[k].size()), MPI_DOUBLE, static_cast<int>(k % size),
                 tag_work, MPI_COMM_WORLD);
#endif
    for (std::size_t k = 0; k < batch.size(); k += size) out[k] = ba.evaluate(batch[k]);
#ifdef STRATUM_HAVE_MPI
    for (std::size_t k = 0; k < batch.size(); ++k) {
      if (k % size == 0) continue;
      MPI_Status st;
      MPI_Probe(static_cast<int>(k % size), tag_result, MPI_COMM_WORLD, &st);
      int len = 0;
      MPI_Get_count(&st, MPI_CHAR, &len);
      std::string s(static_cast<std::size_t>(len), '\0');
      MPI_Recv(s.data(), len, MPI_CHAR, st.MPI_SOURCE, tag_result, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      out[k] = unpack(s, batch[k]);
    }
#endif
    return out;
  };
}

void stop_workers([[maybe_unused]] const MpiSession& mpi) {
#ifdef STRATUM_HAVE_MPI
  for (int r = 1; r < mpi.size(); ++r) MPI_Send(nullptr, 0, MPI_DOUBLE, r, tag_stop, MPI_COMM_WORLD);
#endif
}

const std::vector<std::string>& result_files() {
  static const std::vector<std::string> f = {
      "journal.csv",  "parameters.csv", "correlation.csv", "singular_values.csv",
      "jacobian.csv", "residuals.csv",  "report.md"};
  return f;
}

int manager(const BackAnalysis& ba, const fs::path& out, const MpiSession& mpi) {
  std::optional<OutputFolder> folder;
  std::optional<sweep::Journal> journal;
  try {
    folder.emplace(out.string());
    journal.emplace((out / "journal.csv").string(), ba.hash(), ba.parameters().size(), ba.points());
  } catch (...) {
    stop_workers(mpi);
    throw;
  }
  const std::size_t before = journal->size();
  // Test hook (tests/calibrate/run.sh): STRATUM_CALIBRATE_KILL_AFTER=N kills this process
  // (SIGKILL) once N runs have been journaled, to test the resume as a crash leaves it.
  const char* kill_env = std::getenv("STRATUM_CALIBRATE_KILL_AFTER");
  const std::size_t kill_after = kill_env ? static_cast<std::size_t>(std::strtoul(kill_env, nullptr, 10)) : 0;
  const auto journaled = sweep::journaled(*journal, rank_runner(ba, mpi));
  const sweep::BatchRunner runner = [&](const std::vector<std::vector<double>>& batch) {
    auto out = journaled(batch);
    if (kill_after && journal->size() - before >= kill_after) std::raise(SIGKILL);
    return out;
  };
  std::cerr << "calibrate: " << ba.parameters().size() << " parameters, " << ba.points()
            << " measured points, " << mpi.size() << (mpi.size() == 1 ? " process" : " processes")
            << (before ? ", " + std::to_string(before) + " runs in the journal" : std::string()) << "\n";
  sweep::FitResult r;
  try {
    r = sweep::calibrate(ba, runner, [](int it, double cost, int runs) {
      std::cerr << "calibrate: iteration " << it << ", cost " << sweep::format_number(cost) << ", " << runs
                << " runs\n";
    });
  } catch (const sweep::FitFailed& e) {
    stop_workers(mpi);
    std::cerr << "stratum: " << e.what() << "\n";
    return 2;
  } catch (...) {
    stop_workers(mpi);
    throw;
  }
  stop_workers(mpi);
  const auto files = sweep::report_files(ba, r);
  for (const auto& [name, text] : files) write_file_atomically((out / name).string(), text);
  // The run at the best values with its own output, and each data set's whole computed curve.
  std::vector<std::vector<std::array<double, 2>>> curves;
  (void)ba.evaluate(r.best, (out / "best").string(), &curves);
  for (std::size_t d = 0; d < ba.data().size(); ++d) {
    const auto& ds = ba.data()[d];
    std::string csv = ds.x + "," + ds.y + "\n";
    for (const auto& xy : curves[d])
      csv += sweep::format_number(xy[0]) + "," + sweep::format_number(xy[1]) + "\n";
    write_file_atomically((out / ("fitted_" + ds.name + ".csv")).string(), csv);
  }
  std::cout << files.at("report.md");
  std::cout << "\nruns: " << r.runs << " asked for, " << journal->size() - before << " run now, "
            << journal->reused() << " answered from the journal of an earlier start\n"
            << "results: " << (out / "parameters.csv").string() << ", " << (out / "report.md").string()
            << "\n";
  return 0;
}

} // namespace

const char* calibrate_help() {
  return "usage: stratum calibrate STUDY.toml [--out DIR] [--print-scene]\n"
         "       mpirun -n N stratum calibrate STUDY.toml [--out DIR]\n"
         "\n"
         "Fits parameters of a scene (or point file) to measured curves by weighted least squares\n"
         "(Ceres' Levenberg-Marquardt with bounds), then reports the standard errors, 95 % intervals,\n"
         "correlations and the singular values of the Jacobian at the best values (docs/calibrate.md).\n"
         "Under mpirun the model runs of each Jacobian go to the N ranks at once.\n"
         "\n"
         "options:\n"
         "  --out DIR       output folder (default out/<study name>): journal.csv, parameters.csv,\n"
         "                  correlation.csv, singular_values.csv, jacobian.csv, residuals.csv,\n"
         "                  report.md, fitted_<data>.csv and best/ (the run at the best values)\n"
         "  --print-scene   print the scene at the start values and exit; runs nothing\n"
         "  -h, --help      this text\n"
         "\n"
         "A calibration started again into the same folder takes its finished runs from the journal\n"
         "(after an interruption it continues where it stopped).\n"
         "\n"
         "exit status: 0 done (read report.md: a parameter may be reported as not determined),\n"
         "  1 bad input (the start values' run not reaching every measured point included),\n"
         "  2 the optimizer failed, a result file could not be written or memory ran out, 3 internal error\n";
}

int calibrate(const std::vector<std::string>& args) {
  std::string file, out;
  bool print = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out") {
      if (i + 1 >= args.size()) throw Error("--out needs a directory");
      out = args[++i];
    } else if (args[i] == "--print-scene") {
      print = true;
    } else if (!args[i].empty() && args[i][0] == '-') {
      throw Error("unknown option '" + args[i] + "'; allowed: --out DIR, --print-scene");
    } else if (file.empty()) {
      file = args[i];
    } else {
      throw Error("more than one calibration file given ('" + file + "', '" + args[i] + "')");
    }
  }
  if (file.empty())
    throw Error("no calibration file given (usage: stratum calibrate STUDY.toml [--out DIR])");
  if (out.empty()) out = (fs::path("out") / fs::path(file).stem()).string();
  if (print) {
    const BackAnalysis ba = BackAnalysis::from_file(file);
    std::vector<double> p;
    for (const auto& f : ba.parameters()) p.push_back(f.start);
    std::cout << ba.scene_text(p);
    return 0;
  }
  MpiSession mpi;
  std::optional<BackAnalysis> ba;
  try {
    ba = in_phase("reading the calibration " + file, [&] { return BackAnalysis::from_file(file); });
    refuse_output_below_file("--out", out);
    std::vector<std::string> inputs = {file, ba->base_path()};
    for (const auto& d : ba->data()) inputs.push_back(d.file);
    refuse_output_over_inputs("--out", out, inputs, result_files());
  } catch (const Error&) {
    if (mpi.rank() == 0) throw; // every rank reads the same files: rank 0 says what is wrong
    return 1;
  }
#ifdef STRATUM_HAVE_MPI
  if (mpi.rank() != 0) return worker(*ba);
#endif
  return in_phase("running the calibration " + file, [&] { return manager(*ba, out, mpi); });
}

} // namespace stratum::cli
