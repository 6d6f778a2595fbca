// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <vector>

#include "sonarsynth/sonar.hpp"

namespace sonarsynth {

/// K along-track beam planes: azimuths from the across-track direction, evenly across +-1.25
/// horizontal beam widths (0 for K = 1), and their shares of `beta_eff_rad`, weighted by the
/// two-way horizontal pattern and summing to it exactly.
struct AlongTrackPlanes {
  std::vector<double> azimuth_rad;
  std::vector<double> beta_eff_rad;
  std::size_t size() const { return azimuth_rad.size(); }
};
AlongTrackPlanes make_along_track_planes(const SonarConfig& sonar, int count, double beta_eff_rad);

}  // namespace sonarsynth
