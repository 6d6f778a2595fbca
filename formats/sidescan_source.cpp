// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/sidescan_source.hpp"

#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {

/// The messages of the first `max` anomalies a reader recorded (XTF and JSF anomalies alike).
template <class Anomalies>
std::vector<std::string> first_messages(const Anomalies& anomalies, std::size_t max) {
  std::vector<std::string> out;
  for (const auto& a : anomalies) {
    if (out.size() >= max) break;
    out.push_back(a.message);
  }
  return out;
}

class XtfSource : public SideScanSource {
 public:
  explicit XtfSource(const std::filesystem::path& path) : reader_(path) {}
  bool next(SideScanRecord& r) override {
    while (reader_.next(packet_)) {
      if (packet_.kind != xtf::PacketKind::kPing) continue;
      r.sonar = std::move(packet_.ping.sonar);
      r.nav_valid = packet_.ping.nav_valid && reader_.file_header().NavUnits == 3;
      r.time_valid = packet_.ping.time_valid;
      r.layback_m = packet_.ping.header.Layback;
      r.heading_deg = packet_.ping.header.SensorHeading;
      r.index = packet_.index;
      return true;
    }
    return false;
  }
  SonarFileFormat format() const override { return SonarFileFormat::kXtf; }
  std::uint64_t total_anomalies() const override { return reader_.total_anomalies(); }
  std::vector<std::string> anomaly_messages(std::size_t max) const override {
    return first_messages(reader_.anomalies(), max);
  }

 private:
  xtf::Reader reader_;
  xtf::Packet packet_;
};

class JsfSource : public SideScanSource {
 public:
  explicit JsfSource(const std::filesystem::path& path) : reader_(path) {}
  bool next(SideScanRecord& r) override {
    if (!reader_.next_ping(ping_)) return false;
    r.sonar = std::move(ping_.sonar);
    r.nav_valid = ping_.nav_valid;
    r.time_valid = ping_.time_valid;
    r.layback_m = ping_.layback_m;
    r.heading_deg = deg_from_rad(r.sonar.heading_rad);
    r.index = ping_.index;
    return true;
  }
  SonarFileFormat format() const override { return SonarFileFormat::kJsf; }
  std::uint64_t total_anomalies() const override { return reader_.total_anomalies(); }
  std::vector<std::string> anomaly_messages(std::size_t max) const override {
    return first_messages(reader_.anomalies(), max);
  }

 private:
  jsf::Reader reader_;
  jsf::Ping ping_;
};

}  // namespace

std::unique_ptr<SideScanSource> SideScanSource::open(const std::filesystem::path& path) {
  if (detect_sonar_file_format(path) == SonarFileFormat::kJsf) {
    return std::make_unique<JsfSource>(path);
  }
  return std::make_unique<XtfSource>(path);
}

}  // namespace sonarsynth
