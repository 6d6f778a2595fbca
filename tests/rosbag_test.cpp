// SPDX-License-Identifier: MIT
// ROS 1 bag writer: the MD5 algorithm against RFC 1321's test suite and against the MD5 sums of
// the ROS 1 message packages, and the record framing of a written bag read back by a small
// reader written here from the format 2.0 description (docs/rosbag.md, "File layout").
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/rosbag/messages.hpp"
#include "sonarsynth/formats/rosbag/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::rosbag {
namespace {

namespace fs = std::filesystem;

TEST(RosbagMd5, MatchesRfc1321TestSuite) {
  EXPECT_EQ(md5_hex(""), "d41d8cd98f00b204e9800998ecf8427e");
  EXPECT_EQ(md5_hex("abc"), "900150983cd24fb0d6963f7d28e17f72");
  EXPECT_EQ(md5_hex("message digest"), "f96b697d7cb7938d525a2f31aaf161d0");
  EXPECT_EQ(md5_hex("abcdefghijklmnopqrstuvwxyz"), "c3fcd3d76192e4007dfb496cca67e13b");
  EXPECT_EQ(md5_hex("12345678901234567890123456789012345678901234567890123456789012345678901234567"
                    "890"),
            "57edf4a22be3c955ac49da2e2107b67a");
}

// The MD5 sums the ROS 1 message packages state: sensor_msgs, std_msgs and tf2_msgs from
// Debian 12's python3-sensor-msgs 1.13.1, python3-std-msgs 0.5.13 and python3-tf2-msgs 0.7.6
// (the _md5sum of /usr/lib/python3/dist-packages/<package>/msg/_<Type>.py);
// marine_acoustic_msgs/RawSonarImage from the ROS 1 (catkin) generated code of
// marine_acoustic_msgs 2.0 (gennodejs' md5sum(), roslisp's md5sum), equal to what genmsg 0.6.0
// (python3-genmsg) computes from the .msg files.
TEST(RosbagMd5, MessageSumsEqualTheRosPackages) {
  EXPECT_EQ(message_md5("std_msgs/Header"), "2176decaecbce78abc3b96ef049fabed");
  EXPECT_EQ(message_md5("sensor_msgs/NavSatFix"), "2d3a8cd499b9b4a0249fb98fd05cfa48");
  EXPECT_EQ(message_md5("sensor_msgs/Imu"), "6a62c6daae103f4ff57a132d6f95cec2");
  EXPECT_EQ(message_md5("tf2_msgs/TFMessage"), "94810edda583a504dfda3829e70d7eec");
  EXPECT_EQ(message_md5("marine_acoustic_msgs/RawSonarImage"), "84d7210aa67320a9262e0908f3e466c5");
}

TEST(RosbagMd5, ConstantsCommentsAndNestedTypes) {
  // A made-up package: comments and blank lines do not count, constants come first with their
  // whitespace removed, a nested type counts by its own MD5 (also inside an array).
  const std::vector<MessageText> texts = {
      {"p/Inner", "int8 A = -1  # comment\nfloat64 x\n"},
      {"p/Outer", "# top\n\nInner[] inners\nuint8[4] raw # bytes\nstring NAME_IS = x\n"},
  };
  const std::string inner = md5_hex("int8 A=-1\nfloat64 x");
  EXPECT_EQ(message_md5("p/Inner", texts), inner);
  EXPECT_EQ(message_md5("p/Outer", texts),
            md5_hex("string NAME_IS=x\n" + inner + " inners\nuint8[4] raw"));
  EXPECT_EQ(message_definition("p/Outer", texts), std::string(texts[1].text) + "\n" +
                                                      std::string(80, '=') + "\nMSG: p/Inner\n" +
                                                      std::string(texts[0].text));
  EXPECT_THROW((void)message_md5("p/Missing", texts), Error);
}

// A minimal format 2.0 reader: records as (header fields, data).
struct Record {
  std::uint64_t pos = 0;
  std::map<std::string, std::string> fields;
  std::string data;
};

std::uint32_t u32_at(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i)
    v = v << 8 | static_cast<std::uint8_t>(s[at + static_cast<std::size_t>(i)]);
  return v;
}
std::uint64_t u64_at(const std::string& s, std::size_t at) {
  return u32_at(s, at) | static_cast<std::uint64_t>(u32_at(s, at + 4)) << 32;
}

std::map<std::string, std::string> parse_fields(const std::string& h) {
  std::map<std::string, std::string> out;
  for (std::size_t at = 0; at < h.size();) {
    const std::uint32_t n = u32_at(h, at);
    const std::string f = h.substr(at + 4, n);
    const auto eq = f.find('=');
    out[f.substr(0, eq)] = f.substr(eq + 1);
    at += 4 + n;
  }
  return out;
}

Record record_at(const std::string& bytes, std::uint64_t pos) {
  Record r;
  r.pos = pos;
  const auto at = static_cast<std::size_t>(pos);
  const std::uint32_t hl = u32_at(bytes, at);
  r.fields = parse_fields(bytes.substr(at + 4, hl));
  const std::uint32_t dl = u32_at(bytes, at + 4 + hl);
  r.data = bytes.substr(at + 8 + hl, dl);
  return r;
}
std::uint64_t end_of(const Record& r, const std::string& bytes) {
  return r.pos + 8 + u32_at(bytes, static_cast<std::size_t>(r.pos)) + r.data.size();
}

SonarPing test_ping(std::uint32_t number, int seconds) {
  SonarPing p;
  p.time_utc = UtcTime{std::chrono::seconds{1700000000 + seconds}} + std::chrono::microseconds{250};
  p.ping_number = number;
  p.sensor_position = {0.7, 0.2, 0.0};
  p.slant_range_m = 50.0;
  p.sound_speed_m_s = 1500.0;
  for (std::uint32_t i = 0; i < 100; ++i) {
    p.port.push_back(static_cast<float>(i * 300 + number));
    p.starboard.push_back(static_cast<float>(i + number));
  }
  p.port[7] = 40000.0f;  // clamped to 32767, as XTF
  return p;
}

TEST(RosbagWriter, RecordFramingIndexAndSamples) {
  const fs::path dir = xtf::test::temp_dir("rosbag_framing");
  WriterOptions o;
  o.chunk_bytes = 1000;  // a chunk per ping or so: several chunks
  Writer w(dir / "a.bag", o);
  for (std::uint32_t k = 0; k < 3; ++k) w.write_ping(test_ping(k, static_cast<int>(k)));
  w.close();
  EXPECT_EQ(w.clipped_samples(), 3u);
  std::ifstream in(dir / "a.bag", std::ios::binary);
  const std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(b.substr(0, 13), "#ROSBAG V2.0\n");
  const Record header = record_at(b, 13);
  EXPECT_EQ(header.fields.at("op"), "\x03");
  EXPECT_EQ(end_of(header, b), 13u + 4096u);
  const std::uint64_t index_pos = u64_at(header.fields.at("index_pos"), 0);
  const std::uint32_t conns = u32_at(header.fields.at("conn_count"), 0);
  const std::uint32_t chunks = u32_at(header.fields.at("chunk_count"), 0);
  EXPECT_EQ(conns, 5u);
  EXPECT_GE(chunks, 3u);
  // The index: the connection records, then one chunk info per chunk, to the end of the file.
  std::uint64_t pos = index_pos;
  std::map<std::uint32_t, std::string> topics;
  for (std::uint32_t c = 0; c < conns; ++c) {
    const Record r = record_at(b, pos);
    ASSERT_EQ(r.fields.at("op"), "\x07");
    const auto d = parse_fields(r.data);
    EXPECT_EQ(d.at("topic"), r.fields.at("topic"));
    EXPECT_EQ(d.at("md5sum"), message_md5(d.at("type")));
    topics[u32_at(r.fields.at("conn"), 0)] = d.at("topic");
    pos = end_of(r, b);
  }
  EXPECT_EQ(topics.at(0), kPortTopic);
  std::map<std::string, std::uint32_t> per_topic;
  std::uint64_t prev_end_ns = 0;
  for (std::uint32_t c = 0; c < chunks; ++c) {
    const Record info = record_at(b, pos);
    ASSERT_EQ(info.fields.at("op"), "\x06");
    const Record chunk = record_at(b, u64_at(info.fields.at("chunk_pos"), 0));
    ASSERT_EQ(chunk.fields.at("op"), "\x05");
    EXPECT_EQ(chunk.fields.at("compression"), "none");
    EXPECT_EQ(u32_at(chunk.fields.at("size"), 0), chunk.data.size());
    const std::uint64_t start_ns = u32_at(info.fields.at("start_time"), 0) * 1000000000ull +
                                   u32_at(info.fields.at("start_time"), 4);
    EXPECT_GE(start_ns, prev_end_ns);
    prev_end_ns = u32_at(info.fields.at("end_time"), 0) * 1000000000ull +
                  u32_at(info.fields.at("end_time"), 4);
    // The index data records follow the chunk: each entry points at a message of its
    // connection with its time.
    std::uint64_t ipos = end_of(chunk, b);
    const std::uint32_t n_conn = u32_at(info.fields.at("count"), 0);
    for (std::uint32_t i = 0; i < n_conn; ++i) {
      const Record idx = record_at(b, ipos);
      ASSERT_EQ(idx.fields.at("op"), "\x04");
      const std::uint32_t conn = u32_at(idx.fields.at("conn"), 0);
      EXPECT_EQ(u32_at(info.data, 8 * i), conn);
      const std::uint32_t count = u32_at(idx.fields.at("count"), 0);
      EXPECT_EQ(u32_at(info.data, 8 * i + 4), count);
      for (std::uint32_t e = 0; e < count; ++e) {
        const Record m = record_at(chunk.data, u32_at(idx.data, 12 * e + 8));
        EXPECT_EQ(m.fields.at("op"), "\x02");
        EXPECT_EQ(u32_at(m.fields.at("conn"), 0), conn);
        EXPECT_EQ(m.fields.at("time"), idx.data.substr(12 * e, 8));
        ++per_topic[topics.at(conn)];
        if (conn == 0) {  // port image: header.seq is the ping number, samples at the end
          const std::uint32_t seq = u32_at(m.data, 0);
          const SonarPing p = test_ping(seq, static_cast<int>(seq));
          EXPECT_EQ(u32_at(m.data, 4), 1700000000u + seq);
          EXPECT_EQ(u32_at(m.data, 8), 250000u);
          const std::size_t at = m.data.size() - 200;
          EXPECT_EQ(u32_at(m.data, at - 4), 200u);
          for (std::size_t s = 0; s < 100; ++s) {
            const auto v =
                static_cast<std::uint32_t>(static_cast<std::uint8_t>(m.data[at + 2 * s])) |
                static_cast<std::uint32_t>(static_cast<std::uint8_t>(m.data[at + 2 * s + 1])) << 8;
            EXPECT_EQ(v, s == 7 ? 32767u : static_cast<std::uint32_t>(p.port[s]));
          }
        }
      }
      ipos = end_of(idx, b);
    }
    pos = end_of(info, b);
  }
  EXPECT_EQ(pos, b.size());
  EXPECT_EQ(per_topic[kPortTopic], 3u);
  EXPECT_EQ(per_topic[kStarboardTopic], 3u);
  EXPECT_EQ(per_topic[kFixTopic], 3u);
  EXPECT_EQ(per_topic[kImuTopic], 3u);
  EXPECT_EQ(per_topic[kTfStaticTopic], 1u);
  fs::remove_all(dir);
}

TEST(RosbagWriter, RefusesWhatABagCannotHoldAndLeavesNoFile) {
  const fs::path dir = xtf::test::temp_dir("rosbag_refuse");
  {
    Writer w(dir / "b.bag");
    SonarPing p = test_ping(0, 0);
    p.time_utc = UtcTime{std::chrono::seconds{-5}};
    EXPECT_THROW(w.write_ping(p), InputError);
    p = test_ping(0, 0);
    p.starboard.clear();
    EXPECT_THROW(w.write_ping(p), InputError);
  }
  EXPECT_FALSE(fs::exists(dir / "b.bag"));
  WriterOptions o;
  o.sample_format = "s16";
  EXPECT_THROW(Writer(dir / "c.bag", o), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth::rosbag
