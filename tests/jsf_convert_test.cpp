// SPDX-License-Identifier: MIT
// XTF <-> JSF conversion (library and `sonarsynth convert`).
#include <gtest/gtest.h>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/jsf/convert.hpp"
#include "sonarsynth/formats/jsf/reader.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

TEST(JsfConvert, XtfToJsfToXtfKeepsSamplesBitExact) {
  const fs::path dir = xtf::test::temp_dir("jsf_convert");
  std::vector<xtf::SonarPing> pings;
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
  EXPECT_EQ(to_jsf.from, SonarFileFormat::kXtf);
  EXPECT_EQ(to_jsf.pings, 12u);
  EXPECT_EQ(to_jsf.attitude_records, 1u);
  EXPECT_EQ(to_jsf.pings_skipped, 0u);
  EXPECT_EQ(detect_sonar_file_format(dir / "b.jsf"), SonarFileFormat::kJsf);
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
    const xtf::SonarPing& x = pa.ping.sonar;
    const xtf::SonarPing& y = pc.ping.sonar;
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
    EXPECT_NEAR(deg_from_rad(y.heading_rad), deg_from_rad(x.heading_rad), 0.005 + 1e-5);
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
    EXPECT_NE(std::string(e.what()).find("neither XTF"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)convert_sonar_file(dir / "junk.jsf", dir / "out.png"), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
