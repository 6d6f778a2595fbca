// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {

/// UTC time with microsecond resolution (the same type as survey.hpp's; XTF stores 10 ms, JSF 1
/// ms).
using UtcTime = std::chrono::sys_time<std::chrono::microseconds>;

/// One side-scan ping in SI units, whatever the file format: what the simulator hands to every
/// format's writer and what every format's reader gives back (docs/architecture.md). Angles in
/// radians, distances in metres, speeds in m/s; conversion to the file's degrees and knots happens
/// at the byte level.
struct SonarPing {
  UtcTime time_utc{};             ///< ping time (XTF stores 1/100 s, truncated)
  std::uint32_t ping_number = 0;  ///< consecutive, usually from 0
  /// Sensor (towfish/AUV) position, WGS 84; lat_rad/lon_rad only (height_m is not stored).
  /// Neither latitude nor longitude may be exactly 0 (readers treat 0 as "no position").
  Geodetic sensor_position{};
  /// Ship position if different from the sensor; when empty the writer stores the sensor's.
  std::optional<Geodetic> ship_position{};
  double heading_true_rad = 0.0;  ///< true heading of the sensor, clockwise from north, any value
  double pitch_rad = 0.0;         ///< + nose up
  double roll_rad = 0.0;          ///< + starboard down
  double heave_m = 0.0;           ///< + sensor up
  /// Sensor height above the seafloor, >= 0; 0 = no seabed under the sensor (no bottom pick:
  /// written as SensorPrimaryAltitude 0, which `sonarsynth info` counts).
  double altitude_m = 0.0;
  double depth_m = 0.0;             ///< sensor depth below the surface, + down
  double speed_m_s = 0.0;           ///< sensor speed through water / over ground, >= 0
  double sound_speed_m_s = 1500.0;  ///< c, full (not halved) speed of sound, > 0
  double slant_range_m = 0.0;       ///< slant range of the last sample, > 0
  /// Samples per side ordered NEAR -> FAR, in output sample units (e.g. 0..32767 for u16).
  /// Sample i covers slant range [i, i+1) * slant_range_m / size().
  std::vector<float> port;
  std::vector<float> starboard;
};

/// A stand-alone attitude record (XTF type 3, JSF pitch/roll message 2020).
struct AttitudeSample {
  UtcTime time_utc{};  ///< stored to the millisecond (and microsecond in the epoch fields)
  double heading_true_rad = 0.0;  ///< true heading, clockwise from north
  double pitch_rad = 0.0;         ///< + nose up
  double roll_rad = 0.0;          ///< + starboard down
  double heave_m = 0.0;           ///< + up
  double yaw_rad = 0.0;           ///< + turn right
};

/// A stand-alone, source-time-stamped position fix (XTF type 42).
struct NavigationFix {
  UtcTime time_utc{};   ///< time of the fix, microsecond resolution
  Geodetic position{};  ///< WGS 84, radians; height_m -> RawAltitude (m)
};

}  // namespace sonarsynth
