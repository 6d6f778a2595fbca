// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/xtf/writer.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/time_fields.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth::xtf {
namespace {

constexpr double kMetresPerSecondPerKnot = 1852.0 / 3600.0;
constexpr int kMinYear = 1970;  // MB-System drops pings outside 1970..2100
constexpr int kMaxYear = 2100;

/// At most 7 characters, so that the char[8] field keeps a NUL.
constexpr std::string_view kRecordingProgramName = "sonarsy";

/// The time an XTF record stores: rounded to the nearest 10 ms (HSeconds), half up, with the
/// carry into seconds, minutes... so that the fields never read 100 hundredths.
UtcTime to_hundredths(UtcTime t) {
  using namespace std::chrono;
  return floor<duration<std::int64_t, std::centi>>(t + milliseconds{5});
}

/// Degrees as written to a coordinate field: an exact 0 becomes 1e-9 degrees (0.1 mm), since
/// readers take a coordinate of 0 as "no position" (an equator or Greenwich survey is valid).
double coordinate_deg(double rad) {
  const double deg = deg_from_rad(rad);
  return deg == 0.0 ? kZeroCoordinateDeg : deg;
}

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

std::string lat_lon_text(const Geodetic& g) {
  std::ostringstream os;
  os.precision(10);
  os << "(lat " << g.lat_rad << ", lon " << g.lon_rad << ") rad";
  return os.str();
}

[[noreturn]] void violated(const std::string& what, const std::string& value,
                           const std::string& constraint) {
  throw InputError("xtf writer: " + what + " = " + value + ". Violated constraint: " + constraint);
}

std::uint16_t bytes_per_sample(SampleEncoding e) {
  switch (e) {
    case SampleEncoding::kUint8:
      return 1;
    case SampleEncoding::kFloat32:
      return 4;
    case SampleEncoding::kUint16:
      break;
  }
  return 2;
}

std::uint8_t sample_format_code(SampleEncoding e) {
  switch (e) {
    case SampleEncoding::kUint8:
      return static_cast<std::uint8_t>(SampleFormatCode::kInt8);
    case SampleEncoding::kFloat32:
      return static_cast<std::uint8_t>(SampleFormatCode::kIeeeFloat32);
    case SampleEncoding::kUint16:
      break;
  }
  return static_cast<std::uint8_t>(SampleFormatCode::kInt16);
}

/// Degrees in [0, 360) of an angle in radians.
double heading_deg(double rad) {
  double d = std::fmod(deg_from_rad(rad), 360.0);
  if (d < 0.0) d += 360.0;
  if (d >= 360.0) d = 0.0;
  return d;
}

bool finite_all(std::initializer_list<double> values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

/// The date and time fields of an XTF record: Year, Month, Day, Hour and the minute and second
/// fields (Minute and Second; Minutes and Seconds in XTFATTITUDEDATA).
template <class Record>
void set_date_time(Record& r, const calendar::TimeFields& tf,
                   std::uint8_t Record::*minute = &Record::Minute,
                   std::uint8_t Record::*second = &Record::Second) {
  r.Year = static_cast<std::uint16_t>(tf.year);
  r.Month = static_cast<std::uint8_t>(tf.month);
  r.Day = static_cast<std::uint8_t>(tf.day);
  r.Hour = static_cast<std::uint8_t>(tf.hour);
  r.*minute = static_cast<std::uint8_t>(tf.minute);
  r.*second = static_cast<std::uint8_t>(tf.second);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
void WriterOptions::validate() const {
  if (sonar_name.size() > 16) {
    throw InputError("xtf writer: sonar_name = '" + sonar_name +
                     "'. Violated constraint: at most 16 characters");
  }
  if (note.size() > 200) {
    throw InputError("xtf writer: note has " + std::to_string(note.size()) +
                     " characters. Violated constraint: at most 200 characters");
  }
  if (!(frequency_khz > 0.0 && frequency_khz <= 65535.0)) {
    violated("frequency_khz", num(frequency_khz), "0 < frequency_khz <= 65535");
  }
  if (!(horizontal_beam_angle_rad >= 0.0 && horizontal_beam_angle_rad < kPi)) {
    violated("horizontal_beam_angle_rad", num(horizontal_beam_angle_rad),
             "0 <= horizontal_beam_angle_rad < pi (0 = not stated)");
  }
  if (!(tilt_angle_rad >= 0.0 && tilt_angle_rad <= kPi / 2)) {
    violated("tilt_angle_rad", num(tilt_angle_rad), "0 <= tilt_angle_rad <= pi/2");
  }
  if (!(vertical_beam_width_rad >= 0.0 && vertical_beam_width_rad < kPi)) {
    violated("vertical_beam_width_rad", num(vertical_beam_width_rad),
             "0 <= vertical_beam_width_rad < pi");
  }
  if ((processing_flags & ~(kProcessingTvg | kProcessingBacGac | kProcessingFilter)) != 0) {
    violated("processing_flags", std::to_string(processing_flags),
             "a sum of 4 (TVG), 8 (BAC & GAC) and 16 (filter)");
  }
}

std::vector<std::string> WriterOptions::compatibility_warnings() const {
  std::vector<std::string> w;
  if (sample_encoding == SampleEncoding::kUint8) {
    w.emplace_back(
        "8-bit samples: auvlib/libxtf reads every sample as a signed 16-bit integer and returns "
        "garbage (pyxtf, MBES-lib, OpenSidescan and MB-System accept them)");
  }
  if (sample_encoding == SampleEncoding::kFloat32) {
    w.emplace_back(
        "float32 samples: MB-System (format 211) reads them as zeros and auvlib/libxtf returns "
        "garbage (pyxtf, MBES-lib and OpenSidescan accept them)");
  }
  if (allow_more_than_8192_samples) {
    w.emplace_back(
        "more than 8192 samples per channel allowed: MB-System (format 211) drops every ping "
        "with more than 16384 bytes per channel");
  }
  return w;
}

// ---------------------------------------------------------------------------------------------
Writer::Writer(std::filesystem::path path, WriterOptions options)
    : SonarFileWriter((options.validate(), std::move(path)), options.overwrite),
      options_(std::move(options)),
      stream_buffer_(std::size_t{1} << 20),
      warnings_(options_.compatibility_warnings()) {
  output_.open(out_, stream_buffer_, "xtf writer");
}

Writer::~Writer() {
  if (!closed_ && out_.is_open()) out_.close();
  // output_'s destructor removes the temporary file unless close() committed it.
}

void Writer::append(const std::vector<std::uint8_t>& bytes, std::size_t n) {
  out_.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(n));
  if (!out_) {
    throw FormatError("xtf writer: write failed at byte " + std::to_string(bytes_written_) +
                      " of " + output_.temp_path().string() + ": " + std::strerror(errno));
  }
  bytes_written_ += n;
}

void Writer::start(UtcTime first_time, std::uint32_t port_samples, std::uint32_t stbd_samples) {
  if (closed_) throw FormatError("xtf writer: " + path().string() + " is already closed");
  if (started_) return;
  started_ = true;

  XtfFileHeader& h = header_;
  h.FileFormat = kFileFormat;
  h.SystemType = 1;
  // char[8] fields are read as C strings by some readers: keep a terminating NUL in each.
  h.RecordingProgramName = fixed_string<8>(kRecordingProgramName);
  h.RecordingProgramVersion = fixed_string<8>(std::string_view(kVersion).substr(0, 7));
  h.SonarName = fixed_string<16>(options_.sonar_name);
  h.SonarType = 0;
  h.NoteString = fixed_string<64>(options_.note);
  h.ThisFileName = fixed_string<64>(path().filename().string());
  h.NavUnits = 3;
  h.NumberOfSonarChannels = 2;
  const std::uint16_t bps = bytes_per_sample(options_.sample_encoding);
  for (int side = 0; side < 2; ++side) {
    XtfChanInfo& c = h.ChanInfo[static_cast<std::size_t>(side)];
    c.TypeOfChannel =
        static_cast<std::uint8_t>(side == 0 ? ChannelType::kPort : ChannelType::kStarboard);
    c.SubChannelNumber = static_cast<std::uint8_t>(side);
    c.CorrectionFlags = 1;  // slant-range imagery (2 makes MBES-lib/OpenSidescan drop pings)
    c.UniPolar = 1;
    c.BytesPerSample = bps;
    c.SampleFormat = sample_format_code(options_.sample_encoding);
    c.Reserved = side == 0 ? port_samples : stbd_samples;  // nominal samples per channel
    c.ChannelName = fixed_string<16>(side == 0 ? "Port" : "Starboard");
    c.VoltScale = 5.0f;
    c.Frequency = static_cast<float>(options_.frequency_khz);
    c.HorizBeamAngle = static_cast<float>(deg_from_rad(options_.horizontal_beam_angle_rad));
    c.TiltAngle = static_cast<float>(deg_from_rad(options_.tilt_angle_rad));
    c.BeamWidth = static_cast<float>(deg_from_rad(options_.vertical_beam_width_rad));
  }
  append_record(h);

  // A NOTES packet first: libxtf/auvlib skip the first packet of every file.
  const calendar::TimeFields tf = calendar::fields_from_time(first_time);
  XtfNotesHeader n;
  n.Header.HeaderType = static_cast<std::uint8_t>(HeaderType::kNotes);
  n.Header.NumBytesThisRecord = static_cast<std::uint32_t>(XtfNotesHeader::kSize);
  set_date_time(n, tf);
  n.NotesText = fixed_string<200>(options_.note);
  append_record(n);
}

void Writer::validate_ping(const SonarPing& p, bool check_position) const {
  const std::string who = "ping " + std::to_string(p.ping_number) + ": ";
  const auto check_position_of = [&](const Geodetic& g, const std::string& name) {
    if (!finite_all({g.lat_rad, g.lon_rad}) || std::abs(g.lat_rad) > kPi / 2 ||
        std::abs(g.lon_rad) > kPi) {
      violated(who + name, lat_lon_text(g), "finite, |lat| <= pi/2, |lon| <= pi");
    }
    if (g.lat_rad == 0.0 && g.lon_rad == 0.0) {
      violated(who + name, lat_lon_text(g), "not (0, 0), which XTF readers take as 'no fix'");
    }
  };
  if (check_position) {
    check_position_of(p.sensor_position, "sensor_position");
    if (p.ship_position) check_position_of(*p.ship_position, "ship_position");
  }
  const calendar::TimeFields tf = calendar::fields_from_time(to_hundredths(p.time_utc));
  if (tf.year < kMinYear || tf.year > kMaxYear) {
    violated(who + "time_utc year", std::to_string(tf.year), "1970 <= year <= 2100");
  }
  if (!finite_all({p.heading_true_rad, p.pitch_rad, p.roll_rad, p.heave_m, p.depth_m})) {
    violated(who + "attitude/depth", "non-finite", "heading, pitch, roll, heave, depth finite");
  }
  if (!(std::abs(p.pitch_rad) <= kPi / 2))
    violated(who + "pitch_rad", num(p.pitch_rad), "|pitch_rad| <= pi/2");
  if (!(std::abs(p.roll_rad) <= kPi))
    violated(who + "roll_rad", num(p.roll_rad), "|roll_rad| <= pi");
  if (!(p.altitude_m >= 0.0 && std::isfinite(p.altitude_m))) {
    violated(who + "altitude_m", num(p.altitude_m),
             "altitude_m >= 0 (SensorPrimaryAltitude; 0 = no seabed under the sensor)");
  }
  if (!(p.speed_m_s >= 0.0 && std::isfinite(p.speed_m_s))) {
    violated(who + "speed_m_s", num(p.speed_m_s), "speed_m_s >= 0");
  }
  if (!(p.sound_speed_m_s > 0.0 && std::isfinite(p.sound_speed_m_s))) {
    violated(who + "sound_speed_m_s", num(p.sound_speed_m_s), "sound_speed_m_s > 0");
  }
  if (!(p.slant_range_m > 0.0 && std::isfinite(p.slant_range_m))) {
    violated(who + "slant_range_m", num(p.slant_range_m), "slant_range_m > 0");
  }
  const std::size_t limit =
      options_.allow_more_than_8192_samples ? kMaxSamples : kMaxPortableSamples;
  const std::string limit_text =
      options_.allow_more_than_8192_samples
          ? "<= " + std::to_string(kMaxSamples)
          : "<= 8192 (MB-System reads at most 16384 bytes per channel; see "
            "WriterOptions::allow_more_than_8192_samples)";
  for (const auto* side : {&p.port, &p.starboard}) {
    const std::string name = side == &p.port ? "port.size()" : "starboard.size()";
    if (side->empty()) violated(who + name, "0", name + " >= 1");
    if (side->size() > limit)
      violated(who + name, std::to_string(side->size()), name + " " + limit_text);
  }
}

void Writer::encode_samples(const std::vector<float>& samples, bool reverse, ByteWriter& w) {
  const std::size_t n = samples.size();
  const std::uint16_t bps = bytes_per_sample(options_.sample_encoding);
  const std::span<std::uint8_t> out = w.take(n * bps);
  // Round half up and clamp; non-finite values become 0. Each clamp is counted.
  const auto quantise = [&](float v, double max) -> std::uint32_t {
    if (!std::isfinite(v)) {
      ++clipped_samples_;
      return 0;
    }
    const double r = std::floor(static_cast<double>(v) + 0.5);
    if (r < 0.0) {
      ++clipped_samples_;
      return 0;
    }
    if (r > max) {
      ++clipped_samples_;
      return static_cast<std::uint32_t>(max);
    }
    return static_cast<std::uint32_t>(r);
  };
  for (std::size_t k = 0; k < n; ++k) {
    const float v = samples[reverse ? n - 1 - k : k];
    std::uint8_t* o = out.data() + k * bps;
    switch (options_.sample_encoding) {
      case SampleEncoding::kUint16: {
        const std::uint32_t q = quantise(v, 32767.0);
        o[0] = static_cast<std::uint8_t>(q & 0xFFu);
        o[1] = static_cast<std::uint8_t>(q >> 8);
        break;
      }
      case SampleEncoding::kUint8:
        o[0] = static_cast<std::uint8_t>(quantise(v, 255.0));
        break;
      case SampleEncoding::kFloat32: {
        std::uint32_t bits = 0;
        if (std::isfinite(v)) {
          bits = std::bit_cast<std::uint32_t>(v);
        } else {
          ++clipped_samples_;
        }
        for (int i = 0; i < 4; ++i) o[i] = static_cast<std::uint8_t>((bits >> (8 * i)) & 0xFFu);
        break;
      }
    }
  }
}

void Writer::write_ping(const SonarPing& p, const StoredPingHeaders* stored) {
  validate_ping(p, stored == nullptr);
  start(p.time_utc, static_cast<std::uint32_t>(p.port.size()),
        static_cast<std::uint32_t>(p.starboard.size()));
  if (header_needs_samples_) {
    // The header went out before this first ping (after an attitude or navigation packet):
    // close() rewrites it with the nominal samples per channel.
    header_.ChanInfo[0].Reserved = static_cast<std::uint32_t>(p.port.size());
    header_.ChanInfo[1].Reserved = static_cast<std::uint32_t>(p.starboard.size());
    header_patch_pending_ =
        pings_written_ == 0 && bytes_written_ > XtfFileHeader::kSize + XtfNotesHeader::kSize;
    header_needs_samples_ = false;
  }
  const std::uint16_t bps = bytes_per_sample(options_.sample_encoding);
  const std::uint64_t raw = XtfPingHeader::kSize + 2 * XtfPingChanHeader::kSize +
                            std::uint64_t{bps} * (p.port.size() + p.starboard.size());
  const std::uint64_t total = padded_size(raw);  // <= 256 + 128 + 2 * 4 * 2^20: fits 32 bits
  buffer_.assign(static_cast<std::size_t>(total), 0);
  ByteWriter w(buffer_);

  const calendar::TimeFields tf = calendar::fields_from_time(to_hundredths(p.time_utc));
  const Geodetic ship = p.ship_position.value_or(p.sensor_position);
  const double sv = p.sound_speed_m_s / 2.0;  // XTF stores the one-way ("half") speed
  const double heading = heading_deg(p.heading_true_rad);
  XtfPingHeader h;
  h.Header.HeaderType = static_cast<std::uint8_t>(HeaderType::kSonar);
  h.Header.NumChansToFollow = 2;
  h.Header.NumBytesThisRecord = static_cast<std::uint32_t>(total);
  set_date_time(h, tf);
  h.HSeconds = static_cast<std::uint8_t>(tf.microsecond / 10000);
  h.JulianDay = static_cast<std::uint16_t>(tf.day_of_year0);
  h.PingNumber = p.ping_number;
  h.SoundVelocity = static_cast<float>(sv);
  h.ComputedSoundVelocity = static_cast<float>(p.sound_speed_m_s);
  h.ShipSpeed = static_cast<float>(p.speed_m_s / kMetresPerSecondPerKnot);
  h.ShipGyro = static_cast<float>(heading);
  h.ShipYcoordinate = coordinate_deg(ship.lat_rad);
  h.ShipXcoordinate = coordinate_deg(ship.lon_rad);
  h.SensorSpeed = static_cast<float>(p.speed_m_s / kMetresPerSecondPerKnot);
  h.SensorYcoordinate = coordinate_deg(p.sensor_position.lat_rad);
  h.SensorXcoordinate = coordinate_deg(p.sensor_position.lon_rad);
  h.Layback = 0.0f;  // SensorX/Y already are the sensor position
  h.SensorDepth = static_cast<float>(p.depth_m);
  h.SensorPrimaryAltitude = static_cast<float>(p.altitude_m);
  h.SensorPitch = static_cast<float>(deg_from_rad(p.pitch_rad));
  h.SensorRoll = static_cast<float>(deg_from_rad(p.roll_rad));
  h.SensorHeading = static_cast<float>(heading);
  h.Heave = static_cast<float>(p.heave_m);
  h.AttitudeTimeTag = calendar::time_tag_ms(p.time_utc);
  if (stored) {
    const XtfPacketHeader packet = h.Header;
    h = stored->ping;
    h.Header.MagicNumber = packet.MagicNumber;
    h.Header.HeaderType = packet.HeaderType;
    h.Header.NumChansToFollow = packet.NumChansToFollow;
    h.Header.NumBytesThisRecord = packet.NumBytesThisRecord;
  }
  h.encode(w);

  const double ground =
      p.slant_range_m > p.altitude_m
          ? std::sqrt(p.slant_range_m * p.slant_range_m - p.altitude_m * p.altitude_m)
          : 0.0;
  for (std::uint16_t side = 0; side < 2; ++side) {
    const std::vector<float>& samples = side == 0 ? p.port : p.starboard;
    XtfPingChanHeader c;
    c.ChannelNumber = side;
    c.SlantRange = static_cast<float>(p.slant_range_m);
    c.GroundRange = static_cast<float>(ground);
    c.TimeDelay = 0.0f;
    c.TimeDuration = static_cast<float>(p.slant_range_m / sv);  // two-way time of the last sample
    c.SecondsPerPing = c.TimeDuration;
    c.ProcessingFlags = options_.processing_flags;
    c.Frequency = static_cast<std::uint16_t>(std::lround(options_.frequency_khz));
    c.NumSamples = static_cast<std::uint32_t>(samples.size());
    c.Weight = 0;
    if (stored) {
      c = stored->channels[side];
      c.ChannelNumber = side;
      c.NumSamples = static_cast<std::uint32_t>(samples.size());
    }
    c.encode(w);
    encode_samples(samples, side == 0, w);  // port is stored far -> near
  }
  append(buffer_, buffer_.size());
  ++pings_written_;
}

void Writer::write_attitude(const AttitudeSample& a) {
  if (!finite_all({a.heading_true_rad, a.pitch_rad, a.roll_rad, a.heave_m, a.yaw_rad})) {
    violated("attitude", "non-finite", "heading, pitch, roll, heave, yaw finite");
  }
  const calendar::TimeFields tf = calendar::fields_from_time(a.time_utc);
  if (tf.year < kMinYear || tf.year > kMaxYear) {
    violated("attitude time_utc year", std::to_string(tf.year), "1970 <= year <= 2100");
  }
  start(a.time_utc, 0, 0);
  XtfAttitudeData d;
  d.Header.HeaderType = static_cast<std::uint8_t>(HeaderType::kAttitude);
  d.Header.NumBytesThisRecord = static_cast<std::uint32_t>(XtfAttitudeData::kSize);
  d.EpochMicroseconds = tf.microsecond;
  d.SourceEpoch = static_cast<std::uint32_t>(calendar::epoch_seconds(a.time_utc));
  d.Pitch = static_cast<float>(deg_from_rad(a.pitch_rad));
  d.Roll = static_cast<float>(deg_from_rad(a.roll_rad));
  d.Heave = static_cast<float>(a.heave_m);
  d.Yaw = static_cast<float>(deg_from_rad(a.yaw_rad));
  d.TimeTag = calendar::time_tag_ms(a.time_utc);
  d.Heading = static_cast<float>(heading_deg(a.heading_true_rad));
  set_date_time(d, tf, &XtfAttitudeData::Minutes, &XtfAttitudeData::Seconds);
  d.Milliseconds = static_cast<std::uint16_t>(tf.microsecond / 1000);
  append_record(d);
}

void Writer::write_navigation(const NavigationFix& fix) {
  const Geodetic& g = fix.position;
  if (!finite_all({g.lat_rad, g.lon_rad, g.height_m}) || std::abs(g.lat_rad) > kPi / 2 ||
      std::abs(g.lon_rad) > kPi) {
    violated("navigation position", lat_lon_text(g), "finite, |lat| <= pi/2, |lon| <= pi");
  }
  if (g.lat_rad == 0.0 && g.lon_rad == 0.0) {
    violated("navigation position", lat_lon_text(g),
             "not (0, 0), which XTF readers take as 'no fix'");
  }
  const calendar::TimeFields tf = calendar::fields_from_time(fix.time_utc);
  if (tf.year < kMinYear || tf.year > kMaxYear) {
    violated("navigation time_utc year", std::to_string(tf.year), "1970 <= year <= 2100");
  }
  start(fix.time_utc, 0, 0);
  XtfHeaderNavigation n;
  set_date_time(n, tf);
  n.Microseconds = tf.microsecond;
  n.SourceEpoch = static_cast<std::uint32_t>(calendar::epoch_seconds(fix.time_utc));
  n.TimeTag = calendar::time_tag_ms(fix.time_utc);
  n.RawYcoordinate = coordinate_deg(g.lat_rad);
  n.RawXcoordinate = coordinate_deg(g.lon_rad);
  n.RawAltitude = g.height_m;
  n.TimeFlag = 1;  // source time valid
  append_record(n);
}

void Writer::close() {
  if (closed_) return;
  if (!started_) start(UtcTime{std::chrono::seconds{0}}, 0, 0);  // valid empty file
  if (header_patch_pending_) {
    buffer_.assign(XtfFileHeader::kSize, 0);
    ByteWriter w(buffer_);
    header_.encode(w);
    out_.seekp(0);
    out_.write(reinterpret_cast<const char*>(buffer_.data()),
               static_cast<std::streamsize>(buffer_.size()));
    out_.seekp(0, std::ios::end);
  }
  output_.commit(out_, "xtf writer");
  closed_ = true;
}

}  // namespace sonarsynth::xtf
