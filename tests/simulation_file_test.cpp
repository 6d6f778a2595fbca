// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/simulation_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "sonarsynth/formats/config/option_table.hpp"
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

const char* kLine =
    "  lines: [{name: a, waypoints: [{east_m: -20, north_m: 0}, {east_m: 20, north_m: 0}]}]\n";
const char* kBathy =
    "bathymetry:\n  generate: {centre: {lat_deg: 48.45, lon_deg: -68.83}, size_m: [200, 200], "
    "cell_m: 1, depth_m: 30}\n";

// Equal as option values: NaN (auto) equals NaN.
bool same(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}

// A key left out keeps its struct's default: sections given empty read the same values as
// sections left out (where no reader code runs), and those are the structs' own members.
TEST_F(SimulationFile, DefaultsAreTheStructsDefaults) {
  const SimulationSetup absent =
      load_simulation(write("absent.yaml", std::string(kBathy) + "survey:\n" + kLine));
  const SimulationSetup empty = load_simulation(
      write("empty.yaml", std::string(kBathy) +
                              "sonar: {vertical_beam: {}, pulse: {}}\n"
                              "render: {water: {}, quality: {}}\nnoise: {}\noutput: {}\n"
                              "limits: {}\nsurvey:\n  disturbance: {}\n" +
                              kLine));
  for (const options::Option& o : options::all()) {
    EXPECT_TRUE(same(o.get(absent), o.get(empty))) << o.path();
  }
  // The structs, member by member (not through the table).
  for (const SimulationSetup* s : {&absent, &empty}) {
    const SimulationConfig& c = s->config;
    const SonarConfig sonar;
    EXPECT_EQ(c.sonar.frequency_hz, sonar.frequency_hz);
    EXPECT_EQ(c.sonar.max_range_m, sonar.max_range_m);
    EXPECT_EQ(c.sonar.samples_per_channel, sonar.samples_per_channel);
    EXPECT_EQ(c.sonar.sound_speed_m_s, sonar.sound_speed_m_s);
    EXPECT_EQ(c.sonar.tilt_rad, sonar.tilt_rad);
    EXPECT_EQ(c.sonar.tilt_rad, rad_from_deg(20.0));  // what tilt_deg: 20 gives
    EXPECT_EQ(c.sonar.horizontal_beam_width_rad, sonar.horizontal_beam_width_rad);
    EXPECT_EQ(c.sonar.vertical_beam.shape, sonar.vertical_beam.shape);
    EXPECT_EQ(c.sonar.vertical_beam.width_3db_rad, sonar.vertical_beam.width_3db_rad);
    EXPECT_EQ(c.sonar.pulse, sonar.pulse);
    EXPECT_EQ(c.sonar.pulse_length_s, sonar.pulse_length_s);
    EXPECT_EQ(c.sonar.ping_period_s, sonar.ping_period_s);
    const PhysicsConfig physics;
    EXPECT_EQ(c.physics.backscatter, physics.backscatter);
    EXPECT_EQ(c.physics.shadows, physics.shadows);
    EXPECT_EQ(c.physics.absorption, physics.absorption);
    EXPECT_EQ(c.physics.calibration_k, physics.calibration_k);
    EXPECT_EQ(c.physics.water.temperature_c, physics.water.temperature_c);
    EXPECT_EQ(c.physics.water.salinity_psu, physics.water.salinity_psu);
    EXPECT_EQ(c.physics.water.ph, physics.water.ph);
    EXPECT_EQ(c.physics.water.depth_m, physics.water.depth_m);
    const QualityConfig quality;
    EXPECT_EQ(c.quality.profile.grid_subdivisions, quality.profile.grid_subdivisions);
    EXPECT_EQ(c.quality.profile.object_segments, quality.profile.object_segments);
    EXPECT_EQ(c.quality.gauss_points, quality.gauss_points);
    EXPECT_EQ(c.quality.along_track_planes, quality.along_track_planes);
    EXPECT_EQ(c.quality.along_track_tolerance_db, quality.along_track_tolerance_db);
    const NoiseConfig noise;
    EXPECT_EQ(c.noise.model, noise.model);
    EXPECT_EQ(c.noise.paper_uniform_half_width, noise.paper_uniform_half_width);
    EXPECT_EQ(c.noise.snr_at_max_range_db, noise.snr_at_max_range_db);
    EXPECT_EQ(c.noise.texture, noise.texture);
    EXPECT_EQ(c.noise.freeze_cell_m, noise.freeze_cell_m);
    EXPECT_TRUE(std::isnan(c.noise.paper_uniform_variance));
    const OutputScaling output;
    EXPECT_EQ(c.output.tvg, output.tvg);
    EXPECT_TRUE(std::isnan(c.output.gain_db));
    EXPECT_EQ(c.output.max_value, output.max_value);
    EXPECT_EQ(c.output.normalise, OutputScaling::Normalise::none);
    EXPECT_FALSE(s->display_linear);
    EXPECT_EQ(c.truth, SimulationConfig{}.truth);
    EXPECT_EQ(c.seed, SimulationConfig{}.seed);
    EXPECT_EQ(s->sample_format, "u16");
    EXPECT_FALSE(s->allow_more_than_8192_samples);
    const RunLimits limits;
    EXPECT_EQ(s->limits.max_pings, limits.max_pings);
    EXPECT_EQ(s->limits.max_output_gb, limits.max_output_gb);
    EXPECT_EQ(s->limits.max_memory_gb, limits.max_memory_gb);
    const VehicleConfig vehicle;
    EXPECT_EQ(s->vehicle.speed_m_s, vehicle.speed_m_s);
    EXPECT_EQ(s->vehicle.depth_mode, vehicle.depth_mode);
    EXPECT_EQ(s->vehicle.altitude_m, vehicle.altitude_m);
    EXPECT_EQ(s->vehicle.layback_m, vehicle.layback_m);
    EXPECT_EQ(s->vehicle.turn_time_s, vehicle.turn_time_s);
    EXPECT_EQ(s->vehicle.turn_radius_m, vehicle.turn_radius_m);
    EXPECT_EQ(s->vehicle.disturbance.roll_amplitude_rad, vehicle.disturbance.roll_amplitude_rad);
    EXPECT_EQ(s->vehicle.disturbance.period_s, vehicle.disturbance.period_s);
    EXPECT_EQ(format_utc(s->start_time), "2026-01-01T00:00:00.000000Z");
  }
  // A paper beam given without its widths takes VerticalBeamPattern's.
  const SimulationSetup paper = load_simulation(
      write("paper.yaml",
            std::string(kBathy) + "sonar: {vertical_beam: {shape: paper}}\nsurvey:\n" + kLine));
  EXPECT_EQ(paper.config.sonar.vertical_beam.upper_half_width_rad,
            VerticalBeamPattern{}.upper_half_width_rad);
  EXPECT_EQ(paper.config.sonar.vertical_beam.upper_half_width_rad, rad_from_deg(25.0));
  EXPECT_EQ(paper.config.sonar.vertical_beam.lower_half_width_rad, rad_from_deg(25.0));
}

// effective.yaml of a run (non-default values for every declared option over the variants,
// command-line overrides on top) read back gives the same configuration: every declared option,
// and the struct members compared directly.
TEST_F(SimulationFile, EffectiveYamlRoundTripsEveryOption) {
  const std::string common =
      "seed: 12\n"
      "sonar: {frequency_khz: 300, range_m: 50, samples: 2000, sound_speed_m_s: 1490, "
      "tilt_deg: 12.5, horizontal_beam_deg: 0.7, ping_period_s: 0.2, VB, PULSE}\n"
      "render: {backscatter: lambert, shadows: false, spreading: false, beam_pattern: false, "
      "absorption: false, object_glints: false, calibration_k: 2.5, water: {temperature_c: 4, "
      "salinity_psu: 30, ph: 7.5, depth_m: 100}, quality: {grid_subdivisions: 2, object_segments: "
      "12, "
      "solid_resting_objects: false, gauss_points: 3, "
      "along_track_tolerance_db: 0.5 PLANES}}\n"
      "noise: {model: paper, NOISEU, snr_db: 15, texture: false, "
      "along_track_correlation: false, aperture_translation: false, range_correlation: false, "
      "freeze_cell_m: 0.5}\n"
      "limits: {max_pings: 5000, max_output_gb: 2, max_memory_gb: 3}\n";
  struct Variant {
    std::string vb, pulse, planes, output, survey;
    SimulationOverrides ov;
    std::string noise_u = "uniform_half_width: 0.2";
  };
  SimulationOverrides cli;
  cli.seed = 77;
  cli.range_m = 45.0;
  cli.samples = 1800;
  SimulationOverrides fast = cli;
  fast.quality = "fast";
  const std::vector<Variant> variants = {
      {"vertical_beam: {shape: gaussian, width_deg: 40}", "pulse: {type: cw, length_us: 50}", "",
       "output: {tvg: none, gain_db: 55, sample_format: u8, truth: false, truth_grazing: float, "
       "quantity: intensity, "
       "detector: mean, detector_sub_samples: 2, seabed_median_dbfs: -20, "
       "tvg_spreading_db_per_decade: 25, tvg_absorption_share: 0.5, "
       "mosaic: {nadir: fill, gain_normalisation: off}}\n"
       "sensor: {noise_floor_dbfs: off, volume_reverberation_db: -30, shadow_fill_db: off, "
       "first_return_reflection_db: -5, first_return_rms_slope: 0.4, side_lobe_db: -25, "
       "ring_down_m: off, volume_texture_shape: 0.5, shadow_fill_texture_shape: off, "
       "volume_patch_along_track_m: 1.5, volume_patch_range_m: 0.1, "
       "shadow_fill_patch_along_track_m: 2, shadow_fill_patch_range_m: 0.7}",
       "survey:\n  start_time: \"2013-09-10T21:13:08.25Z\"\n  speed_m_s: 1.5\n  altitude_m: 8\n"
       "  layback_m: 20\n  turn_time_s: 40\n  turn_radius_m: 30\n"
       "  altitude_time_constant_s: 4\n"
       "  disturbance: {roll_deg: 2, pitch_deg: 1, yaw_deg: 3, heave_m: 0.2, period_s: 6, "
       "altitude_m: 0.5, heading_wander_deg: 1.5, wander_period_s: 90}\n",
       cli},
      {"vertical_beam: {shape: paper, upper_half_width_deg: 20, lower_half_width_deg: 30}",
       "pulse: {type: chirp, bandwidth_khz: 50}", ", along_track_planes: 3",
       "output: {sample_format: f32, gain_db: 3, allow_more_than_8192_samples: true, jsf: true, "
       "mosaic: {nadir: raw, gain_normalisation: range}}\n"
       "sensor: {noise_floor_dbfs: -50, volume_reverberation_db: off, shadow_fill_db: -20, "
       "first_return_reflection_db: off, ring_down_m: 0.5}",
       "survey:\n  depth_m: 25\n", fast},
      {"vertical_beam: {shape: sinc, height_over_wavelength: 1.5}", "pulse: {type: cw}",
       ", along_track_planes: auto",
       "output: {tvg: spherical, normalise: per_ping_max, display: linear}", "survey:\n",
       SimulationOverrides{}},
      {"vertical_beam: {shape: uniform}", "pulse: {type: cw}", "", "output: {}", "survey:\n",
       SimulationOverrides{}, "uniform_variance: 0.03"},
  };
  std::set<std::string> changed;  // options given a non-default value by some variant
  const SimulationSetup defaults =
      load_simulation(write("defaults.yaml", std::string(kBathy) + "survey:\n" + kLine));
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const Variant& v = variants[i];
    std::string text = common;
    text.replace(text.find("VB"), 2, v.vb);
    text.replace(text.find("PULSE"), 5, v.pulse);
    text.replace(text.find(" PLANES"), 7, v.planes);
    text.replace(text.find("NOISEU"), 6, v.noise_u);
    const std::string scene =
        write("s" + std::to_string(i) + ".yaml",
              std::string(kBathy) + text + v.output + "\n" + v.survey + kLine);
    const SimulationSetup a = load_simulation(scene, v.ov);
    const Simulator sim(a.scene, a.config, a.reference_altitude_m);
    const fs::path eff = dir_ / ("effective" + std::to_string(i) + ".yaml");
    write_effective_config(scene, v.ov, a, sim, eff);
    const SimulationSetup b = load_simulation(eff.string());
    for (const options::Option& o : options::all()) {
      if (o.kind == options::Kind::seed) {
        EXPECT_EQ(options::seed_of(a), options::seed_of(b));
        if (options::seed_of(a) != options::seed_of(defaults)) changed.insert(o.path());
        continue;
      }
      EXPECT_TRUE(same(o.get(a), o.get(b))) << "variant " << i << ": " << o.path();
      if (!same(o.get(a), o.get(defaults))) changed.insert(o.path());
    }
    // Member by member, without the table.
    const SimulationConfig &x = a.config, &y = b.config;
    EXPECT_EQ(x.seed, y.seed);
    EXPECT_EQ(x.sonar.frequency_hz, y.sonar.frequency_hz);
    EXPECT_EQ(x.sonar.max_range_m, y.sonar.max_range_m);
    EXPECT_EQ(x.sonar.samples_per_channel, y.sonar.samples_per_channel);
    EXPECT_EQ(x.sonar.tilt_rad, y.sonar.tilt_rad);
    EXPECT_EQ(x.sonar.vertical_beam.shape, y.sonar.vertical_beam.shape);
    EXPECT_EQ(x.sonar.vertical_beam.width_3db_rad, y.sonar.vertical_beam.width_3db_rad);
    EXPECT_EQ(x.sonar.vertical_beam.upper_half_width_rad,
              y.sonar.vertical_beam.upper_half_width_rad);
    EXPECT_EQ(x.sonar.vertical_beam.height_over_wavelength,
              y.sonar.vertical_beam.height_over_wavelength);
    EXPECT_EQ(x.sonar.pulse, y.sonar.pulse);
    EXPECT_EQ(x.sonar.pulse_length_s, y.sonar.pulse_length_s);
    EXPECT_EQ(x.sonar.bandwidth_hz, y.sonar.bandwidth_hz);
    EXPECT_EQ(x.physics.backscatter, y.physics.backscatter);
    EXPECT_EQ(x.physics.water.depth_m, y.physics.water.depth_m);
    EXPECT_EQ(x.quality.profile.grid_subdivisions, y.quality.profile.grid_subdivisions);
    EXPECT_EQ(x.quality.profile.object_segments, y.quality.profile.object_segments);
    EXPECT_EQ(x.quality.profile.solid_resting_objects, y.quality.profile.solid_resting_objects);
    EXPECT_EQ(x.quality.gauss_points, y.quality.gauss_points);
    EXPECT_EQ(x.quality.along_track_planes, y.quality.along_track_planes);
    EXPECT_EQ(x.quality.along_track_tolerance_db, y.quality.along_track_tolerance_db);
    EXPECT_EQ(x.noise.model, y.noise.model);
    EXPECT_EQ(x.noise.freeze_cell_m, y.noise.freeze_cell_m);
    EXPECT_TRUE(same(x.noise.paper_uniform_variance, y.noise.paper_uniform_variance));
    EXPECT_EQ(x.output.normalise, y.output.normalise);
    EXPECT_EQ(a.display_linear, b.display_linear);
    EXPECT_EQ(x.output.tvg, y.output.tvg);
    EXPECT_TRUE(same(x.output.gain_db, y.output.gain_db));
    EXPECT_EQ(x.output.max_value, y.output.max_value);
    EXPECT_EQ(x.output.round_to_integer, y.output.round_to_integer);
    EXPECT_EQ(x.output.quantity, y.output.quantity);
    EXPECT_EQ(x.noise.along_track_correlation, y.noise.along_track_correlation);
    EXPECT_EQ(x.noise.aperture_translation, y.noise.aperture_translation);
    EXPECT_EQ(x.noise.range_correlation, y.noise.range_correlation);
    EXPECT_EQ(x.output.detector, y.output.detector);
    EXPECT_EQ(x.output.detector_sub_samples, y.output.detector_sub_samples);
    EXPECT_TRUE(same(x.output.seabed_median_dbfs, y.output.seabed_median_dbfs));
    for (auto [u, w] :
         {std::pair{x.sensor.noise_floor_dbfs, y.sensor.noise_floor_dbfs},
          std::pair{x.sensor.volume_reverberation_db, y.sensor.volume_reverberation_db},
          std::pair{x.sensor.shadow_fill_db, y.sensor.shadow_fill_db},
          std::pair{x.sensor.first_return_reflection_db, y.sensor.first_return_reflection_db},
          std::pair{x.sensor.first_return_rms_slope, y.sensor.first_return_rms_slope},
          std::pair{x.sensor.side_lobe_db, y.sensor.side_lobe_db},
          std::pair{x.sensor.ring_down_m, y.sensor.ring_down_m},
          std::pair{x.sensor.volume_texture_shape, y.sensor.volume_texture_shape},
          std::pair{x.sensor.shadow_fill_texture_shape, y.sensor.shadow_fill_texture_shape},
          std::pair{x.sensor.volume_patch_along_track_m, y.sensor.volume_patch_along_track_m},
          std::pair{x.sensor.volume_patch_range_m, y.sensor.volume_patch_range_m},
          std::pair{x.sensor.shadow_fill_patch_along_track_m,
                    y.sensor.shadow_fill_patch_along_track_m},
          std::pair{x.sensor.shadow_fill_patch_range_m, y.sensor.shadow_fill_patch_range_m},
          std::pair{x.output.tvg_spreading_db_per_decade, y.output.tvg_spreading_db_per_decade},
          std::pair{x.output.tvg_absorption_share, y.output.tvg_absorption_share}}) {
      EXPECT_TRUE(same(u, w)) << u << " vs " << w;
    }
    EXPECT_EQ(x.truth, y.truth);
    EXPECT_EQ(a.mosaic_processing.nadir, b.mosaic_processing.nadir);
    EXPECT_EQ(a.mosaic_processing.gain, b.mosaic_processing.gain);
    EXPECT_EQ(a.sample_format, b.sample_format);
    EXPECT_EQ(a.output_formats, b.output_formats);
    EXPECT_EQ(a.limits.max_pings, b.limits.max_pings);
    EXPECT_EQ(a.vehicle.depth_mode, b.vehicle.depth_mode);
    EXPECT_EQ(a.vehicle.altitude_m, b.vehicle.altitude_m);
    EXPECT_EQ(a.vehicle.depth_m, b.vehicle.depth_m);
    EXPECT_EQ(a.vehicle.turn_time_s, b.vehicle.turn_time_s);
    EXPECT_EQ(a.vehicle.disturbance.yaw_amplitude_rad, b.vehicle.disturbance.yaw_amplitude_rad);
    EXPECT_EQ(a.start_time, b.start_time);
  }
  // The overrides reached the run and effective.yaml: checked above through the round trip,
  // here that they are not the file's values.
  EXPECT_EQ(load_simulation(write("o.yaml", std::string(kBathy) + "survey:\n" + kLine), cli)
                .config.sonar.samples_per_channel,
            1800u);
  for (const options::Option& o : options::all()) {
    EXPECT_TRUE(changed.count(o.path())) << o.path() << " is never given a non-default value";
  }
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
