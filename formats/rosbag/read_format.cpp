// SPDX-License-Identifier: MIT
// The ROS 1 bag format's read side: its SideScanSource, `info`, and the bag -> XTF and
// bag -> JSF conversions (docs/rosbag.md, "Reading bags").
#include "sonarsynth/formats/rosbag/read_format.hpp"

#include <cstring>
#include <memory>
#include <sstream>
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

std::string info_json(const Reader& reader, const BagSummary& s) {
  using info::Json;
  Json j;
  j["file"] = info::file_text(reader.name());
  j["format"] = "ROS 1 bag";
  j["size_bytes"] = reader.file_size();
  j["version"] = "2.0";
  j["chunks"] = reader.chunk_count();
  Json conns = Json::array();
  for (const ConnectionInfo& c : reader.connections()) {
    const char* as = read_as(c.decoded, c.type);
    conns.push_back({{"id", c.id},
                     {"topic", info::file_text(c.topic)},
                     {"type", info::file_text(c.type)},
                     {"md5sum", info::file_text(c.md5sum)},
                     {"messages", c.messages},
                     {"read_as", as ? Json(as) : Json(nullptr)}});
  }
  j["connections"] = std::move(conns);
  add_summary_json(j, s, reader.image_info(), reader.anomalies(), reader.total_anomalies());
  return j.dump(2, ' ', true);
}

std::string info_text(const Reader& reader, const BagSummary& s, std::size_t max_anomalies) {
  std::ostringstream os;
  os << "File: " << reader.name() << " (" << reader.file_size() << " bytes)\n"
     << "Format: ROS 1 bag 2.0, " << reader.chunk_count() << " chunks\nConnections:\n";
  for (const ConnectionInfo& c : reader.connections()) {
    const char* as = read_as(c.decoded, c.type);
    os << "  " << c.topic << " (" << c.type << "): " << c.messages << " messages"
       << (as ? std::string(", read as ") + as : std::string()) << "\n";
  }
  summary_text(os, s, reader.image_info(), reader.anomalies(), reader.total_anomalies(),
               max_anomalies);
  return os.str();
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
  Reader reader(path);
  const BagSummary s = summarise(ping_stream(reader));
  return {info_json(reader, s), info_text(reader, s, max_anomalies)};
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
