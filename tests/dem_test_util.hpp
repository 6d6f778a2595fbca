// SPDX-License-Identifier: MIT
// A small DEM file the terrain tests read.
#pragma once

#include <cmath>
#include <filesystem>
#include <vector>

#include "height_grid_test_util.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::test {

/// Writes to `path` a coarse 8 m GeoTIFF DEM (21 x 17 nodes, 160 m x 128 m) in UTM 56S of the
/// smooth surface z = -25 + 3 sin(x / 20) cos(y / 25) metres.
inline void write_smooth_dem(const std::filesystem::path& path) {
  const HeightGrid grid = sampled_grid({0.0, 128.0, 8.0, -8.0, 21, 17}, [](double x, double y) {
    return -25.0 + 3.0 * std::sin(x / 20.0) * std::cos(y / 25.0);
  });
  write_height_grid_geotiff(path.string(), GeoFrame(56, false, 334000.0, 6252000.0), grid);
}

}  // namespace sonarsynth::test
