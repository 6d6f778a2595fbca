// SPDX-License-Identifier: MIT
// Simulator::render_ping allocates nothing once its workspace and output have held the pings
// of a line (the per-ping pipeline reuses its buffers: no allocation per ping).
// Counted by replacing the global operator new of this test binary; every effect of the default
// sensor is on.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "simulator_test_util.hpp"
#include "sonarsynth/simulator.hpp"

// The replacement pair below is malloc/free by design; GCC's -Wmismatched-new-delete sees
// free() on a pointer from operator new once the calls are inlined (sanitizer builds).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return ::operator new(size);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

namespace sonarsynth {
namespace {

TEST(NoAllocation, RenderPingReusesItsBuffers) {
  // A gently sloping seabed with a box on it; speckle with texture, along-track correlation,
  // three detector looks, the default sensor (noise floor, reverberation, first return,
  // shadow fill), the sonar equation and truth.
  Scene scene =
      test::make_scene(-60, -60, 120, 0.5, [](double x, double) { return -20.0 + 0.02 * x; });
  test::add_on_seabed(scene,
                      test::primitive(ObjectShape::kBox, 3, scene.materials.index_of("sand"),
                                      {15.0, 0.0}, {2.0, 3.0, 1.0}),
                      "box");

  SimulationConfig c;
  c.sonar.max_range_m = 40.0;
  c.sonar.samples_per_channel = 1000;
  c.noise.model = NoiseConfig::Model::kSpeckle;
  c.noise.texture = true;
  c.noise.along_track_correlation = true;
  c.output.detector_sub_samples = 3;
  c.truth = true;
  c.threads = 1;
  const Simulator sim(scene, c, 10.0);
  auto ws = sim.make_workspace();
  RenderedPing out;
  const auto pose = [&](int k) {
    PingPose p = test::pose_at(scene, {0.0, -10.0 + 0.2 * k}, 0.0, 10.0);
    p.ping_index = static_cast<std::uint64_t>(k);
    p.speed_m_s = 2.0;
    return p;
  };
  // A first pass along the line: the buffers grow to what the line needs (the box enters the
  // beam half-way). A second pass over the same pings must allocate nothing.
  for (int k = 0; k < 60; ++k) sim.render_ping(pose(k), *ws, out);
  std::size_t object_samples = 0;
  const long before = g_allocations.load();
  for (int k = 0; k < 60; ++k) {
    sim.render_ping(pose(k), *ws, out);
    for (const SampleClass cls : out.starboard.truth_class) {
      object_samples += cls == SampleClass::object;
    }
  }
  const long allocations = g_allocations.load() - before;
  EXPECT_EQ(allocations, 0) << "allocations in 60 pings";
  EXPECT_GT(object_samples, 0u);  // the box was in view: its code paths ran
}

}  // namespace
}  // namespace sonarsynth
