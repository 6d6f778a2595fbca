// SPDX-License-Identifier: MIT
#include <iostream>

#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/version.hpp"

int main() {
  const auto frame = sonarsynth::GeoFrame::around(
      {sonarsynth::rad_from_deg(48.45), sonarsynth::rad_from_deg(-68.83), 0.0});
  std::cout << "sonarsynth " << sonarsynth::kVersion << " EPSG:" << frame.epsg() << "\n";
  return frame.epsg() == 32619 ? 0 : 1;
}
