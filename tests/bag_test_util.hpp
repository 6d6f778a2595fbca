// SPDX-License-Identifier: MIT
// What the ROS 1 bag and MCAP reader tests share: the pings they write and the XTF packets they
// compare with.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::test {

/// Pings with headings all round the circle, pitch and roll of both signs, ping 5 without a
/// position; u16 samples in 0..32767.
inline SonarPing varied_ping(std::uint32_t k) {
  SonarPing p = xtf::test::make_ping(k, 120 + k % 3, 120 + k % 3);
  p.heading_true_rad = rad_from_deg(std::fmod(37.0 * k + 0.125, 360.0));
  p.pitch_rad = rad_from_deg(k % 2 ? -3.5 : 4.25);
  p.roll_rad = rad_from_deg(k % 3 ? 7.0 : -12.5);
  if (k == 5) p.sensor_position = {};
  return p;
}

/// A ping a bag reader read (`p`, a rosbag::Ping) equals the ping written (`x`): time,
/// samples, position (when `p` has one), attitude, sound speed and slant range.
template <class BagPing>
void expect_read_back(const BagPing& p, const SonarPing& x) {
  EXPECT_EQ(p.sonar.time_utc, x.time_utc);
  EXPECT_EQ(p.sonar.port, x.port);
  EXPECT_EQ(p.sonar.starboard, x.starboard);
  if (p.nav_valid) {
    EXPECT_NEAR(p.sonar.sensor_position.lat_rad, x.sensor_position.lat_rad, 1e-15);
    EXPECT_NEAR(p.sonar.sensor_position.lon_rad, x.sensor_position.lon_rad, 1e-15);
  }
  ASSERT_TRUE(p.attitude_valid);
  EXPECT_NEAR(p.sonar.heading_true_rad, x.heading_true_rad, 1e-12);
  EXPECT_NEAR(p.sonar.pitch_rad, x.pitch_rad, 1e-12);
  EXPECT_NEAR(p.sonar.roll_rad, x.roll_rad, 1e-12);
  EXPECT_NEAR(p.sonar.sound_speed_m_s, x.sound_speed_m_s, 1e-4);
  EXPECT_NEAR(p.sonar.slant_range_m, x.slant_range_m, 1e-5);
}

/// The bytes of a bag written at `path` by a BagWriter with chunks of `chunk_bytes` (its other
/// options the defaults): varied pings 0 to 3.
template <class BagWriter, class BagWriterOptions>
std::vector<std::uint8_t> four_ping_bag(const std::filesystem::path& path,
                                        std::size_t chunk_bytes) {
  {
    BagWriterOptions o;
    o.chunk_bytes = chunk_bytes;
    BagWriter w(path, o);
    for (std::uint32_t k = 0; k < 4; ++k) w.write_ping(varied_ping(k));
    w.close();
  }
  return xtf::test::read_bytes(path);
}

/// The bag `good` cut every `step` bytes gives an error naming `name`, and 400 copies with two
/// bytes overwritten read or throw FormatError, never crash. `error_of(bytes)`: the reader's
/// FormatError message, "" if the bytes read.
template <class ErrorOf>
void expect_cuts_named_and_damage_survived(const std::vector<std::uint8_t>& good, std::size_t step,
                                           const std::string& name, ErrorOf error_of) {
  for (std::size_t cut = 0; cut < good.size(); cut += step) {
    const std::string e = error_of(
        std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut)));
    EXPECT_NE(e.find(name), std::string::npos) << cut;
  }
  for (std::size_t k = 0; k < 400; ++k) {
    std::vector<std::uint8_t> bad = good;
    const std::uint64_t h = xtf::test::splitmix64(k);
    bad[h % bad.size()] = static_cast<std::uint8_t>(h >> 32);
    bad[(h >> 40) % bad.size()] = 0xFF;
    (void)error_of(bad);  // either reads or throws FormatError
  }
}

/// The ping packets of an XTF file.
inline std::vector<xtf::PingRecord> xtf_pings(const std::filesystem::path& path) {
  xtf::Reader r(path);
  xtf::Packet packet;
  std::vector<xtf::PingRecord> out;
  while (r.next(packet)) {
    if (packet.kind == xtf::PacketKind::kPing) out.push_back(packet.ping);
  }
  return out;
}

/// The attitude packets of an XTF file.
inline std::vector<AttitudeSample> xtf_attitudes(const std::filesystem::path& path) {
  xtf::Reader r(path);
  xtf::Packet packet;
  std::vector<AttitudeSample> out;
  while (r.next(packet)) {
    if (packet.kind == xtf::PacketKind::kAttitude) {
      out.push_back(xtf::attitude_sample(packet.attitude));
    }
  }
  return out;
}

/// An attitude packet 37 ms after ping `p` (number `k`): a heading, pitch and roll of its own.
inline AttitudeSample attitude_after(const SonarPing& p, std::uint32_t k) {
  return {p.time_utc + std::chrono::milliseconds(37),
          rad_from_deg(std::fmod(11.0 * k + 350.5, 360.0)),
          rad_from_deg(-2.0 + k),
          rad_from_deg(5.0 - 0.5 * k),
          0.0,
          0.0};
}

/// Writes XTF `path` with the options `o`: varied pings 0 to 19 but ping 5 (XTF refuses a ping
/// without a position), and after every third ping (1, 4, 7...) an attitude packet of its own.
inline void write_round_trip_xtf(const std::filesystem::path& path, const xtf::WriterOptions& o) {
  xtf::Writer w(path, o);
  for (std::uint32_t k = 0; k < 20; ++k) {
    const SonarPing p = varied_ping(k);
    if (k != 5) w.write_ping(p);
    if (k % 3 == 1) w.write_attitude(attitude_after(p, k));
  }
  w.close();
}

/// Every attitude packet of XTF `a` is in XTF `b`, in order: the time exactly, heading, pitch and
/// roll to `tolerance_deg` (heave and yaw are not carried by a ROS Imu message).
inline void expect_same_attitudes(const std::filesystem::path& a, const std::filesystem::path& b,
                                  double tolerance_deg) {
  const std::vector<AttitudeSample> aa = xtf_attitudes(a);
  const std::vector<AttitudeSample> ab = xtf_attitudes(b);
  ASSERT_EQ(ab.size(), aa.size());
  for (std::size_t i = 0; i < aa.size(); ++i) {
    EXPECT_EQ(ab[i].time_utc, aa[i].time_utc) << "attitude " << i;
    const double heading_error_deg =
        std::remainder(deg_from_rad(ab[i].heading_true_rad - aa[i].heading_true_rad), 360.0);
    EXPECT_LT(std::abs(heading_error_deg), tolerance_deg) << "attitude " << i;
    EXPECT_NEAR(deg_from_rad(ab[i].pitch_rad), deg_from_rad(aa[i].pitch_rad), tolerance_deg);
    EXPECT_NEAR(deg_from_rad(ab[i].roll_rad), deg_from_rad(aa[i].roll_rad), tolerance_deg);
  }
}

}  // namespace sonarsynth::test
