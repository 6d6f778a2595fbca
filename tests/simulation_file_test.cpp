// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/simulation_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

class SimulationFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sonarsynth_simfile_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

const char* kScene = R"(
seed: 12
bathymetry:
  generate: {centre: {lat_deg: 48.45, lon_deg: -68.83}, size_m: [200, 200], cell_m: 1, depth_m: 30}
sonar: {frequency_khz: 300, range_m: 50, samples: 2000, pulse: {type: chirp, bandwidth_khz: 50}}
render: {backscatter: lambert, absorption: false, quality: {gauss_points: 3, along_track_planes: 3}}
noise: {model: paper, uniform_half_width: 0.2}
output: {tvg: none, gain_db: 12, sample_format: u8}
)";

TEST_F(SimulationFile, ReadsEverySectionAndSurveyLinesFromAVectorFile) {
  write("lines.geojson", R"({"type": "FeatureCollection",
 "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}},
 "features": [{"type": "Feature", "properties": {"name": "track-7"},
   "geometry": {"type": "LineString", "coordinates": [[-68.8305, 48.4495], [-68.8295, 48.4505]]}}]})");
  const std::string path = write("s.yaml", std::string(kScene) + R"(
survey:
  start_time: "2013-09-10T21:13:08.25Z"
  speed_m_s: 1.5
  depth_m: 25
  layback_m: 20
  disturbance: {roll_deg: 2}
  lines:
    - {file: lines.geojson}
)");
  const SimulationSetup s = load_simulation(path);
  ASSERT_EQ(s.lines.size(), 1u);
  EXPECT_EQ(s.lines[0].name, "track-7");
  const Geodetic a = s.scene.frame.geodetic_from_local(s.lines[0].waypoints_xy_m.front());
  EXPECT_NEAR(deg_from_rad(a.lon_rad), -68.8305, 1e-9);
  EXPECT_NEAR(deg_from_rad(a.lat_rad), 48.4495, 1e-9);
  EXPECT_EQ(format_utc(s.start_time), "2013-09-10T21:13:08.250000Z");
  EXPECT_EQ(s.vehicle.depth_mode, VehicleConfig::DepthMode::kDepth);
  EXPECT_DOUBLE_EQ(s.vehicle.layback_m, 20.0);
  EXPECT_NEAR(s.vehicle.disturbance.roll_amplitude_rad, rad_from_deg(2.0), 1e-15);
  EXPECT_NEAR(s.reference_altitude_m, 5.0, 0.2);  // 30 m deep seabed, 25 m depth
  EXPECT_EQ(s.config.seed, 12u);
  EXPECT_DOUBLE_EQ(s.config.sonar.frequency_hz, 300e3);
  EXPECT_EQ(s.config.sonar.pulse, SonarConfig::Pulse::kChirp);
  EXPECT_NEAR(s.config.sonar.pulse_window_m(), 1500.0 / (2 * 50e3), 1e-12);
  EXPECT_EQ(s.config.physics.backscatter, BackscatterModel::lambert);
  EXPECT_FALSE(s.config.physics.absorption);
  EXPECT_EQ(s.config.quality.along_track_planes, 3);
  EXPECT_EQ(s.config.noise.model, NoiseConfig::Model::kPaper);
  EXPECT_EQ(s.config.output.tvg, TvgLaw::none);
  EXPECT_DOUBLE_EQ(s.config.output.gain_db, 12.0);
  EXPECT_DOUBLE_EQ(s.config.output.max_value, 255.0);
  EXPECT_EQ(s.sample_format, "u8");
}

TEST_F(SimulationFile, OverridesWin) {
  const std::string path = write("s.yaml", std::string(kScene) + R"(
survey: {lines: [{name: a, waypoints: [{east_m: -50, north_m: 0}, {east_m: 50, north_m: 0}]}]}
)");
  SimulationOverrides ov;
  ov.seed = 99;
  ov.range_m = 30.0;
  ov.samples = 512;
  ov.quality = "high";
  ov.threads = 1;
  const SimulationSetup s = load_simulation(path, ov);
  EXPECT_EQ(s.config.seed, 99u);
  EXPECT_DOUBLE_EQ(s.config.sonar.max_range_m, 30.0);
  EXPECT_EQ(s.config.sonar.samples_per_channel, 512u);
  EXPECT_EQ(s.config.quality.gauss_points, 3);
  EXPECT_EQ(s.config.threads, 1u);
}

TEST_F(SimulationFile, AlongTrackPlanesAreAutomaticByDefaultOrACount) {
  std::string scene = kScene;
  scene.erase(scene.find("render:"), scene.find("noise:") - scene.find("render:"));
  const std::string survey = scene +
                             "survey: {lines: [{name: a, waypoints: [{east_m: 0, north_m: 0}, "
                             "{east_m: 9, north_m: 0}]}]}\n";
  auto load = [&](const std::string& render, const SimulationOverrides& ov = {}) {
    return load_simulation(write("q.yaml", survey + render), ov).config.quality;
  };
  QualityConfig q = load("");
  EXPECT_EQ(q.along_track_planes, QualityConfig::kAutoPlanes);
  EXPECT_DOUBLE_EQ(q.along_track_tolerance_db, 1.0);
  q = load("render: {quality: {along_track_planes: auto, along_track_tolerance_db: 0.5}}\n");
  EXPECT_EQ(q.along_track_planes, QualityConfig::kAutoPlanes);
  EXPECT_DOUBLE_EQ(q.along_track_tolerance_db, 0.5);
  EXPECT_EQ(load("render: {quality: {along_track_planes: 7}}\n").along_track_planes, 7);
  SimulationOverrides fast;
  fast.quality = "fast";
  EXPECT_EQ(load("", fast).along_track_planes, 1);
  SimulationOverrides high;
  high.quality = "high";
  q = load("render: {quality: {along_track_planes: 2}}\n", high);
  EXPECT_EQ(q.along_track_planes, QualityConfig::kAutoPlanes);
  EXPECT_DOUBLE_EQ(q.along_track_tolerance_db, 0.25);
  for (const auto& [render, fragment] :
       {std::pair<std::string, std::string>{"render: {quality: {along_track_planes: many}}\n",
                                            "render.quality.along_track_planes = 'many'"},
        {"render: {quality: {along_track_planes: 0}}\n", "render.quality.along_track_planes = '0'"},
        {"render: {quality: {along_track_tolerance_db: 0}}\n",
         "render.quality.along_track_tolerance_db = '0'"},
        {"render: {shadows: true}\nrender: {shadows: false}\n", "render: duplicate key (line"}}) {
    try {
      load(render);
      ADD_FAILURE() << "no error for " << render;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
}

TEST_F(SimulationFile, TimesRoundTripAndBadValuesAreNamed) {
  EXPECT_EQ(format_utc(parse_utc("2026-11-21T09:34:00Z", "t")), "2026-11-21T09:34:00.000000Z");
  EXPECT_EQ(format_utc(parse_utc("2024-02-29T23:59:59.999999Z", "t")),
            "2024-02-29T23:59:59.999999Z");
  EXPECT_THROW(parse_utc("2023-02-29T00:00:00Z", "t"), InputError);  // not a leap year
  EXPECT_THROW(parse_utc("2026-11-21 09:34:00", "t"), InputError);
  EXPECT_THROW(parse_utc("1969-12-31T23:59:59Z", "t"), InputError);
  const std::string base =
      std::string(kScene) +
      "survey: {lines: [{name: a, waypoints: [{east_m: 0, north_m: 0}, {east_m: 9, north_m: 0}]}]";
  auto expect = [&](const std::string& extra, const char* fragment) {
    const std::string path = write("bad.yaml", base + extra + "}\n");
    try {
      load_simulation(path);
      ADD_FAILURE() << "no error for " << extra;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect(", speed_m_s: 0", "survey.speed_m_s = '0'");
  expect(", altitude_m: 5, depth_m: 5", "altitude_m or depth_m");
  expect(", start_time: yesterday", "survey.start_time = 'yesterday'");
  expect(", turn_radius_m: -1", "survey.turn_radius_m = '-1'");
  const std::string dup =
      write("dup.yaml",
            std::string(kScene) +
                "survey: {lines: [{name: a, waypoints: [{east_m: 0, north_m: 0}, {east_m: 9, "
                "north_m: 0}]},"
                " {name: a, waypoints: [{east_m: 0, north_m: 5}, {east_m: 9, north_m: 5}]}]}\n");
  EXPECT_THROW(load_simulation(dup), InputError);
  const std::string bad_name =
      write("name.yaml", std::string(kScene) +
                             "survey: {lines: [{name: ../escape, waypoints: [{east_m: 0, north_m: "
                             "0}, {east_m: 9, north_m: 0}]}]}\n");
  EXPECT_THROW(load_simulation(bad_name), InputError);
}

}  // namespace
}  // namespace sonarsynth
