// SPDX-License-Identifier: MIT
// Writer: whole-file round trips, atomic output, and one test per failure mode of the
// writer-choice matrix of docs/xtf.md §4 proving our writer never produces it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/version.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::xtf {
namespace {

namespace fs = std::filesystem;
using test::make_ping;

template <typename T>
T at(const std::vector<std::uint8_t>& b, std::uint64_t offset) {
  T v;
  std::memcpy(&v, b.data() + offset, sizeof v);
  return v;
}

/// Packet starts found by walking NumBytesThisRecord from byte 1024.
std::vector<std::uint64_t> packet_offsets(const std::vector<std::uint8_t>& b) {
  std::vector<std::uint64_t> out;
  std::uint64_t pos = 1024;
  while (pos + 14 <= b.size()) {
    out.push_back(pos);
    const auto n = at<std::uint32_t>(b, pos + 10);
    if (n == 0) break;
    pos += n;
  }
  EXPECT_EQ(pos, b.size()) << "packets must tile the file exactly";
  return out;
}

class XtfWriterTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("writer"); }
  void TearDown() override { fs::remove_all(dir_); }

  /// A file of `pings` pings, with an attitude and a navigation packet before each.
  fs::path write_file(const std::string& name, std::uint32_t pings, WriterOptions o = {},
                      std::size_t n = 1000) {
    const fs::path p = dir_ / name;
    Writer w(p, o);
    for (std::uint32_t i = 0; i < pings; ++i) {
      SonarPing ping = make_ping(i, n, n);
      AttitudeSample a{ping.time_utc, ping.heading_true_rad, ping.pitch_rad,
                       ping.roll_rad, ping.heave_m,          0.0};
      w.write_attitude(a);
      w.write_navigation({ping.time_utc, ping.sensor_position});
      w.write_ping(ping);
    }
    w.close();
    return p;
  }

  fs::path dir_;
};

TEST_F(XtfWriterTest, WholeFileRoundTrip) {
  const fs::path p = dir_ / "rt.xtf";
  std::vector<SonarPing> in;
  {
    Writer w(p);
    for (std::uint32_t i = 0; i < 20; ++i) {
      in.push_back(make_ping(i, 300 + i, 500 - i));  // different sizes per side and ping
      w.write_attitude({in.back().time_utc + std::chrono::microseconds(1234),
                        rad_from_deg(200.0 + i), rad_from_deg(1.5), rad_from_deg(-2.5), 0.25,
                        rad_from_deg(0.5)});
      w.write_navigation({in.back().time_utc + std::chrono::microseconds(567),
                          {rad_from_deg(48.4), rad_from_deg(-68.8 - 1e-6 * i), -1.5}});
      w.write_ping(in.back());
    }
    w.close();
    EXPECT_EQ(w.pings_written(), 20u);
    EXPECT_EQ(w.clipped_samples(), 0u);
    EXPECT_EQ(w.bytes_written(), fs::file_size(p));
  }
  Reader r(p);
  EXPECT_EQ(r.total_anomalies(), 0u);
  Packet pk;
  std::size_t pings = 0, att = 0, nav = 0, notes = 0;
  while (r.next(pk)) {
    switch (pk.kind) {
      case PacketKind::kPing: {
        const SonarPing& got = pk.ping.sonar;
        const SonarPing& want = in[pings++];
        EXPECT_TRUE(pk.ping.time_valid);
        EXPECT_TRUE(pk.ping.nav_valid);
        EXPECT_EQ(got.time_utc, want.time_utc);  // times are on whole hundredths
        EXPECT_EQ(got.ping_number, want.ping_number);
        EXPECT_NEAR(got.sensor_position.lat_rad, want.sensor_position.lat_rad, 1e-15);
        EXPECT_NEAR(got.sensor_position.lon_rad, want.sensor_position.lon_rad, 1e-15);
        ASSERT_TRUE(got.ship_position.has_value());
        EXPECT_NEAR(got.ship_position->lat_rad, want.ship_position->lat_rad, 1e-15);
        // float32 degrees: ~1e-5 deg relative
        EXPECT_NEAR(got.heading_true_rad, want.heading_true_rad, 1e-6);
        EXPECT_NEAR(got.pitch_rad, want.pitch_rad, 1e-7);
        EXPECT_NEAR(got.roll_rad, want.roll_rad, 1e-7);
        EXPECT_NEAR(got.heave_m, want.heave_m, 1e-6);
        EXPECT_NEAR(got.altitude_m, want.altitude_m, 1e-5);
        EXPECT_NEAR(got.depth_m, want.depth_m, 1e-5);
        EXPECT_NEAR(got.speed_m_s, want.speed_m_s, 1e-5);
        EXPECT_NEAR(got.sound_speed_m_s, want.sound_speed_m_s, 1e-3);
        EXPECT_NEAR(got.slant_range_m, want.slant_range_m, 1e-5);
        EXPECT_EQ(got.port, want.port);  // near -> far after normalisation
        EXPECT_EQ(got.starboard, want.starboard);
        break;
      }
      case PacketKind::kAttitude: {
        const auto& a = pk.attitude;
        EXPECT_NEAR(a.Heading, 200.0 + static_cast<double>(att), 1e-4);
        EXPECT_FLOAT_EQ(a.Pitch, 1.5f);
        EXPECT_FLOAT_EQ(a.Roll, -2.5f);
        EXPECT_FLOAT_EQ(a.Heave, 0.25f);
        EXPECT_EQ(a.EpochMicroseconds, (70000u * att + 1234u) % 1000000u);
        EXPECT_EQ(a.Milliseconds, a.EpochMicroseconds / 1000u);
        EXPECT_EQ(a.Year, 2013);
        ++att;
        break;
      }
      case PacketKind::kNavigation: {
        const auto& n = pk.navigation;
        EXPECT_DOUBLE_EQ(n.RawYcoordinate, deg_from_rad(rad_from_deg(48.4)));
        EXPECT_NEAR(n.RawXcoordinate, -68.8 - 1e-6 * static_cast<double>(nav), 1e-12);
        EXPECT_EQ(n.RawAltitude, -1.5);
        EXPECT_EQ(n.Microseconds, (70000u * nav + 567u) % 1000000u);
        ++nav;
        break;
      }
      case PacketKind::kNotes:
        ++notes;
        break;
      case PacketKind::kOther:
        ADD_FAILURE() << "unexpected packet type " << int{pk.header_type};
    }
  }
  EXPECT_EQ(pings, 20u);
  EXPECT_EQ(att, 20u);
  EXPECT_EQ(nav, 20u);
  EXPECT_EQ(notes, 1u);
}

TEST_F(XtfWriterTest, QuantisationRoundsClampsAndCounts) {
  const fs::path p = dir_ / "q.xtf";
  SonarPing ping = make_ping(0, 6, 6);
  ping.port = {-3.0f, 0.4f, 0.6f, 32766.6f, 40000.0f, std::nanf("")};
  ping.starboard = {1.0f, 2.5f, 3.49f, 32767.4f, 32767.6f, -0.4f};
  Writer w(p);
  w.write_ping(ping);
  w.close();
  EXPECT_EQ(w.clipped_samples(), 4u);  // -3, 40000, NaN, 32767.6
  Reader r(p);
  Packet pk;
  while (r.next(pk) && pk.kind != PacketKind::kPing) {
  }
  EXPECT_EQ(pk.ping.sonar.port, (std::vector<float>{0, 0, 1, 32767, 32767, 0}));
  EXPECT_EQ(pk.ping.sonar.starboard, (std::vector<float>{1, 3, 3, 32767, 32767, 0}));
}

TEST_F(XtfWriterTest, EightBitAndFloatOptionsRoundTripAndWarn) {
  EXPECT_TRUE(WriterOptions{}.compatibility_warnings().empty());
  WriterOptions o8;
  o8.sample_encoding = SampleEncoding::kUint8;
  ASSERT_EQ(o8.compatibility_warnings().size(), 1u);
  EXPECT_NE(o8.compatibility_warnings()[0].find("auvlib"), std::string::npos);
  WriterOptions of;
  of.sample_encoding = SampleEncoding::kFloat32;
  ASSERT_EQ(of.compatibility_warnings().size(), 1u);
  EXPECT_NE(of.compatibility_warnings()[0].find("MB-System"), std::string::npos);
  WriterOptions big;
  big.allow_more_than_8192_samples = true;
  ASSERT_EQ(big.compatibility_warnings().size(), 1u);
  EXPECT_NE(big.compatibility_warnings()[0].find("MB-System"), std::string::npos);

  SonarPing ping = make_ping(0, 4, 4);
  ping.port = {0.0f, 254.6f, 300.0f, 17.2f};
  ping.starboard = {0.25f, 1e6f, -5.5f, 3.75f};
  struct Case {
    const char* file;
    WriterOptions options;
    std::size_t clipped;
    int bytes_per_sample, sample_format;
    std::vector<float> port, starboard;  // as read back
  };
  const Case cases[] = {
      {"u8.xtf", o8, 3, 1, 8, {0, 255, 255, 17}, {0, 255, 0, 4}},
      {"f32.xtf", of, 0, 4, 5, ping.port, ping.starboard},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    Writer w(dir_ / c.file, c.options);
    EXPECT_EQ(w.warnings().size(), 1u);
    w.write_ping(ping);
    w.close();
    EXPECT_EQ(w.clipped_samples(), c.clipped);
    Reader r(dir_ / c.file);
    for (std::size_t ch = 0; ch < 2; ++ch) {
      EXPECT_EQ(r.chan_info()[ch].BytesPerSample, c.bytes_per_sample) << ch;
      EXPECT_EQ(r.chan_info()[ch].SampleFormat, c.sample_format) << ch;
    }
    Packet pk;
    while (r.next(pk) && pk.kind != PacketKind::kPing) {
    }
    EXPECT_EQ(pk.ping.sonar.port, c.port);
    EXPECT_EQ(pk.ping.sonar.starboard, c.starboard);
  }
}

TEST_F(XtfWriterTest, AtomicOutput) {
  const fs::path p = dir_ / "atomic.xtf";
  {
    Writer w(p);
    w.write_ping(make_ping(0, 10, 10));
    EXPECT_FALSE(fs::exists(p)) << "the file must not appear before close()";
  }
  EXPECT_FALSE(fs::exists(p)) << "destructor without close() must leave nothing";
  EXPECT_TRUE(fs::is_empty(dir_)) << "no temporary file may be left behind";
  {
    Writer w(p);
    w.write_ping(make_ping(0, 10, 10));
    w.close();
  }
  EXPECT_TRUE(fs::exists(p));
  EXPECT_THROW(Writer(p, WriterOptions{}), FormatError);  // exists, overwrite = false
  WriterOptions o;
  o.overwrite = true;
  EXPECT_NO_THROW(Writer(p, o));
  EXPECT_TRUE(fs::exists(p)) << "an abandoned overwrite keeps the old file";
}

TEST_F(XtfWriterTest, InvalidPingsAndOptionsAreRejected) {
  WriterOptions bad;
  bad.frequency_khz = 0.0;
  try {
    bad.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Violated constraint: 0 < frequency_khz"),
              std::string::npos)
        << e.what();
  }
  Writer w(dir_ / "bad.xtf");
  const auto rejects = [&](auto mutate, const char* field) {
    SonarPing p = make_ping(3, 10, 10);
    mutate(p);
    try {
      w.write_ping(p);
      ADD_FAILURE() << "accepted a ping with bad " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("ping 3"), std::string::npos) << e.what();
    }
  };
  rejects([](SonarPing& p) { p.sensor_position = {}; }, "sensor_position");
  rejects([](SonarPing& p) { p.sensor_position.lon_rad = 4.0; }, "sensor_position");
  rejects([](SonarPing& p) { p.ship_position = Geodetic{}; }, "ship_position");
  rejects([](SonarPing& p) { p.altitude_m = -1.0; }, "altitude_m");
  rejects([](SonarPing& p) { p.slant_range_m = -1.0; }, "slant_range_m");
  rejects([](SonarPing& p) { p.sound_speed_m_s = 0.0; }, "sound_speed_m_s");
  rejects([](SonarPing& p) { p.port.clear(); }, "port.size()");
  rejects([](SonarPing& p) { p.starboard.resize(8193); }, "starboard.size()");
  rejects([](SonarPing& p) { p.time_utc = test::test_time(0) + std::chrono::years{100}; }, "year");
  EXPECT_EQ(w.pings_written(), 0u);
}

// ---- Writer-choice matrix (§4): each failure mode, and proof that our output avoids it ----

TEST_F(XtfWriterTest, MatrixB_NotesPacketFirst) {
  const auto b = test::read_bytes(write_file("b.xtf", 2));
  ASSERT_GT(b.size(), 1024u + 256u);
  EXPECT_EQ(at<std::uint16_t>(b, 1024), 0xFACE);
  EXPECT_EQ(b[1026], 1) << "first packet must be NOTES (auvlib skips the first packet)";
  EXPECT_EQ(at<std::uint32_t>(b, 1034), 256u);
}

TEST_F(XtfWriterTest, MatrixCK_NumBytesThisRecordIsThePaddedSize) {
  const auto b = test::read_bytes(write_file("k.xtf", 3, {}, 1001));  // odd size forces padding
  for (std::uint64_t off : packet_offsets(b)) {
    const auto n = at<std::uint32_t>(b, off + 10);
    EXPECT_EQ(n % 64, 0u) << "packet at " << off;
    EXPECT_GE(n, 64u);
    if (b[off + 2] == 0) {
      EXPECT_EQ(n, (256u + 2 * (64 + 2 * 1001) + 63) / 64 * 64);
      // padding is zero
      for (std::uint64_t i = off + 256 + 2 * (64 + 2 * 1001); i < off + n; ++i) EXPECT_EQ(b[i], 0);
    }
  }
}

TEST_F(XtfWriterTest, MatrixDEF_SixteenBitUnsignedSampleFormat3ByDefault) {
  const auto b = test::read_bytes(write_file("d.xtf", 1));
  for (int c = 0; c < 2; ++c) {
    const std::size_t ci = 256 + 128 * static_cast<std::size_t>(c);
    EXPECT_EQ(b[ci + 0], c == 0 ? 1 : 2) << "ChanInfo[0] PORT, [1] STBD";
    EXPECT_EQ(b[ci + 1], c);
    EXPECT_EQ(at<std::uint16_t>(b, ci + 4), 1) << "UniPolar";
    EXPECT_EQ(at<std::uint16_t>(b, ci + 6), 2) << "BytesPerSample";
    EXPECT_EQ(b[ci + 74], 3) << "SampleFormat";
  }
}

TEST_F(XtfWriterTest, MatrixG_CorrectionFlags1) {
  const auto b = test::read_bytes(write_file("g.xtf", 1));
  EXPECT_EQ(at<std::uint16_t>(b, 256 + 2), 1);
  EXPECT_EQ(at<std::uint16_t>(b, 384 + 2), 1);
}

TEST_F(XtfWriterTest, MatrixH_SonarTypeBelow69) {
  const auto b = test::read_bytes(write_file("h.xtf", 1));
  EXPECT_LT(at<std::uint16_t>(b, 34), 69);
}

TEST_F(XtfWriterTest, MatrixIQ_At8192SamplesByDefault) {
  WriterOptions o;
  const auto b = test::read_bytes(write_file("p.xtf", 1, o, 8192));
  const auto offs = packet_offsets(b);
  ASSERT_EQ(offs.size(), 4u);  // notes, attitude, navigation, ping
  EXPECT_EQ(at<std::uint32_t>(b, offs[3] + 256 + 42), 8192u);
  Writer w(dir_ / "q.xtf");
  EXPECT_THROW(w.write_ping(make_ping(0, 8200, 8200)), InputError);
  o.allow_more_than_8192_samples = true;
  const auto big = test::read_bytes(write_file("q2.xtf", 1, o, 9000));
  EXPECT_EQ(at<std::uint32_t>(big, packet_offsets(big)[3] + 256 + 42), 9000u);
}

TEST_F(XtfWriterTest, MatrixJ_PacketReservedIsZero) {
  const auto b = test::read_bytes(write_file("j.xtf", 2));
  for (std::uint64_t off : packet_offsets(b)) {
    if (b[off + 2] == 42) continue;  // bytes 3..9 of type 42 are Reserved[7]: zero as well
    EXPECT_EQ(at<std::uint32_t>(b, off + 6), 0u);
  }
}

TEST_F(XtfWriterTest, MatrixL_ChannelNumbers0And1PortFirst) {
  const auto b = test::read_bytes(write_file("l.xtf", 1, {}, 100));
  const auto off = packet_offsets(b)[3];
  ASSERT_EQ(b[off + 2], 0);
  EXPECT_EQ(at<std::uint16_t>(b, off + 4), 2) << "NumChansToFollow";
  EXPECT_EQ(at<std::uint16_t>(b, off + 256), 0) << "first channel = port, ChannelNumber 0";
  EXPECT_EQ(at<std::uint16_t>(b, off + 256 + 64 + 200), 1) << "second = starboard, 1";
  // Port stored far -> near: file sample 0 is the simulator's last (farthest) sample.
  const SonarPing ping = make_ping(0, 100, 100);
  EXPECT_EQ(at<std::uint16_t>(b, off + 256 + 64), static_cast<std::uint16_t>(ping.port.back()));
  EXPECT_EQ(at<std::uint16_t>(b, off + 256 + 64 + 198),
            static_cast<std::uint16_t>(ping.port.front()));
  EXPECT_EQ(at<std::uint16_t>(b, off + 256 + 64 + 200 + 64),
            static_cast<std::uint16_t>(ping.starboard.front()));
}

TEST_F(XtfWriterTest, MatrixM_ValidDates) {
  const auto b = test::read_bytes(write_file("m.xtf", 3));
  for (std::uint64_t off : packet_offsets(b)) {
    const std::uint8_t type = b[off + 2];
    const std::size_t year_at = type == 3 ? 54 : 14;
    const auto year = at<std::uint16_t>(b, off + year_at);
    EXPECT_GE(year, 1970);
    EXPECT_LE(year, 2100);
    const std::uint8_t month = b[off + year_at + 2], day = b[off + year_at + 3];
    EXPECT_GE(month, 1);
    EXPECT_LE(month, 12);
    EXPECT_GE(day, 1);
    EXPECT_LE(day, 31);
  }
  Writer w(dir_ / "m2.xtf");
  SonarPing p = make_ping(0, 4, 4);
  p.time_utc = UtcTime{std::chrono::sys_days{std::chrono::year{1969} / 12 / 31}};
  EXPECT_THROW(w.write_ping(p), InputError);
}

TEST_F(XtfWriterTest, MatrixN_FixTimeZeroAndMatrixO_NavUnits3) {
  const auto b = test::read_bytes(write_file("n.xtf", 1));
  EXPECT_EQ(at<std::uint16_t>(b, 164), 3);
  const auto off = packet_offsets(b)[3];
  EXPECT_EQ(at<std::uint32_t>(b, off + 148), 0u) << "FixTime fields";
  // X = longitude, Y = latitude
  EXPECT_NEAR(at<double>(b, off + 168), -68.8283, 1e-12);
  EXPECT_NEAR(at<double>(b, off + 160), 48.4455, 1e-12);
  EXPECT_NEAR(at<double>(b, off + 136), -68.8284, 1e-12);
  EXPECT_NEAR(at<double>(b, off + 128), 48.4456, 1e-12);
}

TEST_F(XtfWriterTest, ProfileSoundVelocityTimingAltitudeLayback) {
  const auto b = test::read_bytes(write_file("sv.xtf", 1, {}, 64));
  const auto off = packet_offsets(b)[3];
  EXPECT_FLOAT_EQ(at<float>(b, off + 32), 745.0f) << "SoundVelocity = c/2";
  EXPECT_FLOAT_EQ(at<float>(b, off + 72), 1490.0f) << "ComputedSoundVelocity = c";
  EXPECT_FLOAT_EQ(at<float>(b, off + 196), 8.5f) << "SensorPrimaryAltitude";
  EXPECT_EQ(at<float>(b, off + 184), 0.0f) << "Layback";
  for (int c = 0; c < 2; ++c) {
    const std::uint64_t ch = off + 256 + static_cast<std::uint64_t>(c) * (64 + 128);
    EXPECT_EQ(at<float>(b, ch + 12), 0.0f) << "TimeDelay";
    EXPECT_FLOAT_EQ(at<float>(b, ch + 16), 50.0f / 745.0f) << "TimeDuration = SlantRange/SV";
    EXPECT_FLOAT_EQ(at<float>(b, ch + 20), 50.0f / 745.0f) << "SecondsPerPing";
    EXPECT_EQ(at<std::int16_t>(b, ch + 58), 0) << "Weight";
  }
}

// The ping header's time fields hold hundredths of a second: the time is rounded to the
// nearest 10 ms, half up, and the carry reaches the seconds, minutes, hours and the date.
TEST_F(XtfWriterTest, PingTimeRoundsToNearestHundredthWithCarry) {
  using namespace std::chrono;
  struct Case {
    UtcTime t;
    int year, month, day, hour, minute, second, hsec, julian0;
  };
  const auto at_noon = [](std::int64_t us) {
    return UtcTime{sys_days{year{2026} / March / 1} + hours{12} + microseconds{us}};
  };
  const Case cases[] = {
      {at_noon(996'000), 2026, 3, 1, 12, 0, 1, 0, 59},  // 12:00:00.996 -> 12:00:01.00
      {at_noon(994'999), 2026, 3, 1, 12, 0, 0, 99, 59},
      {at_noon(5'000), 2026, 3, 1, 12, 0, 0, 1, 59},  // half up
      {at_noon(4'999), 2026, 3, 1, 12, 0, 0, 0, 59},
      {at_noon(59 * 60'000'000LL + 59'999'000), 2026, 3, 1, 13, 0, 0, 0, 59},
      {UtcTime{sys_days{year{2025} / December / 31} + hours{23} + minutes{59} + seconds{59} +
               milliseconds{995}},
       2026, 1, 1, 0, 0, 0, 0, 0},
  };
  const fs::path path = dir_ / "round.xtf";
  {
    Writer w(path);
    std::uint32_t n = 0;
    for (const Case& c : cases) {
      SonarPing p = make_ping(n++, 4, 4);
      p.time_utc = c.t;
      w.write_ping(p);
    }
    w.close();
  }
  const auto b = test::read_bytes(path);
  const auto offsets = packet_offsets(b);
  ASSERT_EQ(offsets.size(), 1 + std::size(cases));  // NOTES, then the pings
  for (std::size_t i = 0; i < std::size(cases); ++i) {
    const Case& c = cases[i];
    const std::uint64_t o = offsets[i + 1];
    SCOPED_TRACE("case " + std::to_string(i));
    EXPECT_EQ(at<std::uint16_t>(b, o + 14), c.year);
    EXPECT_EQ(b[o + 16], c.month);
    EXPECT_EQ(b[o + 17], c.day);
    EXPECT_EQ(b[o + 18], c.hour);
    EXPECT_EQ(b[o + 19], c.minute);
    EXPECT_EQ(b[o + 20], c.second);
    EXPECT_EQ(b[o + 21], c.hsec);
    EXPECT_EQ(at<std::uint16_t>(b, o + 22), c.julian0);
  }
}

// Readers take a coordinate of exactly 0 as "no position": a ping on the equator or on the prime
// meridian is written 1e-9 degrees off it; only (0, 0) itself is refused.
TEST_F(XtfWriterTest, EquatorAndPrimeMeridianPingsAreWrittenWithNonZeroCoordinates) {
  const fs::path path = dir_ / "zero.xtf";
  {
    Writer w(path);
    SonarPing p = make_ping(0, 4, 4);
    p.sensor_position = {0.0, rad_from_deg(10.5), 0.0};
    p.ship_position = Geodetic{rad_from_deg(-0.25), 0.0, 0.0};
    w.write_ping(p);
    p = make_ping(1, 4, 4);
    p.sensor_position = {rad_from_deg(51.5), 0.0, 0.0};
    w.write_ping(p);
    w.write_navigation({p.time_utc, Geodetic{0.0, rad_from_deg(3.0), 0.0}});
    p = make_ping(2, 4, 4);
    p.sensor_position = {};
    EXPECT_THROW(w.write_ping(p), InputError);
    w.close();
  }
  const auto b = test::read_bytes(path);
  const auto offsets = packet_offsets(b);
  ASSERT_EQ(offsets.size(), 4u);                                   // NOTES, 2 pings, navigation
  EXPECT_EQ(at<double>(b, offsets[1] + 160), kZeroCoordinateDeg);  // SensorY = latitude
  EXPECT_DOUBLE_EQ(at<double>(b, offsets[1] + 168), 10.5);
  EXPECT_DOUBLE_EQ(at<double>(b, offsets[1] + 128), -0.25);        // ShipY
  EXPECT_EQ(at<double>(b, offsets[1] + 136), kZeroCoordinateDeg);  // ShipX
  EXPECT_DOUBLE_EQ(at<double>(b, offsets[2] + 160), 51.5);
  EXPECT_EQ(at<double>(b, offsets[2] + 168), kZeroCoordinateDeg);
  Reader r(path);
  Packet packet;
  std::size_t pings = 0;
  while (r.next(packet)) {
    if (packet.kind != PacketKind::kPing) continue;
    EXPECT_TRUE(packet.ping.nav_valid) << "ping " << pings;
    ++pings;
  }
  EXPECT_EQ(pings, 2u);
}

// RecordingProgramName and RecordingProgramVersion are char[8]; readers print them as C
// strings, so each keeps a terminating NUL.
TEST_F(XtfWriterTest, ProgramNameAndVersionAreNulTerminated) {
  const auto b = test::read_bytes(write_file("name.xtf", 1));
  const std::string name(reinterpret_cast<const char*>(&b[2]), 8);
  const std::string version(reinterpret_cast<const char*>(&b[10]), 8);
  EXPECT_NE(name.find('\0'), std::string::npos) << "RecordingProgramName has no NUL";
  EXPECT_NE(version.find('\0'), std::string::npos) << "RecordingProgramVersion has no NUL";
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(&b[2])), "sonarsy");
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(&b[10])), kVersion);
}

TEST_F(XtfWriterTest, EmptyFileIsValid) {
  const fs::path p = dir_ / "empty.xtf";
  Writer w(p);
  w.close();
  Reader r(p);
  Packet pk;
  ASSERT_TRUE(r.next(pk));
  EXPECT_EQ(pk.kind, PacketKind::kNotes);
  EXPECT_FALSE(r.next(pk));
  EXPECT_EQ(r.total_anomalies(), 0u);
}

}  // namespace
}  // namespace sonarsynth::xtf
