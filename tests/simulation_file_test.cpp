// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/simulation_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "simulation_file_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/option_table.hpp"

namespace sonarsynth {
namespace {

using namespace simulation_file_test;

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

// The founding paper's knobs: gamma (uniform_variance) instead of the half-width, never both;
// K = 1/Imax and the linear display.
TEST_F(SimulationFile, PaperNoiseVarianceNormalisationAndDisplay) {
  const std::string head = std::string(kBathy) + "survey:\n" + kLine;
  const SimulationSetup s = load_simulation(
      write("p.yaml", head + "noise: {model: paper, uniform_variance: 0.03}\n"
                             "output: {normalise: per_ping_max, display: linear}\n"));
  EXPECT_EQ(s.config.noise.paper_uniform_variance, 0.03);
  EXPECT_EQ(s.config.output.normalise, OutputScaling::Normalise::per_ping_max);
  EXPECT_TRUE(s.display_linear);
  const SimulationSetup old =
      load_simulation(write("o.yaml", head + "noise: {model: paper, uniform_half_width: 0.4}\n"));
  EXPECT_EQ(old.config.noise.paper_uniform_half_width, 0.4);
  EXPECT_TRUE(std::isnan(old.config.noise.paper_uniform_variance));
  auto expect = [&](const std::string& extra, std::vector<const char*> fragments) {
    const std::string path = write("bad.yaml", head + extra);
    try {
      load_simulation(path);
      ADD_FAILURE() << "no error for " << extra;
    } catch (const InputError& e) {
      for (const char* f : fragments) {
        EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
      }
    }
  };
  expect("noise: {model: paper, uniform_variance: 0.03, uniform_half_width: 0.3}\n",
         {"bad.yaml", "noise.uniform_variance", "not both"});
  expect("noise: {uniform_variance: 0.5}\n",
         {"bad.yaml", "noise.uniform_variance = '0.5'", "<= 0.333"});
  expect("noise: {uniform_variance: -0.1}\n", {"noise.uniform_variance = '-0.1'"});
  expect("output: {normalise: per_ping}\n",
         {"output.normalise = 'per_ping'", "none or per_ping_max"});
  expect("output: {display: log}\n", {"output.display = 'log'", "db or linear"});
}

// samples/paper_exact.yaml is the paper's model where the paper is explicit (docs/paper-model.md).
TEST_F(SimulationFile, PaperExactSampleIsThePapersModel) {
  const SimulationSetup s = load_simulation(SONARSYNTH_SAMPLES_DIR "/paper_exact.yaml");
  const SimulationConfig& c = s.config;
  EXPECT_EQ(c.physics.backscatter, BackscatterModel::paper);
  const Material& sand = s.scene.materials[s.scene.material_map.default_material()];
  EXPECT_EQ(sand.paper_reflectivity, 0.5);  // R = 0.5
  EXPECT_EQ(c.sonar.vertical_beam.shape, VerticalBeamShape::paper_sine_pair);
  EXPECT_FALSE(c.physics.absorption);
  EXPECT_EQ(c.noise.model, NoiseConfig::Model::kPaper);
  EXPECT_FALSE(std::isnan(c.noise.paper_uniform_variance));
  EXPECT_EQ(c.output.normalise, OutputScaling::Normalise::per_ping_max);
  EXPECT_TRUE(s.display_linear);
  EXPECT_FALSE(s.scene.objects.empty());  // the pipes and rocks
  EXPECT_EQ(s.lines.size(), 1u);
}

TEST_F(SimulationFile, SensorAndCountValuesOutOfRangeAreNamedErrors) {
  const std::string head = std::string(kBathy) + "survey:\n" + kLine +
                           "sonar: {frequency_khz: 400, range_m: 20, samples: 1000}\n";
  for (const auto& [extra, fragment] :
       {std::pair<std::string, std::string>{"output: {detector_sub_samples: 2.5}\n",
                                            "output.detector_sub_samples = '2.5'"},
        {"limits: {max_pings: 100.5}\n", "limits.max_pings = '100.5'"},
        {"sensor: {volume_reverberation_db: 3}\n", "sensor.volume_reverberation_db = '3'"},
        {"sensor: {shadow_fill_db: 1}\n", "sensor.shadow_fill_db = '1'"},
        {"output: {seabed_median_dbfs: -200}\n", "output.seabed_median_dbfs = '-200'"},
        {"sensor: {ring_down_m: 2.5}\n", "ring_down_m <= a tenth of the range"}}) {
    try {
      load_simulation(write("bad.yaml", head + extra));
      ADD_FAILURE() << "no error for " << extra;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
  // The bounds themselves are accepted.
  EXPECT_NO_THROW(load_simulation(write(
      "ok.yaml", head +
                     "sensor: {ring_down_m: 2, volume_reverberation_db: 0, shadow_fill_db: off}\n"
                     "output: {detector_sub_samples: 16, seabed_median_dbfs: -80}\n")));
}

// A pulse type switched away from the preset's needs its own length or bandwidth: a chirp preset
// switched to CW would otherwise be silently one sample long.
// f32 samples hold the counts of the u16 profile, unrounded, with the automatic gain: the same
// image as u16 (docs/xtf.md), not values near the float maximum.
TEST_F(SimulationFile, Float32SamplesHoldTheU16CountsUnrounded) {
  const std::string body = std::string(kBathy) + "survey:\n" + kLine;
  const SimulationSetup u16 = load_simulation(write("u16.yaml", body));
  const SimulationSetup f32 =
      load_simulation(write("f32.yaml", "output: {sample_format: f32}\n" + body));
  EXPECT_EQ(f32.config.output.max_value, 32767.0);
  EXPECT_EQ(u16.config.output.max_value, 32767.0);
  EXPECT_FALSE(f32.config.output.round_to_integer);
  EXPECT_TRUE(std::isnan(f32.config.output.gain_db));  // automatic, as for u16
  // One ping of each: the f32 samples round to the u16 samples.
  const Simulator a(u16.scene, u16.config, u16.reference_altitude_m);
  const Simulator b(f32.scene, f32.config, f32.reference_altitude_m);
  EXPECT_DOUBLE_EQ(a.gain_db(), b.gain_db());
  const PingPose pose =
      sensor_pose(Eigen::Vector3d(0.0, 0.0, -5.0), 0.0, 0.0, 0.0, u16.scene.bathymetry, 7);
  auto wa = a.make_workspace();
  auto wb = b.make_workspace();
  RenderedPing pa, pb;
  a.render_ping(pose, *wa, pa);
  b.render_ping(pose, *wb, pb);
  ASSERT_EQ(pa.starboard.samples.size(), pb.starboard.samples.size());
  std::size_t positive = 0;
  for (std::size_t i = 0; i < pa.starboard.samples.size(); ++i) {
    EXPECT_NEAR(pb.starboard.samples[i], pa.starboard.samples[i], 0.5 + 1e-3) << i;
    positive += pb.starboard.samples[i] > 1.0f ? 1u : 0u;
  }
  EXPECT_GT(positive, pa.starboard.samples.size() / 2);
}

TEST_F(SimulationFile, APulseTypeOtherThanThePresetsNeedsItsOwnKey) {
  const std::string head = std::string(kBathy) + "survey:\n" + kLine;
  for (const auto& [sonar, fragment] :
       {std::pair<std::string, std::string>{"{preset: edgetech-4200-300, pulse: {type: cw}}",
                                            "sonar.pulse.length_us"},
        {"{preset: klein-3900-445, pulse: {type: chirp}}", "sonar.pulse.bandwidth_khz"},
        {"{pulse: {type: chirp}}", "sonar.pulse.bandwidth_khz"}}) {
    try {
      load_simulation(write("bad.yaml", head + "sonar: " + sonar + "\n"));
      ADD_FAILURE() << "no error for " << sonar;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
  const SimulationSetup cw = load_simulation(write(
      "cw.yaml", head + "sonar: {preset: edgetech-4200-300, pulse: {type: cw, length_us: 100}}\n"));
  EXPECT_EQ(cw.config.sonar.pulse, SonarConfig::Pulse::kCw);
  EXPECT_NEAR(cw.config.sonar.pulse_length_s, 100e-6, 1e-15);
  // The preset's own type without a key keeps the preset's value.
  const SimulationSetup chirp = load_simulation(
      write("chirp.yaml", head + "sonar: {preset: edgetech-4200-300, pulse: {type: chirp}}\n"));
  EXPECT_NEAR(chirp.config.sonar.bandwidth_hz, 25e3, 1e-9);
}

}  // namespace
}  // namespace sonarsynth

namespace sonarsynth {
namespace {

// Every bundled sample is a valid simulation file (new keys and presets included), and the
// paper preset is the paper's model: intensity without the sensor stage.
TEST(Samples, EverySampleLoadsAsASimulation) {
  std::size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(SONARSYNTH_SAMPLES_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(load_simulation(entry.path().string()));
    ++count;
  }
  EXPECT_GE(count, 6u);
  const SimulationSetup paper = load_simulation(SONARSYNTH_SAMPLES_DIR "/paper_exact.yaml");
  EXPECT_EQ(paper.config.output.quantity, SampleQuantity::intensity);
  EXPECT_TRUE(std::isnan(paper.config.sensor.noise_floor_dbfs));
  EXPECT_EQ(paper.config.output.normalise, OutputScaling::Normalise::per_ping_max);
  const SimulationSetup seascan = load_simulation(SONARSYNTH_SAMPLES_DIR "/seascan_survey.yaml");
  EXPECT_EQ(seascan.config.output.quantity, SampleQuantity::amplitude);
  EXPECT_DOUBLE_EQ(seascan.config.sonar.frequency_hz, 600e3);
}

TEST_F(SimulationFile, LinesBuiltInCodeFollowTheWaypointRule) {
  const SimulationSetup s =
      load_simulation(write("scene.yaml", std::string(kScene) + "survey: {lines: [{waypoints: "
                                                                "[{east_m: 0, north_m: 0}, "
                                                                "{east_m: 9, north_m: 0}]}]}\n"));
  const Eigen::Vector2d c = s.scene.bathymetry.centre_xy_m();
  const auto message = [&](const SurveyLine& l) {
    try {
      check_survey_line(s.scene, l, "code");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // The scene file's line, in the local frame, passes; east_m/north_m are from the grid's centre.
  EXPECT_EQ(message(s.lines.at(0)), "");
  EXPECT_NEAR((s.lines[0].waypoints_xy_m[1] - c).x(), 9.0, 1e-9);
  EXPECT_NE(message({"l", {c, {NAN, 0.0}}})
                .find("code: survey line 'l' waypoint 1 = (nan, 0) m. "
                      "Violated constraint: finite x and y"),
            std::string::npos)
      << message({"l", {c, {NAN, 0.0}}});
  EXPECT_NE(message({"l", {c, c + Eigen::Vector2d(0.0, 2e6)}}).find("is 2000000 m from the"),
            std::string::npos)
      << message({"l", {c, c + Eigen::Vector2d(0.0, 2e6)}});
}

}  // namespace
}  // namespace sonarsynth
