// SPDX-License-Identifier: MIT
// Waterfall rows: the truth waterfall keeps its layout and padding, the spool file never shows up
// and is released with its owner, a long line is decimated along track to fit max_pixels, and
// the linear display is the founding paper's equation 3.
#include <gdal_priv.h>
#include <gtest/gtest.h>

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
#include "sonarsynth/formats/products/waterfall.hpp"
#include "waterfall_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using namespace test;  // NOLINT: the shared helpers of waterfall_test_util.hpp

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
  const auto [pings, cols, full] = random_image(1003, 32, 5);
  ASSERT_EQ(cols, 64u);
  WaterfallOptions o;
  o.max_pixels = 64 * 100;  // room for 100 rows: 1003 pings need 11 per row -> 92 rows
  o.colormap = Colormap::grey;
  o.fixed_db = true;
  o.lo_db = -10.0;
  o.hi_db = 10.0;
  const Waterfall wf = waterfall_of(o, dir, pings);
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
