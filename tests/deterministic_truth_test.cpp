// SPDX-License-Identifier: MIT
// Runs of the same command give byte-identical files, the multi-band truth rasters included,
// while the lines' truth, waterfalls and the mosaics are written at the same time through GDAL's
// shared block cache (docs/labels.md).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "cli_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

// Two parallel 60 m lines over a rough seabed with a box and its shadow; truth and labels on.
constexpr const char* kScene = R"(
name: twice
seed: 21
bathymetry:
  generate:
    centre: {lat_deg: 43.0, lon_deg: 5.0}
    size_m: [140, 140]
    cell_m: 0.5
    depth_m: 15
    components:
      - {type: fbm, rms_m: 0.1, wavelength_m: 8}
objects:
  - {type: box, id: 3, position: {east_m: 0, north_m: 0}, size_m: [2, 1, 1], heading_deg: 30}
survey:
  speed_m_s: 2.0
  altitude_m: 5
  lines:
    - {name: A, waypoints: [{east_m: -30, north_m: 10}, {east_m: 30, north_m: 10}]}
    - {name: B, waypoints: [{east_m: 30, north_m: -10}, {east_m: -30, north_m: -10}]}
sonar: {frequency_khz: 600, range_m: 30, samples: 600}
output:
  labels: {coco: true}
)";

class DeterministicTruth : public test::ScratchDirTest {};

TEST_F(DeterministicTruth, RunsOfTheSameCommandGiveTheSameBytes) {
  // A block cache of 1 MB, far smaller than a line's truth raster (1200 x 750 x 3 x 4 bytes):
  // blocks are evicted all the time, by whichever thread needs room.
  ASSERT_EQ(::setenv("GDAL_CACHEMAX", "1", 1), 0);
  const fs::path scene = write("scene.yaml", kScene);
  for (const char* run : {"a", "b", "c"}) {
    const test::CliResult r = test::run_cli(
        "simulate " + scene.string() + " -o " + (dir_ / run).string() + " -q --threads 2", dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  ::unsetenv("GDAL_CACHEMAX");
  // Three runs: the block order of the old writing differed in about one pair of runs in three.
  const auto a = test::snapshot(dir_ / "a");
  EXPECT_EQ(a.count("A_truth.tif"), 1u);
  EXPECT_EQ(a.count("truth_mosaic.tif"), 1u);
  for (const char* other : {"b", "c"}) {
    const auto b = test::snapshot(dir_ / other);
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [name, bytes] : a) {
      ASSERT_EQ(b.count(name), 1u) << name;
      EXPECT_TRUE(bytes == b.at(name)) << name << " differs between runs a and " << other;
    }
  }
}

}  // namespace
}  // namespace sonarsynth
