// SPDX-License-Identifier: MIT
// A file DEM in a scene: bicubic interpolation, resampling to a finer cell and generated
// components added on top (docs/scene-format.md, `bathymetry`). The result is checked against
// the same steps taken through the library's own functions (read, resample, generate), and the
// components against the generator's documented formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "cli_test_util.hpp"
#include "dem_test_util.hpp"
#include "error_test_util.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

class SceneBathymetry : public test::ScratchDirTest {
 protected:
  void SetUp() override {
    ScratchDirTest::SetUp();
    test::write_smooth_dem(dir_ / "dem.tif");
  }

  Scene load(const std::string& yaml, const SceneLoadOptions& o = {}) {
    const fs::path p = dir_ / "s.yaml";
    std::ofstream(p) << yaml;
    return load_scene(p.string(), o);
  }
  void expect_error(const std::string& yaml, std::initializer_list<std::string_view> fragments) {
    test::expect_error([&] { load(yaml); }, fragments, yaml);
  }
  // The DEM as read, with the given interpolation.
  HeightGrid dem(Interpolation i) const {
    HeightGrid g = read_height_grid((dir_ / "dem.tif").string()).grid;
    g.set_interpolation(i);
    return g;
  }
};

bool same_bytes(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

const char* kRefined = R"(
seed: 5
bathymetry:
  file: dem.tif
  interpolation: bicubic
  resample_cell_m: 0.5
  components:
    - {type: ripples, wavelength_m: 2.5, amplitude_m: 0.1, crest_azimuth_deg: 30}
    - {type: fbm, rms_m: 0.05, wavelength_m: 10, octaves: 3}
)";

TEST_F(SceneBathymetry, InterpolationIsSelectable) {
  // A file's grid is bicubic unless the file says bilinear.
  const Scene bilinear = load("bathymetry: {file: dem.tif, interpolation: bilinear}\n");
  EXPECT_EQ(bilinear.bathymetry.interpolation(), Interpolation::kBilinear);
  const Scene bicubic = load("bathymetry: {file: dem.tif}\n");
  EXPECT_EQ(bicubic.bathymetry.interpolation(), Interpolation::kBicubic);
  EXPECT_TRUE(same_bytes(bicubic.bathymetry.heights(), bilinear.bathymetry.heights()));
  const Scene generated_default = load(R"(
bathymetry:
  generate: {centre: {lat_deg: -33.9, lon_deg: 151.3}, size_m: [40, 40], cell_m: 1, depth_m: 20}
)");
  EXPECT_EQ(generated_default.bathymetry.interpolation(), Interpolation::kBilinear);
  const Scene generated = load(R"(
bathymetry:
  interpolation: bicubic
  generate: {centre: {lat_deg: -33.9, lon_deg: 151.3}, size_m: [40, 40], cell_m: 1, depth_m: 20}
)");
  EXPECT_EQ(generated.bathymetry.interpolation(), Interpolation::kBicubic);
}

TEST_F(SceneBathymetry, ComponentsAddOntoTheResampledFileBitForBit) {
  const Scene s = load(kRefined);
  // The same steps through the library: the file resampled bicubically onto 0.5 m nodes...
  const HeightGrid file = dem(Interpolation::kBicubic);
  const HeightGrid base = resample(file, refined_geometry(file.geometry(), 0.5));
  const GridGeometry& g = base.geometry();
  EXPECT_EQ(g.cols, 321u);
  EXPECT_EQ(g.rows, 257u);
  ASSERT_EQ(s.bathymetry.geometry().cols, g.cols);
  ASSERT_EQ(s.bathymetry.geometry().rows, g.rows);
  EXPECT_EQ(s.bathymetry.geometry().x0_m, g.x0_m);
  EXPECT_EQ(s.bathymetry.geometry().y0_m, g.y0_m);
  EXPECT_EQ(s.bathymetry.geometry().dy_m, -0.5);
  EXPECT_EQ(s.bathymetry.interpolation(), Interpolation::kBilinear);
  // ... and the components alone, built from what the file says (positions about the grid
  // centre, azimuths clockwise from grid north, the first fbm layer's seed offset 0).
  const Eigen::Vector4d bb = base.bounds();
  const Eigen::Vector2d centre(0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3]));
  BathyGenSpec spec;
  spec.geometry = g;
  spec.seed = 5;
  bathy::Ripples rip;
  rip.wavelength_m = 2.5;
  rip.amplitude_m = 0.1;
  rip.crest_azimuth_rad = rad_from_deg(30.0);
  rip.ref_x_m = centre.x();
  rip.ref_y_m = centre.y();
  bathy::Fbm fbm;
  fbm.rms_m = 0.05;
  fbm.base_wavelength_m = 10.0;
  fbm.octaves = 3;
  spec.components = {rip, fbm};
  HeightGrid comp(g, std::vector<float>(g.size(), 0.0f));
  add_bathymetry_components(spec, comp);
  // The components are the generator's: the same spec generated at a depth, minus the depth.
  spec.depth_m = 20.0;
  const HeightGrid generated = generate_bathymetry(spec);
  double sum2 = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    ASSERT_NEAR(comp.heights()[i], generated.heights()[i] + 20.0, 1e-5);
    sum2 += double(comp.heights()[i]) * comp.heights()[i];
  }
  const double rms = std::sqrt(sum2 / static_cast<double>(g.size()));
  EXPECT_GT(rms, 0.06);  // ripples (0.1 / sqrt 2) with fbm on top
  EXPECT_LT(rms, 0.12);
  // The scene's heights are the resampled file plus the components: float32 additions, bit for
  // bit; the difference is the components to float32 rounding of the sum.
  std::vector<float> expected(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) expected[i] = base.heights()[i] + comp.heights()[i];
  EXPECT_TRUE(same_bytes(s.bathymetry.heights(), expected));
  for (std::size_t i = 0; i < g.size(); i += 97) {
    EXPECT_NEAR(s.bathymetry.heights()[i] - base.heights()[i], comp.heights()[i], 4e-6);
  }
}

TEST_F(SceneBathymetry, SameSeedSameBytesOtherSeedOtherBytes) {
  const Scene a = load(kRefined);
  const Scene b = load(kRefined);
  EXPECT_TRUE(same_bytes(a.bathymetry.heights(), b.bathymetry.heights()));
  std::string other = kRefined;
  other.replace(other.find("seed: 5"), 7, "seed: 6");
  const Scene c = load(other);
  EXPECT_FALSE(same_bytes(a.bathymetry.heights(), c.bathymetry.heights()));
  // --seed replaces the file's seed; bathymetry.seed replaces both.
  SceneLoadOptions o;
  o.seed = 6;
  EXPECT_TRUE(same_bytes(load(kRefined, o).bathymetry.heights(), c.bathymetry.heights()));
  std::string own = kRefined;
  own.replace(own.find("  file: dem.tif\n"), 16, "  file: dem.tif\n  seed: 5\n");
  EXPECT_TRUE(same_bytes(load(own, o).bathymetry.heights(), a.bathymetry.heights()));
}

TEST_F(SceneBathymetry, ComponentsOnTheFileGridWithoutResampling) {
  const Scene s = load(R"(
seed: 1
bathymetry:
  file: dem.tif
  interpolation: bicubic
  components: [{type: seamount, east_m: 8, north_m: -16, height_m: 2, radius_m: 20}]
)");
  const HeightGrid file = dem(Interpolation::kBicubic);
  const GridGeometry& g = file.geometry();
  ASSERT_EQ(s.bathymetry.geometry().cols, g.cols);
  EXPECT_EQ(s.bathymetry.interpolation(), Interpolation::kBicubic);
  // The seamount's formula: height exp(-r^2 / (2 radius^2)) about the grid centre + (8, -16).
  const Eigen::Vector4d bb = file.bounds();
  const Eigen::Vector2d top(0.5 * (bb[0] + bb[2]) + 8.0, 0.5 * (bb[1] + bb[3]) - 16.0);
  for (std::size_t r = 0; r < g.rows; ++r) {
    for (std::size_t c = 0; c < g.cols; ++c) {
      const Eigen::Vector2d p(g.x_of_col(static_cast<double>(c)),
                              g.y_of_row(static_cast<double>(r)));
      const double add = 2.0 * std::exp(-(p - top).squaredNorm() / (2.0 * 20.0 * 20.0));
      EXPECT_NEAR(s.bathymetry.node(c, r) - file.node(c, r), add, 1e-5);
    }
  }
}

TEST_F(SceneBathymetry, BadInputNamesTheKeys) {
  expect_error("bathymetry: {file: dem.tif, interpolation: cubic}\n",
               {"s.yaml", "bathymetry.interpolation = 'cubic'", "bilinear, bicubic"});
  expect_error("bathymetry: {file: dem.tif, resample_cell_m: 16}\n",
               {"bathymetry.resample_cell_m = '16'", "the file's cell (8 m)"});
  expect_error("bathymetry: {file: dem.tif, resample_cell_m: 0}\n",
               {"bathymetry.resample_cell_m = '0'"});
  // 160 m x 128 m at 1 mm: 2e10 nodes, far above 8 GB.
  expect_error("bathymetry: {file: dem.tif, resample_cell_m: 0.001}\n",
               {"bathymetry.resample_cell_m", "limits.max_memory_gb = 8", "160001 x 128001"});
  // The limit is the file's own limits.max_memory_gb: 0.25 m needs 1.3 MB.
  expect_error(
      "bathymetry: {file: dem.tif, resample_cell_m: 0.25}\nlimits: {max_memory_gb: 1e-3}\n",
      {"bathymetry.resample_cell_m", "limits.max_memory_gb = 0.001"});
  EXPECT_NO_THROW(
      load("bathymetry: {file: dem.tif, resample_cell_m: 0.25}\n"
           "limits: {max_memory_gb: 2e-3}\n"));
  expect_error("bathymetry: {file: dem.tif, components: [{type: ripples, amplitude_m: -1}]}\n",
               {"bathymetry.components[0].amplitude_m = '-1'"});
  expect_error("bathymetry: {file: dem.tif, components: [{type: dunes}]}\n",
               {"bathymetry.components[0].type = 'dunes'"});
  // Ripples need two cells of the grid they are added to (the file's 8 m here).
  expect_error("bathymetry: {file: dem.tif, components: [{type: ripples, wavelength_m: 2}]}\n",
               {"bathymetry.components", "wavelength_m >= 2 cells (16 m)"});
  expect_error(R"(
bathymetry:
  components: [{type: ripples}]
  generate: {centre: {lat_deg: -33.9, lon_deg: 151.3}, size_m: [40, 40], cell_m: 1, depth_m: 20}
)",
               {"bathymetry.components", "generate.components"});
}

}  // namespace
}  // namespace sonarsynth
