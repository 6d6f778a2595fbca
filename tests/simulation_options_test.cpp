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
    EXPECT_FALSE(s->bag_truth);
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

// The configuration of `a` and `b` member by member, without the option table.
void expect_same_members(const SimulationSetup& a, const SimulationSetup& b) {
  const SimulationConfig &x = a.config, &y = b.config;
  EXPECT_EQ(x.seed, y.seed);
  EXPECT_EQ(x.sonar.frequency_hz, y.sonar.frequency_hz);
  EXPECT_EQ(x.sonar.max_range_m, y.sonar.max_range_m);
  EXPECT_EQ(x.sonar.samples_per_channel, y.sonar.samples_per_channel);
  EXPECT_EQ(x.sonar.tilt_rad, y.sonar.tilt_rad);
  EXPECT_EQ(x.sonar.vertical_beam.shape, y.sonar.vertical_beam.shape);
  EXPECT_EQ(x.sonar.vertical_beam.width_3db_rad, y.sonar.vertical_beam.width_3db_rad);
  EXPECT_EQ(x.sonar.vertical_beam.upper_half_width_rad, y.sonar.vertical_beam.upper_half_width_rad);
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
  EXPECT_EQ(a.bag_truth, b.bag_truth);
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
