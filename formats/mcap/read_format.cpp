// SPDX-License-Identifier: MIT
// The MCAP format's read side: its SideScanSource, `info`, and the MCAP -> XTF and MCAP -> JSF
// conversions (docs/robotics.md, "Reading bags").
#include "sonarsynth/formats/mcap/read_format.hpp"

#include <cstring>
#include <memory>
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

using rosbag::bag_file_info;
using rosbag::bag_to_xtf;
using rosbag::BagSource;
using rosbag::ContainerInfo;
using rosbag::read_as;
using rosbag::via_xtf_to_jsf;

ContainerInfo container(const Reader& reader) {
  ContainerInfo c{
      .format = "MCAP",
      .keys = {{"profile", info::file_text(reader.profile())},
               {"library", info::file_text(reader.library())},
               {"indexed", reader.indexed()},
               {"chunks", reader.chunk_count()}},
      .text = "MCAP, profile '" + reader.profile() + "', library '" + reader.library() + "', " +
              std::to_string(reader.chunk_count()) + " chunks, " +
              (reader.indexed() ? "read through its index" : "no index: records walked"),
      .list_key = "channels",
      .list_title = "Channels",
      .rows = {}};
  for (const ChannelInfo& ch : reader.channels()) {
    c.rows.push_back(
        {.id = ch.id,
         .topic = ch.topic,
         .type = {"schema", ch.schema},
         .detail = {"message_encoding", ch.message_encoding},
         .text = (ch.schema.empty() ? "no schema" : ch.schema) + ", " + ch.message_encoding,
         .messages = ch.messages,
         .read_as = read_as(ch.decoded, ch.schema)});
  }
  return c;
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
  return bag_file_info<Reader>(path, max_anomalies, container);
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
