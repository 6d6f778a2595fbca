// SPDX-License-Identifier: MIT
// Component config: a YAML scene file with generated bathymetry.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "sonarsynth/formats/config/scene_file.hpp"

int main() {
  const auto path = std::filesystem::temp_directory_path() / "sonarsynth_consumer_scene.yaml";
  std::ofstream(path) << "name: consumer\n"
                         "bathymetry:\n"
                         "  generate:\n"
                         "    centre: {lat_deg: 57.05, lon_deg: 11.20}\n"
                         "    size_m: [40, 40]\n"
                         "    cell_m: 1.0\n"
                         "    depth_m: 18\n"
                         "    components:\n"
                         "      - {type: plane, slope_deg: 1.0, downslope_azimuth_deg: 100}\n";
  const sonarsynth::Scene scene = sonarsynth::load_scene(path.string());
  std::filesystem::remove(path);
  std::cout << "config: scene with " << scene.bathymetry.geometry().size() << " nodes\n";
  return scene.bathymetry.empty() ? 1 : 0;
}
