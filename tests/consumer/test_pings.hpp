// SPDX-License-Identifier: MIT
// The pings the consumer programs write through a codec's Writer: one second apart, at a fixed
// position 10 m above the seabed, 64 samples a side (100 port, 200 starboard).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>

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

/// Writes `count` test pings into a new file `path` (replacing any) with a codec's Writer and
/// options of its defaults, then gives the closed writer to `done`.
template <class Writer, class WriterOptions, class Done>
void write_test_file(const std::filesystem::path& path, std::uint32_t count, double slant_range_m,
                     Done done) {
  WriterOptions options;
  options.overwrite = true;
  Writer writer(path, options);
  write_test_pings(writer, count, slant_range_m);
  done(writer);
}
