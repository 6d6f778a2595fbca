// SPDX-License-Identifier: MIT
// `sonarsynth info FILE.xtf [--json]`: what is in an XTF file, like gdalinfo.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "sonarsynth/formats/json_text.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"

namespace sonarsynth::cli {
namespace {

namespace xtf = sonarsynth::xtf;

std::string json_range(const xtf::ValueRange& r) {
  if (r.count == 0) return "null";
  return "{\"min\": " + json::number(r.min) + ", \"max\": " + json::number(r.max) + "}";
}

std::string text_range(const xtf::ValueRange& r, int precision = 3) {
  if (r.count == 0) return "(none)";
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(precision);
  os << r.min << " .. " << r.max;
  return os.str();
}

const char* channel_type_name(std::uint8_t t) {
  switch (t) {
    case 0:
      return "SUBBOTTOM";
    case 1:
      return "PORT";
    case 2:
      return "STBD";
    case 3:
      return "BATHYMETRY";
    default:
      return "UNKNOWN";
  }
}

void print_json(const xtf::FileSummary& s, std::ostream& os) {
  const xtf::XtfFileHeader& h = s.header;
  os << "{\n  \"file\": " << json::string_literal(s.name) << ",\n  \"size_bytes\": " << s.file_size
     << ",\n  \"header\": {\"FileFormat\": " << int{h.FileFormat}
     << ", \"SystemType\": " << int{h.SystemType} << ", \"RecordingProgramName\": "
     << json::string_literal(xtf::to_string(h.RecordingProgramName))
     << ", \"RecordingProgramVersion\": "
     << json::string_literal(xtf::to_string(h.RecordingProgramVersion))
     << ", \"SonarName\": " << json::string_literal(xtf::to_string(h.SonarName))
     << ", \"SonarType\": " << h.SonarType
     << ", \"NoteString\": " << json::string_literal(xtf::to_string(h.NoteString))
     << ", \"ThisFileName\": " << json::string_literal(xtf::to_string(h.ThisFileName))
     << ", \"NavUnits\": " << h.NavUnits
     << ", \"NumberOfSonarChannels\": " << h.NumberOfSonarChannels
     << ", \"NumberOfBathymetryChannels\": " << h.NumberOfBathymetryChannels << "},\n";
  os << "  \"chan_info\": [";
  for (std::size_t i = 0; i < s.chan_info.size(); ++i) {
    const xtf::XtfChanInfo& c = s.chan_info[i];
    os << (i ? ",\n    " : "\n    ") << "{\"index\": " << i
       << ", \"TypeOfChannel\": " << int{c.TypeOfChannel}
       << ", \"type\": " << json::string_literal(channel_type_name(c.TypeOfChannel))
       << ", \"SubChannelNumber\": " << int{c.SubChannelNumber}
       << ", \"CorrectionFlags\": " << c.CorrectionFlags << ", \"UniPolar\": " << c.UniPolar
       << ", \"BytesPerSample\": " << c.BytesPerSample
       << ", \"SampleFormat\": " << int{c.SampleFormat} << ", \"Reserved\": " << c.Reserved
       << ", \"ChannelName\": " << json::string_literal(xtf::to_string(c.ChannelName))
       << ", \"Frequency\": " << json::number(c.Frequency) << "}";
  }
  os << "\n  ],\n  \"packet_counts\": {";
  bool first = true;
  for (const auto& [type, count] : s.packet_counts) {
    os << (first ? "" : ", ") << json::string_literal(std::to_string(type))
       << ": {\"name\": " << json::string_literal(xtf::header_type_name(type))
       << ", \"count\": " << count << "}";
    first = false;
  }
  os << "},\n  \"pings\": " << s.pings
     << ",\n  \"pings_with_valid_navigation\": " << s.pings_with_valid_nav
     << ",\n  \"channels\": [";
  first = true;
  for (const auto& [number, c] : s.channels) {
    os << (first ? "\n    " : ",\n    ") << "{\"ChannelNumber\": " << number
       << ", \"type\": " << json::string_literal(channel_type_name(c.type_of_channel))
       << ", \"pings\": " << c.pings << ", \"samples\": " << json_range(c.samples)
       << ", \"slant_range_m\": " << json_range(c.slant_range_m) << "}";
    first = false;
  }
  os << "\n  ],\n  \"time\": {\"first\": "
     << (s.first_time ? json::string_literal(xtf::iso8601(*s.first_time)) : "null")
     << ", \"last\": " << (s.last_time ? json::string_literal(xtf::iso8601(*s.last_time)) : "null")
     << ", \"duration_s\": "
     << (s.first_time
             ? json::number(std::chrono::duration<double>(*s.last_time - *s.first_time).count())
             : "null")
     << "},\n  \"navigation\": {\"units\": "
     << json::string_literal(h.NavUnits == 3 ? "degrees" : (h.NavUnits == 0 ? "metres" : "unknown"))
     << ", \"x\": " << json_range(s.sensor_x) << ", \"y\": " << json_range(s.sensor_y)
     << ", \"pings_without_position\": " << s.pings - s.pings_with_valid_nav
     << "},\n  \"ping_attitude\": {\"heading_deg\": " << json_range(s.heading_deg)
     << ", \"pitch_deg\": " << json_range(s.pitch_deg)
     << ", \"roll_deg\": " << json_range(s.roll_deg) << ", \"heave_m\": " << json_range(s.heave_m)
     << ", \"altitude_m\": " << json_range(s.altitude_m)
     << ", \"depth_m\": " << json_range(s.depth_m)
     << ", \"SoundVelocity\": " << json_range(s.sound_velocity)
     << "},\n  \"attitude_packets\": {\"heading_deg\": " << json_range(s.attitude_heading_deg)
     << ", \"pitch_deg\": " << json_range(s.attitude_pitch_deg)
     << ", \"roll_deg\": " << json_range(s.attitude_roll_deg) << "},\n  \"anomaly_counts\": {";
  for (std::size_t k = 0; k < xtf::kAnomalyKindCount; ++k) {
    os << (k ? ", " : "")
       << json::string_literal(xtf::anomaly_kind_name(static_cast<xtf::AnomalyKind>(k))) << ": "
       << s.anomaly_counts[k];
  }
  os << "},\n  \"anomalies\": [";
  for (std::size_t i = 0; i < s.anomalies.size(); ++i) {
    const xtf::Anomaly& a = s.anomalies[i];
    os << (i ? ",\n    " : "\n    ")
       << "{\"kind\": " << json::string_literal(xtf::anomaly_kind_name(a.kind))
       << ", \"offset\": " << a.offset << ", \"packet\": " << a.packet_index
       << ", \"message\": " << json::string_literal(a.message) << "}";
  }
  os << (s.anomalies.empty() ? "]\n}\n" : "\n  ]\n}\n");
}

void print_text(const xtf::FileSummary& s, std::size_t max_anomalies, std::ostream& os) {
  const xtf::XtfFileHeader& h = s.header;
  os << "File: " << s.name << " (" << s.file_size << " bytes)\n"
     << "Format: XTF, FileFormat " << int{h.FileFormat} << ", SystemType " << int{h.SystemType}
     << "\nRecording program: " << xtf::to_string(h.RecordingProgramName) << " "
     << xtf::to_string(h.RecordingProgramVersion) << "\nSonar: " << xtf::to_string(h.SonarName)
     << " (SonarType " << h.SonarType << ")\n";
  if (h.NoteString[0] != '\0') os << "Note: " << xtf::to_string(h.NoteString) << "\n";
  os << "NavUnits: " << h.NavUnits
     << (h.NavUnits == 3 ? " (latitude/longitude, degrees)"
                         : (h.NavUnits == 0 ? " (metres)" : " (unknown)"))
     << "\nChannels: " << h.NumberOfSonarChannels << " sonar, " << h.NumberOfBathymetryChannels
     << " bathymetry\n";
  for (std::size_t i = 0; i < s.chan_info.size(); ++i) {
    const xtf::XtfChanInfo& c = s.chan_info[i];
    if (c.BytesPerSample == 0 && c.TypeOfChannel == 0 && c.SampleFormat == 0) continue;
    os << "  ChanInfo[" << i << "]: " << channel_type_name(c.TypeOfChannel) << " \""
       << xtf::to_string(c.ChannelName) << "\", " << c.BytesPerSample
       << " bytes/sample, SampleFormat " << int{c.SampleFormat} << ", UniPolar " << c.UniPolar
       << ", CorrectionFlags " << c.CorrectionFlags << ", Frequency " << c.Frequency << "\n";
  }
  os << "Packets:\n";
  for (const auto& [type, count] : s.packet_counts) {
    os << "  " << xtf::header_type_name(type) << " (" << int{type} << "): " << count << "\n";
  }
  os << "Sonar pings: " << s.pings << "\n";
  for (const auto& [number, c] : s.channels) {
    os << "  channel " << number << " (" << channel_type_name(c.type_of_channel) << "): " << c.pings
       << " pings, samples " << text_range(c.samples, 0) << ", slant range "
       << text_range(c.slant_range_m, 2) << " m\n";
  }
  if (s.first_time) {
    os << "Time: " << xtf::iso8601(*s.first_time) << " .. " << xtf::iso8601(*s.last_time) << "\n";
  } else {
    os << "Time: (no valid ping time)\n";
  }
  const int p = h.NavUnits == 3 ? 6 : 2;
  os << "Navigation (sensor, " << (h.NavUnits == 3 ? "degrees" : "file units") << "): X "
     << text_range(s.sensor_x, p) << ", Y " << text_range(s.sensor_y, p) << " ("
     << s.pings - s.pings_with_valid_nav << " pings without a position)\n"
     << "Attitude (ping headers, deg): heading " << text_range(s.heading_deg, 2) << ", pitch "
     << text_range(s.pitch_deg, 2) << ", roll " << text_range(s.roll_deg, 2) << "\n"
     << "Altitude " << text_range(s.altitude_m, 2) << " m, depth " << text_range(s.depth_m, 2)
     << " m, SoundVelocity " << text_range(s.sound_velocity, 1) << " m/s\n";
  if (s.attitude_heading_deg.count > 0) {
    os << "Attitude packets (deg): heading " << text_range(s.attitude_heading_deg, 2) << ", pitch "
       << text_range(s.attitude_pitch_deg, 2) << ", roll " << text_range(s.attitude_roll_deg, 2)
       << "\n";
  }
  std::uint64_t total = 0;
  for (auto c : s.anomaly_counts) total += c;
  os << "Anomalies: " << (total == 0 ? "none" : std::to_string(total)) << "\n";
  for (std::size_t k = 0; k < xtf::kAnomalyKindCount; ++k) {
    if (s.anomaly_counts[k] == 0) continue;
    os << "  " << xtf::anomaly_kind_name(static_cast<xtf::AnomalyKind>(k)) << ": "
       << s.anomaly_counts[k] << "\n";
  }
  for (std::size_t i = 0; i < s.anomalies.size() && i < max_anomalies; ++i) {
    os << "  - " << s.anomalies[i].message << "\n";
  }
  if (s.anomalies.size() > max_anomalies) {
    os << "  ... (" << s.anomalies.size() - max_anomalies << " more; see --json)\n";
  }
}

}  // namespace

int run_info(const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string input;
  std::size_t max_anomalies = 20;
  options.add_options()("input,i", po::value<std::string>(&input)->required(), "XTF file")(
      "json", "print JSON instead of text")(
      "max-anomalies", po::value<std::size_t>(&max_anomalies)->default_value(20),
      "anomaly messages listed in the text output");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map vm;
  if (!parse(args, options, positional, vm,
             "usage: sonarsynth info FILE.xtf [--json]\n"
             "Reports an XTF file's header, channels, packet counts, pings, time span, navigation "
             "extent, attitude ranges and anomalies.")) {
    return 0;
  }
  const xtf::FileSummary s = xtf::summarize_file(input);
  if (vm.count("json")) {
    print_json(s, std::cout);
  } else {
    print_text(s, max_anomalies, std::cout);
  }
  return 0;
}

}  // namespace sonarsynth::cli
