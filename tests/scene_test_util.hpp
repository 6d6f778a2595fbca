// SPDX-License-Identifier: MIT
// The scene files the tests run: the head they share (docs/scene-file.md).
#pragma once

#include <sstream>
#include <string>

namespace sonarsynth::test {

/// The head of a scene file on a flat seabed generated around 43 N 5 E (0.5 m cells, `width_m`
/// east by `height_m` north, `depth_m` deep), surveyed from 2026-03-01T10:00:00Z at `speed_m_s`
/// and `altitude_m`. It ends with "  lines:" (no newline), to which the caller appends the lines
/// (and then the objects, sonar...), starting with a newline.
inline std::string flat_scene(const std::string& name, int seed, double width_m, double height_m,
                              double depth_m, double speed_m_s, double altitude_m) {
  std::ostringstream os;
  os << "\nname: " << name << "\nseed: " << seed
     << "\nbathymetry:\n  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [" << width_m
     << ", " << height_m << "], cell_m: 0.5, depth_m: " << depth_m
     << "}\nsurvey:\n  start_time: \"2026-03-01T10:00:00Z\"\n  speed_m_s: " << speed_m_s
     << "\n  altitude_m: " << altitude_m << "\n  lines:";
  return os.str();
}

}  // namespace sonarsynth::test
