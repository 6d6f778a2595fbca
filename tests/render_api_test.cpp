// SPDX-License-Identifier: MIT
// The library's render API: noise keys that cannot repeat silently, clean and noisy samples from
// one call, full sensor poses, the sink lifecycle, the vertical beam's -3 dB width.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

constexpr double kSeabedZ = -30.0;

std::shared_ptr<const Scene> flat_scene() {
  return std::make_shared<const Scene>(
      test::make_scene(-60, -60, 120, 1.0, [](double, double) { return kSeabedZ; }));
}

SimulationConfig speckle_config() {
  SimulationConfig c;
  c.sonar.max_range_m = 30.0;
  c.sonar.samples_per_channel = 600;
  c.threads = 1;
  return c;  // speckle noise, TVG, u16 output
}

// Float output without TVG: the thermal noise of the water column is not rounded away.
SimulationConfig float_config() {
  SimulationConfig c = speckle_config();
  c.output.tvg = TvgLaw::none;
  c.output.round_to_integer = false;
  c.output.max_value = 3.0e38;
  return c;
}

constexpr double kAltitude = 10.0;

PingPose pose_at(const Scene& s, double x, std::optional<std::uint64_t> key) {
  return sensor_pose(Eigen::Vector3d(x, 0.0, kSeabedZ + kAltitude), 0.0, 0.0, 0.0, s.bathymetry,
                     key);
}

// Samples nearer than the altitude see only water: their values are pure thermal noise.
std::vector<float> water_column(const SideOutput& side, const SimulationConfig& c) {
  const auto n = static_cast<std::size_t>(kAltitude / c.sonar.sample_spacing_m()) - 2;
  return {side.samples.begin(), side.samples.begin() + static_cast<std::ptrdiff_t>(n)};
}

std::size_t equal_count(const std::vector<float>& a, const std::vector<float>& b) {
  std::size_t k = 0;
  for (std::size_t i = 0; i < a.size(); ++i) k += a[i] == b[i] ? 1 : 0;
  return k;
}

TEST(RenderApi, UnkeyedPingsGetDifferentNoiseAndTheSameKeyGivesTheSameNoise) {
  const auto scene = flat_scene();
  const SimulationConfig cfg = float_config();
  const Simulator sim(scene, cfg, kAltitude);
  auto ws = sim.make_workspace();
  RenderedPing a, b, c, d;
  sim.render_ping(pose_at(*scene, 0.0, std::nullopt), *ws, a);
  sim.render_ping(pose_at(*scene, 0.3, std::nullopt), *ws, b);
  const std::vector<float> wa = water_column(a.starboard, cfg), wb = water_column(b.starboard, cfg);
  ASSERT_GT(wa.size(), 50u);
  // Thermal noise as floats: two independent draws are practically never equal.
  EXPECT_LT(equal_count(wa, wb), wa.size() / 4);
  // The keys the Simulator assigned are recorded, distinct and outside the survey's range.
  ASSERT_TRUE(a.pose.ping_index && b.pose.ping_index);
  EXPECT_NE(*a.pose.ping_index, *b.pose.ping_index);
  EXPECT_GE(*a.pose.ping_index, std::uint64_t{1} << 63);

  // The same explicit key at the same pose: the same noise, bit for bit, in any order.
  sim.render_ping(pose_at(*scene, 0.3, 7), *ws, c);
  sim.render_ping(pose_at(*scene, 0.0, 8), *ws, d);
  RenderedPing c2;
  sim.render_ping(pose_at(*scene, 0.3, 7), *ws, c2);
  EXPECT_EQ(c.port.samples, c2.port.samples);
  EXPECT_EQ(c.starboard.samples, c2.starboard.samples);
  EXPECT_EQ(*c.pose.ping_index, 7u);
  // ... and a different explicit key changes it.
  EXPECT_LT(equal_count(water_column(c.starboard, cfg), water_column(d.starboard, cfg)),
            wa.size() / 4);
}

TEST(RenderApi, CleanSamplesComeWithTheNoisyOnesAndEqualANoiseFreeRender) {
  const auto scene = flat_scene();
  SimulationConfig cfg = speckle_config();
  cfg.clean_samples = true;
  const Simulator noisy(scene, cfg, kAltitude);
  SimulationConfig quiet_cfg = cfg;
  quiet_cfg.noise.model = NoiseConfig::Model::kNone;
  quiet_cfg.clean_samples = false;
  // The automatic gain allows for the speckle's median: give the noise-free run the same gain.
  quiet_cfg.output.gain_db = noisy.gain_db();
  const Simulator quiet(scene, quiet_cfg, kAltitude);
  auto wn = noisy.make_workspace(), wq = quiet.make_workspace();
  RenderedPing n, q;
  noisy.render_ping(pose_at(*scene, 0.1, 3), *wn, n);
  quiet.render_ping(pose_at(*scene, 0.1, 3), *wq, q);
  EXPECT_EQ(n.starboard.clean_samples, q.starboard.samples);
  EXPECT_EQ(n.port.clean_samples, q.port.samples);
  EXPECT_NE(n.starboard.samples, n.starboard.clean_samples);  // noise was added
  EXPECT_TRUE(q.starboard.clean_samples.empty());             // only on request
}

TEST(RenderApi, SensorPoseTakesTheAltitudeFromTheSeabed) {
  const auto scene = flat_scene();
  const PingPose p =
      sensor_pose(Eigen::Vector3d(3.0, -4.0, -18.5), 1.0, 0.1, -0.2, scene->bathymetry, 42);
  EXPECT_DOUBLE_EQ(p.altitude_m, -18.5 - kSeabedZ);
  EXPECT_EQ(p.sensor_xy_m, Eigen::Vector2d(3.0, -4.0));
  EXPECT_EQ(p.reference_xy_m, p.sensor_xy_m);
  EXPECT_EQ(p.heading_rad, 1.0);
  EXPECT_EQ(p.pitch_rad, 0.1);
  EXPECT_EQ(p.roll_rad, -0.2);
  EXPECT_EQ(p.ping_index, std::optional<std::uint64_t>(42));
  EXPECT_TRUE(std::isnan(
      sensor_pose(Eigen::Vector3d(500.0, 0.0, 0.0), 0, 0, 0, scene->bathymetry).altitude_m));
}

// Records the hooks in order.
struct RecordingSink : PingSink {
  std::vector<std::string> events;
  std::size_t throw_at_ping = static_cast<std::size_t>(-1);
  std::size_t pings = 0;
  void begin(const RunDescription& r) override {
    events.push_back("begin " + std::to_string(r.total_pings) + " " + std::to_string(r.line_count));
  }
  void begin_line(std::size_t l) override { events.push_back("line " + std::to_string(l)); }
  void ping(const RenderedPing&) override {
    if (pings++ == throw_at_ping) throw std::runtime_error("sink failed");
  }
  void end_line(std::size_t l) override { events.push_back("end " + std::to_string(l)); }
  void finish() override { events.emplace_back("finish"); }
  void abort() noexcept override { events.emplace_back("abort"); }
};

Survey two_lines() {
  VehicleConfig v;
  v.speed_m_s = 10.0;
  v.altitude_m = kAltitude;
  return Survey(
      {SurveyLine{"a", {{-20.0, 0.0}, {20.0, 0.0}}}, SurveyLine{"b", {{20.0, 5.0}, {-20.0, 5.0}}}},
      v, 0.2, UtcTime{}, 1);
}

TEST(RenderApi, RunCallsBeginLinesAndFinishInOrder) {
  const auto scene = flat_scene();
  const Simulator sim(scene, speckle_config(), kAltitude);
  const Survey survey = two_lines();
  RecordingSink sink;
  sim.run(survey, sink);
  EXPECT_EQ(sink.pings, survey.total_pings());
  const std::vector<std::string> expected = {"begin " + std::to_string(survey.total_pings()) + " 2",
                                             "line 0",
                                             "end 0",
                                             "line 1",
                                             "end 1",
                                             "finish"};
  EXPECT_EQ(sink.events, expected);
}

TEST(RenderApi, RunCallsAbortAndRethrowsWhenASinkFails) {
  const auto scene = flat_scene();
  const Simulator sim(scene, speckle_config(), kAltitude);
  RecordingSink sink;
  sink.throw_at_ping = 3;
  EXPECT_THROW(sim.run(two_lines(), sink), std::runtime_error);
  const std::vector<std::string> expected = {
      "begin " + std::to_string(two_lines().total_pings()) + " 2", "line 0", "abort"};
  EXPECT_EQ(sink.events, expected);
}

TEST(RenderApi, SimulatorKeepsTheSharedSceneAlive) {
  auto scene = flat_scene();
  const std::weak_ptr<const Scene> watch = scene;
  const Simulator sim(std::move(scene), speckle_config(), kAltitude);
  EXPECT_FALSE(watch.expired());
  EXPECT_EQ(&sim.scene(), watch.lock().get());
  EXPECT_THROW(Simulator(std::shared_ptr<const Scene>(), speckle_config(), kAltitude), InputError);
}

TEST(VerticalBeamWidth, EachShapeGivesItsMinus3dBWidth) {
  VerticalBeamPattern g;
  g.shape = VerticalBeamShape::gaussian;
  g.width_3db_rad = 0.7;
  EXPECT_DOUBLE_EQ(g.width_3db_full_rad(), 0.7);

  VerticalBeamPattern p;
  p.shape = VerticalBeamShape::paper_sine_pair;
  p.upper_half_width_rad = 0.4;
  p.lower_half_width_rad = 0.6;
  // b = cos(pi/2 off / w) = 1/2 at off = 2 w / 3 on each side.
  EXPECT_NEAR(p.width_3db_full_rad(), 2.0 / 3.0 * (0.4 + 0.6), 1e-9);

  VerticalBeamPattern s;
  s.shape = VerticalBeamShape::sinc;
  s.height_over_wavelength = 2.0;
  // [sin x / x]^2 = 1/2 at x = 1.39155737825151, x = pi H sin(off).
  const double off = std::asin(1.39155737825151 / (kPi * 2.0));
  EXPECT_NEAR(s.width_3db_full_rad(), 2.0 * off, 1e-9);

  VerticalBeamPattern t;
  t.shape = VerticalBeamShape::table;
  t.table_off_axis_rad = {-0.5, 0.0, 0.4};
  t.table_gain_db = {-6.0, 0.0, -6.0};
  // Linear in dB: -3.0103 dB (b = 1/2) at 0.5 x 3.0103/6 above and 0.4 x 3.0103/6 below.
  const double db = -10.0 * std::log10(0.5);
  EXPECT_NEAR(t.width_3db_full_rad(), 0.9 * db / 6.0, 1e-9);

  VerticalBeamPattern u;  // uniform: no -3 dB points
  EXPECT_EQ(u.width_3db_full_rad(), 0.0);
}

}  // namespace
}  // namespace sonarsynth
