// SPDX-License-Identifier: MIT
// What the ROS 1 bag and MCAP reader tests share: the pings they write and the XTF packets they
// compare with.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "sonarsynth/formats/io/sonar_ping.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
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
