// SPDX-License-Identifier: MIT
// The option table against the simulation file: a key left out keeps its struct's default, and
// effective.yaml read back gives the same configuration for every declared option.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "simulation_file_test_util.hpp"
#include "sonarsynth/formats/config/option_table.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"

namespace sonarsynth {
namespace {

using namespace simulation_file_test;
using simulation_file_test::expect_same_members;  // with the overloads below
using test::expect_equal_fields;
using test::expect_same_fields;

// The structs of `a` and `b` member by member, without the option table.
void expect_same_members(const PhysicsConfig& a, const PhysicsConfig& b) {
  using P = PhysicsConfig;
  expect_equal_fields(a, b, &P::backscatter, &P::shadows, &P::absorption, &P::calibration_k);
  using W = Seawater;
  expect_equal_fields(a.water, b.water, &W::temperature_c, &W::salinity_psu, &W::ph, &W::depth_m);
}

void expect_same_members(const QualityConfig& a, const QualityConfig& b) {
  using P = ProfileOptions;
  expect_equal_fields(a.profile, b.profile, &P::grid_subdivisions, &P::object_segments,
                      &P::solid_resting_objects);
  using Q = QualityConfig;
  expect_equal_fields(a, b, &Q::gauss_points, &Q::along_track_planes, &Q::along_track_tolerance_db);
}

void expect_same_members(const NoiseConfig& a, const NoiseConfig& b) {
  using N = NoiseConfig;
  expect_equal_fields(a, b, &N::model, &N::paper_uniform_half_width, &N::snr_at_max_range_db,
                      &N::texture, &N::freeze_cell_m, &N::along_track_correlation,
                      &N::aperture_translation, &N::range_correlation);
  expect_same_fields(a, b, &N::paper_uniform_variance);
}

void expect_same_members(const OutputScaling& a, const OutputScaling& b) {
  using O = OutputScaling;
  expect_equal_fields(a, b, &O::normalise, &O::tvg, &O::max_value, &O::round_to_integer,
                      &O::quantity, &O::detector, &O::detector_sub_samples);
  expect_same_fields(a, b, &O::gain_db, &O::seabed_median_dbfs, &O::tvg_spreading_db_per_decade,
                     &O::tvg_absorption_share);
}

void expect_same_members(const RunLimits& a, const RunLimits& b) {
  expect_equal_fields(a, b, &RunLimits::max_pings, &RunLimits::max_output_gb,
                      &RunLimits::max_memory_gb);
}

void expect_same_members(const VehicleConfig& a, const VehicleConfig& b) {
  using V = VehicleConfig;
  expect_equal_fields(a, b, &V::speed_m_s, &V::depth_mode, &V::altitude_m, &V::depth_m,
                      &V::layback_m, &V::turn_time_s, &V::turn_radius_m);
  expect_equal_fields(a.disturbance, b.disturbance, &Disturbance::roll_amplitude_rad,
                      &Disturbance::yaw_amplitude_rad, &Disturbance::period_s);
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
    expect_same_members(c.sonar, SonarConfig{});
    EXPECT_EQ(c.sonar.tilt_rad, rad_from_deg(20.0));  // what tilt_deg: 20 gives
    expect_same_members(c.physics, PhysicsConfig{});
    expect_same_members(c.quality, QualityConfig{});
    expect_same_members(c.noise, NoiseConfig{});
    EXPECT_TRUE(std::isnan(c.noise.paper_uniform_variance));
    expect_same_members(c.output, OutputScaling{});
    EXPECT_TRUE(std::isnan(c.output.gain_db));
    EXPECT_EQ(c.output.normalise, OutputScaling::Normalise::none);
    EXPECT_FALSE(s->display_linear);
    EXPECT_EQ(c.truth, SimulationConfig{}.truth);
    EXPECT_EQ(c.seed, SimulationConfig{}.seed);
    EXPECT_EQ(s->sample_format, "u16");
    EXPECT_FALSE(s->allow_more_than_8192_samples);
    EXPECT_FALSE(s->bag_truth);
    expect_same_members(s->limits, RunLimits{});
    expect_same_members(s->vehicle, VehicleConfig{});
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

// The configuration of `a` and `b` member by member, without the option table.
void expect_same_members(const SimulationSetup& a, const SimulationSetup& b) {
  const SimulationConfig &x = a.config, &y = b.config;
  EXPECT_EQ(x.seed, y.seed);
  expect_same_members(x.sonar, y.sonar);
  expect_same_members(x.physics, y.physics);
  expect_same_members(x.quality, y.quality);
  expect_same_members(x.noise, y.noise);
  expect_same_members(x.output, y.output);
  EXPECT_EQ(a.display_linear, b.display_linear);
  EXPECT_EQ(a.bag_truth, b.bag_truth);
  using Z = SensorConfig;
  expect_same_fields(
      x.sensor, y.sensor, &Z::noise_floor_dbfs, &Z::volume_reverberation_db, &Z::shadow_fill_db,
      &Z::first_return_reflection_db, &Z::first_return_rms_slope, &Z::side_lobe_db, &Z::ring_down_m,
      &Z::volume_texture_shape, &Z::shadow_fill_texture_shape, &Z::volume_patch_along_track_m,
      &Z::volume_patch_range_m, &Z::shadow_fill_patch_along_track_m, &Z::shadow_fill_patch_range_m);
  EXPECT_EQ(x.truth, y.truth);
  EXPECT_EQ(a.mosaic_processing.nadir, b.mosaic_processing.nadir);
  EXPECT_EQ(a.mosaic_processing.gain, b.mosaic_processing.gain);
  EXPECT_EQ(a.sample_format, b.sample_format);
  EXPECT_EQ(a.output_formats, b.output_formats);
  expect_same_members(a.limits, b.limits);
  expect_same_members(a.vehicle, b.vehicle);
  EXPECT_EQ(a.start_time, b.start_time);
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
       "output: {tvg: spherical, normalise: per_ping_max, display: linear, formats: [xtf, mcap], "
       "bag_truth: true}",
       "survey:\n", SimulationOverrides{}},
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
    expect_same_members(a, b);
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

}  // namespace
}  // namespace sonarsynth
