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
#include "sonarsynth/formats/rosbag/read_common.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"

namespace sonarsynth::mcap {
namespace {

using rosbag::add_summary_json;
using rosbag::bag_to_xtf;
using rosbag::BagSource;
using rosbag::BagSummary;
using rosbag::ping_stream;
using rosbag::read_as;
using rosbag::summarise;
using rosbag::summary_text;
using rosbag::via_xtf_to_jsf;

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
  return std::make_unique<BagSource<Reader>>(path, sonar_format());
}

SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  Reader reader(path);
  const BagSummary s = summarise(ping_stream(reader));
  return {info_json(reader, s), info_text(reader, s, max_anomalies)};
}

ConvertResult mcap_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource /*altitude_source*/) {
  return bag_to_xtf<Reader>(sonar_format(), "MCAP file", "MCAP chunk (or message)", in, out,
                            overwrite);
}

ConvertResult mcap_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource altitude_source) {
  return via_xtf_to_jsf(mcap_to_xtf, sonar_format(), in, out, overwrite, altitude_source);
}

}  // namespace sonarsynth::mcap
