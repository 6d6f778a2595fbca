// SPDX-License-Identifier: MIT
#include "worker_threads.hpp"

#include <algorithm>
#include <atomic>
#include <system_error>
#include <utility>

namespace sonarsynth::detail {

namespace {
std::atomic<int> g_starts_left{-1};
}

unsigned max_worker_threads() {
  return std::max(4u, 4u * std::thread::hardware_concurrency());
}

unsigned worker_thread_count(unsigned requested) {
  const unsigned n = requested > 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
  return std::clamp(n, 1u, max_worker_threads());
}

std::jthread try_start_thread(std::function<void()> fn) noexcept {
  int left = g_starts_left.load();
  while (left >= 0) {
    if (left == 0) return {};
    if (g_starts_left.compare_exchange_weak(left, left - 1)) break;
  }
  try {
    return std::jthread(std::move(fn));
  } catch (...) {  // std::system_error (EAGAIN) or bad_alloc
    return {};
  }
}

void fail_thread_starts_after_for_testing(int successes) {
  g_starts_left.store(successes);
}

WorkerPool::WorkerPool(unsigned requested_threads, std::function<void(unsigned)> work)
    : work_(std::move(work)) {
  helpers_.reserve(requested_threads);  // no allocation (nor throw) once threads run
  for (unsigned t = 1; t < requested_threads; ++t) {
    std::jthread h = try_start_thread([this, t] {
      std::uint64_t seen = 0;
      while (true) {
        {
          std::unique_lock lock(mutex_);
          wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
          if (stop_) return;
          seen = generation_;
        }
        work_(t);
        {
          const std::lock_guard lock(mutex_);
          --busy_;
        }
        done_.notify_one();
      }
    });
    // The system refused a thread (pids limit): go on with those that started.
    if (!h.joinable()) break;
    helpers_.push_back(std::move(h));
  }
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  helpers_.clear();  // joins
}

void WorkerPool::start() {
  {
    const std::lock_guard lock(mutex_);
    busy_ = threads() - 1;
    ++generation_;
  }
  wake_.notify_all();
}

void WorkerPool::finish() {
  work_(0);
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return busy_ == 0; });
}

}  // namespace sonarsynth::detail
