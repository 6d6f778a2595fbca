// SPDX-License-Identifier: MIT
// What the file throughput benchmarks (xtf_throughput, bag_throughput) share: the ping
// they write and the median of their runs.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace bench {

/// A 75 m ping at 48.4 N 68.8 W, 10 m altitude, with `samples` u16-range samples per side.
inline sonarsynth::SonarPing throughput_ping(std::size_t samples) {
  sonarsynth::SonarPing ping;
  ping.sensor_position = {sonarsynth::rad_from_deg(48.4), sonarsynth::rad_from_deg(-68.8), 0.0};
  ping.altitude_m = 10.0;
  ping.slant_range_m = 75.0;
  ping.port.resize(samples);
  ping.starboard.resize(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    ping.port[i] = static_cast<float>((i * 7919) % 32768);
    ping.starboard[i] = static_cast<float>((i * 104729) % 32768);
  }
  return ping;
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace bench
