// `stratum sweep STUDY.toml [--out DIR] [--print-scene INDEX]`: runs a parameter study
// (framework/src/sweep/sweep.hpp) on one process, or on N under mpirun/srun: rank 0 is the manager; it hands
// out sample indices one at a time to the ranks that ask (dynamic balancing), runs samples itself on a second
// thread, and is the only writer of the output folder:
//   DIR/journal.csv  the study's hash, then one finished row per line, appended and fsync'd
//                    as each sample finishes: a rerun runs only the samples it lacks;
//   DIR/samples.csv  rewritten from the journal at the end (sorted by index, temporary file
//                    then rename), so it depends only on the study, never on the rank count;
//   DIR/timings.csv  index, rank, host, wall and CPU seconds, status, appended as samples finish.
// The MPI C API is used when the build found MPI (STRATUM_HAVE_MPI) and the process was started
// by an MPI launcher; otherwise everything runs in this one process.
#include "sweep.hpp"
#include "guards.hpp"
#include "sweep_manager.hpp"

#include "sweep/sweep.hpp"

#include "mpi.hpp"

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

namespace fs = std::filesystem;

namespace stratum::cli {

namespace {

using sweep::Study;

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}

[[maybe_unused]] int launcher_size() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* s = std::getenv(v)) return std::atoi(s);
  return 1;
}

} // namespace

MpiSession::MpiSession() {
#ifdef STRATUM_HAVE_MPI
  if (!launched_by_mpi()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw Error("the MPI library does not allow threads (MPI_THREAD_FUNNELED); stratum sweep needs them");
  }
  on_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
#else
  if (launched_by_mpi() && launcher_size() > 1)
    throw Error("this stratum was built without MPI: run stratum sweep as one process, "
                "or build it with libopenmpi-dev installed");
#endif
}

MpiSession::~MpiSession() {
#ifdef STRATUM_HAVE_MPI
  if (on_) MPI_Finalize();
#endif
}

namespace {

#ifdef STRATUM_HAVE_MPI
int worker(const Study& study, const fs::path& out) {
  const std::string host = host_name();
  std::string payload;
  while (true) {
    MPI_Send(payload.data(), static_cast<int>(payload.size()), MPI_CHAR, 0, tag_result, MPI_COMM_WORLD);
    int idx = -1;
    MPI_Recv(&idx, 1, MPI_INT, 0, tag_work, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (idx < 0) return 0;
    payload = pack(study.run(idx, out.string()), host);
  }
}
#endif

} // namespace

const char* sweep_help() {
  return "usage: stratum sweep STUDY.toml [--out DIR] [--print-scene INDEX]\n"
         "       mpirun -n N stratum sweep STUDY.toml [--out DIR]\n"
         "\n"
         "Runs a parameter study (docs/sweep.md): one scene per sample, on this process or on N MPI\n"
         "ranks (rank 0 hands out samples and writes the output). A rerun into the same folder runs\n"
         "only the samples that its journal lacks.\n"
         "\n"
         "options:\n"
         "  --out DIR            output folder (default out/<study name>): journal.csv, samples.csv,\n"
         "                       timings.csv (and samples/<i>/ per sample with [study]\n"
         "                       sample_output = true; off by default)\n"
         "  --print-scene INDEX  print the scene of sample INDEX (0-based) and exit; runs nothing\n"
         "  -h, --help           this text\n"
         "\n"
         "Progress goes to stderr: one line rewritten in place on a terminal, a line every 5 s\n"
         "otherwise.\n"
         "\n"
         "The folder is the study's while it runs: a second sweep (or run) into it stops at once.\n"
         "\n"
         "exit status: 0 done (samples that failed are listed with their reason in samples.csv),\n"
         "  1 bad input (the folder taken by another sweep included), 2 every sample failed, a\n"
         "  result file could not be written or memory ran out, 3 internal error\n";
}

int sweep(const std::vector<std::string>& args) {
  std::string file, out, print;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out") {
      if (i + 1 >= args.size()) throw Error("--out needs a directory");
      out = args[++i];
    } else if (args[i] == "--print-scene") {
      if (i + 1 >= args.size()) throw Error("--print-scene needs a sample index");
      print = args[++i];
    } else if (!args[i].empty() && args[i][0] == '-') {
      throw Error("unknown option '" + args[i] + "'; allowed: --out DIR, --print-scene INDEX");
    } else if (file.empty()) {
      file = args[i];
    } else {
      throw Error("more than one study file given ('" + file + "', '" + args[i] + "')");
    }
  }
  if (file.empty()) throw Error("no study file given (usage: stratum sweep STUDY.toml [--out DIR])");
  if (out.empty()) out = (fs::path("out") / fs::path(file).stem()).string();
  if (!print.empty()) { // the scene of one sample, to run or inspect by hand; no MPI, no output
    const Study study = Study::from_file(file);
    char* end = nullptr;
    const long i = std::strtol(print.c_str(), &end, 10);
    if (*end || i < 0 || static_cast<std::size_t>(i) >= study.samples().size())
      throw Error("--print-scene " + print + ": the study has samples 0 to " +
                  std::to_string(study.samples().size() - 1));
    std::cout << study.scene_text(static_cast<int>(i));
    return 0;
  }

  MpiSession mpi;
  std::optional<Study> study;
  try {
    study = in_phase("reading the study " + file, [&] { return Study::from_file(file); });
    refuse_output_below_file("--out", out);
    // The folder's files must not be the study's own (a study file named samples.csv in it).
    refuse_output_over_inputs("--out", out, {file, study->base_path()},
                              {"journal.csv", "samples.csv", "timings.csv"});
  } catch (const Error&) {
    if (mpi.rank() == 0) throw; // every rank reads the same file: rank 0 says what is wrong
    return 1;
  }
#ifdef STRATUM_HAVE_MPI
  if (mpi.rank() != 0) return worker(*study, out);
#endif
  return in_phase("running the study " + file, [&] { return manager(*study, out, mpi); });
}

} // namespace stratum::cli
