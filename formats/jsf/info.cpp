// SPDX-License-Identifier: MIT
// `sonarsynth info` of a JSF file (docs/jsf.md), as JSON and as text.
#include <sstream>
#include <string>

#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/jsf/summary.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"

namespace sonarsynth::jsf {
namespace {

using info::file_text;
using info::Json;
using info::json_range;
using info::text_range;

std::string time_text(const std::optional<UtcTime>& t) {
  return t ? xtf::iso8601(*t) : std::string("(none)");
}

std::string summary_json(const FileSummary& s) {
  Json j = info::file_json(s.name, "JSF", s.file_size);
  if (s.system_information) {
    const SystemInformation& si = *s.system_information;
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
  j["time"] = info::time_json(s.first_time, s.last_time);
  j["navigation"] = {{"units", "degrees"},
                     {"longitude", json_range(s.longitude_deg)},
                     {"latitude", json_range(s.latitude_deg)},
                     {"pings_without_position", s.pings - s.pings_with_valid_nav}};
  j["ping_attitude"] = info::ping_attitude_json(s, "sound_speed_m_s", s.sound_speed_m_s);
  info::add_anomalies_json(j, s, "message_index", &Anomaly::message_index);
  return j.dump(2, ' ', true);
}

std::string summary_text(const FileSummary& s, std::size_t max_anomalies) {
  std::ostringstream os;
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
     << "Attitude (deg): " << info::attitude_text(s.heading_deg, s.pitch_deg, s.roll_deg) << "\n"
     << "Altitude " << text_range(s.altitude_m, 3) << " m, depth " << text_range(s.depth_m, 3)
     << " m, sound speed " << text_range(s.sound_speed_m_s, 1) << " m/s\n";
  info::anomaly_lines(os, s, max_anomalies);
  return os.str();
}

}  // namespace

SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  const FileSummary s = summarize_file(path);
  return {summary_json(s), summary_text(s, max_anomalies)};
}

}  // namespace sonarsynth::jsf
