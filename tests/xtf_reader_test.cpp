// SPDX-License-Identifier: MIT
// Reader: the real Marine Sonic file against the figures independent readers report, sample
// layouts, more than 6 channels, and broken inputs (never a crash, clear errors or skips).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/summary.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::xtf {
namespace {

namespace fs = std::filesystem;
const fs::path kScotsman = fs::path(SONARSYNTH_TEST_DATA_DIR) / "xtf" / "scotsman-iver2.xtf";

std::vector<std::uint8_t> le16(std::initializer_list<int> v) {
  std::vector<std::uint8_t> b;
  for (int x : v) {
    b.push_back(static_cast<std::uint8_t>(x & 0xFF));
    b.push_back(static_cast<std::uint8_t>((x >> 8) & 0xFF));
  }
  return b;
}

/// Reads every packet; returns the pings.
std::vector<PingRecord> read_pings(Reader& r) {
  std::vector<PingRecord> out;
  Packet p;
  while (r.next(p)) {
    if (p.kind == PacketKind::kPing) out.push_back(p.ping);
  }
  return out;
}

template <typename T>
void put(std::vector<std::uint8_t>& b, std::uint64_t off, T v) {
  std::memcpy(b.data() + off, &v, sizeof v);
}

// ---- The real file ---------------------------------------------------------------------------

TEST(XtfReaderReal, ScotsmanMatchesIndependentReaders) {
  const FileSummary s = summarize_file(kScotsman);
  EXPECT_EQ(s.file_size, 2066304u);
  EXPECT_EQ(s.header.NavUnits, 3);
  EXPECT_EQ(s.header.NumberOfSonarChannels, 2);
  EXPECT_EQ(to_string(s.header.RecordingProgramName), "SEASCAN");
  EXPECT_EQ(s.pings, 461u);
  ASSERT_EQ(s.packet_counts.size(), 1u);
  EXPECT_EQ(s.packet_counts.at(0), 461u);
  ASSERT_TRUE(s.first_time && s.last_time);
  EXPECT_EQ(iso8601(*s.first_time), "2013-09-10T21:13:08.000000Z");
  EXPECT_EQ(iso8601(*s.last_time), "2013-09-10T21:14:00.230000Z");
  // Navigation extent with ping 0's zero position excluded (and flagged).
  // The readers' figures are rounded to 5 decimals: +-0.5e-5 (+ a hair for the rounding).
  EXPECT_NEAR(s.sensor_x.min, -68.82834, 5.1e-6);
  EXPECT_NEAR(s.sensor_x.max, -68.82794, 5.1e-6);
  EXPECT_NEAR(s.sensor_y.min, 48.44545, 5.1e-6);
  EXPECT_NEAR(s.sensor_y.max, 48.44586, 5.1e-6);
  EXPECT_EQ(s.pings_with_valid_nav, 460u);
  EXPECT_EQ(s.anomaly_counts[static_cast<std::size_t>(AnomalyKind::kZeroNavigation)], 1u);
  ASSERT_FALSE(s.anomalies.empty());
  EXPECT_EQ(s.anomalies[0].offset, 1024u);
  std::uint64_t total = 0;
  for (auto c : s.anomaly_counts) total += c;
  EXPECT_EQ(total, 1u);
  ASSERT_EQ(s.channels.size(), 2u);
  for (const auto& [number, c] : s.channels) {
    EXPECT_EQ(c.pings, 461u);
    EXPECT_EQ(c.samples.min, 1024);
    EXPECT_EQ(c.samples.max, 1024);
    EXPECT_NEAR(c.slant_range_m.min, 30.0, 0.05);
    EXPECT_NEAR(c.slant_range_m.max, 30.0, 0.05);
  }
  EXPECT_EQ(s.sound_velocity.min, 750.0);
  EXPECT_EQ(s.sound_velocity.max, 750.0);
}

TEST(XtfReaderReal, ScotsmanPortOrderIsNormalisedNearToFar) {
  // docs/xtf.md §2.1: the transmit bang (32767) is in the LAST stored port samples and the
  // FIRST starboard samples. After normalisation both sides start with the bang: averaged over
  // the pings, the 4 nearest samples are saturated and the 4 farthest are not.
  Reader r(kScotsman);
  Packet p;
  double port_near = 0, port_far = 0, stbd_near = 0, stbd_far = 0;
  int n = 0;
  while (r.next(p)) {
    if (p.kind != PacketKind::kPing || !p.ping.nav_valid) continue;
    const SonarPing& s = p.ping.sonar;
    ASSERT_EQ(s.port.size(), 1024u);
    ASSERT_EQ(s.starboard.size(), 1024u);
    for (int i = 0; i < 4; ++i) {
      port_near += s.port[static_cast<std::size_t>(i)];
      port_far += s.port[static_cast<std::size_t>(1020 + i)];
      stbd_near += s.starboard[static_cast<std::size_t>(i)];
      stbd_far += s.starboard[static_cast<std::size_t>(1020 + i)];
    }
    EXPECT_NEAR(s.sound_speed_m_s, 1500.0, 1e-9);  // 2 x SoundVelocity 750
    ++n;
  }
  ASSERT_EQ(n, 460);
  EXPECT_EQ(port_near / (4 * n), 32767.0);
  EXPECT_EQ(stbd_near / (4 * n), 32767.0);
  EXPECT_LT(port_far / (4 * n), 10000.0);
  EXPECT_LT(stbd_far / (4 * n), 10000.0);
}

TEST(XtfReaderReal, ScotsmanFromMemoryEqualsFromFile) {
  const auto bytes = test::read_bytes(kScotsman);
  Reader a(kScotsman);
  Reader b(bytes, "memory");
  Packet pa, pb;
  std::size_t n = 0;
  while (a.next(pa)) {
    ASSERT_TRUE(b.next(pb));
    ASSERT_EQ(pa.offset, pb.offset);
    EXPECT_EQ(pa.ping.header, pb.ping.header);
    EXPECT_EQ(pa.ping.sonar.port, pb.ping.sonar.port);
    ++n;
  }
  EXPECT_FALSE(b.next(pb));
  EXPECT_EQ(n, 461u);
}

// ---- Sample layouts and channels -------------------------------------------------------------

struct LayoutCase {
  std::uint16_t bps;
  std::uint8_t format;
  std::uint16_t unipolar;
  std::vector<std::uint8_t> bytes;  // 2 samples
  float s0, s1;                     // file order
};

TEST(XtfReaderLayouts, IntegerAndFloatSamples) {
  const auto f32 = [](float a, float b) {
    std::vector<std::uint8_t> v(8);
    std::memcpy(v.data(), &a, 4);
    std::memcpy(v.data() + 4, &b, 4);
    return v;
  };
  const std::vector<LayoutCase> cases = {
      {1, 8, 1, {200, 7}, 200, 7},
      {1, 0, 1, {200, 7}, 200, 7},
      {1, 8, 0, {200, 7}, -56, 7},  // polar = signed
      {2, 3, 1, le16({40000, 5}), 40000, 5},
      {2, 3, 0, le16({40000, 5}), -25536, 5},
      {2, 0, 1, le16({123, 32767}), 123, 32767},
      {4, 2, 1, {0x00, 0x00, 0x01, 0x00, 0xFF, 0xFF, 0xFF, 0xFF}, 65536, 4294967295.0f},
      {4, 2, 0, {0x00, 0x00, 0x01, 0x00, 0xFF, 0xFF, 0xFF, 0xFF}, 65536, -1},
      {4, 5, 1, f32(1.5f, -2.25f), 1.5f, -2.25f},
      // IBM float: 0x42640000 = +100.0 (0.390625 * 16^2); 0xC1100000 = -1.0
      {4, 1, 1, {0x00, 0x00, 0x64, 0x42, 0x00, 0x00, 0x10, 0xC1}, 100.0f, -1.0f},
  };
  for (const LayoutCase& c : cases) {
    test::RawFile f;
    f.append(test::make_header(2, c.bps, c.format, c.unipolar));
    // channel 0 is PORT (reversed by the reader), channel 1 STBD (file order)
    f.append_raw(test::make_sonar_packet(0, {0, 1}, {c.bytes, c.bytes}, {2, 2}));
    Reader r(f.bytes, "layout");
    const auto pings = read_pings(r);
    ASSERT_EQ(pings.size(), 1u) << "bps " << c.bps << " format " << int{c.format};
    EXPECT_EQ(pings[0].sonar.starboard, (std::vector<float>{c.s0, c.s1}))
        << "bps " << c.bps << " format " << int{c.format};
    EXPECT_EQ(pings[0].sonar.port, (std::vector<float>{c.s1, c.s0}));
    EXPECT_EQ(r.total_anomalies(), 0u);
  }
}

TEST(XtfReaderLayouts, MoreThanSixChannels) {
  XtfFileHeader h = test::make_header(10, 2, 3);
  test::RawFile f;
  f.append(h);
  // one extra block with CHANINFO 6..13; 6..9 used (alternate PORT/STBD, 1 byte/sample)
  std::vector<std::uint8_t> block(1024, 0);
  ByteWriter w(block);
  for (std::size_t i = 0; i < 8; ++i) {
    XtfChanInfo c;
    c.TypeOfChannel = static_cast<std::uint8_t>(i % 2 == 0 ? 1 : 2);
    c.BytesPerSample = 1;
    c.SampleFormat = 8;
    c.UniPolar = 1;
    c.encode(w);
  }
  f.append_raw(block);
  std::vector<std::uint16_t> numbers;
  std::vector<std::vector<std::uint8_t>> data;
  for (std::uint16_t k = 0; k < 10; ++k) {
    numbers.push_back(k);
    data.push_back(k < 6 ? le16({k, 100 + k}) : std::vector<std::uint8_t>{std::uint8_t(k), 9});
  }
  f.append_raw(test::make_sonar_packet(0, numbers, data, std::vector<std::uint32_t>(10, 2)));
  Reader r(f.bytes, "ten");
  EXPECT_EQ(r.chan_info().size(), 10u);
  EXPECT_EQ(r.data_offset(), 2048u);
  const auto pings = read_pings(r);
  ASSERT_EQ(pings.size(), 1u);
  ASSERT_EQ(pings[0].channel_count, 10u);
  EXPECT_EQ(pings[0].channels[7].samples, (std::vector<float>{7, 9}));  // STBD: file order
  EXPECT_EQ(pings[0].channels[8].samples, (std::vector<float>{9, 8}));  // PORT: reversed
  EXPECT_EQ(pings[0].channels[3].samples, (std::vector<float>{3, 103}));
  EXPECT_EQ(r.total_anomalies(), 0u);
}

TEST(XtfReaderLayouts, UnknownPacketTypesAreSkipped) {
  test::RawFile f;
  f.append(test::make_header(2, 2, 3));
  XtfPacketHeader unknown;
  unknown.HeaderType = 199;
  unknown.NumBytesThisRecord = 192;
  f.append(unknown, 192);
  f.append_raw(test::make_sonar_packet(5, {0, 1}, {le16({1}), le16({2})}, {1, 1}));
  Reader r(f.bytes, "unknown");
  Packet p;
  ASSERT_TRUE(r.next(p));
  EXPECT_EQ(p.kind, PacketKind::kOther);
  EXPECT_EQ(p.header_type, 199);
  ASSERT_TRUE(r.next(p));
  EXPECT_EQ(p.kind, PacketKind::kPing);
  EXPECT_EQ(p.ping.header.PingNumber, 5u);
  EXPECT_FALSE(r.next(p));
  EXPECT_EQ(r.total_anomalies(), 0u);
}

// ---- Broken inputs ---------------------------------------------------------------------------

class XtfBrokenTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test::RawFile f;
    f.append(test::make_header(2, 2, 3));
    for (std::uint32_t i = 0; i < 3; ++i) {
      f.append_raw(test::make_sonar_packet(i, {0, 1}, {le16({1, 2, 3}), le16({4, 5, 6})}, {3, 3}));
    }
    good_ = f.bytes;
    packet_size_ = (good_.size() - 1024) / 3;
  }
  std::uint64_t packet(int i) const { return 1024 + static_cast<std::uint64_t>(i) * packet_size_; }
  /// Reads `b` (named `name`) and expects `count` pings, the one at `at` numbered `number`, and
  /// one anomaly of `kind`; the reader's anomalies go to `anomalies`.
  static void expect_one_skip(const std::vector<std::uint8_t>& b, const std::string& name,
                              std::size_t count, std::size_t at, std::uint32_t number,
                              AnomalyKind kind, std::vector<Anomaly>* anomalies = nullptr) {
    Reader r(b, name);
    const auto pings = read_pings(r);
    ASSERT_EQ(pings.size(), count);
    EXPECT_EQ(pings[at].header.PingNumber, number);
    EXPECT_EQ(r.anomaly_count(kind), 1u);
    if (anomalies != nullptr) *anomalies = r.anomalies();
  }
  /// What reading `b` (named `name`) gives: the number of pings, the anomalies of `kind` and the
  /// reader's anomalies.
  struct Read {
    std::size_t pings = 0;
    std::uint64_t of_kind = 0;
    std::vector<Anomaly> anomalies;
  };
  static Read read_all(const std::vector<std::uint8_t>& b, const std::string& name,
                       AnomalyKind kind) {
    Reader r(b, name);
    return {read_pings(r).size(), r.anomaly_count(kind), r.anomalies()};
  }
  /// Reads `b` (named `name`) and expects `count` pings and one anomaly of `kind`; returns the
  /// reader's anomalies.
  static std::vector<Anomaly> expect_one_anomaly(const std::vector<std::uint8_t>& b,
                                                 const std::string& name, std::size_t count,
                                                 AnomalyKind kind) {
    Read got = read_all(b, name, kind);
    EXPECT_EQ(got.pings, count);
    EXPECT_EQ(got.of_kind, 1u);
    return std::move(got.anomalies);
  }
  std::vector<std::uint8_t> good_;
  std::uint64_t packet_size_ = 0;
};

TEST_F(XtfBrokenTest, TruncatedHeaderIsAClearError) {
  const std::vector<std::uint8_t> b(good_.begin(), good_.begin() + 1000);
  try {
    Reader r(b, "short.xtf");
    FAIL();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("short.xtf has 1000 bytes"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(Reader(std::span<const std::uint8_t>{}, "empty"), FormatError);
}

TEST_F(XtfBrokenTest, BadFileFormatIsAClearError) {
  auto b = good_;
  b[0] = 0x12;
  try {
    Reader r(b, "x.xtf");
    FAIL();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("FileFormat = 0x12"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Reader(fs::path("/nonexistent/dir/a.xtf")), FormatError);
}

TEST_F(XtfBrokenTest, GarbageBetweenPacketsIsSkipped) {
  auto b = good_;
  const std::vector<std::uint8_t> garbage = {0xCE, 0x00, 0x12, 0xCE, 0xFA, 0xFF, 0xFF, 0xFF, 0xFF,
                                             0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01, 0x02};
  b.insert(b.begin() + static_cast<std::ptrdiff_t>(packet(1)), garbage.begin(), garbage.end());
  std::vector<Anomaly> a;
  ASSERT_NO_FATAL_FAILURE(expect_one_skip(b, "garbage", 3, 2, 2, AnomalyKind::kGarbageSkipped, &a));
  EXPECT_EQ(a[0].offset, packet(1));
  EXPECT_NE(a[0].message.find("skipped 17 bytes"), std::string::npos) << a[0].message;
}

TEST_F(XtfBrokenTest, BadMagicInAPacketResyncs) {
  auto b = good_;
  b[packet(1)] = 0x00;  // ping 1 loses its magic: skipped, ping 2 found again
  expect_one_skip(b, "magic", 2, 1, 2, AnomalyKind::kGarbageSkipped);
}

TEST_F(XtfBrokenTest, NumBytesThisRecordZero) {
  auto b = good_;
  put<std::uint32_t>(b, packet(1) + 10, 0);
  std::vector<Anomaly> a;
  ASSERT_NO_FATAL_FAILURE(expect_one_skip(b, "zero", 2, 1, 2, AnomalyKind::kBadRecordSize, &a));
  EXPECT_NE(a[0].message.find("NumBytesThisRecord = 0 at byte " + std::to_string(packet(1))),
            std::string::npos)
      << a[0].message;
}

TEST_F(XtfBrokenTest, NumBytesThisRecordHuge) {
  auto b = good_;
  put<std::uint32_t>(b, packet(0) + 10, 0xFFFFFFF0u);
  // ping 0 lost, 1 and 2 found by resync
  expect_one_skip(b, "huge", 2, 0, 1, AnomalyKind::kBadRecordSize);
}

TEST_F(XtfBrokenTest, NumBytesThisRecordSmallerThanThePingHeader) {
  auto b = good_;
  put<std::uint32_t>(b, packet(1) + 10, 64);
  const Read got = read_all(b, "small", AnomalyKind::kBadRecordSize);
  EXPECT_EQ(got.pings, 2u);
  EXPECT_GE(got.of_kind, 1u);
}

TEST_F(XtfBrokenTest, TruncatedLastPacketIsReportedAndTheRestKept) {
  const std::vector<std::uint8_t> b(good_.begin(), good_.end() - 30);
  Reader r(b, "trunc");
  const auto pings = read_pings(r);
  ASSERT_EQ(pings.size(), 2u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kTruncatedPacket), 1u);
  EXPECT_EQ(r.anomalies()[0].offset, packet(2));
  // a few trailing bytes, too few for a header
  const std::vector<std::uint8_t> c(good_.begin(),
                                    good_.begin() + static_cast<std::ptrdiff_t>(packet(2)) + 5);
  expect_one_anomaly(c, "trunc2", 2, AnomalyKind::kTruncatedPacket);
}

TEST_F(XtfBrokenTest, NumSamplesBeyondTheRecord) {
  auto b = good_;
  put<std::uint32_t>(b, packet(1) + 256 + 42, 1000000);
  ASSERT_NO_FATAL_FAILURE(
      expect_one_skip(b, "samples", 2, 1, 2, AnomalyKind::kSamplesBeyondRecord));
  put<std::uint32_t>(b, packet(1) + 256 + 42, 0xFFFFFFFFu);  // 64-bit product, no wrap
  expect_one_anomaly(b, "samples2", 2, AnomalyKind::kSamplesBeyondRecord);
}

TEST_F(XtfBrokenTest, ChannelNumberOutOfRange) {
  auto b = good_;
  put<std::uint16_t>(b, packet(0) + 256, 7);
  const std::vector<Anomaly> a = expect_one_anomaly(b, "chan", 2, AnomalyKind::kBadChannel);
  EXPECT_NE(a[0].message.find("ChannelNumber = 7"), std::string::npos);
}

TEST_F(XtfBrokenTest, NumChansToFollowBeyondTheRecord) {
  auto b = good_;
  put<std::uint16_t>(b, packet(0) + 4, 60000);
  expect_one_anomaly(b, "nchan", 2, AnomalyKind::kBadRecordSize);
}

// A count that passes the "64 bytes per channel" bound but not once the samples of the first
// channels are counted: 448-byte packets hold 256 + 2 x (64 + 6) = 396 bytes, a third channel
// header would need 64 more.
TEST_F(XtfBrokenTest, NumChansToFollowBeyondTheRecordAfterTheFirstChannels) {
  ASSERT_EQ(packet_size_, 448u);
  auto b = good_;
  put<std::uint16_t>(b, packet(1) + 4, 3);
  Reader r(b, "third_channel.xtf");
  const auto pings = read_pings(r);
  ASSERT_EQ(pings.size(), 2u);
  EXPECT_EQ(pings[0].header.PingNumber, 0u);
  EXPECT_EQ(pings[1].header.PingNumber, 2u);
  // The good pings are intact.
  ASSERT_EQ(pings[1].channel_count, 2u);
  EXPECT_EQ(pings[1].channels[1].samples, (std::vector<float>{4, 5, 6}));
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kBadRecordSize), 1u);
  EXPECT_EQ(r.total_anomalies(), 1u);
  ASSERT_EQ(r.anomalies().size(), 1u);
  const Anomaly& a = r.anomalies()[0];
  EXPECT_EQ(a.offset, packet(1));
  EXPECT_EQ(a.packet_index, 1u);
  for (const std::string& part :
       {std::string("NumChansToFollow = 3"), std::string("PingNumber 1"), std::string("packet 1"),
        "at byte " + std::to_string(packet(1)), std::string("third_channel.xtf"),
        std::string("header of channel 2")}) {
    EXPECT_NE(a.message.find(part), std::string::npos) << part << " in " << a.message;
  }
  // The summary counts it too, and packet indices follow the file.
  Reader r2(b, "third_channel.xtf");
  const FileSummary s = summarize(r2);
  EXPECT_EQ(s.pings, 2u);
  EXPECT_EQ(s.anomaly_counts[static_cast<std::size_t>(AnomalyKind::kBadRecordSize)], 1u);
  Reader r3(b, "third_channel.xtf");
  Packet p;
  std::vector<std::uint64_t> indices;
  while (r3.next(p)) indices.push_back(p.index);
  EXPECT_EQ(indices, (std::vector<std::uint64_t>{0, 2}));
}

TEST_F(XtfBrokenTest, HeaderClaimingManyChannelsWithoutExtraBlocks) {
  auto b = good_;
  put<std::uint16_t>(b, 166, 60000);  // would need 7500 extra blocks that are not there
  Reader r(b, "manychan");
  EXPECT_EQ(r.data_offset(), 1024u);
  EXPECT_EQ(read_pings(r).size(), 3u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kHeaderChannelCount), 1u);
}

TEST_F(XtfBrokenTest, InvalidTimeAndTimeGoingBackwardsAreFlagged) {
  auto b = good_;
  b[packet(0) + 16] = 13;  // month 13
  b[packet(2) + 21] = 0;   // ping 2 at .00, earlier than ping 1 at .01
  Reader r(b, "time");
  const auto pings = read_pings(r);
  ASSERT_EQ(pings.size(), 3u);
  EXPECT_FALSE(pings[0].time_valid);
  EXPECT_TRUE(pings[1].time_valid);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kInvalidTime), 1u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kTimeBackwards), 1u);
}

TEST_F(XtfBrokenTest, OversizedPacketIsSkippedWithoutReading) {
  ReaderOptions o;
  o.max_packet_bytes = 64;
  Reader r(good_, "limit", o);
  EXPECT_EQ(read_pings(r).size(), 0u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kOversizedPacket), 3u);
  o.max_packet_bytes = 10;
  EXPECT_THROW(Reader(good_, "limit", o), InputError);
}

TEST_F(XtfBrokenTest, AnomalyMessagesAreBoundedButAllCounted) {
  test::RawFile f;
  f.append(test::make_header(2, 2, 3));
  for (std::uint32_t i = 0; i < 50; ++i) {
    auto pk = test::make_sonar_packet(i, {0, 1}, {le16({1}), le16({2})}, {1, 1});
    put<double>(pk, 168, 0.0);  // zero navigation
    f.append_raw(pk);
  }
  ReaderOptions o;
  o.max_anomaly_messages = 5;
  Reader r(f.bytes, "many", o);
  EXPECT_EQ(read_pings(r).size(), 50u);
  EXPECT_EQ(r.anomalies().size(), 5u);
  EXPECT_EQ(r.anomaly_count(AnomalyKind::kZeroNavigation), 50u);
}

/// A virtual 5 GiB file: header, a 4 GiB unknown packet (skipped without being read), then a
/// ping past the 4 GiB mark. Proves offsets and size checks are 64-bit.
class HugeSource final : public ByteSource {
 public:
  HugeSource() {
    test::RawFile f;
    f.append(test::make_header(2, 2, 3));
    XtfPacketHeader big;
    big.HeaderType = 200;
    big.NumBytesThisRecord = 0xFFFFFF00u;
    f.append(big, 64);
    head_ = f.bytes;
    ping_offset_ = 1024 + std::uint64_t{0xFFFFFF00u};
    ping_ = test::make_sonar_packet(9, {0, 1}, {le16({1, 2}), le16({3, 4})}, {2, 2});
    size_ = ping_offset_ + ping_.size();
  }
  std::uint64_t size() const override { return size_; }
  const std::string& name() const override { return name_; }
  void read(std::uint64_t offset, std::span<std::uint8_t> out) override {
    ASSERT_LE(offset + out.size(), size_);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const std::uint64_t o = offset + i;
      out[i] = o < head_.size() ? head_[o] : o >= ping_offset_ ? ping_[o - ping_offset_] : 0;
    }
    bytes_read_ += out.size();
  }
  std::uint64_t ping_offset_ = 0;
  std::uint64_t bytes_read_ = 0;

 private:
  std::vector<std::uint8_t> head_, ping_;
  std::uint64_t size_ = 0;
  std::string name_ = "huge-virtual.xtf";
};

TEST(XtfReaderLarge, OffsetsBeyondFourGigabytes) {
  auto src = std::make_unique<HugeSource>();
  HugeSource* raw = src.get();
  Reader r(std::move(src));
  EXPECT_GT(r.file_size(), std::uint64_t{1} << 32);
  Packet p;
  ASSERT_TRUE(r.next(p));
  EXPECT_EQ(p.kind, PacketKind::kOther);
  EXPECT_EQ(p.size_bytes, 0xFFFFFF00u);
  ASSERT_TRUE(r.next(p));
  EXPECT_EQ(p.kind, PacketKind::kPing);
  EXPECT_EQ(p.offset, raw->ping_offset_);
  EXPECT_GT(p.offset, std::uint64_t{1} << 32);
  EXPECT_EQ(p.ping.sonar.starboard, (std::vector<float>{3, 4}));
  EXPECT_FALSE(r.next(p));
  EXPECT_EQ(r.total_anomalies(), 0u);
  EXPECT_LT(raw->bytes_read_, 1u << 20) << "the 4 GiB packet must be skipped, not read";
}

}  // namespace
}  // namespace sonarsynth::xtf
