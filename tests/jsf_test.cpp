// SPDX-License-Identifier: MIT
// JSF writer and reader: a golden file whose bytes are written out here by hand from the
// offsets and scalings of docs/jsf.md §1 (not produced by the writer), writer -> reader round
// trips, and truncated / corrupted files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/jsf/summary.hpp"
#include "sonarsynth/formats/jsf/writer.hpp"
#include "sonarsynth/version.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::jsf {
namespace {

namespace fs = std::filesystem;
using xtf::test::read_bytes;
using xtf::test::temp_dir;
using xtf::test::write_bytes;

/// Little-endian stores at absolute offsets of a byte vector.
struct Bytes {
  std::vector<std::uint8_t> b;
  void put(std::size_t off, std::uint64_t v, std::size_t n) {
    if (b.size() < off + n) b.resize(off + n, 0);
    for (std::size_t i = 0; i < n; ++i) b[off + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void u8(std::size_t off, std::uint64_t v) { put(off, v, 1); }
  void u16(std::size_t off, std::uint64_t v) { put(off, v, 2); }
  void u32(std::size_t off, std::uint64_t v) { put(off, v, 4); }
  void i16(std::size_t off, std::int64_t v) { put(off, static_cast<std::uint64_t>(v), 2); }
  void i32(std::size_t off, std::int64_t v) { put(off, static_cast<std::uint64_t>(v), 4); }
  void f32(std::size_t off, float v) {
    std::uint32_t u = 0;
    std::memcpy(&u, &v, 4);
    put(off, u, 4);
  }
};

SonarPing golden_ping() {
  using namespace std::chrono;
  SonarPing p;
  p.time_utc = UtcTime{sys_days{year{2013} / September / 10} + hours{21} + minutes{13} +
                       seconds{8} + milliseconds{250}};
  p.ping_number = 7;
  p.sensor_position = {rad_from_deg(48.5), rad_from_deg(-68.75), 0.0};
  p.heading_true_rad = rad_from_deg(90.0);
  p.pitch_rad = rad_from_deg(2.0);
  p.roll_rad = rad_from_deg(-1.0);
  p.heave_m = 0.5;  // up
  p.altitude_m = 10.0;
  p.depth_m = 20.0;
  p.speed_m_s = 1852.0 / 3600.0 * 4.0;  // 4 knots
  p.sound_speed_m_s = 1500.0;
  p.slant_range_m = 30.0;
  p.port = {10, 20, 30, 40};         // near -> far, integers: N = 0
  p.starboard = {0.5f, 1, 1.5f, 2};  // max 2: N = 13 (2 * 2^13 = 16384 <= 32767 < 2 * 2^14)
  return p;
}

/// One message 80 of the golden ping, every field from docs/jsf.md §1.2 worked out by hand.
void golden_sonar_message(Bytes& f, std::size_t at, int channel) {
  // 16-byte header: marker 0x1601, protocol 13, session 0, type 80, command 2, subsystem 20.
  f.u16(at + 0, 0x1601);
  f.u8(at + 2, 13);
  f.u16(at + 4, 80);
  f.u8(at + 6, 2);
  f.u8(at + 7, 20);
  f.u8(at + 8, static_cast<std::uint64_t>(channel));
  f.i32(at + 12, 240 + 2 * 4);
  const std::size_t o = at + 16;
  f.i32(o + 0, 1378847588);  // 2013-09-10T21:13:08Z in seconds since 1970
  f.u32(o + 8, 7);           // ping number
  f.i16(o + 28, 1);          // ID code
  // validity: position, course, speed, heading, pitch/roll, altitude, heave, depth,
  // position interpolated, sound speed = bits 0 1 2 3 5 6 7 9 13 14
  f.u16(o + 30, 1 + 2 + 4 + 8 + 32 + 64 + 128 + 512 + 8192 + 16384);
  f.f32(o + 48, -0.5f);      // heave, positive down
  f.i32(o + 80, -41250000);  // -68.75 deg x 600 000
  f.i32(o + 84, 29100000);   // 48.5 deg x 600 000
  f.i16(o + 88, 2);          // coordinate units: minutes of arc x 10 000
  f.u16(o + 114, 4);         // samples
  f.u32(o + 116, 10000000);  // 2 x 30 m / (1500 m/s x 4) = 10 ms
  f.u16(o + 126, 50000);     // 500 kHz in daHz
  f.u16(o + 128, 50000);
  f.i32(o + 136, 20000);      // depth mm
  f.u16(o + 140, 100);        // 1 / 10 ms
  f.i32(o + 144, 10000);      // altitude mm
  f.f32(o + 148, 1500.0f);    // sound speed
  f.f32(o + 152, 500000.0f);  // mixer frequency
  f.i16(o + 156, 2013);       // CPU time: year, day of year (31+28+31+30+31+30+31+31+10)
  f.i16(o + 158, 253);
  f.i16(o + 160, 21);
  f.i16(o + 162, 13);
  f.i16(o + 164, 8);
  f.i16(o + 166, 3);                      // time basis
  f.i16(o + 168, channel == 0 ? 0 : 13);  // weighting factor
  f.u16(o + 172, 9000);                   // heading 90.00 deg
  f.i16(o + 174, 364);                    // pitch 2 deg x 32768 / 180 = 364.09
  f.i16(o + 176, -182);                   // roll -1 deg x 32768 / 180 = -182.04
  f.i16(o + 186, 21);                     // position-fix time = ping time
  f.i16(o + 188, 13);
  f.i16(o + 190, 8);
  f.i16(o + 192, 90);   // course, whole degrees
  f.i16(o + 194, 40);   // 4 knots in tenths
  f.i16(o + 196, 253);  // fix day of year, year
  f.i16(o + 198, 2013);
  f.u32(o + 200, (21 * 3600 + 13 * 60 + 8) * 1000 + 250);  // ms today
  f.u16(o + 204, channel == 0 ? 40 : 16384);               // max |stored|
  const std::string_view v(kVersion);
  for (std::size_t i = 0; i < 5 && i < v.size(); ++i) {
    f.u8(o + 210 + i, static_cast<std::uint8_t>(v[i]));
  }
  f.i32(o + 216, -1);  // spherical correction disabled
  f.u16(o + 220, 1);   // packet number
  const std::size_t d = o + 240;
  if (channel == 0) {
    for (int i = 0; i < 4; ++i) f.i16(d + 2 * static_cast<std::size_t>(i), 10 * (i + 1));
  } else {
    for (int i = 0; i < 4; ++i) f.i16(d + 2 * static_cast<std::size_t>(i), 4096 * (i + 1));
  }
}

std::vector<std::uint8_t> golden_bytes() {
  Bytes f;
  // System information (182): 24 bytes, subsystems = 1 at body offset 12.
  f.u16(0, 0x1601);
  f.u8(2, 13);
  f.u16(4, 182);
  f.u8(6, 2);
  f.i32(12, 24);
  f.i32(16 + 12, 1);
  f.put(16 + 20, 0, 4);
  golden_sonar_message(f, 40, 0);
  golden_sonar_message(f, 40 + 16 + 248, 1);
  return f.b;
}

TEST(JsfGolden, WriterReproducesHandDerivedBytes) {
  const fs::path dir = temp_dir("jsf_golden");
  const fs::path path = dir / "golden.jsf";
  WriterOptions o;
  o.frequency_hz = 500e3;
  Writer w(path, o);
  w.write_ping(golden_ping());
  w.close();
  const auto got = read_bytes(path);
  const auto want = golden_bytes();
  ASSERT_EQ(got.size(), want.size());
  ASSERT_EQ(want.size(), 40u + 2 * (16 + 240 + 8));
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(int{got[i]}, int{want[i]}) << "byte " << i;
  }
  fs::remove_all(dir);
}

TEST(JsfGolden, ReaderDecodesHandDerivedBytes) {
  const auto bytes = golden_bytes();
  Reader r(bytes, "golden.jsf");
  Ping p;
  ASSERT_TRUE(r.next_ping(p));
  EXPECT_EQ(r.total_anomalies(), 0u);
  EXPECT_TRUE(p.time_valid);
  EXPECT_TRUE(p.nav_valid);
  EXPECT_EQ(p.subsystem, 20);
  const SonarPing want = golden_ping();
  const SonarPing& s = p.sonar;
  EXPECT_EQ(s.time_utc, want.time_utc);
  EXPECT_EQ(s.ping_number, 7u);
  EXPECT_DOUBLE_EQ(deg_from_rad(s.sensor_position.lat_rad), 48.5);
  EXPECT_DOUBLE_EQ(deg_from_rad(s.sensor_position.lon_rad), -68.75);
  EXPECT_NEAR(deg_from_rad(s.heading_true_rad), 90.0, 1e-12);
  EXPECT_NEAR(deg_from_rad(s.pitch_rad), 364 * 180.0 / 32768.0, 1e-12);
  EXPECT_NEAR(deg_from_rad(s.roll_rad), -182 * 180.0 / 32768.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.heave_m, 0.5);
  EXPECT_DOUBLE_EQ(s.altitude_m, 10.0);
  EXPECT_DOUBLE_EQ(s.depth_m, 20.0);
  EXPECT_NEAR(s.speed_m_s, 1852.0 / 3600.0 * 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.sound_speed_m_s, 1500.0);
  EXPECT_DOUBLE_EQ(s.slant_range_m, 30.0);
  EXPECT_EQ(s.port, want.port);
  EXPECT_EQ(s.starboard, want.starboard);
  EXPECT_FALSE(r.next_ping(p));
  ASSERT_TRUE(r.system_information());
  EXPECT_EQ(r.system_information()->subsystems, 1);
  EXPECT_EQ(r.message_counts().at(80), 2u);
  EXPECT_EQ(r.message_counts().at(182), 1u);
}

TEST(JsfWriter, QuantiseBlockFloatingPoint) {
  std::vector<std::int16_t> stored;
  std::uint64_t clipped = 0;
  const std::vector<float> big = {65536.0f, 1.0f};  // 65536 x 2^-1 = 32768 > 32767: N = -2
  EXPECT_EQ(quantise(big, stored, clipped), -2);
  EXPECT_EQ(stored, (std::vector<std::int16_t>{16384, 0}));  // 0.25 rounds to 0
  const std::vector<float> ints = {0.0f, 32767.0f};
  EXPECT_EQ(quantise(ints, stored, clipped), 0);
  EXPECT_EQ(stored, (std::vector<std::int16_t>{0, 32767}));
  EXPECT_EQ(clipped, 0u);
  const std::vector<float> huge = {3.0e38f, 1.0e30f};  // float samples of a gain-0 run
  const std::int16_t n = quantise(huge, stored, clipped);
  EXPECT_LE(std::ldexp(3.0e38, n), 32767.0);
  EXPECT_GT(std::ldexp(3.0e38, n + 1), 32767.0);
  EXPECT_NEAR(std::ldexp(static_cast<double>(stored[0]), -n), 3.0e38, 3.0e38 / 32767.0);
  const std::vector<float> bad = {-1.0f, NAN, 3.0f};
  EXPECT_EQ(quantise(bad, stored, clipped), 0);
  EXPECT_EQ(clipped, 2u);
}

TEST(JsfRoundTrip, WriterToReaderBitExact) {
  const fs::path dir = temp_dir("jsf_round_trip");
  const fs::path path = dir / "rt.jsf";
  std::vector<SonarPing> pings;
  {
    Writer w(path);
    for (std::uint32_t k = 0; k < 20; ++k) {
      SonarPing p = xtf::test::make_ping(k, 1500, 1500);
      if (k == 3) {  // non-integer samples: block floating point, exact for these values
        for (float& v : p.port) v = v / 1024.0f;
      }
      w.write_ping(p);
      w.write_attitude({p.time_utc, p.heading_true_rad, p.pitch_rad, p.roll_rad, 0.25, 0.0});
      pings.push_back(p);
    }
    w.close();
    EXPECT_EQ(w.clipped_samples(), 0u);
  }
  Reader r(path);
  Ping p;
  for (const SonarPing& want : pings) {
    ASSERT_TRUE(r.next_ping(p));
    EXPECT_EQ(p.sonar.port, want.port) << "ping " << want.ping_number;
    EXPECT_EQ(p.sonar.starboard, want.starboard);
    EXPECT_EQ(p.sonar.time_utc, want.time_utc);
    EXPECT_EQ(p.sonar.ping_number, want.ping_number);
    const double res = 0.5 / 600000.0 + 1e-12;  // half the JSF coordinate step, degrees
    EXPECT_NEAR(deg_from_rad(p.sonar.sensor_position.lat_rad),
                deg_from_rad(want.sensor_position.lat_rad), res);
    EXPECT_NEAR(deg_from_rad(p.sonar.sensor_position.lon_rad),
                deg_from_rad(want.sensor_position.lon_rad), res);
    EXPECT_NEAR(deg_from_rad(p.sonar.heading_true_rad), deg_from_rad(want.heading_true_rad),
                0.005 + 1e-9);
    EXPECT_NEAR(deg_from_rad(p.sonar.pitch_rad), deg_from_rad(want.pitch_rad), 90.0 / 32768.0);
    EXPECT_NEAR(deg_from_rad(p.sonar.roll_rad), deg_from_rad(want.roll_rad), 90.0 / 32768.0);
    EXPECT_NEAR(p.sonar.altitude_m, want.altitude_m, 0.0005);
    EXPECT_NEAR(p.sonar.depth_m, want.depth_m, 0.0005);
    EXPECT_NEAR(p.sonar.heave_m, want.heave_m, 1e-6);
    EXPECT_NEAR(p.sonar.speed_m_s, want.speed_m_s, 0.005 * 1852.0 / 3600.0);
    EXPECT_FLOAT_EQ(static_cast<float>(p.sonar.sound_speed_m_s),
                    static_cast<float>(want.sound_speed_m_s));
    // Integer ns sample interval: the slant range moves by at most c n 0.5 ns / 2.
    EXPECT_NEAR(p.sonar.slant_range_m, want.slant_range_m, 1490.0 * 1500 * 0.5e-9 / 2 + 1e-9);
  }
  EXPECT_FALSE(r.next_ping(p));
  EXPECT_EQ(r.total_anomalies(), 0u);
  EXPECT_EQ(r.message_counts().at(2020), 20u);
  fs::remove_all(dir);
}

std::vector<std::uint8_t> three_ping_file(const fs::path& dir) {
  const fs::path path = dir / "three.jsf";
  Writer w(path);
  for (std::uint32_t k = 0; k < 3; ++k) w.write_ping(xtf::test::make_ping(k, 100, 100));
  w.close();
  return read_bytes(path);
}

std::uint64_t count_pings(Reader& r) {
  Ping p;
  std::uint64_t n = 0;
  while (r.next_ping(p)) n += p.sonar.port.empty() || p.sonar.starboard.empty() ? 0 : 1;
  return n;
}

TEST(JsfReader, NotAJsfFile) {
  const std::vector<std::uint8_t> xtf_start = {0x7B, 0x01, 0, 0, 0, 0, 0, 0,
                                               0,    0,    0, 0, 0, 0, 0, 0};
  try {
    Reader r(xtf_start, "x.xtf");
    FAIL() << "no exception";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("not a JSF file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("x.xtf"), std::string::npos);
  }
  EXPECT_THROW(Reader(std::vector<std::uint8_t>{0x01, 0x16}, "short.jsf"), FormatError);
}

TEST(JsfReader, TruncatedFileKeepsCompletePings) {
  const fs::path dir = temp_dir("jsf_truncated");
  const auto whole = three_ping_file(dir);
  ASSERT_GT(whole.size(), 50u);
  // Cut into the last starboard message.
  const std::vector<std::uint8_t> bytes(whole.begin(), whole.end() - 50);
  Reader r(bytes, "cut.jsf");
  EXPECT_EQ(count_pings(r), 2u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kBadByteCount), 1u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kUnpairedChannel), 1u);  // the last port message
  ASSERT_FALSE(r.anomalies().empty());
  EXPECT_NE(r.anomalies()[0].message.find("cut.jsf"), std::string::npos);
  EXPECT_NE(r.anomalies()[0].message.find("announces"), std::string::npos);
  fs::remove_all(dir);
}

TEST(JsfReader, GarbageBetweenMessagesIsSkipped) {
  const fs::path dir = temp_dir("jsf_garbage");
  auto bytes = three_ping_file(dir);
  const std::size_t second_ping = 40 + 2 * (16 + 240 + 200);
  bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(second_ping), 37, 0xAB);
  Reader r(bytes, "garbage.jsf");
  EXPECT_EQ(count_pings(r), 3u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kGarbageSkipped), 1u);
  EXPECT_EQ(r.anomalies().at(0).offset, second_ping);
  EXPECT_NE(r.anomalies()[0].message.find("37 bytes"), std::string::npos)
      << r.anomalies()[0].message;
  fs::remove_all(dir);
}

TEST(JsfReader, CorruptedFieldsAreReported) {
  const fs::path dir = temp_dir("jsf_corrupt");
  auto bytes = three_ping_file(dir);
  const std::size_t port0 = 40;
  // Data format 300 (proprietary) in ping 0 port; 20 000 samples in ping 1 port.
  bytes[port0 + 16 + 34] = 300 & 0xFF;
  bytes[port0 + 16 + 35] = 300 >> 8;
  const std::size_t port1 = 40 + 2 * (16 + 240 + 200);
  bytes[port1 + 16 + 114] = 20000 & 0xFF;
  bytes[port1 + 16 + 115] = 20000 >> 8;
  Reader r(bytes, "corrupt.jsf");
  EXPECT_EQ(count_pings(r), 1u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kBadSonarData), 2u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kUnpairedChannel), 2u);
  std::vector<std::string> bad;
  for (const Anomaly& a : r.anomalies()) {
    if (a.kind == AnomalyKind::kBadSonarData) bad.push_back(a.message);
  }
  ASSERT_EQ(bad.size(), 2u);
  EXPECT_NE(bad[0].find("data format 300"), std::string::npos) << bad[0];
  EXPECT_NE(bad[1].find("20000 samples"), std::string::npos) << bad[1];
  fs::remove_all(dir);
}

TEST(JsfReader, UnknownMessagesSkippedByCount) {
  const fs::path dir = temp_dir("jsf_unknown");
  auto bytes = three_ping_file(dir);
  Bytes extra;
  extra.u16(0, 0x1601);
  extra.u8(2, 13);
  extra.u16(4, 9999);
  extra.i32(12, 5);
  extra.put(16, 0x0116011601ull, 5);  // body bytes that look like markers
  bytes.insert(bytes.begin() + 40, extra.b.begin(), extra.b.end());
  Reader r(bytes, "unknown.jsf");
  EXPECT_EQ(count_pings(r), 3u);
  EXPECT_EQ(r.total_anomalies(), 0u);
  EXPECT_EQ(r.message_counts().at(9999), 1u);
  fs::remove_all(dir);
}

TEST(JsfWriter, RefusesPingsItCannotStore) {
  const fs::path dir = temp_dir("jsf_refuse");
  Writer w(dir / "x.jsf");
  SonarPing p = xtf::test::make_ping(0, 10, 12);
  EXPECT_THROW(w.write_ping(p), InputError);  // sides of different length
  p = xtf::test::make_ping(0, 10, 10);
  p.time_utc = UtcTime{};
  p.time_utc -= std::chrono::hours(24);
  EXPECT_THROW(w.write_ping(p), InputError);  // 1969
  fs::remove_all(dir);
}

TEST(JsfSummary, CountsSubsystemsAndMessages) {
  const fs::path dir = temp_dir("jsf_summary");
  auto bytes = three_ping_file(dir);
  Reader r(bytes, "s.jsf");
  const FileSummary s = summarize(r);
  EXPECT_EQ(s.pings, 3u);
  EXPECT_EQ(s.message_counts.at(80), 6u);
  EXPECT_EQ(s.message_counts.at(182), 1u);
  EXPECT_EQ(s.sonar_counts.at(20).at(0), 3u);
  EXPECT_EQ(s.sonar_counts.at(20).at(1), 3u);
  EXPECT_EQ(s.ping_subsystem, 20);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth::jsf
