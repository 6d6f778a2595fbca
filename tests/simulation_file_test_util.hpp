// SPDX-License-Identifier: MIT
// The fixture and scenes shared by the simulation file tests (simulation_file_test.cpp,
// simulation_options_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_util.hpp"
#include "fields_test_util.hpp"
#include "sonarsynth/sonar.hpp"

namespace sonarsynth::simulation_file_test {

namespace fs = std::filesystem;

class SimulationFile : public test::ScratchDirTest {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    return ScratchDirTest::write(name, text).string();
  }
};

inline constexpr const char* kScene = R"(
seed: 12
bathymetry:
  generate: {centre: {lat_deg: 48.45, lon_deg: -68.83}, size_m: [200, 200], cell_m: 1, depth_m: 30}
sonar: {frequency_khz: 300, range_m: 50, samples: 2000, pulse: {type: chirp, bandwidth_khz: 50}}
render: {backscatter: lambert, absorption: false, quality: {gauss_points: 3, along_track_planes: 3}}
noise: {model: paper, uniform_half_width: 0.2}
output: {tvg: none, gain_db: 12, sample_format: u8}
)";

inline constexpr const char* kLine =
    "  lines: [{name: a, waypoints: [{east_m: -20, north_m: 0}, {east_m: 20, north_m: 0}]}]\n";
inline constexpr const char* kBathy =
    "bathymetry:\n  generate: {centre: {lat_deg: 48.45, lon_deg: -68.83}, size_m: [200, 200], "
    "cell_m: 1, depth_m: 30}\n";

// Equal as option values: NaN (auto) equals NaN.
inline bool same(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}

/// The sonar of `a` and `b` member by member, without the option table.
inline void expect_same_members(const SonarConfig& a, const SonarConfig& b) {
  using S = SonarConfig;
  test::expect_equal_fields(a, b, &S::frequency_hz, &S::max_range_m, &S::samples_per_channel,
                            &S::sound_speed_m_s, &S::tilt_rad, &S::horizontal_beam_width_rad,
                            &S::pulse, &S::pulse_length_s, &S::bandwidth_hz, &S::ping_period_s);
  using V = VerticalBeamPattern;
  test::expect_equal_fields(a.vertical_beam, b.vertical_beam, &V::shape, &V::width_3db_rad,
                            &V::upper_half_width_rad, &V::height_over_wavelength);
}

}  // namespace sonarsynth::simulation_file_test
