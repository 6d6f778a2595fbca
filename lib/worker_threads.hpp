// SPDX-License-Identifier: MIT
// Starting worker threads without hanging or aborting when the system refuses one (containers
// with a pids limit, an exhausted thread table). Internal to sonarsynth_core.
#pragma once

#include <functional>
#include <thread>

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

}  // namespace sonarsynth::detail
