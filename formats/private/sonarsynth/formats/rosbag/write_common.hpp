// SPDX-License-Identifier: MIT
// What the ROS 1 bag format (formats/rosbag/format.cpp) and the MCAP format
// (formats/mcap/format.cpp) share on their write side: the `simulate` writer of one bag per
// survey line and the XTF -> bag conversion (docs/rosbag.md and docs/robotics.md).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/convert_result.hpp"
#include "sonarsynth/formats/io/sonar_format.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/survey_writer.hpp"

namespace sonarsynth::rosbag {

/// One bag per survey line (`<dir>/<line name><extension>`), the same pings as the XTF of the
/// run (to_xtf_ping), so that both agree sample for sample; with output.bag_truth each ping's
/// truth on the truth topics.
template <class BagWriter, class BagWriterOptions>
class BagSurveyWriter : public LineFileWriter<BagWriter, BagWriterOptions> {
 public:
  BagSurveyWriter(const SurveyWriterContext& c, BagWriterOptions o, std::string extension)
      : LineFileWriter<BagWriter, BagWriterOptions>(c.dir, c.line_names, *c.frame, *c.sonar,
                                                    std::move(o), std::move(extension)),
        truth_(c.bag_truth) {}

 private:
  void after_ping(BagWriter& w, const SonarPing& written, const RenderedPing& p) override {
    if (truth_) w.write_truth(written, p.port, p.starboard);
  }
  bool truth_;
};

/// XTF -> bag into the format `to` (`container` names it in the drop reason "not storable in
/// <container>"): a BagWriter with the options `options_of(reader)`, the XTF's attitude packets
/// as Imu messages, every ping with a valid time (without a navigation fix in geographic
/// coordinates: NavSatFix STATUS_NO_FIX). Throws FormatError if no ping is written.
template <class BagWriter, class OptionsOf>
ConvertResult xtf_to_bag(const SonarFormat& to, std::string_view container,
                         const std::filesystem::path& in, const std::filesystem::path& out,
                         OptionsOf options_of) {
  ConvertResult r;
  r.from = &xtf::sonar_format();
  r.to = &to;
  xtf::Reader reader(in);
  BagWriter writer(out, options_of(reader));
  xtf::Packet packet;
  while (xtf::next_ping_copying_attitude(reader, packet, writer, r)) {
    SonarPing& s = packet.ping.sonar;
    if (!packet.ping.nav_valid || reader.file_header().NavUnits != 3) {
      s.sensor_position = {};  // no position: NavSatFix STATUS_NO_FIX
    }
    const std::string reason = !packet.ping.time_valid ? "no valid time" : "";
    try {
      if (!reason.empty()) throw InputError(reason);
      writer.write_ping(s);
      ++r.pings;
    } catch (const InputError& e) {
      ++r.pings_skipped;
      ++r.dropped[reason.empty() ? "not storable in " + std::string(container) : reason];
      r.warn("XTF packet " + std::to_string(packet.index) + " (ping " +
             std::to_string(s.ping_number) + ") dropped: " + e.what());
    }
  }
  r.reader_anomalies = reader.total_anomalies();
  for (const xtf::Anomaly& a : reader.anomalies()) r.warn(a.message);
  if (r.pings == 0) {
    throw FormatError("convert: " + in.string() + ": no ping to write (" +
                      std::to_string(r.pings_skipped) + " dropped)");
  }
  writer.close();
  return r;
}

}  // namespace sonarsynth::rosbag
