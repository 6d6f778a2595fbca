// SPDX-License-Identifier: MIT
// Field tables (sonarsynth/formats/io/fields.hpp): for every XTF and JSF record, a counting IO
// walks the table to exactly the record's documented size, encode writes and decode reads that
// many bytes, and arbitrary bytes decoded and encoded again come back unchanged (the reader and
// the writer walk the same fields with the same widths). Between them the records use every
// call of the field IOs; the byte offsets of single fields are checked against the format
// documents in xtf_records_test.cpp and jsf_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
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

}  // namespace
}  // namespace sonarsynth
