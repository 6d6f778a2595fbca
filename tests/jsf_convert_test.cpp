// SPDX-License-Identifier: MIT
// XTF <-> JSF conversion (library and `sonarsynth convert`).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/format.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/format.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

TEST(JsfConvert, XtfToJsfToXtfKeepsSamplesBitExact) {
  const fs::path dir = xtf::test::temp_dir("jsf_convert");
  std::vector<SonarPing> pings;
  {
    xtf::Writer w(dir / "a.xtf");
    for (std::uint32_t k = 0; k < 12; ++k) {
      pings.push_back(xtf::test::make_ping(k, 2000, 2000));
      w.write_ping(pings.back());
    }
    w.write_attitude({pings.back().time_utc, 1.0, 0.02, -0.03, 0.1, 0.0});
    w.close();
  }
  const ConvertResult to_jsf = convert_sonar_file(dir / "a.xtf", dir / "b.jsf");
  EXPECT_EQ(to_jsf.from, &xtf::sonar_format());
  EXPECT_EQ(to_jsf.to, &jsf::sonar_format());
  EXPECT_EQ(to_jsf.pings, 12u);
  EXPECT_EQ(to_jsf.attitude_records, 1u);
  EXPECT_EQ(to_jsf.pings_skipped, 0u);
  EXPECT_EQ(identify_sonar_format(dir / "b.jsf"), &jsf::sonar_format());
  const ConvertResult back = convert_sonar_file(dir / "b.jsf", dir / "c.xtf");
  EXPECT_EQ(back.pings, 12u);
  EXPECT_EQ(back.attitude_records, 1u);

  xtf::Reader a(dir / "a.xtf");
  xtf::Reader c(dir / "c.xtf");
  xtf::Packet pa, pc;
  std::size_t n = 0;
  const auto next_ping = [](xtf::Reader& r, xtf::Packet& p) {
    while (r.next(p)) {
      if (p.kind == xtf::PacketKind::kPing) return true;
    }
    return false;
  };
  while (next_ping(a, pa)) {
    ASSERT_TRUE(next_ping(c, pc));
    const SonarPing& x = pa.ping.sonar;
    const SonarPing& y = pc.ping.sonar;
    EXPECT_EQ(x.port, y.port) << "ping " << n;
    EXPECT_EQ(x.starboard, y.starboard);
    EXPECT_EQ(x.time_utc, y.time_utc);
    EXPECT_EQ(x.ping_number, y.ping_number);
    // JSF stores 1/600 000 degree: at most half a step of rounding.
    const double step_deg = 1.0 / 600000.0;
    EXPECT_NEAR(deg_from_rad(y.sensor_position.lat_rad), deg_from_rad(x.sensor_position.lat_rad),
                step_deg / 2 + 1e-12);
    EXPECT_NEAR(deg_from_rad(y.sensor_position.lon_rad), deg_from_rad(x.sensor_position.lon_rad),
                step_deg / 2 + 1e-12);
    EXPECT_NEAR(deg_from_rad(y.heading_true_rad), deg_from_rad(x.heading_true_rad), 0.005 + 1e-5);
    EXPECT_NEAR(deg_from_rad(y.pitch_rad), deg_from_rad(x.pitch_rad), 90.0 / 32768.0 + 1e-5);
    EXPECT_NEAR(deg_from_rad(y.roll_rad), deg_from_rad(x.roll_rad), 90.0 / 32768.0 + 1e-5);
    EXPECT_NEAR(y.altitude_m, x.altitude_m, 0.0005 + 1e-6);
    EXPECT_NEAR(y.depth_m, x.depth_m, 0.0005 + 1e-6);
    EXPECT_NEAR(y.heave_m, x.heave_m, 1e-6);
    EXPECT_NEAR(y.slant_range_m, x.slant_range_m, 1490.0 * 2000 * 0.5e-9 / 2 + 1e-5);
    ++n;
  }
  EXPECT_EQ(n, 12u);
  EXPECT_EQ(a.total_anomalies(), 0u);
  EXPECT_EQ(c.total_anomalies(), 0u);
  fs::remove_all(dir);
}

TEST(JsfConvert, RefusesUnknownFormatsClearly) {
  const fs::path dir = xtf::test::temp_dir("jsf_convert_bad");
  xtf::test::write_bytes(dir / "junk.jsf", {'h', 'e', 'l', 'l', 'o'});
  try {
    (void)convert_sonar_file(dir / "junk.jsf", dir / "out.xtf");
    FAIL();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("not a file of any known format (xtf, jsf, rosbag, mcap)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)convert_sonar_file(dir / "junk.jsf", dir / "out.png"), InputError);
  fs::remove_all(dir);
}

const fs::path kData = SONARSYNTH_TEST_DATA_DIR;

std::vector<SonarPing> xtf_pings(const fs::path& path) {
  xtf::Reader r(path);
  xtf::Packet p;
  std::vector<SonarPing> out;
  while (r.next(p)) {
    if (p.kind == xtf::PacketKind::kPing) out.push_back(p.ping.sonar);
  }
  return out;
}

std::vector<SonarPing> jsf_pings(const fs::path& path) {
  jsf::Reader r(path);
  jsf::Ping p;
  std::vector<SonarPing> out;
  while (r.next_ping(p)) out.push_back(p.sonar);
  return out;
}

// The committed fuzzer seed holds the samples of the XTF it was converted from.
TEST(JsfConvert, CommittedSeedHoldsItsXtfSamples) {
  const auto x = xtf_pings(kData / "xtf" / "golden-tiny.xtf");
  const auto j = jsf_pings(kData / "jsf" / "tiny-from-xtf.jsf");
  ASSERT_EQ(x.size(), 2u);
  ASSERT_EQ(j.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(x[i].port, j[i].port);
    EXPECT_EQ(x[i].starboard, j[i].starboard);
    EXPECT_EQ(x[i].time_utc, j[i].time_utc);
  }
}

// The real Iver2 file (16-bit unsigned samples) through JSF and back: every ping keeps its
// samples bit-exactly, ping 0 (no position) too, with its carried XTF header
// (jsf_lossless_test.cpp compares the headers).
TEST(JsfConvert, RealXtfRoundTripsThroughJsf) {
  const fs::path dir = xtf::test::temp_dir("jsf_convert_real");
  const ConvertResult a = convert_sonar_file(kData / "xtf" / "scotsman-iver2.xtf", dir / "i.jsf");
  EXPECT_EQ(a.pings, 461u);
  const ConvertResult b = convert_sonar_file(dir / "i.jsf", dir / "i.xtf");
  EXPECT_EQ(b.pings, 461u);
  EXPECT_EQ(b.pings_skipped, 0u);
  const auto x = xtf_pings(kData / "xtf" / "scotsman-iver2.xtf");
  const auto y = xtf_pings(dir / "i.xtf");
  ASSERT_EQ(y.size(), 461u);
  for (std::size_t i = 0; i < y.size(); ++i) {
    ASSERT_EQ(x[i].port, y[i].port) << "ping " << i;
    ASSERT_EQ(x[i].starboard, y[i].starboard);
    EXPECT_EQ(x[i].time_utc, y[i].time_utc);
  }
  fs::remove_all(dir);
}

TEST(JsfCli, ConvertInfoWaterfallOnJsf) {
  const fs::path dir = xtf::test::temp_dir("jsf_cli");
  const std::string xtf_in = (kData / "xtf" / "golden-tiny.xtf").string();
  // The input is JSF by content even when named .dat.
  auto r = test::run_cli("convert " + xtf_in + " -o " + (dir / "t.jsf").string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("XTF -> JSF, 2 pings, 1 attitude records"), std::string::npos) << r.out;
  fs::copy_file(dir / "t.jsf", dir / "t.dat");
  r = test::run_cli("info --json " + (dir / "t.dat").string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format"], "JSF");
  EXPECT_EQ(j["pings"], 2);
  EXPECT_EQ(j["message_counts"]["80"]["count"], 4);
  EXPECT_EQ(j["message_counts"]["182"]["count"], 1);
  EXPECT_EQ(j["message_counts"]["2020"]["count"], 1);
  ASSERT_EQ(j["subsystems"].size(), 1u);
  EXPECT_EQ(j["subsystems"][0]["subsystem"], 20);
  EXPECT_EQ(j["subsystems"][0]["messages_by_channel"]["0"], 2);
  EXPECT_EQ(j["subsystems"][0]["messages_by_channel"]["1"], 2);
  EXPECT_EQ(j["system_information"]["subsystems"], 1);
  r = test::run_cli("info --json " + xtf_in, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["format"], "XTF");
  r = test::run_cli("waterfall " + (dir / "t.dat").string() + " -o " + (dir / "w.png").string(),
                    dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "w.png"));
  r = test::run_cli("convert " + (dir / "t.jsf").string() + " -o " + (dir / "back.xtf").string(),
                    dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("JSF -> XTF, 2 pings"), std::string::npos) << r.out;
  // A truncated JSF: a clear error naming the file, not a crash.
  auto bytes = xtf::test::read_bytes(dir / "t.jsf");
  bytes.resize(120);  // 182 (40 bytes) + 2020 (60 bytes) + 20 bytes of a message 80
  xtf::test::write_bytes(dir / "cut.jsf", bytes);
  r = test::run_cli("info " + (dir / "cut.jsf").string(), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("bad_byte_count: 1"), std::string::npos) << r.out;
  r = test::run_cli("waterfall " + (dir / "cut.jsf").string() + " -o " + (dir / "cut.png").string(),
                    dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("cut.jsf"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
