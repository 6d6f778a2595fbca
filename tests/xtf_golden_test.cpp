// SPDX-License-Identifier: MIT
// Golden file tests/data/xtf/golden-tiny.xtf (catalogued in tests/data/README.md): its bytes are
// checked at hand-decoded offsets, and the writer must reproduce it byte for byte.
// Recreate it (after an intended format change) with:
//   SONARSYNTH_UPDATE_GOLDEN=1 <build>/tests/xtf_tests --gtest_filter='XtfGolden.*'
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth::xtf {
namespace {

namespace fs = std::filesystem;
const fs::path kGolden = fs::path(SONARSYNTH_TEST_DATA_DIR) / "xtf" / "golden-tiny.xtf";

/// Two pings of 4 samples per side, one attitude and one navigation packet.
void write_golden(const fs::path& path) {
  WriterOptions o;
  o.note = "sonarsynth golden test file";
  o.overwrite = true;
  Writer w(path, o);
  SonarPing p;
  p.time_utc = test::test_time(0);  // 2013-09-10 21:13:08.00
  p.ping_number = 0;
  p.sensor_position = {rad_from_deg(48.5), rad_from_deg(-68.75), 0.0};
  p.heading_true_rad = rad_from_deg(90.0);
  p.altitude_m = 10.0;
  p.depth_m = 20.0;
  p.speed_m_s = 1852.0 / 3600.0 * 4.0;  // 4 knots
  p.sound_speed_m_s = 1490.0;
  p.slant_range_m = 40.0;
  p.port = {10, 20, 30, 40};  // near -> far
  p.starboard = {100, 200, 300, 32767};
  w.write_attitude({p.time_utc, p.heading_true_rad, 0.0, 0.0, 0.0, 0.0});
  w.write_navigation({p.time_utc, p.sensor_position});
  w.write_ping(p);
  p.ping_number = 1;
  p.time_utc = test::test_time(10);
  w.write_ping(p);
  w.close();
}

std::uint32_t u32(const std::vector<std::uint8_t>& b, std::size_t o) {
  return static_cast<std::uint32_t>(b[o] | (b[o + 1] << 8) | (b[o + 2] << 16)) |
         (static_cast<std::uint32_t>(b[o + 3]) << 24);
}
std::uint16_t u16(const std::vector<std::uint8_t>& b, std::size_t o) {
  return static_cast<std::uint16_t>(b[o] | (b[o + 1] << 8));
}

TEST(XtfGolden, HandDecodedBytes) {
  if (std::getenv("SONARSYNTH_UPDATE_GOLDEN") != nullptr) write_golden(kGolden);
  const auto b = test::read_bytes(kGolden);
  ASSERT_EQ(b.size(), 2304u);  // 1024 header + 256 notes + 64 att + 64 nav + 2 x 448 pings
  EXPECT_EQ(b[0], 0x7B);       // FileFormat
  EXPECT_EQ(b[1], 1);          // SystemType
  // RecordingProgramName "sonarsy" and RecordingProgramVersion, each NUL-terminated in char[8]
  EXPECT_EQ(std::vector<std::uint8_t>(b.begin() + 2, b.begin() + 18),
            (std::vector<std::uint8_t>{'s', 'o', 'n', 'a', 'r', 's', 'y', 0, '0', '.', '1', '.',
                                       '0', 0, 0, 0}));
  EXPECT_EQ(u16(b, 164), 3);       // NavUnits: lat/long
  EXPECT_EQ(u16(b, 166), 2);       // NumberOfSonarChannels
  EXPECT_EQ(b[256], 1);            // ChanInfo[0] PORT
  EXPECT_EQ(b[384], 2);            // ChanInfo[1] STBD
  EXPECT_EQ(u16(b, 256 + 2), 1);   // CorrectionFlags slant range
  EXPECT_EQ(u16(b, 256 + 6), 2);   // BytesPerSample
  EXPECT_EQ(b[256 + 74], 3);       // SampleFormat 2-byte integer
  EXPECT_EQ(u32(b, 256 + 8), 4u);  // Reserved = samples per channel
  // NOTES first, exactly 256 bytes
  EXPECT_EQ(b[1024], 0xCE);
  EXPECT_EQ(b[1025], 0xFA);
  EXPECT_EQ(b[1026], 1);
  EXPECT_EQ(u32(b, 1034), 256u);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(&b[1024 + 56])),
            "sonarsynth golden test file");
  // attitude at 1280, navigation at 1344, 64 bytes each
  EXPECT_EQ(b[1282], 3);
  EXPECT_EQ(u32(b, 1290), 64u);
  EXPECT_EQ(b[1346], 42);
  EXPECT_EQ(u32(b, 1354), 64u);
  // ping 0 at 1408: 256 + 2 x (64 + 8) = 400 bytes padded to 448
  const std::size_t p0 = 1408;
  EXPECT_EQ(u16(b, p0), 0xFACE);
  EXPECT_EQ(b[p0 + 2], 0);
  EXPECT_EQ(u16(b, p0 + 4), 2);
  EXPECT_EQ(u32(b, p0 + 10), 448u);
  EXPECT_EQ(u16(b, p0 + 14), 2013);
  EXPECT_EQ(b[p0 + 16], 9);
  EXPECT_EQ(b[p0 + 17], 10);
  EXPECT_EQ(b[p0 + 18], 21);
  EXPECT_EQ(u16(b, p0 + 22), 252);           // JulianDay, 0-based, as Marine Sonic
  EXPECT_EQ(u32(b, p0 + 32), 0x443A4000u);   // SoundVelocity 745.0f = c/2
  EXPECT_EQ(u32(b, p0 + 72), 0x44BA4000u);   // ComputedSoundVelocity 1490.0f
  EXPECT_EQ(u32(b, p0 + 152), 0x40800000u);  // SensorSpeed 4.0f knots
  EXPECT_EQ(u32(b, p0 + 196), 0x41200000u);  // SensorPrimaryAltitude 10.0f
  EXPECT_EQ(u32(b, p0 + 212), 0x42B40000u);  // SensorHeading 90.0f
  // port channel header at 1664, samples at 1728 stored far -> near: 40 30 20 10
  EXPECT_EQ(u16(b, 1664), 0);
  EXPECT_EQ(u32(b, 1664 + 4), 0x42200000u);  // SlantRange 40.0f
  EXPECT_EQ(u32(b, 1664 + 42), 4u);          // NumSamples
  EXPECT_EQ(std::vector<std::uint8_t>(b.begin() + 1728, b.begin() + 1736),
            (std::vector<std::uint8_t>{0x28, 0, 0x1E, 0, 0x14, 0, 0x0A, 0}));
  // starboard channel header at 1736, samples at 1800 near -> far: 100 200 300 32767
  EXPECT_EQ(u16(b, 1736), 1);
  EXPECT_EQ(std::vector<std::uint8_t>(b.begin() + 1800, b.begin() + 1808),
            (std::vector<std::uint8_t>{0x64, 0, 0xC8, 0, 0x2C, 0x01, 0xFF, 0x7F}));
  for (std::size_t i = 1808; i < 1856; ++i) EXPECT_EQ(b[i], 0) << "padding at " << i;
  EXPECT_EQ(u16(b, 1856), 0xFACE);   // ping 1
  EXPECT_EQ(u32(b, 1856 + 28), 1u);  // PingNumber
  EXPECT_EQ(b[1856 + 21], 10);       // HSeconds
}

TEST(XtfGolden, WriterReproducesTheFile) {
  const fs::path dir = test::temp_dir("golden");
  const fs::path p = dir / kGolden.filename();  // same name: ThisFileName is in the header
  write_golden(p);
  EXPECT_EQ(test::read_bytes(p), test::read_bytes(kGolden));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth::xtf
