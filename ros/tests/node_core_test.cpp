// SPDX-License-Identifier: MIT
// The node's ROS-free part against analytic truths: the frames (docs/robotics.md, "Frames"), the
// interpolation, the ping clock, the waterfall's layout and the parameters' mapping onto the
// scene file's options, the latency histogram against exact quantiles.
#include "node_core.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth::ros_node {
namespace {

constexpr double kPi = std::numbers::pi;

// base_link in odom from ROS yaw (about z), pitch (about the new y), roll (about the new x).
Eigen::Quaterniond enu(double yaw, double pitch, double roll) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

TEST(NodeFrames, HeadingPitchRollFromEnuOrientation) {
  // Facing east (yaw 0): heading 90 deg; facing north (yaw 90 deg): heading 0.
  EXPECT_NEAR(attitude_of(enu(0, 0, 0)).heading_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(attitude_of(enu(kPi / 2, 0, 0)).heading_rad, 0.0, 1e-12);
  // A body x axis pointing at (east, north) = (-1, -1) (south-west): heading 225 deg = -135.
  const Attitude sw = attitude_of(enu(-3 * kPi / 4, 0, 0));
  EXPECT_NEAR(std::remainder(sw.heading_rad - 5 * kPi / 4, 2 * kPi), 0.0, 1e-12);
  // ROS pitch + is nose down (about y = left): the renderer's pitch + is nose up.
  const Eigen::Vector3d nose = enu(0.3, 0.2, 0) * Eigen::Vector3d::UnitX();
  EXPECT_LT(nose.z(), 0.0);
  EXPECT_NEAR(attitude_of(enu(0.3, 0.2, 0)).pitch_rad, -0.2, 1e-12);
  // ROS roll + lifts the left (port) side: starboard down, the renderer's roll +.
  const Eigen::Vector3d left = enu(0, 0, 0.1) * Eigen::Vector3d::UnitY();
  EXPECT_GT(left.z(), 0.0);
  const Attitude a = attitude_of(enu(1.1, -0.15, 0.25));
  EXPECT_NEAR(a.heading_rad, kPi / 2 - 1.1, 1e-12);
  EXPECT_NEAR(a.pitch_rad, 0.15, 1e-12);
  EXPECT_NEAR(a.roll_rad, 0.25, 1e-12);
  // A quaternion not normalised gives the same angles.
  Eigen::Quaterniond q = enu(1.1, -0.15, 0.25);
  q.coeffs() *= 3.0;
  EXPECT_NEAR(attitude_of(q).roll_rad, 0.25, 1e-12);
}

TEST(NodeFrames, InterpolationLinearAndSlerpExactAtTheEnds) {
  OdomSample a, b;
  a.stamp_ns = 1'000'000'000;
  b.stamp_ns = 1'400'000'000;
  a.position_m = {0, 0, -5};
  b.position_m = {4, -2, -6};
  a.orientation = enu(0.0, 0, 0);
  b.orientation = enu(0.4, 0, 0);
  a.speed_m_s = 1.0;
  b.speed_m_s = 2.0;
  const OdomSample m = interpolate(a, b, 1'100'000'000);
  EXPECT_NEAR((m.position_m - Eigen::Vector3d(1, -0.5, -5.25)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(attitude_of(m.orientation).heading_rad, kPi / 2 - 0.1, 1e-12);
  EXPECT_NEAR(m.speed_m_s, 1.25, 1e-12);
  EXPECT_EQ(m.stamp_ns, 1'100'000'000u);
  const OdomSample ea = interpolate(a, b, a.stamp_ns), eb = interpolate(a, b, b.stamp_ns);
  EXPECT_EQ(ea.position_m, a.position_m);
  EXPECT_EQ(ea.orientation.coeffs(), a.orientation.coeffs());
  EXPECT_EQ(eb.position_m, b.position_m);
  EXPECT_EQ(eb.orientation.coeffs(), b.orientation.coeffs());
}

TEST(NodeClock, OnePingPerPeriodFromTheFirstPose) {
  PingClock clock(0.04, 1.0);
  std::vector<ScheduledPing> due;
  OdomSample s;
  const std::uint64_t t0 = 5'000'000'000;
  for (std::uint64_t dt : {0ull, 100'000'000ull, 250'000'000ull}) {
    s.stamp_ns = t0 + dt;
    ASSERT_TRUE(clock.add(s, due));
  }
  // 0, 40, ..., 240 ms: 7 pings, in order.
  ASSERT_EQ(due.size(), 7u);
  for (std::size_t k = 0; k < due.size(); ++k) {
    EXPECT_EQ(due[k].index, k);
    EXPECT_EQ(due[k].time_ns, t0 + 40'000'000ull * k);
    EXPECT_EQ(due[k].pose.stamp_ns, due[k].time_ns);
  }
  s.stamp_ns = t0 + 250'000'000;  // not after the last: refused
  EXPECT_FALSE(clock.add(s, due));
  EXPECT_EQ(due.size(), 7u);
  // A 2 s dropout (> max gap 1 s): its pings are skipped, not interpolated.
  s.stamp_ns = t0 + 2'250'000'000;
  ASSERT_TRUE(clock.add(s, due));
  EXPECT_EQ(due.size(), 7u);
  EXPECT_EQ(clock.skipped(), 50u);  // 280 ms ... 2240 ms
  EXPECT_THROW(PingClock(0.0, 1.0), InputError);
  EXPECT_THROW(PingClock(0.1, -1.0), InputError);
}

TEST(NodeWaterfall, NewestRowFirstPortFarToNearOnTheLeft) {
  Waterfall w(3, 4, Colormap::grey, 100.0);
  RenderedPing p;
  p.port.samples = {0, 25, 50, 100};
  p.starboard.samples = {100, 0, 0, 50};
  w.add(p);
  p.port.samples = {100, 100, 100, 100};
  w.add(p);
  std::vector<std::uint8_t> rgb(3 * 8 * 3, 7);
  w.image(rgb.data());
  ASSERT_EQ(rgb.size(), 3u * 8u * 3u);
  const auto px = [&](std::size_t row, std::size_t col) { return rgb[(row * 8 + col) * 3]; };
  EXPECT_EQ(px(0, 0), 255);  // newest: all port samples full scale
  // Row 1, the first ping: port far (100) at the left edge, near (0) next to the centre.
  EXPECT_EQ(px(1, 0), 255);
  EXPECT_EQ(px(1, 1), 128);  // 50 / 100, rounded
  EXPECT_EQ(px(1, 3), 0);
  EXPECT_EQ(px(1, 4), 255);  // starboard near
  EXPECT_EQ(px(1, 7), 128);  // starboard far
  EXPECT_EQ(px(2, 0), 0);    // not filled yet
}

TEST(NodeParameters, OptionValuesGoThroughTheSceneFile) {
  const std::string scene = std::string(SONARSYNTH_ROS_TEST_DIR) + "/node_test_scene.yaml";
  const SimulationSetup base = load_setup(scene, {}, {});
  EXPECT_EQ(base.config.sonar.samples_per_channel, 1024u);
  const SimulationSetup s = load_setup(
      scene, {{"sonar.samples", "256"}, {"sonar.frequency_khz", "410.5"}, {"seed", "7"}}, {});
  EXPECT_EQ(s.config.sonar.samples_per_channel, 256u);
  EXPECT_DOUBLE_EQ(s.config.sonar.frequency_hz, 410.5e3);
  EXPECT_EQ(s.config.seed, 7u);
  SimulationOverrides o;
  o.range_m = 20.0;
  EXPECT_DOUBLE_EQ(load_setup(scene, {}, o).config.sonar.max_range_m, 20.0);
  // A value out of range: the scene file's own message, naming the key.
  try {
    load_setup(scene, {{"sonar.range_m", "-3"}}, {});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("range_m"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_setup(scene, {{"sonar.no_such_key", "1"}}, {}), InputError);
}

// The exact nearest-rank q-quantile: the ceil(q n)-th smallest value.
double exact_quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(k, 1, v.size()) - 1];
}

void expect_quantiles_within_resolution(const std::vector<double>& v, const char* what) {
  LatencyHistogram h;
  for (double x : v) h.add(x);
  ASSERT_EQ(h.count(), v.size());
  EXPECT_EQ(h.min(), *std::min_element(v.begin(), v.end())) << what;
  EXPECT_EQ(h.max(), *std::max_element(v.begin(), v.end())) << what;
  const double bound = LatencyHistogram::kRelativeError * (1.0 + 1e-12);
  for (double q : {1e-4, 0.01, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99, 0.999, 1.0}) {
    const double exact = exact_quantile(v, q);
    EXPECT_LE(std::abs(h.quantile(q) / exact - 1.0), bound)
        << what << " q " << q << ": " << h.quantile(q) << " vs exact " << exact;
  }
}

TEST(NodeLatency, HistogramQuantilesWithinItsResolution) {
  EXPECT_NEAR(LatencyHistogram::kRelativeError, 0.0108893, 1e-6);  // 2^(1/64) - 1
  std::mt19937_64 rng(7);
  std::vector<double> v;
  // A grid of 1 ms steps, shuffled: 1, 2, ..., 20000 ms.
  for (int i = 1; i <= 20000; ++i) v.push_back(1e-3 * i);
  std::shuffle(v.begin(), v.end(), rng);
  expect_quantiles_within_resolution(v, "grid");
  v.clear();
  std::exponential_distribution<double> expo(1.0 / 2e-3);  // mean 2 ms
  for (int i = 0; i < 100000; ++i) v.push_back(expo(rng) + 1e-5);
  expect_quantiles_within_resolution(v, "exponential");
  v.clear();
  std::lognormal_distribution<double> logn(std::log(1e-3), 1.5);  // median 1 ms, wide tail
  for (int i = 0; i < 100000; ++i) v.push_back(logn(rng));
  expect_quantiles_within_resolution(v, "lognormal");
  v.clear();
  std::uniform_real_distribution<double> uni(0.5e-3, 50e-3);
  for (int i = 0; i < 50001; ++i) v.push_back(uni(rng));
  expect_quantiles_within_resolution(v, "uniform");
}

TEST(NodeLatency, HistogramEdgesExactAndOutOfRange) {
  LatencyHistogram h;
  EXPECT_EQ(h.quantile(0.5), 0.0);  // empty
  for (int i = 0; i < 9; ++i) h.add(3.25e-3);
  EXPECT_EQ(h.quantile(0.5), 3.25e-3);  // one value: clamped to min = max, exact
  EXPECT_EQ(h.quantile(1.0), 3.25e-3);
  h.clear();
  EXPECT_EQ(h.count(), 0u);
  // Below the lowest bin (0, a negative value): reported as the minimum, within kLowestS.
  h.add(-1.0);
  h.add(2e-7);
  h.add(5e-7);
  h.add(2000.0);  // above the highest bin: reported as the maximum
  EXPECT_EQ(h.count(), 4u);
  EXPECT_EQ(h.min(), 0.0);
  EXPECT_EQ(h.quantile(0.25), 0.0);
  EXPECT_LE(std::abs(h.quantile(0.75) - 5e-7), LatencyHistogram::kLowestS);
  EXPECT_EQ(h.quantile(1.0), 2000.0);
  // Fixed memory: the same size after a million pings.
  for (int i = 0; i < 1000000; ++i) h.add(1e-3 * (1 + i % 97));
  EXPECT_EQ(h.count(), 1000004u);
  EXPECT_LT(sizeof(LatencyHistogram), 8192u);
}

}  // namespace
}  // namespace sonarsynth::ros_node
