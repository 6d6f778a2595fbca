// SPDX-License-Identifier: MIT
#include "worker_threads.hpp"

#include <algorithm>
#include <atomic>
#include <system_error>

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

}  // namespace sonarsynth::detail
