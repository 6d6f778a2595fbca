// SPDX-License-Identifier: MIT
// The MCAP format's read side: its SideScanSource, `info`, and the MCAP -> XTF and MCAP -> JSF
// conversions (docs/robotics.md, "Reading bags").
#include "sonarsynth/formats/mcap/read_format.hpp"

#include <cstring>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/mcap/format.hpp"
#include "sonarsynth/formats/mcap/opcodes.hpp"
#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/rosbag/read_common.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::mcap {
namespace {

using rosbag::add_summary_json;
using rosbag::BagSummary;
using rosbag::ping_stream;
using rosbag::read_as;
using rosbag::summarise;
using rosbag::summary_text;
using rosbag::via_xtf_to_jsf;
using rosbag::write_xtf;
using rosbag::xtf_options;

class McapSource : public SideScanSource {
 public:
  explicit McapSource(const std::filesystem::path& path) : reader_(path) {}
  bool next(SideScanRecord& r) override {
    if (!reader_.next_ping(ping_)) return false;
    r.sonar = std::move(ping_.sonar);
    r.nav_valid = ping_.nav_valid;
    r.time_valid = true;
    r.layback_m = 0.0;
    r.heading_true_deg = deg_from_rad(r.sonar.heading_true_rad);
    r.index = ping_.index;
    return true;
  }
  const SonarFormat& format() const override { return sonar_format(); }
  std::uint64_t total_anomalies() const override { return reader_.total_anomalies(); }
  std::vector<std::string> anomaly_messages(std::size_t max) const override {
    return first_anomaly_messages(reader_.anomalies(), max);
  }

 private:
  Reader reader_;
  Ping ping_;
};

std::string info_json(const Reader& reader, const BagSummary& s) {
  using info::Json;
  Json j;
  j["file"] = info::file_text(reader.name());
  j["format"] = "MCAP";
  j["size_bytes"] = reader.file_size();
  j["profile"] = info::file_text(reader.profile());
  j["library"] = info::file_text(reader.library());
  j["indexed"] = reader.indexed();
  j["chunks"] = reader.chunk_count();
  Json channels = Json::array();
  for (const ChannelInfo& c : reader.channels()) {
    const char* as = read_as(c.decoded, c.schema);
    channels.push_back({{"id", c.id},
                        {"topic", info::file_text(c.topic)},
                        {"schema", info::file_text(c.schema)},
                        {"message_encoding", info::file_text(c.message_encoding)},
                        {"messages", c.messages},
                        {"read_as", as ? Json(as) : Json(nullptr)}});
  }
  j["channels"] = std::move(channels);
  add_summary_json(j, s, reader.image_info(), reader.anomalies(), reader.total_anomalies());
  return j.dump(2, ' ', true);
}

std::string info_text(const Reader& reader, const BagSummary& s, std::size_t max_anomalies) {
  std::ostringstream os;
  os << "File: " << reader.name() << " (" << reader.file_size() << " bytes)\n"
     << "Format: MCAP, profile '" << reader.profile() << "', library '" << reader.library() << "', "
     << reader.chunk_count() << " chunks, "
     << (reader.indexed() ? "read through its index" : "no index: records walked")
     << "\nChannels:\n";
  for (const ChannelInfo& c : reader.channels()) {
    const char* as = read_as(c.decoded, c.schema);
    os << "  " << c.topic << " (" << (c.schema.empty() ? "no schema" : c.schema) << ", "
       << c.message_encoding << "): " << c.messages << " messages"
       << (as ? std::string(", read as ") + as : std::string()) << "\n";
  }
  summary_text(os, s, reader.image_info(), reader.anomalies(), reader.total_anomalies(),
               max_anomalies);
  return os.str();
}

}  // namespace

bool identify(std::span<const std::uint8_t> head) {
  return head.size() >= kMagic.size() &&
         std::memcmp(head.data(), kMagic.data(), kMagic.size()) == 0;
}

std::unique_ptr<SideScanSource> open_reader(const std::filesystem::path& path) {
  return std::make_unique<McapSource>(path);
}

SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  Reader reader(path);
  const BagSummary s = summarise(ping_stream(reader));
  return {info_json(reader, s), info_text(reader, s, max_anomalies)};
}

ConvertResult mcap_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource /*altitude_source*/) {
  ConvertResult r;
  r.from = &sonar_format();
  r.to = &xtf::sonar_format();
  Reader reader(in);
  xtf::Writer writer(
      out, xtf_options(reader.image_info(),
                       "converted by sonarsynth from the MCAP file " + in.filename().string(),
                       overwrite));
  write_xtf(ping_stream(reader), writer, "MCAP chunk (or message)", in, r);
  return r;
}

ConvertResult mcap_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource altitude_source) {
  return via_xtf_to_jsf(mcap_to_xtf, sonar_format(), in, out, overwrite, altitude_source);
}

}  // namespace sonarsynth::mcap
