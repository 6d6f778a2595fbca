// SPDX-License-Identifier: MIT
// `sonarsynth bathy` end to end: the CLI's file read back through read_height_grid.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_util.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

class BathyCliTest : public test::ScratchDirTest {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs `sonarsynth bathy <args>`; returns the exit status.
  int run(const std::string& args) const { return test::run_cli("bathy " + args, dir_).exit_code; }
  std::size_t file_count() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
    return n;
  }
};

TEST_F(BathyCliTest, WritesGridCentredOnLatLon) {
  const std::string out = path("b.tif");
  ASSERT_EQ(run("-o " + out +
                " --lat -41.29 --lon 174.78 --size 200x100 --cell 0.5 --depth 25"
                " --slope 1,90 --ripples 2,0.1 --fbm 0.2,16,4 --seamount 10,5,3,12"
                " --scarp 0,0,0,1 --seed 5 -q"),
            0);
  const LoadedGrid g = read_height_grid(out);
  EXPECT_EQ(g.frame.epsg(), 32760);  // 174.78 E is in UTM zone 60, southern hemisphere
  const GridGeometry& geo = g.grid.geometry();
  EXPECT_EQ(geo.cols, 400u);
  EXPECT_EQ(geo.rows, 200u);
  EXPECT_DOUBLE_EQ(geo.dx_m, 0.5);
  EXPECT_DOUBLE_EQ(geo.dy_m, -0.5);
  EXPECT_EQ(g.valid_count, 400u * 200u);
  // The centre of the node area is the requested point.
  const Eigen::Vector4d b = g.grid.bounds();
  EXPECT_NEAR(b[2] - b[0], 199.5, 1e-9);
  EXPECT_NEAR(b[3] - b[1], 99.5, 1e-9);
  const Geodetic c = g.frame.geodetic_from_local({0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])});
  EXPECT_NEAR(deg_from_rad(c.lat_rad), -41.29, 1e-8);
  EXPECT_NEAR(deg_from_rad(c.lon_rad), 174.78, 1e-8);
  // Heights around -25 m: slope +-1.7 m over 200 m, the rest a few metres at most.
  const auto [lo, hi] = g.grid.height_range();
  EXPECT_GT(lo, -30.0);
  EXPECT_LT(hi, -19.0);

  // Same options and seed: the same heights; another seed: different heights.
  ASSERT_EQ(run("-o " + path("same.tif") +
                " --lat -41.29 --lon 174.78 --size 200x100 --cell 0.5 --depth 25"
                " --slope 1,90 --ripples 2,0.1 --fbm 0.2,16,4 --seamount 10,5,3,12"
                " --scarp 0,0,0,1 --seed 5 --threads 3 -q"),
            0);
  const LoadedGrid same = read_height_grid(path("same.tif"));
  EXPECT_EQ(std::memcmp(same.grid.heights().data(), g.grid.heights().data(),
                        g.grid.heights().size() * sizeof(float)),
            0);
  ASSERT_EQ(run("-o " + path("other.tif") +
                " --lat -41.29 --lon 174.78 --size 200x100 --cell 0.5 --depth 25 --fbm 0.2,16,4"
                " --seed 6 -q"),
            0);
  EXPECT_NE(read_height_grid(path("other.tif")).grid.heights(), g.grid.heights());
}

TEST_F(BathyCliTest, FlatGridIsMinusDepth) {
  ASSERT_EQ(run("-o " + path("flat.tif") + " --lat 10 --lon 20 --size 10x8 --cell 1 --depth 7 -q"),
            0);
  const LoadedGrid g = read_height_grid(path("flat.tif"));
  for (float h : g.grid.heights()) ASSERT_EQ(h, -7.0f);
}

TEST_F(BathyCliTest, BadValuesFailAndWriteNothing) {
  const std::string base = "-o " + path("bad.tif") + " --lat 43 --lon -70 ";
  EXPECT_EQ(run(base + "--size 100x100 --cell 0"), 1);
  EXPECT_EQ(run(base + "--size 100x100 --cell -1"), 1);
  EXPECT_EQ(run(base + "--size 100x0 --cell 1"), 1);
  EXPECT_EQ(run(base + "--size 100 --cell 1"), 1);
  EXPECT_EQ(run(base + "--size 100x100 --cell 1 --depth -5"), 1);
  EXPECT_EQ(run(base + "--size 100x100 --cell 1 --ripples 0,0.1"), 1);
  EXPECT_EQ(run(base + "--size 100x100 --cell 1 --fbm 0.1,10,0"), 1);
  EXPECT_EQ(run(base + "--size 100x100 --cell 1 --seamount 1,2,3"), 1);
  EXPECT_EQ(run(base + "--size 100x100 --cell 1 --co PREDICTOR=7"), 1);  // fails while writing
  EXPECT_EQ(run("-o " + path("bad.tif") + " --lat 91 --lon 0 --size 100x100 --cell 1"), 1);
  EXPECT_EQ(run(base + "--size 100x100"), 2);  // missing --cell: a usage error
  EXPECT_EQ(file_count(), 0u);                 // no output, no temporary left behind
}

TEST_F(BathyCliTest, RefusesToOverwriteWithoutFlag) {
  const std::string args = "-o " + path("x.tif") + " --lat 43 --lon -70 --size 10x10 --cell 1 -q";
  ASSERT_EQ(run(args + " --depth 5"), 0);
  EXPECT_EQ(run(args + " --depth 9"), 1);
  EXPECT_EQ(read_height_grid(path("x.tif")).grid.heights().front(), -5.0f);
  ASSERT_EQ(run(args + " --depth 9 --overwrite"), 0);
  EXPECT_EQ(read_height_grid(path("x.tif")).grid.heights().front(), -9.0f);
}

// `sonarsynth bathy` and a scene file's bathymetry.generate read the generators through one
// parser: the same components give the same float32 heights, bit for bit. The plane relies on
// the default azimuth, the second fbm layer on the default seed offset (its index), and the
// azimuths are away from 0 so that a true/grid mix-up would show (the meridian convergence at
// 174.78 E, -41.29 is about 2 deg).
TEST_F(BathyCliTest, CliAndSceneFileGiveByteIdenticalGrids) {
  ASSERT_EQ(run("-o " + path("cli.tif") +
                " --lat -41.29 --lon 174.78 --size 120x80 --cell 0.5 --depth 25"
                " --slope 2 --ripples 2.5,0.1,35,0.97 --fbm 0.2,16,4 --fbm 0.05,3"
                " --seamount 10,5,3,12 --scarp 4,-6,60,1.5,3 --seed 5 -q"),
            0);
  {
    std::ofstream os(path("scene.yaml"));
    os << R"(bathymetry:
  generate:
    centre: {lat_deg: -41.29, lon_deg: 174.78}
    size_m: [120, 80]
    cell_m: 0.5
    depth_m: 25
    seed: 5
    components:
      - {type: plane, slope_deg: 2}
      - {type: ripples, wavelength_m: 2.5, amplitude_m: 0.1, crest_azimuth_deg: 35, asymmetry: 0.97}
      - {type: fbm, rms_m: 0.2, wavelength_m: 16, octaves: 4}
      - {type: fbm, rms_m: 0.05, wavelength_m: 3}
      - {type: seamount, east_m: 10, north_m: 5, height_m: 3, radius_m: 12}
      - {type: scarp, east_m: 4, north_m: -6, azimuth_deg: 60, height_m: 1.5, width_m: 3}
)";
  }
  const LoadedGrid cli = read_height_grid(path("cli.tif"));
  const Scene scene = load_scene(path("scene.yaml"));
  EXPECT_EQ(scene.frame.epsg(), cli.frame.epsg());
  const GridGeometry& a = cli.grid.geometry();
  const GridGeometry& b = scene.bathymetry.geometry();
  ASSERT_EQ(a.cols, b.cols);
  ASSERT_EQ(a.rows, b.rows);
  // The same nodes in projected coordinates (each frame has its own local origin).
  const Eigen::Vector4d ba = cli.grid.bounds(), bb = scene.bathymetry.bounds();
  EXPECT_NEAR(cli.frame.projected_from_local({ba[0], ba[1]}).x(),
              scene.frame.projected_from_local({bb[0], bb[1]}).x(), 1e-6);
  EXPECT_NEAR(cli.frame.projected_from_local({ba[0], ba[1]}).y(),
              scene.frame.projected_from_local({bb[0], bb[1]}).y(), 1e-6);
  const auto& ha = cli.grid.heights();
  const auto& hb = scene.bathymetry.heights();
  ASSERT_EQ(ha.size(), hb.size());
  if (a.dy_m == b.dy_m) {
    EXPECT_EQ(std::memcmp(ha.data(), hb.data(), ha.size() * sizeof(float)), 0);
  } else {  // one of them south-up: compare row r with row rows-1-r
    for (std::size_t r = 0; r < a.rows; ++r) {
      ASSERT_EQ(std::memcmp(ha.data() + r * a.cols, hb.data() + (a.rows - 1 - r) * a.cols,
                            a.cols * sizeof(float)),
                0);
    }
  }
}

// The bounds are those of the scene file: a slope above 89 deg is refused, an asymmetry up to
// (not including) 1 accepted.
TEST_F(BathyCliTest, GeneratorBoundsAreTheSceneFiles) {
  const std::string base = "-o " + path("b.tif") + " --lat 43 --lon -70 --size 20x20 --cell 1 -q ";
  EXPECT_EQ(run(base + "--slope 89.5"), 1);
  EXPECT_EQ(run(base + "--ripples 2,0.1,0,1"), 1);
  EXPECT_EQ(run(base + "--fbm 0.1,10,2.5"), 1);  // octaves are an integer
  EXPECT_EQ(file_count(), 0u);
  EXPECT_EQ(run(base + "--slope 89 --ripples 2,0.1,0,0.99"), 0);
}

}  // namespace
}  // namespace sonarsynth
