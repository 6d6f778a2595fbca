// SPDX-License-Identifier: MIT
// Component products: a mosaic of one ping written as a Cloud-Optimized GeoTIFF.
#include <filesystem>
#include <iostream>
#include <vector>

#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/mosaic.hpp"

int main() {
  const auto geometry =
      sonarsynth::MosaicGrid::geometry_covering({-30.0, -10.0}, {30.0, 10.0}, 0.5);
  sonarsynth::MosaicGrid grid(geometry, sonarsynth::MosaicOptions{});
  const std::vector<float> port(200, 1.0f), starboard(200, 2.0f);
  sonarsynth::MosaicPing ping;
  ping.sensor_z_m = 10.0;
  ping.altitude_m = 10.0;
  ping.slant_range_m = 25.0;
  ping.port = port;
  ping.starboard = starboard;
  grid.add(ping);
  const auto dir = std::filesystem::temp_directory_path() / "sonarsynth_consumer_products";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  sonarsynth::MosaicWriteOptions options;
  options.rgb_path = (dir / "mosaic_rgb.tif").string();
  sonarsynth::write_mosaic((dir / "mosaic.tif").string(),
                           sonarsynth::GeoFrame(19, true, 500000.0, 5000000.0), grid.finish(),
                           options);
  const bool ok = std::filesystem::exists(dir / "mosaic.tif");
  std::filesystem::remove_all(dir);
  std::cout << "products: mosaic written\n";
  return ok ? 0 : 1;
}
