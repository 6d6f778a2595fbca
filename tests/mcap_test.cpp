// SPDX-License-Identifier: MIT
// ROS 2 bags in MCAP (docs/robotics.md): a minimal reader written here from the MCAP
// specification walks every record (lengths, CRCs, chunks decompressed, indexes pointing at
// what they claim), decodes the side-scan messages' CDR, and compares them with the XTF of the
// same run; then the independent npm reader (tests/mcap_reader) does the same from outside.
#include <gtest/gtest.h>
#include <zlib.h>
#include <zstd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bag_run_test_util.hpp"
#include "error_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/io/byte_io.hpp"
#include "sonarsynth/formats/mcap/writer.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

std::vector<std::uint8_t> file_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::uint32_t crc(std::span<const std::uint8_t> b) {
  return static_cast<std::uint32_t>(crc32_z(0L, b.data(), b.size()));
}

/// One side-scan message as the test decodes it.
struct SideMessage {
  std::uint64_t time_ns = 0;
  std::string frame_id;
  std::uint32_t dtype = 0;
  std::vector<float> samples;
};

/// What the test-side reader found in a bag.
struct Bag {
  std::map<std::uint16_t, std::string> topics;  // channel id -> topic
  std::map<std::string, std::uint64_t> messages_per_topic;
  std::uint64_t messages = 0, statistics_messages = 0, chunks = 0, chunk_indexes = 0;
  std::vector<SideMessage> port, starboard;
};

std::string str(ByteReader& r) {
  std::string s(r.u32(), '\0');
  for (char& c : s) c = static_cast<char>(r.u8());
  return s;
}

/// CDR of a RawSonarImage (alignment relative to after the 4-byte encapsulation header).
SideMessage decode_raw_sonar_image(std::span<const std::uint8_t> m) {
  EXPECT_EQ(m[0], 0x00);
  EXPECT_EQ(m[1], 0x01);  // CDR_LE
  ByteReader r(m.subspan(4), "cdr");
  const auto align = [&](std::size_t n) { r.skip((n - r.position() % n) % n); };
  const auto f32_seq = [&] {
    align(4);
    const std::uint32_t n = r.u32();
    for (std::uint32_t i = 0; i < n; ++i) (void)r.f32();
  };
  SideMessage s;
  const std::int32_t sec = r.i32();
  const std::uint32_t nanosec = r.u32();
  s.time_ns = static_cast<std::uint64_t>(sec) * 1'000'000'000u + nanosec;
  s.frame_id = str(r);
  s.frame_id.pop_back();  // the CDR string's NUL
  align(4);
  (void)r.f32();  // frequency
  (void)r.f32();  // sound speed
  f32_seq();
  f32_seq();
  (void)r.f32();  // sample rate
  const std::uint32_t samples_per_beam = r.u32();
  EXPECT_EQ(r.u32(), 0u);  // sample0
  f32_seq();
  f32_seq();
  f32_seq();
  EXPECT_EQ(r.u8(), 0);  // is_bigendian
  align(4);
  s.dtype = r.u32();
  EXPECT_EQ(r.u32(), 1u);  // beam_count
  const std::uint32_t n = r.u32();
  for (std::uint32_t i = 0; i < samples_per_beam; ++i) {
    s.samples.push_back(s.dtype == 2   ? static_cast<float>(r.u16())
                        : s.dtype == 0 ? static_cast<float>(r.u8())
                                       : r.f32());
  }
  EXPECT_EQ(n, samples_per_beam * (s.dtype == 2 ? 2u : s.dtype == 0 ? 1u : 4u));
  EXPECT_EQ(r.remaining(), 0u);
  return s;
}

/// The messages of one decompressed chunk; checks its MessageIndex entries against them.
void read_chunk(std::span<const std::uint8_t> records, Bag& bag,
                std::map<std::uint64_t, std::pair<std::uint16_t, std::uint64_t>>& by_offset) {
  ByteReader r(records, "chunk");
  while (r.remaining() > 0) {
    const std::uint64_t at = r.position();
    const std::uint8_t op = r.u8();
    const std::uint64_t len = r.u64();
    ASSERT_LE(len, r.remaining());
    const std::span<const std::uint8_t> body = records.subspan(r.position(), len);
    r.skip(len);
    ASSERT_EQ(op, 0x05) << "only messages inside chunks";
    ByteReader m(body, "message");
    const std::uint16_t channel = m.u16();
    (void)m.u32();  // sequence
    const std::uint64_t log_time = m.u64();
    EXPECT_EQ(m.u64(), log_time);  // publish time
    by_offset[at] = {channel, log_time};
    const std::string& topic = bag.topics.at(channel);
    ++bag.messages_per_topic[topic];
    ++bag.messages;
    if (topic.ends_with("/port") || topic.ends_with("/starboard")) {
      SideMessage s = decode_raw_sonar_image(body.subspan(m.position()));
      EXPECT_EQ(s.time_ns, log_time);
      (topic.ends_with("/port") ? bag.port : bag.starboard).push_back(std::move(s));
    }
  }
}

/// Walks a whole bag record by record (docs/robotics.md, "File layout").
Bag read_bag(const fs::path& path) {
  const std::vector<std::uint8_t> f = file_bytes(path);
  const std::array<std::uint8_t, 8> magic = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
  Bag bag;
  EXPECT_GT(f.size(), 16u);
  EXPECT_TRUE(std::equal(magic.begin(), magic.end(), f.begin()));
  EXPECT_TRUE(std::equal(magic.begin(), magic.end(), f.end() - 8));
  ByteReader r(std::span<const std::uint8_t>(f).first(f.size() - 8), "mcap");
  r.skip(8);
  std::map<std::uint64_t, std::pair<std::uint16_t, std::uint64_t>> messages;  // of the last chunk
  std::map<std::uint64_t, std::uint8_t> opcode_at;
  bool data_end = false, footer = false;
  std::uint64_t summary_start = 0;
  while (r.remaining() > 0) {
    const std::uint64_t at = r.position();
    const std::uint8_t op = r.u8();
    const std::uint64_t len = r.u64();
    EXPECT_LE(len, r.remaining()) << "record at " << at;
    if (len > r.remaining()) break;
    const std::span<const std::uint8_t> body(f.data() + r.position(), len);
    r.skip(len);
    opcode_at[at] = op;
    ByteReader b(body, "record");
    if (op == 0x01) {
      EXPECT_EQ(at, 8u);
      EXPECT_EQ(str(b), "ros2");
    } else if (op == 0x04 && !data_end) {
      const std::uint16_t id = b.u16();
      (void)b.u16();
      bag.topics[id] = str(b);
      EXPECT_EQ(str(b), "cdr");
    } else if (op == 0x03) {
      (void)b.u16();
      (void)str(b);
      EXPECT_EQ(str(b), "ros2msg");
    } else if (op == 0x06) {
      ++bag.chunks;
      (void)b.u64();
      (void)b.u64();
      const std::uint64_t size = b.u64();
      const std::uint32_t stored_crc = b.u32();
      EXPECT_EQ(str(b), "zstd");
      const std::uint64_t n = b.u64();
      EXPECT_EQ(n, b.remaining());
      std::vector<std::uint8_t> plain(size);
      const std::size_t got =
          ZSTD_decompress(plain.data(), plain.size(), body.data() + b.position(), n);
      EXPECT_EQ(got, size) << (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "");
      EXPECT_EQ(crc(plain), stored_crc) << "chunk at " << at;
      messages.clear();
      read_chunk(plain, bag, messages);
    } else if (op == 0x07) {
      const std::uint16_t channel = b.u16();
      const std::uint32_t n = b.u32();
      EXPECT_EQ(n % 16, 0u);
      for (std::uint32_t i = 0; i < n / 16; ++i) {
        const std::uint64_t time = b.u64();
        const auto m = messages.find(b.u64());
        EXPECT_NE(m, messages.end()) << "message index entry not at a message";
        if (m != messages.end()) {
          EXPECT_EQ(m->second, std::make_pair(channel, time));
        }
      }
    } else if (op == 0x0F) {
      data_end = true;
      summary_start = r.position();
      EXPECT_EQ(b.u32(), crc(std::span<const std::uint8_t>(f).first(at))) << "data section CRC";
    } else if (op == 0x0B) {
      bag.statistics_messages = b.u64();
    } else if (op == 0x08) {
      ++bag.chunk_indexes;
      b.skip(16);
      const std::uint64_t chunk_at = b.u64();
      EXPECT_EQ(opcode_at[chunk_at], 0x06);
      const std::uint64_t chunk_length = b.u64();
      EXPECT_EQ(opcode_at[chunk_at + chunk_length], 0x07);
      const std::uint32_t map_bytes = b.u32();
      for (std::uint32_t i = 0; i < map_bytes / 10; ++i) {
        (void)b.u16();
        EXPECT_EQ(opcode_at[b.u64()], 0x07);
      }
    } else if (op == 0x02) {
      footer = true;
      EXPECT_EQ(b.u64(), summary_start);
      const std::uint64_t offsets_at = b.u64();
      EXPECT_EQ(opcode_at[offsets_at], 0x0E);
      EXPECT_EQ(b.u32(), crc(std::span<const std::uint8_t>(f).subspan(
                             summary_start, at + 1 + 8 + 16 - summary_start)))
          << "summary CRC";
      EXPECT_EQ(r.remaining(), 0u);
    }
  }
  EXPECT_TRUE(data_end);
  EXPECT_TRUE(footer);
  return bag;
}

std::uint64_t distance_ns(std::uint64_t a, std::uint64_t b) {
  return a > b ? a - b : b - a;
}

struct XtfPing {
  std::uint64_t time_ns;
  std::vector<float> port, starboard;
};

std::vector<XtfPing> read_xtf(const fs::path& path) {
  xtf::Reader reader(path);
  xtf::Packet packet;
  std::vector<XtfPing> out;
  while (reader.next(packet)) {
    if (packet.kind != xtf::PacketKind::kPing) continue;
    const SonarPing& s = packet.ping.sonar;
    out.push_back({static_cast<std::uint64_t>(s.time_utc.time_since_epoch().count()) * 1000u,
                   s.port, s.starboard});
  }
  return out;
}

class McapTest : public test::BagRunTest {
 protected:
  McapTest() : BagRunTest("mcap_", test::bag_scene("mcap-run", "")) {}
  /// Runs the scene with output.formats [xtf, mcap] and `output` appended.
  fs::path simulate(const std::string& output) {
    return BagRunTest::simulate("formats: [xtf, mcap]" + output);
  }
  /// Every ping of the bag equals the XTF's: samples exactly, time to XTF's 10 ms (rounded).
  static void expect_same_pings(const Bag& bag, const std::vector<XtfPing>& xtf,
                                std::uint32_t dtype) {
    ASSERT_FALSE(xtf.empty());
    ASSERT_EQ(bag.port.size(), xtf.size());
    ASSERT_EQ(bag.starboard.size(), xtf.size());
    for (std::size_t i = 0; i < xtf.size(); ++i) {
      EXPECT_EQ(bag.port[i].samples, xtf[i].port) << "ping " << i;
      EXPECT_EQ(bag.starboard[i].samples, xtf[i].starboard) << "ping " << i;
      EXPECT_EQ(bag.port[i].dtype, dtype);
      EXPECT_EQ(bag.port[i].frame_id, "sidescan_port");
      EXPECT_EQ(bag.starboard[i].frame_id, "sidescan_starboard");
      EXPECT_LE(distance_ns(bag.port[i].time_ns, xtf[i].time_ns), 5'000'000u) << "ping " << i;
    }
  }
};

// The bag of a run: records well formed, CRCs right, every message indexed and counted, and per
// ping a RawSonarImage per side equal to the XTF of the same run.
TEST_F(McapTest, BagOfARunHoldsTheXtfPings) {
  for (const auto& [format, dtype] :
       {std::pair{std::string("u16"), 2u}, std::pair{std::string("f32"), 8u}}) {
    SCOPED_TRACE(format);
    const fs::path out = simulate(", sample_format: " + format);
    const Bag bag = read_bag(out / "a.mcap");
    const std::vector<XtfPing> xtf = read_xtf(out / "a.xtf");
    expect_same_pings(bag, xtf, dtype);
    // 2 side-scan messages + 1 NavSatFix + 1 Imu per ping, and the one /tf_static message.
    EXPECT_EQ(bag.messages, 4 * xtf.size() + 1);
    EXPECT_EQ(bag.statistics_messages, bag.messages);
    EXPECT_EQ(bag.messages_per_topic.at("/sonarsynth/fix"), xtf.size());
    EXPECT_EQ(bag.messages_per_topic.at("/sonarsynth/imu"), xtf.size());
    EXPECT_EQ(bag.messages_per_topic.at("/tf_static"), 1u);
    EXPECT_GE(bag.chunks, 1u);
    EXPECT_EQ(bag.chunk_indexes, bag.chunks);
    fs::remove_all(out);
  }
}

/// Writes `ping` alone into `path` (replaced) with samples encoded as `e`; returns the samples
/// the writer clipped.
template <class Writer, class WriterOptions>
std::uint64_t write_one(const fs::path& path, xtf::SampleEncoding e, const SonarPing& ping) {
  WriterOptions o;
  o.sample_encoding = e;
  o.overwrite = true;
  Writer w(path, o);
  w.write_ping(ping);
  w.close();
  return w.clipped_samples();
}

// Values at the edges of rounding and clamping (halves, negatives, above full scale, NaN,
// infinities) come out of the bag as out of the XTF writer, counted as clipped alike.
TEST_F(McapTest, EdgeValuesQuantiseAsInTheXtf) {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> edge = {-1e9f,    -1.0f,      -0.5f,      -0.49f, 0.0f,          0.49f,
                                   0.5f,     1.5f,       2.5f,       254.5f, 255.49f,       255.5f,
                                   32766.5f, 32767.4f,   32767.5f,   1e9f,   std::nanf(""), inf,
                                   -inf,     8388607.5f, 16777216.0f};
  for (const auto e :
       {xtf::SampleEncoding::kUint16, xtf::SampleEncoding::kUint8, xtf::SampleEncoding::kFloat32}) {
    SCOPED_TRACE(static_cast<int>(e));
    SonarPing p;
    p.time_utc = UtcTime(std::chrono::seconds(1'700'000'000));
    p.sensor_position = {rad_from_deg(43.0), rad_from_deg(5.0)};
    p.altitude_m = 5.0;
    p.slant_range_m = 20.0;
    p.port = edge;
    p.starboard = edge;
    const std::uint64_t mcap_clipped =
        write_one<mcap::Writer, mcap::WriterOptions>(dir_ / "edge.mcap", e, p);
    EXPECT_EQ(mcap_clipped, (write_one<xtf::Writer, xtf::WriterOptions>(dir_ / "edge.xtf", e, p)));
    const std::vector<XtfPing> x = read_xtf(dir_ / "edge.xtf");
    const Bag bag = read_bag(dir_ / "edge.mcap");
    ASSERT_EQ(x.size(), 1u);
    ASSERT_EQ(bag.port.size(), 1u);
    EXPECT_EQ(bag.port[0].samples, x[0].port);
    EXPECT_EQ(bag.starboard[0].samples, x[0].starboard);
  }
}

// Stand-alone attitude samples are Imu messages of their own (indexed, counted in the summary);
// a non-finite angle or a time outside builtin_interfaces/Time is refused, naming the field.
TEST_F(McapTest, AttitudeSamplesAreImuMessages) {
  SonarPing p;
  p.time_utc = UtcTime(std::chrono::seconds(1'700'000'000));
  p.sensor_position = {rad_from_deg(43.0), rad_from_deg(5.0)};
  p.slant_range_m = 20.0;
  p.port = p.starboard = std::vector<float>(16, 100.0f);
  mcap::WriterOptions o;
  o.overwrite = true;
  mcap::Writer w(dir_ / "att.mcap", o);
  w.write_ping(p);
  const AttitudeSample a{p.time_utc + std::chrono::milliseconds(40), 0.5, 0.01, -0.02, 0.0, 0.0};
  w.write_attitude(a);
  w.write_attitude({a.time_utc + std::chrono::milliseconds(40), 0.6, 0.0, 0.0, 0.0, 0.0});
  AttitudeSample nan_heading = a;
  nan_heading.heading_true_rad = std::numeric_limits<double>::quiet_NaN();
  test::expect_error([&] { w.write_attitude(nan_heading); }, {"attitude.heading_true_rad", "nan"},
                     "a NaN heading");
  AttitudeSample before_1970 = a;
  before_1970.time_utc = UtcTime(std::chrono::seconds(-1));
  test::expect_error([&] { w.write_attitude(before_1970); }, {"attitude.time_utc", "-1000000"},
                     "an attitude time before 1970");
  w.close();
  const Bag bag = read_bag(dir_ / "att.mcap");
  EXPECT_EQ(bag.messages_per_topic.at("/sonarsynth/imu"), 3u);
  EXPECT_EQ(bag.messages, 4u + 1u + 2u);
  EXPECT_EQ(bag.statistics_messages, bag.messages);
}

// `convert` XTF -> MCAP: the bag holds the XTF's samples (as uint16, the file's type).
TEST_F(McapTest, ConvertXtfToMcapKeepsEverySample) {
  const fs::path out = simulate("");
  const ConvertResult r = convert_sonar_file(out / "a.xtf", dir_ / "a.mcap");
  const std::vector<XtfPing> xtf = read_xtf(out / "a.xtf");
  EXPECT_EQ(r.pings, xtf.size());
  EXPECT_EQ(r.pings_skipped, 0u);
  expect_same_pings(read_bag(dir_ / "a.mcap"), xtf, 2u);
}

// The independent reader: @mcap/core, @foxglove/rosmsg and @foxglove/rosmsg2-serialization
// (tests/mcap_reader, installed by tests/mcap_reader/install.sh into the build directory).
TEST_F(McapTest, IndependentNpmReaderDecodesTheXtfPings) {
  const fs::path modules = SONARSYNTH_MCAP_READER_MODULES;
  if (const std::string why = test::npm_reader_missing(modules); !why.empty()) GTEST_SKIP() << why;
  const fs::path out = simulate("");
  const fs::path json_path = dir_ / "bag.json";
  const std::string command = "NODE_PATH='" + modules.string() + "' node '" +
                              SONARSYNTH_MCAP_READER_SCRIPT + "' '" + (out / "a.mcap").string() +
                              "' > '" + json_path.string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream in(json_path);
  const nlohmann::json j = nlohmann::json::parse(in);
  const std::vector<XtfPing> xtf = read_xtf(out / "a.xtf");
  EXPECT_EQ(j.at("profile"), "ros2");
  EXPECT_EQ(j.at("messages").get<std::uint64_t>(), 4 * xtf.size() + 1);
  EXPECT_EQ(j.at("compression"), nlohmann::json::array({"zstd"}));
  ASSERT_EQ(j.at("pings").size(), xtf.size());
  for (std::size_t i = 0; i < xtf.size(); ++i) {
    const nlohmann::json& p = j.at("pings")[i];
    EXPECT_EQ(p.at("port").at("samples").get<std::vector<float>>(), xtf[i].port) << i;
    EXPECT_EQ(p.at("starboard").at("samples").get<std::vector<float>>(), xtf[i].starboard) << i;
    const std::uint64_t t_ns = p.at("t_us").get<std::uint64_t>() * 1000u;
    EXPECT_LE(distance_ns(t_ns, xtf[i].time_ns), 5'000'000u) << i;
    // Sample i covers [i, i+1) R / n of slant range: n c / (2 R) samples per second.
    EXPECT_FLOAT_EQ(p.at("port").at("sample_rate").get<float>(), 300.0f * 1500.0f / 40.0f);
  }
  EXPECT_EQ(j.at("nav").size(), xtf.size());
  EXPECT_EQ(j.at("imu").size(), xtf.size());
  // Each side's frame turns base_link's x axis to its beam axis: to port (+y) or starboard (-y),
  // down by the tilt (20 deg, the sonar's default).
  ASSERT_EQ(j.at("tf").size(), 2u);
  const double tilt = rad_from_deg(20.0);
  for (const nlohmann::json& t : j.at("tf")) {
    const nlohmann::json& q = t.at("rotation");
    const double x = q.at("x"), y = q.at("y"), z = q.at("z"), w = q.at("w");
    // The image of (1, 0, 0) under the rotation: the first column of its matrix.
    const std::array<double, 3> axis = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z),
                                        2 * (x * z - w * y)};
    const double side = t.at("child") == "sidescan_port" ? 1.0 : -1.0;
    EXPECT_EQ(t.at("parent"), "base_link");
    EXPECT_NEAR(axis[0], 0.0, 1e-12) << t;
    EXPECT_NEAR(axis[1], side * std::cos(tilt), 1e-12) << t;
    EXPECT_NEAR(axis[2], -std::sin(tilt), 1e-12) << t;
  }
}

}  // namespace
}  // namespace sonarsynth
