// SPDX-License-Identifier: MIT
// `sonarsynth simulate` checks the whole run before rendering: one test per failure mode, each
// asserting the exit code, the message (file, key or line, value) and that no output directory
// appears; warnings (lines partly off the grid, saturation) with fractions computed here from
// the geometry, and the flagged pings counted by `sonarsynth info`.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "cli_test_util.hpp"
#include "sonarsynth/formats/config/run_check.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

// A flat seabed 20 m deep on a 100 m x 100 m grid of 1 m cells centred on the scene's origin;
// positions are metres east/north of the grid centre. One ping per metre (2 m/s, 0.5 s).
struct SceneText {
  std::string bathymetry =
      "generate: {centre: {lat_deg: 57.05, lon_deg: 11.20}, size_m: [100, 100], cell_m: 1, "
      "depth_m: 20}";
  std::string vertical = "altitude_m: 10";
  std::string speed = "2.0";
  std::string lines =
      "    - {name: a, waypoints: [{east_m: -10, north_m: 0}, {east_m: 10, "
      "north_m: 0}]}\n";
  std::string sonar = "{frequency_khz: 400, range_m: 30, samples: 300, ping_period_s: 0.5}";
  std::string output = "{}";
  std::string noise = "{model: none}";
  std::string extra;
  std::string yaml() const {
    return "name: checks\nseed: 3\nbathymetry:\n  " + bathymetry +
           "\nsurvey:\n  speed_m_s: " + speed + "\n  " + vertical + "\n  lines:\n" + lines +
           "sonar: " + sonar + "\nnoise: " + noise + "\noutput: " + output + "\n" + extra;
  }
};

std::string line(const std::string& name, double e0, double n0, double e1, double n1) {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "    - {name: %s, waypoints: [{east_m: %g, north_m: %g}, {east_m: %g, north_m: "
                "%g}]}\n",
                name.c_str(), e0, n0, e1, n1);
  return buf;
}

// The percentage printed right after `prefix` in `text`, or NaN.
double percent_after(const std::string& text, const std::string& prefix) {
  const auto at = text.find(prefix);
  if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  return std::strtod(text.c_str() + at + prefix.size(), nullptr);
}

// A GeoTIFF (EPSG 32632, square cells, north-up) of `cols` x `rows` float heights.
void write_tif(const fs::path& p, int cols, int rows, const std::vector<float>& heights,
               double cell_m = 1.0) {
  GDALAllRegister();
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = drv->Create(p.c_str(), cols, rows, 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {500000.0, cell_m, 0.0, 6300000.0, 0.0, -cell_m};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(32632);
  ds->SetSpatialRef(&srs);
  ASSERT_EQ(
      ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, cols, rows, const_cast<float*>(heights.data()),
                                     cols, rows, GDT_Float32, 0, 0),
      CE_None);
  GDALClose(ds);
}

class RunCheck : public test::ScratchDirTest {
 protected:
  test::CliResult simulate(const SceneText& s, const std::string& options = "") {
    const fs::path scene = write("scene.yaml", s.yaml());
    return test::run_cli("simulate " + scene.string() + " -o " + out().string() +
                             " -q --no-mosaic --no-waterfall --no-truth " + options,
                         dir_);
  }
  // Refused: exit 1, every fragment in the message, and nothing created.
  void expect_refused(const SceneText& s, const std::vector<std::string>& fragments,
                      const std::string& options = "") {
    const auto r = simulate(s, options);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    for (const auto& f : fragments)
      EXPECT_NE(r.err.find(f), std::string::npos) << f << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out()));
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      EXPECT_TRUE(n == "scene.yaml" || n.ends_with(".tif")) << n;
    }
  }
  fs::path out() const { return dir_ / "out"; }
};

TEST_F(RunCheck, TheBaseSceneRuns) {
  const auto r = simulate(SceneText{});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_TRUE(fs::exists(out() / "a.xtf"));
}

TEST_F(RunCheck, TheEstimateBoundsTheFileWrittenAndCreatesNothing) {
  const fs::path scene = write("scene.yaml", SceneText{}.yaml());
  const SimulationSetup setup = load_simulation(scene.string());
  const RunPlan plan = check_simulation(scene.string(), setup, {false, false, false, 0.25}, out());
  EXPECT_FALSE(fs::exists(out()));
  // x = -10 .. 10 m, a ping every metre.
  EXPECT_EQ(plan.total_pings, 21u);
  ASSERT_EQ(plan.lines.size(), 1u);
  EXPECT_EQ(plan.lines[0].seabed_fraction, 1.0);
  EXPECT_EQ(plan.lines[0].short_range_fraction, 0.0);
  EXPECT_TRUE(plan.warnings.empty());
  // With the products off the estimate is the XTF file: an upper bound, short of it by at most
  // the file header and notes.
  ASSERT_EQ(simulate(SceneText{}).exit_code, 0);
  const auto size = fs::file_size(out() / "a.xtf");
  EXPECT_LE(size, plan.output_bytes);
  EXPECT_GT(size + 4096, plan.output_bytes);
}

TEST_F(RunCheck, ALineOffTheGridIsRefusedNamingTheLineAndBothExtents) {
  SceneText s;
  s.lines = line("faraway", 200, 0, 260, 0);
  expect_refused(s, {"scene.yaml: survey line 'faraway': no ping is over valid seabed",
                     "sensor track spans east 200 .. 260 m", "grid spans east -49.5 .. 49.5 m"});
  // With the products on too (before, only the mosaic complained).
  const auto r = test::run_cli(
      "simulate " + (dir_ / "scene.yaml").string() + " -o " + out().string() + " -q", dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("survey line 'faraway': no ping"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(RunCheck, ALineHalfOffTheGridWarnsWithTheFractionAndFlagsThePingsInTheXtf) {
  SceneText s;
  s.lines = line("half", 0, 0, 100, 0);  // the grid ends 50 m east of its centre
  const auto r = simulate(s);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Pings at x = 0, 1, ..., 100; the grid's nodes end at x = 49.5 (100 cells of 1 m): the 51
  // pings at x = 50 .. 100 are off it.
  const double off = percent_after(r.err, "survey line 'half': ");
  EXPECT_NEAR(off, 100.0 * 51.0 / 101.0, 0.1) << r.err;
  EXPECT_NE(r.err.find("not over valid seabed"), std::string::npos) << r.err;
  // The XTF carries them with altitude 0 (no made-up altitude) and `info` counts them.
  const auto info = test::run_cli("info " + (out() / "half.xtf").string(), dir_);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(info.out.find("Anomalies: none"), std::string::npos) << info.out;
  const auto at = info.out.find("pings_without_altitude: ");
  ASSERT_NE(at, std::string::npos) << info.out;
  const long n = std::strtol(info.out.c_str() + at + 24, nullptr, 10);
  EXPECT_EQ(n, 51);
  xtf::Reader reader(out() / "half.xtf");
  xtf::Packet packet;
  long zero = 0, below_one_metre = 0;
  while (reader.next(packet)) {
    if (packet.kind != xtf::PacketKind::kPing) continue;
    const float alt = packet.ping.header.SensorPrimaryAltitude;
    zero += alt == 0.0f;
    below_one_metre += alt > 0.0f && alt < 1.0f;
  }
  EXPECT_EQ(zero, n);
  EXPECT_EQ(below_one_metre, 0);
}

TEST_F(RunCheck, ALaybackThatPutsTheSensorOffTheGridIsRefused) {
  SceneText s;
  s.vertical = "altitude_m: 10\n  layback_m: 10000";
  expect_refused(s, {"survey line 'a': no ping is over valid seabed",
                     "sensor track spans east -10010 .. -9990 m"});
}

TEST_F(RunCheck, ATinyRasterUnderALineIsReportedWithTheFractionOffIt) {
  // 2 x 2 nodes 1 um apart at the centre: of the pings at x = -10, -9, ..., 10 m only the one at
  // x = 0 is over it. (Before, every ping's profile held 30 m / 1 um points: gigabytes.)
  write_tif(dir_ / "tiny.tif", 2, 2, std::vector<float>(4, -20.0f), 1e-6);
  SceneText s;
  s.bathymetry = "file: tiny.tif";
  const auto r = simulate(s, "--threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(percent_after(r.err, "survey line 'a': "), 100.0 * 20.0 / 21.0, 0.1) << r.err;
  s.lines = line("beside", -10, 5, 10, 5);
  fs::remove_all(out());
  expect_refused(s, {"survey line 'beside': no ping is over valid seabed"});
}

TEST_F(RunCheck, AltitudeAboveTheWaterDepthIsRefused) {
  SceneText s;
  s.vertical = "altitude_m: 25";  // 20 m of water
  expect_refused(s, {"survey line 'a': survey.altitude_m = 25 puts the sensor above the sea "
                     "surface"});
}

TEST_F(RunCheck, DepthBelowTheSeabedIsRefused) {
  SceneText s;
  s.vertical = "depth_m: 30";
  expect_refused(
      s, {"survey line 'a': survey.depth_m = 30 puts the sensor below the seabed", "100.0 %"});
}

TEST_F(RunCheck, ASeabedAboveSeaLevelIsRefused) {
  // Dry under the line, 20 m deep in the southern fifth of the grid: the line is refused.
  std::vector<float> heights(100 * 100, 5.0f);
  std::fill(heights.begin() + 80 * 100, heights.end(), -20.0f);
  write_tif(dir_ / "dry.tif", 100, 100, heights);
  SceneText s;
  s.bathymetry = "file: dry.tif";
  expect_refused(s, {"survey line 'a': the seabed is above sea level (height up to 5 m)"});
  // Dry everywhere: no line could be surveyed, so the scene itself is refused.
  write_tif(dir_ / "dry.tif", 100, 100, std::vector<float>(100 * 100, 5.0f));
  expect_refused(s, {"scene.yaml", "bathymetry",
                     "the seabed is above sea level everywhere "
                     "(heights 5 .. 5 m). Violated constraint: bathymetry heights < 0 somewhere"});
}

TEST_F(RunCheck, RangeShorterThanTheAltitudeIsRefusedNamingKeyOrFlag) {
  SceneText s;
  s.sonar = "{frequency_khz: 400, range_m: 5, samples: 300, ping_period_s: 0.5}";
  expect_refused(s, {"scene.yaml: survey line 'a': sonar.range_m = 5 m is not longer than the "
                     "sensor's altitude"});
  expect_refused(SceneText{}, {"--range = 5 m is not longer than the sensor's altitude"},
                 "--range 5");
}

TEST_F(RunCheck, CommandLineOverridesHaveTheScenesBounds) {
  expect_refused(SceneText{}, {"--range = 1000000000", "Violated constraint"}, "--range 1e9");
  expect_refused(SceneText{}, {"--range = -1", "Violated constraint"}, "--range=-1");
  expect_refused(SceneText{}, {"--samples = 0", "Violated constraint"}, "--samples 0");
  expect_refused(SceneText{}, {"--samples = 20000", "output.allow_more_than_8192_samples"},
                 "--samples 20000");
  // The mosaic's pixel size (products on): zero, and so small that the mosaic of 80 m x 60 m
  // (the line and the range either side, within the grid) would need 4.8e15 pixels.
  const fs::path scene = write("scene.yaml", SceneText{}.yaml());
  for (const char* res : {"0", "1e-6"}) {
    const auto r = test::run_cli(
        "simulate " + scene.string() + " -o " + out().string() + " -q --res " + res, dir_);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find(std::string(res) == "0" ? "--res = 0" : "pixels at --res 1e-06 m"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(out()));
  }
}

TEST_F(RunCheck, MoreThan8192SamplesOnlyOnRequest) {
  SceneText s;
  s.sonar = "{frequency_khz: 400, range_m: 30, samples: 20000, ping_period_s: 0.5}";
  expect_refused(s, {"scene.yaml: sonar.samples = '20000'", "<= 8192"});
  s.lines = line("short", 0, 0, 1, 0);
  s.output = "{allow_more_than_8192_samples: true}";
  const auto r = simulate(s);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out() / "short.xtf"));
}

TEST_F(RunCheck, RunawayPingCountsAreRefusedWithTheEstimate) {
  SceneText s;
  s.speed = "1e-9";
  expect_refused(s,
                 {"scene.yaml: the survey would render", "limits.max_pings = 2000000", "line 'a'"});
  s = SceneText{};
  s.sonar = "{frequency_khz: 400, range_m: 0.001, samples: 300}";
  s.vertical = "altitude_m: 0.0005";
  expect_refused(s, {"limits.max_pings"});
  // A ping period shorter than the two-way travel time: 2 x 30 m / 1500 m/s = 0.04 s.
  s = SceneText{};
  s.sonar = "{frequency_khz: 400, range_m: 30, samples: 300, ping_period_s: 1e-9}";
  expect_refused(s, {"scene.yaml: sonar.ping_period_s = '1e-9'", "two-way travel time"});
}

TEST_F(RunCheck, TheLimitsCanBeRaisedOrLowered) {
  // 21 pings (x = -10 .. 10 m every metre): a limit of 20 refuses them, 21 accepts.
  SceneText s;
  s.extra = "limits: {max_pings: 20}\n";
  expect_refused(s, {"would render 21 pings", "limits.max_pings = 20"});
  s.extra = "limits: {max_pings: 21}\n";
  EXPECT_EQ(simulate(s).exit_code, 0);
  fs::remove_all(out());
  // 21 pings of 2 x 300 u16 samples are more than 10 kB.
  s.extra = "limits: {max_output_gb: 1e-5}\n";
  expect_refused(s, {"limits.max_output_gb = 1e-05"});
  s.extra = "limits: {max_memory_gb: 1e-6}\n";
  expect_refused(s, {"limits.max_memory_gb = 1e-06"});
  s.extra = "limits: {max_pings: -3}\n";
  expect_refused(s, {"scene.yaml: limits.max_pings = '-3'"});
}

TEST_F(RunCheck, AnOutputLargerThanTheFreeDiskSpaceIsRefused) {
  // 10^7 pings (100 km at 2 m/s, a ping every 5 ms) of 2 x 8192 u16 samples: at least
  // 10^7 x (256 + 2 x (64 + 16384)) bytes of XTF, with the limits raised out of the way.
  SceneText s;
  s.lines = line("long", 1000, 0, 101000, 0);
  s.sonar = "{frequency_khz: 400, range_m: 3, samples: 8192, ping_period_s: 0.005}";
  s.extra = "limits: {max_pings: 1e8, max_output_gb: 1e6, max_memory_gb: 1e6}\n";
  const double xtf_bytes = 1e7 * (256.0 + 2.0 * (64.0 + 16384.0));
  if (static_cast<double>(fs::space(dir_).available) >= xtf_bytes) {
    GTEST_SKIP() << "more free space than the run would need";
  }
  expect_refused(s, {"scene.yaml: the run would write about", "free. Violated constraint"});
}

TEST_F(RunCheck, GainIsBoundedAndSaturationIsCountedPerLine) {
  SceneText s;
  s.output = "{gain_db: 200}";
  expect_refused(s, {"scene.yaml: output.gain_db = '200'"});
  s.output = "{gain_db: -5000}";
  expect_refused(s, {"scene.yaml: output.gain_db = '-5000'"});
  // 140 dB saturates every sample that holds any echo: on a flat seabed 10 m below the sensor
  // with a 30 m range, the samples beyond the first bottom return, (30 - 10) / 30 of them (the
  // bare echo in intensity: no sensor effects in the water column, no ring-down).
  s.output = "{gain_db: 140, quantity: intensity}";
  s.extra =
      "sensor: {noise_floor_dbfs: off, volume_reverberation_db: off, shadow_fill_db: off, "
      "first_return_reflection_db: off, ring_down_m: off}\n";
  const auto r = simulate(s);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double reported = percent_after(r.err, "survey line 'a': ");
  EXPECT_NEAR(reported, 100.0 * 2.0 / 3.0, 1.0) << r.err;
  EXPECT_NE(r.err.find("saturated at 32767"), std::string::npos) << r.err;
  xtf::Reader reader(out() / "a.xtf");
  xtf::Packet packet;
  double full = 0, total = 0;
  while (reader.next(packet)) {
    if (packet.kind != xtf::PacketKind::kPing) continue;
    for (std::size_t c = 0; c < packet.ping.channel_count; ++c) {
      for (float v : packet.ping.channels[c].samples) {
        full += v == 32767.0f;
        total += 1;
      }
    }
  }
  EXPECT_NEAR(100.0 * full / total, reported, 0.1);
}

// `derived:` with lists of 10 aliases of the level below, `levels` deep: 10^levels leaves.
std::string alias_tower(int levels) {
  std::string t = "derived:\n  l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < levels; ++i) {
    const std::string p = "*l" + std::to_string(i - 1);
    t += "  l" + std::to_string(i) + ": &l" + std::to_string(i) + " [" + p;
    for (int k = 1; k < 10; ++k) t += ", " + p;
    t += "]\n";
  }
  return t;
}

TEST_F(RunCheck, AnAliasBombIsRefusedAndDerivedIsNotCopied) {
  // 10^9 nodes once expanded: refused when the file is read, before any work.
  SceneText s;
  s.extra = alias_tower(9);
  expect_refused(s, {"scene.yaml: the document expands to more than 1000000 nodes"});
  // 10^4: accepted, and `derived` is replaced in effective.yaml, not copied.
  s.extra = alias_tower(4);
  const auto r = simulate(s);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(out() / "effective.yaml");
  const std::string eff((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(eff.find("l3"), std::string::npos);
  EXPECT_NE(eff.find("derived"), std::string::npos);
}

TEST_F(RunCheck, AbsurdRasterHeightsAreNodata) {
  // 4 x 4 nodes at -20 m but for +inf, -inf, 1e38 and -3.4e38 (undeclared nodata markers).
  std::vector<float> h(16, -20.0f);
  h[1] = std::numeric_limits<float>::infinity();
  h[6] = -std::numeric_limits<float>::infinity();
  h[11] = 1e38f;
  h[14] = -3.4e38f;
  write_tif(dir_ / "marks.tif", 4, 4, h);
  const LoadedGrid g = read_height_grid((dir_ / "marks.tif").string());
  EXPECT_EQ(g.valid_count, 12u);
  const auto& z = g.grid.heights();
  for (std::size_t i = 0; i < 16; ++i) {
    if (i == 1 || i == 6 || i == 11 || i == 14) {
      EXPECT_TRUE(std::isnan(z[i])) << i;
    } else {
      EXPECT_EQ(z[i], -20.0f) << i;
    }
  }
}

}  // namespace
}  // namespace sonarsynth
