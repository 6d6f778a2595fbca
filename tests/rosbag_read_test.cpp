// SPDX-License-Identifier: MIT
// ROS 1 bag reader (docs/rosbag.md, "Reading bags"): pings written by the bag writer read back;
// XTF -> bag -> XTF through `convert` keeps every sample and the navigation fields; damaged
// bags give FormatError naming the file, the byte offset and the field, never a crash.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "bag_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/rosbag/reader.hpp"
#include "sonarsynth/formats/rosbag/writer.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::rosbag {
namespace {

namespace fs = std::filesystem;
using test::varied_ping;
using test::xtf_pings;

TEST(RosbagReader, ReadsWhatTheWriterWrote) {
  const fs::path dir = xtf::test::temp_dir("rosbag_read");
  WriterOptions o;
  o.chunk_bytes = 2000;  // several chunks, pings split across them
  o.frequency_hz = 455e3;
  Writer w(dir / "a.bag", o);
  std::vector<SonarPing> in;
  for (std::uint32_t k = 0; k < 12; ++k) {
    in.push_back(varied_ping(k));
    w.write_ping(in.back());
    AttitudeSample a;  // an attitude message at the ping's time: the ping keeps its own
    a.time_utc = in.back().time_utc;
    a.heading_true_rad = 1.0;
    w.write_attitude(a);
  }
  w.close();
  Reader r(dir / "a.bag");
  EXPECT_GT(r.chunk_count(), 3u);
  ASSERT_TRUE(r.image_info());
  EXPECT_EQ(r.image_info()->frequency_hz, 455e3);
  EXPECT_EQ(r.image_info()->dtype, 2u);
  Ping p;
  std::size_t n = 0;
  while (r.next_ping(p)) {
    ASSERT_LT(n, in.size());
    const SonarPing& e = in[n++];
    EXPECT_EQ(p.sonar.ping_number, e.ping_number);
    EXPECT_EQ(p.nav_valid, e.ping_number != 5);
    ASSERT_NO_FATAL_FAILURE(test::expect_read_back(p, e));
  }
  EXPECT_EQ(n, in.size());
  EXPECT_EQ(r.total_anomalies(), 0u);
  // The attitude-only messages are the ones no ping took.
  std::size_t unused = 0;
  for (const ImuSample& s : r.imu()) unused += s.used ? 0u : 1u;
  EXPECT_EQ(unused, in.size());
  fs::remove_all(dir);
}

TEST(RosbagReader, XtfToBagToXtfKeepsSamplesAndNavigation) {
  const fs::path dir = xtf::test::temp_dir("rosbag_round_trip");
  {
    xtf::WriterOptions o;
    o.frequency_khz = 455.0;
    o.tilt_angle_rad = rad_from_deg(20.0);
    o.horizontal_beam_angle_rad = rad_from_deg(0.75);
    o.vertical_beam_width_rad = rad_from_deg(45.0);
    // Attitude packets between pings: Imu messages of their own.
    test::write_round_trip_xtf(dir / "a.xtf", o);
  }
  const ConvertResult to_bag = convert_sonar_file(dir / "a.xtf", dir / "a.bag", false);
  EXPECT_EQ(to_bag.pings, 19u);
  EXPECT_EQ(to_bag.attitude_records, 7u);
  EXPECT_EQ(identify_sonar_format(dir / "a.bag"), find_sonar_format("rosbag"));
  const ConvertResult back = convert_sonar_file(dir / "a.bag", dir / "b.xtf", false);
  EXPECT_EQ(back.pings, 19u);
  EXPECT_EQ(back.pings_skipped, 0u);
  EXPECT_EQ(back.attitude_records, 7u);
  test::expect_same_attitudes(dir / "a.xtf", dir / "b.xtf", 1e-5);
  // The sonar settings: PingInfo and the port frame's transform on /tf_static.
  const xtf::XtfChanInfo ca = xtf::Reader(dir / "a.xtf").chan_info().at(0);
  const xtf::XtfChanInfo cb = xtf::Reader(dir / "b.xtf").chan_info().at(0);
  EXPECT_EQ(cb.Frequency, ca.Frequency);
  EXPECT_NEAR(cb.TiltAngle, ca.TiltAngle, 1e-4);  // degrees
  EXPECT_NEAR(cb.HorizBeamAngle, ca.HorizBeamAngle, 1e-4);
  EXPECT_NEAR(cb.BeamWidth, ca.BeamWidth, 1e-4);
  const auto a = xtf_pings(dir / "a.xtf");
  const auto b = xtf_pings(dir / "b.xtf");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    const xtf::XtfPingHeader& ha = a[k].header;
    const xtf::XtfPingHeader& hb = b[k].header;
    EXPECT_EQ(a[k].sonar.port, b[k].sonar.port);
    EXPECT_EQ(a[k].sonar.starboard, b[k].sonar.starboard);
    EXPECT_EQ(hb.PingNumber, ha.PingNumber);
    EXPECT_EQ(b[k].sonar.time_utc, a[k].sonar.time_utc);
    // Degrees -> the pings' radians -> the bag's degrees -> radians -> degrees: equal to a few
    // double ulps (1e-14 degree is 1 nm).
    EXPECT_NEAR(hb.SensorXcoordinate, ha.SensorXcoordinate, 1e-12);
    EXPECT_NEAR(hb.SensorYcoordinate, ha.SensorYcoordinate, 1e-12);
    EXPECT_EQ(hb.SensorHeading, ha.SensorHeading);
    EXPECT_EQ(hb.SensorPitch, ha.SensorPitch);
    EXPECT_EQ(hb.SensorRoll, ha.SensorRoll);
    EXPECT_EQ(b[k].sonar.sound_speed_m_s, a[k].sonar.sound_speed_m_s);
    EXPECT_NEAR(b[k].sonar.slant_range_m, a[k].sonar.slant_range_m, 1e-5);
  }
  // And on to JSF, through the same reader.
  const ConvertResult to_jsf = convert_sonar_file(dir / "a.bag", dir / "c.jsf", false);
  EXPECT_EQ(to_jsf.pings, 19u);
  auto source = SideScanSource::open(dir / "c.jsf");
  SideScanRecord rec;
  std::size_t n = 0;
  while (source->next(rec)) {
    EXPECT_EQ(rec.sonar.port, a[n].sonar.port);
    ++n;
  }
  EXPECT_EQ(n, a.size());
  EXPECT_FALSE(fs::exists(dir / ".~c.jsf.xtf"));
  fs::remove_all(dir);
}

// A bag assembled record by record (bytes in a std::string), for damaged inputs.
std::string le(std::uint64_t x, int n) {
  std::string v;
  for (int i = 0; i < n; ++i) v += static_cast<char>((x >> (8 * i)) & 0xFFu);
  return v;
}
std::string field(const std::string& name, const std::string& value) {
  return le(name.size() + 1 + value.size(), 4) + name + "=" + value;
}
std::string record(const std::string& header, const std::string& data = "") {
  return le(header.size(), 4) + header + le(data.size(), 4) + data;
}

/// Magic, bag header, one chunk of `compression` holding nothing, the chunk info.
std::vector<std::uint8_t> bag_with_chunk(const std::string& compression, bool chunk_pos,
                                         char info_op = 6) {
  const std::string magic = "#ROSBAG V2.0\n";
  const auto header = [](std::uint64_t index_pos) {
    return record(field("op", "\x03") + field("index_pos", le(index_pos, 8)) +
                  field("conn_count", le(0, 4)) + field("chunk_count", le(1, 4)));
  };
  const std::uint64_t chunk_at = magic.size() + header(0).size();
  const std::string chunk =
      record(field("op", "\x05") + field("compression", compression) + field("size", le(0, 4)));
  std::string info =
      field("op", std::string(1, info_op)) + field("ver", le(1, 4)) + field("count", le(0, 4));
  if (chunk_pos) info += field("chunk_pos", le(chunk_at, 8));
  const std::string bytes = magic + header(chunk_at + chunk.size()) + chunk + record(info);
  return {bytes.begin(), bytes.end()};
}

std::string error_of(const std::vector<std::uint8_t>& bytes) {
  try {
    Reader r(bytes, "damaged.bag");
    Ping p;
    while (r.next_ping(p)) {
    }
  } catch (const FormatError& e) {
    return e.what();
  }
  return "";
}

TEST(RosbagReader, DamagedBagsGiveNamedErrors) {
  EXPECT_EQ(error_of(bag_with_chunk("none", true)), "");
  const std::string bz2 = error_of(bag_with_chunk("bz2", true));  // its chunk at 13 + 77
  EXPECT_NE(bz2.find("damaged.bag: byte 90: chunk compression = 'bz2'"), std::string::npos) << bz2;
  const std::string missing = error_of(bag_with_chunk("none", false));
  EXPECT_NE(missing.find("'chunk_pos' missing"), std::string::npos) << missing;
  const std::string unknown = error_of(bag_with_chunk("none", true, 9));
  EXPECT_NE(unknown.find("op = 9"), std::string::npos) << unknown;
  EXPECT_NE(error_of({}).find("not a ROS bag 2.0"), std::string::npos);
  // A real bag cut anywhere, or with a length made huge: a FormatError, never a crash.
  const fs::path dir = xtf::test::temp_dir("rosbag_damaged");
  const std::vector<std::uint8_t> good =
      test::four_ping_bag<Writer, WriterOptions>(dir / "a.bag", 1500);
  EXPECT_EQ(error_of(good), "");
  test::expect_cuts_named_and_damage_survived(
      good, 97, "damaged.bag", [](const std::vector<std::uint8_t>& b) { return error_of(b); });
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth::rosbag
