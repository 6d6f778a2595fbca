// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf/writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/time_fields.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth::jsf {
namespace {

constexpr double kMetresPerSecondPerKnot = 1852.0 / 3600.0;
constexpr int kMinYear = 1970;
constexpr int kMaxYear = 2100;
/// Bound on the weighting factor N: 2^-200 .. 2^200 spans every finite float sample.
constexpr int kMaxWeighting = 200;

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

[[noreturn]] void violated(const std::string& what, const std::string& value,
                           const std::string& constraint) {
  throw InputError("jsf writer: " + what + " = " + value + ". Violated constraint: " + constraint);
}

template <typename T>
T clamp_round(double v) {
  const double lo = static_cast<double>(std::numeric_limits<T>::min());
  const double hi = static_cast<double>(std::numeric_limits<T>::max());
  if (!std::isfinite(v)) return T{0};
  return static_cast<T>(std::clamp(std::round(v), lo, hi));
}

/// Degrees in [0, 360) of an angle in radians.
double heading_deg(double rad) {
  double d = std::fmod(deg_from_rad(rad), 360.0);
  if (d < 0.0) d += 360.0;
  if (d >= 360.0) d = 0.0;
  return d;
}

/// Pitch/roll as i16 fractions of 180 degrees (+-32768 = +-180).
std::int16_t half_turn_fraction(double rad) {
  return clamp_round<std::int16_t>(deg_from_rad(rad) * 32768.0 / 180.0);
}

}  // namespace

void WriterOptions::validate() const {
  if (!(frequency_hz > 0.0 && frequency_hz <= 655350.0)) {
    violated("frequency_hz", num(frequency_hz), "0 < frequency_hz <= 655350 (u16 daHz)");
  }
  if (subsystem < kSubsystemSideScanLow || subsystem > kSubsystemSideScanVeryHigh) {
    violated("subsystem", std::to_string(subsystem), "20, 21 or 22 (side scan)");
  }
}

std::int16_t quantise(std::span<const float> samples, std::vector<std::int16_t>& stored,
                      std::uint64_t& clipped) {
  stored.resize(samples.size());
  // One pass: the largest valid sample, and whether every sample is an integer in 0..32767
  // (then N = 0 and the samples are stored as they are).
  bool integers = true;  // over the valid (finite, >= 0) samples
  bool invalid = false;
  float max = 0.0f;
  for (const float v : samples) {
    if (!(v >= 0.0f) || !std::isfinite(v)) {
      invalid = true;
      continue;
    }
    max = v > max ? v : max;
    integers = integers && v <= 32767.0f && static_cast<float>(static_cast<std::int32_t>(v)) == v;
  }
  if (integers && !invalid) {
    for (std::size_t i = 0; i < samples.size(); ++i) {
      stored[i] = static_cast<std::int16_t>(samples[i]);
    }
    return 0;
  }
  int n = 0;
  if (!integers && max > 0.0f) {
    n = static_cast<int>(std::floor(std::log2(32767.0 / static_cast<double>(max))));
    while (n > -kMaxWeighting && std::ldexp(static_cast<double>(max), n) > 32767.0) --n;
    while (n < kMaxWeighting && std::ldexp(static_cast<double>(max), n + 1) <= 32767.0) ++n;
    n = std::clamp(n, -kMaxWeighting, kMaxWeighting);
  }
  const double scale = std::ldexp(1.0, n);  // exact: a power of two
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const float v = samples[i];
    if (!(v >= 0.0f) || !std::isfinite(v)) {
      ++clipped;
      stored[i] = 0;
      continue;
    }
    const double q = std::round(static_cast<double>(v) * scale);
    stored[i] = static_cast<std::int16_t>(std::min(q, 32767.0));
  }
  return static_cast<std::int16_t>(n);
}

SonarDataHeader sonar_header(const SonarPing& p, const WriterOptions& options) {
  using namespace std::chrono;
  SonarDataHeader h;
  const auto t_ms = floor<milliseconds>(p.time_utc);
  const calendar::TimeFields tf = calendar::fields_from_time(t_ms);
  const auto day = floor<days>(t_ms);
  h.ping_time_s = static_cast<std::int32_t>(floor<seconds>(t_ms).time_since_epoch().count());
  h.ms_today = static_cast<std::uint32_t>((t_ms - day).count());
  h.year = static_cast<std::int16_t>(tf.year);
  h.day_of_year = static_cast<std::int16_t>(tf.day_of_year0 + 1);
  h.hour = static_cast<std::int16_t>(tf.hour);
  h.minute = static_cast<std::int16_t>(tf.minute);
  h.second = static_cast<std::int16_t>(tf.second);
  h.fix_year = h.year;  // the position is the sonar's at the ping (validity bit 13)
  h.fix_day_of_year = h.day_of_year;
  h.fix_hour = h.hour;
  h.fix_minute = h.minute;
  h.fix_second = h.second;
  h.ping_number = p.ping_number;
  h.id_code = 1;
  h.data_format = 0;
  h.longitude =
      clamp_round<std::int32_t>(deg_from_rad(p.sensor_position.lon_rad) * kCoordinatePerDegree);
  h.latitude =
      clamp_round<std::int32_t>(deg_from_rad(p.sensor_position.lat_rad) * kCoordinatePerDegree);
  h.coordinate_units = kUnitsMinutesOfArc;
  // A NaN field is "unknown": written as 0 (sound speed: the assumed one) with its validity
  // bit clear (docs/conversion.md, "Repairs").
  const bool c_known = !std::isnan(p.sound_speed_m_s);
  const double c = c_known ? p.sound_speed_m_s : kAssumedSoundSpeed_m_s;
  const std::size_t n = std::max(p.port.size(), p.starboard.size());
  const double dt_ns = 2.0 * p.slant_range_m / (c * static_cast<double>(n)) * 1e9;
  h.sample_interval_ns = clamp_round<std::uint32_t>(dt_ns);
  h.sample_frequency_hz =
      h.sample_interval_ns == 0
          ? 0
          : static_cast<std::uint16_t>(
                static_cast<std::uint64_t>(std::llround(1e9 / h.sample_interval_ns)) & 0xFFFFu);
  const auto dahz = clamp_round<std::uint16_t>(options.frequency_hz / 10.0);
  h.start_frequency_dahz = dahz;
  h.end_frequency_dahz = dahz;
  h.mixer_frequency_hz = static_cast<float>(options.frequency_hz);
  h.depth_mm = clamp_round<std::int32_t>(p.depth_m * 1000.0);
  h.altitude_mm = clamp_round<std::int32_t>(p.altitude_m * 1000.0);
  h.sound_speed_m_s = static_cast<float>(c);
  h.time_basis = 3;
  const bool heading_known = std::isfinite(p.heading_true_rad);
  const double heading = heading_known ? heading_deg(p.heading_true_rad) : 0.0;
  h.heading_cdeg = static_cast<std::uint16_t>(std::lround(heading * 100.0) % 36000);
  h.pitch = half_turn_fraction(p.pitch_rad);
  h.roll = half_turn_fraction(p.roll_rad);  // + starboard down = + port up
  const bool heave_known = std::isfinite(p.heave_m);
  h.heave_m = heave_known ? static_cast<float>(-p.heave_m) : 0.0f;  // JSF: positive down
  // Course: the heading (the simulator's sensor moves along its heading), whole degrees plus
  // hundredths in LSB1 bits 8-15.
  const long course_cdeg = std::lround(heading * 100.0) % 36000;
  h.course_deg = static_cast<std::int16_t>(course_cdeg / 100);
  h.lsb1 = static_cast<std::uint16_t>((course_cdeg % 100) << 8);
  // Speed: tenths of a knot plus the hundredths digit in LSB2 bits 0-3.
  const bool speed_known = std::isfinite(p.speed_m_s) && p.speed_m_s >= 0.0;
  const long speed_ckn =
      speed_known
          ? std::clamp<long>(std::lround(p.speed_m_s / kMetresPerSecondPerKnot * 100.0), 0, 327679)
          : 0;
  h.speed_dkn = static_cast<std::int16_t>(speed_ckn / 10);
  h.lsb2 = static_cast<std::uint16_t>(speed_ckn % 10);
  std::uint16_t valid = validity::kPosition | validity::kPositionInterpolated;
  if (heading_known) valid |= validity::kCourse | validity::kHeading;
  if (speed_known) valid |= validity::kSpeed;
  if (std::isfinite(p.pitch_rad) && std::isfinite(p.roll_rad)) valid |= validity::kPitchRoll;
  if (heave_known) valid |= validity::kHeave;
  if (std::isfinite(p.depth_m)) valid |= validity::kDepth;
  if (c_known) valid |= validity::kSoundSpeed;
  if (p.altitude_m > 0.0) valid |= validity::kAltitude;
  h.validity_flags = valid;
  h.spherical_correction = -1;
  h.packet_number = 1;
  const std::string_view version(kVersion);
  h.software_version = fixed_string<6>(version.substr(0, 5));
  h.layback_m = 0.0f;
  return h;
}

Writer::Writer(std::filesystem::path path, WriterOptions options)
    : SonarFileWriter((options.validate(), std::move(path)), options.overwrite),
      options_(std::move(options)),
      stream_buffer_(std::size_t{1} << 20) {
  output_.open(out_, stream_buffer_, "jsf writer");
}

Writer::~Writer() {
  if (!closed_ && out_.is_open()) out_.close();
}

void Writer::append(std::size_t n) {
  out_.write(reinterpret_cast<const char*>(buffer_.data()), static_cast<std::streamsize>(n));
  if (!out_) {
    throw FormatError("jsf writer: write failed at byte " + std::to_string(bytes_written_) +
                      " of " + output_.temp_path().string() + ": " + std::strerror(errno));
  }
  bytes_written_ += n;
}

void Writer::start() {
  if (closed_) throw FormatError("jsf writer: " + path().string() + " is already closed");
  if (started_) return;
  started_ = true;
  MessageHeader m;
  m.message_type = static_cast<std::uint16_t>(MessageType::kSystemInformation);
  const std::size_t body =
      SystemInformation::kSize + (options_.xtf_file_fields ? XtfFileFields::kSize : 0);
  m.byte_count = static_cast<std::int32_t>(body);
  SystemInformation s;
  s.system_type = options_.system_type;
  s.subsystems = 1;
  buffer_.assign(MessageHeader::kSize + body, 0);
  ByteWriter w(buffer_, "jsf");
  m.encode(w);
  s.encode(w);
  if (options_.xtf_file_fields) options_.xtf_file_fields->encode(w);
  append(buffer_.size());
}

void Writer::write_channel(const SonarDataHeader& base, std::uint8_t channel,
                           const std::vector<float>& samples) {
  SonarDataHeader h = base;
  h.weighting_factor = quantise(samples, stored_, clipped_samples_);
  const auto n = static_cast<std::uint32_t>(samples.size());
  h.samples = static_cast<std::uint16_t>(n & 0xFFFFu);
  h.msb1 = static_cast<std::uint16_t>((n >> 16) << 8);
  std::int16_t max_stored = 0;
  for (const std::int16_t v : stored_) max_stored = std::max(max_stored, v);
  h.max_abs_adc = static_cast<std::uint16_t>(max_stored);
  MessageHeader m;
  m.message_type = static_cast<std::uint16_t>(MessageType::kSonarData);
  m.subsystem = options_.subsystem;
  m.channel = channel;
  m.byte_count = static_cast<std::int32_t>(SonarDataHeader::kSize + 2 * std::size_t{n});
  buffer_.resize(MessageHeader::kSize + static_cast<std::size_t>(m.byte_count));
  ByteWriter w(buffer_, "jsf");
  m.encode(w);
  h.encode(w);
  const std::span<std::uint8_t> out = w.take(2 * stored_.size());
  for (std::size_t i = 0; i < stored_.size(); ++i) {
    const auto u = static_cast<std::uint16_t>(stored_[i]);
    out[2 * i] = static_cast<std::uint8_t>(u & 0xFFu);
    out[2 * i + 1] = static_cast<std::uint8_t>(u >> 8);
  }
  append(buffer_.size());
}

void Writer::write_ping(const SonarPing& p, const XtfPingFields* xtf_fields) {
  const std::string who = "ping " + std::to_string(p.ping_number) + ": ";
  const Geodetic& g = p.sensor_position;
  if (!(std::isfinite(g.lat_rad) && std::isfinite(g.lon_rad)) || std::abs(g.lat_rad) > kPi / 2 ||
      std::abs(g.lon_rad) > kPi) {
    violated(who + "sensor_position", "(lat " + num(g.lat_rad) + ", lon " + num(g.lon_rad) + ")",
             "finite, |lat| <= pi/2, |lon| <= pi");
  }
  const int year = calendar::fields_from_time(p.time_utc).year;
  if (year < kMinYear || year > kMaxYear) {
    violated(who + "time_utc year", std::to_string(year), "1970 <= year <= 2100");
  }
  if (!(std::isnan(p.sound_speed_m_s) ||
        (p.sound_speed_m_s > 0.0 && std::isfinite(p.sound_speed_m_s)))) {
    violated(who + "sound_speed_m_s", num(p.sound_speed_m_s),
             "sound_speed_m_s > 0 (NaN = unknown: 1500 m/s assumed, validity bit clear)");
  }
  if (!(p.slant_range_m > 0.0 && std::isfinite(p.slant_range_m))) {
    violated(who + "slant_range_m", num(p.slant_range_m), "slant_range_m > 0");
  }
  if (!(p.altitude_m >= 0.0 && std::isfinite(p.altitude_m))) {
    violated(who + "altitude_m", num(p.altitude_m), "altitude_m >= 0 (0 = no seabed)");
  }
  for (const auto* side : {&p.port, &p.starboard}) {
    const std::string name = side == &p.port ? "port.size()" : "starboard.size()";
    if (side->empty()) violated(who + name, "0", name + " >= 1");
    if (side->size() > kMaxSamples) {
      violated(who + name, std::to_string(side->size()),
               name + " <= " + std::to_string(kMaxSamples) + " (20-bit sample count)");
    }
  }
  if (p.port.size() != p.starboard.size()) {
    violated(who + "starboard.size()", std::to_string(p.starboard.size()),
             "equal to port.size() = " + std::to_string(p.port.size()) +
                 " (one sample interval for both sides)");
  }
  const SonarDataHeader base = sonar_header(p, options_);
  if (base.sample_interval_ns == 0) {
    violated(who + "sample interval", "0 ns", "2 slant_range_m / (c samples) >= 0.5 ns");
  }
  start();
  if (xtf_fields) {
    MessageHeader m;
    m.message_type = static_cast<std::uint16_t>(MessageType::kSonarsynthXtfPing);
    m.subsystem = options_.subsystem;
    m.byte_count = static_cast<std::int32_t>(XtfPingFields::kSize);
    buffer_.assign(MessageHeader::kSize + XtfPingFields::kSize, 0);
    ByteWriter w(buffer_, "jsf");
    m.encode(w);
    xtf_fields->encode(w);
    append(buffer_.size());
  }
  write_channel(base, kChannelPort, p.port);  // near -> far on both sides
  write_channel(base, kChannelStarboard, p.starboard);
  ++pings_written_;
}

void Writer::write_attitude(const AttitudeSample& a) {
  using namespace std::chrono;
  for (const double v : {a.heading_true_rad, a.pitch_rad, a.roll_rad, a.heave_m, a.yaw_rad}) {
    if (!std::isfinite(v)) violated("attitude", "non-finite", "heading, pitch, roll, heave finite");
  }
  const int year = calendar::fields_from_time(a.time_utc).year;
  if (year < kMinYear || year > kMaxYear) {
    violated("attitude time_utc year", std::to_string(year), "1970 <= year <= 2100");
  }
  start();
  MessageHeader m;
  m.message_type = static_cast<std::uint16_t>(MessageType::kPitchRoll);
  m.byte_count = 44;
  buffer_.assign(MessageHeader::kSize + 44, 0);
  ByteWriter w(buffer_, "jsf");
  m.encode(w);
  const auto t_ms = floor<milliseconds>(a.time_utc);
  const auto s = floor<seconds>(t_ms);
  w.i32(static_cast<std::int32_t>(s.time_since_epoch().count()));
  w.i32(static_cast<std::int32_t>((t_ms - s).count()));
  w.zeros(4);
  w.zeros(12);  // accelerations and angular rates: not known
  w.i16(half_turn_fraction(a.pitch_rad));
  w.i16(half_turn_fraction(a.roll_rad));
  w.i16(0);                                               // temperature
  w.u16(0);                                               // device info
  w.i16(clamp_round<std::int16_t>(-a.heave_m * 1000.0));  // mm, down +
  w.u16(static_cast<std::uint16_t>(std::lround(heading_deg(a.heading_true_rad) * 100.0) % 36000));
  // validity: pitch (6), roll (7), heave (8), heading (9), yaw (12)
  w.i32((1 << 6) | (1 << 7) | (1 << 8) | (1 << 9) | (1 << 12));
  w.i16(clamp_round<std::int16_t>(deg_from_rad(a.yaw_rad) * 100.0));
  w.i16(0);
  append(buffer_.size());
}

void Writer::close() {
  if (closed_) return;
  start();  // an empty file still carries its system information message
  output_.commit(out_, "jsf writer");
  closed_ = true;
}

}  // namespace sonarsynth::jsf
