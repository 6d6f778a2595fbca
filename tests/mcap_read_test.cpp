// SPDX-License-Identifier: MIT
// MCAP reader (docs/robotics.md, "Reading bags"): pings written by the MCAP writer read back;
// XTF -> MCAP -> XTF through `convert` keeps every sample and the navigation fields (a test run
// and a real survey file); bags written by independent code (@mcap/core, tests/mcap_reader)
// with other topics and frames, uncompressed, unchunked or without summary; damaged files give
// FormatError naming the file, the byte offset and the field, never a crash.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bag_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/mcap/read_records.hpp"
#include "sonarsynth/formats/mcap/reader.hpp"
#include "sonarsynth/formats/mcap/writer.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::mcap {
namespace {

namespace fs = std::filesystem;
using test::varied_ping;
using test::xtf_attitudes;
using test::xtf_pings;
using xtf::test::make_ping;

TEST(McapReader, ReadsWhatTheWriterWrote) {
  const fs::path dir = xtf::test::temp_dir("mcap_read");
  for (const auto e :
       {xtf::SampleEncoding::kUint16, xtf::SampleEncoding::kUint8, xtf::SampleEncoding::kFloat32}) {
    WriterOptions o;
    o.chunk_bytes = 2000;  // several chunks
    o.frequency_hz = 455e3;
    o.sample_encoding = e;
    o.overwrite = true;
    Writer w(dir / "a.mcap", o);
    std::vector<SonarPing> in;
    for (std::uint32_t k = 0; k < 12; ++k) {
      in.push_back(varied_ping(k));
      if (e == xtf::SampleEncoding::kUint8) {
        for (float& v : in.back().port) v = std::fmod(v, 256.0f);
        for (float& v : in.back().starboard) v = std::fmod(v, 256.0f);
      }
      w.write_ping(in.back());
    }
    w.close();
    Reader r(dir / "a.mcap");
    EXPECT_TRUE(r.indexed());
    EXPECT_GT(r.chunk_count(), 3u);
    EXPECT_EQ(r.profile(), "ros2");
    ASSERT_TRUE(r.image_info());
    EXPECT_EQ(r.image_info()->frequency_hz, 455e3);
    EXPECT_NEAR(r.image_info()->tilt_rad, o.tilt_rad, 1e-12);
    Ping p;
    std::size_t n = 0;
    while (r.next_ping(p)) {
      ASSERT_LT(n, in.size());
      const SonarPing& x = in[n];
      EXPECT_EQ(p.sonar.ping_number, n);  // the Message sequence
      EXPECT_EQ(p.nav_valid, n != 5);
      ASSERT_NO_FATAL_FAILURE(test::expect_read_back(p, x));
      ++n;
    }
    EXPECT_EQ(n, in.size());
    EXPECT_EQ(r.total_anomalies(), 0u);
  }
  fs::remove_all(dir);
}

/// XTF `a` -> MCAP -> XTF `b`: every ping of `a` with a position is in `b` with the same
/// samples, time, position, attitude and sound speed, and every attitude packet of `a` is in `b`
/// with its time and angles.
void expect_round_trip(const fs::path& a, const fs::path& dir, std::size_t without_position) {
  const ConvertResult to_bag = convert_sonar_file(a, dir / "a.mcap", true);
  EXPECT_EQ(identify_sonar_format(dir / "a.mcap"), find_sonar_format("mcap"));
  const ConvertResult back = convert_sonar_file(dir / "a.mcap", dir / "b.xtf", true);
  EXPECT_EQ(back.pings + without_position, to_bag.pings);
  EXPECT_EQ(back.reader_anomalies, 0u);
  const std::size_t attitudes = xtf_attitudes(a).size();
  EXPECT_EQ(to_bag.attitude_records, attitudes);
  EXPECT_EQ(back.attitude_records, attitudes);
  // The XTF's float degrees through a quaternion, back to float degrees.
  test::expect_same_attitudes(a, dir / "b.xtf", 1e-5);
  const xtf::XtfChanInfo ca = xtf::Reader(a).chan_info().at(0);
  const xtf::XtfChanInfo cb = xtf::Reader(dir / "b.xtf").chan_info().at(0);
  EXPECT_EQ(cb.Frequency, ca.Frequency);
  EXPECT_EQ(cb.BytesPerSample, ca.BytesPerSample);
  const auto pa = xtf_pings(a);
  const auto pb = xtf_pings(dir / "b.xtf");
  std::size_t k = 0, skipped = 0;
  for (const xtf::PingRecord& x : pa) {
    if (!x.nav_valid) {
      ++skipped;
      continue;
    }
    ASSERT_LT(k, pb.size());
    const xtf::PingRecord& y = pb[k++];
    EXPECT_EQ(y.sonar.port, x.sonar.port);
    EXPECT_EQ(y.sonar.starboard, x.sonar.starboard);
    EXPECT_EQ(y.sonar.time_utc, x.sonar.time_utc);
    // Degrees -> radians -> the bag's degrees -> radians -> degrees: a few double ulps.
    EXPECT_NEAR(y.header.SensorXcoordinate, x.header.SensorXcoordinate, 1e-12);
    EXPECT_NEAR(y.header.SensorYcoordinate, x.header.SensorYcoordinate, 1e-12);
    // The XTF's float degrees through a quaternion: equal to float precision.
    EXPECT_NEAR(y.header.SensorHeading, x.header.SensorHeading, 1e-5);
    EXPECT_NEAR(y.header.SensorPitch, x.header.SensorPitch, 1e-5);
    EXPECT_NEAR(y.header.SensorRoll, x.header.SensorRoll, 1e-5);
    EXPECT_EQ(y.sonar.sound_speed_m_s, x.sonar.sound_speed_m_s);
    EXPECT_NEAR(y.sonar.slant_range_m, x.sonar.slant_range_m, 1e-5 * x.sonar.slant_range_m);
  }
  EXPECT_EQ(k, pb.size());
  EXPECT_EQ(skipped, without_position);
}

TEST(McapReader, XtfToMcapToXtfKeepsSamplesAndNavigation) {
  const fs::path dir = xtf::test::temp_dir("mcap_round_trip");
  {
    xtf::WriterOptions o;
    o.frequency_khz = 455.0;
    // Attitude packets between pings: Imu messages of their own.
    test::write_round_trip_xtf(dir / "a.xtf", o);
  }
  expect_round_trip(dir / "a.xtf", dir, 0);
  // A real survey (docs/conversion.md): its first ping has no position.
  expect_round_trip(fs::path(SONARSYNTH_TEST_DATA_DIR) / "xtf" / "scotsman-iver2.xtf", dir, 1);
  // And on to JSF through the same reader.
  const ConvertResult to_jsf = convert_sonar_file(dir / "a.mcap", dir / "c.jsf", true);
  const auto b = xtf_pings(dir / "b.xtf");
  EXPECT_EQ(to_jsf.pings, b.size());
  auto source = SideScanSource::open(dir / "c.jsf");
  SideScanRecord rec;
  std::size_t n = 0;
  while (source->next(rec)) EXPECT_EQ(rec.sonar.port, b.at(n++).sonar.port);
  EXPECT_EQ(n, b.size());
  fs::remove_all(dir);
}

// A bag written by independent code (tests/mcap_reader/write_foreign.js): other topics and
// frames, found by schema; uncompressed chunks, no chunks, no summary.
TEST(McapReader, BagsOfOtherWritersRead) {
  const fs::path modules = SONARSYNTH_MCAP_READER_MODULES;
  if (!fs::exists(modules / "@mcap" / "core")) {
    GTEST_SKIP() << "the npm packages are not installed (" << modules.string()
                 << " missing): run tests/mcap_reader/install.sh BUILD_DIR (scripts/test.sh does)";
  }
  const fs::path dir = xtf::test::temp_dir("mcap_foreign");
  {
    Writer w(dir / "schemas.mcap");
    w.write_ping(make_ping(0, 4, 4));
    w.close();
  }
  for (const std::string mode : {"indexed", "unchunked", "nosummary"}) {
    const fs::path bag = dir / (mode + ".mcap");
    const std::string command =
        "NODE_PATH='" + modules.string() + "' node '" + SONARSYNTH_MCAP_WRITE_FOREIGN + "' '" +
        (dir / "schemas.mcap").string() + "' '" + bag.string() + "' " + mode;
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const auto info = nlohmann::json::parse(sonar_file_info(bag).json);
    EXPECT_EQ(info["format"], "MCAP");
    EXPECT_EQ(info["library"], "write_foreign.js");
    EXPECT_EQ(info["indexed"], mode == "indexed") << mode;
    EXPECT_EQ(info["pings"], 6);
    EXPECT_EQ(info["pings_with_valid_navigation"], 6);
    EXPECT_EQ(info["pings_with_attitude"], 6);
    EXPECT_EQ(info["anomaly_count"], 0) << info.dump(1);
    std::map<std::string, nlohmann::json> read_as;
    for (const auto& c : info["channels"]) read_as[c["topic"]] = c["read_as"];
    EXPECT_EQ(read_as["/robot/sss/raw"], "side-scan images");
    EXPECT_EQ(read_as["/robot/gps/fix"], "navigation");
    EXPECT_EQ(read_as["/robot/imu/data"], "attitude");
    EXPECT_TRUE(read_as["/robot/status"].is_null());
    const std::vector<std::uint8_t> bytes = xtf::test::read_bytes(bag);
    if (mode == "nosummary") {  // footer summary_start = 0
      EXPECT_EQ(read::le(bytes.data() + bytes.size() - 8 - 20, 8), 0u);
    }
    Reader r(bag);
    Ping p;
    std::uint32_t k = 0;
    while (r.next_ping(p)) {
      for (std::uint32_t i = 0; i < 250; ++i) {
        EXPECT_EQ(p.sonar.port.at(i), static_cast<float>((1009 * k + 37 * i) % 32768));
        EXPECT_EQ(p.sonar.starboard.at(i), static_cast<float>((1009 * k + 37 * i + 5000) % 32768));
      }
      EXPECT_EQ(p.sonar.time_utc.time_since_epoch().count(),
                1700000000120000 + std::int64_t{250000} * k);
      EXPECT_NEAR(deg_from_rad(p.sonar.sensor_position.lat_rad), 47.25 + 1e-5 * k, 1e-12);
      EXPECT_NEAR(deg_from_rad(p.sonar.heading_true_rad), 30.0 + k, 1e-9);
      EXPECT_NEAR(p.sonar.slant_range_m, 30.0, 1e-4);
      ++k;
    }
    EXPECT_EQ(k, 6u) << mode;
  }
  fs::remove_all(dir);
}

// MCAP records assembled byte by byte, for damaged inputs.
struct Bytes {
  std::vector<std::uint8_t> b;
  Bytes& u(std::uint64_t x, int n) {
    for (int i = 0; i < n; ++i) {  // little endian; bytes past the eighth are zero
      b.push_back(i < 8 ? static_cast<std::uint8_t>((x >> (8 * i)) & 0xFFu) : std::uint8_t{0});
    }
    return *this;
  }
  Bytes& str(const std::string& s) {
    u(s.size(), 4);
    b.insert(b.end(), s.begin(), s.end());
    return *this;
  }
  Bytes& raw(const std::vector<std::uint8_t>& r) {
    b.insert(b.end(), r.begin(), r.end());
    return *this;
  }
  Bytes& record(std::uint8_t op, const Bytes& content) {
    u(op, 1).u(content.b.size(), 8);
    return raw(content.b);
  }
};

const std::vector<std::uint8_t> kMagic = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};

/// Magic, header, a NavSatFix schema and channel, one chunk of `compression` holding
/// `records`, DataEnd, a footer without summary, magic.
std::vector<std::uint8_t> small_bag(const std::string& compression, const Bytes& records) {
  Bytes f;
  f.raw(kMagic).record(0x01, Bytes().str("ros2").str("test"));
  f.record(0x03, Bytes().u(1, 2).str("sensor_msgs/msg/NavSatFix").str("ros2msg").str(""));
  f.record(0x04, Bytes().u(1, 2).u(1, 2).str("/fix").str("cdr").u(0, 4));
  f.record(0x06, Bytes()
                     .u(0, 8)
                     .u(0, 8)
                     .u(records.b.size(), 8)
                     .u(0, 4)
                     .str(compression)
                     .u(records.b.size(), 8)
                     .raw(records.b));
  f.record(0x0F, Bytes().u(0, 4)).record(0x02, Bytes().u(0, 8).u(0, 8).u(0, 4)).raw(kMagic);
  return f.b;
}

std::string error_of(const std::vector<std::uint8_t>& bytes, std::string* anomaly = nullptr) {
  try {
    Reader r(bytes, "damaged.mcap");
    Ping p;
    while (r.next_ping(p)) {
    }
    if (anomaly && !r.anomalies().empty()) *anomaly = r.anomalies().front().message;
  } catch (const FormatError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::vector<std::uint8_t>& bytes, const std::string& what) {
  const std::string e = error_of(bytes);
  EXPECT_NE(e.find("mcap reader: damaged.mcap: " + what), std::string::npos) << e;
}

void patch(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b[at + i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFu);
}

TEST(McapReader, DamagedFilesGiveNamedErrors) {
  // A NavSatFix in big-endian CDR: skipped, named; lz4 and unknown chunk compressions refused.
  Bytes fix;
  fix.u(0, 2).u(0, 2);  // encapsulation 00 00: CDR_BE
  fix.u(0, 64);
  Bytes message;
  message.record(0x05, Bytes().u(1, 2).u(0, 4).u(0, 8).u(0, 8).raw(fix.b));
  std::string anomaly;
  EXPECT_EQ(error_of(small_bag("", message), &anomaly), "");
  EXPECT_NE(anomaly.find("damaged.mcap: chunk at byte 120, uncompressed byte 31: "
                         "sensor_msgs/msg/NavSatFix: CDR encapsulation 0 0: big-endian CDR"),
            std::string::npos)
      << anomaly;
  expect_error(small_bag("lz4", message), "byte 157: chunk compression = 'lz4': not read");
  expect_error({}, "byte 0: not an MCAP file");
  // A bag of the writer: 3 chunks, with its summary.
  const fs::path dir = xtf::test::temp_dir("mcap_damaged");
  const std::vector<std::uint8_t> good =
      test::four_ping_bag<Writer, WriterOptions>(dir / "a.mcap", 1100);
  EXPECT_EQ(error_of(good), "");
  const std::size_t footer = good.size() - 8 - 29;
  const auto summary = static_cast<std::size_t>(read::le(good.data() + footer + 9, 8));
  // The first chunk: the records after the header, schemas and channels.
  std::size_t chunk = 8;
  while (good[chunk] != 0x06) chunk += 9 + static_cast<std::size_t>(read::le(&good[chunk + 1], 8));
  const std::size_t chunk_end = chunk + 9 + static_cast<std::size_t>(read::le(&good[chunk + 1], 8));
  {
    std::vector<std::uint8_t> bad = good;  // truncated: no closing magic
    bad.resize(good.size() - 5);
    expect_error(bad, "byte " + std::to_string(bad.size() - 8) + ": truncated or damaged");
  }
  {
    std::vector<std::uint8_t> bad = good;  // a schema name changed: the summary CRC
    bad[summary + 9 + 2 + 4] ^= 0x20;
    expect_error(bad, "byte " + std::to_string(footer + 25) + ": footer summary_crc = ");
  }
  {
    std::vector<std::uint8_t> bad = good;  // the chunk's CRC field
    bad[chunk + 9 + 24] ^= 0x01;
    expect_error(bad, "byte " + std::to_string(chunk + 33) + ": chunk uncompressed_crc = ");
  }
  {
    std::vector<std::uint8_t> bad = good;  // the summary's first chunk index moved by one byte
    patch(bad, footer + 25, 0, 4);         // summary CRC 0: not checked
    std::size_t at = summary;
    while (bad[at] != 0x08) at += 9 + static_cast<std::size_t>(read::le(&bad[at + 1], 8));
    patch(bad, at + 9 + 16, chunk + 1, 8);
    expect_error(bad, "byte " + std::to_string(chunk + 1) + ": opcode ");
    patch(bad, at + 9 + 16, summary, 8);
    expect_error(bad, "byte " + std::to_string(at + 9 + 16) + ": chunk index chunk_start_offset");
  }
  {
    std::vector<std::uint8_t> bad = good;  // a message index entry past the chunk's records
    patch(bad, chunk_end + 9 + 2 + 4 + 8, 1u << 30, 8);
    expect_error(bad, "byte " + std::to_string(chunk_end + 9 + 2 + 4 + 16) +
                          ": message index records.offset = 1073741824");
  }
  // Cut anywhere, or with bytes overwritten: a FormatError or a read, never a crash.
  test::expect_cuts_named_and_damage_survived(
      good, 61, "damaged.mcap", [](const std::vector<std::uint8_t>& b) { return error_of(b); });
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth::mcap
