// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/raster/gdal_grid.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "cli_test_util.hpp"
#include "error_test_util.hpp"
#include "sonarsynth/bathy_gen.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;
using test::error_of;

const std::string kBag = std::string(SONARSYNTH_TEST_DATA_DIR) + "/bathymetry/tiny_sr.bag";
constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

class GdalGridTest : public test::ScratchDirTest {
 protected:
  void SetUp() override {
    gdal::ensure_registered();
    ScratchDirTest::SetUp();
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Expects reading `file` to fail with a FormatError naming the file and `reason`.
  void expect_read_error(const std::string& file, std::string_view reason) {
    test::expect_error<FormatError>([&] { read_height_grid(path(file)); }, {file, reason}, file);
  }

  // A float32 GeoTIFF built directly with GDAL (independent of the code under test).
  void make_tiff(const std::string& file, int cols, int rows, std::vector<float> data,
                 const double* gt, const std::string& crs_user_input,
                 std::optional<double> nodata = std::nullopt) const {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDataset* ds = drv->Create(file.c_str(), cols, rows, 1, GDT_Float32, nullptr);
    ASSERT_NE(ds, nullptr);
    if (gt) ds->SetGeoTransform(const_cast<double*>(gt));
    if (!crs_user_input.empty()) {
      OGRSpatialReference srs;
      ASSERT_EQ(srs.SetFromUserInput(crs_user_input.c_str()), OGRERR_NONE);
      ds->SetSpatialRef(&srs);
    }
    if (nodata) ds->GetRasterBand(1)->SetNoDataValue(*nodata);
    ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, cols, rows, data.data(), cols, rows,
                                             GDT_Float32, 0, 0, nullptr),
              CE_None);
    GDALClose(ds);
  }
};

TEST_F(GdalGridTest, ReadsRealBag) {
  const LoadedGrid g = read_height_grid(kBag);
  EXPECT_EQ(g.driver, "BAG");
  EXPECT_FALSE(g.warped);
  EXPECT_EQ(g.frame.epsg(), 32619);
  const GridGeometry& geo = g.grid.geometry();
  EXPECT_EQ(geo.cols, 117u);
  EXPECT_EQ(geo.rows, 87u);
  EXPECT_DOUBLE_EQ(geo.dx_m, 0.5);
  EXPECT_DOUBLE_EQ(geo.dy_m, -0.5);
  const auto [lo, hi] = g.grid.height_range();
  EXPECT_NEAR(lo, -13.77, 0.01);
  EXPECT_NEAR(hi, -12.07, 0.01);

  // Independent reading with GDAL: the node (c, r) is the pixel centre of the geotransform and
  // holds the band value, 1e6 = nodata.
  const char* const oo[] = {"REPORT_VERTCRS=NO", nullptr};
  gdal::DatasetPtr ds = gdal::open_raster(kBag, "test", oo);
  double gt[6];
  ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
  std::vector<float> raw(117 * 87);
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 117, 87, raw.data(), 117, 87, GDT_Float32,
                                           0, 0, nullptr),
            CE_None);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] == 1e6f) {
      ASSERT_TRUE(std::isnan(g.grid.heights()[i])) << i;
    } else {
      ++valid;
      ASSERT_EQ(g.grid.heights()[i], raw[i]) << i;
    }
  }
  EXPECT_EQ(g.valid_count, valid);
  EXPECT_NEAR(static_cast<double>(valid) / static_cast<double>(raw.size()), 0.969, 0.005);
  const Eigen::Vector2d en = g.frame.projected_from_local({geo.x_of_col(10), geo.y_of_row(20)});
  EXPECT_NEAR(en.x(), gt[0] + 10.5 * gt[1], 1e-6);
  EXPECT_NEAR(en.y(), gt[3] + 20.5 * gt[5], 1e-6);

  // Centre of the grid, through the frame: 43.0678 N 70.7048 W.
  const Eigen::Vector4d b = g.grid.bounds();
  const Geodetic c = g.frame.geodetic_from_local({0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])});
  EXPECT_NEAR(deg_from_rad(c.lat_rad), 43.0678, 2e-4);
  EXPECT_NEAR(deg_from_rad(c.lon_rad), -70.7048, 2e-4);
}

// max_nodes refuses a larger grid (117 x 87 = 10179 nodes) by name and size, and admits it at
// exactly its size.
TEST_F(GdalGridTest, MaxNodesRefusesALargerGrid) {
  GridReadOptions o;
  o.max_nodes = 117 * 87 - 1;
  try {
    read_height_grid(kBag, o);
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    const std::string m = e.what();
    for (const std::string& part :
         {kBag, std::string("117 x 87 nodes"), std::string("max_nodes = 10178")}) {
      EXPECT_NE(m.find(part), std::string::npos) << part << " in " << m;
    }
  }
  o.max_nodes = 117 * 87;
  EXPECT_EQ(read_height_grid(kBag, o).grid.geometry().cols, 117u);
}

TEST_F(GdalGridTest, DepthPositiveDownNegates) {
  GridReadOptions o;
  o.depth_positive_down = true;
  const LoadedGrid up = read_height_grid(kBag);
  const LoadedGrid down = read_height_grid(kBag, o);
  ASSERT_EQ(up.grid.heights().size(), down.grid.heights().size());
  for (std::size_t i = 0; i < up.grid.heights().size(); ++i) {
    const float a = up.grid.heights()[i];
    const float b = down.grid.heights()[i];
    if (std::isnan(a)) {
      ASSERT_TRUE(std::isnan(b));
    } else {
      ASSERT_EQ(a, -b);
    }
  }
}

TEST_F(GdalGridTest, WriteReadRoundTripSouthernHemisphere) {
  const Geodetic centre{rad_from_deg(-33.86), rad_from_deg(151.21), 0.0};
  const GeoFrame frame = GeoFrame::around(centre);
  ASSERT_EQ(frame.epsg(), 32756);
  BathyGenSpec spec;
  const Eigen::Vector2d c = frame.local_from_geodetic(centre);
  spec.geometry = BathyGenSpec::centred_geometry(c.x(), c.y(), 150.0, 100.0, 0.5);
  bathy::Fbm f;
  f.rms_m = 0.5;
  spec.components.push_back(f);
  spec.components.push_back(bathy::Seamount{c.x(), c.y(), 4.0, 15.0});
  HeightGrid grid = generate_bathymetry(spec);
  grid.mutable_heights()[17] = kNaNf;  // holes survive
  grid.mutable_heights()[1234] = kNaNf;

  const std::string out = path("rt.tif");
  GridWriteOptions wo;
  wo.metadata.push_back({"SONARSYNTH_TEST", "yes"});
  write_height_grid_geotiff(out, frame, grid, wo);
  const LoadedGrid back = read_height_grid(out);
  EXPECT_EQ(back.frame.epsg(), 32756);
  EXPECT_FALSE(back.warped);
  ASSERT_EQ(back.grid.geometry().cols, grid.geometry().cols);
  ASSERT_EQ(back.grid.geometry().rows, grid.geometry().rows);
  EXPECT_EQ(std::memcmp(back.grid.heights().data(), grid.heights().data(),
                        grid.heights().size() * sizeof(float)),
            0);
  EXPECT_EQ(back.valid_count, grid.heights().size() - 2);
  const GridGeometry& a = grid.geometry();
  const GridGeometry& b = back.grid.geometry();
  EXPECT_DOUBLE_EQ(b.dx_m, a.dx_m);
  EXPECT_DOUBLE_EQ(b.dy_m, a.dy_m);
  const Eigen::Vector2d en_a = frame.projected_from_local({a.x0_m, a.y0_m});
  const Eigen::Vector2d en_b = back.frame.projected_from_local({b.x0_m, b.y0_m});
  EXPECT_NEAR(en_a.x(), en_b.x(), 1e-6);
  EXPECT_NEAR(en_a.y(), en_b.y(), 1e-6);
  // The file itself: corner half a cell before the first node, EPSG, AREA_OR_POINT, nodata.
  gdal::DatasetPtr ds = gdal::open_raster(out, "test");
  double gt[6];
  ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
  EXPECT_NEAR(gt[0], en_a.x() - 0.25, 1e-6);
  EXPECT_NEAR(gt[3], en_a.y() + 0.25, 1e-6);
  EXPECT_STREQ(ds->GetSpatialRef()->GetAuthorityCode(nullptr), "32756");
  EXPECT_STREQ(ds->GetMetadataItem("AREA_OR_POINT"), "Area");
  EXPECT_STREQ(ds->GetMetadataItem("SONARSYNTH_TEST"), "yes");
  int has = 0;
  EXPECT_TRUE(std::isnan(ds->GetRasterBand(1)->GetNoDataValue(&has)));
  EXPECT_TRUE(has);
  // What the band holds: elevations (up positive) in metres.
  EXPECT_STREQ(ds->GetRasterBand(1)->GetDescription(), "elevation");
  EXPECT_STREQ(ds->GetRasterBand(1)->GetUnitType(), "m");
  EXPECT_STREQ(ds->GetMetadataItem("SONARSYNTH_UNITS"), "m");
  // Geodesy round trip lat/lon -> local -> grid index -> local -> lat/lon.
  const Eigen::Vector2d xy = back.frame.local_from_geodetic(centre);
  const double col = b.col_of_x(xy.x());
  const double row = b.row_of_y(xy.y());
  const Geodetic again = back.frame.geodetic_from_local({b.x_of_col(col), b.y_of_row(row)});
  EXPECT_NEAR(again.lat_rad, centre.lat_rad, 1e-12);
  EXPECT_NEAR(again.lon_rad, centre.lon_rad, 1e-12);
  // The seamount summit is at the centre.
  EXPECT_NEAR(back.grid.height_m(xy.x(), xy.y()), grid.height_m(c.x(), c.y()), 1e-6);
}

TEST_F(GdalGridTest, WriterRefusesToOverwriteAndLeavesNothingOnError) {
  const GeoFrame frame(31, true, 500000.0, 5000000.0);
  HeightGrid grid(BathyGenSpec::centred_geometry(0, 0, 4, 4, 1), std::vector<float>(16, -5.0f));
  const std::string out = path("x.tif");
  { std::ofstream(out) << "precious"; }
  EXPECT_NE(error_of<FormatError>([&] {
              write_height_grid_geotiff(out, frame, grid);
            }).find("already exists"),
            std::string::npos);
  std::ifstream in(out);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "precious");
  GridWriteOptions bad;
  bad.creation_options.push_back({"PREDICTOR", "7"});
  bad.overwrite = true;
  EXPECT_THROW(write_height_grid_geotiff(path("y.tif"), frame, grid, bad), FormatError);
  for (const auto& e : fs::directory_iterator(dir_)) {
    EXPECT_EQ(e.path().filename(), "x.tif") << "left behind: " << e.path();
  }
}

// f(lat, lon) in metres: a plane plus a gentle curvature, degrees in.
double analytic_height(double lat, double lon, double lat0, double lon0) {
  const double a = lat - lat0;
  const double b = lon - lon0;
  return -80.0 + 4000.0 * a - 3000.0 * b + 20000.0 * a * a;
}

TEST_F(GdalGridTest, WarpsGeographicRasterAcrossZoneBoundary) {
  // 0.02 x 0.02 deg around 40 S, 6 E: straddles the UTM 31/32 boundary (6 E).
  const double lat0 = -40.0, lon0 = 6.0, cell = 1e-4;
  const int n = 200;
  const double gt[6] = {lon0 - 0.01, cell, 0.0, lat0 + 0.01, 0.0, -cell};
  std::vector<float> data(n * n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      data[r * n + c] = static_cast<float>(
          analytic_height(gt[3] + (r + 0.5) * gt[5], gt[0] + (c + 0.5) * gt[1], lat0, lon0));
    }
  }
  data[5 * n + 7] = -9999.0f;  // a nodata pixel
  const std::string file = path("ll.tif");
  make_tiff(file, n, n, data, gt, "EPSG:4326", -9999.0);
  const LoadedGrid g = read_height_grid(file);
  EXPECT_TRUE(g.warped);
  EXPECT_TRUE(g.frame.epsg() == 32731 || g.frame.epsg() == 32732) << g.frame.epsg();
  // About the source resolution (1e-4 deg = 8.5 m east x 11.1 m north).
  EXPECT_GT(g.grid.geometry().dx_m, 5.0);
  EXPECT_LT(g.grid.geometry().dx_m, 15.0);

  // Bilinear resampling of a surface that is linear in (lat, lon) plus a small quadratic is exact
  // up to the quadratic's interpolation error (|f''| h^2 / 8 = 20000 * 2 * (1e-4)^2 / 8 = 5e-5 m,
  // twice) and the transformer's 0.01 px error (0.01 * 0.45 m); a half-pixel geolocation error
  // would cost ~0.2 m.
  int checked = 0;
  for (double dlat : {-0.006, -0.0013, 0.0, 0.0042, 0.007}) {
    for (double dlon : {-0.0071, -0.0004, 0.0003, 0.0029, 0.0068}) {
      const Geodetic p{rad_from_deg(lat0 + dlat), rad_from_deg(lon0 + dlon), 0.0};
      const Eigen::Vector2d xy = g.frame.local_from_geodetic(p);
      const double z = g.grid.height_m(xy.x(), xy.y());
      ASSERT_FALSE(std::isnan(z)) << dlat << "," << dlon;
      EXPECT_NEAR(z, analytic_height(lat0 + dlat, lon0 + dlon, lat0, lon0), 0.01)
          << dlat << "," << dlon;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 25);
  // The nodata pixel stays a hole; outside the source footprint is a hole, not 0.
  const double hole_lat = gt[3] + 5.5 * gt[5], hole_lon = gt[0] + 7.5 * gt[1];
  const Eigen::Vector2d hole =
      g.frame.local_from_geodetic({rad_from_deg(hole_lat), rad_from_deg(hole_lon), 0.0});
  EXPECT_TRUE(std::isnan(g.grid.height_m(hole.x(), hole.y())));
  std::size_t nan_count = g.grid.heights().size() - g.valid_count;
  EXPECT_GT(nan_count, 0u);
  for (float h : g.grid.heights()) {
    if (!std::isnan(h)) {
      ASSERT_LT(h, 0.0f);  // every valid value is a real depth, never a fill 0
    }
  }
}

TEST_F(GdalGridTest, ReadsOtherProjectedCrsByWarping) {
  // NAD83 / UTM 19N: same zone, other datum, so warped into WGS 84 / UTM 19N.
  const double gt[6] = {361000.0, 2.0, 0.0, 4770000.0, 0.0, -2.0};
  std::vector<float> data(50 * 40, -12.5f);
  make_tiff(path("nad.tif"), 50, 40, data, gt, "EPSG:26919");
  const LoadedGrid g = read_height_grid(path("nad.tif"));
  EXPECT_TRUE(g.warped);
  EXPECT_EQ(g.frame.epsg(), 32619);
  const auto [lo, hi] = g.grid.height_range();
  EXPECT_FLOAT_EQ(static_cast<float>(lo), -12.5f);
  EXPECT_FLOAT_EQ(static_cast<float>(hi), -12.5f);
}

TEST_F(GdalGridTest, MissingFile) {
  const std::string p = path("nope.tif");
  const std::string msg = error_of<FormatError>([&] { read_height_grid(p); });
  EXPECT_NE(msg.find(p), std::string::npos) << msg;
  EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
}

TEST_F(GdalGridTest, NotARaster) {
  { std::ofstream(path("junk.tif")) << "this is not a GeoTIFF"; }
  const std::string msg = error_of<FormatError>([&] { read_height_grid(path("junk.tif")); });
  EXPECT_NE(msg.find("junk.tif"), std::string::npos) << msg;
}

TEST_F(GdalGridTest, NoGeotransform) {
  make_tiff(path("nogt.tif"), 4, 4, std::vector<float>(16, -1.0f), nullptr, "EPSG:32619");
  expect_read_error("nogt.tif", "no geotransform");
}

TEST_F(GdalGridTest, NoCrs) {
  const double gt[6] = {361000.0, 1.0, 0.0, 4770000.0, 0.0, -1.0};
  make_tiff(path("nocrs.tif"), 4, 4, std::vector<float>(16, -1.0f), gt, "");
  expect_read_error("nocrs.tif", "no coordinate reference system");
}

TEST_F(GdalGridTest, UnknownCrs) {
  const double gt[6] = {0.0, 1.0, 0.0, 10.0, 0.0, -1.0};
  make_tiff(path("local.tif"), 4, 4, std::vector<float>(16, -1.0f), gt,
            "LOCAL_CS[\"site grid\",UNIT[\"metre\",1]]");
  expect_read_error("local.tif", "unknown CRS");
}

// A geographic CRS whose identifier is EPSG:4978, the geocentric WGS 84: the definition and the
// identifier contradict each other, and PROJ 9.1 crashes looking for an operation from it
// (docs/architecture.md, "Input CRSs"). The reader refuses such a file, naming the identifier.
const std::string kGeogWithGeocentricId =
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
    "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433],AUTHORITY[\"EPSG\",\"4978\"]]";

TEST_F(GdalGridTest, ProjectedCrsWhoseBaseIdIsGeocentricIsRefused) {
  const std::string wkt =
      "PROJCS[\"custom TM\"," + kGeogWithGeocentricId +
      ",PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],"
      "PARAMETER[\"central_meridian\",3],PARAMETER[\"scale_factor\",1],"
      "PARAMETER[\"false_easting\",0],PARAMETER[\"false_northing\",0],"
      "UNIT[\"metre\",1]]";
  const double gt[6] = {1000.0, 2.0, 0.0, 5500000.0, 0.0, -2.0};
  make_tiff(path("tm.tif"), 4, 4, std::vector<float>(16, -10.0f), gt, wkt);
  expect_read_error("tm.tif", "EPSG:4978, which is a geocentric CRS");
}

TEST_F(GdalGridTest, GeographicCrsWithGeocentricIdIsRefused) {
  // An ASCII grid and its .prj (GDAL's GeoTIFF writer does not keep this identifier).
  {
    std::ofstream asc(path("geog.asc"));
    asc << "ncols 4\nnrows 4\nxllcorner 3.0\nyllcorner 49.996\ncellsize 0.001\n";
    for (int r = 0; r < 4; ++r) asc << "-10 -10 -10 -10\n";
  }
  { std::ofstream(path("geog.prj")) << kGeogWithGeocentricId; }
  expect_read_error("geog.asc", "EPSG:4978, which is a geocentric CRS");
}

TEST_F(GdalGridTest, GeographicCrsWithItsOwnIdIsRead) {
  // The check refuses only contradictions: the same definition identified as EPSG:4326 is read.
  std::string wkt = kGeogWithGeocentricId;
  wkt.replace(wkt.find("4978"), 4, "4326");
  {
    std::ofstream asc(path("geog.asc"));
    asc << "ncols 4\nnrows 4\nxllcorner 3.0\nyllcorner 49.996\ncellsize 0.001\n";
    for (int r = 0; r < 4; ++r) asc << "-10 -10 -10 -10\n";
  }
  { std::ofstream(path("geog.prj")) << wkt; }
  const LoadedGrid g = read_height_grid(path("geog.asc"));
  EXPECT_TRUE(g.warped);
  EXPECT_EQ(g.frame.epsg(), 32631);
}

TEST_F(GdalGridTest, VectorLayerWithGeocentricIdOnItsGeographicCrsIsRefused) {
  // The same contradiction in a vector layer's CRS (scene objects, survey lines): GeoPackage keeps
  // the identifier. Written with GDAL directly.
  const std::string file = path("lines.gpkg");
  {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GPKG");
    ASSERT_NE(drv, nullptr);
    GDALDataset* ds = drv->Create(file.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
    ASSERT_NE(ds, nullptr);
    OGRSpatialReference srs;
    ASSERT_EQ(srs.importFromWkt(kGeogWithGeocentricId.c_str()), OGRERR_NONE);
    OGRLayer* layer = ds->CreateLayer("lines", &srs, wkbPoint, nullptr);
    ASSERT_NE(layer, nullptr);
    OGRFeature feature(layer->GetLayerDefn());
    OGRPoint point(3.0, 50.0);
    feature.SetGeometry(&point);
    ASSERT_EQ(layer->CreateFeature(&feature), OGRERR_NONE);
    GDALClose(ds);
  }
  const std::string msg = error_of<FormatError>(
      [&] { (void)gdal::open_vector_layer(file, "", 32631, false, "survey"); });
  EXPECT_NE(msg.find("lines.gpkg"), std::string::npos) << msg;
  EXPECT_NE(msg.find("EPSG:4978, which is a geocentric CRS"), std::string::npos) << msg;
}

TEST_F(GdalGridTest, AllNodata) {
  const double gt[6] = {361000.0, 1.0, 0.0, 4770000.0, 0.0, -1.0};
  std::vector<float> data(16, -9999.0f);
  data[3] = kNaNf;
  make_tiff(path("empty.tif"), 4, 4, data, gt, "EPSG:32619", -9999.0);
  expect_read_error("empty.tif", "every node is nodata");
}

TEST_F(GdalGridTest, NoFullyValidCell) {
  const double gt[6] = {361000.0, 1.0, 0.0, 4770000.0, 0.0, -1.0};
  // A checkerboard: valid nodes, but no 2 x 2 block of them.
  std::vector<float> data(16);
  for (int i = 0; i < 16; ++i) data[i] = ((i / 4 + i % 4) % 2) ? -9999.0f : -3.0f;
  make_tiff(path("sparse.tif"), 4, 4, data, gt, "EPSG:32619", -9999.0);
  const std::string msg = error_of<FormatError>([&] { read_height_grid(path("sparse.tif")); });
  EXPECT_NE(msg.find("no 2 x 2 block"), std::string::npos) << msg;
}

TEST_F(GdalGridTest, ZeroCellSize) {
  make_tiff(path("base.tif"), 4, 4, std::vector<float>(16, -1.0f), nullptr, "");
  // A VRT wrapping it with a zero pixel width.
  std::ofstream(path("zero.vrt"))
      << "<VRTDataset rasterXSize=\"4\" rasterYSize=\"4\">"
         "<SRS>EPSG:32619</SRS><GeoTransform>361000, 0, 0, 4770000, 0, -1</GeoTransform>"
         "<VRTRasterBand dataType=\"Float32\" band=\"1\"><SimpleSource>"
         "<SourceFilename relativeToVRT=\"1\">base.tif</SourceFilename><SourceBand>1</SourceBand>"
         "</SimpleSource></VRTRasterBand></VRTDataset>";
  expect_read_error("zero.vrt", "cell size != 0");
}

TEST_F(GdalGridTest, BadOptions) {
  GridReadOptions o;
  o.band = 3;  // the BAG has 2 bands
  const std::string msg = error_of<InputError>([&] { read_height_grid(kBag, o); });
  EXPECT_NE(msg.find("band = 3"), std::string::npos) << msg;
  o.band = 0;
  EXPECT_NE(error_of<InputError>([&] { o.validate(); }).find("band >= 1"), std::string::npos);
}

}  // namespace
}  // namespace sonarsynth
