// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/jsf/records.hpp"

#include <algorithm>
#include <string>
#include <string_view>

#include "sonarsynth/error.hpp"

namespace sonarsynth::jsf {

const char* message_type_name(std::uint16_t type) {
  switch (type) {
    case 40:
      return "sonar message status";
    case 80:
      return "sonar data";
    case 82:
      return "side scan data (old)";
    case 86:
      return "4400-SAS processed data";
    case 181:
      return "navigation offsets";
    case 182:
      return "system information";
    case 426:
      return "file timestamp";
    case 428:
      return "file padding";
    case 1260:
      return "target file data";
    case 2000:
      return "serial port raw data";
    case 2002:
      return "NMEA string";
    case 2020:
      return "pitch/roll";
    case 2040:
      return "miscellaneous analog sensors";
    case 2060:
      return "pressure sensor";
    case 2080:
      return "Doppler velocity log";
    case 2090:
      return "situation";
    case 2091:
      return "situation comprehensive";
    case 9999:
      return "sonarsynth XTF ping fields";
    case 2100:
      return "cable counter";
    case 2101:
      return "kilometre of pipe";
    case 2111:
      return "container timestamp";
    default:
      break;
  }
  return nullptr;
}

void MessageHeader::encode(ByteWriter& w) const {
  w.u16(start_marker);
  w.u8(protocol_version);
  w.u8(session_id);
  w.u16(message_type);
  w.u8(command_type);
  w.u8(subsystem);
  w.u8(channel);
  w.u8(sequence);
  w.u16(reserved);
  w.i32(byte_count);
}

MessageHeader MessageHeader::decode(ByteReader& r) {
  MessageHeader h;
  h.start_marker = r.u16();
  h.protocol_version = r.u8();
  h.session_id = r.u8();
  h.message_type = r.u16();
  h.command_type = r.u8();
  h.subsystem = r.u8();
  h.channel = r.u8();
  h.sequence = r.u8();
  h.reserved = r.u16();
  h.byte_count = r.i32();
  return h;
}

void SonarDataHeader::encode(ByteWriter& w) const {
  const std::size_t start = w.position();
  w.i32(ping_time_s);
  w.u32(starting_depth);
  w.u32(ping_number);
  for (const std::int16_t v : reserved0) w.i16(v);
  w.u16(msb1);
  w.u16(lsb1);
  w.u16(lsb2);
  for (const std::int16_t v : reserved1) w.i16(v);
  w.i16(id_code);
  w.u16(validity_flags);
  w.u16(reserved2);
  w.i16(data_format);
  w.i16(tow_aft_cm);
  w.i16(tow_starboard_cm);
  for (const std::int16_t v : reserved3) w.i16(v);
  w.f32(km_of_pipe);
  w.f32(heave_m);
  for (const std::int16_t v : reserved4) w.i16(v);
  w.f32(gap_filler_offset_m);
  w.i32(longitude);
  w.i32(latitude);
  w.i16(coordinate_units);
  w.chars(annotation);
  w.u16(samples);
  w.u32(sample_interval_ns);
  w.u16(adc_gain);
  w.i16(transmit_level);
  w.i16(reserved5);
  w.u16(start_frequency_dahz);
  w.u16(end_frequency_dahz);
  w.u16(sweep_length_ms);
  w.i32(pressure_mpsi);
  w.i32(depth_mm);
  w.u16(sample_frequency_hz);
  w.u16(pulse_id);
  w.i32(altitude_mm);
  w.f32(sound_speed_mps);
  w.f32(mixer_frequency_hz);
  w.i16(year);
  w.i16(day_of_year);
  w.i16(hour);
  w.i16(minute);
  w.i16(second);
  w.i16(time_basis);
  w.i16(weighting_factor);
  w.i16(pulses_in_water);
  w.u16(heading_cdeg);
  w.i16(pitch);
  w.i16(roll);
  w.i16(reserved6);
  w.i16(reserved7);
  w.i16(trigger_source);
  w.u16(mark_number);
  w.i16(fix_hour);
  w.i16(fix_minute);
  w.i16(fix_second);
  w.i16(course_deg);
  w.i16(speed_dkn);
  w.i16(fix_day_of_year);
  w.i16(fix_year);
  w.u32(ms_today);
  w.u16(max_abs_adc);
  for (const std::int16_t v : reserved8) w.i16(v);
  w.chars(software_version);
  w.i32(spherical_correction);
  w.u16(packet_number);
  w.i16(adc_decimation);
  w.i16(reserved9);
  w.i16(water_temperature_dc);
  w.f32(layback_m);
  w.i32(reserved10);
  w.u16(cable_out_dm);
  w.u16(reserved11);
  if (w.position() - start != kSize) {
    throw FormatError("jsf: sonar data header encoded to " + std::to_string(w.position() - start) +
                      " bytes instead of 240");
  }
}

SonarDataHeader SonarDataHeader::decode(ByteReader& r) {
  SonarDataHeader h;
  h.ping_time_s = r.i32();
  h.starting_depth = r.u32();
  h.ping_number = r.u32();
  for (std::int16_t& v : h.reserved0) v = r.i16();
  h.msb1 = r.u16();
  h.lsb1 = r.u16();
  h.lsb2 = r.u16();
  for (std::int16_t& v : h.reserved1) v = r.i16();
  h.id_code = r.i16();
  h.validity_flags = r.u16();
  h.reserved2 = r.u16();
  h.data_format = r.i16();
  h.tow_aft_cm = r.i16();
  h.tow_starboard_cm = r.i16();
  for (std::int16_t& v : h.reserved3) v = r.i16();
  h.km_of_pipe = r.f32();
  h.heave_m = r.f32();
  for (std::int16_t& v : h.reserved4) v = r.i16();
  h.gap_filler_offset_m = r.f32();
  h.longitude = r.i32();
  h.latitude = r.i32();
  h.coordinate_units = r.i16();
  r.chars(h.annotation);
  h.samples = r.u16();
  h.sample_interval_ns = r.u32();
  h.adc_gain = r.u16();
  h.transmit_level = r.i16();
  h.reserved5 = r.i16();
  h.start_frequency_dahz = r.u16();
  h.end_frequency_dahz = r.u16();
  h.sweep_length_ms = r.u16();
  h.pressure_mpsi = r.i32();
  h.depth_mm = r.i32();
  h.sample_frequency_hz = r.u16();
  h.pulse_id = r.u16();
  h.altitude_mm = r.i32();
  h.sound_speed_mps = r.f32();
  h.mixer_frequency_hz = r.f32();
  h.year = r.i16();
  h.day_of_year = r.i16();
  h.hour = r.i16();
  h.minute = r.i16();
  h.second = r.i16();
  h.time_basis = r.i16();
  h.weighting_factor = r.i16();
  h.pulses_in_water = r.i16();
  h.heading_cdeg = r.u16();
  h.pitch = r.i16();
  h.roll = r.i16();
  h.reserved6 = r.i16();
  h.reserved7 = r.i16();
  h.trigger_source = r.i16();
  h.mark_number = r.u16();
  h.fix_hour = r.i16();
  h.fix_minute = r.i16();
  h.fix_second = r.i16();
  h.course_deg = r.i16();
  h.speed_dkn = r.i16();
  h.fix_day_of_year = r.i16();
  h.fix_year = r.i16();
  h.ms_today = r.u32();
  h.max_abs_adc = r.u16();
  for (std::int16_t& v : h.reserved8) v = r.i16();
  r.chars(h.software_version);
  h.spherical_correction = r.i32();
  h.packet_number = r.u16();
  h.adc_decimation = r.i16();
  h.reserved9 = r.i16();
  h.water_temperature_dc = r.i16();
  h.layback_m = r.f32();
  h.reserved10 = r.i32();
  h.cable_out_dm = r.u16();
  h.reserved11 = r.u16();
  return h;
}

void SystemInformation::encode(ByteWriter& w) const {
  w.i32(system_type);
  w.i32(low_rate_io);
  w.i32(software_version);
  w.i32(subsystems);
  w.i32(serial_port_devices);
  w.i32(serial_number);
}

SystemInformation SystemInformation::decode(ByteReader& r) {
  SystemInformation s;
  s.system_type = r.i32();
  s.low_rate_io = r.i32();
  s.software_version = r.i32();
  s.subsystems = r.i32();
  s.serial_port_devices = r.i32();
  s.serial_number = r.i32();
  return s;
}

namespace {
constexpr std::string_view kXtfTag = "sonarsynth-xtf";

void encode_tag(ByteWriter& w) {
  std::array<char, 16> tag{};
  std::copy(kXtfTag.begin(), kXtfTag.end(), tag.begin());
  w.chars(tag);
  w.u32(XtfFileFields::kLayout);
}

bool decode_tag(ByteReader& r) {
  std::array<char, 16> tag{};
  r.chars(tag);
  const std::uint32_t layout = r.u32();
  return std::string_view(tag.data(), kXtfTag.size()) == kXtfTag && tag[kXtfTag.size()] == 0 &&
         layout == XtfFileFields::kLayout;
}
}  // namespace

void XtfFileFields::encode(ByteWriter& w) const {
  encode_tag(w);
  w.chars(sonar_name);
  w.chars(note);
  w.u16(bytes_per_sample);
  w.u8(sample_format);
  w.u8(uni_polar);
  w.f32(frequency_khz);
  w.f32(horizontal_beam_angle_deg);
  w.f32(tilt_angle_deg);
  w.f32(beam_width_deg);
  w.u32(0);
}

bool XtfFileFields::decode(ByteReader& r, XtfFileFields& f) {
  if (!decode_tag(r)) return false;
  r.chars(f.sonar_name);
  r.chars(f.note);
  f.bytes_per_sample = r.u16();
  f.sample_format = r.u8();
  f.uni_polar = r.u8();
  f.frequency_khz = r.f32();
  f.horizontal_beam_angle_deg = r.f32();
  f.tilt_angle_deg = r.f32();
  f.beam_width_deg = r.f32();
  r.skip(4);
  return true;
}

void XtfPingFields::encode(ByteWriter& w) const {
  encode_tag(w);
  ping.encode(w);
  for (const auto& c : channels) c.encode(w);
}

bool XtfPingFields::decode(ByteReader& r, XtfPingFields& f) {
  if (!decode_tag(r)) return false;
  f.ping = xtf::XtfPingHeader::decode(r);
  for (auto& c : f.channels) c = xtf::XtfPingChanHeader::decode(r);
  return true;
}

}  // namespace sonarsynth::jsf
