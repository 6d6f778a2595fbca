// SPDX-License-Identifier: MIT
// MosaicGrid by runs of samples against the point-by-point gridding (set_sample_runs(false)):
// the same image bit for bit and the same statistics, over varied geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "height_grid_test_util.hpp"
#include "mosaic_test_util.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth {
namespace {

/// A seabed with a slope, ripples and a hole (NaN) in it.
HeightGrid rough_seabed() {
  GridGeometry g;
  g.dx_m = 0.3;
  g.dy_m = -0.3;
  g.cols = 400;
  g.rows = 400;
  g.x0_m = -60.0;
  g.y0_m = 60.0;
  return test::sampled_grid(g, [](double x, double y) {
    const bool hole = std::hypot(x - 20.0, y + 15.0) < 4.0;
    return hole ? NAN : -15.0 + 0.1 * x + 1.5 * std::sin(0.4 * y + 0.1 * x);
  });
}

struct Case {
  MosaicRule rule;
  double pixel_m;
  std::size_t tile_px;
  bool bathymetry;
  double nadir_blank_m;
  bool along_track_fill;
};

void expect_same(const MosaicImage& a, const MosaicImage& b, const std::string& what) {
  test::expect_same_bits(a, b, what);
  EXPECT_GT(test::gridded_pixels(a), 1000u) << what;  // the case grids something
}

TEST(MosaicRuns, RunsOfSamplesGiveThePointByPointImageBitForBit) {
  const HeightGrid seabed = rough_seabed();
  const std::vector<Case> cases = {
      {MosaicRule::weighted_mean, 0.25, 256, true, 0.0, true},
      {MosaicRule::weighted_mean, 0.05, 256, true, 1.0, true},  // cells finer than samples
      {MosaicRule::weighted_mean, 1.0, 7, false, 0.0, true},    // tiles not a power of two
      {MosaicRule::max, 0.25, 64, true, 0.0, false},
      {MosaicRule::nearest, 0.4, 256, false, 0.5, true},
  };
  for (const Case& c : cases) {
    MosaicOptions o;
    o.rule = c.rule;
    o.nadir_blank_m = c.nadir_blank_m;
    o.along_track_fill = c.along_track_fill;
    const GridGeometry g = MosaicGrid::geometry_covering({-50, -50}, {50, 50}, c.pixel_m);
    const HeightGrid* bathy = c.bathymetry ? &seabed : nullptr;
    MosaicGrid by_runs(g, o, bathy, c.tile_px);
    MosaicGrid by_point(g, o, bathy, c.tile_px);
    by_point.set_sample_runs(false);
    std::mt19937_64 rng(5);
    std::exponential_distribution<float> speckle(1.0f);
    std::vector<float> port(1500), stbd(1500);
    std::vector<std::int32_t> port_labels(1500), stbd_labels(1500);
    // Headings along the grid axes (the position moves along one axis only), oblique ones and
    // a turn; the track leaves the grid at the end.
    const double headings[] = {0.0, 0.5 * std::numbers::pi, std::numbers::pi, 0.7, -2.3};
    int k = 0;
    for (double heading : headings) {
      by_runs.break_line();
      by_point.break_line();
      for (int i = 0; i < 40; ++i, ++k) {
        for (std::size_t s = 0; s < port.size(); ++s) {
          port[s] = speckle(rng);
          stbd[s] = s % 97 == 0 ? NAN : speckle(rng);  // some samples not finite
          port_labels[s] = static_cast<std::int32_t>(s / 200);
          stbd_labels[s] = s % 3 == 0 ? MosaicImage::kNoLabel : static_cast<std::int32_t>(s / 90);
        }
        MosaicPing p;
        const double h = heading + 0.01 * i;
        p.sensor_xy_m = {-20.0 + 0.15 * i * std::sin(h) + 3.0 * (k % 5),
                         -10.0 + 0.15 * i * std::cos(h) + 0.37 * k};
        p.heading_grid_rad = h;
        p.pitch_rad = 0.02 * std::sin(0.3 * k);
        p.altitude_m = 6.0 + 0.05 * (k % 9);
        p.slant_range_m = 40.0;
        p.port = port;
        p.starboard = stbd;
        p.port_labels = port_labels;
        p.starboard_labels = stbd_labels;
        const MosaicAddStats a = by_runs.add(p);
        const MosaicAddStats b = by_point.add(p);
        ASSERT_EQ(a.samples_placed, b.samples_placed);
        ASSERT_EQ(a.samples_water, b.samples_water);
        ASSERT_EQ(a.samples_outside, b.samples_outside);
        ASSERT_EQ(a.fill_points, b.fill_points);
        ASSERT_EQ(a.along_fill_points, b.along_fill_points);
      }
    }
    const std::string what = "rule " + std::to_string(static_cast<int>(c.rule)) + ", pixel " +
                             std::to_string(c.pixel_m) + " m";
    expect_same(std::move(by_runs).finish(), std::move(by_point).finish(), what);
  }
}

}  // namespace
}  // namespace sonarsynth
