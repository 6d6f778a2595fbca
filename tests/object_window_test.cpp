// SPDX-License-Identifier: MIT
// The object window of the automatic along-track plane count (docs/physics.md §1.3): a side
// that sees an object renders the object's planes only over the slant ranges the object and its
// shadow affect, and the seabed's planes elsewhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "simulator_test_util.hpp"
#include "sonarsynth/along_track_planes.hpp"
#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/simulator.hpp"

namespace sonarsynth {
namespace {

using test::make_scene;
using test::plain_config;
using test::pose_at;

// An undulating seabed 20 m below the sensor, 0 <= y <= 60 m in 0.2 m facets, with a closed
// 3 m x 2 m box section from y = 25 m (2 m tall, resting on the seabed) when `box`.
double box_base_z() {
  return -20.0 + 0.3 * std::sin(0.7 * 25.0) + 0.1 * std::sin(2.3 * 25.0) - 0.2;
}

BeamProfile profile_with(bool box) {
  BeamProfile p;
  p.sensor_z_m = 0.0;
  for (int i = 0; i <= 300; ++i) {
    const double y = 0.2 * i;
    p.y_m.push_back(y);
    p.z_m.push_back(-20.0 + 0.3 * std::sin(0.7 * y) + 0.1 * std::sin(2.3 * y));
    if (i > 0) {
      p.label.push_back(0);
      p.material.push_back(0);
    }
  }
  if (box) {
    const double z0 = box_base_z();
    // Clockwise in (y, z) (BeamProfile).
    const double ys[] = {25.0, 25.0, 28.0, 28.0}, zs[] = {z0, z0 + 2.0, z0 + 2.0, z0};
    p.add_section(ys, zs, 4, 7, 0);
  }
  return p;
}

SideParams side_params(double pulse_window_m) {
  SideParams par;
  par.sample_spacing_m = 0.02;
  par.samples = 3500;  // 70 m
  par.beam_axis_depression_rad = 0.5;
  par.pulse_window_m = pulse_window_m;
  return par;
}

TEST(ObjectWindow, RenderFromAndFewerSamplesLeaveTheWindowBitIdentical) {
  const BeamProfile prof = profile_with(true);
  for (const double w : {0.0, 0.05, 0.04}) {  // bin, split bins, whole bins
    const SideParams full = side_params(w);
    SideEcho a, b;
    render_side(prof, full, a);
    SideParams part = full;
    part.samples = 2200;
    part.render_from_m = 24.3;
    render_side(prof, part, b);
    const double dr = full.sample_spacing_m, reach = std::max(w, dr);
    std::size_t checked = 0, lit = 0;
    for (std::size_t i = 0; i < part.samples; ++i) {
      // Sample i integrates [(i + 1) dr - reach, (i + 1) dr].
      if (static_cast<double>(i + 1) * dr - reach < part.render_from_m) continue;
      ASSERT_EQ(a.intensity[i], b.intensity[i]) << "sample " << i << ", pulse window " << w;
      ++checked;
      lit += a.intensity[i] > 0.0;
    }
    EXPECT_GT(checked, 900u);
    EXPECT_GT(lit, 100u);
    // Nearer, the skipped facets leave samples dark that the full render lights.
    EXPECT_EQ(b.intensity[1000], 0.0);
    EXPECT_GT(a.intensity[1000], 0.0);
  }
}

TEST(ObjectWindow, TheObjectChangesNothingOutsideItsWindow) {
  const BeamProfile with = profile_with(true), without = profile_with(false);
  double r_lo = 0.0, r_hi = 0.0;
  EXPECT_FALSE(object_range_window(without, r_lo, r_hi));
  ASSERT_TRUE(object_range_window(with, r_lo, r_hi));
  // Its nearest point to the sensor: the front face's top corner.
  EXPECT_NEAR(r_lo, std::hypot(25.0, box_base_z() + 2.0), 1e-12);
  // The box's top edge (y 28 m, 2 m up) casts a shadow that ends before the profile's end.
  EXPECT_GT(r_hi, 33.0);
  EXPECT_LT(r_hi, 60.0);
  for (const double w : {0.0, 0.05}) {
    const SideParams par = side_params(w);
    SideEcho a, b;
    render_side(with, par, a);
    render_side(without, par, b);
    const double dr = par.sample_spacing_m, reach = std::max(w, dr);
    std::size_t outside = 0, differ_inside = 0;
    for (std::size_t i = 0; i < par.samples; ++i) {
      const double hi = static_cast<double>(i + 1) * dr, lo = hi - reach;
      if (hi < r_lo || lo > r_hi) {
        ASSERT_NEAR(a.intensity[i], b.intensity[i], 1e-12 * b.intensity[i]) << "sample " << i;
        ++outside;
      } else {
        differ_inside += std::abs(a.intensity[i] - b.intensity[i]) > 1e-3 * b.intensity[i];
      }
    }
    EXPECT_GT(outside, 2000u);
    // The box's echo and its shadow fill most of the window.
    EXPECT_GT(static_cast<double>(differ_inside), 0.5 * (r_hi - r_lo) / dr);
  }
}

// A flat seabed with a tall box at an angle to the track, 25 m to starboard: the seabed needs
// one plane, the box more.
class BoxScene : public ::testing::Test {
 protected:
  BoxScene() : scene_(make_scene(-60, -60, 120, 0.25, [](double, double) { return -20.0; })) {
    test::add_on_seabed(scene_,
                        test::primitive(ObjectShape::kBox, 4, scene_.materials.index_of("steel"),
                                        {26.0, 0.0}, {4.0, 1.0, 2.0}, rad_from_deg(40.0)),
                        "box");
    cfg_ = plain_config();
    cfg_.sonar.samples_per_channel = 2000;
    cfg_.sonar.horizontal_beam_width_rad = rad_from_deg(1.5);
    pilot_ = test::poses_at_y(scene_, {-6.0, -2.0, 0.0, 2.0, 6.0});
  }
  std::vector<std::vector<float>> render(int planes) const {
    SimulationConfig cfg = cfg_;
    cfg.quality.along_track_planes = planes;
    return test::render_sides(Simulator(scene_, cfg, 10.0, pilot_), pilot_);
  }
  Scene scene_;
  SimulationConfig cfg_;
  std::vector<PingPose> pilot_;
};

TEST_F(BoxScene, WindowHoldsTheObjectPlanesAndTheSeabedPlanesElsewhere) {
  const Simulator sim(scene_, cfg_, 10.0, pilot_);
  const AlongTrackChoice& c = sim.along_track();
  ASSERT_TRUE(c.automatic);
  EXPECT_EQ(c.planes, 1);  // the flat seabed
  ASSERT_GT(c.object_planes, 1);
  EXPECT_GT(c.object_estimated_error_db, c.estimated_error_db);
  const auto one = render(1), many = render(c.object_planes), autom = render(0);
  std::size_t window = 0, differ = 0;
  for (std::size_t s = 0; s < autom.size(); ++s) {
    for (std::size_t i = 0; i < autom[s].size(); ++i) {
      const float a = autom[s][i], x = one[s][i], y = many[s][i];
      // On the flat seabed every plane sees the same profile: the planes' shares of beta_eff
      // sum to the one plane's, so the two counts agree to round-off there.
      const bool same = std::abs(x - y) <= 1e-5f * std::max(x, y);
      differ += !same;
      if (same) {
        EXPECT_NEAR(a, x, 1e-5f * x) << "side " << s << " sample " << i;
      } else {
        // Where the object makes the counts differ the window holds the object planes (bit for
        // bit but for the central plane, the run plane's scaled to its share: round-off).
        EXPECT_NEAR(a, y, 1e-6f * y) << "side " << s << " sample " << i;
        ++window;
      }
    }
  }
  EXPECT_GT(differ, 100u);
  EXPECT_EQ(window, differ);
}

TEST_F(BoxScene, ExplicitCountsAndSceneWithoutObjectsHaveNoWindow) {
  SimulationConfig cfg = cfg_;
  cfg.quality.along_track_planes = 5;
  const Simulator fixed(scene_, cfg, 10.0, pilot_);
  EXPECT_EQ(fixed.along_track().object_planes, 5);
  EXPECT_TRUE(std::isnan(fixed.along_track().object_estimated_error_db));
  Scene bare = scene_;
  bare.objects = ObjectSet();
  const Simulator plain(bare, cfg_, 10.0, pilot_);
  EXPECT_EQ(plain.along_track().planes, 1);
  EXPECT_EQ(plain.along_track().object_planes, 1);
  EXPECT_TRUE(std::isnan(plain.along_track().object_estimated_error_db));
}

}  // namespace
}  // namespace sonarsynth
