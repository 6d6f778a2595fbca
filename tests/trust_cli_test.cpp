// SPDX-License-Identifier: MIT
// User errors end as named errors (exit 1: the file, the key path or flag, the value) and leave
// nothing behind; runs that used to fail or to drift do not: --seed reproduces through
// effective.yaml, equator and prime-meridian surveys simulate, long lines get a decimated
// waterfall instead of a failure.
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include "cli_test_util.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "xtf_test_util.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

// A small generated scene with a rough seabed (so the bathymetry depends on the seed), one line.
// `extra` is appended at the top level; `line` replaces the survey line.
std::string scene(const std::string& extra = "",
                  const std::string& line =
                      "    - {name: l1, waypoints: [{east_m: -25, north_m: -8}, {east_m: 25, "
                      "north_m: -8}]}\n",
                  const std::string& centre = "{lat_deg: -33.8510, lon_deg: 151.2990}") {
  return R"(name: trust
seed: 4
bathymetry:
  generate:
    centre: )" +
         centre + R"(
    size_m: [80, 80]
    cell_m: 0.5
    depth_m: 15
    components:
      - {type: fbm, rms_m: 0.3, wavelength_m: 10, octaves: 3}
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 2.0
  altitude_m: 5
  lines:
)" + line +
         "sonar: {frequency_khz: 600, range_m: 20, samples: 200, tilt_deg: 15}\n"
         "noise: {model: none}\n" +
         extra;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class TrustCli : public test::ScratchDirTest {
 protected:
  /// Names of the entries of the scratch directory.
  std::set<std::string> listing() const {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.insert(e.path().filename().string());
    return out;
  }
  /// Runs `args`, expecting exit 1 with every one of `wanted` in stderr and the scratch directory
  /// exactly as before.
  void expect_named_error(const std::string& args, std::initializer_list<std::string> wanted) {
    const auto before = listing();
    const test::CliResult r = test::run_cli(args, dir_);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    for (const std::string& w : wanted) {
      EXPECT_NE(r.err.find(w), std::string::npos) << "missing '" << w << "' in: " << r.err;
    }
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(": : "), std::string::npos) << "empty key path in: " << r.err;
    EXPECT_EQ(listing(), before) << args;
  }
  /// `simulate` of a scene text, expecting a named error.
  void expect_scene_error(const std::string& text, std::initializer_list<std::string> wanted,
                          const std::string& flags = "") {
    const fs::path s = write("bad.yaml", text);
    expect_named_error("simulate " + s.string() + " -o " + (dir_ / "out").string() + " -q " + flags,
                       wanted);
  }
};

// --seed reaches everything seeded, the generated bathymetry included: simulating the
// effective.yaml of a --seed run gives the same XTF and products byte for byte, and another seed
// gives another seabed (noise is off, so only the bathymetry depends on the seed).
TEST_F(TrustCli, SeedOverrideIsReproducedByEffectiveYaml) {
  const fs::path s = write("s.yaml", scene());
  auto run = [&](const std::string& in, const std::string& out, const std::string& flags) {
    const auto r =
        test::run_cli("simulate " + in + " -o " + (dir_ / out).string() + " -q " + flags, dir_);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  };
  run(s.string(), "a", "--seed 77 --no-waterfall --res 0.5");
  // The product options are not scene settings: effective.yaml lists them to be given again.
  const std::string effective = bytes_of(dir_ / "a" / "effective.yaml");
  const std::string tag = "# product options:";
  const auto at = effective.find(tag);
  ASSERT_NE(at, std::string::npos) << effective;
  const std::string flags =
      effective.substr(at + tag.size(), effective.find('\n', at) - at - tag.size());
  EXPECT_EQ(flags, " --no-waterfall --res 0.5");
  run((dir_ / "a" / "effective.yaml").string(), "b", flags);
  run(s.string(), "c", "--seed 78 --no-waterfall --no-mosaic --no-truth");
  for (const char* f : {"l1.xtf", "l1_truth.tif", "mosaic.tif", "truth_mosaic.tif"}) {
    const std::string a = bytes_of(dir_ / "a" / f), b = bytes_of(dir_ / "b" / f);
    EXPECT_GT(a.size(), 1000u) << f;
    EXPECT_TRUE(a == b) << f << " differs between the --seed run and its effective.yaml";
  }
  EXPECT_FALSE(bytes_of(dir_ / "a" / "l1.xtf") == bytes_of(dir_ / "c" / "l1.xtf"))
      << "--seed 78 gave the XTF of --seed 77: the seed does not reach the bathymetry";
}

// Lines along the equator and along the prime meridian simulate; every ping reads back with a
// valid position within a millimetre of its line.
TEST_F(TrustCli, EquatorAndPrimeMeridianSurveysSimulate) {
  const std::string lines =
      "    - {name: eq, waypoints: [{lat_deg: 0, lon_deg: 0.0001}, {lat_deg: 0, lon_deg: "
      "0.0005}]}\n"
      "    - {name: gw, waypoints: [{lat_deg: 0.0001, lon_deg: 0}, {lat_deg: 0.0005, lon_deg: "
      "0}]}\n";
  const fs::path s = write("s.yaml", scene("", lines, "{lat_deg: 0.0003, lon_deg: 0.0003}"));
  const auto r = test::run_cli("simulate " + s.string() + " -o " + (dir_ / "o").string() +
                                   " -q --no-mosaic --no-truth --no-waterfall",
                               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"eq.xtf", "gw.xtf"}) {
    xtf::Reader reader(dir_ / "o" / name);
    xtf::Packet p;
    std::size_t pings = 0;
    while (reader.next(p)) {
      if (p.kind != xtf::PacketKind::kPing) continue;
      ++pings;
      EXPECT_TRUE(p.ping.nav_valid) << name << " ping " << pings;
      const double off_deg =
          name[0] == 'e' ? p.ping.header.SensorYcoordinate : p.ping.header.SensorXcoordinate;
      EXPECT_LT(std::abs(off_deg) * 111320.0, 1e-3) << name;
    }
    EXPECT_GT(pings, 10u) << name;
  }
}

// A long line: the waterfall CLI decimates along track to fit --max-pixels and says so.
TEST_F(TrustCli, WaterfallOfALongLineIsDecimatedNotRefused) {
  const fs::path xtf_path = dir_ / "long.xtf";
  {
    xtf::Writer w(xtf_path);
    for (std::uint32_t i = 0; i < 601; ++i) w.write_ping(xtf::test::make_ping(i, 16, 16));
    w.close();
  }
  const auto r = test::run_cli("waterfall " + xtf_path.string() + " -o " +
                                   (dir_ / "w.png").string() + " --grey --max-pixels 3200",
                               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 32 columns: room for 100 rows; 601 pings need 7 per row -> ceil(601 / 7) = 86 rows.
  EXPECT_NE(r.out.find("32 x 86 pixels (601 pings decimated along track: each row the mean of 7"),
            std::string::npos)
      << r.out;
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open((dir_ / "w.png").c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(ds->GetRasterXSize(), 32);
  EXPECT_EQ(ds->GetRasterYSize(), 86);
  GDALClose(ds);
}

// simulate keeps a long line: its waterfall is decimated to ceil(pings / N) rows (the row values
// are checked against an independent decimation in waterfall_test.cpp), the run says so, and
// the XTF is written in full.
TEST_F(TrustCli, SimulateDecimatesTheWaterfallOfALongLineAndKeepsTheXtf) {
  const fs::path s = write("s.yaml", scene());
  const auto r = test::run_cli("simulate " + s.string() + " -o " + (dir_ / "o").string() +
                                   " --no-mosaic --no-truth --waterfall-max-pixels 40000",
                               dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::size_t pings = 0;
  {
    xtf::Reader reader(dir_ / "o" / "l1.xtf");
    xtf::Packet p;
    while (reader.next(p)) pings += p.kind == xtf::PacketKind::kPing ? 1 : 0;
  }
  // 400 columns: room for 100 rows.
  ASSERT_GT(pings, 100u);
  const std::size_t n = (pings + 99) / 100, rows = (pings + n - 1) / n;
  EXPECT_NE(r.out.find("l1_waterfall.png: " + std::to_string(pings) +
                       " pings decimated along track, each row the mean of " + std::to_string(n) +
                       " pings"),
            std::string::npos)
      << r.out;
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open((dir_ / "o" / "l1_waterfall.png").c_str(),
                                      GDAL_OF_RASTER | GDAL_OF_READONLY);
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(ds->GetRasterXSize(), 400);
  EXPECT_EQ(static_cast<std::size_t>(ds->GetRasterYSize()), rows);
  GDALClose(ds);
  // A limit below one ping's row is refused before rendering.
  expect_named_error(
      "simulate " + s.string() + " -o " + (dir_ / "o2").string() + " -q --waterfall-max-pixels 399",
      {"waterfall max pixels = 399", "2 x samples = 400 pixels"});
}

// YAML that used to end in an internal error (exit 3) names the file, the key path and value.
TEST_F(TrustCli, MalformedYamlValuesAreNamedErrors) {
  expect_scene_error(scene("? [a, b]\n: 1\n"),
                     {"bad.yaml: key", "complex YAML keys are not supported"});
  expect_scene_error(scene("",
                           "    - {name: l1, waypoints: [{lat_deg: null, lon_deg: 151.299}, "
                           "{lat_deg: -33.851, lon_deg: 151.2995}]}\n"),
                     {"bad.yaml: survey.lines[0].waypoints[0].lat_deg: missing"});
  expect_scene_error(
      scene("",
            "    - {name: l1, waypoints: [{east_m: 0, north_m: ~}, {east_m: 5, north_m: 0}]}\n"),
      {"bad.yaml: survey.lines[0].waypoints[0].north_m: missing"});
  expect_scene_error(scene("seabed:\n  polygons:\n    - {material: rock, coordinates_deg: "
                           "[[-33.851, 151.299], [-33.852, 151.299], [-33.8505, 151.2995]], "
                           "holes_deg: 5}\n"),
                     {"bad.yaml: seabed.polygons[0].holes_deg = '5'. Violated constraint"});
  std::string null_altitude = scene();
  null_altitude.replace(null_altitude.find("altitude_m: 5"), 13, "altitude_m: null");
  expect_scene_error(null_altitude, {"bad.yaml: survey.altitude_m = null. Violated constraint"});
  std::string table = scene();
  table.replace(table.find("tilt_deg: 15}"), 13,
                "tilt_deg: 15, vertical_beam: {shape: table, off_axis_deg: [0, abc, 40], "
                "gain_db: [0, -3, -20]}}");
  expect_scene_error(table, {"bad.yaml: sonar.vertical_beam.off_axis_deg[1] = 'abc'",
                             "Violated constraint: a finite number"});
  expect_scene_error(scene("seabed:\n  polygons:\n    - {material: rock, coordinates_deg: "
                           "[[-33.851, 151.299], [null, 151.2995], [-33.8505, 151.2995]]}\n"),
                     {"bad.yaml: seabed.polygons[0].coordinates_deg[1][0] = null"});
  expect_scene_error(
      scene("seabed:\n  polygons:\n    - {material: rock, coordinates_deg: "
            "[[-33.851, 151.299], [-33.852, .nan], [-33.8505, 151.2995]]}\n"),
      {"bad.yaml: seabed.polygons[0].coordinates_deg[1][1] = '.nan'", "a finite number"});
  write("far.geojson",
        R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties":)"
        R"( {"name": "far"}, "geometry": {"type": "LineString", "coordinates":)"
        R"( [[151.299, -33.851], [166.299, -33.851]]}}]})");
  expect_scene_error(scene("", "    - {file: far.geojson}\n"),
                     {"far.geojson: line 'far' vertex (", ") in EPSG:32756 is",
                      "from the bathymetry grid's centre. Violated constraint: <= 1e6 m"});
  fs::remove(dir_ / "far.geojson");
  expect_scene_error(scene("",
                           "    - {name: l1, waypoints: [{east_m: -1e7, north_m: 0}, {east_m: "
                           "1e7, north_m: 0}]}\n"),
                     {"bad.yaml: survey.lines[0].waypoints[0].east_m = '-1e7'", "|east_m| <= 1e6"});
  std::string huge = scene();
  huge.replace(huge.find("size_m: [80, 80]"), 16, "size_m: [4e4, 4e4]");
  expect_scene_error(
      huge, {"bad.yaml: bathymetry.generate: bathymetry generator: grid of 40000 m x 40000 m",
             "80000 x 80000 = 6400000000 cells", "cells <= 268435456"});
}

// Values that reach the program by other routes: a vector layer's attribute, a section whose keys
// are not checked (copied into effective.yaml), the bathy command's grid size.
TEST_F(TrustCli, LayerAttributesUncheckedSectionsAndBathyGridsFailByName) {
  write("objs.geojson",
        R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties":)"
        R"( {"type": "box", "size_m": "[1, 2"}, "geometry": {"type": "Point", "coordinates":)"
        R"( [151.299, -33.851]}}]})");
  expect_scene_error(scene("objects:\n  - {file: objs.geojson}\n"),
                     {"objs.geojson feature 0: size_m = '[1, 2'"});
  fs::remove(dir_ / "objs.geojson");
  // A complex key where keys are not checked is copied into effective.yaml, not an internal
  // error after the rendering.
  const fs::path s = write("s.yaml", scene("description: {? [a, b] : 1}\n"));
  const auto r = test::run_cli("simulate " + s.string() + " -o " + (dir_ / "o").string() +
                                   " -q --no-mosaic --no-truth --no-waterfall",
                               dir_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "o" / "effective.yaml"));
  expect_named_error("bathy -q -o " + (dir_ / "big.tif").string() +
                         " --lat 10 --lon 10 --size 40000x40000 --cell 0.5",
                     {"80000 x 80000 = 6400000000 cells", "cells <= 268435456"});
}

// Command-line overrides are named by their flag, not blamed on the scene file.
TEST_F(TrustCli, OverrideErrorsNameTheFlag) {
  expect_scene_error(scene(), {"--range = 0. Violated constraint: > 0", "sonar.range_m"},
                     "--range=0");
  expect_scene_error(scene(), {"--samples = 0. Violated constraint: >= 1", "sonar.samples"},
                     "--samples 0");
  expect_scene_error(scene(), {"--seed = '-1'. Violated constraint: an integer from 0"},
                     "--seed=-1");
}

// mosaic: a display copy whose name is not a format we write, creation options GDAL does not
// accept, and a --bathymetry that misses the survey are named before anything is written.
TEST_F(TrustCli, MosaicOptionErrorsAreNamedAndWriteNothing) {
  const fs::path golden = fs::path(SONARSYNTH_TEST_DATA_DIR) / "xtf" / "golden-tiny.xtf";
  const std::string base = "mosaic " + golden.string() + " -o " + (dir_ / "m.tif").string();
  expect_named_error(base + " --rgb " + (dir_ / "x.jpg").string(),
                     {(dir_ / "x.jpg").string(), "unsupported extension", ".png (PNG)"});
  expect_named_error(base + " --co COMPRESS=NOPE", {"COMPRESS=NOPE", "COG driver"});
  expect_named_error(base + " --of GTiff --co NOT_AN_OPTION=1", {"NOT_AN_OPTION=1", "GTiff"});
  // A bathymetry 60 km from the two pings of the golden file (48.5 N, 68.75 W).
  auto r = test::run_cli("bathy -q -o " + (dir_ / "far.tif").string() +
                             " --lat 48.0 --lon -68.75 --size 100x100 --cell 2",
                         dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_named_error(base + " --bathymetry " + (dir_ / "far.tif").string(),
                     {"--bathymetry " + (dir_ / "far.tif").string(), "does not overlap the survey",
                      "no ping could be gridded"});
  expect_named_error("bathy -q -o " + (dir_ / "b.tif").string() +
                         " --lat 10 --lon 10 --size 20x20 --cell 1 --co COMPRESS=NOPE",
                     {"bathy: creation option COMPRESS=NOPE is not valid for the GTiff driver"});
  expect_named_error("bathy -q -o " + (dir_ / "b.tif").string() +
                         " --lat 10 --lon 10 --size 20x20 --cell 1 --seed=-1",
                     {"--seed = '-1'. Violated constraint"});
  // simulate refuses bad creation options before rendering anything.
  expect_scene_error(scene(), {"COMPRESS=NOPE", "COG driver"}, "--co COMPRESS=NOPE");
}

// `--version` names the vector kernels' instruction set; SONARSYNTH_SIMD caps it, and a value
// outside the list is a named error (exit 1), never a silent fallback.
TEST_F(TrustCli, VersionNamesTheVectorKernelsAndTheirCap) {
  ::unsetenv("SONARSYNTH_SIMD");
  const test::CliResult plain = test::run_cli("--version", dir_);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_NE(plain.out.find("vector kernels: "), std::string::npos) << plain.out;
  ::setenv("SONARSYNTH_SIMD", "scalar", 1);
  const test::CliResult scalar = test::run_cli("--version", dir_);
  EXPECT_EQ(scalar.exit_code, 0) << scalar.err;
  EXPECT_NE(scalar.out.find("vector kernels: scalar"), std::string::npos) << scalar.out;
  ::setenv("SONARSYNTH_SIMD", "sse9", 1);
  const test::CliResult bad = test::run_cli("--version", dir_);
  ::unsetenv("SONARSYNTH_SIMD");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("SONARSYNTH_SIMD = 'sse9'"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace sonarsynth
