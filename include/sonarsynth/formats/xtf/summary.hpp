// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth::xtf {

/// Minimum and maximum of a series of values (empty when count == 0).
struct ValueRange {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  std::uint64_t count = 0;
  void add(double v) {
    if (!(v == v)) return;  // NaN
    min = v < min ? v : min;
    max = v > max ? v : max;
    ++count;
  }
};

/// Per ChannelNumber statistics over the sonar pings.
struct ChannelSummary {
  std::uint64_t pings = 0;
  ValueRange samples;        ///< NumSamples
  ValueRange slant_range_m;  ///< SlantRange
  std::uint8_t type_of_channel = 0;
};

/// What `sonarsynth info` reports about an XTF file, gathered in one streaming pass.
struct FileSummary {
  std::string name;
  std::uint64_t file_size = 0;
  XtfFileHeader header;
  std::vector<XtfChanInfo> chan_info;
  std::map<std::uint8_t, std::uint64_t> packet_counts;  ///< by HeaderType
  std::uint64_t pings = 0;
  std::uint64_t pings_with_valid_nav = 0;
  std::uint64_t pings_with_valid_time = 0;
  std::map<std::uint16_t, ChannelSummary> channels;  ///< by ChannelNumber
  std::optional<UtcTime> first_time;                 ///< first valid ping time
  std::optional<UtcTime> last_time;                  ///< last valid ping time
  /// Sensor X (longitude or easting) and Y (latitude or northing) of pings with valid nav, in
  /// the file's NavUnits (degrees for 3).
  ValueRange sensor_x;
  ValueRange sensor_y;
  // Ping-header attitude and geometry over all pings, file units (degrees, metres).
  ValueRange heading_deg, pitch_deg, roll_deg, heave_m, altitude_m, depth_m, sound_velocity;
  // Attitude packets (type 3), degrees.
  ValueRange attitude_heading_deg, attitude_pitch_deg, attitude_roll_deg;
  std::uint64_t navigation_packets_valid = 0;
  /// Pings whose SensorPrimaryAltitude is 0 or not finite: no seabed (no bottom pick) under the
  /// sensor. `info` lists them with the anomalies.
  std::uint64_t pings_without_altitude = 0;
  std::array<std::uint64_t, kAnomalyKindCount> anomaly_counts{};
  std::vector<Anomaly> anomalies;  ///< the first ReaderOptions::max_anomaly_messages
};

/// Reads every packet of `reader` (streaming) and summarises the file.
FileSummary summarize(Reader& reader);
/// Opens `path` and summarises it. Throws FormatError if it is not a readable XTF file.
FileSummary summarize_file(const std::filesystem::path& path, ReaderOptions options = {});

/// "2013-09-10T21:13:08.000000Z".
std::string iso8601(UtcTime t);

}  // namespace sonarsynth::xtf
