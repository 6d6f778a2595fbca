// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"

namespace sonarsynth::jsf {

using xtf::ValueRange;

/// What `sonarsynth info` reports about a JSF file, gathered in one streaming pass.
struct FileSummary {
  std::string name;
  std::uint64_t file_size = 0;
  std::map<std::uint16_t, std::uint64_t> message_counts;  ///< by message type
  /// Sonar data messages by subsystem, then channel.
  std::map<std::uint8_t, std::map<std::uint8_t, std::uint64_t>> sonar_counts;
  std::optional<SystemInformation> system_information;
  int ping_subsystem = -1;  ///< the subsystem assembled into pings
  std::uint64_t pings = 0;
  std::uint64_t pings_with_valid_nav = 0;
  std::uint64_t pings_with_valid_time = 0;
  std::uint64_t pings_without_altitude = 0;
  std::optional<UtcTime> first_time;
  std::optional<UtcTime> last_time;
  ValueRange samples, slant_range_m, sample_interval_ns, weighting_factor;
  ValueRange longitude_deg, latitude_deg;  ///< pings with valid navigation
  ValueRange heading_deg, pitch_deg, roll_deg, heave_m, altitude_m, depth_m, sound_speed_m_s;
  std::array<std::uint64_t, kAnomalyKindCount> anomaly_counts{};
  std::vector<Anomaly> anomalies;
};

FileSummary summarize(Reader& reader);
/// Opens `path` and summarises it. Throws FormatError if it is not a JSF file.
FileSummary summarize_file(const std::filesystem::path& path, ReaderOptions options = {});

}  // namespace sonarsynth::jsf
