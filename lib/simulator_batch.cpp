// SPDX-License-Identifier: MIT
// Simulator::render_batch: poses rendered on worker threads into the caller's arrays.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <exception>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/simulator.hpp"
#include "worker_threads.hpp"

namespace sonarsynth {

namespace {

// Copies one side's vector into its slot of a (pings, 2, samples) array.
template <class T, class V>
void put(T* dst, std::size_t slot, std::size_t samples, const V& v) {
  if (v.size() != samples) {
    throw Error("render_batch: a side of " + std::to_string(v.size()) + " samples, not " +
                std::to_string(samples));
  }
  std::memcpy(dst + slot * samples, v.data(), samples * sizeof(T));
}

void store(const BatchOutput& out, std::size_t slot, std::size_t samples, const SideOutput& s) {
  put(out.samples, slot, samples, s.samples);
  if (out.clean_samples) put(out.clean_samples, slot, samples, s.clean_samples);
  if (out.truth_class) {
    put(out.truth_class, slot, samples, s.truth_class);
    put(out.object_id, slot, samples, s.truth_label);
    put(out.grazing_rad, slot, samples, s.truth_grazing_rad);
    put(out.ground_x_m, slot, samples, s.truth_ground_x_m);
    put(out.ground_y_m, slot, samples, s.truth_ground_y_m);
  }
  if (out.saturated) out.saturated[slot] = s.saturated;
  if (out.invalid) out.invalid[slot] = s.invalid;
}

}  // namespace

void Simulator::render_batch(const std::vector<PingPose>& poses, const BatchOutput& out,
                             unsigned threads, const std::string& who) const {
  render_batch(
      poses.size(), [&](std::size_t i) { return poses[i]; }, out, threads, who);
}

void Simulator::render_batch(std::size_t count, const std::function<PingPose(std::size_t)>& pose_at,
                             const BatchOutput& out, unsigned threads,
                             const std::string& who) const {
  const bool truth_arrays =
      out.truth_class || out.object_id || out.grazing_rad || out.ground_x_m || out.ground_y_m;
  const bool all_truth =
      out.truth_class && out.object_id && out.grazing_rad && out.ground_x_m && out.ground_y_m;
  if (!out.samples) throw InputError("render_batch: no samples array");
  if (config_.truth ? !all_truth : truth_arrays) {
    throw InputError(std::string("render_batch: the five truth arrays are needed exactly when ") +
                     "truth is on (it is " + (config_.truth ? "on" : "off") + ")");
  }
  if (config_.clean_samples != (out.clean_samples != nullptr)) {
    throw InputError(std::string("render_batch: clean_samples is needed exactly when the ") +
                     "option clean_samples is on (it is " + (config_.clean_samples ? "on" : "off") +
                     ")");
  }
  // Every pose checked before any is rendered.
  for (std::size_t i = 0; i < count; ++i) {
    const PingPose p = pose_at(i);
    const std::string e = pose_error(p, scene_->bathymetry);
    if (!e.empty()) throw InputError(who + "[" + std::to_string(i) + "]: " + e);
    if (!p.ping_index) {
      throw InputError(who + "[" + std::to_string(i) +
                       "]: ping_index (the noise key) is unset. Violated constraint: every pose "
                       "of a batch carries its noise key");
    }
  }
  if (count == 0) return;

  const std::size_t samples = config_.sonar.samples_per_channel;
  const unsigned requested = static_cast<unsigned>(std::min<std::size_t>(
      detail::worker_thread_count(threads > 0 ? threads : config_.threads), count));
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(requested);
  // Each pose is claimed through the counter and stored in its own slots: the output is the same
  // for any thread count or schedule.
  const auto work = [&](unsigned t) {
    try {
      WorkspacePtr ws = make_workspace();
      RenderedPing ping;
      for (std::size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) {
        render_ping(pose_at(i), *ws, ping);
        store(out, 2 * i, samples, ping.port);
        store(out, 2 * i + 1, samples, ping.starboard);
      }
    } catch (...) {
      if (!errors[t]) errors[t] = std::current_exception();
      next.store(count);  // the others stop claiming poses
    }
  };
  {
    // Helpers the system refuses to start are left out (the output does not depend on it).
    detail::WorkerPool pool(requested, work);
    pool.start();
    pool.finish();
  }
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace sonarsynth
