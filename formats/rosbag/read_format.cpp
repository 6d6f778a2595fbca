// SPDX-License-Identifier: MIT
// The ROS 1 bag format's read side: its SideScanSource, `info`, and the bag -> XTF and
// bag -> JSF conversions (docs/rosbag.md, "Reading bags").
#include "sonarsynth/formats/rosbag/read_format.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/rosbag/format.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/info_json.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth::rosbag {
namespace {

class RosbagSource : public ReaderSource<Reader> {
 public:
  explicit RosbagSource(const std::filesystem::path& path) : ReaderSource(path, sonar_format()) {}
  bool next(SideScanRecord& r) override {
    if (!reader_.next_ping(ping_)) return false;
    r.sonar = std::move(ping_.sonar);
    r.nav_valid = ping_.nav_valid;
    r.time_valid = true;
    r.layback_m = 0.0;
    r.heading_deg = deg_from_rad(r.sonar.heading_rad);
    r.index = ping_.index;
    return true;
  }

 private:
  Ping ping_;
};

const char* read_as(const ConnectionInfo& c) {
  if (!c.decoded) return nullptr;
  if (c.type == "sensor_msgs/NavSatFix") return "navigation";
  if (c.type == "sensor_msgs/Imu") return "attitude";
  if (c.type == "tf2_msgs/TFMessage") return "sonar tilt";
  return "side-scan images";
}

struct Summary {
  std::uint64_t pings = 0, nav = 0, attitude = 0;
  xtf::ValueRange samples, slant_range_m, sound_speed_m_s, lat_deg, lon_deg, heading_deg, pitch_deg,
      roll_deg;
  std::optional<UtcTime> first, last;
};

Summary summarise(Reader& reader) {
  Summary s;
  Ping p;
  while (reader.next_ping(p)) {
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
      s.heading_deg.add(deg_from_rad(p.sonar.heading_rad));
      s.pitch_deg.add(deg_from_rad(p.sonar.pitch_rad));
      s.roll_deg.add(deg_from_rad(p.sonar.roll_rad));
    }
    if (!s.first || p.sonar.time_utc < *s.first) s.first = p.sonar.time_utc;
    if (!s.last || p.sonar.time_utc > *s.last) s.last = p.sonar.time_utc;
  }
  return s;
}

std::string info_json(const Reader& reader, const Summary& s) {
  using info::Json;
  using info::json_range;
  Json j;
  j["file"] = info::file_text(reader.name());
  j["format"] = "ROS 1 bag";
  j["size_bytes"] = reader.file_size();
  j["version"] = "2.0";
  j["chunks"] = reader.chunk_count();
  Json conns = Json::array();
  for (const ConnectionInfo& c : reader.connections()) {
    const char* as = read_as(c);
    conns.push_back({{"id", c.id},
                     {"topic", info::file_text(c.topic)},
                     {"type", info::file_text(c.type)},
                     {"md5sum", info::file_text(c.md5sum)},
                     {"messages", c.messages},
                     {"read_as", as ? Json(as) : Json(nullptr)}});
  }
  j["connections"] = std::move(conns);
  j["sonar"] = nullptr;  // of the first image and /tf_static; 0 = not in the bag
  if (const auto& ii = reader.image_info()) {
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
  j["anomaly_count"] = reader.total_anomalies();
  Json anomalies = Json::array();
  for (const Anomaly& a : reader.anomalies()) {
    anomalies.push_back({{"offset", a.offset}, {"message", info::file_text(a.message)}});
  }
  j["anomalies"] = std::move(anomalies);
  return j.dump(2, ' ', true);
}

std::string info_text(const Reader& reader, const Summary& s, std::size_t max_anomalies) {
  using info::text_range;
  const auto time_text = [](const std::optional<UtcTime>& t) {
    return t ? xtf::iso8601(*t) : std::string("(none)");
  };
  std::ostringstream os;
  os << "File: " << reader.name() << " (" << reader.file_size() << " bytes)\n"
     << "Format: ROS 1 bag 2.0, " << reader.chunk_count() << " chunks\nConnections:\n";
  for (const ConnectionInfo& c : reader.connections()) {
    const char* as = read_as(c);
    os << "  " << c.topic << " (" << c.type << "): " << c.messages << " messages"
       << (as ? std::string(", read as ") + as : std::string()) << "\n";
  }
  if (const auto& ii = reader.image_info()) {
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
     << "Anomalies: " << reader.total_anomalies() << "\n";
  std::size_t k = 0;
  for (const Anomaly& a : reader.anomalies()) {
    if (k++ >= max_anomalies) break;
    os << "  " << a.message << "\n";
  }
  return os.str();
}

xtf::WriterOptions xtf_options(const Reader& reader, const std::filesystem::path& in,
                               bool overwrite) {
  xtf::WriterOptions o;
  o.overwrite = overwrite;
  o.note = "converted by sonarsynth from the ROS 1 bag " + in.filename().string();
  if (o.note.size() > 200) o.note.resize(200);
  if (!reader.image_info()) return o;
  const ImageInfo& ii = *reader.image_info();
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

}  // namespace

bool identify(std::span<const std::uint8_t> head) {
  static constexpr char kMagic[] = "#ROSBAG V";
  return head.size() >= sizeof kMagic - 1 &&
         std::memcmp(head.data(), kMagic, sizeof kMagic - 1) == 0;
}

std::unique_ptr<SideScanSource> open_reader(const std::filesystem::path& path) {
  return std::make_unique<RosbagSource>(path);
}

SonarFileInfo file_info(const std::filesystem::path& path, std::size_t max_anomalies) {
  Reader reader(path);
  const Summary s = summarise(reader);
  return {info_json(reader, s), info_text(reader, s, max_anomalies)};
}

ConvertResult rosbag_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                            bool overwrite, AltitudeSource /*altitude_source*/) {
  ConvertResult r;
  r.from = &sonar_format();
  r.to = &xtf::sonar_format();
  Reader reader(in);
  xtf::Writer writer(out, xtf_options(reader, in, overwrite));
  const bool u16 =
      !reader.image_info() || (reader.image_info()->dtype != 0 && reader.image_info()->dtype < 8);
  // Imu messages no ping took become XTF attitude packets, before the first later ping.
  const std::vector<ImuSample>& imu = reader.imu();
  std::size_t next_imu = 0;
  const auto flush_attitude = [&](std::uint64_t before_ns) {
    for (; next_imu < imu.size() && imu[next_imu].stamp_ns < before_ns; ++next_imu) {
      if (imu[next_imu].used || !imu[next_imu].known) continue;
      try {
        writer.write_attitude(imu[next_imu].attitude);
        ++r.attitude_records;
      } catch (const InputError& e) {
        r.warn(std::string("Imu message skipped: ") + e.what());
      }
    }
  };
  Ping p;
  while (reader.next_ping(p)) {
    const auto us = p.sonar.time_utc.time_since_epoch().count();
    flush_attitude(static_cast<std::uint64_t>(us) * 1000u);
    const std::string where = "bag message at byte " + std::to_string(p.offset) + " (ping " +
                              std::to_string(p.sonar.ping_number) + ")";
    if (!p.nav_valid) {
      ++r.pings_skipped;
      ++r.dropped["no position"];
      r.warn(where + " dropped: no position (no NavSatFix with a fix at or before it)");
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
      r.warn(where + " dropped: " + e.what());
    }
  }
  flush_attitude(std::numeric_limits<std::uint64_t>::max());
  r.reader_anomalies = reader.total_anomalies();
  for (const Anomaly& a : reader.anomalies()) r.warn(a.message);
  if (r.pings == 0) {
    throw FormatError("convert: " + in.string() + ": no ping to write (" +
                      std::to_string(r.pings_skipped) + " dropped)");
  }
  writer.close();
  return r;
}

ConvertResult rosbag_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
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
  ConvertResult first = rosbag_to_xtf(in, xtf, true, altitude_source);
  ConvertResult r = xtf_to_jsf(xtf, out, overwrite, altitude_source);
  r.from = &sonar_format();
  r.pings_skipped += first.pings_skipped;
  r.reader_anomalies += first.reader_anomalies;
  for (const auto& [k, v] : first.dropped) r.dropped[k] += v;
  for (const auto& [k, v] : first.repaired) r.repaired[k] += v;
  first.warnings.insert(first.warnings.end(), r.warnings.begin(), r.warnings.end());
  r.warnings = std::move(first.warnings);
  return r;
}

}  // namespace sonarsynth::rosbag
