// SPDX-License-Identifier: MIT
// Damaged fields in XTF and JSF files: `convert` repairs what the output can hold as "unknown",
// drops (counted by reason) what it cannot, fails when nothing is left; the JSF reader reports
// a missing sound speed, a lossy weighting factor and an implausible sample interval
// (docs/conversion.md, "Drops and repairs"; docs/jsf.md). `mosaic` and `waterfall` name the
// file and the limit when they cannot proceed. The damaged files are made here by editing the
// bytes of files the test writes.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "cli_test_util.hpp"
#include "scene_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/jsf/writer.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

constexpr std::uint32_t kPings = 6;
constexpr std::size_t kSamples = 200;

template <typename T>
void put(Bytes& b, std::size_t at, T v) {
  std::memcpy(b.data() + at, &v, sizeof v);  // little-endian host, as the formats
}

class ConvertTrust : public test::ScratchDirTest {
 protected:
  /// An XTF file of kPings clean pings, and its library conversion to JSF.
  void SetUp() override {
    test::ScratchDirTest::SetUp();
    xtf::Writer w(dir_ / "clean.xtf");
    for (std::uint32_t k = 0; k < kPings; ++k) {
      pings_.push_back(xtf::test::make_ping(k, kSamples, kSamples));
      w.write_ping(pings_.back());
    }
    w.close();
    ASSERT_EQ(convert_sonar_file(dir_ / "clean.xtf", dir_ / "clean.jsf").pings, kPings);
  }

  /// A copy of clean.jsf with `edit(ping, body)` applied to both sonar data messages of each
  /// ping (body = the byte offset of the 240-byte sonar data header).
  fs::path damaged_jsf(const std::string& name,
                       const std::function<void(std::uint32_t, Bytes&, std::size_t)>& edit) {
    Bytes b = xtf::test::read_bytes(dir_ / "clean.jsf");
    std::size_t pos = 0;
    std::uint32_t sonar = 0;
    while (pos + 16 <= b.size()) {
      std::uint16_t type = 0;
      std::int32_t count = 0;
      std::memcpy(&type, b.data() + pos + 4, 2);
      std::memcpy(&count, b.data() + pos + 12, 4);
      if (type == 80) edit(sonar++ / 2, b, pos + 16);
      pos += 16 + static_cast<std::size_t>(count);
    }
    const fs::path p = dir_ / name;
    xtf::test::write_bytes(p, b);
    return p;
  }

  /// A copy of clean.xtf with `edit(ping, header, channels)` applied to each ping's decoded
  /// headers before they are encoded back.
  fs::path damaged_xtf(const std::string& name,
                       const std::function<void(std::uint32_t, xtf::XtfPingHeader&,
                                                std::array<xtf::XtfPingChanHeader, 2>&)>& edit) {
    Bytes b = xtf::test::read_bytes(dir_ / "clean.xtf");
    std::vector<std::uint64_t> offsets;
    {
      xtf::Reader r(dir_ / "clean.xtf");
      xtf::Packet p;
      while (r.next(p)) {
        if (p.kind == xtf::PacketKind::kPing) offsets.push_back(p.offset);
      }
    }
    for (std::uint32_t k = 0; k < offsets.size(); ++k) {
      const std::size_t at = static_cast<std::size_t>(offsets[k]);
      const std::size_t chan1 = at + xtf::XtfPingHeader::kSize + xtf::XtfPingChanHeader::kSize +
                                2 * kSamples;  // u16 samples
      ByteReader hr(std::span<const std::uint8_t>(b).subspan(at), "test");
      xtf::XtfPingHeader h = xtf::XtfPingHeader::decode(hr);
      std::array<xtf::XtfPingChanHeader, 2> c;
      for (int s = 0; s < 2; ++s) {
        ByteReader cr(std::span<const std::uint8_t>(b).subspan(
                          s == 0 ? at + xtf::XtfPingHeader::kSize : chan1),
                      "test");
        c[static_cast<std::size_t>(s)] = xtf::XtfPingChanHeader::decode(cr);
      }
      edit(k, h, c);
      ByteWriter hw(std::span<std::uint8_t>(b).subspan(at, xtf::XtfPingHeader::kSize));
      h.encode(hw);
      for (int s = 0; s < 2; ++s) {
        ByteWriter cw(std::span<std::uint8_t>(b).subspan(
            s == 0 ? at + xtf::XtfPingHeader::kSize : chan1, xtf::XtfPingChanHeader::kSize));
        c[static_cast<std::size_t>(s)].encode(cw);
      }
    }
    const fs::path p = dir_ / name;
    xtf::test::write_bytes(p, b);
    return p;
  }

  std::vector<SonarPing> read_xtf(const fs::path& p) {
    std::vector<SonarPing> out;
    xtf::Reader r(p);
    xtf::Packet k;
    while (r.next(k)) {
      if (k.kind == xtf::PacketKind::kPing) out.push_back(k.ping.sonar);
    }
    return out;
  }

  std::vector<SonarPing> read_jsf(const fs::path& p) {
    std::vector<SonarPing> out;
    jsf::Reader r(p);
    jsf::Ping k;
    while (r.next_ping(k)) out.push_back(k.sonar);
    return out;
  }

  test::CliResult cli(const std::string& args) { return test::run_cli(args, dir_); }

  std::vector<SonarPing> pings_;
};

bool has(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

// JSF -> XTF: EdgeTech's "no altimeter lock" (altitude < 0), a NaN heave and a pitch of -180
// degrees are written as XTF's 0; a sample interval of 0 and one of 2^32-1 ns drop their pings,
// counted by reason; a NaN sound speed is reported (ping, byte, value) and 1500 m/s assumed.
TEST_F(ConvertTrust, JsfToXtfRepairsUnknownFieldsAndCountsDrops) {
  const fs::path in = damaged_jsf("bad.jsf", [](std::uint32_t ping, Bytes& b, std::size_t h) {
    if (ping == 0) {
      put<std::int32_t>(b, h + 144, -1000);                            // altitude -1 m
      put<float>(b, h + 48, std::numeric_limits<float>::quiet_NaN());  // heave
      put<std::int16_t>(b, h + 174, -32768);                           // pitch -180 deg
    }
    if (ping == 1) put<std::uint32_t>(b, h + 116, 0);            // sample interval 0
    if (ping == 2) put<float>(b, h + 148, std::nanf(""));        // sound speed NaN
    if (ping == 3) put<std::uint32_t>(b, h + 116, 0xFFFFFFFFu);  // 4.29 s per sample
    if (ping == 4) put<float>(b, h + 148, -1480.0f);             // sound speed negative
  });
  const test::CliResult r = cli("convert " + in.string() + " -o " + (dir_ / "out.xtf").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "JSF -> XTF, 4 pings")) << r.out;
  for (const char* part :
       {"dropped 2 of 6 pings", "slant range 0 (sample interval 0: no sample spacing): 1",
        "slant range over 100 km (implausible sample interval): 1",
        "altitude negative or not finite -> 0 (no altitude): 1", "heave not finite -> 0: 1",
        "pitch beyond +-90 deg -> 0: 1",
        "ping 2: sound speed nan m/s is not a speed; 1500 m/s assumed",
        "ping 4: sound speed -1480 m/s", "sample interval 4294967295 ns x 200 samples",
        "JSF ping 1 at byte"}) {
    EXPECT_TRUE(has(r.err, part)) << part << " in " << r.err;
  }

  const std::vector<SonarPing> out = read_xtf(dir_ / "out.xtf");
  const std::vector<std::uint32_t> kept = {0, 2, 4, 5};
  ASSERT_EQ(out.size(), kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const SonarPing& want = pings_[kept[i]];
    EXPECT_EQ(out[i].ping_number, want.ping_number);
    EXPECT_EQ(out[i].port, want.port) << "every sample kept, ping " << kept[i];
    EXPECT_EQ(out[i].starboard, want.starboard);
  }
  EXPECT_EQ(out[0].altitude_m, 0.0);
  EXPECT_EQ(out[0].heave_m, 0.0);
  EXPECT_EQ(out[0].pitch_rad, 0.0);
  EXPECT_NEAR(out[0].roll_rad, pings_[0].roll_rad, 1e-4) << "the rest of the ping as it was";
  EXPECT_EQ(out[1].sound_speed_m_s, 1500.0);
  EXPECT_NEAR(out[3].altitude_m, pings_[5].altitude_m, 1e-3);
}

// Every ping dropped: exit 1 naming the file and the reason, and no output left behind.
TEST_F(ConvertTrust, JsfToXtfFailsWhenNothingIsLeft) {
  const fs::path in = damaged_jsf("zero.jsf", [](std::uint32_t, Bytes& b, std::size_t h) {
    put<std::uint32_t>(b, h + 116, 0);
  });
  const auto before = test::snapshot(dir_);
  const test::CliResult r = cli("convert " + in.string() + " -o " + (dir_ / "out.xtf").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err,
                  "zero.jsf: none of its 6 pings could be converted (slant range 0 "
                  "(sample interval 0: no sample spacing): 6"))
      << r.err;
  EXPECT_TRUE(has(r.err, "nothing written")) << r.err;
  EXPECT_EQ(test::snapshot(dir_), before) << "no output, no temporary";
  // The library says the same.
  EXPECT_THROW(convert_sonar_file(in, dir_ / "out.xtf"), FormatError);
  EXPECT_FALSE(fs::exists(dir_ / "out.xtf"));
}

// An input without any ping (an XTF cut after its file header): the same failure, not an empty
// output.
TEST_F(ConvertTrust, FailsOnAnInputWithoutPings) {
  Bytes b = xtf::test::read_bytes(dir_ / "clean.xtf");
  b.resize(1024 + 100);  // the file header and a cut packet
  xtf::test::write_bytes(dir_ / "cut.xtf", b);
  const auto before = test::snapshot(dir_);
  const test::CliResult r =
      cli("convert " + (dir_ / "cut.xtf").string() + " -o " + (dir_ / "out.jsf").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "cut.xtf: no side-scan ping to convert (1 reader anomalies; first: "))
      << r.err;
  EXPECT_EQ(test::snapshot(dir_), before);
}

// XTF -> JSF: a NaN altitude and a sound speed of 0 are written as JSF's "unknown" (altitude 0,
// sound speed 1500 m/s with the validity bit clear); a slant range of 0 drops the ping.
TEST_F(ConvertTrust, XtfToJsfRepairsUnknownFieldsAndCountsDrops) {
  const fs::path in = damaged_xtf("bad.xtf", [](std::uint32_t ping, xtf::XtfPingHeader& h,
                                                std::array<xtf::XtfPingChanHeader, 2>& c) {
    if (ping == 0) h.SensorPrimaryAltitude = std::numeric_limits<float>::quiet_NaN();
    if (ping == 1) h.SoundVelocity = h.ComputedSoundVelocity = 0.0f;
    if (ping == 2) c[0].SlantRange = c[1].SlantRange = 0.0f;
    if (ping == 3) h.Heave = std::numeric_limits<float>::quiet_NaN();
  });
  const test::CliResult r = cli("convert " + in.string() + " -o " + (dir_ / "out.jsf").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "XTF -> JSF, 5 pings")) << r.out;
  for (const char* part :
       {"dropped 1 of 6 pings", "slant range 0 (sample interval 0: no sample spacing): 1",
        "XTF packet", "altitude negative or not finite -> 0 (no altitude): 1",
        "sound speed <= 0 or not finite -> unknown (1500 m/s for the sample interval): 1",
        "heave not finite -> unknown: 1"}) {
    EXPECT_TRUE(has(r.err, part)) << part << " in " << r.err;
  }

  const std::vector<SonarPing> out = read_jsf(dir_ / "out.jsf");
  const std::vector<std::uint32_t> kept = {0, 1, 3, 4, 5};
  ASSERT_EQ(out.size(), kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    EXPECT_EQ(out[i].ping_number, pings_[kept[i]].ping_number);
    EXPECT_EQ(out[i].port, pings_[kept[i]].port) << "every sample kept, ping " << kept[i];
    EXPECT_EQ(out[i].starboard, pings_[kept[i]].starboard);
    // The slant range survives: with the assumed 1500 m/s both ways for ping 1.
    EXPECT_NEAR(out[i].slant_range_m, pings_[kept[i]].slant_range_m, 1500.0 * 0.5e-9 * kSamples);
  }
  EXPECT_EQ(out[0].altitude_m, 0.0);
  EXPECT_EQ(out[1].sound_speed_m_s, 1500.0);
  EXPECT_EQ(out[2].heave_m, 0.0);
  // The validity bits say which fields are unknown.
  jsf::Reader jr(dir_ / "out.jsf");
  jsf::Ping p;
  std::vector<std::uint16_t> flags;
  while (jr.next_ping(p)) flags.push_back(p.header.validity_flags);
  ASSERT_EQ(flags.size(), 5u);
  EXPECT_EQ(flags[0] & jsf::validity::kAltitude, 0);
  EXPECT_NE(flags[3] & jsf::validity::kAltitude, 0);
  EXPECT_EQ(flags[1] & jsf::validity::kSoundSpeed, 0);
  EXPECT_NE(flags[0] & jsf::validity::kSoundSpeed, 0);
  EXPECT_EQ(flags[2] & jsf::validity::kHeave, 0);
  EXPECT_NE(flags[1] & jsf::validity::kHeave, 0);
}

TEST_F(ConvertTrust, XtfToJsfFailsWhenNothingIsLeft) {
  const fs::path in = damaged_xtf(
      "zero.xtf", [](std::uint32_t, xtf::XtfPingHeader&, std::array<xtf::XtfPingChanHeader, 2>& c) {
        c[0].SlantRange = c[1].SlantRange = 0.0f;
      });
  const auto before = test::snapshot(dir_);
  const test::CliResult r = cli("convert " + in.string() + " -o " + (dir_ / "out.jsf").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "zero.xtf: none of its 6 pings could be converted (slant range 0"))
      << r.err;
  EXPECT_EQ(test::snapshot(dir_), before) << "no output, no temporary";
}

// A weighting factor beyond what a float holds (201: every sample x 2^-201 underflows) is
// reported, naming the value and the byte; one within it decodes exactly.
TEST_F(ConvertTrust, JsfReaderReportsAWeightingFactorThatLosesTheSamples) {
  const fs::path in = damaged_jsf("wf.jsf", [](std::uint32_t ping, Bytes& b, std::size_t h) {
    std::int16_t n = 0;
    std::memcpy(&n, b.data() + h + 168, 2);
    EXPECT_EQ(n, 0) << "integer samples are stored with N = 0";
    if (ping == 0) put<std::int16_t>(b, h + 168, 201);
    if (ping == 1) put<std::int16_t>(b, h + 168, 3);  // exact: x 1/8
  });
  jsf::Reader r(in);
  jsf::Ping p;
  ASSERT_TRUE(r.next_ping(p));
  EXPECT_EQ(r.anomaly_count(jsf::AnomalyKind::kBadWeighting), 2u) << "port and starboard";
  ASSERT_FALSE(r.anomalies().empty());
  const std::string& m = r.anomalies().front().message;
  EXPECT_TRUE(has(m, "weighting factor 201")) << m;
  EXPECT_TRUE(has(m, "at byte ")) << m;
  ASSERT_TRUE(r.next_ping(p));
  for (std::size_t i = 0; i < kSamples; ++i) {
    ASSERT_EQ(p.sonar.port[i], pings_[1].port[i] / 8.0f);
  }
  EXPECT_EQ(r.anomaly_count(jsf::AnomalyKind::kBadWeighting), 2u);
  // `info` and `convert` show it.
  const test::CliResult info = cli("info " + in.string());
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_TRUE(has(info.out, "bad_weighting_factor: 2")) << info.out;
  const test::CliResult c = cli("convert " + in.string() + " -o " + (dir_ / "wf.xtf").string());
  EXPECT_EQ(c.exit_code, 0) << c.err;
  EXPECT_TRUE(has(c.err, "weighting factor 201")) << c.err;
}

// `mosaic -o m.tif --rgb m.tif` would leave only the display copy: refused before reading.
TEST_F(ConvertTrust, MosaicRefusesTheSameFileForMosaicAndDisplayCopy) {
  const auto before = test::snapshot(dir_);
  const std::string m = (dir_ / "m.tif").string();
  const std::string m2 = (dir_ / "." / "m.tif").string();
  const test::CliResult r =
      cli("mosaic " + (dir_ / "clean.xtf").string() + " -o " + m + " --rgb " + m2);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "--rgb " + m2 + " is the same file as -o " + m)) << r.err;
  EXPECT_EQ(test::snapshot(dir_), before);
}

// Nothing to grid: the error names the file (every ping without altitude here).
TEST_F(ConvertTrust, MosaicNamesTheFileWhenNoPingCanBeGridded) {
  const fs::path in = damaged_jsf(
      "flat.jsf", [](std::uint32_t, Bytes& b, std::size_t h) { put<std::int32_t>(b, h + 144, 0); });
  const auto before = test::snapshot(dir_);
  const test::CliResult r =
      cli("mosaic " + in.string() + " --altitude-source header -o " + (dir_ / "m.tif").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, in.string() + ": no ping could be gridded (6 pings, 0 without "
                                       "navigation, 6 without altitude)"))
      << r.err;
  EXPECT_EQ(test::snapshot(dir_), before);
}

// A thread the system refuses (here: a 3 GB thread stack under a 2 GB address-space limit) is a
// named error, exit 1, naming what it was for; nothing is left behind.
TEST_F(ConvertTrust, MosaicNamesARefusedThread) {
#ifdef SONARSYNTH_TEST_SANITIZED
  GTEST_SKIP() << "the sanitizers reserve more address space than the limit";
#endif
  const auto before = test::snapshot(dir_);
  const std::string cmd = "ulimit -s 3000000 && ulimit -v 2000000 && exec " +
                          std::string(SONARSYNTH_CLI) + " mosaic " + (dir_ / "clean.xtf").string() +
                          " -q -o " + (dir_ / "m.tif").string();
  const fs::path err = dir_.string() + "_err.txt";
  const int status = std::system(("sh -c '" + cmd + "' 2>" + err.string()).c_str());
  test::CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = test::read_text(err);
  fs::remove(err);
  if (has(r.err, "ulimit: ")) GTEST_SKIP() << "cannot set the limits: " << r.err;
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "m.tif: could not start the thread that writes the display copy"))
      << r.err;
  EXPECT_TRUE(has(r.err, "Resource temporarily unavailable")) << r.err;
  EXPECT_FALSE(has(r.err, "internal error")) << r.err;
  EXPECT_EQ(test::snapshot(dir_), before);
}

// One ping wider than libpng allows: refused at that ping, naming file, ping and limit, before
// the rest is spooled; no image and no spool left. A .tif has no such limit.
TEST_F(ConvertTrust, WaterfallRefusesAPingWiderThanPngEarly) {
  {
    jsf::Writer w(dir_ / "wide.jsf");
    for (std::uint32_t k = 0; k < 4; ++k) {
      w.write_ping(xtf::test::make_ping(k, k == 2 ? 600000 : kSamples, k == 2 ? 600000 : kSamples));
    }
    w.close();
  }
  const auto before = test::snapshot(dir_);
  const test::CliResult r =
      cli("waterfall " + (dir_ / "wide.jsf").string() + " -o " + (dir_ / "w.png").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err,
                  "wide.jsf: ping 2 (ping number 2): a row of 1200000 pixels (2 x 600000 "
                  "samples) exceeds the image's width limit of 1000000"))
      << r.err;
  EXPECT_FALSE(has(r.err, "IHDR")) << r.err;
  EXPECT_EQ(test::snapshot(dir_), before);
}

// The same refusal in a command that does not name its threads: still a named error, exit 1.
TEST_F(ConvertTrust, SimulateTurnsARefusedThreadIntoANamedError) {
#ifdef SONARSYNTH_TEST_SANITIZED
  GTEST_SKIP() << "the sanitizers reserve more address space than the limit";
#endif
  write("scene.yaml", test::flat_scene("quick", 3, 60, 60, 20, 2.0, 8) + R"(
    - {name: L1, waypoints: [{lat_deg: 43.0, lon_deg: 4.9999}, {lat_deg: 43.0, lon_deg: 5.0001}]}
sonar: {frequency_khz: 600, range_m: 25, samples: 128}
)");
  const auto before = test::snapshot(dir_);
  const std::string cmd = "ulimit -s 3000000 && ulimit -v 2000000 && exec " +
                          std::string(SONARSYNTH_CLI) + " simulate " +
                          (dir_ / "scene.yaml").string() + " -q -o " + (dir_ / "out").string();
  const fs::path err = dir_.string() + "_err.txt";
  const int status = std::system(("sh -c '" + cmd + "' 2>" + err.string()).c_str());
  const std::string text = test::read_text(err);
  fs::remove(err);
  if (has(text, "ulimit: ")) GTEST_SKIP() << "cannot set the limits: " << text;
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1) << text;
  EXPECT_TRUE(has(text,
                  "sonarsynth simulate: error: could not start a thread: Resource "
                  "temporarily unavailable"))
      << text;
  EXPECT_EQ(test::snapshot(dir_), before);
}

}  // namespace
}  // namespace sonarsynth
