// SPDX-License-Identifier: MIT
// Simulator::render_batch: equal, bit for bit, to render_ping of each pose, whatever the thread
// count and the split into batches; and the pose checks (check_pose) it applies before rendering
// anything.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

constexpr double kSeabedZ = -20.0;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The seabed: a gentle slope whose heights at the nodes (integer x, y) and bilinear values at
// half-integer points are exact in float.
double seabed_at(double x, double y) {
  return kSeabedZ + x / 32.0 - y / 64.0;
}

// The slope with the test box, speckle noise, truth and clean samples on.
struct Fixture {
  std::shared_ptr<const Scene> scene;
  SimulationConfig config;
  std::unique_ptr<Simulator> sim;
  std::vector<PingPose> poses;

  Fixture() {
    Scene s = test::make_scene(-60.0, -60.0, 120.0, 1.0, seabed_at);
    scene = std::make_shared<const Scene>(test::with_test_box(std::move(s), 0));
    config.sonar.max_range_m = 30.0;
    config.sonar.samples_per_channel = 300;
    config.truth = true;
    config.clean_samples = true;
    config.threads = 1;
    sim = std::make_unique<Simulator>(scene, config, 8.0);
    for (int i = 0; i < 7; ++i) {
      const Eigen::Vector3d at(-10.0 + 3.0 * i, 0.5 * i, kSeabedZ + 8.0);
      poses.push_back(sensor_pose(at, 0.05 * i, 0.01 * i, -0.02 * i, scene->bathymetry,
                                  100 + static_cast<std::uint64_t>(i)));
    }
  }
};

// Arrays of shape (pings, 2, samples) and their BatchOutput.
struct Arrays {
  std::size_t n, s;
  std::vector<float> samples, clean, grazing;
  std::vector<SampleClass> cls;
  std::vector<std::int32_t> id;
  std::vector<double> gx, gy;
  std::vector<std::uint32_t> saturated, invalid;

  Arrays(std::size_t pings, std::size_t per_side)
      : n(pings),
        s(per_side),
        samples(2 * n * s, -7.0f),
        clean(2 * n * s, -7.0f),
        grazing(2 * n * s, -7.0f),
        cls(2 * n * s, SampleClass::no_seabed),
        id(2 * n * s, -7),
        gx(2 * n * s, -7.0),
        gy(2 * n * s, -7.0),
        saturated(2 * n, 7),
        invalid(2 * n, 7) {}

  BatchOutput out() {
    return {samples.data(), clean.data(), cls.data(),       id.data(),     grazing.data(),
            gx.data(),      gy.data(),    saturated.data(), invalid.data()};
  }
  bool untouched() const {
    for (const float v : samples) {
      if (v != -7.0f) return false;
    }
    for (const std::int32_t v : id) {
      if (v != -7) return false;
    }
    return true;
  }
};

template <class T>
bool same_bytes(const T* a, const std::vector<T>& b, std::size_t offset, std::size_t count) {
  return std::memcmp(a, b.data() + offset, count * sizeof(T)) == 0;
}

// Slot `slot` of `a` holds exactly the side `s`.
void expect_side(const Arrays& a, std::size_t slot, const SideOutput& s) {
  const std::size_t o = slot * a.s;
  EXPECT_TRUE(same_bytes(s.samples.data(), a.samples, o, a.s)) << slot;
  EXPECT_TRUE(same_bytes(s.clean_samples.data(), a.clean, o, a.s)) << slot;
  EXPECT_TRUE(same_bytes(s.truth_class.data(), a.cls, o, a.s)) << slot;
  EXPECT_TRUE(same_bytes(s.truth_label.data(), a.id, o, a.s)) << slot;
  EXPECT_TRUE(same_bytes(s.truth_grazing_rad.data(), a.grazing, o, a.s)) << slot;
  // The batch's positions are the ping's, from the same float ground ranges.
  std::vector<double> x(s.truth_ground_range_m.size()), y(x.size());
  s.truth_ground_positions(x.data(), y.data());
  EXPECT_TRUE(same_bytes(x.data(), a.gx, o, a.s)) << slot;
  EXPECT_TRUE(same_bytes(y.data(), a.gy, o, a.s)) << slot;
  EXPECT_EQ(a.saturated[slot], s.saturated);
  EXPECT_EQ(a.invalid[slot], s.invalid);
}

TEST(RenderBatch, EqualsRenderPingForAnyThreadCountAndSplit) {
  const Fixture f;
  const std::size_t n = f.poses.size(), s = f.config.sonar.samples_per_channel;
  // The reference: render_ping of each pose, one after the other.
  std::vector<RenderedPing> single(n);
  auto ws = f.sim->make_workspace();
  for (std::size_t i = 0; i < n; ++i) f.sim->render_ping(f.poses[i], *ws, single[i]);
  bool box_seen = false;
  for (const RenderedPing& p : single) {
    for (const std::int32_t v : p.starboard.truth_label) box_seen = box_seen || v == 9;
  }
  ASSERT_TRUE(box_seen);  // the object is in the comparison

  for (const unsigned threads : {1u, 2u, 3u}) {
    Arrays a(n, s);
    f.sim->render_batch(f.poses, a.out(), threads);
    for (std::size_t i = 0; i < n; ++i) {
      expect_side(a, 2 * i, single[i].port);
      expect_side(a, 2 * i + 1, single[i].starboard);
    }
  }
  // Split into batches of 3, 1 and 3 poses (in the reverse order), each into its own arrays.
  const std::size_t first[] = {4, 3, 0}, count[] = {3, 1, 3};
  for (int b = 0; b < 3; ++b) {
    Arrays a(count[b], s);
    f.sim->render_batch(
        count[b], [&](std::size_t i) { return f.poses[first[b] + i]; }, a.out(), 2);
    for (std::size_t i = 0; i < count[b]; ++i) {
      expect_side(a, 2 * i, single[first[b] + i].port);
      expect_side(a, 2 * i + 1, single[first[b] + i].starboard);
    }
  }
}

TEST(RenderBatch, RefusesBuffersThatDoNotMatchTheConfiguration) {
  const Fixture f;
  Arrays a(f.poses.size(), f.config.sonar.samples_per_channel);
  BatchOutput no_truth = a.out();
  no_truth.object_id = nullptr;
  EXPECT_THROW(f.sim->render_batch(f.poses, no_truth), InputError);
  BatchOutput no_clean = a.out();
  no_clean.clean_samples = nullptr;
  EXPECT_THROW(f.sim->render_batch(f.poses, no_clean), InputError);
  EXPECT_TRUE(a.untouched());
}

// The message of the batch's refusal of `poses` with pose 3 changed by `change`; the buffers
// must stay untouched (nothing rendered).
std::string refusal(const Fixture& f, void (*change)(PingPose&)) {
  std::vector<PingPose> poses = f.poses;
  change(poses[3]);
  Arrays a(poses.size(), f.config.sonar.samples_per_channel);
  try {
    f.sim->render_batch(poses, a.out(), 2, "poses");
  } catch (const InputError& e) {
    EXPECT_TRUE(a.untouched());
    return e.what();
  }
  return "(no error)";
}

TEST(RenderBatch, ChecksEveryPoseBeforeRendering) {
  const Fixture f;
  EXPECT_EQ(refusal(f, [](PingPose& p) { p.sensor_xy_m.x() = kNaN; }),
            "poses[3]: sensor_x_m = nan. Violated constraint: a finite number");
  EXPECT_EQ(refusal(f, [](PingPose& p) { p.sensor_xy_m.y() = -kInf; }),
            "poses[3]: sensor_y_m = -inf. Violated constraint: a finite number");
  EXPECT_EQ(refusal(f, [](PingPose& p) { p.heading_rad = kInf; }),
            "poses[3]: heading_rad = inf. Violated constraint: a finite number");
  EXPECT_EQ(refusal(f, [](PingPose& p) { p.pitch_rad = 1.6; }),
            "poses[3]: pitch_rad = 1.6. Violated constraint: |pitch_rad| <= 1.553343034 rad (89 "
            "deg, the bound of the scene file's survey.disturbance)");
  EXPECT_EQ(refusal(f, [](PingPose& p) { p.roll_rad = kNaN; }).substr(0, 52),
            "poses[3]: roll_rad = nan. Violated constraint: |roll");
  EXPECT_EQ(refusal(f, [](PingPose& p) { p.ping_index.reset(); }),
            "poses[3]: ping_index (the noise key) is unset. Violated constraint: every pose of "
            "a batch carries its noise key");
  // 1 km under the seabed: the seabed height there is computed independently (the slope).
  const std::string under = refusal(f, [](PingPose& p) { p.sensor_z_m -= 1000.0; });
  const Eigen::Vector2d xy = f.poses[3].sensor_xy_m;
  const double z = f.poses[3].sensor_z_m - 1000.0, seabed = seabed_at(xy.x(), xy.y());
  char expected[300];
  std::snprintf(expected, sizeof expected,
                "poses[3]: sensor_z_m = %.10g. Violated constraint: sensor_z_m > %.10g m, the "
                "seabed height at (sensor_x_m, sensor_y_m) = (%.10g, %.10g) (the sensor above "
                "the seabed: altitude %.10g m)",
                z, seabed, xy.x(), xy.y(), z - seabed);
  EXPECT_EQ(under, expected);
  EXPECT_NE(refusal(f, [](PingPose& p) { p.sensor_z_m = 2.0; })
                .find("poses[3]: sensor_z_m = 2. Violated constraint: sensor_z_m <= 0"),
            std::string::npos);
}

TEST(CheckPose, BoundsAndTheSeabedRule) {
  const Fixture f;
  const HeightGrid& g = f.scene->bathymetry;
  PingPose p = f.poses[0];
  EXPECT_EQ(pose_error(p, g), "");
  // The attitude bound itself is allowed, beyond it is not.
  p.pitch_rad = -rad_from_deg(kMaxAttitudeDeg);
  p.roll_rad = rad_from_deg(kMaxAttitudeDeg);
  EXPECT_EQ(pose_error(p, g), "");
  p.roll_rad = std::nextafter(p.roll_rad, 2.0);
  EXPECT_NE(pose_error(p, g).find("roll_rad = "), std::string::npos);
  // On the seabed (altitude 0) is under it (the scene file's rule: altitude > 0); a millimetre
  // above is fine.
  p = f.poses[0];
  const double h = g.height_m(p.sensor_xy_m.x(), p.sensor_xy_m.y());
  p.sensor_z_m = h;
  EXPECT_NE(pose_error(p, g).find("altitude 0 m"), std::string::npos) << pose_error(p, g);
  p.sensor_z_m = h + 1e-3;
  EXPECT_EQ(pose_error(p, g), "");
  // Off the grid there is no seabed to check against: any finite height below the surface...
  p.sensor_xy_m = {500.0, 0.0};
  p.sensor_z_m = -1000.0;
  EXPECT_EQ(pose_error(p, g), "");
  // ... and above it too, as a survey's pings off the grid.
  p.sensor_z_m = 10.0;
  EXPECT_EQ(pose_error(p, g), "");
  // Inf altitude and a negative speed are refused; a NaN altitude (unknown) is not.
  p = f.poses[0];
  p.altitude_m = kNaN;
  EXPECT_EQ(pose_error(p, g), "");
  p.altitude_m = kInf;
  EXPECT_NE(pose_error(p, g).find("altitude_m = inf"), std::string::npos);
  p = f.poses[0];
  p.speed_m_s = -1.0;
  EXPECT_NE(pose_error(p, g).find("speed_m_s = -1"), std::string::npos);
  // Names of the caller's arguments, and check_pose's prefix.
  p = f.poses[0];
  p.sensor_z_m = kNaN;
  try {
    check_pose(p, g, "render_ping", {"x_m", "y_m", "z_m", "h", "p", "r"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "render_ping: z_m = nan. Violated constraint: a finite number");
  }
}

}  // namespace
}  // namespace sonarsynth
