// SPDX-License-Identifier: MIT
// Streamed waterfalls: rows spooled to an unnamed temporary file come back as the image that
// assembling them in memory gives, and the written PNG/GeoTIFF hold the expected colours
// (percentile scaling identical to robust_db_range of the whole image). More in
// waterfall_rows_test.cpp.
#include "sonarsynth/formats/products/waterfall.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mosaic_test_util.hpp"
#include "sonarsynth/colormap.hpp"
#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "waterfall_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using namespace test;  // NOLINT: the shared helpers of waterfall_test_util.hpp

TEST(DbRangeSampler, EqualsRobustDbRangeForAnyChunking) {
  std::mt19937 rng(5);
  std::lognormal_distribution<float> value(0.0f, 2.0f);
  std::uniform_int_distribution<int> special(0, 49);
  const std::size_t max_samples = 1000;
  for (const std::size_t n : {0u, 1u, 999u, 1000u, 1001u, 1999u, 2000u, 2501u, 10007u}) {
    std::vector<float> v(n);
    for (float& x : v) {
      const int s = special(rng);
      x = s == 0 ? kNaN : s == 1 ? 0.0f : s == 2 ? -1.0f : value(rng);
    }
    const DisplayRange want = robust_db_range(v, 2.0, 97.0, max_samples);
    for (const std::size_t chunk : {std::size_t{1}, std::size_t{7}, max_samples, n + 1}) {
      DbRangeSampler s(n, max_samples);
      for (std::size_t i = 0; i < n; i += chunk) {
        s.add(std::span<const float>(v).subspan(i, std::min(chunk, n - i)));
      }
      const DisplayRange got = s.range(2.0, 97.0);
      EXPECT_EQ(got.lo_db, want.lo_db) << "n = " << n << ", chunk = " << chunk;
      EXPECT_EQ(got.hi_db, want.hi_db) << "n = " << n << ", chunk = " << chunk;
    }
  }
  DbRangeSampler s(10);
  EXPECT_THROW(s.range(50.0, 50.0), InputError);
}

// The waterfall's bounded subsample (range_samples, 2^18 floats) against the exact percentiles of
// a whole 8192 x 2000 image like a waterfall (a range-dependent mean, speckle, NaN padding and
// zeros): the picked values' ranks in the whole image are within 0.1 percentile points of the
// asked percentiles (binomial rank error of a subsample of n: sqrt(p (1 - p) / n) = 0.02 points
// at p = 1 % and n = 2^18, so 0.1 is 5 standard deviations).
TEST(DbRangeSampler, BoundedSubsampleIsWithinATenthOfAPercentileOfTheExactRanks) {
  const std::size_t cols = 8192, rows = 2000;
  std::mt19937 rng(9);
  std::exponential_distribution<float> speckle(1.0f);
  std::vector<float> img(cols * rows);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < cols; ++c) {
      const double range = std::abs(static_cast<double>(c) - 4095.5) / 4096.0;
      const auto mean = static_cast<float>(1000.0 * std::exp(-4.0 * range));
      float& v = img[r * cols + c];
      v = c < r % 97 ? kNaN : (c % 1000 == 3 ? 0.0f : mean * speckle(rng));
    }
  }
  const std::size_t samples = WaterfallOptions{}.range_samples;
  DbRangeSampler s(img.size(), samples);
  for (std::size_t r = 0; r < rows; ++r) {
    s.add(std::span<const float>(img).subspan(r * cols, cols));
  }
  const DisplayRange got = s.range(1.0, 99.0);
  std::vector<double> db;
  for (const float v : img) {
    if (std::isfinite(v) && v > 0.0f) db.push_back(10.0 * std::log10(static_cast<double>(v)));
  }
  std::sort(db.begin(), db.end());
  const auto n = static_cast<double>(db.size());
  const auto rank_pct = [&](double x) {  // percentile rank of x in the whole image (mid rank)
    const auto lo = std::lower_bound(db.begin(), db.end(), x) - db.begin();
    const auto hi = std::upper_bound(db.begin(), db.end(), x) - db.begin();
    return 100.0 * 0.5 * static_cast<double>(lo + hi) / n;
  };
  EXPECT_NEAR(rank_pct(got.lo_db), 1.0, 0.1);
  EXPECT_NEAR(rank_pct(got.hi_db), 99.0, 0.1);
}

// Many rows of varying side lengths (the width grows after rows were spooled): the streamed
// image is the one assembled in memory, bit for bit.
TEST(Waterfall, StreamedImageEqualsInMemoryAssembly) {
  const auto dir = test::mosaic_temp_dir("wf_stream");
  const std::vector<Ping> pings = random_pings(500, 300, 1);
  WaterfallOptions o;
  o.spool_dir = dir;
  Waterfall wf(o);
  for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 50.0, 10.0);
  std::size_t cols = 0;
  const std::vector<float> want = expected_image(pings, &cols, kNaN);
  EXPECT_EQ(wf.rows(), pings.size());
  EXPECT_EQ(wf.cols(), cols);
  const std::vector<float> got = wf.image();
  ASSERT_EQ(got.size(), want.size());
  std::size_t bad = 0;
  for (std::size_t i = 0; i < want.size(); ++i) bad += !same_float(got[i], want[i]);
  EXPECT_EQ(bad, 0u);
  // Slant correction resamples each side to the same number of samples.
  o.slant_correct = true;
  Waterfall ground(o);
  for (const Ping& p : pings) ground.add_ping(p.port, p.stbd, 50.0, 10.0);
  EXPECT_EQ(ground.rows(), pings.size());
  EXPECT_EQ(ground.cols(), cols);
  fs::remove_all(dir);
}

// A small image written as PNG and GeoTIFF, grey and coloured: the bytes read back are the
// colours of the expected image under robust_db_range (percentiles) or the fixed window.
TEST(Waterfall, PngAndTifHoldTheExpectedColours) {
  const auto dir = test::mosaic_temp_dir("wf_bytes");
  const auto [pings, cols, img] = random_image(9, 6, 2);
  for (const Colormap map : {Colormap::grey, Colormap::black_brown_yellow}) {
    for (const bool fixed : {false, true}) {
      WaterfallOptions o;
      o.colormap = map;
      o.lo_percentile = 5.0;
      o.hi_percentile = 90.0;
      o.fixed_db = fixed;
      o.lo_db = -3.0;
      o.hi_db = 6.0;
      const Waterfall wf = waterfall_of(o, dir, pings);
      const DisplayRange range = fixed ? DisplayRange{-3.0, 6.0} : robust_db_range(img, 5.0, 90.0);
      const std::vector<std::uint8_t> want = colourise(img, range, map);
      for (const std::string ext : {".png", ".tif"}) {
        // (One append at a time: GCC 12 reports a false -Wrestrict on "w" + std::string here.)
        std::string name = "w";
        name += std::to_string(static_cast<int>(map));
        name += std::to_string(fixed);
        name += ext;
        const std::string path = (dir / name).string();
        wf.write(path);
        int c = 0, r = 0;
        std::string driver;
        const std::vector<std::uint8_t> got = read_bytes(path, &c, &r, &driver);
        EXPECT_EQ(driver, ext == ".png" ? "PNG" : "GTiff");
        EXPECT_EQ(static_cast<std::size_t>(c), cols);
        EXPECT_EQ(static_cast<std::size_t>(r), pings.size());
        EXPECT_EQ(got, want) << path;
      }
    }
  }
  // Nothing but the outputs in the directory (no temporary names left).
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().front(), 'w') << e.path();
    ++files;
  }
  EXPECT_EQ(files, 8u);
  fs::remove_all(dir);
}

// An image large enough (2.4 M pixels) for robust_db_range to subsample it: the streamed
// scaling (first pass over the spool) takes the same subsample, so the PNG has exactly the
// colours of the in-memory scaling.
TEST(Waterfall, PercentileScalingEqualsRobustDbRangeOfTheWholeImage) {
  const auto dir = test::mosaic_temp_dir("wf_scale");
  const auto [pings, cols, img] = random_image(2000, 600, 3);
  WaterfallOptions o;
  o.colormap = Colormap::grey;
  ASSERT_GT(img.size(), 8 * o.range_samples);  // the subsample takes every 9th value at most
  const std::string path = write_waterfall(o, pings, dir, "big.png");
  int c = 0, r = 0;
  std::string driver;
  const std::vector<std::uint8_t> got = read_bytes(path, &c, &r, &driver);
  const std::vector<std::uint8_t> want =
      colourise(img, robust_db_range(img, 1.0, 99.0, o.range_samples), Colormap::grey);
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(mismatched_bytes(got, want), 0u);
  fs::remove_all(dir);
}

/// The chunk types of the PNG file at `path`, in order (read from its bytes: 8-byte signature,
/// then per chunk a big-endian length, the type, the data and a CRC checked against zlib's).
std::vector<std::string> png_chunks(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> f((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
  const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (f.size() < 8 || !std::equal(signature, signature + 8, f.begin())) return {"no signature"};
  std::vector<std::string> types;
  std::size_t at = 8;
  while (at + 12 <= f.size()) {
    const std::uint32_t len = (std::uint32_t{f[at]} << 24) | (std::uint32_t{f[at + 1]} << 16) |
                              (std::uint32_t{f[at + 2]} << 8) | std::uint32_t{f[at + 3]};
    if (at + 12 + len > f.size()) return {"truncated chunk"};
    const std::uint8_t* p = f.data() + at + 4;
    const std::uint32_t crc_stored = (std::uint32_t{p[4 + len]} << 24) |
                                     (std::uint32_t{p[5 + len]} << 16) |
                                     (std::uint32_t{p[6 + len]} << 8) | std::uint32_t{p[7 + len]};
    if (crc32(0L, p, 4 + len) != crc_stored) return {"bad CRC"};
    types.emplace_back(reinterpret_cast<const char*>(p), 4);
    at += 12 + len;
  }
  if (at != f.size()) types.emplace_back("trailing bytes");
  return types;
}

// A colour waterfall whose compressed image data fills several IDAT chunks: the chunks are a
// valid sequence (IHDR first, tEXt before the image data, the IDATs together, IEND last, every
// CRC right) and every pixel reads back as the colours of the image.
TEST(Waterfall, LargeColourPngSplitsItsImageDataIntoValidChunks) {
  const auto dir = test::mosaic_temp_dir("wf_chunks");
  const auto [pings, cols, img] = random_image(1500, 600, 5);
  WaterfallOptions o;
  o.colormap = Colormap::black_brown_yellow;
  const std::string path = write_waterfall(o, pings, dir, "colour.png");
  const std::vector<std::string> chunks = png_chunks(path);
  ASSERT_GE(chunks.size(), 4u);
  EXPECT_EQ(chunks.front(), "IHDR");
  EXPECT_EQ(chunks.back(), "IEND");
  const auto first_idat = std::find(chunks.begin(), chunks.end(), "IDAT");
  const auto idats = std::count(chunks.begin(), chunks.end(), "IDAT");
  EXPECT_GE(idats, 3);  // 5.4 MB of pixels, chunks of at most 256 KiB
  EXPECT_TRUE(std::all_of(first_idat, first_idat + idats,
                          [](const std::string& t) { return t == "IDAT"; }));
  EXPECT_GE(std::count(chunks.begin(), first_idat, "tEXt"), 1);
  int c = 0, r = 0;
  std::string driver;
  const std::vector<std::uint8_t> got = read_bytes(path, &c, &r, &driver);
  const std::vector<std::uint8_t> want =
      colourise(img, robust_db_range(img, o.lo_percentile, o.hi_percentile, o.range_samples),
                Colormap::black_brown_yellow);
  EXPECT_EQ(static_cast<std::size_t>(c), cols);
  EXPECT_EQ(static_cast<std::size_t>(r), pings.size());
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(mismatched_bytes(got, want), 0u);
  fs::remove_all(dir);
}

// The PNG's text chunks as GDAL reads them back: every item, a later item of the same key
// replacing the earlier one (as GDAL's own PNG driver does); a key PNG cannot hold (over 79
// characters) is an error naming it and leaves no file.
TEST(Waterfall, PngTextChunksAreTheMetadataItems) {
  const auto dir = test::mosaic_temp_dir("wf_text");
  const std::vector<Ping> pings = random_pings(5, 4, 3);
  WaterfallOptions o;
  o.metadata = {{"B_ITEM", "first"}, {"A_ITEM", "x = 1, y = 2"}, {"B_ITEM", "second"}};
  const std::string path = write_waterfall(o, pings, dir, "t.png");
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  ASSERT_NE(ds, nullptr);
  EXPECT_STREQ(ds->GetDriver()->GetDescription(), "PNG");
  EXPECT_STREQ(ds->GetMetadataItem("A_ITEM"), "x = 1, y = 2");
  EXPECT_STREQ(ds->GetMetadataItem("B_ITEM"), "second");
  EXPECT_STREQ(ds->GetMetadataItem("SONARSYNTH_NODATA"), "0 (black): no sample");
  EXPECT_EQ(ds->GetRasterCount(), 3);
  GDALClose(ds);
  const std::string long_key(80, 'K');
  WaterfallOptions bad;
  bad.spool_dir = dir;
  bad.metadata.emplace_back(long_key, "v");
  Waterfall wf2(bad);
  for (const Ping& p : pings) wf2.add_ping(p.port, p.stbd, 0.0, 0.0);
  const std::string bad_path = (dir / "bad.png").string();
  try {
    wf2.write(bad_path);
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::strstr(e.what(), long_key.c_str()), nullptr) << e.what();
    EXPECT_NE(std::strstr(e.what(), "bad.png"), nullptr) << e.what();
  }
  EXPECT_FALSE(fs::exists(bad_path));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
