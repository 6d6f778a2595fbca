// SPDX-License-Identifier: MIT
// The small dataset spec the dataset tests draw from (docs/dataset.md).
#pragma once

#include <string>

namespace sonarsynth::test {

// Tiny items: a 6 m line at 3 m/s, 10 m range, 200 samples (tens of pings each).
inline std::string tiny_spec(int count, const std::string& extra = "") {
  return "name: tiny\nseed: 99\ncount: " + std::to_string(count) + R"(
location: {lat_deg: 43.0, lon_deg: 5.0}
seabed:
  depth_m: [10, 14]
  cell_m: 0.5
  material: {sand: 2, mud: 1}
  slope_deg: [0, 2]
  roughness: {rms_m: [0.01, 0.05], wavelength_m: [5, 10]}
  ripples: {probability: 0.5, wavelength_m: [1, 2], amplitude_m: [0.02, 0.04]}
objects:
  count: [1, 3]
  burial: [0, 0.3]
  across_track_m: [2, 8]
  types:
    rock: {weight: 2, diameter_m: [0.5, 1.5]}
    box: {length_m: [1, 3], width_m: [0.5, 1], height_m: [0.4, 1]}
    pipe: {diameter_m: [0.2, 0.4], length_m: [3, 6]}
    moored: {diameter_m: [0.4, 0.8], height_m: [2, 3]}
survey:
  line_length_m: 6
  altitude_m: [3, 5]
  speed_m_s: 3
sonar: {preset: seascan-hds-600, range_m: 10, samples: 200}
noise: {model: speckle, snr_db: [15, 30]}
run: {quality: fast}
)" + extra;
}

}  // namespace sonarsynth::test
