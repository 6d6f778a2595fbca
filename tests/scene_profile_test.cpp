// SPDX-License-Identifier: MIT
#include "sonarsynth/scene_profile.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "object_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/scene.hpp"

namespace sonarsynth {
namespace {

using test::add_on_seabed;
using test::flat_scene;
using test::primitive;

double max_z(const BeamProfile& p, std::int32_t* label_at_max = nullptr) {
  double best = -1e9;
  for (std::size_t i = 0; i < p.nodes(); ++i) {
    if (p.z_m[i] > best) {
      best = p.z_m[i];
      if (label_at_max && i > 0) *label_at_max = p.label[i - 1];
    }
  }
  return best;
}

TEST(SceneProfile, SeabedOnlyProfileIsTheGridProfile) {
  Scene scene = flat_scene(1.0, 20.0);
  scene.objects.build_index();
  BeamProfile prof;
  ProfileScratch scratch;
  build_beam_profile(scene, {0.3, 0.2}, {1.0, 0.0}, 30.0, -10.0, {}, prof, scratch);
  ASSERT_GE(prof.nodes(), 30u);
  EXPECT_DOUBLE_EQ(prof.y_m.front(), 0.0);
  EXPECT_DOUBLE_EQ(prof.y_m.back(), 30.0);
  EXPECT_EQ(prof.label.size(), prof.nodes() - 1);
  for (double z : prof.z_m) EXPECT_NEAR(z, -20.0, 1e-6);
  for (auto m : prof.material) EXPECT_EQ(m, scene.materials.index_of("sand"));
  EXPECT_DOUBLE_EQ(prof.sensor_z_m, -10.0);
}

// The heightfield mode (solid_resting_objects = false): resting objects in the height profile.
ProfileOptions heightfield() {
  ProfileOptions o;
  o.solid_resting_objects = false;
  return o;
}

TEST(SceneProfile, ThinPipeOnCoarseGridIsSeenAtFullHeight) {
  // A 0.5 m pipe (radius 0.25) on a 1 m grid, running north; ping line running east across it.
  Scene scene = flat_scene(1.0, 20.0);
  add_on_seabed(scene,
                primitive(ObjectShape::kCylinder, 7, scene.materials.index_of("steel"),
                          {12.37, 0.0}, {20.0, 0.25, 0.25}, 0.0),
                "pipe");
  BeamProfile prof;
  ProfileScratch scratch;
  build_beam_profile(scene, {0.0, 3.0}, {1.0, 0.0}, 40.0, -10.0, heightfield(), prof, scratch);
  std::int32_t label = -1;
  EXPECT_NEAR(max_z(prof, &label), -19.5, 1e-3);  // the pipe's crest, 16 segments
  EXPECT_EQ(label, 7);
  // Every node inside the footprint lies on the circle; outside, on the seabed.
  for (std::size_t i = 0; i < prof.nodes(); ++i) {
    const double v = prof.y_m[i] - 12.37;
    if (std::abs(v) < 0.25 - 1e-9) {
      EXPECT_NEAR(prof.z_m[i], -19.75 + std::sqrt(0.0625 - v * v), 1e-6) << prof.y_m[i];
    } else if (std::abs(v) > 0.25 + 1e-9) {
      EXPECT_NEAR(prof.z_m[i], -20.0, 1e-6);
    }
  }
  // Facets on the pipe carry its id and material; nodes stay in order.
  int pipe_facets = 0;
  for (std::size_t f = 0; f + 1 < prof.nodes(); ++f) {
    EXPECT_LE(prof.y_m[f], prof.y_m[f + 1]);
    if (prof.label[f] == 7) {
      ++pipe_facets;
      EXPECT_EQ(prof.material[f], scene.materials.index_of("steel"));
    }
  }
  EXPECT_GE(pipe_facets, 16);
}

TEST(SceneProfile, BoxHasVerticalWallsAtItsFootprintEdges) {
  Scene scene = flat_scene(0.5, 10.0);
  // u east: 1 m along the ray, 10 m wide, 1 m high
  add_on_seabed(scene, primitive(ObjectShape::kBox, 3, 0, {30.5, 0.0}, {0.5, 5.0, 0.5}, kPi / 2),
                "box");
  BeamProfile prof;
  ProfileScratch scratch;
  build_beam_profile(scene, {0.0, 0.0}, {1.0, 0.0}, 45.0, 0.0, heightfield(), prof, scratch);
  int walls = 0;
  for (std::size_t i = 0; i + 1 < prof.nodes(); ++i) {
    if (prof.y_m[i] == prof.y_m[i + 1]) {
      ++walls;
      EXPECT_NEAR(std::abs(prof.z_m[i + 1] - prof.z_m[i]), 1.0, 1e-6);
      EXPECT_TRUE(std::abs(prof.y_m[i] - 30.0) < 1e-9 || std::abs(prof.y_m[i] - 31.0) < 1e-9);
      EXPECT_EQ(prof.label[i], 3);
    }
  }
  EXPECT_EQ(walls, 2);
  EXPECT_NEAR(max_z(prof), -9.0, 1e-6);
}

TEST(SceneProfile, ObjectsAsClosedSectionsOnTheCircleAndTheBox) {
  // Default: a resting pipe and a box off the seabed as clockwise closed sections; the height
  // profile stays the seabed's.
  Scene scene = flat_scene(1.0, 20.0);
  add_on_seabed(scene, primitive(ObjectShape::kCylinder, 7, 0, {12.37, 0.0}, {20.0, 0.25, 0.25}),
                "pipe");
  // u east: 1 m along the ray
  add_on_seabed(scene, primitive(ObjectShape::kBox, 3, 0, {30.5, 0.0}, {0.5, 5.0, 0.5}, kPi / 2),
                "box", 2.0);
  BeamProfile prof;
  ProfileScratch scratch;
  build_beam_profile(scene, {0.0, 0.0}, {1.0, 0.0}, 40.0, -10.0, {}, prof, scratch);
  for (double z : prof.z_m) EXPECT_NEAR(z, -20.0, 1e-6);
  for (auto l : prof.label) EXPECT_EQ(l, 0);
  ASSERT_EQ(prof.sections(), 2u);
  double area[2] = {0.0, 0.0};
  for (std::size_t s = 0; s < 2; ++s) {
    const std::uint32_t a = prof.section_start[s], b = prof.section_start[s + 1];
    for (std::uint32_t k = a; k < b; ++k) {
      const std::uint32_t n = k + 1 < b ? k + 1 : a;
      // Shoelace: negative for a clockwise polygon in (y, z).
      area[s] += 0.5 * (prof.section_y_m[k] * prof.section_z_m[n] -
                        prof.section_y_m[n] * prof.section_z_m[k]);
      if (prof.section_label[s] == 7) {
        EXPECT_NEAR(std::hypot(prof.section_y_m[k] - 12.37, prof.section_z_m[k] + 19.75), 0.25,
                    1e-6);
      }
    }
  }
  const std::size_t ip = prof.section_label[0] == 7 ? 0 : 1;
  EXPECT_EQ(prof.section_label[1 - ip], 3);
  EXPECT_EQ(prof.section_start[ip + 1] - prof.section_start[ip], 32u);  // 16 per half
  // The 32-gon inscribed in the circle and the 1 m x 1 m box.
  EXPECT_NEAR(area[ip], -0.5 * 32 * 0.0625 * std::sin(2 * kPi / 32), 1e-6);
  EXPECT_NEAR(area[1 - ip], -1.0, 1e-6);
}

TEST(SceneProfile, RejectsBadOptions) {
  ProfileOptions o;
  o.grid_subdivisions = 0;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.object_segments = 1;
  EXPECT_THROW(o.validate(), InputError);
}

}  // namespace
}  // namespace sonarsynth
