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

#include "stratum/files.hpp"
#include "sweep/sweep.hpp"

#ifdef STRATUM_HAVE_MPI
#define OMPI_SKIP_MPICXX 1 // the C API only
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
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

constexpr int tag_result = 1, tag_work = 2;
using Clock = std::chrono::steady_clock;

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

/// MPI_Init_thread / MPI_Finalize around the study (only rank 0's main thread calls MPI).
class MpiSession {
public:
  MpiSession() {
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
  ~MpiSession() {
#ifdef STRATUM_HAVE_MPI
    if (on_) MPI_Finalize();
#endif
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }

private:
  bool on_ = false;
  int rank_ = 0, size_ = 1;
};

std::string host_name() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

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
/// "index\nstatus\nseconds\ncpu seconds\nhost\nrow": what a worker sends back.
std::string pack(const SampleResult& r, const std::string& host) {
  return std::to_string(r.index) + "\n" + r.status + "\n" + seconds_text(r.seconds) + "\n" +
         seconds_text(r.cpu_seconds) + "\n" + host + "\n" + r.row;
}

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
    if (n < 0) throw Error("cannot write '" + path + "'");
    done += static_cast<std::size_t>(n);
  }
}

/// The journal: a hash line, then finished rows, each appended with one write and fsync'd.
class Journal {
public:
  Journal(const fs::path& path, const std::string& hash, std::size_t samples) : path_(path.string()) {
    const std::string head = "# stratum sweep journal, study hash " + hash + "\n";
    if (fs::exists(path)) {
      std::ifstream in(path, std::ios::binary);
      std::stringstream ss;
      ss << in.rdbuf();
      const std::string text = ss.str();
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
    if (::fsync(fd_) != 0) throw Error("cannot write '" + path_ + "' to the disk (fsync)");
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

int manager(const Study& study, const fs::path& out, [[maybe_unused]] const MpiSession& mpi) {
  const std::size_t total = study.samples().size();
  std::exception_ptr setup_error;
  std::unique_ptr<Journal> journal;
  std::deque<int> pending;
  std::ofstream timings;
  std::size_t failed_before = 0;
  try {
    fs::create_directories(out);
    journal = std::make_unique<Journal>(out / "journal.csv", study.hash(), total);
    for (std::size_t i = 0; i < total; ++i)
      if (!journal->rows().count(i)) pending.push_back(static_cast<int>(i));
    for (const auto& [i, row] : journal->rows())
      if (status_of(row) == "failed") ++failed_before;
    const bool fresh = !fs::exists(out / "timings.csv");
    timings.open(out / "timings.csv", std::ios::app);
    if (!timings) throw Error("cannot write '" + (out / "timings.csv").string() + "'");
    if (fresh) timings << "index,rank,host,seconds,cpu_seconds,status\n" << std::flush;
  } catch (...) {
    setup_error = std::current_exception();
    pending.clear();
  }
  const std::size_t done_before = setup_error ? 0 : journal->rows().size();
  if (!setup_error && done_before > 0)
    std::cerr << "sweep: resuming " << out.string() << ": " << done_before << " of " << total
              << " samples are in the journal, " << pending.size() << " to run\n";

  std::mutex mu; // guards pending, local_done and the local thread's results
  std::vector<SampleResult> local_results;
  std::atomic<bool> local_done = pending.empty();
  std::size_t running = 0, stopped_workers = 0, recorded = 0;
  const std::size_t kill = kill_after();
  const std::string host = host_name();
  Progress progress(total, done_before, failed_before);
  std::size_t counts[3] = {0, 0, 0}; // converged, stopped, failed in this run

  auto record = [&](const SampleResult& r, int rank, const std::string& h) {
    journal->append(static_cast<std::size_t>(r.index), r.row);
    timings << r.index << "," << rank << "," << h << "," << seconds_text(r.seconds) << ","
            << seconds_text(r.cpu_seconds) << "," << r.status << "\n"
            << std::flush;
    progress.finished(r.status == "failed");
    ++counts[r.status == "converged" ? 0 : r.status == "stopped" ? 1 : 2];
    if (kill && ++recorded == kill) std::raise(SIGKILL);
  };

  std::thread local;
  if (!local_done) {
    local = std::thread([&] {
      while (true) {
        int idx;
        {
          std::lock_guard<std::mutex> lock(mu);
          if (pending.empty()) break;
          idx = pending.front();
          pending.pop_front();
          ++running;
        }
        SampleResult r = study.run(idx, out.string());
        std::lock_guard<std::mutex> lock(mu);
        local_results.push_back(std::move(r));
      }
      local_done = true;
    });
  }
  std::exception_ptr run_error;
  try {
    while (true) {
      bool busy = false;
#ifdef STRATUM_HAVE_MPI
      if (mpi.size() > 1) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, tag_result, MPI_COMM_WORLD, &flag, &st);
        if (flag) {
          busy = true;
          int n = 0;
          MPI_Get_count(&st, MPI_CHAR, &n);
          std::string buf(static_cast<std::size_t>(n), '\0');
          MPI_Recv(buf.data(), n, MPI_CHAR, st.MPI_SOURCE, tag_result, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
          int idx = -1;
          {
            std::lock_guard<std::mutex> lock(mu);
            if (!buf.empty()) --running;
            if (!pending.empty()) {
              idx = pending.front();
              pending.pop_front();
              ++running;
            }
          }
          if (idx < 0) ++stopped_workers;
          MPI_Send(&idx, 1, MPI_INT, st.MPI_SOURCE, tag_work, MPI_COMM_WORLD);
          if (!buf.empty()) {
            const Finished f = unpack(buf, st.MPI_SOURCE);
            record(f.result, f.rank, f.host);
          }
        }
      }
#endif
      std::vector<SampleResult> mine;
      std::size_t now_running;
      {
        std::lock_guard<std::mutex> lock(mu);
        mine.swap(local_results);
        running -= mine.size();
        now_running = running;
      }
      for (const auto& r : mine) record(r, 0, host);
      busy = busy || !mine.empty();
      progress.show(now_running);
      if (local_done && stopped_workers + 1 == static_cast<std::size_t>(mpi.size())) {
        std::lock_guard<std::mutex> lock(mu);
        if (local_results.empty() && running == 0) break;
      }
      if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  } catch (...) {
    run_error = std::current_exception();
    {
      std::lock_guard<std::mutex> lock(mu);
      pending.clear();
    }
  }
  if (local.joinable()) local.join();
  if (setup_error) std::rethrow_exception(setup_error); // every worker was told to stop
#ifdef STRATUM_HAVE_MPI
  if (run_error && mpi.size() > 1) { // workers may be waiting for an answer: end the job
    try {
      std::rethrow_exception(run_error);
    } catch (const std::exception& e) {
      std::cerr << "stratum: " << e.what() << "\n";
    }
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
#endif
  if (run_error) std::rethrow_exception(run_error);
  progress.show(0, true);
  progress.end();

  std::string csv = study.header() + "\n";
  std::size_t converged = 0, stopped = 0, failed = 0;
  for (const auto& [i, row] : journal->rows()) {
    csv += row + "\n";
    const std::string s = status_of(row);
    (s == "converged" ? converged : s == "stopped" ? stopped : failed) += 1;
  }
  stratum::write_file_atomically((out / "samples.csv").string(), csv);
  std::cout << "done: " << total << " samples (" << converged << " converged, " << stopped << " stopped, "
            << failed << " failed), " << counts[0] + counts[1] + counts[2] << " run now on " << mpi.size()
            << (mpi.size() == 1 ? " process" : " processes")
            << "\nresults: " << (out / "samples.csv").string() << "\n";
  if (failed)
    std::cerr << "sweep: " << failed << " of " << total
              << " samples failed: their status and reason are in samples.csv\n";
  return 0;
}

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
         "exit status: 0 done (samples that failed are listed with their reason in samples.csv),\n"
         "  1 bad input, 3 internal error\n";
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
    study = Study::from_file(file);
  } catch (const Error&) {
    if (mpi.rank() == 0) throw; // every rank reads the same file: rank 0 says what is wrong
    return 1;
  }
#ifdef STRATUM_HAVE_MPI
  if (mpi.rank() != 0) return worker(*study, out);
#endif
  return manager(*study, out, mpi);
}

} // namespace stratum::cli
