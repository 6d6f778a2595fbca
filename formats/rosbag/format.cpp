// SPDX-License-Identifier: MIT
// The ROS 1 bag format's descriptor, `simulate` writer, XTF -> bag conversion and its read side:
// the SideScanSource, `info`, and the bag -> XTF and bag -> JSF conversions (docs/rosbag.md,
// docs/architecture.md "Adding a sonar format").
#include "sonarsynth/formats/rosbag/format.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/rosbag/message_bytes.hpp"
#include "sonarsynth/formats/rosbag/read_common.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"
#include "sonarsynth/formats/rosbag/write_common.hpp"
#include "sonarsynth/formats/rosbag/writer.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::rosbag {
namespace {

std::unique_ptr<SurveyFileSink> create_survey_writer(const SurveyWriterContext& c) {
  WriterOptions o = simulation_writer_options(*c.sonar, c.sample_format);
  o.overwrite = true;  // inside the run's own fresh temporary directory
  return std::make_unique<BagSurveyWriter<Writer, WriterOptions>>(c, std::move(o), ".bag");
}

// Per ping: two image messages (record header ~60 bytes, message ~110 bytes plus the samples),
// a NavSatFix (~150) and an Imu (~380) with their index entries (12 bytes each); per line the
// 4 KiB bag header, the definitions (~8 KiB, twice) and the transforms.
double estimated_bytes(const SonarConfig& sonar, const std::string& sample_format, double pings,
                       std::size_t lines) {
  const double bps = sample_format == "u8" ? 1.0 : (sample_format == "f32" ? 4.0 : 2.0);
  const double samples = static_cast<double>(sonar.samples_per_channel);
  return pings * (2.0 * (200.0 + bps * samples) + 800.0) +
         static_cast<double>(lines) * (4096.0 + 24000.0);
}

/// A finite XTF CHANINFO angle in degrees as radians, or 0 (unknown) outside [0, max_deg].
double angle_or_unknown(float deg, double max_deg) {
  const double d = static_cast<double>(deg);
  return d > 0.0 && d <= max_deg ? rad_from_deg(d) : 0.0;
}

WriterOptions conversion_options(const xtf::Reader& reader, bool overwrite) {
  WriterOptions o;
  o.overwrite = overwrite;
  o.u16_full_range = true;
  if (reader.chan_info().empty()) return o;
  const xtf::XtfChanInfo& c = reader.chan_info()[0];
  const bool ieee =
      c.SampleFormat == static_cast<std::uint8_t>(xtf::SampleFormatCode::kIeeeFloat32);
  o.sample_format = ieee || c.BytesPerSample == 4 ? "f32" : (c.BytesPerSample == 1 ? "u8" : "u16");
  const double khz = static_cast<double>(c.Frequency);
  o.frequency_hz = std::isfinite(khz) && khz > 0.0 ? khz * 1e3 : 0.0;
  o.horizontal_beam_width_rad = angle_or_unknown(c.HorizBeamAngle, 179.0);
  o.vertical_beam_width_rad = angle_or_unknown(c.BeamWidth, 179.0);
  o.tilt_rad = angle_or_unknown(c.TiltAngle, 90.0);
  return o;
}

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

bool identify(std::span<const std::uint8_t> head) {
  static constexpr char kMagic[] = "#ROSBAG V";
  return head.size() >= sizeof kMagic - 1 &&
         std::memcmp(head.data(), kMagic, sizeof kMagic - 1) == 0;
}

}  // namespace

WriterOptions simulation_writer_options(const SonarConfig& sonar,
                                        const std::string& sample_format) {
  WriterOptions o;
  o.sample_format = sample_format;
  o.frequency_hz = sonar.frequency_hz;
  o.horizontal_beam_width_rad = sonar.horizontal_beam_width_rad;
  o.vertical_beam_width_rad = sonar.vertical_beam.width_3db_full_rad();
  o.tilt_rad = sonar.tilt_rad;
  return o;
}

namespace {

/// Converts an XTF file into a ROS 1 bag (docs/rosbag.md, "Conversion"): every ping with its
/// samples (the XTF's sample type), time, number, position, heading, pitch, roll and sound speed;
/// XTF attitude packets as Imu messages. The bag's messages have no field for altitude, depth,
/// speed or heave: they are not carried, and `altitude_source` has no effect. Pings the bag
/// cannot hold are dropped and counted by reason. Throws FormatError for unreadable input and
/// when no ping is left to write (then no output file is created).
ConvertResult xtf_to_rosbag(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource /*altitude_source*/) {
  return xtf_to_bag<Writer>(
      sonar_format(), "a ROS 1 bag", in, out,
      [overwrite](const xtf::Reader& reader) { return conversion_options(reader, overwrite); });
}

/// Converts a ROS 1 bag into XTF (docs/rosbag.md, "Reading bags"): every ping (the port and
/// starboard images of one header.stamp) with its samples (u8 -> u8, float -> f32, other types
/// -> u16 clamped to 0..32767), time, number, sound speed, slant range, the position of the
/// NavSatFix and the heading, pitch and roll of the Imu at or before it; the other Imu messages
/// as attitude packets. Pings without a position are dropped (XTF's (0, 0) is "no fix").
/// `altitude_source` has no effect. Throws FormatError for unreadable input and when no ping is
/// left to write (then no output file is created).
ConvertResult rosbag_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource /*altitude_source*/) {
  return bag_to_xtf<Reader>(sonar_format(), "ROS 1 bag", "bag message", in, out, overwrite);
}

}  // namespace

const SonarFormat& sonar_format() {
  static const SonarFormat format = reading_and_simulating_format(
      "rosbag", "ROS 1 bag",
      "ROS 1 bag, format 2.0 (marine_acoustic_msgs side-scan images, navigation)", {".bag"},
      identify, open_ping_source<Reader, Ping, sonar_format>, bag_file_info<Reader, container>,
      create_survey_writer, estimated_bytes,
      {{"xtf", "rosbag", xtf_to_rosbag},
       {"rosbag", "xtf", rosbag_to_xtf},
       {"rosbag", "jsf", bag_to_jsf<rosbag_to_xtf, sonar_format>}});
  return format;
}

}  // namespace sonarsynth::rosbag
