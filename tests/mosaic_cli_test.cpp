// SPDX-License-Identifier: MIT
// `sonarsynth mosaic` / `sonarsynth waterfall` end to end: bad input fails cleanly (non-zero
// exit, a message, no output file); the waterfall has nadir in the middle.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "mosaic_test_util.hpp"
#include "sonarsynth/formats/io/byte_io.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/records.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

class MosaicCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::mosaic_temp_dir(std::string("cli_") +
                                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Runs `sonarsynth <args>`; returns the exit status and keeps stderr in err_.
  int run(const std::string& args) {
    const test::CliResult r = test::run_cli(args, dir_);
    err_ = r.err;
    return r.exit_code;
  }
  /// Files in the directory other than the inputs.
  std::size_t outputs() const {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir_)) {
      if (e.path().extension() != ".xtf" && e.path().extension() != ".txt") ++n;
    }
    return n;
  }

  /// Runs `sonarsynth <args>`; keeps stdout in out_ too.
  int run_out(const std::string& args) {
    const test::CliResult r = test::run_cli(args, dir_);
    err_ = r.err;
    out_ = r.out;
    return r.exit_code;
  }
  /// Names of the files in the directory, sorted.
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }
  std::vector<std::uint8_t> bytes(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  void write(const std::string& name, const std::vector<std::uint8_t>& b) const {
    std::ofstream out(path(name), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  }
  /// `field` of each sonar packet of an XTF file, in file order.
  std::vector<std::uint64_t> of_pings(const std::string& name,
                                      std::uint64_t xtf::Packet::*field) const {
    xtf::Reader r(fs::path(path(name)));
    xtf::Packet p;
    std::vector<std::uint64_t> out;
    while (r.next(p)) {
      if (p.kind == xtf::PacketKind::kPing) out.push_back(p.*field);
    }
    return out;
  }
  /// Byte offsets of the sonar packets of an XTF file, in file order.
  std::vector<std::uint64_t> ping_offsets(const std::string& name) const {
    return of_pings(name, &xtf::Packet::offset);
  }
  /// Packet indices (0-based among all packets) of the sonar packets, in file order.
  std::vector<std::uint64_t> ping_packet_indices(const std::string& name) const {
    return of_pings(name, &xtf::Packet::index);
  }

  fs::path dir_;
  std::string err_;
  std::string out_;
};

/// Offset of a float or double field inside the encoded XTFPINGHEADER, found by encoding a
/// header whose field holds a marker value (no byte layout is assumed here).
template <class T>
std::size_t ping_header_offset_of(T xtf::XtfPingHeader::*field) {
  xtf::XtfPingHeader h;
  const T marker = static_cast<T>(123456.75);
  h.*field = marker;
  std::vector<std::uint8_t> b(xtf::XtfPingHeader::kSize, 0);
  ByteWriter w(b);
  h.encode(w);
  for (std::size_t i = 0; i + sizeof(T) <= b.size(); ++i) {
    if (std::memcmp(&b[i], &marker, sizeof(T)) == 0) return i;
  }
  return 0;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_F(MosaicCliTest, UnreadableFileFails) {
  std::ofstream(path("junk.xtf")) << "this is not an XTF file";
  EXPECT_EQ(run("mosaic " + path("junk.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_NE(err_.find("junk.xtf"), std::string::npos) << err_;
  EXPECT_EQ(run("mosaic " + path("missing.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_NE(err_.find("missing.xtf"), std::string::npos) << err_;
  EXPECT_EQ(run("waterfall " + path("junk.xtf") + " -o " + path("w.png")), 1);
  EXPECT_EQ(outputs(), 0u);
}

// --depth-positive describes a --bathymetry grid: alone it would be silently ignored.
TEST_F(MosaicCliTest, DepthPositiveWithoutBathymetryIsAnError) {
  EXPECT_EQ(run("mosaic " + path("a.xtf") + " -o " + path("m.tif") + " --depth-positive"), 1);
  EXPECT_NE(err_.find("--depth-positive given without --bathymetry"), std::string::npos) << err_;
  EXPECT_EQ(outputs(), 0u);
}

TEST_F(MosaicCliTest, FileWithoutSonarChannelsFails) {
  {
    xtf::Writer w(path("empty.xtf"));
    AttitudeSample a;
    a.time_utc = UtcTime{std::chrono::seconds{1700000000}};
    w.write_attitude(a);
    w.close();
  }
  EXPECT_EQ(run("mosaic " + path("empty.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_NE(err_.find("no sonar channel"), std::string::npos) << err_;
  EXPECT_EQ(run("waterfall " + path("empty.xtf") + " -o " + path("w.png")), 1);
  EXPECT_NE(err_.find("no sonar channel"), std::string::npos) << err_;
  EXPECT_EQ(outputs(), 0u);
}

TEST_F(MosaicCliTest, AllZeroNavigationFails) {
  test::LineSpec s;
  s.start = {48.4456, -68.8281};
  s.heading_deg = 0.0;  // every ping at the same longitude: one byte pattern to zero
  s.pings = 20;
  test::write_line(path("line.xtf"), s);
  // Zero every sensor/ship longitude and latitude in the file's bytes.
  std::vector<std::uint8_t> bytes;
  {
    std::ifstream in(path("line.xtf"), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::size_t zeroed = 0;
  auto zero_all = [&](double v) {
    std::uint8_t pat[8];
    std::memcpy(pat, &v, 8);
    for (std::size_t i = 0; i + 8 <= bytes.size(); ++i) {
      if (std::memcmp(&bytes[i], pat, 8) == 0) {
        std::memset(&bytes[i], 0, 8);
        ++zeroed;
      }
    }
  };
  zero_all(s.start.lon_deg);
  for (int i = 0; i < s.pings; ++i) zero_all(test::ping_position(s, i).lat_deg);
  ASSERT_GE(zeroed, 2u * static_cast<std::size_t>(s.pings));
  {
    std::ofstream out(path("line.xtf"), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  }
  EXPECT_EQ(run("mosaic " + path("line.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_NE(err_.find("no ping has valid navigation"), std::string::npos) << err_;
  EXPECT_EQ(outputs(), 0u);
}

TEST_F(MosaicCliTest, ExistingOutputNeedsOverwrite) {
  test::LineSpec s;
  s.start = {48.4456, -68.8281};
  s.pings = 30;
  test::write_line(path("line.xtf"), s);
  std::ofstream(path("m.tif")) << "precious";
  EXPECT_EQ(run("mosaic " + path("line.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_NE(err_.find("already exists"), std::string::npos) << err_;
  EXPECT_EQ(fs::file_size(path("m.tif")), 8u);
  EXPECT_FALSE(fs::exists(path("m_rgb.tif")));
  // With --overwrite both files appear; the existing display copy alone also blocks.
  EXPECT_EQ(run("mosaic " + path("line.xtf") + " -o " + path("m.tif") + " --overwrite -q"), 0)
      << err_;
  EXPECT_GT(fs::file_size(path("m.tif")), 8u);
  EXPECT_TRUE(fs::exists(path("m_rgb.tif")));
  fs::remove(path("m.tif"));
  EXPECT_EQ(run("mosaic " + path("line.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_FALSE(fs::exists(path("m.tif")));
  std::ofstream(path("w.png")) << "x";
  EXPECT_EQ(run("waterfall " + path("line.xtf") + " -o " + path("w.png")), 1);
  EXPECT_EQ(fs::file_size(path("w.png")), 1u);
}

// --linear V: grey level = sample / V, clamped (the founding paper's display, docs/paper-model.md);
// a scale that is not positive, or one given with --lo-db/--hi-db, is refused.
TEST_F(MosaicCliTest, LinearDisplayScaleOfWaterfallAndMosaic) {
  test::LineSpec s;
  s.start = {48.4456, -68.8281};
  s.pings = 10;
  s.samples = 100;
  s.bright = 37;  // 1000; every other sample is 1
  test::write_line(path("line.xtf"), s);
  ASSERT_EQ(run("waterfall " + path("line.xtf") + " -o " + path("l.png") + " --grey --linear 4 -q"),
            0)
      << err_;
  const test::Raster l = test::read_band(path("l.png"));
  ASSERT_EQ(l.cols, 200);
  for (int r = 0; r < l.rows; ++r) {
    EXPECT_EQ(l.data[static_cast<std::size_t>(r * l.cols + 100 + 37)], 255.0f);  // 1000/4 -> 1
    EXPECT_EQ(l.data[static_cast<std::size_t>(r * l.cols + 100 + 36)], 64.0f);   // 255 / 4
    EXPECT_EQ(l.data[static_cast<std::size_t>(r * l.cols + 5)], 64.0f);
  }
  EXPECT_EQ(run("waterfall " + path("line.xtf") + " -o " + path("z.png") + " --linear 0"), 1);
  EXPECT_NE(err_.find("--linear"), std::string::npos) << err_;
  EXPECT_EQ(run("waterfall " + path("line.xtf") + " -o " + path("z.png") +
                " --linear 5 --lo-db 0 --hi-db 10"),
            1);
  EXPECT_NE(err_.find("--linear and --lo-db/--hi-db"), std::string::npos) << err_;
  EXPECT_EQ(run("mosaic " + path("line.xtf") + " -o " + path("m.tif") + " --linear -3"), 1);
  EXPECT_NE(err_.find("--linear"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(path("z.png")));
  EXPECT_FALSE(fs::exists(path("m.tif")));
  ASSERT_EQ(run("mosaic " + path("line.xtf") + " -o " + path("m.tif") + " --linear 4 -q"), 0)
      << err_;
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path("m_rgb.tif").c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  ASSERT_NE(ds, nullptr);
  EXPECT_STREQ(ds->GetMetadataItem("SONARSYNTH_DISPLAY_SCALE"), "linear: value / 4 (1)");
  GDALClose(ds);
}

TEST_F(MosaicCliTest, RealFileMosaicWarnsAboutTheZeroNavigationPing) {
  const std::string xtf = SONARSYNTH_TEST_DATA_DIR "/xtf/scotsman-iver2.xtf";
  ASSERT_EQ(run("mosaic " + xtf + " -o " + path("m.tif") + " --no-rgb -q"), 0) << err_;
  EXPECT_NE(err_.find("skipped 1 of 461 pings"), std::string::npos) << err_;
  EXPECT_TRUE(fs::exists(path("m.tif")));
  EXPECT_EQ(outputs(), 1u);
}

// Waterfall: 2N columns x pings rows; port near range is column N-1, starboard near N.
TEST_F(MosaicCliTest, WaterfallHasNadirInTheMiddle) {
  const std::string xtf = SONARSYNTH_TEST_DATA_DIR "/xtf/scotsman-iver2.xtf";
  ASSERT_EQ(run("waterfall " + xtf + " -o " + path("w.png") + " --grey -q"), 0) << err_;
  const test::Raster w = test::read_band(path("w.png"));
  EXPECT_EQ(w.cols, 2 * 1024);
  EXPECT_EQ(w.rows, 461);
  // The water column (darkest) is at the middle, the seabed at the sides: mean of the 100
  // columns either side of the centre vs the outer 100 columns of each side.
  auto column_mean = [&](int c0, int c1) {
    double s = 0.0;
    for (int r = 0; r < w.rows; ++r) {
      for (int c = c0; c < c1; ++c) s += w.data[static_cast<std::size_t>(r * w.cols + c)];
    }
    return s / (w.rows * (c1 - c0));
  };
  const double middle = column_mean(1024 - 100, 1024 + 100);
  const double edges = 0.5 * (column_mean(0, 100) + column_mean(2048 - 100, 2048));
  EXPECT_LT(middle, 0.6 * edges);

  // A synthetic line with one bright starboard sample: it appears at column N + index.
  test::LineSpec s;
  s.start = {48.4456, -68.8281};
  s.pings = 10;
  s.samples = 100;
  s.bright = 37;
  test::write_line(path("line.xtf"), s);
  ASSERT_EQ(run("waterfall " + path("line.xtf") + " -o " + path("l.png") + " --grey -q"), 0);
  const test::Raster l = test::read_band(path("l.png"));
  ASSERT_EQ(l.cols, 200);
  ASSERT_EQ(l.rows, 10);
  for (int r = 0; r < l.rows; ++r) {
    EXPECT_EQ(l.data[static_cast<std::size_t>(r * l.cols + 100 + 37)], 255.0f);
    EXPECT_LT(l.data[static_cast<std::size_t>(r * l.cols + 100 - 1 - 37)], 255.0f);
  }
}

// ---- One bad ping in a file: skipped with an anomaly, the rest of the file is used ----------

// A ping whose NumChansToFollow (3) exceeds what its record holds once its two channels are
// read: `info`, `waterfall` and `mosaic` use the other pings and report the anomaly with the
// file, the packet and the value.
TEST_F(MosaicCliTest, MalformedPingIsSkippedByInfoWaterfallAndMosaic) {
  test::LineSpec s;
  s.start = {48.4456, -68.8281};
  s.pings = 20;
  s.samples = 100;
  test::write_line(path("bad.xtf"), s);
  const std::vector<std::uint64_t> offsets = ping_offsets("bad.xtf");
  const std::vector<std::uint64_t> indices = ping_packet_indices("bad.xtf");
  ASSERT_EQ(offsets.size(), 20u);
  auto b = bytes("bad.xtf");
  const std::uint64_t bad = offsets[7];
  const std::uint16_t three = 3;
  std::memcpy(&b[bad + 4], &three, 2);  // NumChansToFollow: bytes 4-5 of the packet header
  write("bad.xtf", b);
  const std::vector<std::string> inputs = listing();

  ASSERT_EQ(run_out("info " + path("bad.xtf")), 0) << err_;
  EXPECT_TRUE(contains(out_, "Sonar pings: 19")) << out_;
  EXPECT_TRUE(contains(out_, "bad_record_size: 1")) << out_;
  for (const std::string& part : {std::string("NumChansToFollow = 3"), std::string("PingNumber 7"),
                                  "at byte " + std::to_string(bad) + " of " + path("bad.xtf")}) {
    EXPECT_TRUE(contains(out_, part)) << part << " in " << out_;
  }

  ASSERT_EQ(run_out("info --json " + path("bad.xtf")), 0) << err_;
  const nlohmann::json info = nlohmann::json::parse(out_);
  bool found = false;
  for (const auto& a : info.at("anomalies")) {
    found = found || (a.at("kind") == "bad_record_size" && a.at("offset") == bad &&
                      a.at("packet") == indices[7]);
  }
  EXPECT_TRUE(found) << out_;

  ASSERT_EQ(run_out("waterfall " + path("bad.xtf") + " -o " + path("w.png") + " --grey -q"), 0)
      << err_;
  EXPECT_EQ(test::read_band(path("w.png")).rows, 19);
  EXPECT_TRUE(contains(err_, "warning: 1 anomalies")) << err_;
  EXPECT_TRUE(contains(err_, "NumChansToFollow = 3")) << err_;
  EXPECT_TRUE(contains(err_, path("bad.xtf"))) << err_;

  ASSERT_EQ(run_out("mosaic " + path("bad.xtf") + " -o " + path("m.tif") + " --no-rgb"), 0) << err_;
  EXPECT_TRUE(contains(out_, "19 of 19 pings")) << out_;
  EXPECT_TRUE(contains(err_, "warning: 1 anomalies")) << err_;
  EXPECT_TRUE(contains(err_, "PingNumber 7")) << err_;

  // The input is untouched and the only new files are the two outputs.
  EXPECT_EQ(bytes("bad.xtf"), b);
  std::vector<std::string> expected = inputs;
  expected.push_back("m.tif");
  expected.push_back("w.png");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(listing(), expected);
}

// ---- Navigation outliers and the pixel cap ---------------------------------------------------

class MosaicOutlierTest : public MosaicCliTest {
 protected:
  MosaicOutlierTest() {
    spec_.start = {48.4456, -68.8281};
    spec_.heading_deg = 33.0;
    spec_.pings = 120;
    spec_.spacing_m = 0.5;
    spec_.samples = 100;
  }
  /// Mosaics `name` into `out`; returns the exit status.
  int mosaic(const std::string& name, const std::string& out, const std::string& extra = "") {
    return run_out("mosaic " + path(name) + " -o " + path(out) + " --no-rgb --res 0.5 " + extra);
  }
  /// The reference: the same line without ping `skip`.
  test::Raster reference_without(int skip) {
    test::write_line(path("ref.xtf"), spec_, [&](int i, SonarPing&) { return i != skip; });
    EXPECT_EQ(mosaic("ref.xtf", "ref.tif"), 0) << err_;
    EXPECT_TRUE(err_.empty()) << err_;
    test::Raster r = test::read_band(path("ref.tif"));
    fs::remove(path("ref.tif"));
    fs::remove(path("ref.xtf"));
    return r;
  }
  /// Writes the line to `name` with `field` of ping `ping`'s header patched to NaN (the writer
  /// refuses one).
  template <class T>
  void write_line_with_nan(const std::string& name, T xtf::XtfPingHeader::*field, int ping) {
    test::write_line(path(name), spec_);
    const std::size_t at = ping_header_offset_of(field);
    ASSERT_GT(at, 0u);
    auto b = bytes(name);
    const T nan = std::numeric_limits<T>::quiet_NaN();
    std::memcpy(&b[ping_offsets(name)[static_cast<std::size_t>(ping)] + at], &nan, sizeof(T));
    write(name, b);
  }
  /// err_ names ping `ping` of `name` with its packet index.
  void expect_ping_named(const std::string& name, int ping) const {
    const std::string packet =
        std::to_string(ping_packet_indices(name)[static_cast<std::size_t>(ping)]);
    EXPECT_TRUE(
        contains(err_, path(name) + ": ping " + std::to_string(ping) + " (packet " + packet + ")"))
        << err_;
  }
  static void expect_same_grid(const test::Raster& a, const test::Raster& b) {
    EXPECT_EQ(a.cols, b.cols);
    EXPECT_EQ(a.rows, b.rows);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(a.gt[i], b.gt[i]) << "geotransform " << i;
  }
  test::LineSpec spec_;
};

// One ping 2 km off the line (a GPS jump): without the test the grid would reach it.
TEST_F(MosaicOutlierTest, GpsJumpOfOnePingIsDroppedFromTheExtent) {
  const test::Raster ref = reference_without(60);
  ASSERT_GT(ref.cols, 0);
  test::write_line(path("jump.xtf"), spec_, [&](int i, SonarPing& p) {
    if (i == 60) {
      const test::LatLon far = test::direct(test::ping_position(spec_, i), 123.0, 2000.0);
      p.sensor_position = {rad_from_deg(far.lat_deg), rad_from_deg(far.lon_deg), 0.0};
    }
    return true;
  });
  const auto input = bytes("jump.xtf");
  ASSERT_EQ(mosaic("jump.xtf", "m.tif"), 0) << err_;
  EXPECT_TRUE(contains(err_, "dropped 1 of 120 pings as navigation outliers (1 position jumps"))
      << err_;
  expect_ping_named("jump.xtf", 60);
  // 2000 m across the track and the medians 3 pings (1.5 m) along it, in UTM metres: the
  // geodesic distance times the point scale factor k there (GeographicLib).
  {
    const test::LatLon at = test::ping_position(spec_, 60);
    int zone = 0;
    bool northp = false;
    double x = 0, y = 0, gamma = 0, k = 0;
    GeographicLib::UTMUPS::Forward(at.lat_deg, at.lon_deg, zone, northp, x, y, gamma, k);
    const double expected = std::hypot(2000.0 * k, 1.5);
    for (const std::string side : {"before", "after"}) {
      const std::string tail = " m from the median of the 5 " + side;
      const std::size_t end = err_.find(tail);
      ASSERT_NE(end, std::string::npos) << err_;
      const std::size_t begin = err_.rfind(' ', end - 1) + 1;
      EXPECT_NEAR(std::stod(err_.substr(begin, end - begin)), expected, 0.01) << err_;
    }
    EXPECT_TRUE(contains(err_, "(threshold 50 m)")) << err_;
  }
  EXPECT_TRUE(contains(out_, "119 of 120 pings")) << out_;
  expect_same_grid(test::read_band(path("m.tif")), ref);
  EXPECT_EQ(bytes("jump.xtf"), input);
  EXPECT_EQ(listing(), (std::vector<std::string>{"jump.xtf", "m.tif"}));
}

// A survey that stops and resumes 300 m away is not an outlier: the first ping after the gap
// is near the pings after it, the last one before near the pings before it.
TEST_F(MosaicOutlierTest, ResumingElsewhereAfterAGapIsKept) {
  test::write_line(path("gap.xtf"), spec_, [&](int i, SonarPing& p) {
    if (i >= 60) {
      const test::LatLon moved = test::direct(test::ping_position(spec_, i), 123.0, 300.0);
      p.sensor_position = {rad_from_deg(moved.lat_deg), rad_from_deg(moved.lon_deg), 0.0};
    }
    return true;
  });
  ASSERT_EQ(mosaic("gap.xtf", "m.tif"), 0) << err_;
  EXPECT_FALSE(contains(err_, "dropped")) << err_;
  EXPECT_TRUE(contains(out_, "120 of 120 pings")) << out_;
}

// SlantRange 1e6 m on one ping: without the test, 4e6 x 4e6 pixels.
TEST_F(MosaicOutlierTest, AbsurdSlantRangeIsDropped) {
  const test::Raster ref = reference_without(30);
  test::write_line(path("range.xtf"), spec_, [&](int i, SonarPing& p) {
    if (i == 30) p.slant_range_m = 1e6;
    return true;
  });
  ASSERT_EQ(mosaic("range.xtf", "m.tif"), 0) << err_;
  EXPECT_TRUE(contains(err_,
                       "dropped 1 of 120 pings as navigation outliers (0 position jumps, 1 "
                       "slant ranges, 0 headings)"))
      << err_;
  expect_ping_named("range.xtf", 30);
  EXPECT_TRUE(contains(err_, "SlantRange = 1e+06 m")) << err_;
  expect_same_grid(test::read_band(path("m.tif")), ref);
}

// A NaN SensorHeading (patched in: the writer refuses one) drops that ping, not the batch.
TEST_F(MosaicOutlierTest, NanHeadingDoesNotAbort) {
  const test::Raster ref = reference_without(119);
  ASSERT_NO_FATAL_FAILURE(write_line_with_nan("nan.xtf", &xtf::XtfPingHeader::SensorHeading, 119));
  ASSERT_EQ(mosaic("nan.xtf", "m.tif"), 0) << err_;
  EXPECT_TRUE(contains(err_, "0 slant ranges, 1 headings)")) << err_;
  expect_ping_named("nan.xtf", 119);
  EXPECT_TRUE(contains(err_, "SensorHeading = nan")) << err_;
  expect_same_grid(test::read_band(path("m.tif")), ref);
}

// A NaN position is no position: skipped and counted as such, the grid as without the ping.
TEST_F(MosaicOutlierTest, NanPositionIsSkipped) {
  const test::Raster ref = reference_without(0);
  ASSERT_NO_FATAL_FAILURE(
      write_line_with_nan("nanpos.xtf", &xtf::XtfPingHeader::SensorXcoordinate, 0));
  ASSERT_EQ(mosaic("nanpos.xtf", "m.tif"), 0) << err_;
  EXPECT_TRUE(contains(err_, "skipped 1 of 120 pings with missing or zero navigation")) << err_;
  expect_same_grid(test::read_band(path("m.tif")), ref);
}

// Two lines 20 km apart diagonally (each fine, and not outliers: they are separate files) make
// an 80000 x 80000 pixel mosaic at 0.25 m: refused before any allocation, nothing written;
// --max-pixels can lower (or raise) the limit.
TEST_F(MosaicOutlierTest, PixelCapRefusesWithAClearMessageAndWritesNothing) {
  spec_.pings = 20;
  test::write_line(path("a.xtf"), spec_);
  spec_.start = test::direct(spec_.start, 45.0, 20000.0);
  test::write_line(path("b.xtf"), spec_);
  const std::vector<std::string> inputs = listing();
  ASSERT_EQ(run_out("mosaic " + path("a.xtf") + " " + path("b.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_TRUE(contains(err_, "error: xtf mosaic: the mosaic of 2 files would be about")) << err_;
  EXPECT_TRUE(contains(err_, "at 0.25 m per pixel), more than max_pixels = 268435456")) << err_;
  EXPECT_TRUE(contains(err_, "--max-pixels")) << err_;
  EXPECT_EQ(listing(), inputs);

  // The cap is the option's: one short line of ~ (2 x 50 + 10) m square at 0.5 m is
  // ~220 x 220 pixels, refused under 1000 and accepted under 10^6.
  ASSERT_EQ(mosaic("a.xtf", "m.tif", "--max-pixels 1000"), 1);
  EXPECT_TRUE(contains(err_, "the mosaic of " + path("a.xtf") + " would be about")) << err_;
  EXPECT_TRUE(contains(err_, "more than max_pixels = 1000")) << err_;
  EXPECT_EQ(listing(), inputs);
  ASSERT_EQ(mosaic("a.xtf", "m.tif", "--max-pixels 1000000"), 0) << err_;
  EXPECT_TRUE(fs::exists(path("m.tif")));
}

}  // namespace
}  // namespace sonarsynth
