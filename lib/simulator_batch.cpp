// SPDX-License-Identifier: MIT
// Simulator::render_batch: poses rendered on worker threads into the caller's arrays.
#include <algorithm>
#include <atomic>
#include <exception>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/simulator.hpp"
#include "worker_threads.hpp"

namespace sonarsynth {

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

  const std::size_t samples = side_samples();
  const unsigned requested = static_cast<unsigned>(std::min<std::size_t>(
      detail::worker_thread_count(threads > 0 ? threads : config_.threads), count));
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(requested);
  // Each pose is claimed through the counter and stored in its own slots: the output is the same
  // for any thread count or schedule.
  const auto work = [&](unsigned t) {
    try {
      WorkspacePtr ws;
      {
        const std::lock_guard lock(spare_mutex_);
        if (!spare_workspaces_.empty()) {
          ws = std::move(spare_workspaces_.back());
          spare_workspaces_.pop_back();
        }
      }
      if (!ws) ws = make_workspace();
      std::uint32_t unused[4] = {};
      for (std::size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) {
        const PingPose pose = pose_at(i);
        SideSpans sides[2];
        for (std::size_t k = 0; k < 2; ++k) {
          const std::size_t slot = 2 * i + k, at = slot * samples;
          SideSpans& o = sides[k];
          o.samples = out.samples + at;
          if (out.clean_samples) o.clean_samples = out.clean_samples + at;
          if (out.truth_class) {
            o.truth_class = out.truth_class + at;
            o.truth_label = out.object_id + at;
            o.truth_grazing_rad = out.grazing_rad + at;
            o.truth_ground_x_m = out.ground_x_m + at;
            o.truth_ground_y_m = out.ground_y_m + at;
          }
          o.saturated = out.saturated ? out.saturated + slot : &unused[2 * k];
          o.invalid = out.invalid ? out.invalid + slot : &unused[2 * k + 1];
        }
        // Straight into the caller's slots: render_ping's output, without its copy.
        render_sides(pose, *pose.ping_index, *ws, sides[0], sides[1], nullptr);
      }
      const std::lock_guard lock(spare_mutex_);
      spare_workspaces_.push_back(std::move(ws));
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
