// SPDX-License-Identifier: MIT
// Helpers of the formats' `info` summaries (formats/xtf/info.cpp, formats/jsf/info.cpp).
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "sonarsynth/formats/xtf/summary.hpp"

namespace sonarsynth::info {

using Json = nlohmann::ordered_json;  // keys in the order written

inline Json json_range(const xtf::ValueRange& r) {
  if (r.count == 0) return nullptr;
  return {{"min", r.min}, {"max", r.max}};
}

/// Text from a file (any bytes) as JSON: each byte one character (ISO 8859-1), so that every
/// byte is kept and the output is valid UTF-8 (printed as \u00XX escapes: ASCII output).
inline std::string file_text(const std::string& bytes) {
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

inline std::string text_range(const xtf::ValueRange& r, int precision = 3) {
  if (r.count == 0) return "(none)";
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(precision);
  os << r.min << " .. " << r.max;
  return os.str();
}

/// "file", "format" and "size_bytes", the first keys of every summary.
inline Json file_json(const std::string& name, const char* format, std::uint64_t file_size) {
  Json j;
  j["file"] = file_text(name);
  j["format"] = format;
  j["size_bytes"] = file_size;
  return j;
}

/// "time": the first and last valid ping times and the seconds between (null where unknown).
inline Json time_json(const std::optional<UtcTime>& first, const std::optional<UtcTime>& last) {
  Json time = {{"first", nullptr}, {"last", nullptr}, {"duration_s", nullptr}};
  if (first) time["first"] = xtf::iso8601(*first);
  if (last) time["last"] = xtf::iso8601(*last);
  if (first && last) time["duration_s"] = std::chrono::duration<double>(*last - *first).count();
  return time;
}

/// "ping_attitude": the ranges of a summary's ping attitude and geometry; the sound speed under
/// the name the format gives it.
template <class Summary>
Json ping_attitude_json(const Summary& s, const char* sound_speed_key,
                        const xtf::ValueRange& sound_speed) {
  return {{"heading_deg", json_range(s.heading_deg)},
          {"pitch_deg", json_range(s.pitch_deg)},
          {"roll_deg", json_range(s.roll_deg)},
          {"heave_m", json_range(s.heave_m)},
          {"altitude_m", json_range(s.altitude_m)},
          {"pings_without_altitude", s.pings_without_altitude},
          {"depth_m", json_range(s.depth_m)},
          {sound_speed_key, json_range(sound_speed)}};
}

/// "anomaly_counts" (every kind, by name) and "anomalies" (each with its index under
/// `index_key`) of a summary; `anomaly_kind_name` is the format's, found by the kind's type.
template <class Summary, class Index>
void add_anomalies_json(Json& j, const Summary& s, const char* index_key, Index index) {
  using Kind = decltype(s.anomalies.front().kind);
  Json counts = Json::object();
  for (std::size_t k = 0; k < s.anomaly_counts.size(); ++k) {
    counts[anomaly_kind_name(static_cast<Kind>(k))] = s.anomaly_counts[k];
  }
  j["anomaly_counts"] = std::move(counts);
  Json anomalies = Json::array();
  for (const auto& a : s.anomalies) {
    anomalies.push_back({{"kind", anomaly_kind_name(a.kind)},
                         {"offset", a.offset},
                         {index_key, a.*index},
                         {"message", file_text(a.message)}});
  }
  j["anomalies"] = std::move(anomalies);
}

/// "heading h0 .. h1, pitch p0 .. p1, roll r0 .. r1" in degrees.
inline std::string attitude_text(const xtf::ValueRange& heading, const xtf::ValueRange& pitch,
                                 const xtf::ValueRange& roll) {
  return "heading " + text_range(heading, 2) + ", pitch " + text_range(pitch, 2) + ", roll " +
         text_range(roll, 2);
}

/// "Anomalies: N" (N counting `extra_count` too), `extra_line` if N has some, one line per
/// anomaly kind found ("  name: count"), then the first `max_anomalies` messages.
template <class Summary>
void anomaly_lines(std::ostream& os, const Summary& s, std::size_t max_anomalies,
                   std::uint64_t extra_count = 0, const std::string& extra_line = {}) {
  std::uint64_t total = extra_count;
  for (auto c : s.anomaly_counts) total += c;
  os << "Anomalies: " << (total == 0 ? "none" : std::to_string(total)) << "\n";
  if (extra_count > 0) os << extra_line;
  using Kind = decltype(s.anomalies.front().kind);
  for (std::size_t k = 0; k < s.anomaly_counts.size(); ++k) {
    if (s.anomaly_counts[k] == 0) continue;
    os << "  " << anomaly_kind_name(static_cast<Kind>(k)) << ": " << s.anomaly_counts[k] << "\n";
  }
  for (std::size_t i = 0; i < s.anomalies.size() && i < max_anomalies; ++i) {
    os << "  - " << s.anomalies[i].message << "\n";
  }
}

}  // namespace sonarsynth::info
