// SPDX-License-Identifier: MIT
// What `simulate` writes besides the XTF files, checked against independent computations:
// the truth vectors (targets.geojson, tracks.geojson, coverage.geojson; docs/labels.md) against
// PROJ's geodetic conversion, the XTF navigation read back and the truth class rasters; the
// processed mosaic (output.mosaic, docs/scene-format.md) against the plain gridding and the
// flat seabed it shows; the overviews and ground control points of every raster.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <GeographicLib/Geodesic.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "scene_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/products/survey_products.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/geo_frame.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

// A flat seabed (no relief: the slant->ground mapping of the XTF samples is exact), two lines,
// a pipe both lines cross, a rock given by latitude/longitude within the swath of line a, a box
// 150 m from every line (the swath reaches 20 m).
const std::string kScene = test::flat_scene("geo-products", 11, 400, 400, 12, 3.0, 5) + R"(
    - {name: a, waypoints: [{east_m: -40, north_m: 0}, {east_m: 40, north_m: 0}]}
    - {name: b, waypoints: [{east_m: 30, north_m: -20}, {east_m: -30, north_m: 15}]}
objects:
  - {type: pipe, id: 3, name: cable, start: {east_m: 0, north_m: -30}, end: {east_m: 0, north_m: 30}, diameter_m: 0.4}
  - {type: rock, id: 5, position: {lat_deg: 43.00008, lon_deg: 5.0002}, diameter_m: 1.2}
  - {type: box, id: 8, position: {east_m: 150, north_m: 150}, size_m: [3, 2, 1], heading_deg: 30}
sonar: {frequency_khz: 600, range_m: 20, samples: 400}
)";

class GeoProductsTest : public test::ScratchDirTest {
 protected:
  void SetUp() override {
    ScratchDirTest::SetUp();
    GDALAllRegister();
  }
  std::string write_scene(const std::string& text, const std::string& name = "scene.yaml") {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
};

struct Layer {
  std::unique_ptr<GDALDataset> ds;
  OGRLayer* layer = nullptr;
};

Layer open_layer(const fs::path& path) {
  Layer l;
  l.ds.reset(GDALDataset::Open(path.string().c_str(), GDAL_OF_VECTOR));
  if (l.ds) l.layer = l.ds->GetLayer(0);
  return l;
}

std::unique_ptr<OGRCoordinateTransformation> wgs84_to(int epsg) {
  OGRSpatialReference from, to;
  from.importFromEPSG(4326);
  from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  to.importFromEPSG(epsg);
  to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return std::unique_ptr<OGRCoordinateTransformation>(
      OGRCreateCoordinateTransformation(&from, &to));
}

struct Band {
  int cols = 0, rows = 0;
  std::vector<double> v;
  double at(int c, int r) const { return v[static_cast<std::size_t>(r) * cols + c]; }
};

Band read_band(const fs::path& path, int band = 1) {
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.string().c_str(), GDAL_OF_RASTER));
  Band b;
  if (!ds) return b;
  b.cols = ds->GetRasterXSize();
  b.rows = ds->GetRasterYSize();
  b.v.resize(static_cast<std::size_t>(b.cols) * b.rows);
  if (ds->GetRasterBand(band)->RasterIO(GF_Read, 0, 0, b.cols, b.rows, b.v.data(), b.cols, b.rows,
                                        GDT_Float64, 0, 0, nullptr) != CE_None) {
    b.v.clear();
  }
  return b;
}

// targets.geojson: one Point per object at the scene file's position (a lat/lon position
// exactly, east/north ones through PROJ's UTM <-> geodetic conversion), its sizes, and the
// lines and pings that see it, which are the rows of the line's truth raster whose object_id
// band holds its id; the box outside every swath is listed with no line.
TEST_F(GeoProductsTest, TargetsArePlacedAndSeenAsTheSceneAndTheTruthRastersSay) {
  RunOptions o;
  o.products.mosaic = false;
  const fs::path out = dir_ / "out";
  const RunResult r = run_simulation(write_scene(kScene), out, o);
  for (const char* f : {"targets.geojson", "tracks.geojson", "coverage.geojson"}) {
    EXPECT_NE(std::find(r.files.begin(), r.files.end(), out / f), r.files.end()) << f;
  }
  Layer t = open_layer(out / "targets.geojson");
  ASSERT_TRUE(t.layer);
  std::map<int, std::unique_ptr<OGRFeature>> by_id;
  for (auto& f : *t.layer) by_id[f->GetFieldAsInteger("id")].reset(f.release());
  ASSERT_EQ(by_id.size(), 3u);
  const int epsg = by_id[3]->GetFieldAsInteger("epsg");
  EXPECT_EQ(epsg, 32631);  // 5 deg E, northern hemisphere
  const auto ct = wgs84_to(epsg);
  // The grid centre in UTM: the same for every target (east/north are relative to it).
  double centre_e = 0.0, centre_n = 0.0;
  for (auto& [id, f] : by_id) {
    const OGRPoint* p = f->GetGeometryRef()->toPoint();
    EXPECT_DOUBLE_EQ(p->getX(), f->GetFieldAsDouble("lon_deg"));
    EXPECT_DOUBLE_EQ(p->getY(), f->GetFieldAsDouble("lat_deg"));
    double e = p->getX(), n = p->getY();
    ASSERT_TRUE(ct->Transform(1, &e, &n));
    EXPECT_NEAR(e, f->GetFieldAsDouble("utm_easting_m"), 1e-3) << id;
    EXPECT_NEAR(n, f->GetFieldAsDouble("utm_northing_m"), 1e-3) << id;
    const double ce = e - f->GetFieldAsDouble("east_m"), cn = n - f->GetFieldAsDouble("north_m");
    if (id == 3) {
      centre_e = ce;
      centre_n = cn;
    }
    EXPECT_NEAR(ce, centre_e, 1e-3) << id;
    EXPECT_NEAR(cn, centre_n, 1e-3) << id;
  }
  // Positions as given.
  EXPECT_NEAR(by_id[3]->GetFieldAsDouble("east_m"), 0.0, 1e-9);
  EXPECT_NEAR(by_id[3]->GetFieldAsDouble("north_m"), 0.0, 1e-9);  // midpoint of start and end
  EXPECT_NEAR(by_id[5]->GetFieldAsDouble("lat_deg"), 43.00008, 1e-10);
  EXPECT_NEAR(by_id[5]->GetFieldAsDouble("lon_deg"), 5.0002, 1e-10);
  EXPECT_NEAR(by_id[8]->GetFieldAsDouble("east_m"), 150.0, 1e-9);
  EXPECT_NEAR(by_id[8]->GetFieldAsDouble("north_m"), 150.0, 1e-9);
  // Names, types and sizes.
  EXPECT_STREQ(by_id[3]->GetFieldAsString("name"), "cable");
  EXPECT_STREQ(by_id[3]->GetFieldAsString("type"), "pipe");
  EXPECT_NEAR(by_id[3]->GetFieldAsDouble("length_m"), 60.0, 1e-9);
  EXPECT_NEAR(by_id[3]->GetFieldAsDouble("diameter_m"), 0.4, 1e-9);
  EXPECT_NEAR(by_id[3]->GetFieldAsDouble("heading_deg"), 0.0, 1e-9);
  EXPECT_STREQ(by_id[5]->GetFieldAsString("type"), "rock");
  EXPECT_NEAR(by_id[5]->GetFieldAsDouble("diameter_m"), 1.2, 1e-9);
  EXPECT_NEAR(by_id[8]->GetFieldAsDouble("length_m"), 3.0, 1e-9);
  EXPECT_NEAR(by_id[8]->GetFieldAsDouble("width_m"), 2.0, 1e-9);
  EXPECT_NEAR(by_id[8]->GetFieldAsDouble("height_m"), 1.0, 1e-9);
  EXPECT_NEAR(by_id[8]->GetFieldAsDouble("heading_deg"), 30.0, 1e-9);
  EXPECT_TRUE(by_id[8]->IsFieldNull(by_id[8]->GetFieldIndex("diameter_m")));

  // The sightings against the instance rasters: first and last row holding the id, and the
  // number of rows that do.
  std::map<int, std::string> expected;
  for (const int id : {3, 5, 8}) {
    std::string json = "[";
    for (const std::string& line : r.line_names) {
      // Band 2 of the truth raster: the object id of each sample's echo.
      const Band inst = read_band(out / (line + "_truth.tif"), 2);
      ASSERT_FALSE(inst.v.empty());
      int first = -1, last = -1, rows = 0;
      for (int row = 0; row < inst.rows; ++row) {
        bool any = false;
        for (int c = 0; c < inst.cols && !any; ++c) any = inst.at(c, row) == id;
        if (!any) continue;
        if (first < 0) first = row;
        last = row;
        ++rows;
      }
      if (rows == 0) continue;
      json += std::string(json.size() > 1 ? ", " : "") + "line " + line + " " +
              std::to_string(first) + "-" + std::to_string(last) + " " + std::to_string(rows);
    }
    expected[id] = json + "]";
  }
  for (auto& [id, f] : by_id) {
    // The JSON list, reduced to the same words.
    const std::string text = f->GetFieldAsString("seen_by");
    std::string got = "[";
    std::size_t pos = 0;
    while ((pos = text.find("\"line\": \"", pos)) != std::string::npos) {
      const std::size_t a = pos + 9, b = text.find('"', a);
      const auto num = [&](const char* key) {
        const std::size_t k = text.find(key, b) + std::string(key).size();
        return std::stoll(text.substr(k, text.find_first_of(",}", k) - k));
      };
      got += std::string(got.size() > 1 ? ", " : "") + "line " + text.substr(a, b - a) + " " +
             std::to_string(num("\"first_ping\": ")) + "-" +
             std::to_string(num("\"last_ping\": ")) + " " + std::to_string(num("\"pings\": "));
      pos = b;
    }
    got += "]";
    EXPECT_EQ(got, expected[id]) << id << ": " << text;
  }
  EXPECT_NE(expected[3], "[]");  // the pipe is seen (by both lines)
  EXPECT_NE(expected[5], "[]");
  EXPECT_EQ(expected[8], "[]");  // outside every swath: no ping
  EXPECT_EQ(std::string(by_id[8]->GetFieldAsString("seen_by")), "[ ]");
  EXPECT_EQ(by_id[8]->GetFieldAsInteger64("pings"), 0);
}

// tracks.geojson: one LineString per line whose vertices are the XTF's sensor positions (read
// back, degrees), with its first and last ping times; coverage.geojson: every seabed sample of
// the line (truth class raster), placed on the flat seabed from the XTF's position, heading,
// altitude and slant range (GeographicLib's geodesic, not the simulator's frame), lies within
// half its own ground footprint of its side's polygon, and a point 2 m beyond the swath's reach
// does not.
TEST_F(GeoProductsTest, TracksAreTheXtfNavigationAndCoverageHoldsEverySeabedSample) {
  RunOptions o;
  o.products.mosaic = false;
  o.products.waterfalls = false;
  const fs::path out = dir_ / "out";
  const RunResult r = run_simulation(write_scene(kScene), out, o);
  Layer tracks = open_layer(out / "tracks.geojson");
  Layer coverage = open_layer(out / "coverage.geojson");
  ASSERT_TRUE(tracks.layer && coverage.layer);
  std::map<std::string, std::unique_ptr<OGRFeature>> track;
  for (auto& f : *tracks.layer) track[f->GetFieldAsString("line")].reset(f.release());
  std::map<std::string, std::unique_ptr<OGRGeometry>> side_polygon;
  for (auto& f : *coverage.layer) {
    side_polygon[std::string(f->GetFieldAsString("line")) + "/" + f->GetFieldAsString("side")]
        .reset(f->StealGeometry());
  }
  ASSERT_EQ(track.size(), 2u);
  ASSERT_EQ(side_polygon.size(), 4u);
  const int epsg = 32631;
  const auto ct = wgs84_to(epsg);
  for (auto& [k, g] : side_polygon) ASSERT_EQ(g->transform(ct.get()), OGRERR_NONE) << k;
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  for (const std::string& line : r.line_names) {
    ASSERT_TRUE(track.count(line));
    const OGRLineString* ls = track[line]->GetGeometryRef()->toLineString();
    const Band cls = read_band(out / (line + "_truth_class.tif"));
    ASSERT_FALSE(cls.v.empty());
    const int side_cols = cls.cols / 2;
    xtf::Reader reader(out / (line + ".xtf"));
    xtf::Packet p;
    int k = 0;
    std::size_t checked = 0;
    while (reader.next(p)) {
      if (p.kind != xtf::PacketKind::kPing) continue;
      const SonarPing& s = p.ping.sonar;
      ASSERT_LT(k, ls->getNumPoints());
      EXPECT_NEAR(ls->getX(k), deg_from_rad(s.sensor_position.lon_rad), 1e-9) << line << k;
      EXPECT_NEAR(ls->getY(k), deg_from_rad(s.sensor_position.lat_rad), 1e-9) << line << k;
      if (k == 0) {
        // The GeoJSON driver reads the ISO text back as a date-time.
        int y = 0, mo = 0, d = 0, h = 0, mi = 0, tz = 0;
        float sec = 0.0f;
        ASSERT_TRUE(track[line]->GetFieldAsDateTime(track[line]->GetFieldIndex("first_ping_time"),
                                                    &y, &mo, &d, &h, &mi, &sec, &tz));
        char text[64];
        std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%05.2f", y, mo, d, h, mi,
                      static_cast<double>(sec));
        EXPECT_EQ(std::string(text), format_utc(s.time_utc).substr(0, 22));
      }
      // Every 5th ping, every 3rd sample: its ground position against the side's polygon.
      if (k % 5 == 0) {
        for (const bool stbd : {false, true}) {
          const auto& samples = stbd ? s.starboard : s.port;
          const double dr = s.slant_range_m / static_cast<double>(samples.size());
          OGRGeometry* poly = side_polygon[line + (stbd ? "/starboard" : "/port")].get();
          for (std::size_t i = 0; i < samples.size(); i += 3) {
            const int col =
                stbd ? side_cols + static_cast<int>(i) : side_cols - 1 - static_cast<int>(i);
            const double c = cls.at(col, k);
            // Seabed samples (an object's echo comes from above the seabed: the flat-bottom
            // mapping does not place it).
            if (c != 1.0) continue;
            const double rr = (static_cast<double>(i) + 0.5) * dr;
            // A sample whose centre is still in the water (it straddles the seabed at nadir)
            // has no flat-bottom ground range.
            if (!(rr > s.altitude_m)) continue;
            const double ground = std::sqrt(rr * rr - s.altitude_m * s.altitude_m);
            const double footprint = rr * dr / ground;  // ground extent of the sample
            const double azimuth = deg_from_rad(s.heading_true_rad) + (stbd ? 90.0 : -90.0);
            double lat = 0.0, lon = 0.0;
            geod.Direct(deg_from_rad(s.sensor_position.lat_rad),
                        deg_from_rad(s.sensor_position.lon_rad), azimuth, ground, lat, lon);
            double e = lon, n = lat;
            ASSERT_TRUE(ct->Transform(1, &e, &n));
            const OGRPoint pt(e, n);
            EXPECT_LE(pt.Distance(poly), 0.5 * footprint + 0.01)
                << line << " ping " << k << (stbd ? " stbd " : " port ") << i;
            ++checked;
          }
          // 2 m beyond the farthest ground the swath reaches: outside.
          const double reach =
              std::sqrt(s.slant_range_m * s.slant_range_m - s.altitude_m * s.altitude_m);
          double lat = 0.0, lon = 0.0;
          geod.Direct(
              deg_from_rad(s.sensor_position.lat_rad), deg_from_rad(s.sensor_position.lon_rad),
              deg_from_rad(s.heading_true_rad) + (stbd ? 90.0 : -90.0), reach + 2.0, lat, lon);
          double e = lon, n = lat;
          ASSERT_TRUE(ct->Transform(1, &e, &n));
          const OGRPoint beyond(e, n);
          EXPECT_GT(beyond.Distance(poly), 1.0) << line << " ping " << k;
        }
      }
      ++k;
    }
    EXPECT_EQ(k, ls->getNumPoints()) << line;
    EXPECT_EQ(track[line]->GetFieldAsInteger64("pings"), k);
    EXPECT_GT(checked, 1000u) << line;
  }
}

/// The pixels of band 1 of a GeoTIFF with its geotransform.
struct Image {
  Band band;
  double gt[6] = {0, 1, 0, 0, 0, -1};
};
Image read_image(const fs::path& path) {
  Image im;
  im.band = read_band(path);
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.string().c_str(), GDAL_OF_RASTER));
  if (ds) ds->GetGeoTransform(im.gt);
  return im;
}

const std::string kFlatScene = test::flat_scene("flat", 3, 160, 160, 20, 2.0, 8) + R"(
    - {name: a, waypoints: [{east_m: -40, north_m: 0}, {east_m: 40, north_m: 0}]}
sonar: {frequency_khz: 600, range_m: 40, samples: 1000}
)";

// output.mosaic on a flat seabed: the default (blank nadir, angle normalisation) mosaic has
// nothing gridded within the first return's ground reach; its pixels within 2 m of the track
// have the mean level of those 10-20 m out within 1 dB, and none is brighter than that level
// plus 10 dB (the margin of speckle: a single-look amplitude exceeds its mean by 9.5 dB with
// probability 1e-3, and near the track a sample covers several pixels, where 10-20 m out a pixel
// averages several samples); its across-track mean profile (1 m bins from 1.5 m to 34 m on both
// sides) stays within +-1 dB of its mean, where the raw gridding's spans more than 10 dB (the
// beam pattern and the TVG: what the normalisation removes).
TEST_F(GeoProductsTest, ProcessedMosaicHasNoNadirSeamAndAFlatAcrossTrackLevel) {
  RunOptions o;
  o.products.waterfalls = false;
  std::map<std::string, Image> images;
  for (const char* mode : {"processed", "raw"}) {
    std::string text = kFlatScene;
    if (std::string(mode) == "raw") {
      text += "output: {mosaic: {nadir: raw, gain_normalisation: off}}\n";
    }
    const fs::path out = dir_ / mode;
    run_simulation(write_scene(text, std::string(mode) + ".yaml"), out, o);
    images[mode] = read_image(out / "mosaic.tif");
    ASSERT_FALSE(images[mode].band.v.empty());
  }
  // The grid centre (the line runs along its row) in the mosaic's UTM coordinates.
  const auto ct = wgs84_to(32631);
  double cx = 5.0, cy = 43.0;
  ASSERT_TRUE(ct->Transform(1, &cx, &cy));
  const auto level_db = [&](const Image& im, double y0, double y1, std::vector<double>* pixels) {
    double sum = 0.0;
    std::size_t n = 0;
    for (int r = 0; r < im.band.rows; ++r) {
      const double y = im.gt[3] + (r + 0.5) * im.gt[5] - cy;
      if (y < y0 || y >= y1) continue;
      for (int c = 0; c < im.band.cols; ++c) {
        const double x = im.gt[0] + (c + 0.5) * im.gt[1] - cx;
        if (std::abs(x) > 25.0) continue;
        const double v = im.band.at(c, r);
        if (std::isnan(v)) continue;
        sum += v;
        ++n;
        if (pixels) pixels->push_back(20.0 * std::log10(v));
      }
    }
    return n ? 20.0 * std::log10(sum / static_cast<double>(n)) : std::nan("");
  };
  const auto spread = [&](const Image& im) {
    double lo = INFINITY, hi = -INFINITY, sum = 0.0;
    int n = 0;
    for (double y = 1.5; y < 34.0; y += 1.0) {
      for (const double s : {-1.0, 1.0}) {
        const double l = level_db(im, s > 0 ? y : -y - 1.0, s > 0 ? y + 1.0 : -y, nullptr);
        EXPECT_FALSE(std::isnan(l)) << y;
        lo = std::min(lo, l);
        hi = std::max(hi, l);
        sum += l;
        ++n;
      }
    }
    return std::pair<double, double>{hi - sum / n, sum / n - lo};
  };
  const auto [above, below] = spread(images["processed"]);
  EXPECT_LE(above, 1.0);
  EXPECT_LE(below, 1.0);
  const auto [raw_above, raw_below] = spread(images["raw"]);
  EXPECT_GT(raw_above + raw_below, 10.0);
  // No seam: the pixels near the track against the seabed's level further out.
  std::vector<double> near;
  const double near_db = level_db(images["processed"], -2.0, 2.0, &near);
  const double mid_db = 0.5 * (level_db(images["processed"], 10.0, 20.0, nullptr) +
                               level_db(images["processed"], -20.0, -10.0, nullptr));
  ASSERT_FALSE(near.empty());
  EXPECT_NEAR(near_db, mid_db, 1.0);
  EXPECT_LE(*std::max_element(near.begin(), near.end()), mid_db + 10.0) << mid_db;
  // The blanked first return: within 0.3 m of the track (inside its ground reach
  // sqrt(2 H e + e^2) = 0.80 m for H = 8 m, e = pulse window (none: one sample) + one sample =
  // 0.04 m) nothing.
  std::vector<double> centre;
  level_db(images["processed"], -0.3, 0.3, &centre);
  EXPECT_TRUE(centre.empty()) << centre.size();
}

// output.mosaic {nadir: raw, gain_normalisation: off} is the gridding `simulate` did before the
// settings existed: the library's SurveyProducts with its default options (no blanking, no
// normalisation) fed the same pings gives the same mosaic pixels, bit for bit.
TEST_F(GeoProductsTest, RawSettingsReproduceThePlainGriddingBitForBit) {
  const std::string scene =
      write_scene(std::string(kFlatScene) +
                  "output: {mosaic: {nadir: raw, gain_normalisation: off}}\nnoise: {model: "
                  "speckle}\n");
  RunOptions o;
  o.products.waterfalls = false;
  const fs::path out = dir_ / "run";
  run_simulation(scene, out, o);
  // The old code path: the products' library defaults, driven by the Simulator directly.
  const auto setup = std::make_shared<SimulationSetup>(load_simulation(scene));
  const std::shared_ptr<const Scene> shared(setup, &setup->scene);
  const Survey survey = setup->make_survey();
  const Simulator sim(shared, setup->config, setup->reference_altitude_m,
                      pilot_poses(survey, shared->bathymetry));
  const fs::path ref = dir_ / "ref";
  fs::create_directories(ref);
  SurveyProductOptions po;
  po.waterfalls = false;
  {
    SurveyProducts products(ref, shared, setup->config.sonar, setup->lines, po);
    sim.run(survey, products);
  }
  const Band got = read_band(out / "mosaic.tif");
  const Band want = read_band(ref / "mosaic.tif");
  ASSERT_EQ(got.v.size(), want.v.size());
  ASSERT_FALSE(got.v.empty());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < got.v.size(); ++i) {
    const bool same = (std::isnan(got.v[i]) && std::isnan(want.v[i])) || got.v[i] == want.v[i];
    differ += same ? 0 : 1;
  }
  EXPECT_EQ(differ, 0u);
}

// Every TIFF of a run larger than 512 pixels a side has internal overviews, stored as GDAL's
// COG validator asks (validate_cloud_optimized_geotiff.py's checks, here through GDAL's TIFF
// metadata): the IFDs by decreasing size at increasing offsets, the smallest overview's data
// first and the full resolution's last. The line rasters carry ground control points in the
// scene's UTM zone that lie on the seabed their samples see.
TEST_F(GeoProductsTest, EveryLargeTiffHasOverviewsInCloudOptimisedOrder) {
  std::string text = kFlatScene;
  text.replace(text.find("samples: 1000"), 13, "samples: 600");
  RunOptions o;
  o.products.waterfalls = true;
  const fs::path out = dir_ / "out";
  const RunResult r = run_simulation(write_scene(text), out, o);
  std::size_t large = 0;
  for (const fs::path& f : r.files) {
    if (f.extension() != ".tif") continue;
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(f.string().c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(ds) << f;
    GDALRasterBand* b = ds->GetRasterBand(1);
    if (ds->GetRasterXSize() <= 512 && ds->GetRasterYSize() <= 512) continue;
    ++large;
    ASSERT_GT(b->GetOverviewCount(), 0) << f;
    const auto item = [](GDALRasterBand* band, const std::string& key) {
      const char* v = band->GetMetadataItem(key.c_str(), "TIFF");
      return v ? std::stoll(v) : -1LL;
    };
    long long ifd = item(b, "IFD_OFFSET");
    long long data = item(b, "BLOCK_OFFSET_0_0");
    for (int i = 0; i < b->GetOverviewCount(); ++i) {
      GDALRasterBand* ov = b->GetOverview(i);
      EXPECT_GT(item(ov, "IFD_OFFSET"), ifd) << f << " overview " << i;
      EXPECT_LT(item(ov, "BLOCK_OFFSET_0_0"), data) << f << " overview " << i;
      ifd = item(ov, "IFD_OFFSET");
      data = item(ov, "BLOCK_OFFSET_0_0");
    }
    EXPECT_GT(data, ifd) << f;
  }
  EXPECT_GE(large, 7u);  // mosaic, rgb, truth mosaic, its class and instance, the line's three
  // `--of GTiff`: every one of them a plain tiled GeoTIFF instead, each level's data after the
  // full resolution's, and no LAYOUT=COG.
  o.products.write_options.format = MosaicRasterFormat::gtiff;
  const fs::path plain_out = dir_ / "plain";
  const RunResult plain = run_simulation(write_scene(text, "plain.yaml"), plain_out, o);
  std::size_t plain_large = 0;
  for (const fs::path& f : plain.files) {
    if (f.extension() != ".tif") continue;
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(f.string().c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(ds) << f;
    EXPECT_EQ(ds->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE"), nullptr) << f;
    GDALRasterBand* b = ds->GetRasterBand(1);
    if (ds->GetRasterXSize() <= 512 && ds->GetRasterYSize() <= 512) continue;
    ++plain_large;
    ASSERT_GT(b->GetOverviewCount(), 0) << f;
    int bx = 0, by = 0;
    b->GetBlockSize(&bx, &by);
    EXPECT_LT(bx, ds->GetRasterXSize()) << f << ": tiled, not strips of the full width";
    const char* full = b->GetMetadataItem("BLOCK_OFFSET_0_0", "TIFF");
    ASSERT_TRUE(full) << f;
    for (int i = 0; i < b->GetOverviewCount(); ++i) {
      const char* ov = b->GetOverview(i)->GetMetadataItem("BLOCK_OFFSET_0_0", "TIFF");
      ASSERT_TRUE(ov) << f << " overview " << i;
      EXPECT_GT(std::stoll(ov), std::stoll(full)) << f << " overview " << i;
    }
  }
  EXPECT_EQ(plain_large, large);
  // The line rasters' GCPs: in EPSG:32631, on the line's swath (within range of the track).
  for (const char* suffix : {"_truth.tif", "_truth_class.tif", "_truth_instance.tif"}) {
    std::unique_ptr<GDALDataset> ds(
        GDALDataset::Open((out / (std::string("a") + suffix)).string().c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(ds);
    ASSERT_GE(ds->GetGCPCount(), 32) << suffix;
    const OGRSpatialReference* srs = ds->GetGCPSpatialRef();
    ASSERT_TRUE(srs);
    EXPECT_STREQ(srs->GetAuthorityCode(nullptr), "32631");
    double cx = 5.0, cy = 43.0;
    ASSERT_TRUE(wgs84_to(32631)->Transform(1, &cx, &cy));
    const int side = ds->GetRasterXSize() / 2;
    for (int i = 0; i < ds->GetGCPCount(); ++i) {
      const GDAL_GCP& g = ds->GetGCPs()[i];
      // The line runs east along the grid centre's row: the ground range is the northing
      // offset, port (left of the middle column) to the north.
      const double across = g.dfGCPY - cy;
      EXPECT_LE(std::abs(g.dfGCPX - cx), 41.0) << i;
      EXPECT_LE(std::abs(across), 40.0) << i;
      EXPECT_EQ(across > 0.0, g.dfGCPPixel < side) << i;
    }
  }
}

// Bad settings name the file, the key and the value.
TEST_F(GeoProductsTest, BadMosaicSettingsNameFileKeyAndValue) {
  for (const char* bad : {"nadir: seam", "gain_normalisation: beam", "blanking: 3"}) {
    const std::string path =
        write_scene(std::string(kFlatScene) + "output: {mosaic: {" + bad + "}}\n", "bad.yaml");
    try {
      load_simulation(path);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("bad.yaml"), std::string::npos) << m;
      EXPECT_NE(m.find("mosaic"), std::string::npos) << m;
      const std::string value = std::string(bad).substr(std::string(bad).find(':') + 2);
      const std::string key = std::string(bad).substr(0, std::string(bad).find(':'));
      EXPECT_NE(m.find(key), std::string::npos) << m;
      if (key != "blanking") {
        EXPECT_NE(m.find(value), std::string::npos) << m;
      }
    }
  }
}

}  // namespace
}  // namespace sonarsynth
