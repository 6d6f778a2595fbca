// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf/convert.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

#include "sonarsynth/bottom_track.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/time_fields.hpp"
#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/jsf/writer.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {

/// The two formats this file converts between.
enum class SonarFileFormat : std::uint8_t { kXtf, kJsf };

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

/// The field a writer's InputError names ("xtf writer: ping 7: altitude_m = -1. Violated
/// constraint: ..." -> "altitude_m"): the key its drops are counted under.
std::string writer_reason(const std::string& message) {
  std::size_t from = message.find("ping ");
  from = from == std::string::npos ? std::string::npos : message.find(": ", from);
  const std::size_t to = from == std::string::npos ? from : message.find(" = ", from);
  if (to == std::string::npos) return message;
  return "refused by the writer: " + message.substr(from + 2, to - from - 2);
}

/// Drops one ping: counted under `reason`, the first few named with `where` and `detail`.
void drop(ConvertResult& r, const std::string& reason, const std::string& where,
          const std::string& detail) {
  ++r.pings_skipped;
  ++r.dropped[reason];
  r.warn(where + " dropped: " + detail);
}

/// Why a ping cannot be converted at all (docs/conversion.md, "Drops"), or "" if it can.
std::string drop_reason(const SonarPing& s) {
  if (s.port.empty() || s.starboard.empty()) return "one side missing";
  if (!(s.slant_range_m > 0.0)) return "slant range 0 (sample interval 0: no sample spacing)";
  if (!(s.slant_range_m <= jsf::kMaxPlausibleSlantRange_m)) {
    return "slant range over 100 km (implausible sample interval)";
  }
  return "";
}

/// Writes the fields the output cannot hold as they are but can hold as "unknown" so, each
/// repair counted by its rule (docs/conversion.md, "Repairs").
void repair(SonarFileFormat to, SonarPing& s, ConvertResult& r) {
  const auto fix = [&](double& v, bool ok, double unknown, const char* rule) {
    if (ok) return;
    v = unknown;
    ++r.repaired[rule];
  };
  const double nan = std::nan("");
  // Negative: EdgeTech's "no altimeter lock"; both formats read 0 as "no altitude".
  fix(s.altitude_m, s.altitude_m >= 0.0 && std::isfinite(s.altitude_m), 0.0,
      "altitude negative or not finite -> 0 (no altitude)");
  if (to == SonarFileFormat::kJsf) {
    // JSF has a validity bit per field: the writer clears it for NaN.
    fix(s.sound_speed_m_s, s.sound_speed_m_s > 0.0 && std::isfinite(s.sound_speed_m_s), nan,
        "sound speed <= 0 or not finite -> unknown (1500 m/s for the sample interval)");
    fix(s.heave_m, std::isfinite(s.heave_m), nan, "heave not finite -> unknown");
    fix(s.depth_m, std::isfinite(s.depth_m), nan, "depth not finite -> unknown");
    fix(s.speed_m_s, s.speed_m_s >= 0.0 && std::isfinite(s.speed_m_s), nan,
        "speed negative or not finite -> unknown");
    fix(s.heading_true_rad, std::isfinite(s.heading_true_rad), nan,
        "heading not finite -> unknown");
    const bool attitude_ok = std::abs(s.pitch_rad) <= kPi / 2 && std::abs(s.roll_rad) <= kPi;
    if (!attitude_ok) {
      s.pitch_rad = s.roll_rad = nan;
      ++r.repaired["pitch beyond +-90 deg or roll beyond +-180 deg -> unknown"];
    }
    return;
  }
  // XTF has no validity flags: 0 is the value of a sensor that is not there.
  fix(s.heave_m, std::isfinite(s.heave_m), 0.0, "heave not finite -> 0");
  fix(s.depth_m, std::isfinite(s.depth_m), 0.0, "depth not finite -> 0");
  fix(s.speed_m_s, s.speed_m_s >= 0.0 && std::isfinite(s.speed_m_s), 0.0,
      "speed negative or not finite -> 0");
  fix(s.pitch_rad, std::abs(s.pitch_rad) <= kPi / 2, 0.0, "pitch beyond +-90 deg -> 0");
  fix(s.roll_rad, std::abs(s.roll_rad) <= kPi, 0.0, "roll beyond +-180 deg -> 0");
  fix(s.sound_speed_m_s, s.sound_speed_m_s > 0.0 && std::isfinite(s.sound_speed_m_s),
      jsf::kAssumedSoundSpeed_m_s, "sound speed <= 0 or not finite -> 1500 m/s");
}

/// Nothing left to write: fails naming the input and the reasons (the output is not created).
void refuse_empty(const std::filesystem::path& in, const ConvertResult& r) {
  if (r.pings > 0) return;
  if (r.pings_skipped == 0) {
    throw FormatError("convert: " + in.string() + ": no side-scan ping to convert" +
                      (r.warnings.empty()
                           ? std::string()
                           : " (" + std::to_string(r.reader_anomalies) +
                                 " reader anomalies; first: " + r.warnings.front() + ")") +
                      "; nothing written");
  }
  std::string reasons;
  for (const auto& [reason, n] : r.dropped) {
    reasons += (reasons.empty() ? "" : ", ") + reason + ": " + std::to_string(n);
  }
  throw FormatError("convert: " + in.string() + ": none of its " + std::to_string(r.pings_skipped) +
                    " pings could be converted (" + reasons +
                    (r.warnings.empty() ? std::string() : "; first: " + r.warnings.front()) +
                    "); nothing written");
}

/// Tracked altitude of every ping of `in`, in the order the converters read them; empty with
/// AltitudeSource::kHeader (nothing to track: the header altitude is copied as it is).
std::vector<double> tracked_altitudes(const std::filesystem::path& in, SonarFileFormat from,
                                      AltitudeSource source) {
  if (source == AltitudeSource::kHeader) return {};
  BottomTracker tracker;
  if (from == SonarFileFormat::kXtf) {
    xtf::Reader reader(in);
    xtf::Packet p;
    while (reader.next(p)) {
      if (p.kind != xtf::PacketKind::kPing) continue;
      tracker.add_ping(p.ping.sonar.port, p.ping.sonar.starboard, p.ping.sonar.slant_range_m);
    }
  } else {
    jsf::Reader reader(in);
    jsf::Ping p;
    while (reader.next_ping(p)) {
      tracker.add_ping(p.sonar.port, p.sonar.starboard, p.sonar.slant_range_m);
    }
  }
  return tracker.altitudes_m();
}

/// Replaces the altitude of the k-th ping by the chosen one (docs/conversion.md); a ping
/// without one keeps its header altitude.
void choose_ping_altitude(SonarPing& s, std::size_t k, const std::vector<double>& tracked,
                          AltitudeSource source, ConvertResult& r) {
  if (source == AltitudeSource::kHeader) return;
  const double t = k < tracked.size() ? tracked[k] : std::nan("");
  const std::size_t n = std::max(s.port.size(), s.starboard.size());
  const double dr = n > 0 ? s.slant_range_m / static_cast<double>(n) : std::nan("");
  const AltitudeChoice a = choose_altitude(source, s.altitude_m, t, dr);
  if (a.tracked) {
    s.altitude_m = a.altitude_m;
    ++r.pings_tracked_altitude;
  }
}

/// What both directions share: the result with its from/to formats, the altitudes tracked for
/// the chosen source, ping by ping, and the accounting of each write and of the reader's
/// anomalies.
class Conversion {
 public:
  Conversion(const std::filesystem::path& in, SonarFileFormat from, AltitudeSource source)
      : in_(in), source_(source), tracked_(tracked_altitudes(in, from, source)) {
    result.from = from == SonarFileFormat::kXtf ? &xtf::sonar_format() : &jsf::sonar_format();
    result.to = from == SonarFileFormat::kXtf ? &jsf::sonar_format() : &xtf::sonar_format();
  }
  /// The next ping read (every ping, in the order tracked_altitudes() read them).
  void choose_altitude(SonarPing& s) {
    choose_ping_altitude(s, next_++, tracked_, source_, result);
  }
  /// Runs `write` (one ping); a ping the writer refuses is dropped and counted.
  template <class Write>
  void write_ping(const std::string& where, Write&& write) {
    try {
      write();
      ++result.pings;
    } catch (const InputError& e) {
      drop(result, writer_reason(e.what()), where, e.what());
    }
  }
  /// After the last ping: the reader's anomalies, and the refusal when no ping was converted.
  template <class Reader>
  void finish(const Reader& reader) {
    result.reader_anomalies = reader.total_anomalies();
    for (const auto& a : reader.anomalies()) result.warn(a.message);
    refuse_empty(in_, result);
  }

  ConvertResult result;

 private:
  std::filesystem::path in_;
  AltitudeSource source_;
  std::vector<double> tracked_;
  std::size_t next_ = 0;
};

template <std::size_t N>
std::string text_of(const std::array<char, N>& a) {
  std::size_t n = 0;
  while (n < N && a[n] != 0) ++n;
  return std::string(a.data(), n);
}

/// The file-level XTF fields JSF has no place for (docs/conversion.md, "Lossless round trip"):
/// the header's sonar name, the first NOTES packet's text (else the header's NoteString) and
/// the first channel's sample layout, frequency and beam angles.
jsf::XtfFileFields xtf_file_fields(const std::filesystem::path& in) {
  xtf::Reader reader(in);
  jsf::XtfFileFields f;
  const xtf::XtfFileHeader& h = reader.file_header();
  f.sonar_name = h.SonarName;
  f.note = fixed_string<200>(text_of(h.NoteString));
  xtf::Packet p;
  while (reader.next(p) && p.kind != xtf::PacketKind::kPing) {
    if (p.kind == xtf::PacketKind::kNotes) {
      f.note = p.notes.NotesText;
      break;
    }
  }
  if (!reader.chan_info().empty()) {
    const xtf::XtfChanInfo& c = reader.chan_info()[0];
    f.bytes_per_sample = c.BytesPerSample;
    f.sample_format = c.SampleFormat;
    f.uni_polar = static_cast<std::uint8_t>(c.UniPolar);
    f.frequency_khz = c.Frequency;
    f.horizontal_beam_angle_deg = c.HorizBeamAngle;
    f.tilt_angle_deg = c.TiltAngle;
    f.beam_width_deg = c.BeamWidth;
  }
  return f;
}

/// The ping's header and its first port and starboard channel headers, as the file has them;
/// the coordinates 0 when they are not longitude/latitude (NavUnits other than 3), since the XTF
/// written back says NavUnits 3: the ping then comes back without a position, as in the JSF.
jsf::XtfPingFields xtf_ping_fields(const xtf::PingRecord& ping, std::uint16_t nav_units) {
  jsf::XtfPingFields f;
  f.ping = ping.header;
  if (nav_units != 3) {
    f.ping.ShipXcoordinate = f.ping.ShipYcoordinate = 0.0;
    f.ping.SensorXcoordinate = f.ping.SensorYcoordinate = 0.0;
  }
  bool port = false, starboard = false;
  for (std::size_t i = 0; i < ping.channel_count; ++i) {
    const xtf::ChannelData& c = ping.channels[i];
    if (!port && c.type_of_channel == static_cast<std::uint8_t>(xtf::ChannelType::kPort)) {
      f.channels[0] = c.header;
      port = true;
    } else if (!starboard &&
               c.type_of_channel == static_cast<std::uint8_t>(xtf::ChannelType::kStarboard)) {
      f.channels[1] = c.header;
      starboard = true;
    }
  }
  return f;
}

/// Whether a ping's carried XTF header still describes its message 80 (docs/conversion.md,
/// "Lossless round trip"): every value the JSF holds within the JSF's resolution of the XTF
/// one. A JSF edited after the conversion (another tool, a repair) fails this and its ping is
/// written from the message-80 values.
bool carried_agrees(const jsf::XtfPingFields& f, const jsf::Ping& p) {
  const xtf::XtfPingHeader& h = f.ping;
  const SonarPing& s = p.sonar;
  const auto near = [](double jsf_value, double xtf_value, double step) {
    return std::abs(jsf_value - xtf_value) <= step / 2 + 1e-6 * (1.0 + std::abs(xtf_value));
  };
  const double knot_m_s = 1852.0 / 3600.0;
  double dh = std::fmod(std::abs(deg_from_rad(s.heading_true_rad) - h.SensorHeading), 360.0);
  dh = std::min(dh, 360.0 - dh);
  const std::size_t n = std::max(s.port.size(), s.starboard.size());
  const double range_step = s.sound_speed_m_s * static_cast<double>(n) * 1e-9;
  const bool position =
      p.nav_valid
          ? near(deg_from_rad(s.sensor_position.lat_rad), h.SensorYcoordinate, 1.0 / 6e5) &&
                near(deg_from_rad(s.sensor_position.lon_rad), h.SensorXcoordinate, 1.0 / 6e5)
          : true;
  // The XTF time to 10 ms (HSeconds); the JSF's is that time, to 1 ms.
  const std::optional<UtcTime> t = calendar::time_from_fields(
      h.Year, h.Month, h.Day, h.Hour, h.Minute, h.Second, std::uint32_t{h.HSeconds} * 10000u);
  const bool time =
      !p.time_valid || (t && std::chrono::abs(s.time_utc - *t) <= std::chrono::milliseconds{10});
  return position && time && near(s.altitude_m, h.SensorPrimaryAltitude, 1e-3) &&
         near(s.depth_m, h.SensorDepth, 1e-3) && near(s.heave_m, h.Heave, 1e-6) &&
         near(deg_from_rad(s.pitch_rad), h.SensorPitch, 180.0 / 32768.0) &&
         near(deg_from_rad(s.roll_rad), h.SensorRoll, 180.0 / 32768.0) && dh <= 0.005 + 1e-4 &&
         near(s.speed_m_s / knot_m_s, h.SensorSpeed, 0.1) &&
         near(s.sound_speed_m_s, 2.0 * h.SoundVelocity, 1e-3) &&
         near(s.slant_range_m, f.channels[0].SlantRange, range_step);
}

/// The XTF writer's options from the carried file fields: each only if the writer accepts it.
void apply_xtf_file_fields(const jsf::XtfFileFields& f, xtf::WriterOptions& o) {
  o.sonar_name = text_of(f.sonar_name);
  o.note = text_of(f.note);
  if (f.bytes_per_sample == 1) o.sample_encoding = xtf::SampleEncoding::kUint8;
  if (f.bytes_per_sample == 4 &&
      f.sample_format == static_cast<std::uint8_t>(xtf::SampleFormatCode::kIeeeFloat32)) {
    o.sample_encoding = xtf::SampleEncoding::kFloat32;
  }
  const auto set = [](double& v, float deg, double lo, double hi) {
    const double rad = rad_from_deg(static_cast<double>(deg));
    if (rad >= lo && rad < hi) v = rad;
  };
  if (f.frequency_khz > 0.0f && f.frequency_khz <= 65535.0f) o.frequency_khz = f.frequency_khz;
  set(o.horizontal_beam_angle_rad, f.horizontal_beam_angle_deg, 0.0, kPi);
  set(o.tilt_angle_rad, f.tilt_angle_deg, 0.0, kPi / 2 + 1e-12);
  set(o.vertical_beam_width_rad, f.beam_width_deg, 0.0, kPi);
}

}  // namespace

ConvertResult xtf_to_jsf(const std::filesystem::path& in, const std::filesystem::path& out,
                         bool overwrite, AltitudeSource source) {
  Conversion c(in, SonarFileFormat::kXtf, source);
  ConvertResult& r = c.result;
  xtf::Reader reader(in);
  jsf::WriterOptions o;
  o.overwrite = overwrite;
  o.xtf_file_fields = xtf_file_fields(in);
  const double khz = reader.chan_info().empty() ? 0.0 : reader.chan_info()[0].Frequency;
  if (khz > 0.0 && khz * 1e3 <= 655350.0) o.frequency_hz = khz * 1e3;
  jsf::Writer writer(out, o);
  xtf::Packet packet;
  while (xtf::next_ping_copying_attitude(reader, packet, writer, r)) {
    SonarPing& s = packet.ping.sonar;
    c.choose_altitude(s);
    if (!packet.ping.nav_valid || reader.file_header().NavUnits != 3) {
      s.sensor_position = {};  // stored as 0, 0: "no position" for JSF readers
    }
    const std::string where = "XTF packet " + std::to_string(packet.index) + " (ping " +
                              std::to_string(s.ping_number) + ")";
    const std::string why = drop_reason(s);
    if (!why.empty()) {
      drop(r, why, where, why + " (slant range " + num(s.slant_range_m) + " m)");
      continue;
    }
    repair(SonarFileFormat::kJsf, s, r);
    const jsf::XtfPingFields carried = xtf_ping_fields(packet.ping, reader.file_header().NavUnits);
    c.write_ping(where, [&] { writer.write_ping(s, &carried); });
  }
  c.finish(reader);
  writer.close();
  return r;
}

ConvertResult jsf_to_xtf(const std::filesystem::path& in, const std::filesystem::path& out,
                         bool overwrite, AltitudeSource source) {
  Conversion c(in, SonarFileFormat::kJsf, source);
  ConvertResult& r = c.result;
  jsf::Reader reader(in);
  std::unique_ptr<xtf::Writer> writer;
  xtf::WriterOptions o;
  o.overwrite = overwrite;
  o.note = "converted by sonarsynth from the JSF file " + in.filename().string();
  if (o.note.size() > 200) o.note.resize(200);
  const auto open = [&](double frequency_hz) {
    if (writer) return;
    if (frequency_hz > 0.0 && frequency_hz <= 65535e3) o.frequency_khz = frequency_hz / 1e3;
    if (reader.xtf_file_fields()) apply_xtf_file_fields(*reader.xtf_file_fields(), o);
    writer = std::make_unique<xtf::Writer>(out, o);
  };
  jsf::Message m;
  jsf::Ping ping;
  // Pings through next_ping(); pitch/roll messages are not pings and are read separately, so
  // walk the messages once for attitude, once for pings, and merge by order of offset.
  std::vector<std::pair<std::uint64_t, AttitudeSample>> attitude;
  {
    jsf::Reader scan(in);
    while (scan.next(m)) {
      if (m.kind == jsf::MessageKind::kPitchRoll) attitude.emplace_back(m.offset, m.attitude);
    }
  }
  auto next_attitude = attitude.begin();
  const auto flush_attitude = [&](std::uint64_t before) {
    for (; next_attitude != attitude.end() && next_attitude->first < before; ++next_attitude) {
      open(0.0);
      try {
        writer->write_attitude(next_attitude->second);
        ++r.attitude_records;
      } catch (const InputError& e) {
        r.warn(std::string("pitch/roll message skipped: ") + e.what());
      }
    }
  };
  while (reader.next_ping(ping)) {
    c.choose_altitude(ping.sonar);
    flush_attitude(ping.offset);
    open(ping.header.mixer_frequency_hz);
    std::string why = drop_reason(ping.sonar);
    if (ping.xtf_fields && !carried_agrees(*ping.xtf_fields, ping)) {
      ping.xtf_fields.reset();
      ++r.repaired["carried XTF header disagrees with the JSF ping -> written from the JSF"];
    }
    // A ping without a position is kept only with its carried XTF header (zero coordinates,
    // XTF's "no fix", as the XTF it came from had them).
    if (!ping.nav_valid && !ping.xtf_fields) why = "no position";
    if (!ping.time_valid) why = "no valid time";
    if (ping.sonar.port.empty() || ping.sonar.starboard.empty()) why = "one side missing";
    const std::string where = "JSF ping " + std::to_string(ping.sonar.ping_number) + " at byte " +
                              std::to_string(ping.offset);
    if (!why.empty()) {
      drop(r, why, where,
           why + " (slant range " + num(ping.sonar.slant_range_m) + " m, sample interval " +
               std::to_string(ping.header.sample_interval_ns) + " ns)");
      continue;
    }
    repair(SonarFileFormat::kXtf, ping.sonar, r);
    std::optional<xtf::StoredPingHeaders> stored;
    if (ping.xtf_fields)
      stored = xtf::StoredPingHeaders{ping.xtf_fields->ping, ping.xtf_fields->channels};
    c.write_ping(where, [&] { writer->write_ping(ping.sonar, stored ? &*stored : nullptr); });
  }
  c.finish(reader);
  flush_attitude(reader.file_size() + 1);
  open(0.0);
  writer->close();
  return r;
}

}  // namespace sonarsynth
