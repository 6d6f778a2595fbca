// SPDX-License-Identifier: MIT
// `sonarsynth mosaic` / `sonarsynth waterfall` end to end: bad input fails cleanly (non-zero
// exit, a message, no output file); the waterfall has nadir in the middle.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "mosaic_test_util.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

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

  fs::path dir_;
  std::string err_;
};

TEST_F(MosaicCliTest, UnreadableFileFails) {
  std::ofstream(path("junk.xtf")) << "this is not an XTF file";
  EXPECT_EQ(run("mosaic " + path("junk.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_NE(err_.find("junk.xtf"), std::string::npos) << err_;
  EXPECT_EQ(run("mosaic " + path("missing.xtf") + " -o " + path("m.tif")), 1);
  EXPECT_NE(err_.find("missing.xtf"), std::string::npos) << err_;
  EXPECT_EQ(run("waterfall " + path("junk.xtf") + " -o " + path("w.png")), 1);
  EXPECT_EQ(outputs(), 0u);
}

TEST_F(MosaicCliTest, FileWithoutSonarChannelsFails) {
  {
    xtf::Writer w(path("empty.xtf"));
    xtf::AttitudeSample a;
    a.time_utc = xtf::UtcTime{std::chrono::seconds{1700000000}};
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

}  // namespace
}  // namespace sonarsynth
