// `stratum sweep`, rank 0's side (framework/cli/sweep.cpp has the overview): the journal, the
// timings, the progress line, the local sample thread, the answers to the workers' requests
// and samples.csv at the end.
#include "sweep_manager.hpp"

#include "files.hpp"
#include "output/output_folder.hpp"

#include "mpi.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;

namespace stratum::cli {

namespace {

using sweep::SampleResult;
using sweep::Study;

using Clock = std::chrono::steady_clock;

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

struct Finished {
  SampleResult result;
  int rank = 0;
  std::string host;
};

#ifdef STRATUM_HAVE_MPI
Finished unpack(const std::string& s, int rank) {
  Finished f;
  f.rank = rank;
  std::size_t a = 0;
  auto field = [&] {
    const auto b = s.find('\n', a);
    std::string v = s.substr(a, b - a);
    a = b + 1;
    return v;
  };
  f.result.index = std::stoi(field());
  f.result.status = field();
  f.result.seconds = std::stod(field());
  f.result.cpu_seconds = std::stod(field());
  f.host = field();
  f.result.row = s.substr(a);
  return f;
}
#endif

void write_all(int fd, const std::string& s, const std::string& path) {
  std::size_t done = 0;
  while (done < s.size()) {
    const auto n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw WriteError("cannot write '" + path + "': " + write_failure(errno));
    done += static_cast<std::size_t>(n);
  }
}

/// The journal: a hash line, then finished rows, each appended with one write and fsync'd.
class Journal {
public:
  Journal(const fs::path& path, const std::string& hash, std::size_t samples) : path_(path.string()) {
    const std::string head = "# stratum sweep journal, study hash " + hash + "\n";
    if (fs::exists(path)) {
      const std::string text = read_text_file(path_, SourceLocation{}, "sweep journal", file_limits::journal);
      if (text.compare(0, head.size(), head) != 0) {
        const auto e = text.find('\n');
        throw Error(path_ + ": written by another study (" + text.substr(0, e == std::string::npos ? 60 : e) +
                    "; this one has hash " + hash +
                    "): the study file or its base file changed. Give another --out folder, or delete the "
                    "folder to run the study again from the start");
      }
      std::size_t pos = head.size(), complete = head.size();
      while (true) {
        const auto e = text.find('\n', pos);
        if (e == std::string::npos) break; // a torn last line (killed while writing): dropped
        const std::string line = text.substr(pos, e - pos);
        pos = complete = e + 1;
        const auto comma = line.find(',');
        if (comma == std::string::npos) continue;
        const std::size_t index = std::strtoul(line.substr(0, comma).c_str(), nullptr, 10);
        if (index < samples && !rows_.count(index)) rows_[index] = line;
      }
      if (complete < text.size()) fs::resize_file(path, complete);
      fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    } else {
      fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
      if (fd_ >= 0) {
        write_all(fd_, head, path_);
        ::fsync(fd_);
      }
    }
    if (fd_ < 0) throw Error("cannot open the journal '" + path_ + "' for writing");
  }
  ~Journal() {
    if (fd_ >= 0) ::close(fd_);
  }
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  void append(std::size_t index, const std::string& row) {
    write_all(fd_, row + "\n", path_);
    if (::fsync(fd_) != 0)
      throw WriteError("cannot write '" + path_ + "' to the disk (fsync): " + write_failure(errno));
    rows_[index] = row;
  }
  [[nodiscard]] const std::map<std::size_t, std::string>& rows() const { return rows_; }

private:
  std::string path_;
  int fd_ = -1;
  std::map<std::size_t, std::string> rows_;
};

std::string duration_text(double s) {
  char buf[48];
  if (s < 90)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 5400)
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  else
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  return buf;
}

/// The manager's progress line: rewritten in place on a terminal, one line every 5 s otherwise.
class Progress {
public:
  Progress(std::size_t total, std::size_t done_before, std::size_t failed_before)
      : total_(total), before_(done_before), failed_(failed_before), tty_(isatty(STDERR_FILENO) != 0) {}
  void finished(bool failed) {
    ++now_;
    if (failed) ++failed_;
  }
  void show(std::size_t running, bool force = false) {
    const auto t = Clock::now();
    const double since = std::chrono::duration<double>(t - last_).count();
    if (!force && since < (tty_ ? 0.5 : 5.0)) return;
    last_ = t;
    const double elapsed = std::chrono::duration<double>(t - start_).count();
    std::ostringstream o;
    o << "sweep: " << before_ + now_ << "/" << total_ << " done, " << running << " running, " << failed_
      << " failed";
    if (now_ > 0 && elapsed > 0) {
      const double rate = static_cast<double>(now_) / elapsed; // samples per second
      char buf[32];
      std::snprintf(buf, sizeof buf, rate * 60 >= 100 ? "%.0f" : "%.3g", rate * 60);
      o << ", " << buf << " samples/min";
      const std::size_t left = total_ - before_ - now_;
      if (left) o << ", about " << duration_text(static_cast<double>(left) / rate) << " left";
    }
    if (tty_)
      std::cerr << "\r" << o.str() << "\033[K" << std::flush;
    else
      std::cerr << o.str() << "\n";
  }
  void end() {
    if (tty_) std::cerr << "\n";
  }

private:
  std::size_t total_, before_, now_ = 0, failed_;
  bool tty_;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
};

/// The status field of a row: the one before the reason (the only quoted field, or empty).
std::string status_of(const std::string& row) {
  auto end = row.find('"');
  end = (end == std::string::npos ? row.size() : end) - 1; // the comma before the reason
  const auto begin = row.rfind(',', end - 1) + 1;
  return row.substr(begin, end - begin);
}

std::size_t kill_after() { // test hook: SIGKILL the manager after this many journal records
  const char* s = std::getenv("STRATUM_SWEEP_KILL_AFTER");
  return s ? static_cast<std::size_t>(std::strtoul(s, nullptr, 10)) : 0;
}

/// Rank 0's side of a study while it runs: the output files, the samples not yet handed out, the
/// local sample thread's results and the workers told to stop.
class Manager {
public:
  Manager(const Study& study, const fs::path& out, const MpiSession& mpi)
      : study_(study), out_(out), mpi_(mpi), total_(study.samples().size()) {}
  /// Runs the study to its end and writes samples.csv; 0, or 2 when every sample failed (the
  /// failed samples are listed there).
  int run();

private:
  /// Opens the journal and timings.csv and lists the samples to run (on failure: setup_error_
  /// and no sample to run, so that every worker is told to stop).
  void open_output();
  /// Appends a finished sample to the journal and timings.csv and counts it.
  void record(const SampleResult& r, int rank, const std::string& h);
  /// The local thread: runs the pending samples until none is left.
  void run_local();
  /// Answers one worker's request (and records the result it brings), if one is waiting;
  /// true when it did.
  bool serve_worker();
  /// Records the local thread's results; true when there were any. now_running: the samples
  /// handed out and not finished.
  bool collect_local(std::size_t& now_running);
  /// Serves the workers and the local thread until every sample is recorded and every worker
  /// was told to stop.
  void serve();
  /// samples.csv from the journal, and the closing lines; false when every sample failed.
  [[nodiscard]] bool write_samples() const;

  const Study& study_;
  const fs::path out_;
  const MpiSession& mpi_;
  const std::size_t total_;
  std::exception_ptr setup_error_;
  std::optional<OutputFolder> folder_;
  std::unique_ptr<Journal> journal_;
  std::deque<int> pending_;
  std::ofstream timings_;
  std::size_t failed_before_ = 0;
  std::mutex mu_; // guards pending_, local_done_ and the local thread's results
  std::vector<SampleResult> local_results_;
  std::atomic<bool> local_done_ = false;
  std::size_t running_ = 0, stopped_workers_ = 0, recorded_ = 0;
  std::size_t kill_ = 0;
  std::string host_;
  std::optional<Progress> progress_;
  std::size_t counts_[3] = {0, 0, 0}; // converged, stopped, failed in this run
};

void Manager::open_output() {
  try {
    // The folder is this study's while it runs (a lock file in it, held until the process ends):
    // a second sweep (or run) into it stops at once instead of running every sample again.
    folder_.emplace(out_.string());
    journal_ = std::make_unique<Journal>(out_ / "journal.csv", study_.hash(), total_);
    for (std::size_t i = 0; i < total_; ++i)
      if (!journal_->rows().count(i)) pending_.push_back(static_cast<int>(i));
    for (const auto& [i, row] : journal_->rows())
      if (status_of(row) == "failed") ++failed_before_;
    const bool fresh = !fs::exists(out_ / "timings.csv");
    timings_.open(out_ / "timings.csv", std::ios::app);
    if (!timings_) throw Error("cannot write '" + (out_ / "timings.csv").string() + "'");
    if (fresh) timings_ << "index,rank,host,seconds,cpu_seconds,status\n" << std::flush;
  } catch (...) {
    setup_error_ = std::current_exception();
    pending_.clear();
  }
}

void Manager::record(const SampleResult& r, int rank, const std::string& h) {
  journal_->append(static_cast<std::size_t>(r.index), r.row);
  timings_ << r.index << "," << rank << "," << h << "," << seconds_text(r.seconds) << ","
           << seconds_text(r.cpu_seconds) << "," << r.status << "\n"
           << std::flush;
  if (!timings_)
    throw WriteError("cannot write '" + (out_ / "timings.csv").string() + "': " + write_failure(errno));
  progress_->finished(r.status == "failed");
  ++counts_[r.status == "converged" ? 0 : r.status == "stopped" ? 1 : 2];
  if (kill_ && ++recorded_ == kill_) std::raise(SIGKILL);
}

void Manager::run_local() {
  while (true) {
    int idx;
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (pending_.empty()) break;
      idx = pending_.front();
      pending_.pop_front();
      ++running_;
    }
    SampleResult r = study_.run(idx, out_.string());
    std::lock_guard<std::mutex> lock(mu_);
    local_results_.push_back(std::move(r));
  }
  local_done_ = true;
}

bool Manager::serve_worker() {
#ifdef STRATUM_HAVE_MPI
  if (mpi_.size() <= 1) return false;
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(MPI_ANY_SOURCE, tag_result, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return false;
  int n = 0;
  MPI_Get_count(&st, MPI_CHAR, &n);
  std::string buf(static_cast<std::size_t>(n), '\0');
  MPI_Recv(buf.data(), n, MPI_CHAR, st.MPI_SOURCE, tag_result, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  int idx = -1;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (!buf.empty()) --running_;
    if (!pending_.empty()) {
      idx = pending_.front();
      pending_.pop_front();
      ++running_;
    }
  }
  if (idx < 0) ++stopped_workers_;
  MPI_Send(&idx, 1, MPI_INT, st.MPI_SOURCE, tag_work, MPI_COMM_WORLD);
  if (!buf.empty()) {
    const Finished f = unpack(buf, st.MPI_SOURCE);
    record(f.result, f.rank, f.host);
  }
  return true;
#else
  return false;
#endif
}

bool Manager::collect_local(std::size_t& now_running) {
  std::vector<SampleResult> mine;
  {
    std::lock_guard<std::mutex> lock(mu_);
    mine.swap(local_results_);
    running_ -= mine.size();
    now_running = running_;
  }
  for (const auto& r : mine) record(r, 0, host_);
  return !mine.empty();
}

void Manager::serve() {
  while (true) {
    bool busy = serve_worker();
    std::size_t now_running;
    busy = collect_local(now_running) || busy;
    progress_->show(now_running);
    if (local_done_ && stopped_workers_ + 1 == static_cast<std::size_t>(mpi_.size())) {
      std::lock_guard<std::mutex> lock(mu_);
      if (local_results_.empty() && running_ == 0) break;
    }
    if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

bool Manager::write_samples() const {
  std::string csv = study_.header() + "\n";
  std::size_t converged = 0, stopped = 0, failed = 0;
  std::string first_failed; // the first failed row, whose reason the closing line quotes
  for (const auto& [i, row] : journal_->rows()) {
    csv += row + "\n";
    const std::string s = status_of(row);
    (s == "converged" ? converged : s == "stopped" ? stopped : failed) += 1;
    if (s == "failed" && first_failed.empty()) first_failed = row;
  }
  stratum::write_file_atomically((out_ / "samples.csv").string(), csv);
  const bool all_failed = total_ > 0 && failed == total_;
  std::cout << (all_failed ? "failed: every sample failed: " : "done: ") << total_ << " samples ("
            << converged << " converged, " << stopped << " stopped, " << failed << " failed), "
            << counts_[0] + counts_[1] + counts_[2] << " run now on " << mpi_.size()
            << (mpi_.size() == 1 ? " process" : " processes")
            << "\nresults: " << (out_ / "samples.csv").string() << "\n";
  if (all_failed) {
    // Nothing to learn from the study: most likely one setting that every sample shares is wrong.
    const auto quote = first_failed.find('"');
    std::string reason = quote == std::string::npos ? std::string() : first_failed.substr(quote + 1);
    if (!reason.empty() && reason.back() == '"') reason.pop_back();
    for (auto q = reason.find("\"\""); q != std::string::npos; q = reason.find("\"\"", q + 1))
      reason.erase(q, 1);
    std::cerr << "sweep: failed: every one of the " << total_ << " samples failed (sample "
              << first_failed.substr(0, first_failed.find(',')) << ": " << reason
              << "); their status and reason are in samples.csv\n";
  } else if (failed) {
    std::cerr << "sweep: " << failed << " of " << total_
              << " samples failed: their status and reason are in samples.csv\n";
  }
  return !all_failed;
}

int Manager::run() {
  open_output();
  const std::size_t done_before = setup_error_ ? 0 : journal_->rows().size();
  if (!setup_error_ && done_before > 0)
    std::cerr << "sweep: resuming " << out_.string() << ": " << done_before << " of " << total_
              << " samples are in the journal, " << pending_.size() << " to run\n";
  local_done_ = pending_.empty();
  kill_ = kill_after();
  host_ = host_name();
  progress_.emplace(total_, done_before, failed_before_);

  std::thread local;
  if (!local_done_) local = std::thread([this] { run_local(); });
  std::exception_ptr run_error;
  try {
    serve();
  } catch (...) {
    run_error = std::current_exception();
    {
      std::lock_guard<std::mutex> lock(mu_);
      pending_.clear();
    }
  }
  if (local.joinable()) local.join();
  if (setup_error_) std::rethrow_exception(setup_error_); // every worker was told to stop
#ifdef STRATUM_HAVE_MPI
  if (run_error && mpi_.size() > 1) { // workers may be waiting for an answer: end the job
    try {
      std::rethrow_exception(run_error);
    } catch (const std::exception& e) {
      std::cerr << "stratum: " << e.what() << "\n";
    }
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
#endif
  if (run_error) std::rethrow_exception(run_error);
  progress_->show(0, true);
  progress_->end();
  return write_samples() ? 0 : 2;
}

} // namespace

std::string host_name() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

#ifdef STRATUM_HAVE_MPI
/// "index\nstatus\nseconds\ncpu seconds\nhost\nrow": what a worker sends back.
std::string pack(const SampleResult& r, const std::string& host) {
  return std::to_string(r.index) + "\n" + r.status + "\n" + seconds_text(r.seconds) + "\n" +
         seconds_text(r.cpu_seconds) + "\n" + host + "\n" + r.row;
}
#endif

int manager(const Study& study, const fs::path& out, const MpiSession& mpi) {
  return Manager(study, out, mpi).run();
}

} // namespace stratum::cli
