// SPDX-License-Identifier: MIT
// When the system refuses to start a thread (a container's pids limit), the renderers go on with
// the threads that started and give the same output; they never hang or abort. The refusal is
// simulated by the worker_threads testing hook (a real pids limit cannot be set as root).
#include "worker_threads.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <thread>

#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

struct ResetHook {
  ~ResetHook() { detail::fail_thread_starts_after_for_testing(-1); }
};

struct CollectSink : PingSink {
  std::vector<std::vector<float>> samples;
  void ping(const RenderedPing& p) override {
    samples.push_back(p.port.samples);
    samples.push_back(p.starboard.samples);
  }
};

std::vector<std::vector<float>> render(unsigned threads, int starts_allowed) {
  BathyGenSpec spec;
  spec.depth_m = 20.0;
  spec.geometry = BathyGenSpec::centred_geometry(0.0, 0.0, 120.0, 120.0, 0.5);
  spec.components.push_back(bathy::Ripples{});
  spec.num_threads = 1;
  Scene scene(GeoFrame(31, true, 500000.0, 5000000.0));
  scene.bathymetry = generate_bathymetry(spec);
  scene.material_map = MaterialMap(scene.materials.index_of("sand"));
  SimulationConfig cfg;  // speckle, texture, TVG, quantisation: everything on
  cfg.sonar.max_range_m = 30.0;
  cfg.sonar.samples_per_channel = 256;
  cfg.quality.along_track_planes = 1;
  cfg.threads = threads;
  VehicleConfig v;
  v.speed_m_s = 5.0;
  Survey survey({SurveyLine{"L", {{-40.0, 0.0}, {40.0, 5.0}}}}, v, 0.05, UtcTime{}, 3);
  const ResetHook reset;
  detail::fail_thread_starts_after_for_testing(starts_allowed);
  Simulator sim(scene, cfg, v.altitude_m);
  CollectSink sink;
  sim.run(survey, sink);
  EXPECT_EQ(sink.samples.size(), 2 * survey.total_pings());
  return sink.samples;
}

TEST(WorkerThreads, SimulatorGoesOnWithTheThreadsThatStarted) {
  const auto reference = render(1, -1);
  ASSERT_FALSE(reference.empty());
  EXPECT_TRUE(render(4, 1) == reference) << "4 requested, 1 helper started";
  EXPECT_TRUE(render(4, 0) == reference) << "4 requested, no helper started";
}

TEST(WorkerThreads, BathymetryComputesTheRefusedThreadsShareItself) {
  BathyGenSpec s;
  s.depth_m = 20.0;
  s.geometry = BathyGenSpec::centred_geometry(0.0, 0.0, 80.0, 60.0, 0.25);
  s.seed = 7;
  s.components.push_back(bathy::Fbm{});
  s.num_threads = 1;
  const HeightGrid one = generate_bathymetry(s);
  const ResetHook reset;
  for (const int allowed : {0, 2}) {
    detail::fail_thread_starts_after_for_testing(allowed);
    s.num_threads = 6;
    const HeightGrid many = generate_bathymetry(s);
    ASSERT_EQ(many.heights().size(), one.heights().size());
    EXPECT_EQ(std::memcmp(many.heights().data(), one.heights().data(),
                          one.heights().size() * sizeof(float)),
              0)
        << allowed << " threads allowed";
  }
}

// A request is honoured up to four threads per hardware thread (four if that is unknown) and
// cut to that beyond it; 0 asks for one per hardware thread. Every request up to the limit is
// tried, and requests past it up to the largest unsigned.
TEST(WorkerThreads, CountHonoursRequestsUpToFourPerHardwareThread) {
  const unsigned hardware = std::thread::hardware_concurrency();  // 0 when unknown
  const unsigned limit = 4u * (hardware > 0 ? hardware : 1u);
  for (unsigned r = 1; r <= limit; ++r) EXPECT_EQ(detail::worker_thread_count(r), r) << r;
  for (const unsigned r : {limit + 1, 2 * limit, 100000u, std::numeric_limits<unsigned>::max()}) {
    EXPECT_EQ(detail::worker_thread_count(r), limit) << r;
  }
  EXPECT_EQ(detail::worker_thread_count(0), hardware > 0 ? hardware : 1u);
  EXPECT_EQ(detail::max_worker_threads(), limit);
}

}  // namespace
}  // namespace sonarsynth
