// SPDX-License-Identifier: MIT
// Streamed waterfalls: rows spooled to an unnamed temporary file come back as the image that
// assembling them in memory gives, the written PNG/GeoTIFF hold the expected colours (percentile
// scaling identical to robust_db_range of the whole image), the truth waterfall keeps its
// layout and padding, and the spool file never shows up and is released with its owner.
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

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// One ping: port and starboard samples NEAR -> FAR.
struct Ping {
  std::vector<float> port;
  std::vector<float> stbd;
};

/// Pings with side lengths varying from 0 to `max_side` (the longest reached only at ping
/// `pings` / 2, so the width grows after rows were spooled), speckle-like values with some
/// zeros and NaNs.
std::vector<Ping> random_pings(int pings, std::size_t max_side, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> len(0, max_side - 1);
  std::exponential_distribution<float> speckle(0.5f);
  std::uniform_int_distribution<int> special(0, 99);
  auto side = [&](std::size_t n) {
    std::vector<float> v(n);
    for (float& x : v) {
      const int s = special(rng);
      x = s == 0 ? 0.0f : s == 1 ? kNaN : 1e-3f + speckle(rng);
    }
    return v;
  };
  std::vector<Ping> out(static_cast<std::size_t>(pings));
  for (int i = 0; i < pings; ++i) {
    const std::size_t np = i == pings / 2 ? max_side : len(rng);
    const std::size_t ns = i % 7 == 3 ? 0 : len(rng);
    out[static_cast<std::size_t>(i)] = {side(np), side(ns)};
  }
  return out;
}

/// The waterfall layout computed directly: 2 x longest side columns, port FAR -> NEAR then
/// starboard NEAR -> FAR, `pad` elsewhere.
std::vector<float> expected_image(const std::vector<Ping>& pings, std::size_t* cols, float pad) {
  std::size_t side = 0;
  for (const Ping& p : pings) side = std::max({side, p.port.size(), p.stbd.size()});
  *cols = 2 * side;
  std::vector<float> img(*cols * pings.size(), pad);
  for (std::size_t r = 0; r < pings.size(); ++r) {
    for (std::size_t i = 0; i < pings[r].port.size(); ++i) {
      img[r * *cols + side - 1 - i] = pings[r].port[i];
    }
    for (std::size_t i = 0; i < pings[r].stbd.size(); ++i) {
      img[r * *cols + side + i] = pings[r].stbd[i];
    }
  }
  return img;
}

bool same_float(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

/// Band-sequential u8 colours of a linear image: black for NaN.
std::vector<std::uint8_t> colourise(const std::vector<float>& img, DisplayRange range,
                                    Colormap map) {
  const bool grey = map == Colormap::grey;
  const std::size_t n = img.size();
  std::vector<std::uint8_t> out((grey ? 1 : 3) * n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = range.value(img[i]);
    if (std::isnan(v)) continue;
    const Rgb8 c = colormap(map, v);
    out[i] = c.r;
    if (!grey) {
      out[n + i] = c.g;
      out[2 * n + i] = c.b;
    }
  }
  return out;
}

/// All bands of a raster as band-sequential u8 (empty if unreadable); the driver's name.
std::vector<std::uint8_t> read_bytes(const std::string& path, int* cols, int* rows,
                                     std::string* driver) {
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return {};
  *cols = ds->GetRasterXSize();
  *rows = ds->GetRasterYSize();
  *driver = ds->GetDriver()->GetDescription();
  const int bands = ds->GetRasterCount();
  const std::size_t n = static_cast<std::size_t>(*cols) * static_cast<std::size_t>(*rows);
  std::vector<std::uint8_t> out(n * static_cast<std::size_t>(bands));
  for (int b = 0; b < bands; ++b) {
    if (ds->GetRasterBand(b + 1)->RasterIO(GF_Read, 0, 0, *cols, *rows,
                                           out.data() + static_cast<std::size_t>(b) * n, *cols,
                                           *rows, GDT_Byte, 0, 0, nullptr) != CE_None) {
      out.clear();
      break;
    }
  }
  GDALClose(ds);
  return out;
}

/// The number of positions where two equally long byte images differ (a count, not a dump of
/// millions of pixels, when they do).
std::size_t mismatched_bytes(const std::vector<std::uint8_t>& got,
                             const std::vector<std::uint8_t>& want) {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < want.size(); ++i) bad += got[i] != want[i];
  return bad;
}

/// Open descriptors of this process on files in `dir` (as /proc/self/fd shows them; a spool
/// file reads "<dir>/<name> (deleted)").
std::vector<std::string> open_files_in(const fs::path& dir) {
  const std::string prefix = fs::canonical(dir).string() + "/";
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator("/proc/self/fd")) {
    std::error_code ec;
    const std::string target = fs::read_symlink(e.path(), ec).string();
    if (!ec && target.rfind(prefix, 0) == 0) out.push_back(target);
  }
  return out;
}

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
  const std::vector<Ping> pings = random_pings(9, 6, 2);
  std::size_t cols = 0;
  const std::vector<float> img = expected_image(pings, &cols, kNaN);
  for (const Colormap map : {Colormap::grey, Colormap::black_brown_yellow}) {
    for (const bool fixed : {false, true}) {
      WaterfallOptions o;
      o.colormap = map;
      o.lo_percentile = 5.0;
      o.hi_percentile = 90.0;
      o.fixed_db = fixed;
      o.lo_db = -3.0;
      o.hi_db = 6.0;
      o.spool_dir = dir;
      Waterfall wf(o);
      for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 0.0, 0.0);
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
  const std::vector<Ping> pings = random_pings(2000, 600, 3);
  std::size_t cols = 0;
  const std::vector<float> img = expected_image(pings, &cols, kNaN);
  WaterfallOptions o;
  o.colormap = Colormap::grey;
  o.spool_dir = dir;
  ASSERT_GT(img.size(), 8 * o.range_samples);  // the subsample takes every 9th value at most
  Waterfall wf(o);
  for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 0.0, 0.0);
  const std::string path = (dir / "big.png").string();
  wf.write(path);
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
  const std::vector<Ping> pings = random_pings(1500, 600, 5);
  std::size_t cols = 0;
  const std::vector<float> img = expected_image(pings, &cols, kNaN);
  WaterfallOptions o;
  o.colormap = Colormap::black_brown_yellow;
  o.spool_dir = dir;
  Waterfall wf(o);
  for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 0.0, 0.0);
  const std::string path = (dir / "colour.png").string();
  wf.write(path);
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

// The truth waterfall of many rows of varying lengths, in both grazing encodings: each band is
// the in-memory assembly with its padding (class 255, id -1, grazing nodata); band names are
// kept. Float32: the grazing angle in degrees as rendered (to 1e-4 deg). Int32 (the default):
// class and id exact, the grazing angle in hundredths of a degree that read back through the
// band's scale within 0.005 deg of the rendered angle (rounding to nearest; 1e-6 for the float
// degrees), nodata INT32_MIN where no seabed echo.
TEST(TruthWaterfall, StreamedBandsEqualInMemoryAssembly) {
  const auto dir = test::mosaic_temp_dir("truth_stream");
  std::mt19937 rng(4);
  std::uniform_int_distribution<std::size_t> len(0, 299);
  std::uniform_int_distribution<int> cls(0, 4), id(-1, 1000);
  std::uniform_real_distribution<float> graz(0.0f, 1.5f);
  TruthWaterfall t(dir);
  std::vector<Ping> band[3];  // class, id, grazing (deg)
  for (int i = 0; i < 700; ++i) {
    const std::size_t n[2] = {i == 350 ? 300 : len(rng), i % 5 == 0 ? 0 : len(rng)};
    std::vector<SampleClass> c[2];
    std::vector<std::int32_t> d[2];
    std::vector<float> g[2];
    for (int s = 0; s < 2; ++s) {
      for (std::size_t k = 0; k < n[s]; ++k) {
        c[s].push_back(static_cast<SampleClass>(cls(rng)));
        d[s].push_back(id(rng));
        g[s].push_back(k % 11 == 0 ? kNaN : graz(rng));
      }
    }
    t.add_ping(c[0], c[1], d[0], d[1], g[0], g[1]);
    for (int b = 0; b < 3; ++b) band[b].emplace_back();
    for (int s = 0; s < 2; ++s) {
      for (std::size_t k = 0; k < n[s]; ++k) {
        const float v[3] = {static_cast<float>(static_cast<std::uint8_t>(c[s][k])),
                            static_cast<float>(d[s][k]),
                            static_cast<float>(static_cast<double>(g[s][k]) * 180.0 / kPi)};
        for (int b = 0; b < 3; ++b)
          (s == 0 ? band[b].back().port : band[b].back().stbd).push_back(v[b]);
      }
    }
  }
  const char* names[3] = {"class", "object_id", "grazing_angle_deg"};
  GDALAllRegister();
  for (const TruthGrazing encoding : {TruthGrazing::float32, TruthGrazing::hundredths}) {
    const bool hundredths = encoding == TruthGrazing::hundredths;
    SCOPED_TRACE(hundredths ? "hundredths" : "float32");
    const std::string path = (dir / (hundredths ? "truth_i32.tif" : "truth_f32.tif")).string();
    t.set_grazing(encoding);
    t.write(path);
    const float pads[3] = {255.0f, -1.0f, kNaN};
    GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
    ASSERT_NE(ds, nullptr);
    int has_nodata = 0;
    const double nodata = ds->GetRasterBand(3)->GetNoDataValue(&has_nodata);
    EXPECT_TRUE(has_nodata);
    int has_scale = 0;
    const double scale = ds->GetRasterBand(3)->GetScale(&has_scale);
    EXPECT_EQ(ds->GetRasterBand(3)->GetOffset(nullptr), 0.0);
    if (hundredths) {
      EXPECT_EQ(ds->GetRasterBand(1)->GetRasterDataType(), GDT_Int32);
      EXPECT_EQ(nodata, -2147483648.0);
      EXPECT_TRUE(has_scale);
      EXPECT_EQ(scale, 0.01);
    } else {
      EXPECT_EQ(ds->GetRasterBand(1)->GetRasterDataType(), GDT_Float32);
      EXPECT_TRUE(std::isnan(nodata));
      EXPECT_EQ(scale, 1.0);
    }
    for (int b = 0; b < 3; ++b) {
      EXPECT_STREQ(ds->GetRasterBand(b + 1)->GetDescription(), names[b]);
      std::size_t cols = 0;
      const std::vector<float> want = expected_image(band[b], &cols, pads[b]);
      const test::Raster got = test::read_band(path, b + 1);
      ASSERT_EQ(static_cast<std::size_t>(got.cols), cols);
      ASSERT_EQ(static_cast<std::size_t>(got.rows), band[b].size());
      ASSERT_EQ(got.data.size(), want.size());
      std::size_t bad = 0;
      double worst_deg = 0.0;
      for (std::size_t i = 0; i < want.size(); ++i) {
        if (b < 2) {
          bad += !same_float(got.data[i], want[i]);
        } else if (std::isnan(want[i])) {
          bad += hundredths ? static_cast<double>(got.data[i]) != nodata : !std::isnan(got.data[i]);
        } else {
          const double deg = hundredths ? scale * static_cast<double>(got.data[i])
                                        : static_cast<double>(got.data[i]);
          const double err = std::abs(deg - static_cast<double>(want[i]));
          worst_deg = std::max(worst_deg, err);
          bad += err > (hundredths ? 0.005 + 1e-6 : 1e-4);
        }
      }
      EXPECT_EQ(bad, 0u) << names[b];
      if (b == 2 && hundredths) {
        EXPECT_GT(worst_deg, 0.004);  // the rounding is seen
      }
    }
    EXPECT_STREQ(ds->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE"), "ZSTD");
    EXPECT_STREQ(ds->GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE"), "BAND");
    int bx = 0, by = 0;
    ds->GetRasterBand(1)->GetBlockSize(&bx, &by);
    EXPECT_EQ(bx, 256);  // tiled
    GDALClose(ds);
  }
  fs::remove_all(dir);
}

// The PNG's text chunks as GDAL reads them back: every item, a later item of the same key
// replacing the earlier one (as GDAL's own PNG driver does); a key PNG cannot hold (over 79
// characters) is an error naming it and leaves no file.
TEST(Waterfall, PngTextChunksAreTheMetadataItems) {
  const auto dir = test::mosaic_temp_dir("wf_text");
  const std::vector<Ping> pings = random_pings(5, 4, 3);
  WaterfallOptions o;
  o.spool_dir = dir;
  o.metadata = {{"B_ITEM", "first"}, {"A_ITEM", "x = 1, y = 2"}, {"B_ITEM", "second"}};
  Waterfall wf(o);
  for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 0.0, 0.0);
  const std::string path = (dir / "t.png").string();
  wf.write(path);
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

// The spool file is never visible in its directory, is open (unnamed) while the waterfall
// lives, and is closed when it is destroyed, also after a write that threw; a missing spool
// directory is an error naming it.
TEST(Waterfall, SpoolFileIsUnnamedAndReleased) {
  const auto spool = test::mosaic_temp_dir("wf_spool");
  const auto out = test::mosaic_temp_dir("wf_spool_out");
  const std::vector<Ping> pings = random_pings(50, 40, 6);
  auto dir_is_empty = [&] { return fs::directory_iterator(spool) == fs::directory_iterator(); };
  {
    WaterfallOptions o;
    o.spool_dir = spool;
    Waterfall wf(o);
    TruthWaterfall t(spool);
    const std::vector<SampleClass> c(10, SampleClass::seabed);
    const std::vector<std::int32_t> id(10, 0);
    const std::vector<float> g(10, 0.5f);
    for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 0.0, 0.0);
    t.add_ping(c, c, id, id, g, g);
    EXPECT_TRUE(dir_is_empty());
    const std::vector<std::string> open = open_files_in(spool);
    ASSERT_EQ(open.size(), 2u);
    for (const std::string& f : open) EXPECT_NE(f.find(" (deleted)"), std::string::npos) << f;
    wf.write((out / "w.png").string());
    t.write((out / "t.tif").string());
    EXPECT_TRUE(dir_is_empty());
    // Writes that throw: an existing output, a bad extension, a missing directory.
    EXPECT_THROW(wf.write((out / "w.png").string()), FormatError);
    EXPECT_THROW(wf.write((out / "w.jpg").string()), InputError);
    EXPECT_THROW(t.write((out / "t.tif").string()), FormatError);
    EXPECT_THROW(t.write((out / "missing" / "t.tif").string()), FormatError);
    EXPECT_TRUE(dir_is_empty());
    // Still readable after the writes (each write reads the spool from the start).
    EXPECT_EQ(wf.image().size(), wf.rows() * wf.cols());
    wf.write((out / "w2.tif").string());
  }
  EXPECT_TRUE(open_files_in(spool).empty());
  EXPECT_TRUE(dir_is_empty());
  std::vector<std::string> outputs;
  for (const auto& e : fs::directory_iterator(out)) outputs.push_back(e.path().filename());
  std::sort(outputs.begin(), outputs.end());
  EXPECT_EQ(outputs, (std::vector<std::string>{"t.tif", "w.png", "w2.tif"}));
  WaterfallOptions o;
  o.spool_dir = spool / "missing";
  try {
    Waterfall wf(o);
    ADD_FAILURE() << "no error for a missing spool directory";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find((spool / "missing").string()), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(TruthWaterfall(spool / "missing"), FormatError);
  fs::remove_all(spool);
  fs::remove_all(out);
}

/// Along-track decimation computed directly from the full image: row k the mean of rows
/// k n .. k n + n - 1 (the last row what is left), pixel by pixel over the finite values (NaN if
/// none), summed in double in ping order.
std::vector<float> decimated(const std::vector<float>& img, std::size_t cols, std::size_t n) {
  const std::size_t rows = img.size() / cols;
  const std::size_t out_rows = (rows + n - 1) / n;
  std::vector<float> out(out_rows * cols, kNaN);
  for (std::size_t k = 0; k < out_rows; ++k) {
    for (std::size_t c = 0; c < cols; ++c) {
      double sum = 0.0;
      int count = 0;
      for (std::size_t r = k * n; r < std::min(rows, (k + 1) * n); ++r) {
        const float v = img[r * cols + c];
        if (std::isnan(v)) continue;
        sum += static_cast<double>(v);
        ++count;
      }
      if (count > 0) out[k * cols + c] = static_cast<float>(sum / count);
    }
  }
  return out;
}

// A line longer than max_pixels allows is not refused: the image is decimated along track,
// ceil(pings / N) rows for the smallest N that fits, each row the mean of N pings.
TEST(Waterfall, LongLineIsDecimatedAlongTrackToFitMaxPixels) {
  const auto dir = test::mosaic_temp_dir("wf_decimate");
  const std::vector<Ping> pings = random_pings(1003, 32, 5);
  std::size_t cols = 0;
  const std::vector<float> full = expected_image(pings, &cols, kNaN);
  ASSERT_EQ(cols, 64u);
  WaterfallOptions o;
  o.max_pixels = 64 * 100;  // room for 100 rows: 1003 pings need 11 per row -> 92 rows
  o.colormap = Colormap::grey;
  o.fixed_db = true;
  o.lo_db = -10.0;
  o.hi_db = 10.0;
  o.spool_dir = dir;
  Waterfall wf(o);
  for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 0.0, 0.0);
  EXPECT_EQ(wf.rows(), 1003u);
  EXPECT_EQ(wf.pings_per_row(), 11u);
  EXPECT_EQ(wf.image_rows(), 92u);  // ceil(1003 / 11)
  const std::vector<float> want = decimated(full, cols, 11);
  const std::vector<float> got = wf.image();
  ASSERT_EQ(got.size(), want.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < got.size(); ++i) differ += same_float(got[i], want[i]) ? 0 : 1;
  EXPECT_EQ(differ, 0u);
  // The written image holds those rows' colours.
  const std::string path = (dir / "long.png").string();
  wf.write(path);
  int c = 0, r = 0;
  std::string driver;
  const std::vector<std::uint8_t> bytes = read_bytes(path, &c, &r, &driver);
  EXPECT_EQ(static_cast<std::size_t>(c), cols);
  EXPECT_EQ(r, 92);
  EXPECT_EQ(bytes, colourise(want, DisplayRange{-10.0, 10.0}, Colormap::grey));
  fs::remove_all(dir);
}

// Up to max_pixels nothing is decimated; a single row wider than max_pixels is refused.
TEST(Waterfall, MaxPixelsDecimatesOnlyWhenNeededAndBoundsTheRowWidth) {
  WaterfallOptions o;
  o.max_pixels = 100;
  Waterfall wf(o);
  const std::vector<float> side(10, 1.0f);
  for (int i = 0; i < 5; ++i) wf.add_ping(side, side, 0.0, 0.0);
  EXPECT_EQ(wf.pings_per_row(), 1u);  // 20 x 5 = 100 pixels: fits
  wf.add_ping(side, side, 0.0, 0.0);
  EXPECT_EQ(wf.pings_per_row(), 2u);  // 20 x 6 > 100: two pings per row, 3 rows
  EXPECT_EQ(wf.image_rows(), 3u);
  const std::vector<float> wide(51, 1.0f);
  try {
    wf.add_ping(wide, side, 0.0, 0.0);
    ADD_FAILURE() << "accepted a row of 102 pixels with max_pixels = 100";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ping 6: a row of 102 pixels exceeds max_pixels = 100"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(wf.rows(), 6u);
  EXPECT_EQ(wf.cols(), 20u);
}

// The linear display (output.display: linear, docs/paper-model.md): the colour of a sample is
// eq. (3) of the founding paper at I = sample / full scale, clamped to [0, 1].
TEST(Waterfall, LinearDisplayIsPaperEquationThreeOfSampleOverFullScale) {
  const auto dir = test::mosaic_temp_dir("wf_linear");
  const std::vector<float> port = {0.0f, 25.0f, 50.0f, 80.0f};
  const std::vector<float> stbd = {90.0f, 100.0f, 150.0f, kNaN};
  WaterfallOptions o;
  o.linear_full_scale = 100.0;
  o.spool_dir = dir;
  Waterfall wf(o);
  wf.add_ping(port, stbd, 0.0, 0.0);
  const std::string path = (dir / "linear.tif").string();
  wf.write(path);
  int c = 0, r = 0;
  std::string driver;
  const std::vector<std::uint8_t> bytes = read_bytes(path, &c, &r, &driver);
  ASSERT_EQ(c, 8);
  ASSERT_EQ(r, 1);
  // Columns: port far -> near, then starboard near -> far; eq. (3) written out here.
  const double level[8] = {0.8, 0.5, 0.25, 0.0, 0.9, 1.0, 1.0, -1.0};
  for (int i = 0; i < 8; ++i) {
    const double v = level[i];
    double want[3] = {0.0, 0.0, 0.0};  // NaN: black
    if (v >= 0.8) {
      want[0] = 255.0;
      want[1] = 255.0 * (1.883 * v - 0.883);
      want[2] = 255.0 * (-1.99 * v + 1.99);
    } else if (v >= 0.0) {
      want[0] = 255.0 * 1.25 * v;
      want[1] = 255.0 * 0.7812 * v;
      want[2] = 255.0 * 0.4975 * v;
    }
    for (int b = 0; b < 3; ++b) {
      EXPECT_NEAR(bytes[static_cast<std::size_t>(b * 8 + i)], want[b], 0.5 + 1e-9)
          << "column " << i << " band " << b;
    }
  }
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  ASSERT_NE(ds, nullptr);
  EXPECT_NE(
      std::string(ds->GetMetadataItem("SONARSYNTH_DISPLAY_SCALE")).find("linear: value / 100"),
      std::string::npos);
  GDALClose(ds);
  o.linear_full_scale = -1.0;
  EXPECT_THROW(o.validate(), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
