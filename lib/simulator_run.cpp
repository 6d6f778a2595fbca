// SPDX-License-Identifier: MIT
// Simulator::run: the survey rendered on worker threads, handed to a sink in order.
#include <algorithm>
#include <atomic>
#include <exception>

#include "sonarsynth/simulator.hpp"
#include "worker_threads.hpp"

namespace sonarsynth {

RenderTimings Simulator::run(
    const Survey& survey, PingSink& sink,
    const std::function<void(std::uint64_t, std::uint64_t)>& progress) const {
  try {
    RunDescription d;
    d.config = config_;
    d.gain_db = gain_db();
    d.absorption_db_per_m = alpha_db_per_m_;
    d.total_pings = survey.total_pings();
    d.line_count = survey.line_count();
    sink.begin(d);
    const RenderTimings t = run_pings(survey, sink, progress);
    sink.finish();
    return t;
  } catch (...) {
    sink.abort();
    throw;
  }
}

RenderTimings Simulator::run_pings(
    const Survey& survey, PingSink& sink,
    const std::function<void(std::uint64_t, std::uint64_t)>& progress) const {
  const unsigned requested_threads = detail::worker_thread_count(config_.threads);
  const std::uint64_t total = survey.total_pings();
  // 32 pings per thread a block, fewer when pings are large (long sides with truth) so that a
  // block holds at most kBlockBytes: two blocks are in flight. Never fewer than one per thread
  // (the output does not depend on the block size, see Job).
  constexpr std::uint64_t kBlockBytes = 4ULL << 20;
  const std::uint64_t sample_bytes = sizeof(float) * (config_.clean_samples ? 2 : 1) +
                                     (config_.truth ? sizeof(SampleClass) + sizeof(std::int32_t) +
                                                          sizeof(float) + 2 * sizeof(double)
                                                    : 0);
  const std::uint64_t ping_bytes =
      std::max<std::uint64_t>(1, 2 * config_.sonar.samples_per_channel * sample_bytes);
  const std::uint64_t block = std::clamp<std::uint64_t>(kBlockBytes / ping_bytes, requested_threads,
                                                        32ULL * requested_threads);
  std::vector<WorkspacePtr> workspaces;
  std::vector<RenderTimings> timings(requested_threads);
  for (unsigned t = 0; t < requested_threads; ++t) workspaces.push_back(make_workspace());
  // Two buffers: the calling thread hands block b to the sink while the helpers already render
  // block b + 1 (it then joins them).
  std::vector<RenderedPing> pings[2] = {std::vector<RenderedPing>(std::min(block, total)),
                                        std::vector<RenderedPing>(std::min(block, total))};
  std::vector<std::exception_ptr> errors(requested_threads);

  // The block being rendered: pings [first, first + count) into pings[buf]. Runs of `run`
  // consecutive pings are claimed through an atomic counter (dynamic load balance; consecutive
  // pings on one thread reuse what its workspace keeps between pings) and each ping is stored at
  // its own index; every ping is a pure function of its index (what a workspace keeps gives the
  // values it would compute), so the output is the same for any thread count or schedule.
  struct Job {
    std::uint64_t first = 0, count = 0, run = 1;
    int buf = 0;
    std::atomic<std::uint64_t> next{0};
  } job;
  auto work = [&](unsigned t) {
    try {
      for (std::uint64_t i0 = job.next.fetch_add(job.run); i0 < job.count;
           i0 = job.next.fetch_add(job.run)) {
        const std::uint64_t i1 = std::min(job.count, i0 + job.run);
        for (std::uint64_t i = i0; i < i1; ++i) {
          render_ping(survey.pose(job.first + i, scene_->bathymetry), *workspaces[t],
                      pings[job.buf][i], &timings[t]);
        }
      }
    } catch (...) {
      if (!errors[t]) errors[t] = std::current_exception();
      job.next.store(job.count);  // the others stop claiming pings
    }
  };

  // Persistent helper threads 1 .. threads - 1, woken once per block (detail::WorkerPool); if
  // the system refuses some, the others go on and the output does not depend on the count.
  detail::WorkerPool pool(requested_threads, work);
  // Declared after `pool`, so destroyed before it (also when the sink throws): no more pings
  // claimed, then the pool wakes its helpers for exit and joins them.
  struct StopClaims {
    Job& job;
    ~StopClaims() { job.next.store(job.count); }
  } stop_claims{job};
  auto start = [&](std::uint64_t first, int buf) {
    job.first = first;  // the helpers are idle between finish() and start()
    job.count = std::min(block, total - first);
    // About four runs per thread and block: long enough to keep state, short enough to balance.
    job.run = std::max<std::uint64_t>(1, job.count / (4ULL * requested_threads));
    job.buf = buf;
    job.next.store(0);
    pool.start();
  };
  auto finish = [&] {
    pool.finish();
    for (auto& e : errors) {
      if (e) std::rethrow_exception(e);
    }
  };

  std::size_t current_line = static_cast<std::size_t>(-1);
  auto emit = [&](const std::vector<RenderedPing>& buf, std::uint64_t first, std::uint64_t count) {
    for (std::uint64_t i = 0; i < count; ++i) {
      const std::size_t line = buf[i].pose.line;
      if (line != current_line) {
        if (current_line != static_cast<std::size_t>(-1)) sink.end_line(current_line);
        sink.begin_line(line);
        current_line = line;
      }
      sink.ping(buf[i]);
    }
    if (progress) progress(first + count, total);
  };

  if (total > 0) {
    start(0, 0);
    finish();
  }
  for (std::uint64_t first = 0; first < total; first += block) {
    const std::uint64_t count = std::min(block, total - first);
    const int buf = static_cast<int>((first / block) % 2);
    const std::uint64_t next_first = first + block;
    if (next_first < total) start(next_first, 1 - buf);
    emit(pings[buf], first, count);
    if (next_first < total) finish();
  }
  if (current_line != static_cast<std::size_t>(-1)) sink.end_line(current_line);
  RenderTimings sum;
  for (const auto& t : timings) {
    sum.profile_s += t.profile_s;
    sum.render_s += t.render_s;
    sum.noise_s += t.noise_s;
    sum.refined_sides += t.refined_sides;
    sum.refined_planes += t.refined_planes;
    sum.window_sides += t.window_sides;
    sum.window_samples += t.window_samples;
  }
  return sum;
}

}  // namespace sonarsynth
