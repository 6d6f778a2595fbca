// SPDX-License-Identifier: MIT
// Every XTF record: encode writes exactly kSize bytes, decode(encode) is the identity on bytes,
// and selected fields land at the byte offsets the spec tables give (docs/xtf.md §1).
#include <gtest/gtest.h>

#include <cstring>

#include "sonarsynth/formats/xtf/records.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::xtf {
namespace {

template <typename Record>
std::vector<std::uint8_t> encode(const Record& r) {
  std::vector<std::uint8_t> b(Record::kSize, 0xEE);
  ByteWriter w(b);
  r.encode(w);
  EXPECT_EQ(w.position(), Record::kSize);
  return b;
}

template <typename Record>
void expect_bytes_round_trip(std::uint64_t seed) {
  // Arbitrary bytes -> decode -> encode must give the same bytes back: every field is read and
  // written at the same place and with the same width.
  std::vector<std::uint8_t> in(Record::kSize);
  for (std::size_t i = 0; i < in.size(); ++i) {
    in[i] = static_cast<std::uint8_t>(test::splitmix64(seed * 4096 + i));
  }
  ByteReader r(in);
  const Record rec = Record::decode(r);
  EXPECT_EQ(r.position(), Record::kSize);
  EXPECT_EQ(encode(rec), in);
}

template <typename T>
T at(const std::vector<std::uint8_t>& b, std::size_t offset) {
  T v;
  std::memcpy(&v, b.data() + offset, sizeof v);  // the test host is little-endian (x86-64)
  return v;
}

TEST(XtfRecords, SizesMatchTheSpec) {
  EXPECT_EQ(XtfChanInfo::kSize, 128u);
  EXPECT_EQ(XtfFileHeader::kSize, 1024u);
  EXPECT_EQ(XtfPacketHeader::kSize, 14u);
  EXPECT_EQ(XtfPingHeader::kSize, 256u);
  EXPECT_EQ(XtfPingChanHeader::kSize, 64u);
  EXPECT_EQ(XtfNotesHeader::kSize, 256u);
  EXPECT_EQ(XtfAttitudeData::kSize, 64u);
  EXPECT_EQ(XtfHeaderNavigation::kSize, 64u);
}

TEST(XtfRecords, EveryRecordRoundTripsItsBytes) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    expect_bytes_round_trip<XtfChanInfo>(seed);
    expect_bytes_round_trip<XtfFileHeader>(seed);
    expect_bytes_round_trip<XtfPacketHeader>(seed);
    expect_bytes_round_trip<XtfPingHeader>(seed);
    expect_bytes_round_trip<XtfPingChanHeader>(seed);
    expect_bytes_round_trip<XtfNotesHeader>(seed);
    expect_bytes_round_trip<XtfAttitudeData>(seed);
    expect_bytes_round_trip<XtfHeaderNavigation>(seed);
  }
}

TEST(XtfRecords, EncodeIntoAShortBufferThrows) {
  std::vector<std::uint8_t> b(XtfPingHeader::kSize - 1);
  ByteWriter w(b);
  EXPECT_THROW(XtfPingHeader{}.encode(w), FormatError);
  ByteReader r(b);
  EXPECT_THROW(XtfPingHeader::decode(r), FormatError);
}

TEST(XtfRecords, FileHeaderFieldOffsets) {
  XtfFileHeader h;
  h.RecordingProgramName = fixed_string<8>("Isis");
  h.SonarType = 44;
  h.NavUnits = 3;
  h.NumberOfSonarChannels = 2;
  h.NavigationLatency = -7;
  h.MRUOffsetRoll = 1.5f;
  h.ChanInfo[1].TypeOfChannel = 2;
  h.ChanInfo[1].BytesPerSample = 2;
  h.ChanInfo[1].Reserved = 1024;
  h.ChanInfo[1].Frequency = 600.0f;
  h.ChanInfo[1].SampleFormat = 3;
  const auto b = encode(h);
  EXPECT_EQ(b[0], 0x7B);
  EXPECT_EQ(b[1], 1);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(&b[2]), 4), "Isis");
  EXPECT_EQ(at<std::uint16_t>(b, 34), 44);
  EXPECT_EQ(at<std::uint16_t>(b, 164), 3);
  EXPECT_EQ(at<std::uint16_t>(b, 166), 2);
  EXPECT_EQ(at<std::int32_t>(b, 204), -7);
  EXPECT_EQ(at<float>(b, 252), 1.5f);
  EXPECT_EQ(b[256 + 128 + 0], 2);
  EXPECT_EQ(at<std::uint16_t>(b, 256 + 128 + 6), 2);
  EXPECT_EQ(at<std::uint32_t>(b, 256 + 128 + 8), 1024u);
  EXPECT_EQ(at<float>(b, 256 + 128 + 32), 600.0f);
  EXPECT_EQ(b[256 + 128 + 74], 3);
}

TEST(XtfRecords, PingHeaderFieldOffsets) {
  XtfPingHeader h;
  h.Header.NumChansToFollow = 2;
  h.Header.NumBytesThisRecord = 4480;
  h.Year = 2013;
  h.HSeconds = 23;
  h.PingNumber = 77;
  h.SoundVelocity = 750.0f;
  h.ComputedSoundVelocity = 1500.0f;
  h.ShipXcoordinate = -68.5;
  h.SensorYcoordinate = 48.25;
  h.SensorXcoordinate = -68.75;
  h.SensorPrimaryAltitude = 9.5f;
  h.SensorHeading = 123.5f;
  h.OptionalOffset = 0xA1B2C3D4u;
  h.CableOutHundredths = 9;
  const auto b = encode(h);
  EXPECT_EQ(at<std::uint16_t>(b, 0), 0xFACE);
  EXPECT_EQ(b[0], 0xCE);
  EXPECT_EQ(b[1], 0xFA);
  EXPECT_EQ(at<std::uint16_t>(b, 4), 2);
  EXPECT_EQ(at<std::uint32_t>(b, 10), 4480u);
  EXPECT_EQ(at<std::uint16_t>(b, 14), 2013);
  EXPECT_EQ(b[21], 23);
  EXPECT_EQ(at<std::uint32_t>(b, 28), 77u);
  EXPECT_EQ(at<float>(b, 32), 750.0f);
  EXPECT_EQ(at<float>(b, 72), 1500.0f);
  EXPECT_EQ(at<double>(b, 136), -68.5);
  EXPECT_EQ(at<double>(b, 160), 48.25);
  EXPECT_EQ(at<double>(b, 168), -68.75);
  EXPECT_EQ(at<float>(b, 196), 9.5f);
  EXPECT_EQ(at<float>(b, 212), 123.5f);
  EXPECT_EQ(at<std::uint32_t>(b, 245), 0xA1B2C3D4u);  // unaligned, as in the spec
  EXPECT_EQ(b[249], 9);
}

TEST(XtfRecords, PingChanHeaderFieldOffsets) {
  XtfPingChanHeader c;
  c.ChannelNumber = 1;
  c.SlantRange = 30.0f;
  c.TimeDuration = 0.04f;
  c.Frequency = 600;
  c.NumSamples = 1024;
  c.Weight = -3;
  const auto b = encode(c);
  EXPECT_EQ(at<std::uint16_t>(b, 0), 1);
  EXPECT_EQ(at<float>(b, 4), 30.0f);
  EXPECT_EQ(at<float>(b, 16), 0.04f);
  EXPECT_EQ(at<std::uint16_t>(b, 26), 600);
  EXPECT_EQ(at<std::uint32_t>(b, 42), 1024u);
  EXPECT_EQ(at<std::int16_t>(b, 58), -3);
}

TEST(XtfRecords, AttitudeNavigationNotesFieldOffsets) {
  XtfAttitudeData a;
  a.Header.HeaderType = 3;
  a.EpochMicroseconds = 123456;
  a.SourceEpoch = 1378847588;
  a.Pitch = 1.25f;
  a.TimeTag = 987654;
  a.Heading = 271.5f;
  a.Year = 2013;
  a.Milliseconds = 999;
  auto b = encode(a);
  EXPECT_EQ(b[2], 3);  // HeaderType at 2 (the spec table's "offset 1" is a typo)
  EXPECT_EQ(at<std::uint32_t>(b, 22), 123456u);
  EXPECT_EQ(at<std::uint32_t>(b, 26), 1378847588u);
  EXPECT_EQ(at<float>(b, 30), 1.25f);
  EXPECT_EQ(at<std::uint32_t>(b, 46), 987654u);
  EXPECT_EQ(at<float>(b, 50), 271.5f);
  EXPECT_EQ(at<std::uint16_t>(b, 54), 2013);
  EXPECT_EQ(at<std::uint16_t>(b, 61), 999);

  XtfHeaderNavigation n;
  n.Microseconds = 654321;
  n.RawYcoordinate = 48.5;
  n.RawXcoordinate = -68.5;
  n.RawAltitude = -3.0;
  n.TimeFlag = 1;
  b = encode(n);
  EXPECT_EQ(b[2], 42);
  EXPECT_EQ(at<std::uint32_t>(b, 10), 64u);
  EXPECT_EQ(at<std::uint32_t>(b, 21), 654321u);
  EXPECT_EQ(at<double>(b, 33), 48.5);
  EXPECT_EQ(at<double>(b, 41), -68.5);
  EXPECT_EQ(at<double>(b, 49), -3.0);
  EXPECT_EQ(b[57], 1);

  XtfNotesHeader t;
  t.NotesText = fixed_string<200>("hello");
  b = encode(t);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(&b[56]), 5), "hello");
}

TEST(XtfRecords, FixedStrings) {
  EXPECT_EQ(to_string(fixed_string<4>("ab")), "ab");
  EXPECT_EQ(to_string(fixed_string<4>("abcdef")), "abcd");  // full field, no terminator
}

TEST(XtfRecords, ExtraChanInfoBlocks) {
  EXPECT_EQ(XtfFileHeader::extra_blocks(0), 0u);
  EXPECT_EQ(XtfFileHeader::extra_blocks(6), 0u);
  EXPECT_EQ(XtfFileHeader::extra_blocks(7), 1u);
  EXPECT_EQ(XtfFileHeader::extra_blocks(14), 1u);
  EXPECT_EQ(XtfFileHeader::extra_blocks(15), 2u);
}

}  // namespace
}  // namespace sonarsynth::xtf
