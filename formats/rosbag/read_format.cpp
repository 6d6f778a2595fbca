// SPDX-License-Identifier: MIT
// The ROS 1 bag format's read side: its SideScanSource, `info`, and the bag -> XTF and
// bag -> JSF conversions (docs/rosbag.md, "Reading bags").
#include "sonarsynth/formats/rosbag/read_format.hpp"

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/rosbag/format.hpp"
#include "sonarsynth/formats/rosbag/read_common.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"

namespace sonarsynth::rosbag {
namespace {

ContainerInfo container(const Reader& reader) {
  ContainerInfo c{.format = "ROS 1 bag",
                  .keys = {{"version", "2.0"}, {"chunks", reader.chunk_count()}},
                  .text = "ROS 1 bag 2.0, " + std::to_string(reader.chunk_count()) + " chunks",
                  .list_key = "connections",
                  .list_title = "Connections",
                  .rows = {}};
  for (const ConnectionInfo& conn : reader.connections()) {
    c.rows.push_back({.id = conn.id,
                      .topic = conn.topic,
                      .type = {"type", conn.type},
                      .detail = {"md5sum", conn.md5sum},
                      .text = conn.type,
                      .messages = conn.messages,
                      .read_as = read_as(conn.decoded, conn.type)});
  }
  return c;
}

}  // namespace

bool identify(std::span<const std::uint8_t> head) {
  static constexpr char kMagic[] = "#ROSBAG V";
  return head.size() >= sizeof kMagic - 1 &&
         std::memcmp(head.data(), kMagic, sizeof kMagic - 1) == 0;
}

std::unique_ptr<SideScanSource> open_reader(const std::filesystem::path& path) {
  return std::make_unique<BagSource<Reader>>(path, sonar_format());
}

SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  return bag_file_info<Reader>(path, max_anomalies, container);
}

ConvertResult rosbag_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource /*altitude_source*/) {
  return bag_to_xtf<Reader>(sonar_format(), "ROS 1 bag", "bag message", in, out, overwrite);
}

ConvertResult rosbag_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource altitude_source) {
  return via_xtf_to_jsf(rosbag_to_xtf, sonar_format(), in, out, overwrite, altitude_source);
}

}  // namespace sonarsynth::rosbag
