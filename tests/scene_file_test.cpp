// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/scene_file.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cli_test_util.hpp"
#include "error_test_util.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

class SceneFile : public test::ScratchDirTest {
 protected:
  // Expects load_scene to throw E with every fragment in its message.
  template <class E>
  void expect_error(const std::string& yaml, std::initializer_list<std::string_view> fragments) {
    const std::string path = write("bad.yaml", yaml);
    test::expect_error<E>([&] { load_scene(path); }, fragments, yaml);
  }
};

const char* kFlat = R"(
bathymetry:
  generate:
    centre: {lat_deg: -33.9, lon_deg: 151.3}
    size_m: [100, 80]
    cell_m: 0.5
    depth_m: 25
)";

TEST_F(SceneFile, PaperSceneHasFourPipesInASquareAndFourCornerRocks) {
  const Scene s = load_scene(SONARSYNTH_SAMPLES_DIR "/paper_pipes.yaml");
  ASSERT_EQ(s.objects.primitives().size(), 8u);
  const Eigen::Vector4d bb = s.bathymetry.bounds();
  const Eigen::Vector2d c(0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3]));
  int pipes = 0, rocks = 0;
  for (const auto& p : s.objects.primitives()) {
    if (p.shape == ObjectShape::kCylinder) {
      ++pipes;
      EXPECT_NEAR(2 * p.half_extent_m.x(), 480.0, 1e-9);
      EXPECT_NEAR(2 * p.half_extent_m.y(), 0.5, 1e-12);
      // Pipe centres lie at the middle of the square's sides.
      const Eigen::Vector2d d = (p.centre_xy_m - c).cwiseAbs();
      EXPECT_NEAR(std::max(d.x(), d.y()), 240.0, 1e-6);
      EXPECT_NEAR(std::min(d.x(), d.y()), 0.0, 1e-6);
    } else {
      ++rocks;
      EXPECT_EQ(p.shape, ObjectShape::kEllipsoid);
      EXPECT_NEAR(2 * p.half_extent_m.z(), 1.7, 1e-12);
      const Eigen::Vector2d d = (p.centre_xy_m - c).cwiseAbs();
      EXPECT_NEAR(d.x(), 240.0, 1e-6);
      EXPECT_NEAR(d.y(), 240.0, 1e-6);
      // Resting on the seabed: the rock's top is 1.7 m above the seabed under it.
      std::int32_t id = 0;
      const double top = s.objects.top_at(p.centre_xy_m.x(), p.centre_xy_m.y(), &id);
      EXPECT_NEAR(top - s.bathymetry.height_m(p.centre_xy_m.x(), p.centre_xy_m.y()), 1.7, 1e-3);
      EXPECT_EQ(id, p.id);
    }
  }
  EXPECT_EQ(pipes, 4);
  EXPECT_EQ(rocks, 4);
  EXPECT_EQ(s.frame.epsg(), 32652);
  EXPECT_NEAR(s.bathymetry.height_m(c.x(), c.y()), -20.0, 0.2);
}

TEST_F(SceneFile, SamplesLoad) {
  const Scene rough = load_scene(SONARSYNTH_SAMPLES_DIR "/rough_seabed.yaml");
  EXPECT_EQ(rough.objects.primitives().size(), 7u);  // box, pipe, 2 rocks, wreck of 3 boxes
  EXPECT_EQ(rough.material_map.polygon_count(), 2u);
  const Scene real = load_scene(SONARSYNTH_SAMPLES_DIR "/real_ledges.yaml");
  EXPECT_EQ(real.frame.epsg(), 32619);
  EXPECT_EQ(real.objects.primitives().size(), 3u);
  EXPECT_EQ(real.material_map.default_material(), real.materials.index_of("rock"));
}

TEST_F(SceneFile, GeographicPositionsRoundTripThroughTheFrame) {
  const std::string path = write("s.yaml", std::string(kFlat) + R"(
objects:
  - {type: box, position: {lat_deg: -33.9001, lon_deg: 151.3002}, size_m: [1, 1, 1]}
)");
  const Scene s = load_scene(path);
  ASSERT_EQ(s.objects.primitives().size(), 1u);
  const Geodetic g = s.frame.geodetic_from_local(s.objects.primitives()[0].centre_xy_m);
  EXPECT_NEAR(deg_from_rad(g.lat_rad), -33.9001, 1e-10);
  EXPECT_NEAR(deg_from_rad(g.lon_rad), 151.3002, 1e-10);
  EXPECT_EQ(s.frame.epsg(), 32756);  // southern hemisphere
  EXPECT_EQ(s.objects.primitives()[0].id, 1);
}

TEST_F(SceneFile, ObjectsAndPolygonsFromGeoJsonLayers) {
  write("objects.geojson", R"({"type": "FeatureCollection",
 "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}},
 "features": [
  {"type": "Feature", "properties": {"type": "rock", "diameter_m": 1.2, "id": 40},
   "geometry": {"type": "Point", "coordinates": [151.3001, -33.9002]}},
  {"type": "Feature", "properties": {"diameter_m": 0.4},
   "geometry": {"type": "LineString", "coordinates": [[151.2999, -33.9001], [151.3003, -33.9001]]}},
  {"type": "Feature", "properties": {"type": "box", "size_m": "2,1,0.5", "heading_deg": 30},
   "geometry": {"type": "Point", "coordinates": [151.3, -33.9]}}
 ]})");
  write("areas.geojson", R"({"type": "FeatureCollection",
 "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}},
 "features": [{"type": "Feature", "properties": {"kind": "gravel"},
   "geometry": {"type": "Polygon", "coordinates": [[[151.2999, -33.9002], [151.3001, -33.9002],
     [151.3001, -33.9000], [151.2999, -33.9000], [151.2999, -33.9002]]]}}]})");
  const std::string path = write("s.yaml", std::string(kFlat) + R"(
seabed:
  material: mud
  polygons:
    - {file: areas.geojson, material_field: kind}
objects:
  - {file: objects.geojson}
)");
  const Scene s = load_scene(path);
  ASSERT_EQ(s.objects.primitives().size(), 3u);
  const auto& rock = s.objects.primitives()[0];
  EXPECT_EQ(rock.id, 40);
  EXPECT_EQ(rock.shape, ObjectShape::kEllipsoid);
  const Geodetic g = s.frame.geodetic_from_local(rock.centre_xy_m);
  EXPECT_NEAR(deg_from_rad(g.lon_rad), 151.3001, 1e-9);
  EXPECT_NEAR(deg_from_rad(g.lat_rad), -33.9002, 1e-9);
  const auto& pipe = s.objects.primitives()[1];
  EXPECT_EQ(pipe.shape, ObjectShape::kCylinder);
  EXPECT_NEAR(2 * pipe.half_extent_m.x(), 36.97, 0.05);  // 0.0004 deg of longitude at 33.9 S
  EXPECT_NEAR(s.objects.primitives()[2].half_extent_m.x(), 1.0, 1e-12);
  // The polygon assigns gravel inside, the default mud outside.
  const Eigen::Vector2d inside =
      s.frame.local_from_geodetic({rad_from_deg(-33.9001), rad_from_deg(151.3), 0});
  EXPECT_EQ(s.material_map.material_at(inside.x(), inside.y()), s.materials.index_of("gravel"));
  EXPECT_EQ(s.material_map.material_at(inside.x() + 30, inside.y()), s.materials.index_of("mud"));
}

TEST_F(SceneFile, ClassificationRasterAssignsMaterials) {
  // A 2 x 1 class raster in EPSG:4326: west half = 1 (mud), east half = 2 (gravel).
  GDALAllRegister();
  const std::string tif = (dir_ / "classes.tif").string();
  {
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDataset* ds = drv->Create(tif.c_str(), 2, 1, 1, GDT_Byte, nullptr);
    double gt[6] = {151.299, 0.001, 0, -33.899, 0, -0.002};
    ds->SetGeoTransform(gt);
    OGRSpatialReference srs;
    srs.importFromEPSG(4326);
    ds->SetSpatialRef(&srs);
    std::uint8_t v[2] = {1, 2};
    ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 2, 1, v, 2, 1, GDT_Byte, 0, 0),
              CE_None);
    GDALClose(ds);
  }
  const std::string path = write("s.yaml", std::string(kFlat) + R"(
seabed:
  classification: {file: classes.tif, classes: {1: mud, 2: gravel}}
)");
  const Scene s = load_scene(path);
  auto at = [&](double lat, double lon) {
    const Eigen::Vector2d p =
        s.frame.local_from_geodetic({rad_from_deg(lat), rad_from_deg(lon), 0});
    return s.materials[s.material_map.material_at(p.x(), p.y())].name;
  };
  EXPECT_EQ(at(-33.9, 151.2995), "mud");
  EXPECT_EQ(at(-33.9, 151.3005), "gravel");
  EXPECT_EQ(at(-33.95, 151.3005), "sand");  // outside the raster: the default
}

TEST_F(SceneFile, BadInputNamesFileKeyAndValue) {
  expect_error<FormatError>("bathymetry: [unclosed", {"bad.yaml", "malformed YAML", "line"});
  expect_error<InputError>(std::string(kFlat) + "objecs: []\n",
                           {"bad.yaml", "objecs", "unknown key"});
  expect_error<InputError>(std::string(kFlat) +
                               "objects:\n  - {type: pipe, position: {east_m: 0, north_m: 0}, "
                               "length_m: 10, diameter_m: -0.5}\n",
                           {"bad.yaml", "objects[0].diameter_m = '-0.5'", "Violated constraint"});
  expect_error<InputError>(
      std::string(kFlat) +
          "objects:\n  - {type: rock, position: {east_m: 60, north_m: 0}, diameter_m: 1}\n",
      {"bad.yaml", "objects[0]", "outside the bathymetry grid"});
  expect_error<InputError>(std::string(kFlat) +
                               "objects:\n  - {type: box, material: granite, position: {east_m: 0, "
                               "north_m: 0}, size_m: [1, 1, 1]}\n",
                           {"objects[0].material", "unknown material 'granite'"});
  expect_error<InputError>(
      std::string(kFlat) + "objects:\n  - {type: spaceship, position: {east_m: 0, north_m: 0}}\n",
      {"objects[0].type = 'spaceship'"});
  expect_error<InputError>(R"(
bathymetry:
  generate: {centre: {lat_deg: 10, lon_deg: 10}, size_m: [100, 100], cell_m: 0, depth_m: 20}
)",
                           {"bad.yaml", "bathymetry.generate.cell_m = '0'"});
  expect_error<InputError>(R"(
bathymetry:
  generate: {centre: {lat_deg: 10, lon_deg: 10}, size_m: [100, 100], cell_m: -1, depth_m: 20}
)",
                           {"cell_m = '-1'"});
  expect_error<InputError>("bathymetry: {file: a.tif, generate: {}}\n",
                           {"exactly one of file or generate"});
  expect_error<FormatError>("bathymetry: {file: missing.tif}\n", {"missing.tif"});
  expect_error<InputError>(
      std::string(kFlat) +
          "objects:\n  - {type: box, id: 3, position: {east_m: 0, north_m: 0}, size_m: [1, 1, 1]}\n"
          "  - {type: box, id: 3, position: {east_m: 5, north_m: 0}, size_m: [1, 1, 1]}\n",
      {"objects[1].id = '3'", "unique"});
  EXPECT_THROW(load_scene((dir_ / "nope.yaml").string()), FormatError);
}

}  // namespace
}  // namespace sonarsynth
