// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/sink_threads.hpp"

#include <time.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <stdexcept>
#include <utility>

namespace sonarsynth::detail {

double thread_cpu_s() noexcept {
  timespec ts{};
  if (::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return 0.0;
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void release_free_memory() noexcept {
#if defined(__GLIBC__)
  ::malloc_trim(0);
#endif
}

BackgroundJob::~BackgroundJob() {
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !busy_; });
    stopping_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void BackgroundJob::loop() noexcept {
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return stopping_ || job_; });
      if (!job_) return;  // stopping, nothing left
      job = std::move(job_);
      job_ = nullptr;
    }
    std::exception_ptr error;
    try {
      job();
    } catch (...) {
      error = std::current_exception();
    }
    job = nullptr;  // what the job holds is released before it counts as done
    release_free_memory();
    {
      std::lock_guard lock(mutex_);
      if (error && !error_) error_ = error;
      cpu_s_ = thread_cpu_s();
      busy_ = false;
    }
    changed_.notify_all();
  }
}

void BackgroundJob::run(std::function<void()> job) {
  wait();
  {
    std::lock_guard lock(mutex_);
    job_ = std::move(job);
    busy_ = true;
  }
  if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
  changed_.notify_all();
}

void BackgroundJob::wait() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return !busy_; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

double BackgroundJob::cpu_s() const {
  std::lock_guard lock(mutex_);
  return cpu_s_;
}

std::shared_ptr<const RenderedPing> copy_for_sinks(const RenderedPing& ping) {
  auto copy = std::make_shared<RenderedPing>();
  copy->pose = ping.pose;
  auto side = [](const SideOutput& from, SideOutput& to) {
    to.samples = from.samples;
    to.saturated = from.saturated;
    to.invalid = from.invalid;
    to.truth_class = from.truth_class;
    to.truth_label = from.truth_label;
    to.truth_grazing_rad = from.truth_grazing_rad;
    // The truth vectors' coverage and the truth rasters' ground control points.
    to.truth_ground_range_m = from.truth_ground_range_m;
    to.truth_nadir_xy_m = from.truth_nadir_xy_m;
    to.truth_across_dir = from.truth_across_dir;
  };
  side(ping.port, copy->port);
  side(ping.starboard, copy->starboard);
  return copy;
}

SinkThread::SinkThread(PingSink& sink, std::string name, std::size_t capacity)
    : sink_(sink), name_(std::move(name)), capacity_(capacity < 1 ? 1 : capacity) {
  thread_ = std::thread([this] { loop(); });
}

SinkThread::~SinkThread() {
  stop();
}

void SinkThread::stop() noexcept {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    queue_.clear();
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SinkThread::loop() noexcept {
  for (;;) {
    Item item;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) break;
      item = std::move(queue_.front());
      queue_.pop_front();
    }
    changed_.notify_all();  // room in the queue
    try {
      switch (item.kind) {
        case Kind::begin_line:
          sink_.begin_line(item.line);
          break;
        case Kind::ping:
          sink_.ping(*item.ping);
          break;
        case Kind::end_line:
          sink_.end_line(item.line);
          break;
        case Kind::finish:
          sink_.finish();
          break;
      }
    } catch (...) {
      std::lock_guard lock(mutex_);
      error_ = std::current_exception();
      done_ = true;
      queue_.clear();
    }
    bool done = false;
    {
      std::lock_guard lock(mutex_);
      if (item.kind == Kind::finish) done_ = true;
      done = done_;
    }
    if (done) {
      changed_.notify_all();
      break;
    }
  }
  cpu_s_ = thread_cpu_s();  // read after the join
}

void SinkThread::push(Item item) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return error_ || stopping_ || done_ || queue_.size() < capacity_; });
  if (error_) std::rethrow_exception(error_);
  if (stopping_ || done_) throw std::logic_error(name_ + ": ping sink called after its end");
  queue_.push_back(std::move(item));
  lock.unlock();
  changed_.notify_all();
}

void SinkThread::begin_line(std::size_t line) {
  push({Kind::begin_line, line, nullptr});
}

void SinkThread::ping(std::shared_ptr<const RenderedPing> ping) {
  push({Kind::ping, 0, std::move(ping)});
}

void SinkThread::end_line(std::size_t line) {
  push({Kind::end_line, line, nullptr});
}

void SinkThread::request_finish() {
  push({Kind::finish, 0, nullptr});
}

void SinkThread::wait_finished() {
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return done_ || stopping_; });
  }
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(error_);
}

void SinkThread::abort() noexcept {
  stop();
  sink_.abort();
}

ParallelSink::ParallelSink(std::vector<PingSink*> inline_sinks, std::vector<Threaded> threaded,
                           std::size_t capacity)
    : inline_(std::move(inline_sinks)) {
  for (const Threaded& t : threaded) {
    threaded_sinks_.push_back(t.sink);
    threads_.push_back(std::make_unique<SinkThread>(*t.sink, t.name, capacity));
  }
}

void ParallelSink::begin(const RunDescription& run) {
  // Before any item is queued: the threads are idle until the first one.
  for (auto* s : threaded_sinks_) s->begin(run);
  for (auto* s : inline_) s->begin(run);
}

void ParallelSink::begin_line(std::size_t line) {
  for (auto& t : threads_) t->begin_line(line);
  for (auto* s : inline_) s->begin_line(line);
}

void ParallelSink::ping(const RenderedPing& ping) {
  if (!threads_.empty()) {
    const std::shared_ptr<const RenderedPing> copy = copy_for_sinks(ping);
    for (auto& t : threads_) t->ping(copy);
  }
  for (auto* s : inline_) s->ping(ping);
}

void ParallelSink::end_line(std::size_t line) {
  for (auto& t : threads_) t->end_line(line);
  for (auto* s : inline_) s->end_line(line);
}

void ParallelSink::finish() {
  for (auto& t : threads_) t->request_finish();  // all finish in parallel
  for (auto& t : threads_) t->wait_finished();
  for (auto* s : inline_) s->finish();
}

void ParallelSink::abort() noexcept {
  for (auto& t : threads_) t->abort();
  for (auto* s : inline_) s->abort();
}

std::vector<std::pair<std::string, double>> ParallelSink::thread_cpu_s() const {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& t : threads_) out.emplace_back(t->name(), t->cpu_s());
  return out;
}

}  // namespace sonarsynth::detail
