// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/geo_frame.hpp"

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

/// The pings of a Reader with next_ping(Ping&) as side-scan records: its Ping's `sonar`,
/// `nav_valid` and `index`, the heading in degrees; `time_valid` and `layback_m` where the Ping
/// has them (JSF), else a valid time and no layback (a bag's pings).
template <class Reader, class Ping>
class PingReaderSource : public ReaderSource<Reader> {
 public:
  PingReaderSource(const std::filesystem::path& path, const SonarFormat& format)
      : ReaderSource<Reader>(path, format) {}
  bool next(SideScanRecord& r) override {
    if (!this->reader_.next_ping(ping_)) return false;
    r.sonar = std::move(ping_.sonar);
    r.nav_valid = ping_.nav_valid;
    r.time_valid = true;
    r.layback_m = 0.0;
    if constexpr (requires(const Ping& p) {
                    p.time_valid;
                    p.layback_m;
                  }) {
      r.time_valid = ping_.time_valid;
      r.layback_m = ping_.layback_m;
    }
    r.heading_true_deg = deg_from_rad(r.sonar.heading_true_rad);
    r.index = ping_.index;
    return true;
  }

 private:
  Ping ping_;
};

/// The SonarFormat::open_reader of a format whose Reader has next_ping(Ping&): its pings as
/// `format()`'s (PingReaderSource).
template <class Reader, class Ping, const SonarFormat& (*format)()>
std::unique_ptr<SideScanSource> open_ping_source(const std::filesystem::path& path) {
  return std::make_unique<PingReaderSource<Reader, Ping>>(path, format());
}

}  // namespace sonarsynth
