// SPDX-License-Identifier: MIT
// The MCAP format's descriptor, its `simulate` writer, the XTF -> MCAP conversion and its read
// side: the SideScanSource, `info`, and the MCAP -> XTF and MCAP -> JSF conversions
// (docs/robotics.md, docs/architecture.md "Adding a sonar format").
#include "sonarsynth/formats/mcap/format.hpp"

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/mcap/opcodes.hpp"
#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/mcap/writer.hpp"
#include "sonarsynth/formats/rosbag/read_common.hpp"
#include "sonarsynth/formats/rosbag/write_common.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"

namespace sonarsynth::mcap {
namespace {

std::unique_ptr<SurveyFileSink> create_survey_writer(const SurveyWriterContext& c) {
  WriterOptions o;
  o.sample_encoding = xtf_sample_encoding(c.sample_format);
  o.frequency_hz = c.sonar->frequency_hz;
  o.horizontal_beam_width_rad = c.sonar->horizontal_beam_width_rad;
  o.vertical_beam_width_rad = c.sonar->vertical_beam.width_3db_full_rad();
  o.tilt_rad = c.sonar->tilt_rad;
  o.overwrite = true;  // inside the run's own fresh temporary directory
  o.truth = c.bag_truth;
  return std::make_unique<rosbag::BagSurveyWriter<Writer, WriterOptions>>(c, o, ".mcap");
}

// Per ping: four Message records (31 bytes each) with their CDR messages (NavSatFix 128 bytes,
// Imu 336, RawSonarImage about 112 + samples), 16 bytes of message index each; zstd never grows
// data by more than its bound (about 1/256). Per line: a fixed 16 KiB for the schemas, the
// summary and the TF message.
double estimated_bytes(const SonarConfig& sonar, const std::string& sample_format, double pings,
                       std::size_t lines) {
  const double bytes_per_sample = sample_format == "f32" ? 4.0 : sample_format == "u8" ? 1.0 : 2.0;
  const double samples = static_cast<double>(sonar.samples_per_channel);
  const double ping =
      4.0 * (31.0 + 16.0) + 128.0 + 336.0 + 2.0 * (160.0 + bytes_per_sample * samples);
  return pings * ping * (1.0 + 1.0 / 128.0) + 16384.0 * static_cast<double>(lines);
}

xtf::SampleEncoding encoding_of(const xtf::Reader& reader) {
  if (reader.chan_info().empty()) return xtf::SampleEncoding::kFloat32;
  const xtf::XtfChanInfo& c = reader.chan_info()[0];
  if (c.UniPolar == 1 && c.BytesPerSample == 2) return xtf::SampleEncoding::kUint16;
  if (c.UniPolar == 1 && c.BytesPerSample == 1) return xtf::SampleEncoding::kUint8;
  return xtf::SampleEncoding::kFloat32;
}

WriterOptions conversion_options(const xtf::Reader& reader, bool overwrite) {
  WriterOptions o;
  o.overwrite = overwrite;
  o.sample_encoding = encoding_of(reader);
  if (!reader.chan_info().empty()) {
    const xtf::XtfChanInfo& c = reader.chan_info()[0];
    if (c.Frequency > 0.0f) o.frequency_hz = 1e3 * c.Frequency;
    const auto angle = [](float deg, double fallback) {
      const double rad = rad_from_deg(deg);
      return rad >= 0.0 && rad < kPi ? rad : fallback;
    };
    o.horizontal_beam_width_rad = angle(c.HorizBeamAngle, o.horizontal_beam_width_rad);
    o.vertical_beam_width_rad = angle(c.BeamWidth, o.vertical_beam_width_rad);
    o.tilt_rad = angle(c.TiltAngle, o.tilt_rad);
  }
  return o;
}

using rosbag::bag_to_xtf;
using rosbag::ContainerInfo;
using rosbag::read_as;

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

bool identify(std::span<const std::uint8_t> head) {
  return head.size() >= kMagic.size() &&
         std::memcmp(head.data(), kMagic.data(), kMagic.size()) == 0;
}

/// Converts an XTF file into a ROS 2 bag (docs/robotics.md, "convert"): every ping the reader
/// gives, its samples in the XTF file's own sample type (16- or 8-bit unsigned integers as
/// uint16/uint8, anything else as float32). Pings the bag cannot hold are dropped and counted by
/// reason. Throws FormatError for unreadable input and when no ping is left (then no output file
/// is created). `altitude_source` is not used: the bag's messages carry no altitude.
ConvertResult xtf_to_mcap(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource /*altitude_source*/) {
  return rosbag::xtf_to_bag<Writer>(
      sonar_format(), "MCAP", in, out,
      [overwrite](const xtf::Reader& reader) { return conversion_options(reader, overwrite); });
}

/// Converts a ROS 2 bag into XTF (docs/robotics.md, "Reading bags"): every ping (the port and
/// starboard RawSonarImage of one header.stamp) with its samples (uint8 -> u8, float -> f32,
/// other types -> u16 clamped to 0..32767), time, sound speed, slant range, the position of the
/// NavSatFix and the heading, pitch and roll of the Imu at or before it, the port image's
/// Message sequence as ping number; the other Imu messages as attitude packets. Pings without a
/// position are dropped (XTF's (0, 0) is "no fix"). `altitude_source` has no effect. Throws
/// FormatError for unreadable input and when no ping is left to write (then no output file is
/// created).
ConvertResult mcap_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                          bool overwrite, AltitudeSource /*altitude_source*/) {
  return bag_to_xtf<Reader>(sonar_format(), "MCAP file", "MCAP chunk (or message)", in, out,
                            overwrite);
}

}  // namespace

const SonarFormat& sonar_format() {
  static const SonarFormat format = reading_and_simulating_format(
      "mcap", "MCAP", "ROS 2 bag in MCAP, a RawSonarImage per side (docs/robotics.md)", {".mcap"},
      identify, open_ping_source<Reader, rosbag::Ping, sonar_format>,
      rosbag::bag_file_info<Reader, container>, create_survey_writer, estimated_bytes,
      {{"xtf", "mcap", xtf_to_mcap},
       {"mcap", "xtf", mcap_to_xtf},
       {"mcap", "jsf", rosbag::bag_to_jsf<mcap_to_xtf, sonar_format>}});
  return format;
}

}  // namespace sonarsynth::mcap
