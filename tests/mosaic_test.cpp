// SPDX-License-Identifier: MIT
// Mosaic: georeferencing accuracy against independent geodesics, linear averaging, slant->ground
// on a bathymetry grid, GeoTIFF conventions, the real Marine Sonic file.
#include "sonarsynth/mosaic.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>

#include "mosaic_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/formats/products/xtf_mosaic.hpp"

namespace sonarsynth {
namespace {

using test::LatLon;
using test::LineSpec;

constexpr double kPixel = 0.25;

/// Mosaics one XTF file into a GTiff and reads it back.
test::Raster mosaic_file(const std::filesystem::path& xtf, const std::filesystem::path& tif,
                         int* epsg = nullptr) {
  XtfMosaicOptions mo;
  mo.pixel_size_m = kPixel;
  const XtfMosaicResult r = mosaic_xtf({xtf}, mo);
  if (epsg) *epsg = r.frame.epsg();
  MosaicWriteOptions wo;
  wo.format = MosaicRasterFormat::gtiff;
  write_mosaic(tif.string(), r.frame, r.image, wo);
  return test::read_band(tif.string());
}

/// Distance (metres, projected) from `target` to the centre of the brightest pixel within 3 m.
double peak_distance_m(const test::Raster& img, LatLon target, int zone) {
  const auto [te, tn] = test::utm(target, zone);
  float best = -1.0f;
  double dist = 1e9;
  for (int r = 0; r < img.rows; ++r) {
    for (int c = 0; c < img.cols; ++c) {
      const double e = img.gt[0] + (c + 0.5) * img.gt[1];
      const double n = img.gt[3] + (r + 0.5) * img.gt[5];
      const double d = std::hypot(e - te, n - tn);
      const float v = img.data[static_cast<std::size_t>(r) * static_cast<std::size_t>(img.cols) +
                               static_cast<std::size_t>(c)];
      if (d < 3.0 && v > best) {
        best = v;
        dist = d;
      }
    }
  }
  EXPECT_GT(best, 100.0f) << "no bright target near the expected position";
  return dist;
}

struct GeoCase {
  const char* name;
  LatLon start;
  double heading_deg;
  int zone;
  int epsg;
};

class MosaicGeoreferencing : public ::testing::TestWithParam<GeoCase> {};

// A point target (a bright sample at slant range r on starboard in one ping) lands at ground
// range sqrt(r^2 - A^2) at right angles to the fish heading (true, so the meridian convergence
// must be applied in the grid), within one pixel; an opposite line over the same targets agrees.
TEST_P(MosaicGeoreferencing, PointTargetsWithinOnePixelOfGeodesicTruthOnOppositeLines) {
  const GeoCase& c = GetParam();
  const auto dir = test::mosaic_temp_dir(std::string("geo_") + c.name);
  LineSpec a;
  a.start = c.start;
  a.heading_deg = c.heading_deg;
  a.bright_pings = {50, 100, 150};
  const double y = test::bright_ground_range_m(a);
  LineSpec b = a;  // opposite heading, 2y to starboard of a, starting at a's end
  b.heading_deg = a.heading_deg + 180.0;
  b.start = test::direct(test::ping_position(a, a.pings - 1), a.heading_deg + 90.0, 2.0 * y);
  b.bright_pings = {a.pings - 1 - 50, a.pings - 1 - 100, a.pings - 1 - 150};  // abeam the same
  test::write_line(dir / "a.xtf", a);
  test::write_line(dir / "b.xtf", b);
  int epsg_a = 0, epsg_b = 0;
  const test::Raster ma = mosaic_file(dir / "a.xtf", dir / "a.tif", &epsg_a);
  const test::Raster mb = mosaic_file(dir / "b.xtf", dir / "b.tif", &epsg_b);
  EXPECT_EQ(epsg_a, c.epsg);
  EXPECT_EQ(epsg_b, c.epsg);
  for (int ping : {50, 100, 150}) {
    const LatLon fish = test::ping_position(a, ping);
    const LatLon target = test::direct(fish, a.heading_deg + 90.0, y);
    const double da = peak_distance_m(ma, target, c.zone);
    const double db = peak_distance_m(mb, target, c.zone);
    EXPECT_LE(da, kPixel) << "line a, ping " << ping;
    EXPECT_LE(db, kPixel) << "line b over ping " << ping;
  }
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Places, MosaicGeoreferencing,
    ::testing::Values(GeoCase{"north", {48.4456, -68.8281}, 33.0, 19, 32619},
                      GeoCase{"south", {-33.9, 18.4}, 33.0, 34, 32734},
                      // Fish 30 m west of the 18 E zone edge heading east: data straddle it.
                      GeoCase{"zone_edge", {-33.9, 17.99968}, 90.0, 33, 32733}),
    [](const auto& p) { return std::string(p.param.name); });

// The same check in the core, with a known pitch: the footprint moves A tan(pitch) ahead.
TEST(MosaicGrid, PitchShiftsTheGroundLineAheadByAltitudeTanPitch) {
  const GridGeometry g = MosaicGrid::geometry_covering({-60, -60}, {60, 60}, 0.1);
  MosaicOptions o;
  o.rule = MosaicRule::max;
  o.along_track_fill = false;
  MosaicGrid grid(g, o);
  std::vector<float> stbd(500, 1.0f), port;
  stbd[299] = 1000.0f;
  MosaicPing p;
  p.heading_grid_rad = 0.0;  // north: starboard is +x
  p.altitude_m = 10.0;
  p.pitch_rad = rad_from_deg(10.0);
  p.slant_range_m = 50.0;
  p.starboard = stbd;
  grid.add(p);
  const MosaicImage img = grid.finish();
  const double x = MosaicGrid::flat_ground_range_m(29.95, 10.0);
  const double y = 10.0 * std::tan(rad_from_deg(10.0));
  const auto col = static_cast<std::size_t>(std::floor(g.col_of_x(x) + 0.5));
  const auto row = static_cast<std::size_t>(std::floor(g.row_of_y(y) + 0.5));
  EXPECT_EQ(img.intensity[row * g.cols + col], 1000.0f);
}

// Against a bathymetry grid: a seabed sloping up to starboard (z = z0 + m x) places the sample
// where y^2 + (zs - z0 - m y)^2 = r^2 (analytic), not at the flat-bottom sqrt(r^2 - A^2).
TEST(MosaicGrid, BathymetrySlopeMatchesAnalyticIntersection) {
  const double m = std::tan(rad_from_deg(10.0));
  const double z0 = -20.0, zs = -10.0;
  GridGeometry bg;
  bg.x0_m = -60;
  bg.y0_m = 60;
  bg.dx_m = 1.0;
  bg.dy_m = -1.0;
  bg.cols = 121;
  bg.rows = 121;
  std::vector<float> h(bg.size());
  for (std::size_t r = 0; r < bg.rows; ++r) {
    for (std::size_t c = 0; c < bg.cols; ++c) {
      h[r * bg.cols + c] = static_cast<float>(z0 + m * bg.x_of_col(static_cast<double>(c)));
    }
  }
  const HeightGrid bathy(bg, h);
  const GridGeometry g = MosaicGrid::geometry_covering({-50, -5}, {50, 5}, 0.1);
  MosaicOptions o;
  o.rule = MosaicRule::max;
  MosaicGrid grid(g, o, &bathy);
  std::vector<float> stbd(500, 1.0f);
  stbd[299] = 1000.0f;
  MosaicPing p;
  p.altitude_m = zs - z0;
  p.sensor_z_m = zs;
  p.slant_range_m = 50.0;
  p.starboard = stbd;
  grid.add(p);
  const MosaicImage img = grid.finish();
  const double r = 29.95, hh = zs - z0;
  const double y =
      (m * hh + std::sqrt(m * m * hh * hh - (1 + m * m) * (hh * hh - r * r))) / (1 + m * m);
  const double flat = MosaicGrid::flat_ground_range_m(r, hh);
  ASSERT_GT(std::abs(flat - y), 5 * g.dx_m);  // the test can tell the two corrections apart
  const auto row = static_cast<std::size_t>(std::floor(g.row_of_y(0.0) + 0.5));
  double peak_x = 0;
  float best = 0;
  for (std::size_t c = 0; c < g.cols; ++c) {
    if (img.intensity[row * g.cols + c] > best) {
      best = img.intensity[row * g.cols + c];
      peak_x = g.x_of_col(static_cast<double>(c));
    }
  }
  EXPECT_EQ(best, 1000.0f);
  EXPECT_NEAR(peak_x, y, g.dx_m);
}

// The nadir gap: on a flat bottom 10 m below with 0.1 m bins, the first seabed sample (centre
// 10.05 m) lands 1.001 m from nadir; the bin holding the altitude covers the seabed from nadir,
// so with nadir_fill the pixels in between take that sample's value, and without it they are
// nodata.
TEST(MosaicGrid, NadirGapTakesTheFirstSeabedSample) {
  const GridGeometry g = MosaicGrid::geometry_covering({-5, -1}, {5, 11}, 0.1);
  const double first_g = MosaicGrid::flat_ground_range_m(10.05, 10.0);
  ASSERT_NEAR(first_g, 1.0012, 1e-4);
  for (const bool fill : {true, false}) {
    MosaicOptions o;
    o.nadir_fill = fill;
    MosaicGrid grid(g, o);
    const std::vector<float> port(500, 1.0f), stbd(500, 2.0f);
    for (int i = 0; i <= 200; ++i)
      grid.add(test::level_ping({0.0, 0.05 * i}, 10.0, 50.0, port, stbd));
    const MosaicImage img = grid.finish();
    const auto row = static_cast<std::size_t>(std::floor(g.row_of_y(5.0) + 0.5));
    for (std::size_t c = 0; c < g.cols; ++c) {
      const double x = g.x_of_col(static_cast<double>(c));
      const float v = img.intensity[row * g.cols + c];
      if (std::abs(x) > first_g + 0.1) {
        EXPECT_EQ(v, x < 0 ? 1.0f : 2.0f) << "x = " << x;
      } else if (!fill && std::abs(x) < first_g - 0.1) {
        EXPECT_TRUE(std::isnan(v)) << "x = " << x << ": " << v;
      } else if (fill && std::abs(x) > 0.06) {
        EXPECT_EQ(v, x < 0 ? 1.0f : 2.0f) << "x = " << x;
      } else if (fill) {
        EXPECT_TRUE(v >= 1.0f && v <= 2.0f) << "x = " << x << ": " << v;
      }
    }
  }
}

// Single-look speckle (exponential intensity, mean mu): the mosaic mean equals mu. Averaging
// the same samples in dB would be 2.51 dB low, far outside the tolerance used here.
TEST(MosaicGrid, AveragesLinearIntensityWithoutSpeckleBias) {
  const double mu = 100.0;
  const GridGeometry g = MosaicGrid::geometry_covering({-50, -1}, {50, 21}, 1.0);
  MosaicGrid grid(g, MosaicOptions{});
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> speckle(1.0 / mu);
  std::vector<float> port(500), stbd(500);
  double sum_db = 0.0;
  std::size_t n_db = 0;
  for (int i = 0; i < 400; ++i) {
    for (auto* side : {&port, &stbd}) {
      for (float& v : *side) {
        v = static_cast<float>(speckle(rng));
        sum_db += 10.0 * std::log10(static_cast<double>(v));
        ++n_db;
      }
    }
    grid.add(test::level_ping({0.0, 0.05 * i}, 5.0, 50.0, port, stbd));
  }
  const MosaicImage img = grid.finish();
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < img.intensity.size(); ++i) {
    if (img.count[i] >= 50) {
      sum += img.intensity[i];
      ++n;
    }
  }
  ASSERT_GT(n, 1000u);
  const double mosaic_db = 10.0 * std::log10(sum / static_cast<double>(n));
  const double truth_db = 10.0 * std::log10(mu);
  EXPECT_NEAR(mosaic_db, truth_db, 0.1);
  // The dB-domain average of the same samples is 2.51 dB low (Euler-Mascheroni: 10 gamma/ln 10).
  const double db_average = sum_db / static_cast<double>(n_db);
  EXPECT_NEAR(truth_db - db_average, 2.507, 0.1);
}

TEST(MosaicGrid, MaxAndNearestRules) {
  const GridGeometry g = MosaicGrid::geometry_covering({-20, -20}, {20, 20}, 1.0);
  for (MosaicRule rule : {MosaicRule::max, MosaicRule::nearest}) {
    MosaicOptions o;
    o.rule = rule;
    o.along_track_fill = false;
    MosaicGrid grid(g, o);
    // Two pings heading north at x = 0 and x = 10: the pixel at x = 5 is seen at ground range
    // 5 (stbd of the first, value 1) and 5 (port of the second, value 2) -> max 2, nearest 1
    // (first on ties); at x = 8 ground range 8 (value 1) and 2 (value 2).
    std::vector<float> ones(200, 1.0f), twos(200, 2.0f), none;
    const MosaicPing a = test::level_ping({0.0, 0.0}, 1.0, 20.0, {}, ones);
    grid.add(a);
    MosaicPing b = a;
    b.sensor_xy_m = {10.0, 0.0};
    b.starboard = none;
    b.port = twos;
    grid.add(b);
    const MosaicImage img = grid.finish();
    const auto row = static_cast<std::size_t>(std::floor(g.row_of_y(0.0) + 0.5));
    const auto px = [&](double x) {
      return img
          .intensity[row * g.cols + static_cast<std::size_t>(std::floor(g.col_of_x(x) + 0.5))];
    };
    if (rule == MosaicRule::max) {
      EXPECT_EQ(px(8.0), 2.0f);
      EXPECT_EQ(px(15.0), 1.0f);
    } else {
      EXPECT_EQ(px(8.0), 2.0f);  // 2 m from b's nadir, 8 m from a's
      EXPECT_EQ(px(3.0), 1.0f);  // 3 m from a's nadir, 7 m from b's
    }
  }
}

TEST(MosaicGrid, LabelsTakeTheNearestToNadir) {
  const GridGeometry g = MosaicGrid::geometry_covering({-20, -20}, {20, 20}, 1.0);
  MosaicGrid grid(g, MosaicOptions{});
  std::vector<float> v(200, 1.0f);
  std::vector<std::int32_t> la(200, 7), lb(200, 9);
  MosaicPing a = test::level_ping({0.0, 0.0}, 1.0, 20.0, {}, v);
  a.starboard_labels = la;
  grid.add(a);
  grid.break_line();
  MosaicPing b = a;
  b.sensor_xy_m = {10.0, 0.0};
  b.starboard = {};
  b.starboard_labels = {};
  b.port = v;
  b.port_labels = lb;
  grid.add(b);
  const MosaicImage img = grid.finish();
  ASSERT_EQ(img.labels.size(), g.size());
  const auto row = static_cast<std::size_t>(std::floor(g.row_of_y(0.0) + 0.5));
  EXPECT_EQ(img.labels[row * g.cols + static_cast<std::size_t>(g.col_of_x(3.0) + 0.5)], 7);
  EXPECT_EQ(img.labels[row * g.cols + static_cast<std::size_t>(g.col_of_x(8.0) + 0.5)], 9);
}

// finish() && computes the image in the buffer of the sums (or values) to save memory; it must
// give the bits of the copying finish() const&, which divides into a fresh buffer, for every rule.
TEST(MosaicGrid, TheMovingFinishGivesTheCopyingFinishBitForBit) {
  const GridGeometry g = MosaicGrid::geometry_covering({-40, -10}, {40, 30}, 0.5);
  for (MosaicRule rule : {MosaicRule::weighted_mean, MosaicRule::max, MosaicRule::nearest}) {
    MosaicOptions o;
    o.rule = rule;
    MosaicGrid grid(g, o);
    std::mt19937_64 rng(11);
    std::exponential_distribution<float> speckle(0.01f);
    std::vector<float> port(300), stbd(300);
    std::vector<std::int32_t> labels(300);
    for (int i = 0; i < 60; ++i) {
      for (auto* side : {&port, &stbd}) {
        for (float& v : *side) v = speckle(rng);
      }
      for (std::size_t k = 0; k < labels.size(); ++k) labels[k] = static_cast<std::int32_t>(k % 5);
      MosaicPing p;
      p.sensor_xy_m = {0.3 * i, 0.25 * i};
      p.heading_grid_rad = 0.2;
      p.altitude_m = 4.0;
      p.slant_range_m = 30.0;
      p.port = port;
      p.starboard = stbd;
      p.port_labels = labels;
      grid.add(p);
    }
    const MosaicImage copied = grid.finish();
    const MosaicImage moved = std::move(grid).finish();
    ASSERT_EQ(moved.intensity.size(), g.size());
    std::size_t empty = 0;
    for (std::size_t i = 0; i < g.size(); ++i) {
      std::uint32_t a = 0, b = 0;
      std::memcpy(&a, &copied.intensity[i], sizeof a);
      std::memcpy(&b, &moved.intensity[i], sizeof b);
      ASSERT_EQ(a, b) << "pixel " << i << ", rule " << static_cast<int>(rule);
      if (copied.count[i] == 0) {
        ++empty;
        EXPECT_TRUE(std::isnan(moved.intensity[i]));
      }
    }
    EXPECT_GT(empty, 0u);  // the scene has empty pixels (NaN) as well as gridded ones
    EXPECT_LT(empty, g.size());
    EXPECT_EQ(copied.count, moved.count);
    EXPECT_EQ(copied.labels, moved.labels);
  }
}

TEST(MosaicGrid, RejectsBadOptionsAndPings) {
  MosaicOptions o;
  o.taper_fraction = 0.7;
  EXPECT_THROW(o.validate(), InputError);
  const GridGeometry g = MosaicGrid::geometry_covering({0, 0}, {10, 10}, 1.0);
  MosaicGrid grid(g, MosaicOptions{});
  MosaicPing p;
  p.slant_range_m = 10.0;
  EXPECT_THROW(grid.add(p), InputError);  // altitude 0 on a flat bottom
}

// The real Iver2 / Marine Sonic file: ping 0 has zero navigation and is skipped and counted;
// the mosaic is in UTM 19N around lon -68.83, lat 48.45 and covers every fix of the file.
TEST(XtfMosaic, RealMarineSonicFileLandsInPlace) {
  const auto dir = test::mosaic_temp_dir("iver2");
  const std::filesystem::path xtf = SONARSYNTH_TEST_DATA_DIR "/xtf/scotsman-iver2.xtf";
  const XtfMosaicResult r = mosaic_xtf({xtf}, XtfMosaicOptions{});
  EXPECT_EQ(r.pings, 461u);
  EXPECT_EQ(r.pings_no_navigation, 1u);
  EXPECT_EQ(r.pings_gridded, 460u);
  EXPECT_EQ(r.frame.epsg(), 32619);
  std::size_t finite = 0;
  for (float v : r.image.intensity) {
    if (std::isfinite(v)) {
      ++finite;
      EXPECT_GE(v, 0.0f);
    }
  }
  EXPECT_GT(finite, r.image.intensity.size() / 10);
  MosaicWriteOptions wo;
  wo.count_band = true;
  wo.rgb_path = (dir / "m_rgb.tif").string();
  const std::string tif = (dir / "m.tif").string();
  write_mosaic(tif, r.frame, r.image, wo);
  const test::Raster img = test::read_band(tif);
  ASSERT_FALSE(img.data.empty());
  // The file's navigation box (corners) lies inside the raster, which is around (-68.83, 48.45).
  for (LatLon p : {LatLon{48.44545, -68.82834}, LatLon{48.44586, -68.82794}}) {
    const auto [e, n] = test::utm(p, 19);
    EXPECT_GT(e, img.gt[0]);
    EXPECT_LT(e, img.gt[0] + img.cols * img.gt[1]);
    EXPECT_LT(n, img.gt[3]);
    EXPECT_GT(n, img.gt[3] + img.rows * img.gt[5]);
  }
  double lat = 0, lon = 0;
  int zone = 0;
  bool northp = false;
  const double ce = img.gt[0] + 0.5 * img.cols * img.gt[1];
  const double cn = img.gt[3] + 0.5 * img.rows * img.gt[5];
  GeographicLib::UTMUPS::Reverse(19, true, ce, cn, lat, lon);
  (void)zone;
  (void)northp;
  EXPECT_NEAR(lon, -68.83, 0.005);
  EXPECT_NEAR(lat, 48.45, 0.005);
  // Display copy: RGBA with alpha 0 exactly where the mosaic has no data.
  const test::Raster alpha = test::read_band(wo.rgb_path, 4);
  ASSERT_EQ(alpha.data.size(), img.data.size());
  for (std::size_t i = 0; i < img.data.size(); ++i) {
    ASSERT_EQ(alpha.data[i] == 0.0f, std::isnan(img.data[i])) << "pixel " << i;
  }
  std::filesystem::remove_all(dir);
}

// GeoTIFF conventions, checked through GDAL: EPSG, Area pixels with the origin at the pixel
// corner, NaN nodata, band description, overviews; COG layout by default.
TEST(MosaicWriter, GeoTiffConventions) {
  const auto dir = test::mosaic_temp_dir("conventions");
  const GeoFrame frame = GeoFrame::around({rad_from_deg(-33.9), rad_from_deg(18.4), 0.0});
  const GridGeometry g = MosaicGrid::geometry_covering({-40.0, -30.0}, {100.0, 70.0}, 0.25);
  MosaicImage img;
  img.geometry = g;
  img.intensity.assign(g.size(), 5.0f);
  img.intensity[0] = std::nanf("");
  img.count.assign(g.size(), 3);
  for (MosaicRasterFormat f : {MosaicRasterFormat::cog, MosaicRasterFormat::gtiff}) {
    const std::string path = (dir / (f == MosaicRasterFormat::cog ? "c.tif" : "g.tif")).string();
    MosaicWriteOptions wo;
    wo.format = f;
    wo.count_band = true;
    wo.metadata = {{"SONARSYNTH_SEED", "77"}};
    wo.rgb_path = path.substr(0, path.size() - 4) + "_rgb.tif";
    write_mosaic(path, frame, img, wo);
    GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
    ASSERT_NE(ds, nullptr);
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    ASSERT_NE(srs, nullptr);
    EXPECT_STREQ(srs->GetAuthorityCode(nullptr), "32734");
    EXPECT_STREQ(ds->GetMetadataItem("AREA_OR_POINT"), "Area");
    double gt[6];
    ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
    // Pixel edges on multiples of the pixel size (local frame), origin = top-left corner.
    EXPECT_DOUBLE_EQ(gt[0], frame.origin_easting_m() - 40.0);
    EXPECT_DOUBLE_EQ(gt[3], frame.origin_northing_m() + 70.0);
    EXPECT_DOUBLE_EQ(gt[1], 0.25);
    EXPECT_DOUBLE_EQ(gt[5], -0.25);
    EXPECT_EQ(ds->GetRasterXSize(), 560);
    EXPECT_EQ(ds->GetRasterYSize(), 400);
    GDALRasterBand* b = ds->GetRasterBand(1);
    int has_nodata = 0;
    EXPECT_TRUE(std::isnan(b->GetNoDataValue(&has_nodata)));
    EXPECT_TRUE(has_nodata);
    EXPECT_STREQ(b->GetDescription(), "backscatter (the XTF sample values, gridded linearly)");
    EXPECT_STREQ(b->GetUnitType(), "counts");
    EXPECT_STREQ(ds->GetRasterBand(2)->GetDescription(), "count");
    EXPECT_STREQ(ds->GetMetadataItem("SONARSYNTH_SEED"), "77");  // the caller's items
    EXPECT_STREQ(ds->GetMetadataItem("SONARSYNTH_QUANTITY"),
                 "backscatter (the XTF sample values, gridded linearly)");
    EXPECT_STREQ(ds->GetMetadataItem("SONARSYNTH_UNITS"), "counts");
    {
      // The display copy: the caller's items, averaged overviews (down to < 256 pixels).
      GDALDataset* rgb = GDALDataset::Open(wo.rgb_path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
      ASSERT_NE(rgb, nullptr);
      EXPECT_STREQ(rgb->GetMetadataItem("SONARSYNTH_SEED"), "77");
      for (int k = 1; k <= 4; ++k) {
        EXPECT_GE(rgb->GetRasterBand(k)->GetOverviewCount(), 1) << k;
      }
      std::uint8_t px[4] = {};  // an overview pixel of the constant: its colour, opaque
      std::uint8_t full[4] = {};
      for (int k = 0; k < 4; ++k) {
        GDALRasterBand* band = rgb->GetRasterBand(k + 1);
        ASSERT_EQ(band->GetOverview(0)->RasterIO(GF_Read, 10, 10, 1, 1, &px[k], 1, 1, GDT_Byte, 0,
                                                 0, nullptr),
                  CE_None);
        ASSERT_EQ(band->RasterIO(GF_Read, 20, 20, 1, 1, &full[k], 1, 1, GDT_Byte, 0, 0, nullptr),
                  CE_None);
        EXPECT_EQ(px[k], full[k]) << k;
      }
      EXPECT_EQ(px[3], 255);
      GDALClose(rgb);
    }
    EXPECT_GE(b->GetOverviewCount(), 1);
    // COG: GDAL reports the layout; GTiff: a plain tiled GeoTIFF (image, then its overviews),
    // the display copy too.
    for (const std::string& file : {path, wo.rgb_path}) {
      GDALDataset* t = GDALDataset::Open(file.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
      ASSERT_NE(t, nullptr);
      const char* layout = t->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
      if (f == MosaicRasterFormat::cog) {
        ASSERT_NE(layout, nullptr) << file;
        EXPECT_STREQ(layout, "COG") << file;
      } else {
        EXPECT_EQ(layout, nullptr) << file << ": " << layout;
        int bx = 0, by = 0;
        t->GetRasterBand(1)->GetBlockSize(&bx, &by);
        EXPECT_LT(bx, t->GetRasterXSize()) << file << ": tiled, not strips of the full width";
        EXPECT_EQ(bx, by) << file;
      }
      GDALClose(t);
    }
    // Averaged overview of a constant: the constant (linear average, nodata ignored).
    float ov = 0.0f;
    ASSERT_EQ(
        b->GetOverview(0)->RasterIO(GF_Read, 10, 10, 1, 1, &ov, 1, 1, GDT_Float32, 0, 0, nullptr),
        CE_None);
    EXPECT_FLOAT_EQ(ov, 5.0f);
    GDALClose(ds);
  }
  // An existing output without overwrite: error, and the file is untouched.
  const auto before = std::filesystem::file_size(dir / "c.tif");
  EXPECT_THROW(write_mosaic((dir / "c.tif").string(), frame, img, {}), FormatError);
  EXPECT_EQ(std::filesystem::file_size(dir / "c.tif"), before);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth

namespace sonarsynth {
namespace {

// Truth waterfall: the same column layout as the intensity waterfall (port far -> near |
// starboard near -> far), padding 255 / -1 / NaN for a shorter side.
TEST(TruthWaterfall, RoundTripsClassIdAndGrazing) {
  const auto dir = test::mosaic_temp_dir("truth_wf");
  TruthWaterfall t;
  const std::vector<SampleClass> pc{SampleClass::water_column, SampleClass::seabed,
                                    SampleClass::object};
  const std::vector<SampleClass> sc{SampleClass::water_column, SampleClass::shadow};
  const std::vector<std::int32_t> pid{-1, 0, 42}, sid{-1, -1};
  const std::vector<float> pg{std::nanf(""), 0.5f, 0.25f}, sg{std::nanf(""), std::nanf("")};
  t.add_ping(pc, sc, pid, sid, pg, sg);
  EXPECT_THROW(t.add_ping(pc, sc, sid, sid, pg, sg), InputError);
  const std::string path = (dir / "truth.tif").string();
  t.write(path);
  const test::Raster cls = test::read_band(path, 1);
  const test::Raster id = test::read_band(path, 2);
  const test::Raster graz = test::read_band(path, 3);
  ASSERT_EQ(cls.cols, 6);
  ASSERT_EQ(cls.rows, 1);
  // Port near (index 0) is column 2, far (index 2) column 0; starboard near is column 3.
  EXPECT_EQ(cls.data[0], static_cast<float>(SampleClass::object));
  EXPECT_EQ(cls.data[1], static_cast<float>(SampleClass::seabed));
  EXPECT_EQ(cls.data[2], static_cast<float>(SampleClass::water_column));
  EXPECT_EQ(cls.data[4], static_cast<float>(SampleClass::shadow));
  EXPECT_EQ(cls.data[5], 255.0f);
  EXPECT_EQ(id.data[0], 42.0f);
  EXPECT_EQ(id.data[5], -1.0f);
  // Hundredths of a degree (band scale 0.01), nodata INT32_MIN.
  EXPECT_NEAR(0.01 * graz.data[1], 0.5 * 180.0 / kPi, 0.005);
  EXPECT_EQ(graz.data[1], 2865.0f);  // 28.6479 deg
  EXPECT_EQ(graz.data[5], -2147483648.0f);
  EXPECT_THROW(t.write(path), FormatError);  // exists, no overwrite
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
