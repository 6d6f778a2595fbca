// SPDX-License-Identifier: MIT
#pragma once

// Helpers for the XTF tests: temporary directories, whole-file bytes, a deterministic ping
// generator and a raw packet builder that assembles files from the records directly (so reader
// tests do not depend on the Writer).

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/xtf/records.hpp"

namespace sonarsynth::xtf::test {

inline std::filesystem::path temp_dir(const std::string& name) {
  return sonarsynth::test::fresh_temp_dir("xtf_" + name);
}

inline std::vector<std::uint8_t> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const std::filesystem::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// 2013-09-10 21:13:08 UTC plus `hundredths` * 10 ms.
inline UtcTime test_time(std::int64_t hundredths) {
  using namespace std::chrono;
  return UtcTime{sys_days{year{2013} / September / 10} + hours{21} + minutes{13} + seconds{8} +
                 milliseconds{10 * hundredths}};
}

/// A deterministic ping with integer samples in [0, 32767] (so u16 quantisation is exact).
inline SonarPing make_ping(std::uint32_t number, std::size_t port_n, std::size_t stbd_n) {
  SonarPing p;
  p.time_utc = test_time(7 * number);
  p.ping_number = number;
  p.sensor_position = {rad_from_deg(48.4455 + 1e-5 * number), rad_from_deg(-68.8283), 0.0};
  p.ship_position = Geodetic{rad_from_deg(48.4456), rad_from_deg(-68.8284), 0.0};
  p.heading_true_rad = rad_from_deg(10.0 + number);
  p.pitch_rad = rad_from_deg(-1.5);
  p.roll_rad = rad_from_deg(2.25);
  p.heave_m = 0.125;
  p.altitude_m = 8.5;
  p.depth_m = 20.25;
  p.speed_m_s = 2.0;
  p.sound_speed_m_s = 1490.0;
  p.slant_range_m = 50.0;
  for (std::size_t i = 0; i < port_n; ++i) {
    p.port.push_back(static_cast<float>(splitmix64(number * 100000 + i) % 32768));
  }
  for (std::size_t i = 0; i < stbd_n; ++i) {
    p.starboard.push_back(static_cast<float>(splitmix64(number * 100000 + 50000 + i) % 32768));
  }
  return p;
}

/// Assembles a file from records: a header, then packets appended as raw bytes.
struct RawFile {
  std::vector<std::uint8_t> bytes;

  template <typename Record>
  void append(const Record& r, std::size_t total_size = Record::kSize) {
    std::vector<std::uint8_t> b(total_size, 0);
    ByteWriter w(b);
    r.encode(w);
    bytes.insert(bytes.end(), b.begin(), b.end());
  }
  void append_raw(const std::vector<std::uint8_t>& b) {
    bytes.insert(bytes.end(), b.begin(), b.end());
  }
};

/// A file header with `n` channels of alternating PORT/STBD type and the given sample layout.
inline XtfFileHeader make_header(std::uint16_t n, std::uint16_t bytes_per_sample,
                                 std::uint8_t sample_format, std::uint16_t unipolar = 1) {
  XtfFileHeader h;
  h.NavUnits = 3;
  h.NumberOfSonarChannels = n;
  for (std::size_t i = 0; i < h.ChanInfo.size(); ++i) {
    h.ChanInfo[i].TypeOfChannel = static_cast<std::uint8_t>(i % 2 == 0 ? 1 : 2);
    h.ChanInfo[i].SubChannelNumber = static_cast<std::uint8_t>(i);
    h.ChanInfo[i].BytesPerSample = bytes_per_sample;
    h.ChanInfo[i].SampleFormat = sample_format;
    h.ChanInfo[i].UniPolar = unipolar;
  }
  return h;
}

/// A sonar packet: ping header + one channel header + raw sample bytes per channel, padded to 64.
inline std::vector<std::uint8_t> make_sonar_packet(
    std::uint32_t ping_number, const std::vector<std::uint16_t>& channel_numbers,
    const std::vector<std::vector<std::uint8_t>>& sample_bytes,
    const std::vector<std::uint32_t>& num_samples) {
  std::size_t raw = XtfPingHeader::kSize;
  for (const auto& s : sample_bytes) raw += XtfPingChanHeader::kSize + s.size();
  const std::size_t total = (raw + 63) / 64 * 64;
  std::vector<std::uint8_t> b(total, 0);
  ByteWriter w(b);
  XtfPingHeader h;
  h.Header.HeaderType = 0;
  h.Header.NumChansToFollow = static_cast<std::uint16_t>(channel_numbers.size());
  h.Header.NumBytesThisRecord = static_cast<std::uint32_t>(total);
  h.Year = 2013;
  h.Month = 9;
  h.Day = 10;
  h.Hour = 21;
  h.Minute = 13;
  h.Second = 8;
  h.HSeconds = static_cast<std::uint8_t>(ping_number % 100);
  h.PingNumber = ping_number;
  h.SoundVelocity = 750.0f;
  h.SensorXcoordinate = -68.83;
  h.SensorYcoordinate = 48.45;
  h.SensorPrimaryAltitude = 5.0f;
  h.encode(w);
  for (std::size_t c = 0; c < channel_numbers.size(); ++c) {
    XtfPingChanHeader ch;
    ch.ChannelNumber = channel_numbers[c];
    ch.SlantRange = 30.0f;
    ch.NumSamples = num_samples[c];
    ch.encode(w);
    for (std::uint8_t v : sample_bytes[c]) w.u8(v);
  }
  return b;
}

}  // namespace sonarsynth::xtf::test
