// SPDX-License-Identifier: MIT
// Worker threads: starting them without hanging or aborting when the system refuses one
// (containers with a pids limit, an exhausted thread table), and the persistent pool the
// simulator renders with. Internal to sonarsynth_core.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace sonarsynth::detail {

/// The most threads a renderer starts: four per hardware thread (at least 4). More only adds
/// memory and scheduling cost; results do not depend on the count.
unsigned max_worker_threads();

/// `requested` (0 = hardware concurrency) clamped to [1, max_worker_threads()].
unsigned worker_thread_count(unsigned requested);

/// Starts `fn` on a new thread. Returns a thread that is not joinable if the system cannot create
/// one (std::system_error from std::jthread); never throws.
std::jthread try_start_thread(std::function<void()> fn) noexcept;

/// Testing only: after `successes` more successful starts, try_start_thread fails as if the
/// system had refused; a negative value (the default) never fails.
void fail_thread_starts_after_for_testing(int successes);

/// Persistent helper threads that work in rounds together with the calling thread. start() wakes
/// the helpers, each of which calls work(t) once with its index t in [1, threads()); finish()
/// calls work(0) on the calling thread, then waits until every helper has returned from work.
/// Helpers the system refuses to start are left out (threads() counts those that started plus
/// the caller); the result of a round must not depend on the count. work must not throw (catch
/// and hand exceptions over in the caller's own state). Data the round reads may be written
/// between finish() and the next start() without further synchronisation. The destructor wakes
/// the helpers for exit and joins them; a round still running is finished first, so make work
/// return early (e.g. stop handing out items) before destroying a pool in the middle of a round.
class WorkerPool {
 public:
  WorkerPool(unsigned requested_threads, std::function<void(unsigned)> work);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Helpers that started, plus the calling thread.
  unsigned threads() const { return static_cast<unsigned>(helpers_.size()) + 1; }
  /// Begins a round on the helpers (returns at once).
  void start();
  /// Does the calling thread's share of the round, then waits for the helpers' shares.
  void finish();

 private:
  std::function<void(unsigned)> work_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;
  unsigned busy_ = 0;
  bool stop_ = false;
  std::vector<std::jthread> helpers_;
};

}  // namespace sonarsynth::detail
