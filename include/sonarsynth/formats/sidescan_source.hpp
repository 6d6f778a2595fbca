// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"

namespace sonarsynth {

/// One side-scan ping of an XTF or JSF file, as the product commands (mosaic, waterfall,
/// match) use it.
struct SideScanRecord {
  SonarPing sonar;          ///< SI units, port/starboard near -> far
  bool nav_valid = false;   ///< sonar.sensor_position is a geographic position
  bool time_valid = false;  ///< sonar.time_utc is a valid date and time
  double layback_m = 0.0;   ///< file layback (0 if none)
  double heading_deg = 0.0;
  std::uint64_t index = 0;  ///< increasing, unique in the file (XTF packet / JSF message index)
};

/// The pings of a side-scan file whatever its format: JSF when it starts with the JSF marker
/// (docs/jsf.md), XTF otherwise (so that a file that is neither gets the XTF reader's error).
class SideScanSource {
 public:
  virtual ~SideScanSource() = default;
  /// Throws FormatError if the file cannot be opened or is not a readable XTF/JSF file.
  static std::unique_ptr<SideScanSource> open(const std::filesystem::path& path);
  /// The next ping; false at the end. Broken records are skipped and counted as anomalies.
  virtual bool next(SideScanRecord& record) = 0;
  virtual SonarFileFormat format() const = 0;
  virtual std::uint64_t total_anomalies() const = 0;
  /// The first kept anomaly messages (at most `max`).
  virtual std::vector<std::string> anomaly_messages(std::size_t max) const = 0;
};

}  // namespace sonarsynth
