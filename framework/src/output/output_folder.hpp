// The output folder of one run (internal): owned by that run while it writes, and free of an
// earlier run's files that the new run would otherwise leave beside its own.
#pragma once

#include <string>

namespace stratum {

/// Holds an exclusive lock (flock on <dir>/.stratum.lock) for its lifetime. Creates the folder.
/// Throws Error when the folder is another run's, or when the path exists and is not a folder.
/// The lock goes with the process, so a killed run leaves no stale lock behind.
class OutputFolder {
public:
  explicit OutputFolder(const std::string& dir);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// Moves what an earlier run of the scene `stem` wrote here (<stem>.pvd, <stem>_*.vtu/.vtp/.csv/.pvd,
  /// diagnostics.csv, curves/, checkpoints/) into <dir>/previous_run/, replacing an older one.
  /// A run restarted after stage `keep_stages` keeps the checkpoints of stages 1..keep_stages
  /// (the state it continues from). Returns how many entries were moved.
  int move_aside_previous(const std::string& stem, int keep_stages = 0) const;

private:
  std::string dir_;
  int fd_ = -1;
};

} // namespace stratum
