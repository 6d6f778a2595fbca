// SPDX-License-Identifier: MIT
#pragma once
// Private helpers of run_simulation and the survey products: ping sinks run on threads of their
// own, fed through bounded queues, so that the products are written while the survey renders.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sonarsynth/ping_sink.hpp"

namespace sonarsynth::detail {

/// CPU time of the calling thread, seconds (CLOCK_THREAD_CPUTIME_ID).
double thread_cpu_s() noexcept;

/// Returns the free pages of the C allocator's heaps to the system (glibc: malloc_trim; a no-op
/// elsewhere). Large buffers freed by one thread otherwise stay resident in that thread's arena,
/// and the resident size of the run keeps the sum of every thread's largest moment.
void release_free_memory() noexcept;

/// One job at a time on a thread of its own (the same thread for every job, started with the
/// first): run() waits for the previous job (rethrowing its exception), then hands `job` over;
/// wait() waits for the last one and rethrows its exception. The destructor waits without
/// throwing. Used to write a finished line's images while the next line accumulates.
class BackgroundJob {
 public:
  BackgroundJob() = default;
  ~BackgroundJob();
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;
  void run(std::function<void()> job);
  void wait();
  /// Thread CPU time of the jobs finished so far, seconds.
  double cpu_s() const;

 private:
  void loop() noexcept;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::function<void()> job_;  ///< the job handed over, until the thread takes it
  bool busy_ = false;          ///< a job is handed over or running
  bool stopping_ = false;
  std::exception_ptr error_;
  double cpu_s_ = 0.0;
  std::thread thread_;
};

/// A copy of the part of a rendered ping that the sinks read (samples, truth class, label,
/// grazing angle and ground position, the pose), shared by every queue that holds it.
std::shared_ptr<const RenderedPing> copy_for_sinks(const RenderedPing& ping);

/// Calls the hooks of a sink on a thread of its own, in the order they were queued. At most
/// `capacity` pings wait in the queue: queueing more blocks the caller until the sink catches up
/// (memory stays bounded whatever the survey length). If the sink throws, the thread stops
/// consuming and the exception is rethrown by the next call made from the producing side
/// (ping, begin_line, end_line, finish); abort() stops the thread, then calls the sink's abort().
class SinkThread {
 public:
  SinkThread(PingSink& sink, std::string name, std::size_t capacity);
  ~SinkThread();  ///< stops the thread without calling the sink's abort()
  SinkThread(const SinkThread&) = delete;
  SinkThread& operator=(const SinkThread&) = delete;

  void begin_line(std::size_t line);
  void ping(std::shared_ptr<const RenderedPing> ping);
  void end_line(std::size_t line);
  /// Queues finish() (returns at once; see wait_finished()).
  void request_finish();
  /// Waits for the thread to run finish(), joins it, rethrows the sink's exception if any.
  void wait_finished();
  void abort() noexcept;
  const std::string& name() const { return name_; }
  /// CPU time of the thread, seconds (valid after finish()).
  double cpu_s() const { return cpu_s_; }

 private:
  enum class Kind { begin_line, ping, end_line, finish };
  struct Item {
    Kind kind;
    std::size_t line = 0;
    std::shared_ptr<const RenderedPing> ping;
  };
  void push(Item item);
  void loop() noexcept;
  void stop() noexcept;

  PingSink& sink_;
  std::string name_;
  std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Item> queue_;
  bool stopping_ = false;
  bool done_ = false;  ///< the thread ran finish() or failed
  std::exception_ptr error_;
  double cpu_s_ = 0.0;
  std::thread thread_;
};

/// A sink that passes every call on to `inline_sinks` on the calling thread, in order, and to
/// each of `threaded` on a SinkThread of its own (one shared copy of each ping for all of them).
/// Errors of a threaded sink surface at the next call from the producing side (the Simulator
/// then calls abort(): every threaded sink is stopped and aborted, then the inline ones).
class ParallelSink : public PingSink {
 public:
  struct Threaded {
    PingSink* sink;
    std::string name;
  };
  ParallelSink(std::vector<PingSink*> inline_sinks, std::vector<Threaded> threaded,
               std::size_t capacity = 32);
  void begin(const RunDescription& run) override;
  void begin_line(std::size_t line) override;
  void ping(const RenderedPing& ping) override;
  void end_line(std::size_t line) override;
  void finish() override;
  void abort() noexcept override;
  /// Per threaded sink: name and CPU seconds of its thread (after finish()).
  std::vector<std::pair<std::string, double>> thread_cpu_s() const;

 private:
  std::vector<PingSink*> inline_;
  std::vector<PingSink*> threaded_sinks_;
  std::vector<std::unique_ptr<SinkThread>> threads_;
};

}  // namespace sonarsynth::detail
