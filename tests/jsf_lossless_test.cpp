// SPDX-License-Identifier: MIT
// XTF -> JSF -> XTF is lossless for what sonarsynth's XTF writer writes (docs/conversion.md,
// "Lossless round trip"): the bytes of the two XTF files are compared, and every difference is
// named by record and byte offset (offsets of docs/xtf.md §1).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>

#include "cli_test_util.hpp"
#include "fields_test_util.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

/// A record of an XTF file: its name and its byte range.
struct Record {
  std::string name;
  std::uint64_t begin = 0;
  std::uint64_t end = 0;
};

/// The file header and every packet of `path`, in file order (the reader's offsets and sizes).
std::vector<Record> records(const fs::path& path) {
  std::vector<Record> out{{"file header", 0, xtf::XtfFileHeader::kSize}};
  xtf::Reader r(path);
  xtf::Packet p;
  std::uint64_t pings = 0;
  while (r.next(p)) {
    std::string name =
        "packet " + std::to_string(p.index) + " (type " + std::to_string(p.header_type) + ")";
    if (p.kind == xtf::PacketKind::kPing) name = "ping " + std::to_string(pings++);
    out.push_back({name, p.offset, p.offset + p.size_bytes});
  }
  return out;
}

/// Where `a` and `b` differ, record by record (records paired by name): "RECORD bytes FROM-TO"
/// per run of differing bytes, relative to the record's start (for a ping: 0-255 the ping
/// header, 256-319 the port channel header, then its samples, then the starboard channel header
/// and samples), a record's size if it differs, a record that only one file has. Records named
/// in `skip` are not compared. Empty if identical.
std::vector<std::string> differences(const fs::path& a, const fs::path& b,
                                     const std::set<std::string>& skip = {}) {
  const auto x = xtf::test::read_bytes(a);
  const auto y = xtf::test::read_bytes(b);
  const std::vector<Record> ra = records(a);
  const std::vector<Record> rb = records(b);
  std::vector<std::string> out;
  for (const Record& p : ra) {
    if (skip.count(p.name)) continue;
    const auto q =
        std::find_if(rb.begin(), rb.end(), [&](const Record& r) { return r.name == p.name; });
    if (q == rb.end()) {
      out.push_back(p.name + " missing");
      continue;
    }
    if (p.end - p.begin != q->end - q->begin) out.push_back(p.name + " size differs");
    const std::size_t n = std::min(p.end - p.begin, q->end - q->begin);
    for (std::size_t i = 0; i < n; ++i) {
      if (x[p.begin + i] == y[q->begin + i]) continue;
      // A run ends at 8 equal bytes (a float whose last bits differ is one run).
      std::size_t j = i;
      for (std::size_t e = i + 1; e < n && e <= j + 8; ++e) {
        if (x[p.begin + e] != y[q->begin + e]) j = e;
      }
      out.push_back(p.name + " bytes " + std::to_string(i) + "-" + std::to_string(j));
      i = j;
    }
  }
  for (const Record& q : rb) {
    if (!skip.count(q.name) &&
        std::none_of(ra.begin(), ra.end(), [&](const Record& r) { return r.name == q.name; })) {
      out.push_back(q.name + " added");
    }
  }
  return out;
}

std::string summary(const std::vector<std::string>& d) {
  std::ostringstream os;
  os << d.size() << " differing runs:";
  for (std::size_t i = 0; i < d.size() && i < 40; ++i) os << "\n  " << d[i];
  return os.str();
}

/// The JSF walked as the strictest public readers walk it (docs/jsf.md §1; SidescanTools raises
/// at a message without the 01 16 marker, auvlib pairs neighbouring sonar data messages, every
/// reader skips a type it does not know by its byte count): the byte counts chain to the end of
/// the file, every message has protocol version 13, the types are 80, 182, 2020 and 9999, the
/// 182 message comes first with its 24 standard bytes, and the sonar data messages alone run
/// port, starboard, port... with one ping number per pair. Returns the pings.
std::uint64_t strict_walk(const fs::path& jsf) {
  const auto b = xtf::test::read_bytes(jsf);
  const auto u16 = [&](std::size_t o) { return static_cast<unsigned>(b[o] | b[o + 1] << 8); };
  const auto u32 = [&](std::size_t o) {
    return static_cast<std::uint32_t>(u16(o)) | static_cast<std::uint32_t>(u16(o + 2)) << 16;
  };
  std::size_t off = 0;
  std::uint64_t sonar = 0;
  std::uint32_t port_ping = 0;
  while (off < b.size()) {
    EXPECT_GE(b.size() - off, 16u) << "a message header cut at byte " << off;
    if (b.size() - off < 16) return 0;
    EXPECT_EQ(u16(off), 0x1601u) << "byte " << off;
    EXPECT_EQ(b[off + 2], 13u) << "byte " << off;
    const unsigned type = u16(off + 4);
    const std::uint32_t count = u32(off + 12);
    EXPECT_TRUE(type == 80 || type == 182 || type == 2020 || type == 9999) << type;
    if (off == 0) {
      EXPECT_EQ(type, 182u);
      EXPECT_GE(count, 24u);
      EXPECT_EQ(u32(off + 16 + 12), 1u) << "one subsystem";
    }
    if (type == 80) {
      const std::uint32_t n = u16(off + 16 + 114) + ((u16(off + 16 + 16) >> 8 & 0xFu) << 16);
      EXPECT_EQ(count, 240 + 2 * n) << "byte count of the sonar data message at " << off;
      EXPECT_EQ(b[off + 8], sonar % 2) << "channel of sonar data message " << sonar;
      const std::uint32_t ping = u32(off + 16 + 8);
      if (sonar % 2 == 0) port_ping = ping;
      EXPECT_EQ(ping, port_ping) << "ping number of sonar data message " << sonar;
      ++sonar;
    }
    off += 16 + std::size_t{count};
  }
  EXPECT_EQ(off, b.size()) << "the byte counts run past the end";
  EXPECT_EQ(sonar % 2, 0u);
  return sonar / 2;
}

/// `in` -> dir/rt.jsf -> out (which should be named as `in`, since ThisFileName holds the name).
void round_trip(const fs::path& in, const fs::path& dir, const fs::path& out) {
  const ConvertResult a = convert_sonar_file(in, dir / "rt.jsf");
  EXPECT_EQ(a.pings_skipped, 0u);
  EXPECT_EQ(strict_walk(dir / "rt.jsf"), a.pings);
  const ConvertResult b = convert_sonar_file(dir / "rt.jsf", out);
  EXPECT_EQ(b.pings_skipped, 0u);
  EXPECT_EQ(b.pings, a.pings);
}

// Options away from every default and pings whose values JSF cannot hold (positions finer than
// 1/600 000 degree, a slant range that is no whole number of nanoseconds per sample, altitude
// and depth finer than a millimetre, a ship position apart from the sensor's).
TEST(JsfLossless, WriterOptionsAndPingFieldsSurvive) {
  const fs::path dir = xtf::test::temp_dir("jsf_lossless_options");
  fs::create_directories(dir / "back");
  xtf::WriterOptions o;
  o.sonar_name = "Klein 3900 synth";
  o.note = std::string(140, 'n') + " the end of a long note, beyond the 64 of the header";
  o.frequency_khz = 455.5;
  o.horizontal_beam_angle_rad = rad_from_deg(0.5);
  o.tilt_angle_rad = rad_from_deg(20.0);
  o.vertical_beam_width_rad = rad_from_deg(36.7);
  o.processing_flags = xtf::kProcessingTvg | xtf::kProcessingFilter;
  {
    xtf::Writer w(dir / "a.xtf", o);
    for (std::uint32_t k = 0; k < 9; ++k) {
      SonarPing p = xtf::test::make_ping(k, 300, 300);
      p.time_utc += std::chrono::microseconds{1234567 * k + 3};  // not whole 10 ms
      p.sensor_position.lat_rad += 1.234567e-9 * k;
      p.sensor_position.lon_rad -= 7.654321e-9 * k;
      p.heading_true_rad = 6.2 + 0.0123456789 * k;
      p.pitch_rad = -0.0123456789 * k;
      p.roll_rad = 0.0234567891 * k;
      p.heave_m = 0.1234567 * k;
      p.altitude_m = 8.123456789 + 0.01 * k;
      p.depth_m = 20.987654321;
      p.speed_m_s = 1.23456789;
      p.sound_speed_m_s = 1493.123456;
      p.slant_range_m = 37.123456789;
      w.write_ping(p);
    }
    w.close();
  }
  round_trip(dir / "a.xtf", dir, dir / "back" / "a.xtf");
  const auto d = differences(dir / "a.xtf", dir / "back" / "a.xtf");
  EXPECT_TRUE(d.empty()) << summary(d);
  fs::remove_all(dir);
}

// A line of `sonarsynth simulate` on a sample scene (u16 and u8 samples).
TEST(JsfLossless, SimulatedSampleSurvives) {
  const fs::path dir = xtf::test::temp_dir("jsf_lossless_sim");
  for (const std::string format : {"u16", "u8"}) {
    const fs::path scene = dir / ("scene_" + format + ".yaml");
    {
      std::ifstream in(fs::path(SONARSYNTH_SAMPLES_DIR) / "rough_seabed.yaml");
      std::ofstream out(scene);
      out << in.rdbuf() << "\noutput: {sample_format: " << format << "}\n";
    }
    const fs::path run = dir / ("run_" + format);
    const test::CliResult r =
        test::run_cli("simulate " + scene.string() + " -o " + run.string() +
                          " -q --no-mosaic --no-waterfall --no-truth --samples 256 --range 20",
                      dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    fs::create_directories(run / "back");
    round_trip(run / "L1.xtf", run, run / "back" / "L1.xtf");
    const auto d = differences(run / "L1.xtf", run / "back" / "L1.xtf");
    EXPECT_TRUE(d.empty()) << format << ": " << summary(d);
  }
  fs::remove_all(dir);
}

// A JSF edited after the conversion (ping 1's altitude, ping 2's time): the edited pings are
// written from their message 80 (the carried header no longer describes them), counted as
// repairs; the other from its header.
TEST(JsfLossless, EditedJsfPingIsWrittenFromTheJsf) {
  const fs::path dir = xtf::test::temp_dir("jsf_lossless_edited");
  {
    xtf::Writer w(dir / "a.xtf");
    for (std::uint32_t k = 0; k < 3; ++k) w.write_ping(xtf::test::make_ping(k, 100, 100));
    w.close();
  }
  (void)convert_sonar_file(dir / "a.xtf", dir / "a.jsf");
  // The altitude (offset 144 of the message-80 header, mm) of both messages of ping 1.
  auto b = xtf::test::read_bytes(dir / "a.jsf");
  std::size_t off = 0;
  int edited = 0;
  while (off + 16 <= b.size()) {
    const unsigned type = static_cast<unsigned>(b[off + 4] | b[off + 5] << 8);
    const std::uint32_t count = static_cast<std::uint32_t>(b[off + 12] | b[off + 13] << 8 |
                                                           b[off + 14] << 16 | b[off + 15] << 24);
    if (type == 80 && b[off + 16 + 8] == 1) {
      const std::int32_t mm = 12345;
      for (int i = 0; i < 4; ++i) b[off + 16 + 144 + i] = static_cast<std::uint8_t>(mm >> (8 * i));
      ++edited;
    }
    if (type == 80 && b[off + 16 + 8] == 2) {
      b[off + 16] = static_cast<std::uint8_t>(b[off + 16] + 1);  // the time (offset 0), + 1 s
      ++edited;
    }
    off += 16 + count;
  }
  ASSERT_EQ(edited, 4);
  xtf::test::write_bytes(dir / "a.jsf", b);
  const ConvertResult r = convert_sonar_file(dir / "a.jsf", dir / "b.xtf");
  EXPECT_EQ(r.pings, 3u);
  EXPECT_EQ(r.repaired.at("carried XTF header disagrees with the JSF ping -> written from the JSF"),
            2u);
  const auto d = differences(dir / "a.xtf", dir / "b.xtf", {"file header"});
  ASSERT_FALSE(d.empty());
  for (const std::string& e : d) {
    EXPECT_TRUE(e.rfind("ping 1 ", 0) == 0 || e.rfind("ping 2 ", 0) == 0) << e;
  }
  xtf::Reader x(dir / "b.xtf");
  xtf::Packet p;
  while (x.next(p)) {
    if (p.kind == xtf::PacketKind::kPing && p.ping.sonar.ping_number == 1) {
      EXPECT_FLOAT_EQ(p.ping.header.SensorPrimaryAltitude, 12.345f);
    }
  }
  fs::remove_all(dir);
}

// An XTF whose coordinates are not longitude/latitude (NavUnits 0: metres): no ping is dropped;
// they come back with zero coordinates (no position), as the JSF has them, since the XTF written
// back says NavUnits 3; every other header field and sample comes back.
TEST(JsfLossless, ProjectedCoordinatesComeBackAsNoPosition) {
  const fs::path dir = xtf::test::temp_dir("jsf_lossless_navunits");
  fs::create_directories(dir / "back");
  {
    xtf::Writer w(dir / "a.xtf");
    for (std::uint32_t k = 0; k < 4; ++k) w.write_ping(xtf::test::make_ping(k, 100, 100));
    w.close();
  }
  auto bytes = xtf::test::read_bytes(dir / "a.xtf");
  bytes[164] = 0;  // NavUnits (docs/xtf.md §1.1, offset 164): 0 = metres
  xtf::test::write_bytes(dir / "a.xtf", bytes);
  round_trip(dir / "a.xtf", dir, dir / "back" / "a.xtf");
  const auto d = differences(dir / "a.xtf", dir / "back" / "a.xtf");
  // The NavUnits byte, and in each ping the ship (128-143) and sensor (160-175) coordinates.
  std::vector<std::string> want = {"file header bytes 164-164"};
  for (int k = 0; k < 4; ++k) {
    want.push_back("ping " + std::to_string(k) + " bytes 128-143");
    want.push_back("ping " + std::to_string(k) + " bytes 160-175");
  }
  EXPECT_EQ(d, want) << summary(d);
  xtf::Reader r(dir / "back" / "a.xtf");
  xtf::Packet p;
  while (r.next(p)) {
    if (p.kind != xtf::PacketKind::kPing) continue;
    EXPECT_EQ(p.ping.header.SensorXcoordinate, 0.0);
    EXPECT_EQ(p.ping.header.SensorYcoordinate, 0.0);
  }
  EXPECT_EQ(r.anomaly_count(xtf::AnomalyKind::kZeroNavigation), 4u);
  fs::remove_all(dir);
}

// The real Iver2 file (Marine Sonic): every ping comes back (ping 0 has no position), every
// ping and channel header and every sample identical; of the file header, the fields that
// describe the data (sonar name, note, navigation units, the channels' frequency and beam).
TEST(JsfLossless, RealIver2FileSurvives) {
  const fs::path dir = xtf::test::temp_dir("jsf_lossless_iver2");
  fs::create_directories(dir / "back");
  const fs::path in = fs::path(SONARSYNTH_TEST_DATA_DIR) / "xtf" / "scotsman-iver2.xtf";
  round_trip(in, dir, dir / "back" / "scotsman-iver2.xtf");
  const fs::path out = dir / "back" / "scotsman-iver2.xtf";
  // Every ping packet. The file header is compared field by field below; the round trip adds
  // the NOTES packet sonarsynth writes first (its text: the header's NoteString).
  const auto d = differences(in, out, {"file header", "packet 0 (type 1)"});
  EXPECT_TRUE(d.empty()) << summary(d);
  xtf::Reader a(in);
  xtf::Reader b(out);
  const xtf::XtfFileHeader& x = a.file_header();
  const xtf::XtfFileHeader& y = b.file_header();
  using H = xtf::XtfFileHeader;
  test::expect_equal_fields(x, y, &H::SonarName, &H::NoteString, &H::NavUnits,
                            &H::NumberOfSonarChannels);
  for (std::size_t c = 0; c < 2; ++c) {
    SCOPED_TRACE("channel " + std::to_string(c));
    using C = xtf::XtfChanInfo;
    test::expect_equal_fields(x.ChanInfo[c], y.ChanInfo[c], &C::TypeOfChannel, &C::BytesPerSample,
                              &C::SampleFormat, &C::UniPolar, &C::Frequency, &C::HorizBeamAngle,
                              &C::TiltAngle, &C::BeamWidth);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
