// `stratum sweep`, internal to the CLI: what the process entry and the worker
// (framework/cli/sweep.cpp) and the manager (framework/cli/sweep_manager.cpp) share: the MPI
// session, the message tags and the wire format of a finished sample.
#pragma once

#include "sweep/sweep.hpp"

#include <filesystem>
#include <string>

namespace stratum::cli {

constexpr int tag_result = 1, tag_work = 2;

/// MPI_Init_thread / MPI_Finalize around the study (only rank 0's main thread calls MPI).
class MpiSession {
public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }

private:
  bool on_ = false;
  int rank_ = 0, size_ = 1;
};

/// This machine's host name ("unknown" when it has none).
std::string host_name();

/// "index\nstatus\nseconds\ncpu seconds\nhost\nrow": what a worker sends back.
#ifdef STRATUM_HAVE_MPI
std::string pack(const sweep::SampleResult& r, const std::string& host);
#endif

/// Rank 0: hands out the samples, runs samples itself on a second thread, writes the output
/// folder; 0 when the study is done (failed samples are in samples.csv).
int manager(const sweep::Study& study, const std::filesystem::path& out, const MpiSession& mpi);

} // namespace stratum::cli
