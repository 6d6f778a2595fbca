// SPDX-License-Identifier: MIT
// The K-distribution texture and the roughness of object materials (docs/physics.md §1.6, §1.11):
// the texture on an object face follows the Gamma law of its texture_shape, is frozen on the
// object (the same at the same point whatever the ping's speckle), and a ping rendered twice
// is identical.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

using namespace test;  // the Simulator tests' scenes and configurations

constexpr double kNu = 4.0;  // the box's texture shape

// A flat seabed 20 m deep and a 2 m high box 10 m across (x 10 to 20 m) and 30 m along the
// track (y -15 to 15 m), of a textured material.
Scene box_scene(double roughness_rms_m = 0.0) {
  Scene scene = make_scene(-40, -40, 80, 1.0, [](double, double) { return -20.0; });
  const std::uint16_t painted = scene.materials.set({.name = "painted",
                                                     .lambert_mu = 0.1,
                                                     .texture_shape_nu = kNu,
                                                     .roughness_rms_m = roughness_rms_m,
                                                     .roughness_length_m = 0.1});
  return with_test_box(std::move(scene), painted);
}

// The texture of each object sample of the starboard side at `pose`: the textured over the
// untextured intensity (same speckle keys); NaN elsewhere.
std::vector<double> object_texture(const Simulator& with, const Simulator& without,
                                   const PingPose& pose) {
  auto wa = with.make_workspace(), wb = without.make_workspace();
  RenderedPing a, b;
  with.render_ping(pose, *wa, a);
  without.render_ping(pose, *wb, b);
  std::vector<double> t(a.starboard.samples.size(), std::nan(""));
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (a.starboard.truth_class[i] == SampleClass::object && b.starboard.samples[i] > 0.0f) {
      t[i] = static_cast<double>(a.starboard.samples[i]) / b.starboard.samples[i];
    }
  }
  return t;
}

TEST(ObjectTexture, FollowsTheGammaLawOfItsShape) {
  const Scene scene = box_scene();
  const Simulator with(scene, speckle_config(true), 10.0),
      without(scene, speckle_config(false), 10.0);
  double n = 0.0, sum = 0.0, sum2 = 0.0, below_half = 0.0;
  for (int k = 0; k < 100; ++k) {
    PingPose pose = pose_at(scene, {0.0, -10.0 + 0.2 * k}, 0.0, 10.0);
    pose.ping_index = static_cast<std::uint64_t>(k);
    for (double t : object_texture(with, without, pose)) {
      if (std::isnan(t)) continue;
      n += 1.0;
      sum += t;
      sum2 += t * t;
      below_half += t < 0.5 ? 1.0 : 0.0;
    }
  }
  ASSERT_GT(n, 10000.0);
  // Gamma(nu, 1/nu): mean 1, variance 1/nu, P(T < 1/2) = 1 - e^-2 (1 + 2 + 2 + 4/3) for nu = 4.
  const double mean = sum / n;
  EXPECT_NEAR(mean, 1.0, 0.02);
  EXPECT_NEAR(sum2 / n - mean * mean, 1.0 / kNu, 0.02);
  EXPECT_NEAR(below_half / n, 1.0 - std::exp(-2.0) * (5.0 + 4.0 / 3.0), 0.015);
}

TEST(ObjectTexture, FrozenOnTheObjectWhileTheSpeckleChanges) {
  const Scene scene = box_scene();
  const Simulator with(scene, speckle_config(true), 10.0),
      without(scene, speckle_config(false), 10.0);
  // Two pings from the same place whose speckle differs (another noise key and along-track
  // position, as for the next ping of a survey): the same object points, the same texture.
  PingPose first = pose_at(scene, {0.0, 1.0}, 0.0, 10.0);
  first.ping_index = 1;
  first.along_track_m = 100.0;
  PingPose next = first;
  next.ping_index = 2;
  next.along_track_m = 100.3;
  const std::vector<double> t1 = object_texture(with, without, first);
  const std::vector<double> t2 = object_texture(with, without, next);
  auto wa = without.make_workspace();
  RenderedPing a, b;
  without.render_ping(first, *wa, a);
  without.render_ping(next, *wa, b);
  std::size_t compared = 0, speckle_differs = 0;
  for (std::size_t i = 0; i < t1.size(); ++i) {
    if (std::isnan(t1[i])) continue;
    ++compared;
    EXPECT_NEAR(t2[i], t1[i], 1e-6 * t1[i]) << i;  // float samples
    speckle_differs += a.starboard.samples[i] != b.starboard.samples[i] ? 1 : 0;
  }
  EXPECT_GT(compared, 100u);
  EXPECT_GT(speckle_differs, compared / 2);
}

TEST(ObjectTexture, SamePingRenderedTwiceIsIdenticalWithRoughnessAndTexture) {
  const Scene smooth = box_scene(), rough = box_scene(0.01);
  SimulationConfig cfg;  // everything on
  cfg.sonar.max_range_m = 40.0;
  cfg.sonar.samples_per_channel = 800;
  cfg.threads = 1;
  const Simulator sim(rough, cfg, 10.0), sim_smooth(smooth, cfg, 10.0);
  PingPose pose = pose_at(rough, {0.0, 2.0}, 0.0, 10.0);
  pose.ping_index = 7;
  auto ws = sim.make_workspace();
  RenderedPing a, b, c;
  sim.render_ping(pose, *ws, a);
  sim.render_ping(pose, *ws, b);
  EXPECT_EQ(a.starboard.samples, b.starboard.samples);
  EXPECT_EQ(a.port.samples, b.port.samples);
  // The roughness changes the object's echo (the grazing angle varies along its faces), not the
  // seabed's in front of it.
  sim_smooth.render_ping(pose, *ws, c);
  std::size_t object_differs = 0, seabed_differs = 0;
  float grazing_spread = 0.0f;
  for (std::size_t i = 1; i < a.starboard.samples.size(); ++i) {
    const bool object = a.starboard.truth_class[i] == SampleClass::object &&
                        c.starboard.truth_class[i] == SampleClass::object;
    const bool seabed = a.starboard.truth_class[i] == SampleClass::seabed &&
                        a.starboard.truth_ground_xy(i).x() < 7.5;  // nearer than the box (12.8 m)
    const bool differs = a.starboard.samples[i] != c.starboard.samples[i];
    object_differs += object && differs ? 1 : 0;
    seabed_differs += seabed && differs ? 1 : 0;
    if (object) {
      grazing_spread = std::max(grazing_spread, std::abs(a.starboard.truth_grazing_rad[i] -
                                                         c.starboard.truth_grazing_rad[i]));
    }
  }
  EXPECT_GT(object_differs, 100u);
  EXPECT_EQ(seabed_differs, 0u);
  EXPECT_GT(grazing_spread, 0.1f);  // facets tilted by the roughness
}

}  // namespace
}  // namespace sonarsynth
