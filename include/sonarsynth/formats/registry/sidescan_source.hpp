// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"

namespace sonarsynth {

/// One side-scan ping of a sonar file of any format, as the product commands (mosaic, waterfall,
/// match, info) and Python use it.
struct SideScanRecord {
  SonarPing sonar;                ///< SI units, port/starboard near -> far
  bool nav_valid = false;         ///< sonar.sensor_position is a geographic position
  bool time_valid = false;        ///< sonar.time_utc is a valid date and time
  double layback_m = 0.0;         ///< file layback (0 if none)
  double heading_true_deg = 0.0;  ///< true heading as the file stores it, clockwise from north
  std::uint64_t index = 0;        ///< increasing, unique in the file (e.g. XTF packet, JSF message)
};

/// The pings of a side-scan file whatever its format; each format's open_reader makes one
/// (SonarFormat, formats/<codec>/format.cpp).
class SideScanSource {
 public:
  virtual ~SideScanSource() = default;
  /// The reader of the format identify_sonar_format() finds by the file's first bytes (the
  /// first format of the list, XTF, when none claims it, so that such a file gets its reader's
  /// error). Defined with the format list (formats/registry/sonar_formats.cpp). Throws FormatError
  /// if the file cannot be opened or read.
  static std::unique_ptr<SideScanSource> open(const std::filesystem::path& path);
  /// The next ping; false at the end. Broken records are skipped and counted as anomalies.
  virtual bool next(SideScanRecord& record) = 0;
  virtual const SonarFormat& format() const = 0;
  virtual std::uint64_t total_anomalies() const = 0;
  /// The first kept anomaly messages (at most `max`).
  virtual std::vector<std::string> anomaly_messages(std::size_t max) const = 0;
};

/// The messages of the first `max` of a reader's anomalies (elements with a `message`): what the
/// formats' anomaly_messages() return.
template <class Anomalies>
std::vector<std::string> first_anomaly_messages(const Anomalies& anomalies, std::size_t max) {
  std::vector<std::string> out;
  for (const auto& a : anomalies) {
    if (out.size() >= max) break;
    out.push_back(a.message);
  }
  return out;
}

/// What a format's SideScanSource forwards to its Reader (made from the path, with
/// total_anomalies() and anomalies()): the format's source derives from it and adds next().
template <class Reader>
class ReaderSource : public SideScanSource {
 public:
  ReaderSource(const std::filesystem::path& path, const SonarFormat& format)
      : reader_(path), format_(format) {}
  const SonarFormat& format() const override { return format_; }
  std::uint64_t total_anomalies() const override { return reader_.total_anomalies(); }
  std::vector<std::string> anomaly_messages(std::size_t max) const override {
    return first_anomaly_messages(reader_.anomalies(), max);
  }

 protected:
  Reader reader_;

 private:
  const SonarFormat& format_;
};

}  // namespace sonarsynth
