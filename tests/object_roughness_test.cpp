// SPDX-License-Identifier: MIT
// Roughness of object surfaces (docs/physics.md §1.11): the displaced section against the
// configured RMS and the Gaussian autocorrelation exp(-d^2 / (2 L^2)) of its correlation length.
#include "sonarsynth/object_roughness.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "object_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/scene_profile.hpp"

namespace sonarsynth {
namespace {

constexpr double kSeabedZ = -20.0, kTopZ = -18.0;  // a 2 m box on a flat seabed
constexpr double kRms = 0.02, kLength = 0.1;

// A flat seabed and one 10 m wide box (x from 10 to 20 m, y from -15 to 15 m) of material
// `mat`, labelled `id`.
Scene box_scene(const Material& mat, std::int32_t id) {
  Scene scene(GeoFrame(19, true, 500000.0, 5000000.0));
  const std::size_t n = 61;
  GridGeometry g{-30.0, 30.0, 1.0, -1.0, n, n};
  scene.bathymetry = HeightGrid(g, std::vector<float>(g.size(), static_cast<float>(kSeabedZ)));
  scene.material_map = MaterialMap(scene.materials.index_of("sand"));
  // u along north
  test::add_on_seabed(scene,
                      test::primitive(ObjectShape::kBox, id, scene.materials.set(mat), {15.0, 0.0},
                                      {15.0, 5.0, 1.0}),
                      "box");
  return scene;
}

// Heights above the box top of the section's top-face nodes away from the corners, in the order
// of the section (outward), for the plane through (0, y) looking east.
std::vector<double> top_heights(const Scene& scene, double y, ProfileScratch& scratch) {
  BeamProfile prof;
  build_beam_profile(scene, {0.0, y}, {1.0, 0.0}, 40.0, -10.0, {}, prof, scratch);
  EXPECT_EQ(prof.sections(), 1u);
  std::vector<double> h;
  for (std::size_t k = 0; k < prof.section_y_m.size(); ++k) {
    const double yy = prof.section_y_m[k], z = prof.section_z_m[k];
    if (yy > 10.2 && yy < 19.8 && z > kTopZ - 0.5) {
      if (!h.empty()) {
        EXPECT_NEAR(yy - prof.section_y_m[k - 1], kLength / 3.0, 1e-9);
      }
      h.push_back(z - kTopZ);
    }
  }
  return h;
}

TEST(ObjectRoughness, SmoothMaterialLeavesTheSectionExact) {
  const Scene scene = box_scene(Material{.name = "plate"}, 3);
  BeamProfile prof;
  ProfileScratch scratch;
  build_beam_profile(scene, {0.0, 1.3}, {1.0, 0.0}, 40.0, -10.0, {}, prof, scratch);
  ASSERT_EQ(prof.sections(), 1u);
  EXPECT_EQ(prof.section_y_m.size(), 4u);  // the four corners, nothing added
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_TRUE(prof.section_z_m[k] == kTopZ || prof.section_z_m[k] == kSeabedZ);
  }
}

TEST(ObjectRoughness, DisplacementHasTheConfiguredRmsAndCorrelation) {
  const Material rough{.name = "plate", .roughness_rms_m = kRms, .roughness_length_m = kLength};
  // Lag L (3 nodes) and 3 L (9 nodes): exp(-1/2) and exp(-9/2).
  double sum2 = 0.0, lag1 = 0.0, lag3 = 0.0, n = 0.0;
  double sum2_lag1 = 0.0, sum2_lag3 = 0.0;
  ProfileScratch scratch;
  for (std::int32_t id = 1; id <= 40; ++id) {
    const Scene scene = box_scene(rough, id);
    for (int plane = 0; plane < 10; ++plane) {
      const std::vector<double> h = top_heights(scene, -12.0 + 2.5 * plane, scratch);
      ASSERT_GT(h.size(), 250u);
      for (std::size_t j = 0; j < h.size(); ++j) {
        sum2 += h[j] * h[j];
        n += 1.0;
        if (j + 3 < h.size()) {
          lag1 += h[j] * h[j + 3];
          sum2_lag1 += h[j] * h[j];
        }
        if (j + 9 < h.size()) {
          lag3 += h[j] * h[j + 9];
          sum2_lag3 += h[j] * h[j];
        }
      }
    }
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), kRms, 0.03 * kRms);
  EXPECT_NEAR(lag1 / sum2_lag1, std::exp(-0.5), 0.05);
  EXPECT_NEAR(lag3 / sum2_lag3, std::exp(-4.5), 0.05);
}

TEST(ObjectRoughness, FrozenOnTheObjectAndKeyedOnItsId) {
  const Material rough{.name = "plate", .roughness_rms_m = kRms, .roughness_length_m = kLength};
  ProfileScratch scratch;
  const Scene a = box_scene(rough, 5), b = box_scene(rough, 5), c = box_scene(rough, 6);
  // The same plane twice (any scratch state), and in an identical scene: the same surface.
  const std::vector<double> h1 = top_heights(a, 2.0, scratch);
  top_heights(a, 7.0, scratch);
  EXPECT_EQ(top_heights(a, 2.0, scratch), h1);
  EXPECT_EQ(top_heights(b, 2.0, scratch), h1);
  // Another object: another surface.
  EXPECT_NE(top_heights(c, 2.0, scratch), h1);
  // The node over (15, 2) moved up by the field there (the top face's normal is vertical).
  BeamProfile prof;
  build_beam_profile(a, {0.0, 2.0}, {1.0, 0.0}, 40.0, -10.0, {}, prof, scratch);
  const RoughnessWaves waves(5);
  int found = 0;
  for (std::size_t k = 0; k < prof.section_y_m.size(); ++k) {
    if (std::abs(prof.section_y_m[k] - 15.0) < 1e-9 && prof.section_z_m[k] > kTopZ - 0.5) {
      EXPECT_NEAR(prof.section_z_m[k] - kTopZ, kRms * waves.unit_height(15.0, 2.0, kTopZ, kLength),
                  1e-12);
      ++found;
    }
  }
  EXPECT_EQ(found, 1);
}

TEST(ObjectRoughness, BadValuesAreRejected) {
  EXPECT_THROW((Material{.name = "x", .roughness_rms_m = -0.1}.validate()), InputError);
  EXPECT_THROW(
      (Material{.name = "x", .roughness_rms_m = 0.1, .roughness_length_m = 0.0}.validate()),
      InputError);
}

}  // namespace
}  // namespace sonarsynth
