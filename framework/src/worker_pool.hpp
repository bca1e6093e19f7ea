// A small pool of worker threads for the element loop (framework-internal).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace stratum {

/// Runs a job over an index range on `threads` threads: the caller and threads - 1 workers,
/// which sleep between jobs (no spinning, so an idle pool costs nothing on a shared machine).
/// Blocks of indices are handed out dynamically; run() returns when all are done and
/// rethrows the first exception a block threw.
class WorkerPool {
public:
  /// fn(begin, end, worker): process indices [begin, end); worker in [0, threads) names the
  /// thread, for per-thread scratch.
  using Job = std::function<void(std::size_t, std::size_t, int)>;

  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  [[nodiscard]] int threads() const { return static_cast<int>(workers_.size()) + 1; }
  void run(std::size_t n, std::size_t block, const Job& job);

private:
  void work(int worker);
  void loop(int worker);

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  const Job* job_ = nullptr;
  std::size_t n_ = 0, block_ = 1;
  std::atomic<std::size_t> next_{0};
  unsigned long generation_ = 0;
  int busy_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

/// The number of threads a setting asks for: n >= 1 as given, 0 = the hardware's threads.
[[nodiscard]] int resolve_threads(long long setting);

} // namespace stratum
