// SPDX-License-Identifier: MIT
#pragma once

// EdgeTech JSF messages as docs/jsf.md §1 describes them: the 16-byte message header, the
// 240-byte header of sonar data message 80 and the system information message 182. Each struct
// keeps the documents' fields in file order, has kSize and lists its fields once, with their
// widths, in a field table (`fields`, io/fields.hpp) that both encode and decode walk, field by
// field in explicit little-endian (never cast from raw bytes). Units are those of the file (minutes
// of arc x 10 000, millimetres, 1/100 degree...); conversion to SI happens in
// writer.cpp/reader.cpp.

#include <array>
#include <cstddef>
#include <cstdint>

#include "sonarsynth/formats/io/byte_io.hpp"
#include "sonarsynth/formats/io/fields.hpp"
#include "sonarsynth/formats/xtf/records.hpp"

namespace sonarsynth::jsf {

inline constexpr std::uint16_t kStartMarker = 0x1601;  ///< bytes 01 16 at every message start
inline constexpr std::uint8_t kProtocolVersion = 13;   ///< 0x0D: every field we write is defined
inline constexpr std::uint8_t kCommandNormal = 2;

/// Message types this project names (docs/jsf.md §1.4).
enum class MessageType : std::uint16_t {
  kSonarData = 80,
  kNavigationOffsets = 181,
  kSystemInformation = 182,
  kFileTimestamp = 426,
  kNmeaString = 2002,
  kPitchRoll = 2020,
  kPressure = 2060,
  kDopplerVelocityLog = 2080,
  kSituation = 2091,
  /// Not EdgeTech's: the XTF header fields of the next ping (XtfPingFields), written by
  /// `convert` (docs/jsf.md §1.4); every reader skips it by its byte count.
  kSonarsynthXtfPing = 9999,
};
/// "sonar data", "system information", ...; nullptr for a type this project does not name.
const char* message_type_name(std::uint16_t type);

inline constexpr std::uint8_t kSubsystemSideScanLow = 20;
inline constexpr std::uint8_t kSubsystemSideScanHigh = 21;
inline constexpr std::uint8_t kSubsystemSideScanVeryHigh = 22;
inline constexpr std::uint8_t kChannelPort = 0;
inline constexpr std::uint8_t kChannelStarboard = 1;

/// Message 80 validity flags (offset 30).
namespace validity {
inline constexpr std::uint16_t kPosition = 1u << 0;
inline constexpr std::uint16_t kCourse = 1u << 1;
inline constexpr std::uint16_t kSpeed = 1u << 2;
inline constexpr std::uint16_t kHeading = 1u << 3;
inline constexpr std::uint16_t kPressure = 1u << 4;
inline constexpr std::uint16_t kPitchRoll = 1u << 5;
inline constexpr std::uint16_t kAltitude = 1u << 6;
inline constexpr std::uint16_t kHeave = 1u << 7;
inline constexpr std::uint16_t kWaterTemperature = 1u << 8;
inline constexpr std::uint16_t kDepth = 1u << 9;
inline constexpr std::uint16_t kAnnotation = 1u << 10;
inline constexpr std::uint16_t kCableCounter = 1u << 11;
inline constexpr std::uint16_t kKp = 1u << 12;
inline constexpr std::uint16_t kPositionInterpolated = 1u << 13;
inline constexpr std::uint16_t kSoundSpeed = 1u << 14;
}  // namespace validity

/// The sound speed assumed when a ping's is missing (the speed MB-System assumes).
inline constexpr double kAssumedSoundSpeed_m_s = 1500.0;
/// Longest slant range taken as plausible: GLORIA, the longest-range side-scan, reached about
/// 30 km; a longer one comes from a corrupted sample interval (docs/jsf.md §3).
inline constexpr double kMaxPlausibleSlantRange_m = 100e3;

/// Coordinate units (offset 88): 2 = longitude/latitude in minutes of arc x 10 000.
inline constexpr std::int16_t kUnitsMinutesOfArc = 2;
/// Degrees = coordinate / 600 000 for units 2.
inline constexpr double kCoordinatePerDegree = 600000.0;

/// The 16-byte header in front of every message.
struct MessageHeader {
  static constexpr std::size_t kSize = 16;
  std::uint16_t start_marker = kStartMarker;
  std::uint8_t protocol_version = kProtocolVersion;
  std::uint8_t session_id = 0;
  std::uint16_t message_type = 0;
  std::uint8_t command_type = kCommandNormal;
  std::uint8_t subsystem = 0;
  std::uint8_t channel = 0;
  std::uint8_t sequence = 0;
  std::uint16_t reserved = 0;
  std::int32_t byte_count = 0;  ///< bytes after this header up to the next message
  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.u16(s.start_marker);
    io.u8(s.protocol_version);
    io.u8(s.session_id);
    io.u16(s.message_type);
    io.u8(s.command_type);
    io.u8(s.subsystem);
    io.u8(s.channel);
    io.u8(s.sequence);
    io.u16(s.reserved);
    io.i32(s.byte_count);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static MessageHeader decode(ByteReader& r) { return read_fields<MessageHeader>(r); }
};

/// The 240-byte header of a sonar data message (type 80), offsets of docs/jsf.md §1.2.
struct SonarDataHeader {
  static constexpr std::size_t kSize = 240;
  std::int32_t ping_time_s = 0;              ///< 0: seconds since 1970-01-01 UTC
  std::uint32_t starting_depth = 0;          ///< 4: window offset, samples
  std::uint32_t ping_number = 0;             ///< 8
  std::array<std::int16_t, 2> reserved0{};   ///< 12
  std::uint16_t msb1 = 0;                    ///< 16: high nibbles (bits 8-11: samples)
  std::uint16_t lsb1 = 0;                    ///< 18: bits 8-15 course fraction, 1/100 degree
  std::uint16_t lsb2 = 0;                    ///< 20: bits 0-3 speed 1/100 knot, 4-13 sweep us
  std::array<std::int16_t, 3> reserved1{};   ///< 22
  std::int16_t id_code = 1;                  ///< 28
  std::uint16_t validity_flags = 0;          ///< 30
  std::uint16_t reserved2 = 0;               ///< 32
  std::int16_t data_format = 0;              ///< 34: 0 envelope int16
  std::int16_t tow_aft_cm = 0;               ///< 36
  std::int16_t tow_starboard_cm = 0;         ///< 38
  std::array<std::int16_t, 2> reserved3{};   ///< 40
  float km_of_pipe = 0.0f;                   ///< 44
  float heave_m = 0.0f;                      ///< 48: positive down
  std::array<std::int16_t, 12> reserved4{};  ///< 52 (must stay 0: docs/jsf.md §1.2)
  float gap_filler_offset_m = 0.0f;          ///< 76
  std::int32_t longitude = 0;                ///< 80: minutes x 10 000 (units 2)
  std::int32_t latitude = 0;                 ///< 84
  std::int16_t coordinate_units = kUnitsMinutesOfArc;  ///< 88
  std::array<char, 24> annotation{};                   ///< 90
  std::uint16_t samples = 0;                           ///< 114: low 16 bits
  std::uint32_t sample_interval_ns = 0;                ///< 116
  std::uint16_t adc_gain = 0;                          ///< 120
  std::int16_t transmit_level = 0;                     ///< 122
  std::int16_t reserved5 = 0;                          ///< 124
  std::uint16_t start_frequency_dahz = 0;              ///< 126
  std::uint16_t end_frequency_dahz = 0;                ///< 128
  std::uint16_t sweep_length_ms = 0;                   ///< 130
  std::int32_t pressure_mpsi = 0;                      ///< 132: 1/1000 PSI
  std::int32_t depth_mm = 0;                           ///< 136
  std::uint16_t sample_frequency_hz = 0;               ///< 140: modulo 65 536
  std::uint16_t pulse_id = 0;                          ///< 142
  std::int32_t altitude_mm = 0;                        ///< 144
  float sound_speed_m_s = 0.0f;                        ///< 148
  float mixer_frequency_hz = 0.0f;                     ///< 152
  std::int16_t year = 0;                               ///< 156: CPU time, UTC
  std::int16_t day_of_year = 0;                        ///< 158: 1..366
  std::int16_t hour = 0;                               ///< 160
  std::int16_t minute = 0;                             ///< 162
  std::int16_t second = 0;                             ///< 164
  std::int16_t time_basis = 3;                         ///< 166
  std::int16_t weighting_factor = 0;                   ///< 168: value = stored x 2^-N
  std::int16_t pulses_in_water = 0;                    ///< 170
  std::uint16_t heading_cdeg = 0;                      ///< 172: 1/100 degree
  std::int16_t pitch = 0;                              ///< 174: degrees x 32768/180, bow up +
  std::int16_t roll = 0;                               ///< 176: degrees x 32768/180, port up +
  std::int16_t reserved6 = 0;                          ///< 178
  std::int16_t reserved7 = 0;                          ///< 180
  std::int16_t trigger_source = 0;                     ///< 182
  std::uint16_t mark_number = 0;                       ///< 184
  std::int16_t fix_hour = 0;                           ///< 186
  std::int16_t fix_minute = 0;                         ///< 188
  std::int16_t fix_second = 0;                         ///< 190
  std::int16_t course_deg = 0;                         ///< 192: whole degrees
  std::int16_t speed_dkn = 0;                          ///< 194: 1/10 knot
  std::int16_t fix_day_of_year = 0;                    ///< 196
  std::int16_t fix_year = 0;                           ///< 198
  std::uint32_t ms_today = 0;                          ///< 200: milliseconds since midnight UTC
  std::uint16_t max_abs_adc = 0;                       ///< 204
  std::array<std::int16_t, 2> reserved8{};             ///< 206
  std::array<char, 6> software_version{};              ///< 210
  std::int32_t spherical_correction = 0;               ///< 216: samples x 100, -1 = disabled
  std::uint16_t packet_number = 1;                     ///< 220
  std::int16_t adc_decimation = 0;                     ///< 222: x 100
  std::int16_t reserved9 = 0;                          ///< 224
  std::int16_t water_temperature_dc = 0;               ///< 226: 1/10 degree C
  float layback_m = 0.0f;                              ///< 228
  std::int32_t reserved10 = 0;                         ///< 232
  std::uint16_t cable_out_dm = 0;                      ///< 236
  std::uint16_t reserved11 = 0;                        ///< 238

  /// Samples per channel: offset 114 plus the MSB1 nibble (bits 8-11) << 16.
  std::uint32_t sample_count() const {
    return samples + (static_cast<std::uint32_t>((msb1 >> 8) & 0xFu) << 16);
  }
  /// int16 values per sample: 2 for the complex formats 1 and 9, else 1.
  std::uint32_t values_per_sample() const { return data_format == 1 || data_format == 9 ? 2 : 1; }

  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.i32(s.ping_time_s);
    io.u32(s.starting_depth);
    io.u32(s.ping_number);
    for (auto& v : s.reserved0) io.i16(v);
    io.u16(s.msb1);
    io.u16(s.lsb1);
    io.u16(s.lsb2);
    for (auto& v : s.reserved1) io.i16(v);
    io.i16(s.id_code);
    io.u16(s.validity_flags);
    io.u16(s.reserved2);
    io.i16(s.data_format);
    io.i16(s.tow_aft_cm);
    io.i16(s.tow_starboard_cm);
    for (auto& v : s.reserved3) io.i16(v);
    io.f32(s.km_of_pipe);
    io.f32(s.heave_m);
    for (auto& v : s.reserved4) io.i16(v);
    io.f32(s.gap_filler_offset_m);
    io.i32(s.longitude);
    io.i32(s.latitude);
    io.i16(s.coordinate_units);
    io.chars(s.annotation);
    io.u16(s.samples);
    io.u32(s.sample_interval_ns);
    io.u16(s.adc_gain);
    io.i16(s.transmit_level);
    io.i16(s.reserved5);
    io.u16(s.start_frequency_dahz);
    io.u16(s.end_frequency_dahz);
    io.u16(s.sweep_length_ms);
    io.i32(s.pressure_mpsi);
    io.i32(s.depth_mm);
    io.u16(s.sample_frequency_hz);
    io.u16(s.pulse_id);
    io.i32(s.altitude_mm);
    io.f32(s.sound_speed_m_s);
    io.f32(s.mixer_frequency_hz);
    io.i16(s.year);
    io.i16(s.day_of_year);
    io.i16(s.hour);
    io.i16(s.minute);
    io.i16(s.second);
    io.i16(s.time_basis);
    io.i16(s.weighting_factor);
    io.i16(s.pulses_in_water);
    io.u16(s.heading_cdeg);
    io.i16(s.pitch);
    io.i16(s.roll);
    io.i16(s.reserved6);
    io.i16(s.reserved7);
    io.i16(s.trigger_source);
    io.u16(s.mark_number);
    io.i16(s.fix_hour);
    io.i16(s.fix_minute);
    io.i16(s.fix_second);
    io.i16(s.course_deg);
    io.i16(s.speed_dkn);
    io.i16(s.fix_day_of_year);
    io.i16(s.fix_year);
    io.u32(s.ms_today);
    io.u16(s.max_abs_adc);
    for (auto& v : s.reserved8) io.i16(v);
    io.chars(s.software_version);
    io.i32(s.spherical_correction);
    io.u16(s.packet_number);
    io.i16(s.adc_decimation);
    io.i16(s.reserved9);
    io.i16(s.water_temperature_dc);
    io.f32(s.layback_m);
    io.i32(s.reserved10);
    io.u16(s.cable_out_dm);
    io.u16(s.reserved11);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static SonarDataHeader decode(ByteReader& r) { return read_fields<SonarDataHeader>(r); }
};

/// System information (type 182): the first 24 bytes (vendor bytes may follow).
struct SystemInformation {
  static constexpr std::size_t kSize = 24;
  std::int32_t system_type = 0;
  std::int32_t low_rate_io = 0;
  std::int32_t software_version = 0;
  std::int32_t subsystems = 0;
  std::int32_t serial_port_devices = 0;
  std::int32_t serial_number = 0;
  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.i32(s.system_type);
    io.i32(s.low_rate_io);
    io.i32(s.software_version);
    io.i32(s.subsystems);
    io.i32(s.serial_port_devices);
    io.i32(s.serial_number);
  }
  void encode(ByteWriter& w) const { write_fields(w, *this); }
  static SystemInformation decode(ByteReader& r) { return read_fields<SystemInformation>(r); }
};

/// Bytes in front of XtfFileFields and XtfPingFields: the tag "sonarsynth-xtf" (16 bytes, NUL
/// padded) and the layout number (u32).
inline constexpr std::size_t kXtfTagSize = 20;

/// What an XTF file held that JSF has no field for, carried by `convert` XTF -> JSF so that
/// JSF -> XTF restores it (docs/conversion.md, "Lossless round trip").
/// The file's: vendor bytes of the system information message 182, after its 24 bytes.
struct XtfFileFields {
  static constexpr std::size_t kSize = 260;
  static constexpr std::uint32_t kLayout = 1;
  std::array<char, 16> sonar_name{};   ///< XTFFILEHEADER SonarName
  std::array<char, 200> note{};        ///< the first NOTES packet's text, or else NoteString
  std::uint16_t bytes_per_sample = 0;  ///< CHANINFO[0] BytesPerSample, SampleFormat, UniPolar
  std::uint8_t sample_format = 0;
  std::uint8_t uni_polar = 0;
  float frequency_khz = 0.0f;  ///< CHANINFO[0], as the XTF stores them
  float horizontal_beam_angle_deg = 0.0f;
  float tilt_angle_deg = 0.0f;
  float beam_width_deg = 0.0f;
  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.chars(s.sonar_name);
    io.chars(s.note);
    io.u16(s.bytes_per_sample);
    io.u8(s.sample_format);
    io.u8(s.uni_polar);
    io.f32(s.frequency_khz);
    io.f32(s.horizontal_beam_angle_deg);
    io.f32(s.tilt_angle_deg);
    io.f32(s.beam_width_deg);
    io.reserved(4);
  }
  /// Tag "sonarsynth-xtf" (16 bytes), layout (u32), then the fields in order, 4 bytes reserved.
  void encode(ByteWriter& w) const;
  /// nullopt-like: false if the bytes do not start with the tag and layout.
  static bool decode(ByteReader& r, XtfFileFields& out);
};

/// A ping's: body of message kSonarsynthXtfPing, written right before the ping's port message.
struct XtfPingFields {
  static constexpr std::size_t kSize =
      kXtfTagSize + xtf::XtfPingHeader::kSize + 2 * xtf::XtfPingChanHeader::kSize;
  xtf::XtfPingHeader ping;                           ///< as the XTF stored it
  std::array<xtf::XtfPingChanHeader, 2> channels{};  ///< port, starboard
  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    xtf::XtfPingHeader::fields(io, s.ping);
    for (auto& c : s.channels) xtf::XtfPingChanHeader::fields(io, c);
  }
  /// Tag "sonarsynth-xtf" (16 bytes), layout (u32), then the three XTF records.
  void encode(ByteWriter& w) const;
  static bool decode(ByteReader& r, XtfPingFields& out);
};

}  // namespace sonarsynth::jsf
