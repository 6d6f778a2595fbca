// SPDX-License-Identifier: MIT
#include "sonarsynth/scene_object.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/material.hpp"

namespace sonarsynth {
namespace {

// Deterministic test randomness (splitmix64), independent of the standard library.
struct Rng {
  std::uint64_t s;
  double uniform(double a, double b) {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return a + (b - a) * static_cast<double>(z >> 11) * 0x1.0p-53;
  }
};

HeightGrid plane_grid(double cell, double slope_x, double z0) {
  const std::size_t n = static_cast<std::size_t>(200.0 / cell) + 1;
  GridGeometry g{-100.0, 100.0, cell, -cell, n, n};
  std::vector<float> z(g.size());
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < n; ++c) {
      z[r * n + c] = static_cast<float>(z0 + slope_x * g.x_of_col(static_cast<double>(c)));
    }
  }
  return HeightGrid(g, std::move(z));
}

ObjectPrimitive pipe(double x, double y, double heading_deg, double radius, double length) {
  ObjectPrimitive p;
  p.shape = ObjectShape::kCylinder;
  p.centre_xy_m = {x, y};
  p.heading_rad = rad_from_deg(heading_deg);
  p.half_extent_m = {length / 2, radius, radius};
  return p;
}

TEST(SceneObject, PipeDrapesOnSlopedSeabedAtFullResolution) {
  // A 0.25 m radius pipe (0.5 m across) on a 1 m grid sloping 5 % along x, heading east.
  const HeightGrid seabed = plane_grid(1.0, 0.05, -20.0);
  ObjectPrimitive p = pipe(3.3, -7.6, 90.0, 0.25, 40.0);
  p.place_on_seabed(seabed, 0.0, 0.0, "objects[0]");
  for (double x = -16.0; x <= 23.0; x += 0.37) {
    double zb = 0, zt = 0;
    ASSERT_TRUE(p.vertical_extent(x, -7.6, zb, zt)) << x;
    EXPECT_NEAR(zb, -20.0 + 0.05 * x, 1e-4);  // resting on the seabed under its axis
    EXPECT_NEAR(zt, zb + 0.5, 1e-4);
    // 0.2 m off the axis the top follows the circle: sqrt(r^2 - v^2) above the axis.
    ASSERT_TRUE(p.vertical_extent(x, -7.6 - 0.2, zb, zt));
    EXPECT_NEAR(zt, -20.0 + 0.05 * x + 0.25 + std::sqrt(0.25 * 0.25 - 0.04), 1e-4);
  }
  double zb = 0, zt = 0;
  EXPECT_FALSE(p.vertical_extent(3.3, -7.6 + 0.26, zb, zt));  // just beside it
  EXPECT_FALSE(p.vertical_extent(23.4, -7.6, zb, zt));        // beyond its end
}

TEST(SceneObject, ClearanceLiftsAndEmbedSinks) {
  const HeightGrid seabed = plane_grid(1.0, 0.0, -10.0);
  ObjectPrimitive rock;
  rock.shape = ObjectShape::kEllipsoid;
  rock.half_extent_m = {1.0, 0.8, 0.85};  // a 1.7 m high rock
  rock.place_on_seabed(seabed, 0.0, 0.25, "rock");
  EXPECT_NEAR(rock.base_at(0.0), -10.0 - 0.25 * 1.7, 1e-5);
  ObjectPrimitive span = pipe(0, 0, 0, 0.5, 10);
  span.place_on_seabed(seabed, 1.5, 0.0, "span");
  double zb = 0, zt = 0;
  ASSERT_TRUE(span.vertical_extent(0.0, 0.0, zb, zt));
  EXPECT_NEAR(zb, -8.5, 1e-5);
  EXPECT_NEAR(zt, -7.5, 1e-5);
}

TEST(SceneObject, FootprintIntervalMatchesPointTests) {
  Rng rng{42};
  for (ObjectShape shape : {ObjectShape::kBox, ObjectShape::kCylinder, ObjectShape::kEllipsoid}) {
    for (int trial = 0; trial < 200; ++trial) {
      ObjectPrimitive p;
      p.shape = shape;
      p.centre_xy_m = {rng.uniform(-5, 5), rng.uniform(-5, 5)};
      p.heading_rad = rng.uniform(-kPi, kPi);
      p.half_extent_m = {rng.uniform(0.1, 4), rng.uniform(0.1, 2), 1.0};
      p.base_z_m = {0.0f};
      const double ang = rng.uniform(-kPi, kPi);
      const Eigen::Vector2d dir(std::cos(ang), std::sin(ang));
      const Eigen::Vector2d start(rng.uniform(-10, 10), rng.uniform(-10, 10));
      double s0 = 0, s1 = 0;
      const bool hit = p.footprint_interval(start, dir, s0, s1);
      // Brute force along the line with a fine step, classifying by vertical_extent().
      for (double s = -40.0; s <= 40.0; s += 0.01) {
        const Eigen::Vector2d q = start + s * dir;
        double zb = 0, zt = 0;
        const bool inside = p.vertical_extent(q.x(), q.y(), zb, zt);
        const bool in_interval = hit && s >= s0 - 1e-9 && s <= s1 + 1e-9;
        if (inside != in_interval) {
          // Only allowed within rounding of the boundary.
          EXPECT_TRUE(hit && (std::abs(s - s0) < 1e-6 || std::abs(s - s1) < 1e-6))
              << to_string(shape) << " trial " << trial << " s " << s;
        }
      }
    }
  }
}

TEST(ObjectSet, CandidatesAlongContainEveryObjectTheSegmentCrosses) {
  Rng rng{7};
  ObjectSet set;
  for (int i = 0; i < 500; ++i) {
    ObjectPrimitive p;
    p.shape = i % 3 == 0 ? ObjectShape::kCylinder
                         : (i % 3 == 1 ? ObjectShape::kBox : ObjectShape::kEllipsoid);
    p.id = i + 1;
    p.centre_xy_m = {rng.uniform(-500, 500), rng.uniform(-500, 500)};
    p.heading_rad = rng.uniform(0, 2 * kPi);
    p.half_extent_m = {rng.uniform(0.5, 30), rng.uniform(0.2, 3), 1.0};
    p.base_z_m = {0.0f};
    set.add(p);
  }
  set.build_index(16.0);
  std::vector<std::uint32_t> cand;
  std::size_t total_candidates = 0, total_hits = 0;
  for (int q = 0; q < 300; ++q) {
    const double ang = rng.uniform(-kPi, kPi);
    const Eigen::Vector2d dir(std::cos(ang), std::sin(ang));
    const Eigen::Vector2d start(rng.uniform(-600, 600), rng.uniform(-600, 600));
    const double len = rng.uniform(1, 150);
    set.candidates_along(start, dir, len, cand);
    total_candidates += cand.size();
    for (std::uint32_t i = 0; i < set.primitives().size(); ++i) {
      double s0 = 0, s1 = 0;
      if (set.primitives()[i].footprint_interval(start, dir, s0, s1) && s1 >= 0 && s0 <= len) {
        ++total_hits;
        EXPECT_TRUE(std::binary_search(cand.begin(), cand.end(), i))
            << "query " << q << " obj " << i;
      }
    }
  }
  EXPECT_GT(total_hits, 20u);  // the queries do cross objects
  // The index prunes: far fewer candidates than objects x queries.
  EXPECT_LT(total_candidates, 300u * 500u / 10u);
}

TEST(SceneObject, RejectsBadInputWithNames) {
  const HeightGrid seabed = plane_grid(1.0, 0.0, -10.0);
  ObjectPrimitive p = pipe(0, 0, 0, -0.5, 10);
  try {
    p.place_on_seabed(seabed, 0.0, 0.0, "scene.yaml: objects[3]");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("objects[3]: radius_m = -0.5"), std::string::npos)
        << e.what();
  }
  ObjectPrimitive outside = pipe(95.0, 0, 90, 0.5, 20);  // reaches x = 105, grid ends at 100
  EXPECT_THROW(outside.place_on_seabed(seabed, 0, 0, "objects[0]"), InputError);
  ObjectPrimitive box;
  box.centre_xy_m = {99.8, 0.0};
  EXPECT_THROW(box.place_on_seabed(seabed, 0, 0, "objects[1]"), InputError);
}

TEST(MaterialMap, PolygonsOverRasterOverDefault) {
  MaterialTable t = MaterialTable::defaults();
  MaterialMap map(t.index_of("sand"));
  ClassRaster r;
  r.geometry = {0.0, 0.0, 1.0, 1.0, 10, 10};
  r.classes.assign(100, ClassRaster::kNoClass);
  r.classes[5 * 10 + 5] = t.index_of("gravel");
  map.set_raster(r);
  MaterialPolygon poly;
  poly.rings = {{{4, 4}, {8, 4}, {8, 8}, {4, 8}}, {{5.5, 5.5}, {6.5, 5.5}, {6.5, 6.5}, {5.5, 6.5}}};
  poly.material = t.index_of("rock");
  map.add_polygon(poly);
  EXPECT_EQ(map.material_at(5.2, 4.9), t.index_of("rock"));    // polygon over raster cell
  EXPECT_EQ(map.material_at(6.0, 6.0), t.index_of("sand"));    // in the hole: default
  EXPECT_EQ(map.material_at(20.0, 20.0), t.index_of("sand"));  // outside everything
  EXPECT_FALSE(map.uniform());
  EXPECT_THROW(t.index_of("granite"), InputError);
  EXPECT_THROW(t.set({"bad", 2.0, 0.5, 0.0}), InputError);
}

}  // namespace
}  // namespace sonarsynth
