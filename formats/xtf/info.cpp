// SPDX-License-Identifier: MIT
// `sonarsynth info` of an XTF file (docs/xtf.md), as JSON and as text.
#include <array>
#include <sstream>
#include <string>

#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"

namespace sonarsynth::xtf {
namespace {

using info::file_text;
using info::Json;
using info::json_range;
using info::text_range;

const char* channel_type_name(std::uint8_t t) {
  static constexpr std::array<const char*, 4> kNames = {"SUBBOTTOM", "PORT", "STBD", "BATHYMETRY"};
  return t < kNames.size() ? kNames[t] : "UNKNOWN";
}

std::string summary_json(const FileSummary& s) {
  const XtfFileHeader& h = s.header;
  Json j = info::file_json(s.name, "XTF", s.file_size);
  j["header"] = {
      {"FileFormat", h.FileFormat},
      {"SystemType", h.SystemType},
      {"RecordingProgramName", file_text(sonarsynth::to_string(h.RecordingProgramName))},
      {"RecordingProgramVersion", file_text(sonarsynth::to_string(h.RecordingProgramVersion))},
      {"SonarName", file_text(sonarsynth::to_string(h.SonarName))},
      {"SonarType", h.SonarType},
      {"NoteString", file_text(sonarsynth::to_string(h.NoteString))},
      {"ThisFileName", file_text(sonarsynth::to_string(h.ThisFileName))},
      {"NavUnits", h.NavUnits},
      {"NumberOfSonarChannels", h.NumberOfSonarChannels},
      {"NumberOfBathymetryChannels", h.NumberOfBathymetryChannels}};
  Json chan_info = Json::array();
  for (std::size_t i = 0; i < s.chan_info.size(); ++i) {
    const XtfChanInfo& c = s.chan_info[i];
    chan_info.push_back({{"index", i},
                         {"TypeOfChannel", c.TypeOfChannel},
                         {"type", channel_type_name(c.TypeOfChannel)},
                         {"SubChannelNumber", c.SubChannelNumber},
                         {"CorrectionFlags", c.CorrectionFlags},
                         {"UniPolar", c.UniPolar},
                         {"BytesPerSample", c.BytesPerSample},
                         {"SampleFormat", c.SampleFormat},
                         {"Reserved", c.Reserved},
                         {"ChannelName", file_text(sonarsynth::to_string(c.ChannelName))},
                         {"Frequency", c.Frequency}});
  }
  j["chan_info"] = std::move(chan_info);
  Json packets = Json::object();
  for (const auto& [type, count] : s.packet_counts) {
    packets[std::to_string(type)] = {{"name", xtf::header_type_name(type)}, {"count", count}};
  }
  j["packet_counts"] = std::move(packets);
  j["pings"] = s.pings;
  j["pings_with_valid_navigation"] = s.pings_with_valid_nav;
  Json channels = Json::array();
  for (const auto& [number, c] : s.channels) {
    channels.push_back({{"ChannelNumber", number},
                        {"type", channel_type_name(c.type_of_channel)},
                        {"pings", c.pings},
                        {"samples", json_range(c.samples)},
                        {"slant_range_m", json_range(c.slant_range_m)}});
  }
  j["channels"] = std::move(channels);
  j["time"] = info::time_json(s.first_time, s.last_time);
  j["navigation"] = {
      {"units", h.NavUnits == 3 ? "degrees" : (h.NavUnits == 0 ? "metres" : "unknown")},
      {"x", json_range(s.sensor_x)},
      {"y", json_range(s.sensor_y)},
      {"pings_without_position", s.pings - s.pings_with_valid_nav}};
  j["ping_attitude"] = info::ping_attitude_json(s, "SoundVelocity", s.sound_velocity);
  j["attitude_packets"] = {{"heading_deg", json_range(s.attitude_heading_deg)},
                           {"pitch_deg", json_range(s.attitude_pitch_deg)},
                           {"roll_deg", json_range(s.attitude_roll_deg)}};
  info::add_anomalies_json(j, s, "packet", &Anomaly::packet_index);
  return j.dump(2, ' ', true);
}

std::string summary_text(const FileSummary& s, std::size_t max_anomalies) {
  std::ostringstream os;
  const XtfFileHeader& h = s.header;
  os << "File: " << s.name << " (" << s.file_size << " bytes)\n"
     << "Format: XTF, FileFormat " << int{h.FileFormat} << ", SystemType " << int{h.SystemType}
     << "\nRecording program: " << sonarsynth::to_string(h.RecordingProgramName) << " "
     << sonarsynth::to_string(h.RecordingProgramVersion)
     << "\nSonar: " << sonarsynth::to_string(h.SonarName) << " (SonarType " << h.SonarType << ")\n";
  if (h.NoteString[0] != '\0') os << "Note: " << sonarsynth::to_string(h.NoteString) << "\n";
  os << "NavUnits: " << h.NavUnits
     << (h.NavUnits == 3 ? " (latitude/longitude, degrees)"
                         : (h.NavUnits == 0 ? " (metres)" : " (unknown)"))
     << "\nChannels: " << h.NumberOfSonarChannels << " sonar, " << h.NumberOfBathymetryChannels
     << " bathymetry\n";
  for (std::size_t i = 0; i < s.chan_info.size(); ++i) {
    const XtfChanInfo& c = s.chan_info[i];
    if (c.BytesPerSample == 0 && c.TypeOfChannel == 0 && c.SampleFormat == 0) continue;
    os << "  ChanInfo[" << i << "]: " << channel_type_name(c.TypeOfChannel) << " \""
       << sonarsynth::to_string(c.ChannelName) << "\", " << c.BytesPerSample
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
     << "Attitude (ping headers, deg): "
     << info::attitude_text(s.heading_deg, s.pitch_deg, s.roll_deg) << "\n"
     << "Altitude " << text_range(s.altitude_m, 2) << " m, depth " << text_range(s.depth_m, 2)
     << " m, SoundVelocity " << text_range(s.sound_velocity, 1) << " m/s\n";
  if (s.attitude_heading_deg.count > 0) {
    os << "Attitude packets (deg): "
       << info::attitude_text(s.attitude_heading_deg, s.attitude_pitch_deg, s.attitude_roll_deg)
       << "\n";
  }
  info::anomaly_lines(os, s, max_anomalies, s.pings_without_altitude,
                      "  pings_without_altitude: " + std::to_string(s.pings_without_altitude) +
                          " (SensorPrimaryAltitude 0: no seabed under the sensor)\n");
  if (s.anomalies.size() > max_anomalies) {
    os << "  ... (" << s.anomalies.size() - max_anomalies << " more; see --json)\n";
  }
  return os.str();
}

}  // namespace

SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  const FileSummary s = summarize_file(path);
  return {summary_json(s), summary_text(s, max_anomalies)};
}

}  // namespace sonarsynth::xtf
