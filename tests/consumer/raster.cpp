// SPDX-License-Identifier: MIT
// Component raster: a generated seabed written as GeoTIFF and read back through GDAL.
#include <filesystem>
#include <iostream>

#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"

int main() {
  sonarsynth::BathyGenSpec spec;
  spec.depth_m = 20.0;
  spec.geometry = sonarsynth::BathyGenSpec::centred_geometry(0.0, 0.0, 20.0, 10.0, 1.0);
  const sonarsynth::HeightGrid grid = sonarsynth::generate_bathymetry(spec);
  const sonarsynth::GeoFrame frame(19, true, 500000.0, 5000000.0);
  const auto path = std::filesystem::temp_directory_path() / "sonarsynth_consumer_raster.tif";
  sonarsynth::GridWriteOptions options;
  options.overwrite = true;
  sonarsynth::write_height_grid_geotiff(path.string(), frame, grid, options);
  const sonarsynth::LoadedGrid back = sonarsynth::read_height_grid(path.string());
  std::filesystem::remove(path);
  std::cout << "raster: " << back.driver << " " << back.grid.geometry().cols << " x "
            << back.grid.geometry().rows << "\n";
  return back.grid.geometry().size() == grid.geometry().size() ? 0 : 1;
}
