// SPDX-License-Identifier: MIT
// `sonarsynth info FILE [--json]`: what is in an XTF or JSF file, like gdalinfo.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/summary.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"

namespace sonarsynth::cli {
namespace {

namespace xtf = sonarsynth::xtf;
namespace jsf = sonarsynth::jsf;

using Json = nlohmann::ordered_json;  // keys in the order written

Json json_range(const xtf::ValueRange& r) {
  if (r.count == 0) return nullptr;
  return {{"min", r.min}, {"max", r.max}};
}

/// Text from a file (any bytes) as JSON: each byte one character (ISO 8859-1), so that every
/// byte is kept and the output is valid UTF-8 (printed as \u00XX escapes: ASCII output).
std::string file_text(const std::string& bytes) {
  std::string out;
  for (const char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
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
  Json j;
  j["file"] = file_text(s.name);
  j["format"] = "XTF";
  j["size_bytes"] = s.file_size;
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
    const xtf::XtfChanInfo& c = s.chan_info[i];
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
  Json time = {{"first", nullptr}, {"last", nullptr}, {"duration_s", nullptr}};
  if (s.first_time) time["first"] = xtf::iso8601(*s.first_time);
  if (s.last_time) time["last"] = xtf::iso8601(*s.last_time);
  if (s.first_time && s.last_time) {
    time["duration_s"] = std::chrono::duration<double>(*s.last_time - *s.first_time).count();
  }
  j["time"] = std::move(time);
  j["navigation"] = {
      {"units", h.NavUnits == 3 ? "degrees" : (h.NavUnits == 0 ? "metres" : "unknown")},
      {"x", json_range(s.sensor_x)},
      {"y", json_range(s.sensor_y)},
      {"pings_without_position", s.pings - s.pings_with_valid_nav}};
  j["ping_attitude"] = {{"heading_deg", json_range(s.heading_deg)},
                        {"pitch_deg", json_range(s.pitch_deg)},
                        {"roll_deg", json_range(s.roll_deg)},
                        {"heave_m", json_range(s.heave_m)},
                        {"altitude_m", json_range(s.altitude_m)},
                        {"pings_without_altitude", s.pings_without_altitude},
                        {"depth_m", json_range(s.depth_m)},
                        {"SoundVelocity", json_range(s.sound_velocity)}};
  j["attitude_packets"] = {{"heading_deg", json_range(s.attitude_heading_deg)},
                           {"pitch_deg", json_range(s.attitude_pitch_deg)},
                           {"roll_deg", json_range(s.attitude_roll_deg)}};
  Json anomaly_counts = Json::object();
  for (std::size_t k = 0; k < xtf::kAnomalyKindCount; ++k) {
    anomaly_counts[xtf::anomaly_kind_name(static_cast<xtf::AnomalyKind>(k))] = s.anomaly_counts[k];
  }
  j["anomaly_counts"] = std::move(anomaly_counts);
  Json anomalies = Json::array();
  for (const xtf::Anomaly& a : s.anomalies) {
    anomalies.push_back({{"kind", xtf::anomaly_kind_name(a.kind)},
                         {"offset", a.offset},
                         {"packet", a.packet_index},
                         {"message", file_text(a.message)}});
  }
  j["anomalies"] = std::move(anomalies);
  os << j.dump(2, ' ', true) << "\n";
}

void print_text(const xtf::FileSummary& s, std::size_t max_anomalies, std::ostream& os) {
  const xtf::XtfFileHeader& h = s.header;
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
    const xtf::XtfChanInfo& c = s.chan_info[i];
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
  total += s.pings_without_altitude;
  os << "Anomalies: " << (total == 0 ? "none" : std::to_string(total)) << "\n";
  if (s.pings_without_altitude > 0) {
    os << "  pings_without_altitude: " << s.pings_without_altitude
       << " (SensorPrimaryAltitude 0: no seabed under the sensor)\n";
  }
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

std::string time_text(const std::optional<UtcTime>& t) {
  return t ? xtf::iso8601(*t) : std::string("(none)");
}

Json jsf_json(const jsf::FileSummary& s) {
  Json j;
  j["file"] = file_text(s.name);
  j["format"] = "JSF";
  j["size_bytes"] = s.file_size;
  if (s.system_information) {
    const jsf::SystemInformation& si = *s.system_information;
    j["system_information"] = {{"system_type", si.system_type},
                               {"software_version", si.software_version},
                               {"subsystems", si.subsystems},
                               {"serial_number", si.serial_number}};
  } else {
    j["system_information"] = nullptr;
  }
  Json messages = Json::object();
  for (const auto& [type, count] : s.message_counts) {
    const char* name = jsf::message_type_name(type);
    messages[std::to_string(type)] = {{"name", name ? name : "unknown"}, {"count", count}};
  }
  j["message_counts"] = std::move(messages);
  Json subsystems = Json::array();
  for (const auto& [sub, channels] : s.sonar_counts) {
    Json ch = Json::object();
    std::uint64_t total = 0;
    for (const auto& [c, n] : channels) {
      ch[std::to_string(c)] = n;
      total += n;
    }
    subsystems.push_back({{"subsystem", sub},
                          {"sonar_data_messages", total},
                          {"messages_by_channel", std::move(ch)},
                          {"read_as_pings", int{sub} == s.ping_subsystem}});
  }
  j["subsystems"] = std::move(subsystems);
  j["pings"] = s.pings;
  j["pings_with_valid_navigation"] = s.pings_with_valid_nav;
  j["samples"] = json_range(s.samples);
  j["sample_interval_ns"] = json_range(s.sample_interval_ns);
  j["slant_range_m"] = json_range(s.slant_range_m);
  j["weighting_factor"] = json_range(s.weighting_factor);
  Json time = {{"first", nullptr}, {"last", nullptr}, {"duration_s", nullptr}};
  if (s.first_time) time["first"] = xtf::iso8601(*s.first_time);
  if (s.last_time) time["last"] = xtf::iso8601(*s.last_time);
  if (s.first_time && s.last_time) {
    time["duration_s"] = std::chrono::duration<double>(*s.last_time - *s.first_time).count();
  }
  j["time"] = std::move(time);
  j["navigation"] = {{"units", "degrees"},
                     {"longitude", json_range(s.longitude_deg)},
                     {"latitude", json_range(s.latitude_deg)},
                     {"pings_without_position", s.pings - s.pings_with_valid_nav}};
  j["ping_attitude"] = {{"heading_deg", json_range(s.heading_deg)},
                        {"pitch_deg", json_range(s.pitch_deg)},
                        {"roll_deg", json_range(s.roll_deg)},
                        {"heave_m", json_range(s.heave_m)},
                        {"altitude_m", json_range(s.altitude_m)},
                        {"pings_without_altitude", s.pings_without_altitude},
                        {"depth_m", json_range(s.depth_m)},
                        {"sound_speed_mps", json_range(s.sound_speed_mps)}};
  Json anomaly_counts = Json::object();
  for (std::size_t k = 0; k < jsf::kAnomalyKindCount; ++k) {
    anomaly_counts[jsf::anomaly_kind_name(static_cast<jsf::AnomalyKind>(k))] = s.anomaly_counts[k];
  }
  j["anomaly_counts"] = std::move(anomaly_counts);
  Json anomalies = Json::array();
  for (const jsf::Anomaly& a : s.anomalies) {
    anomalies.push_back({{"kind", jsf::anomaly_kind_name(a.kind)},
                         {"offset", a.offset},
                         {"message_index", a.message_index},
                         {"message", file_text(a.message)}});
  }
  j["anomalies"] = std::move(anomalies);
  return j;
}

void print_jsf_text(const jsf::FileSummary& s, std::size_t max_anomalies, std::ostream& os) {
  os << "File: " << s.name << " (" << s.file_size << " bytes)\nFormat: JSF (EdgeTech)\n";
  if (s.system_information) {
    os << "System: type " << s.system_information->system_type << ", "
       << s.system_information->subsystems << " subsystems\n";
  }
  os << "Messages:\n";
  for (const auto& [type, count] : s.message_counts) {
    const char* name = jsf::message_type_name(type);
    os << "  " << (name ? name : "unknown") << " (" << type << "): " << count << "\n";
  }
  os << "Subsystems (sonar data messages):\n";
  for (const auto& [sub, channels] : s.sonar_counts) {
    os << "  " << int{sub} << ":";
    for (const auto& [c, n] : channels) os << " channel " << int{c} << " x " << n;
    os << (int{sub} == s.ping_subsystem ? " (read as pings)" : "") << "\n";
  }
  os << "Sonar pings: " << s.pings << ", samples " << text_range(s.samples, 0) << ", slant range "
     << text_range(s.slant_range_m, 2) << " m\n"
     << "Time: " << time_text(s.first_time) << " .. " << time_text(s.last_time) << "\n"
     << "Navigation (sensor, degrees): longitude " << text_range(s.longitude_deg, 6)
     << ", latitude " << text_range(s.latitude_deg, 6) << " (" << s.pings - s.pings_with_valid_nav
     << " pings without a position)\n"
     << "Attitude (deg): heading " << text_range(s.heading_deg, 2) << ", pitch "
     << text_range(s.pitch_deg, 2) << ", roll " << text_range(s.roll_deg, 2) << "\n"
     << "Altitude " << text_range(s.altitude_m, 3) << " m, depth " << text_range(s.depth_m, 3)
     << " m, sound speed " << text_range(s.sound_speed_mps, 1) << " m/s\n";
  std::uint64_t total = 0;
  for (auto c : s.anomaly_counts) total += c;
  os << "Anomalies: " << (total == 0 ? "none" : std::to_string(total)) << "\n";
  for (std::size_t k = 0; k < jsf::kAnomalyKindCount; ++k) {
    if (s.anomaly_counts[k] == 0) continue;
    os << "  " << jsf::anomaly_kind_name(static_cast<jsf::AnomalyKind>(k)) << ": "
       << s.anomaly_counts[k] << "\n";
  }
  for (std::size_t i = 0; i < s.anomalies.size() && i < max_anomalies; ++i) {
    os << "  - " << s.anomalies[i].message << "\n";
  }
}

}  // namespace

int run_info(const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string input;
  std::size_t max_anomalies = 20;
  options.add_options()("input,i", po::value<std::string>(&input)->required(),
                        "XTF or JSF file (format from the content)")("json",
                                                                     "print JSON instead of text")(
      "max-anomalies", po::value<std::size_t>(&max_anomalies)->default_value(20),
      "anomaly messages listed in the text output");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map vm;
  if (!parse(args, options, positional, vm,
             "usage: sonarsynth info FILE.xtf|FILE.jsf [--json]\n"
             "Reports an XTF or JSF file's header, channels or subsystems, packet or message "
             "counts, pings, time span, navigation "
             "extent, attitude ranges and anomalies.")) {
    return 0;
  }
  if (detect_sonar_file_format(input) == SonarFileFormat::kJsf) {
    const jsf::FileSummary s = jsf::summarize_file(input);
    if (vm.count("json")) {
      std::cout << jsf_json(s).dump(2, ' ', true) << "\n";
    } else {
      print_jsf_text(s, max_anomalies, std::cout);
    }
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
