// SPDX-License-Identifier: MIT
// What the ROS 1 bag format (formats/rosbag/format.cpp) and the MCAP format
// (formats/mcap/format.cpp) share on their read side: the reader, the summary of `info`, its
// JSON and text after the container's own part, and the bag -> XTF and bag -> JSF conversions
// (docs/rosbag.md and docs/robotics.md, "Reading bags").
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sonarsynth/formats/io/convert_result.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"

namespace sonarsynth::rosbag {

/// What `info` and the conversions read of a bag reader (rosbag::Reader or mcap::Reader).
struct PingStream {
  std::function<bool(Ping&)> next_ping;
  const std::optional<ImageInfo>& image_info;
  const std::vector<ImuSample>& imu;  ///< `used` set as pings take them
  const std::vector<Anomaly>& anomalies;
  std::function<std::uint64_t()> total_anomalies;
};

template <class BagReader>
PingStream ping_stream(BagReader& reader) {
  return {[&reader](Ping& p) { return reader.next_ping(p); }, reader.image_info(), reader.imu(),
          reader.anomalies(), [&reader] { return reader.total_anomalies(); }};
}

/// What a connection (or channel) of `type` (or schema name) is read as; nullptr if not decoded.
const char* read_as(bool decoded, std::string_view type);

struct BagSummary {
  std::uint64_t pings = 0, nav = 0, attitude = 0;
  xtf::ValueRange samples, slant_range_m, sound_speed_m_s, lat_deg, lon_deg, heading_deg, pitch_deg,
      roll_deg;
  std::optional<UtcTime> first, last;
};

/// Reads every ping.
BagSummary summarise(const PingStream& bag);
/// `info --json` from "sonar" on, after the container's keys.
void add_summary_json(info::Json& j, const BagSummary& s,
                      const std::optional<ImageInfo>& image_info,
                      const std::vector<Anomaly>& anomalies, std::uint64_t total_anomalies);
/// `info` from the "Sonar" line on, after the container's lines.
void summary_text(std::ostream& os, const BagSummary& s, const std::optional<ImageInfo>& image_info,
                  const std::vector<Anomaly>& anomalies, std::uint64_t total_anomalies,
                  std::size_t max_anomalies);

/// A connection (ROS 1) or channel (MCAP) as `info` lists it.
struct TopicRow {
  std::uint64_t id = 0;
  std::string topic;
  std::pair<const char*, std::string> type, detail;  ///< JSON keys and values after "topic"
  std::string text;                                  ///< the text's words in parentheses
  std::uint64_t messages = 0;
  const char* read_as = nullptr;  ///< read_as() of it
};

/// What `info` says of a bag's container, before the summary.
struct ContainerInfo {
  const char* format;      ///< "format" of the JSON
  info::Json keys;         ///< the container's keys after "size_bytes" (an object)
  std::string text;        ///< the text's line after "Format: "
  const char* list_key;    ///< the JSON key of the rows ("connections") ...
  const char* list_title;  ///< ... and the text's ("Connections")
  std::vector<TopicRow> rows;
};

/// `info` of the bag read by `reader` (named `name`, `size` bytes) of container `c`: the
/// container's part, then the summary `s`'s.
SonarFileInfo bag_info(const ContainerInfo& c, const std::string& name, std::uint64_t size,
                       const PingStream& bag, const BagSummary& s, std::size_t max_anomalies);

/// A bag format's SonarFormat::info: `info` of the bag `path` read by a BagReader, its container
/// described by `describe(reader)`.
template <class BagReader, ContainerInfo (*describe)(const BagReader&)>
SonarFileInfo bag_file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  BagReader reader(path);
  const PingStream bag = ping_stream(reader);
  const BagSummary s = summarise(bag);
  return bag_info(describe(reader), reader.name(), reader.file_size(), bag, s, max_anomalies);
}

/// The XTF writer's options from the first image's settings; `note` names the source file.
xtf::WriterOptions xtf_options(const std::optional<ImageInfo>& image_info, std::string note,
                               bool overwrite);
/// Writes every ping with a position (and the Imu messages no ping took, as attitude packets)
/// to `writer`, counting in `r`; `what` names a ping's place in warnings ("bag message").
/// Throws FormatError if no ping is written.
void write_xtf(const PingStream& bag, xtf::Writer& writer, std::string_view what,
               const std::filesystem::path& in, ConvertResult& r);

/// Bag -> XTF for a bag reader of the format `from`: the XTF options from the first image, the
/// file note "converted by sonarsynth from the <container> <file name>", every ping through
/// write_xtf (`what` as there).
template <class BagReader>
ConvertResult bag_to_xtf(const SonarFormat& from, std::string_view container, std::string_view what,
                         const std::filesystem::path& in, const std::filesystem::path& out,
                         bool overwrite) {
  ConvertResult r;
  r.from = &from;
  r.to = &xtf::sonar_format();
  BagReader reader(in);
  xtf::Writer writer(out, xtf_options(reader.image_info(),
                                      "converted by sonarsynth from the " + std::string(container) +
                                          " " + in.filename().string(),
                                      overwrite));
  write_xtf(ping_stream(reader), writer, what, in, r);
  return r;
}

using ConvertFunction = ConvertResult (*)(const std::filesystem::path& in,
                                          const std::filesystem::path& out, bool overwrite,
                                          AltitudeSource altitude_source);
/// The conversion to JSF: `to_xtf` into an XTF file beside the output (removed afterwards),
/// then XTF -> JSF; the drops, repairs and warnings of both.
ConvertResult via_xtf_to_jsf(ConvertFunction to_xtf, const SonarFormat& from,
                             const std::filesystem::path& in, const std::filesystem::path& out,
                             bool overwrite, AltitudeSource altitude_source);
/// A bag format's (`format()`'s) conversion to JSF: its conversion to XTF `to_xtf` into a
/// temporary XTF file beside `out`, then xtf_to_jsf() (via_xtf_to_jsf).
template <ConvertFunction to_xtf, const SonarFormat& (*format)()>
ConvertResult bag_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                         bool overwrite, AltitudeSource altitude_source) {
  return via_xtf_to_jsf(to_xtf, format(), in, out, overwrite, altitude_source);
}

}  // namespace sonarsynth::rosbag
