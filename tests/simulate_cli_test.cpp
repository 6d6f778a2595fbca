// SPDX-License-Identifier: MIT
// `sonarsynth simulate` end to end: every product exists and opens in GDAL with the right CRS
// and extent; objects placed at known lat/lon appear in the intensity and truth mosaics within
// one pixel; opposite lines agree; the effective configuration reproduces the run; bad input
// leaves nothing behind.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <utility>

#include "cli_test_util.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/render_side.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

// A flat seabed, one 1 m x 1 m x 0.1 m steel plate (low, so layover shifts it < 0.05 m) at a known
// position, two anti-parallel lines 12 m either side of it. Noise off, so the box's echo is the
// brightest thing in the mosaic.
constexpr double kLat = -33.8512, kLon = 151.2987;  // southern hemisphere: EPSG 32756
std::string scene_yaml(const std::string& lines) {
  return R"(
name: georef
seed: 4
bathymetry:
  generate: {centre: {lat_deg: -33.8510, lon_deg: 151.2990}, size_m: [120, 120], cell_m: 0.25, depth_m: 15}
objects:
  - {type: box, id: 9, position: {lat_deg: -33.8512, lon_deg: 151.2987}, size_m: [1.0, 1.0, 0.1], heading_deg: 0}
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 2.0
  altitude_m: 6
  lines:
)" + lines +
         R"(
sonar: {frequency_khz: 600, range_m: 30, samples: 600, tilt_deg: 15, horizontal_beam_deg: 0.3}
noise: {model: none}
)";
}

// Line waypoints 12 m north (eastward) or 12 m south (westward) of the box, in lat/lon.
std::string line(const char* name, double dlat_m, bool eastward) {
  const double dlat = dlat_m / 111000.0;
  const double dlon = 30.0 / (111000.0 * std::cos(kLat * kPi / 180.0));
  char buf[400];
  const double a = eastward ? -dlon : dlon;
  std::snprintf(buf, sizeof buf,
                "    - {name: %s, waypoints: [{lat_deg: %.8f, lon_deg: %.8f}, {lat_deg: %.8f, "
                "lon_deg: %.8f}]}\n",
                name, kLat + dlat, kLon + a, kLat + dlat, kLon - a);
  return buf;
}

struct Raster {
  int cols = 0, rows = 0;
  double gt[6] = {};
  std::string epsg;
  std::vector<double> band1;
};

Raster read_raster(const fs::path& p) {
  GDALAllRegister();
  Raster r;
  GDALDataset* ds = GDALDataset::Open(p.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return r;
  r.cols = ds->GetRasterXSize();
  r.rows = ds->GetRasterYSize();
  ds->GetGeoTransform(r.gt);
  if (const OGRSpatialReference* srs = ds->GetSpatialRef()) {
    const char* code = srs->GetAuthorityCode(nullptr);
    r.epsg = code ? code : "";
  }
  r.band1.resize(static_cast<std::size_t>(r.cols) * static_cast<std::size_t>(r.rows));
  if (ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, r.cols, r.rows, r.band1.data(), r.cols, r.rows,
                                     GDT_Float64, 0, 0) != CE_None) {
    r.band1.clear();
  }
  GDALClose(ds);
  return r;
}

// Easting/northing of the object's true position in its UTM zone (GeoFrame is GeographicLib).
Eigen::Vector2d true_en() {
  const Geodetic g{rad_from_deg(kLat), rad_from_deg(kLon), 0};
  const GeoFrame f(56, false, 0.0, 0.0);
  return f.projected_from_local(f.local_from_geodetic(g));
}

// Centre (E, N) of the pixels selected by `pick`, or NaN.
template <class F>
Eigen::Vector2d centroid(const Raster& r, F pick) {
  double se = 0, sn = 0, n = 0;
  for (int row = 0; row < r.rows; ++row) {
    for (int col = 0; col < r.cols; ++col) {
      if (pick(r.band1[static_cast<std::size_t>(row) * static_cast<std::size_t>(r.cols) +
                       static_cast<std::size_t>(col)])) {
        se += r.gt[0] + (col + 0.5) * r.gt[1];
        sn += r.gt[3] + (row + 0.5) * r.gt[5];
        n += 1;
      }
    }
  }
  return n > 0 ? Eigen::Vector2d(se / n, sn / n) : Eigen::Vector2d(NAN, NAN);
}

class SimulateCli : public test::ScratchDirTest {};

// The mosaic is the raw gridding here (output.mosaic, docs/scene-format.md): the test places the
// echo as stored. The default angle normalisation lifts the bins the beam pattern leaves nearly
// empty (a few counts after quantisation, without noise) to the survey's mean level, and those
// can then outshine the plate.
TEST_F(SimulateCli, ProductsExistOpenInGdalAndPutTheObjectWithinOnePixel) {
  const fs::path scene =
      write("s.yaml", scene_yaml(line("north", 12.0, true) + line("south", -12.0, false)) +
                          "output: {mosaic: {nadir: raw, gain_normalisation: off}}\n");
  const auto r = test::run_cli(
      "simulate " + scene.string() + " -o " + (dir_ / "out").string() + " -q --res 0.2", dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f :
       {"north.xtf", "south.xtf", "north_waterfall.png", "south_waterfall.png", "north_truth.tif",
        "south_truth.tif", "mosaic.tif", "mosaic_rgb.tif", "truth_mosaic.tif", "effective.yaml"}) {
    EXPECT_TRUE(fs::exists(dir_ / "out" / f)) << f;
  }
  // XTF: readable, one file per line, pings with navigation.
  xtf::Reader reader(dir_ / "out" / "north.xtf");
  xtf::Packet packet;
  int pings = 0;
  while (reader.next(packet))
    pings += packet.kind == xtf::PacketKind::kPing && packet.ping.nav_valid;
  // A ping every 2 m/s x (2 x 30 m / 1500 m/s) = 0.08 m over the line's length, both ends.
  const GeoFrame frame = GeoFrame::around({rad_from_deg(kLat), rad_from_deg(kLon), 0});
  const double dlon = 30.0 / (111000.0 * std::cos(kLat * kPi / 180.0));
  const double lat = kLat + 12.0 / 111000.0;
  const double len = (frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(kLon + dlon), 0}) -
                      frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(kLon - dlon), 0}))
                         .norm();
  EXPECT_EQ(pings, static_cast<int>(std::floor(len / 0.08)) + 1);
  const Raster mosaic = read_raster(dir_ / "out" / "mosaic.tif");
  const Raster truth = read_raster(dir_ / "out" / "truth_mosaic.tif");
  ASSERT_FALSE(mosaic.band1.empty());
  EXPECT_EQ(mosaic.epsg, "32756");
  EXPECT_EQ(truth.epsg, "32756");
  EXPECT_EQ(truth.cols, mosaic.cols);
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(truth.gt[i], mosaic.gt[i]);
  const Eigen::Vector2d en = true_en();
  // The extent contains the object and the lines.
  EXPECT_LT(mosaic.gt[0], en.x() - 25);
  EXPECT_GT(mosaic.gt[0] + mosaic.cols * mosaic.gt[1], en.x() + 25);
  // Truth mosaic: the pixels labelled 9 are centred on the box (1 m): within one pixel.
  const Eigen::Vector2d c_truth = centroid(truth, [](double v) { return v == 9.0; });
  EXPECT_LT((c_truth - en).norm(), 0.2) << c_truth.transpose() << " vs " << en.transpose();
  // Intensity mosaic: the brightest pixels (the box's top and near face) lie on the box.
  double vmax = 0;
  for (double v : mosaic.band1) {
    if (std::isfinite(v)) vmax = std::max(vmax, v);
  }
  const Eigen::Vector2d c_peak =
      centroid(mosaic, [&](double v) { return std::isfinite(v) && v > 0.5 * vmax; });
  EXPECT_LT((c_peak - en).cwiseAbs().maxCoeff(), 0.5 + 0.2)
      << c_peak.transpose() << " vs " << en.transpose();
}

// Every product says what it holds: the run's seed (given on the command line, overriding the
// scene's 4) and the scene's sonar (600 kHz, 30 m, 600 samples, tilt 15 deg, horizontal beam
// 0.3 deg) as metadata items, the version CMake gives the project, quantity, units, band
// descriptions and nodata; the display mosaic has overviews.
TEST_F(SimulateCli, ProductsCarryTheRunsMetadataAndSayWhatTheyHold) {
  const fs::path scene = write("s.yaml", scene_yaml(line("north", 12.0, true)));
  const auto r = test::run_cli("simulate " + scene.string() + " -o " + (dir_ / "out").string() +
                                   " -q --res 0.2 --seed 12345",
                               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  GDALAllRegister();
  const auto open = [&](const char* name) {
    return std::unique_ptr<GDALDataset>(
        GDALDataset::Open((dir_ / "out" / name).c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  };
  const auto item = [](GDALDataset& ds, const char* key) {
    const char* v = ds.GetMetadataItem(key);
    return std::string(v ? v : "(missing)");
  };
  const auto number = [&](GDALDataset& ds, const char* key) {
    const std::string v = item(ds, key);
    return v == "(missing)" ? std::nan("") : std::stod(v);
  };
  for (const char* name : {"mosaic.tif", "mosaic_rgb.tif", "truth_mosaic.tif", "north_truth.tif",
                           "north_waterfall.png"}) {
    SCOPED_TRACE(name);
    const auto ds = open(name);
    ASSERT_NE(ds, nullptr);
    EXPECT_EQ(item(*ds, "SONARSYNTH_SEED"), "12345");
    EXPECT_EQ(item(*ds, "SONARSYNTH_SCENE"), "georef");
    EXPECT_EQ(item(*ds, "SONARSYNTH_VERSION"), SONARSYNTH_PROJECT_VERSION);
    EXPECT_DOUBLE_EQ(number(*ds, "SONARSYNTH_SONAR_FREQUENCY_HZ"), 600e3);
    EXPECT_DOUBLE_EQ(number(*ds, "SONARSYNTH_SONAR_RANGE_M"), 30.0);
    EXPECT_DOUBLE_EQ(number(*ds, "SONARSYNTH_SONAR_SAMPLES_PER_SIDE"), 600.0);
    EXPECT_DOUBLE_EQ(number(*ds, "SONARSYNTH_SONAR_TILT_DEG"), 15.0);
    EXPECT_DOUBLE_EQ(number(*ds, "SONARSYNTH_SONAR_HORIZONTAL_BEAM_DEG"), 0.3);
    EXPECT_EQ(item(*ds, "SONARSYNTH_TVG"), "20 log10(R) + 2 x 1 alpha R");  // the default TVG
    EXPECT_TRUE(std::isfinite(number(*ds, "SONARSYNTH_GAIN_DB")));
    EXPECT_DOUBLE_EQ(number(*ds, "SONARSYNTH_FULL_SCALE"), 32767.0);  // u16 samples
    EXPECT_NE(item(*ds, "SONARSYNTH_QUANTITY"), "(missing)");
    EXPECT_EQ(item(*ds, "SONARSYNTH_SAMPLE_QUANTITY"), "amplitude");  // the default
    EXPECT_EQ(item(*ds, "SONARSYNTH_DETECTOR"), "3 looks, max");
    EXPECT_NE(item(*ds, "SONARSYNTH_UNITS"), "(missing)");
    EXPECT_NE(item(*ds, "SONARSYNTH_NODATA"), "(missing)");
  }
  // The float mosaic: the samples' amplitude (the default quantity) gridded linearly, in XTF
  // sample counts, NaN nodata.
  const auto mosaic = open("mosaic.tif");
  ASSERT_NE(mosaic, nullptr);
  GDALRasterBand* b = mosaic->GetRasterBand(1);
  EXPECT_STREQ(b->GetDescription(), "backscatter (linear amplitude: the stored envelope)");
  EXPECT_STREQ(b->GetUnitType(), "counts");
  int has = 0;
  EXPECT_TRUE(std::isnan(b->GetNoDataValue(&has)));
  EXPECT_TRUE(has);
  // The display copy: RGBA with averaged overviews (the float mosaic's COG driver stops at 512
  // pixels, the display copy's at 256).
  const auto rgb = open("mosaic_rgb.tif");
  ASSERT_NE(rgb, nullptr);
  ASSERT_GT(rgb->GetRasterXSize(), 256);  // overviews go down to < 256 pixels
  const char* rgba[4] = {"red", "green", "blue", "alpha (0 = nodata)"};
  for (int k = 0; k < 4; ++k) {
    EXPECT_STREQ(rgb->GetRasterBand(k + 1)->GetDescription(), rgba[k]);
    EXPECT_GE(rgb->GetRasterBand(k + 1)->GetOverviewCount(), 1) << k;
  }
  EXPECT_EQ(rgb->GetRasterBand(4)->GetColorInterpretation(), GCI_AlphaBand);
  EXPECT_NE(item(*rgb, "SONARSYNTH_DISPLAY_SCALE"), "(missing)");
  // The truth mosaic: object ids, nodata INT32_MIN.
  const auto truth = open("truth_mosaic.tif");
  ASSERT_NE(truth, nullptr);
  EXPECT_STREQ(truth->GetRasterBand(1)->GetDescription(), "object_id");
  EXPECT_EQ(truth->GetRasterBand(1)->GetNoDataValue(&has), -2147483648.0);
  EXPECT_TRUE(has);
  // The truth waterfall: class codes as SampleClass numbers them, Int32, the grazing angle in
  // hundredths of a degree (band scale 0.01, offset 0), nodata INT32_MIN.
  const auto tw = open("north_truth.tif");
  ASSERT_NE(tw, nullptr);
  const char* bands[3] = {"class", "object_id", "grazing_angle_deg"};
  for (int k = 0; k < 3; ++k) {
    EXPECT_STREQ(tw->GetRasterBand(k + 1)->GetDescription(), bands[k]);
    EXPECT_EQ(tw->GetRasterBand(k + 1)->GetRasterDataType(), GDT_Int32) << k;
    EXPECT_EQ(tw->GetRasterBand(k + 1)->GetNoDataValue(&has), -2147483648.0) << k;
  }
  EXPECT_STREQ(tw->GetRasterBand(3)->GetUnitType(), "deg");
  EXPECT_EQ(tw->GetRasterBand(3)->GetScale(&has), 0.01);
  EXPECT_TRUE(has);
  EXPECT_NE(item(*tw, "SONARSYNTH_GRAZING_ENCODING").find("hundredths"), std::string::npos);
  const std::string codes = item(*tw, "SONARSYNTH_CLASS_CODES");
  for (const auto& [c, n] : {std::pair{SampleClass::water_column, "water_column"},
                             {SampleClass::seabed, "seabed"},
                             {SampleClass::object, "object"},
                             {SampleClass::shadow, "shadow"},
                             {SampleClass::no_seabed, "no_seabed"}}) {
    const std::string want = std::to_string(static_cast<int>(c)) + " = " + n;
    EXPECT_NE(codes.find(want), std::string::npos) << want << " in " << codes;
  }
  EXPECT_NE(codes.find("255 = padding"), std::string::npos) << codes;
}

TEST_F(SimulateCli, OppositeLinesPutTheObjectInTheSamePlace) {
  const Eigen::Vector2d en = true_en();
  Eigen::Vector2d c[2];
  int k = 0;
  for (const std::string& l : {line("north", 12.0, true), line("south", -12.0, false)}) {
    const fs::path scene = write("s.yaml", scene_yaml(l));
    const fs::path out = dir_ / ("out" + std::to_string(k));
    const auto r = test::run_cli(
        "simulate " + scene.string() + " -o " + out.string() + " -q --res 0.2 --no-waterfall",
        dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    c[k] = centroid(read_raster(out / "truth_mosaic.tif"), [](double v) { return v == 9.0; });
    EXPECT_LT((c[k] - en).norm(), 0.2) << k;
    ++k;
  }
  EXPECT_LT((c[0] - c[1]).norm(), 0.2);
}

TEST_F(SimulateCli, EffectiveConfigurationReproducesTheRunExactly) {
  std::string text = scene_yaml(line("north", 12.0, true));
  text.replace(text.find("noise: {model: none}"), 20, "noise: {model: speckle}");
  const fs::path scene = write("s.yaml", text);
  auto r = test::run_cli("simulate " + scene.string() + " -o " + (dir_ / "a").string() +
                             " -q --seed 77 --no-mosaic --no-waterfall --no-truth",
                         dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("simulate " + (dir_ / "a" / "effective.yaml").string() + " -o " +
                        (dir_ / "b").string() +
                        " -q --no-mosaic --no-waterfall --no-truth --threads 1",
                    dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  const std::string a = bytes(dir_ / "a" / "north.xtf"), b = bytes(dir_ / "b" / "north.xtf");
  EXPECT_GT(a.size(), 100000u);
  EXPECT_TRUE(a == b) << "effective.yaml did not reproduce the XTF file";
}

TEST_F(SimulateCli, BadInputFailsCleanlyAndLeavesNothing) {
  const fs::path scene = write("s.yaml", scene_yaml(line("north", 12.0, true)));
  // An existing output directory is not replaced without --overwrite.
  fs::create_directories(dir_ / "exists");
  std::ofstream(dir_ / "exists" / "keep.txt") << "mine";
  auto r = test::run_cli("simulate " + scene.string() + " -o " + (dir_ / "exists").string() + " -q",
                         dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("already exists"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "exists" / "keep.txt"));
  // A bad value: named, non-zero exit, no output directory and no temporary left.
  std::string bad = scene_yaml(line("north", 12.0, true));
  bad.replace(bad.find("altitude_m: 6"), 13, "altitude_m: -6");
  const fs::path bad_scene = write("bad.yaml", bad);
  r = test::run_cli("simulate " + bad_scene.string() + " -o " + (dir_ / "o").string() + " -q",
                    dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.yaml: survey.altitude_m = '-6'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "o"));
  // A bad option value.
  r = test::run_cli(
      "simulate " + scene.string() + " -o " + (dir_ / "o").string() + " -q --quality ultra", dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--quality = 'ultra'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "o"));
  for (const auto& e : fs::directory_iterator(dir_)) {
    EXPECT_EQ(e.path().filename().string().find(".o.part"), std::string::npos) << e.path();
  }
}

}  // namespace
}  // namespace sonarsynth
