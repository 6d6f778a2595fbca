// SPDX-License-Identifier: MIT
// The pings the consumer programs write through a codec's Writer: one second apart, at a fixed
// position 10 m above the seabed, 64 samples a side (100 port, 200 starboard).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <utility>

#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/geo_frame.hpp"

template <class Writer>
void write_test_pings(Writer& writer, std::uint32_t count, double slant_range_m) {
  for (std::uint32_t i = 0; i < count; ++i) {
    sonarsynth::SonarPing ping;
    ping.time_utc = sonarsynth::UtcTime(std::chrono::seconds(1'700'000'000 + i));
    ping.ping_number = i;
    ping.sensor_position = {sonarsynth::rad_from_deg(48.45), sonarsynth::rad_from_deg(-68.83)};
    ping.altitude_m = 10.0;
    ping.slant_range_m = slant_range_m;
    ping.port.assign(64, 100.0f);
    ping.starboard.assign(64, 200.0f);
    writer.write_ping(ping);
  }
  writer.close();
}

/// Writes three test pings (48 m slant range) into a new file `<temp dir>/<name>` (replacing
/// any) with a codec's Writer and options of its defaults; returns the file's path and what
/// `count` (a member of the Writer, e.g. &Writer::pings_written) says of the closed writer.
template <class Writer, class WriterOptions, class Count>
std::pair<std::filesystem::path, std::uint64_t> write_test_file(const char* name, Count count) {
  const auto path = std::filesystem::temp_directory_path() / name;
  WriterOptions options;
  options.overwrite = true;
  Writer writer(path, options);
  write_test_pings(writer, 3, 48.0);
  return {path, std::invoke(count, writer)};
}
