#include "worker_pool.hpp"

#include <algorithm>
#include <utility>

namespace stratum {

WorkerPool::WorkerPool(int threads) {
  for (int w = 1; w < threads; ++w) workers_.emplace_back([this, w] { loop(w); });
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void WorkerPool::work(int worker) {
  for (;;) {
    const std::size_t begin = next_.fetch_add(block_);
    if (begin >= n_) return;
    try {
      (*job_)(begin, std::min(begin + block_, n_), worker);
    } catch (...) {
      const std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
      next_ = n_; // the others stop taking blocks
    }
  }
}

void WorkerPool::loop(int worker) {
  unsigned long seen = 0;
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    lock.unlock();
    work(worker);
    lock.lock();
    if (--busy_ == 0) done_.notify_one();
  }
}

void WorkerPool::run(std::size_t n, std::size_t block, const Job& job) {
  if (n == 0) return;
  block = std::max<std::size_t>(block, 1);
  if (workers_.empty() || n <= block) {
    job(0, n, 0);
    return;
  }
  {
    const std::lock_guard lock(mutex_);
    job_ = &job;
    n_ = n;
    block_ = block;
    next_ = 0;
    busy_ = static_cast<int>(workers_.size());
    error_ = nullptr;
    ++generation_;
  }
  wake_.notify_all();
  work(0);
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return busy_ == 0; });
  job_ = nullptr;
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

int resolve_threads(long long setting) {
  if (setting >= 1) return static_cast<int>(setting);
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

} // namespace stratum
