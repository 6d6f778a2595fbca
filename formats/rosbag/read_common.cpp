// SPDX-License-Identifier: MIT
// The bag formats' shared read side (formats/private/sonarsynth/formats/rosbag/read_common.hpp):
// `info`'s summary and the bag -> XTF and bag -> JSF conversions (docs/rosbag.md and
// docs/robotics.md, "Reading bags").
#include "sonarsynth/formats/rosbag/read_common.hpp"

#include <chrono>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::rosbag {
namespace {

void note(ConvertResult& r, std::string w) {
  if (r.warnings.size() < 10) r.warnings.push_back(std::move(w));
}

}  // namespace

const char* read_as(bool decoded, std::string_view type) {
  if (!decoded) return nullptr;
  if (type.find("NavSatFix") != std::string_view::npos) return "navigation";
  if (type.find("Imu") != std::string_view::npos) return "attitude";
  if (type.find("TFMessage") != std::string_view::npos) return "sonar tilt";
  return "side-scan images";
}

BagSummary summarise(const PingStream& bag) {
  BagSummary s;
  Ping p;
  while (bag.next_ping(p)) {
    ++s.pings;
    s.samples.add(static_cast<double>(p.sonar.port.size()));
    s.samples.add(static_cast<double>(p.sonar.starboard.size()));
    s.slant_range_m.add(p.sonar.slant_range_m);
    s.sound_speed_m_s.add(p.sonar.sound_speed_m_s);
    if (p.nav_valid) {
      ++s.nav;
      s.lat_deg.add(deg_from_rad(p.sonar.sensor_position.lat_rad));
      s.lon_deg.add(deg_from_rad(p.sonar.sensor_position.lon_rad));
    }
    if (p.attitude_valid) {
      ++s.attitude;
      s.heading_deg.add(deg_from_rad(p.sonar.heading_true_rad));
      s.pitch_deg.add(deg_from_rad(p.sonar.pitch_rad));
      s.roll_deg.add(deg_from_rad(p.sonar.roll_rad));
    }
    if (!s.first || p.sonar.time_utc < *s.first) s.first = p.sonar.time_utc;
    if (!s.last || p.sonar.time_utc > *s.last) s.last = p.sonar.time_utc;
  }
  return s;
}

void add_summary_json(info::Json& j, const BagSummary& s,
                      const std::optional<ImageInfo>& image_info,
                      const std::vector<Anomaly>& anomalies, std::uint64_t total_anomalies) {
  using info::Json;
  using info::json_range;
  j["sonar"] = nullptr;  // of the first image and /tf_static; 0 = not in the bag
  if (const auto& ii = image_info) {
    j["sonar"] = {{"frequency_hz", ii->frequency_hz},
                  {"horizontal_beam_width_deg", deg_from_rad(ii->horizontal_beam_width_rad)},
                  {"vertical_beam_width_deg", deg_from_rad(ii->vertical_beam_width_rad)},
                  {"tilt_deg", deg_from_rad(ii->tilt_rad)},
                  {"dtype", ii->dtype}};
  }
  j["pings"] = s.pings;
  j["pings_with_valid_navigation"] = s.nav;
  j["pings_with_attitude"] = s.attitude;
  j["samples"] = json_range(s.samples);
  j["slant_range_m"] = json_range(s.slant_range_m);
  j["sound_speed_m_s"] = json_range(s.sound_speed_m_s);
  Json time = {{"first", nullptr}, {"last", nullptr}, {"duration_s", nullptr}};
  if (s.first) time["first"] = xtf::iso8601(*s.first);
  if (s.last) time["last"] = xtf::iso8601(*s.last);
  if (s.first && s.last) {
    time["duration_s"] = std::chrono::duration<double>(*s.last - *s.first).count();
  }
  j["time"] = std::move(time);
  j["navigation"] = {{"units", "degrees"},
                     {"longitude", json_range(s.lon_deg)},
                     {"latitude", json_range(s.lat_deg)},
                     {"pings_without_position", s.pings - s.nav}};
  j["ping_attitude"] = {{"heading_deg", json_range(s.heading_deg)},
                        {"pitch_deg", json_range(s.pitch_deg)},
                        {"roll_deg", json_range(s.roll_deg)}};
  j["anomaly_count"] = total_anomalies;
  Json list = Json::array();
  for (const Anomaly& a : anomalies) {
    list.push_back({{"offset", a.offset}, {"message", info::file_text(a.message)}});
  }
  j["anomalies"] = std::move(list);
}

void summary_text(std::ostream& os, const BagSummary& s, const std::optional<ImageInfo>& image_info,
                  const std::vector<Anomaly>& anomalies, std::uint64_t total_anomalies,
                  std::size_t max_anomalies) {
  using info::text_range;
  const auto time_text = [](const std::optional<UtcTime>& t) {
    return t ? xtf::iso8601(*t) : std::string("(none)");
  };
  if (const auto& ii = image_info) {
    os << "Sonar (first image, /tf_static; 0 = unknown): frequency " << ii->frequency_hz / 1e3
       << " kHz, beam widths " << deg_from_rad(ii->horizontal_beam_width_rad) << " x "
       << deg_from_rad(ii->vertical_beam_width_rad) << " deg, tilt " << deg_from_rad(ii->tilt_rad)
       << " deg, dtype " << ii->dtype << "\n";
  }
  os << "Sonar pings: " << s.pings << ", samples " << text_range(s.samples, 0) << ", slant range "
     << text_range(s.slant_range_m, 2) << " m\n"
     << "Time: " << time_text(s.first) << " .. " << time_text(s.last) << "\n"
     << "Navigation (sensor, degrees): longitude " << text_range(s.lon_deg, 6) << ", latitude "
     << text_range(s.lat_deg, 6) << " (" << s.pings - s.nav << " pings without position)\n"
     << "Attitude (degrees): heading " << text_range(s.heading_deg, 2) << ", pitch "
     << text_range(s.pitch_deg, 2) << ", roll " << text_range(s.roll_deg, 2) << " ("
     << s.pings - s.attitude << " pings without)\n"
     << "Anomalies: " << total_anomalies << "\n";
  std::size_t k = 0;
  for (const Anomaly& a : anomalies) {
    if (k++ >= max_anomalies) break;
    os << "  " << a.message << "\n";
  }
}

SonarFileInfo bag_info(const ContainerInfo& c, const std::string& name, std::uint64_t size,
                       const PingStream& bag, const BagSummary& s, std::size_t max_anomalies) {
  using info::Json;
  Json j = info::file_json(name, c.format, size);
  for (const auto& [key, value] : c.keys.items()) j[key] = value;
  Json rows = Json::array();
  std::ostringstream os;
  os << "File: " << name << " (" << size << " bytes)\nFormat: " << c.text << "\n"
     << c.list_title << ":\n";
  for (const TopicRow& r : c.rows) {
    rows.push_back({{"id", r.id},
                    {"topic", info::file_text(r.topic)},
                    {r.type.first, info::file_text(r.type.second)},
                    {r.detail.first, info::file_text(r.detail.second)},
                    {"messages", r.messages},
                    {"read_as", r.read_as ? Json(r.read_as) : Json(nullptr)}});
    os << "  " << r.topic << " (" << r.text << "): " << r.messages << " messages"
       << (r.read_as ? std::string(", read as ") + r.read_as : std::string()) << "\n";
  }
  j[c.list_key] = std::move(rows);
  add_summary_json(j, s, bag.image_info, bag.anomalies, bag.total_anomalies());
  summary_text(os, s, bag.image_info, bag.anomalies, bag.total_anomalies(), max_anomalies);
  return {j.dump(2, ' ', true), os.str()};
}

xtf::WriterOptions xtf_options(const std::optional<ImageInfo>& image_info, std::string note,
                               bool overwrite) {
  xtf::WriterOptions o;
  o.overwrite = overwrite;
  o.note = std::move(note);
  if (o.note.size() > 200) o.note.resize(200);
  if (!image_info) return o;
  const ImageInfo& ii = *image_info;
  o.sample_encoding = ii.dtype == 0   ? xtf::SampleEncoding::kUint8
                      : ii.dtype >= 8 ? xtf::SampleEncoding::kFloat32
                                      : xtf::SampleEncoding::kUint16;
  if (ii.frequency_hz > 0.0 && ii.frequency_hz <= 65535e3) o.frequency_khz = ii.frequency_hz / 1e3;
  const auto width = [](double w) { return w > 0.0 && w < std::numbers::pi ? w : 0.0; };
  o.horizontal_beam_angle_rad = width(ii.horizontal_beam_width_rad);
  o.vertical_beam_width_rad = width(ii.vertical_beam_width_rad);
  if (ii.tilt_rad > 0.0 && ii.tilt_rad <= std::numbers::pi / 2) o.tilt_angle_rad = ii.tilt_rad;
  return o;
}

void write_xtf(const PingStream& bag, xtf::Writer& writer, std::string_view what,
               const std::filesystem::path& in, ConvertResult& r) {
  const bool u16 = !bag.image_info || (bag.image_info->dtype != 0 && bag.image_info->dtype < 8);
  // Imu messages no ping took become XTF attitude packets, before the first later ping.
  const std::vector<ImuSample>& imu = bag.imu;
  std::size_t next_imu = 0;
  const auto flush_attitude = [&](std::uint64_t before_ns) {
    for (; next_imu < imu.size() && imu[next_imu].stamp_ns < before_ns; ++next_imu) {
      if (imu[next_imu].used || !imu[next_imu].known) continue;
      try {
        writer.write_attitude(imu[next_imu].attitude);
        ++r.attitude_records;
      } catch (const InputError& e) {
        note(r, std::string("Imu message skipped: ") + e.what());
      }
    }
  };
  Ping p;
  while (bag.next_ping(p)) {
    const auto us = p.sonar.time_utc.time_since_epoch().count();
    flush_attitude(static_cast<std::uint64_t>(us) * 1000u);
    const std::string where = std::string(what) + " at byte " + std::to_string(p.offset) +
                              " (ping " + std::to_string(p.sonar.ping_number) + ")";
    if (!p.nav_valid) {
      ++r.pings_skipped;
      ++r.dropped["no position"];
      note(r, where + " dropped: no position (no NavSatFix with a fix at or before it)");
      continue;
    }
    if (u16) {
      std::uint64_t high = 0;
      for (const auto* side : {&p.sonar.port, &p.sonar.starboard}) {
        for (const float v : *side) high += v > 32767.0f ? 1u : 0u;
      }
      if (high > 0)
        ++r.repaired["u16 samples above 32767 -> clamped to 32767 (the XTF writer's range)"];
    }
    try {
      writer.write_ping(p.sonar);
      ++r.pings;
    } catch (const InputError& e) {
      ++r.pings_skipped;
      ++r.dropped["not storable in XTF"];
      note(r, where + " dropped: " + e.what());
    }
  }
  flush_attitude(std::numeric_limits<std::uint64_t>::max());
  r.reader_anomalies = bag.total_anomalies();
  for (const Anomaly& a : bag.anomalies) note(r, a.message);
  if (r.pings == 0) {
    throw FormatError("convert: " + in.string() + ": no ping to write (" +
                      std::to_string(r.pings_skipped) + " dropped)");
  }
  writer.close();
}

ConvertResult via_xtf_to_jsf(ConvertFunction to_xtf, const SonarFormat& from,
                             const std::filesystem::path& in, const std::filesystem::path& out,
                             bool overwrite, AltitudeSource altitude_source) {
  if (!overwrite && std::filesystem::exists(out)) {
    throw FormatError(out.string() + ": already exists (use --overwrite to replace it)");
  }
  // Through an XTF file beside the output, removed afterwards.
  const std::filesystem::path xtf = out.parent_path() / (".~" + out.filename().string() + ".xtf");
  struct Remove {
    const std::filesystem::path& p;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove(p, ec);
    }
  } remove{xtf};
  ConvertResult first = to_xtf(in, xtf, true, altitude_source);
  ConvertResult r = xtf_to_jsf(xtf, out, overwrite, altitude_source);
  r.from = &from;
  r.pings_skipped += first.pings_skipped;
  r.reader_anomalies += first.reader_anomalies;
  for (const auto& [k, v] : first.dropped) r.dropped[k] += v;
  for (const auto& [k, v] : first.repaired) r.repaired[k] += v;
  first.warnings.insert(first.warnings.end(), r.warnings.begin(), r.warnings.end());
  r.warnings = std::move(first.warnings);
  return r;
}

}  // namespace sonarsynth::rosbag
