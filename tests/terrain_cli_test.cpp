// SPDX-License-Identifier: MIT
// `sonarsynth simulate` on a file DEM made bicubic, resampled finer and roughened with generated
// components (docs/scene-format.md, `bathymetry`): the run succeeds and its effective.yaml
// reproduces it byte for byte; a resampled grid beyond limits.max_memory_gb is refused naming the
// keys, before anything is written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cli_test_util.hpp"
#include "dem_test_util.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

class TerrainCli : public test::ScratchDirTest {
 protected:
  // An 8 m DEM (160 m x 128 m) of a smooth surface in UTM 56S, and a scene on it.
  fs::path scene(const std::string& refine) {
    test::write_smooth_dem(dir_ / "dem.tif");
    // A name: the default (the file's stem) would differ for effective.yaml.
    return write("s.yaml",
                 "name: rough\nseed: 3\nbathymetry:\n  file: dem.tif\n  interpolation: bicubic\n" +
                     refine + R"(
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 2.0
  altitude_m: 8
  lines: [{name: a, waypoints: [{east_m: -20, north_m: 0}, {east_m: 20, north_m: 0}]}]
sonar: {frequency_khz: 400, range_m: 30, samples: 300, ping_period_s: 0.5}
noise: {model: speckle}
)");
  }
};

TEST_F(TerrainCli, RoughenedFileDemRunsAndReproducesFromEffectiveYaml) {
  const fs::path s = scene(
      "  resample_cell_m: 0.5\n  components:\n"
      "    - {type: fbm, rms_m: 0.1, wavelength_m: 8, octaves: 3}\n"
      "    - {type: ripples, wavelength_m: 2, amplitude_m: 0.05, crest_azimuth_deg: 10}\n");
  const std::string flags = " -q --no-mosaic --no-waterfall --no-truth";
  auto r = test::run_cli("simulate " + s.string() + " -o " + (dir_ / "a").string() + flags, dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("simulate " + (dir_ / "a" / "effective.yaml").string() + " -o " +
                        (dir_ / "b").string() + flags + " --threads 1",
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string a = test::read_text(dir_ / "a" / "a.xtf");
  EXPECT_GT(a.size(), 10000u);
  EXPECT_TRUE(a == test::read_text(dir_ / "b" / "a.xtf"));
  // Another component seed (--seed) gives another seabed, hence other samples.
  r = test::run_cli("simulate " + s.string() + " -o " + (dir_ / "c").string() + flags + " --seed 4",
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(a == test::read_text(dir_ / "c" / "a.xtf"));
}

TEST_F(TerrainCli, TooFineAResampledGridIsRefusedNamingTheKeys) {
  const fs::path s = scene("  resample_cell_m: 0.002\n");
  const auto r =
      test::run_cli("simulate " + s.string() + " -o " + (dir_ / "out").string() + " -q", dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bathymetry.resample_cell_m: resample_cell_m = 0.002"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("limits.max_memory_gb"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

}  // namespace
}  // namespace sonarsynth
