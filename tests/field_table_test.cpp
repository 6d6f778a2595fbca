// SPDX-License-Identifier: MIT
// Field tables (sonarsynth/formats/io/fields.hpp): for every XTF and JSF record, a counting IO
// walks the table to exactly the record's documented size, encode writes and decode reads that
// many bytes, and arbitrary bytes decoded and encoded again come back unchanged (the reader and
// the writer walk the same fields with the same widths).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <span>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/io/fields.hpp"
#include "sonarsynth/formats/jsf/records.hpp"
#include "sonarsynth/formats/xtf/records.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth {
namespace {

/// The widths FieldCounter adds up, field by field, for a record default-constructed at run time.
template <class Record>
std::size_t counted_size() {
  FieldCounter c;
  Record r{};
  Record::fields(c, r);
  return c.size();
}

std::vector<std::uint8_t> arbitrary_bytes(std::size_t n, std::uint64_t seed) {
  std::vector<std::uint8_t> b(n);
  for (std::size_t i = 0; i < n; ++i) {
    b[i] = static_cast<std::uint8_t>(xtf::test::splitmix64(seed * 65536 + i));
  }
  return b;
}

/// Table size == kSize; decode reads and encode writes exactly kSize bytes; arbitrary bytes
/// round-trip unchanged.
template <class Record>
void expect_table_covers_record(std::size_t documented_size) {
  SCOPED_TRACE(documented_size);
  EXPECT_EQ(Record::kSize, documented_size);
  EXPECT_EQ(counted_size<Record>(), documented_size);
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const std::vector<std::uint8_t> in = arbitrary_bytes(Record::kSize, seed);
    ByteReader r(in, "test");
    const Record rec = Record::decode(r);
    EXPECT_EQ(r.position(), Record::kSize);
    std::vector<std::uint8_t> out(Record::kSize + 8, 0xEE);
    ByteWriter w(out, "test");
    rec.encode(w);
    EXPECT_EQ(w.position(), Record::kSize);
    out.resize(Record::kSize);
    EXPECT_EQ(out, in);
  }
}

TEST(FieldTables, CoverEveryXtfRecord) {
  expect_table_covers_record<xtf::XtfChanInfo>(128);
  expect_table_covers_record<xtf::XtfFileHeader>(1024);
  expect_table_covers_record<xtf::XtfPacketHeader>(14);
  expect_table_covers_record<xtf::XtfPingHeader>(256);
  expect_table_covers_record<xtf::XtfPingChanHeader>(64);
  expect_table_covers_record<xtf::XtfNotesHeader>(256);
  expect_table_covers_record<xtf::XtfAttitudeData>(64);
  expect_table_covers_record<xtf::XtfHeaderNavigation>(64);
}

TEST(FieldTables, CoverEveryJsfRecord) {
  // docs/jsf.md §1: 16-byte message header, 240-byte sonar data header, 24-byte system info.
  expect_table_covers_record<jsf::MessageHeader>(16);
  expect_table_covers_record<jsf::SonarDataHeader>(240);
  expect_table_covers_record<jsf::SystemInformation>(24);
}

/// The tagged records: tag + layout (20 bytes) + the table; the file fields end in 4 reserved
/// bytes, which decode skips and encode writes as zeros.
template <class Record>
void expect_tagged_record(std::size_t documented_size, std::size_t reserved_tail) {
  SCOPED_TRACE(documented_size);
  EXPECT_EQ(Record::kSize, documented_size);
  EXPECT_EQ(jsf::kXtfTagSize + counted_size<Record>(), documented_size);
  std::vector<std::uint8_t> in = arbitrary_bytes(Record::kSize, 7);
  std::fill(in.begin(), in.begin() + 20, std::uint8_t{0});
  constexpr std::string_view tag = "sonarsynth-xtf";
  std::copy(tag.begin(), tag.end(), in.begin());
  in[16] = static_cast<std::uint8_t>(jsf::XtfFileFields::kLayout);
  ByteReader r(in, "test");
  Record rec;
  ASSERT_TRUE(Record::decode(r, rec));
  EXPECT_EQ(r.position(), Record::kSize);
  std::vector<std::uint8_t> out(Record::kSize, 0xEE);
  ByteWriter w(out, "test");
  rec.encode(w);
  EXPECT_EQ(w.position(), Record::kSize);
  std::fill(in.end() - static_cast<std::ptrdiff_t>(reserved_tail), in.end(), std::uint8_t{0});
  EXPECT_EQ(out, in);
  // A wrong tag is refused after reading only the tag and the layout.
  in[0] = 'S';
  ByteReader bad(in, "test");
  EXPECT_FALSE(Record::decode(bad, rec));
  EXPECT_EQ(bad.position(), jsf::kXtfTagSize);
}

TEST(FieldTables, CoverTheTaggedJsfRecords) {
  expect_tagged_record<jsf::XtfFileFields>(260, 4);
  expect_tagged_record<jsf::XtfPingFields>(20 + 256 + 2 * 64, 0);
}

/// One field of each kind: the counter's widths are the writer's.
struct Mixed {
  std::uint8_t a = 1;
  std::uint16_t b = 2;
  std::uint32_t c = 3;
  std::uint64_t d = 4;
  std::int8_t e = -5;
  std::int16_t f = -6;
  std::int32_t g = -7;
  float h = 8.5f;
  double i = -9.25;
  std::array<std::uint8_t, 3> j{{10, 11, 12}};
  std::array<char, 5> k{{'a', 'b'}};
  template <class IO, class Self>
  static constexpr void fields(IO& io, Self& s) {
    io.u8(s.a);
    io.u16(s.b);
    io.u32(s.c);
    io.u64(s.d);
    io.i8(s.e);
    io.i16(s.f);
    io.i32(s.g);
    io.f32(s.h);
    io.f64(s.i);
    io.bytes(s.j);
    io.chars(s.k);
    io.reserved(2);
  }
};

TEST(FieldTables, CounterAddsTheWidthsTheWriterWrites) {
  constexpr std::size_t expected = 1 + 2 + 4 + 8 + 1 + 2 + 4 + 4 + 8 + 3 + 5 + 2;
  static_assert(field_table_size<Mixed>() == expected);
  std::vector<std::uint8_t> out(expected + 4, 0xEE);
  ByteWriter w(out, "test");
  write_fields(w, Mixed{});
  EXPECT_EQ(w.position(), expected);
  // Little-endian, field after field; the reserved bytes are zeros.
  EXPECT_EQ(out[0], 1);
  EXPECT_EQ(out[1], 2);
  EXPECT_EQ(out[2], 0);
  EXPECT_EQ(out[3], 3);
  EXPECT_EQ(out[7], 4);
  EXPECT_EQ(out[15], 0xFB);  // -5
  EXPECT_EQ(out[expected - 2], 0);
  EXPECT_EQ(out[expected - 1], 0);
  EXPECT_EQ(out[expected], 0xEE);
  ByteReader r(std::span<const std::uint8_t>(out).first(expected), "test");
  const Mixed back = read_fields<Mixed>(r);
  EXPECT_EQ(r.position(), expected);
  EXPECT_EQ(back.d, 4u);
  EXPECT_EQ(back.g, -7);
  EXPECT_EQ(back.i, -9.25);
  EXPECT_EQ(back.j, (std::array<std::uint8_t, 3>{{10, 11, 12}}));
  EXPECT_EQ(back.k[1], 'b');
}

}  // namespace
}  // namespace sonarsynth
