// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/option_table.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/survey.hpp"

namespace sonarsynth::options {
namespace {

using S = SimulationSetup;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Accessors of one struct field: PLAIN in the file's unit, SCALED (struct = file * k), DEG
// (degrees in the file, radians in the struct).
#define PLAIN(field)                                       \
  [](const S& s) { return static_cast<double>(s.field); }, \
      [](S& s, double v) { s.field = static_cast<std::remove_cvref_t<decltype(s.field)>>(v); }
#define SCALED(field, k) \
  [](const S& s) { return s.field / (k); }, [](S& s, double v) { s.field = (k)*v; }
#define DEG(field)                                  \
  [](const S& s) { return deg_from_rad(s.field); }, \
      [](S& s, double v) { s.field = rad_from_deg(v); }
#define BOOL(field) \
  [](const S& s) { return s.field ? 1.0 : 0.0; }, [](S& s, double v) { s.field = v != 0.0; }

// The text of a command-line number: all of it, or an InputError naming the flag.
template <typename T>
T flag_number(const std::string& text, std::string_view flag, const char* allowed) {
  T v{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end) {
    throw InputError(std::string(flag) + " = '" + text + "'. Violated constraint: " + allowed);
  }
  return v;
}

// The command-line flags: the bounds of their values are those of the rows they override.
const Flag kSeed{"--seed", "random seed (overrides the scene file's)",
                 [](const SimulationOverrides& o) { return o.seed.has_value(); },
                 [](SimulationOverrides& o, const std::string& t, std::string_view flag) {
                   o.seed = flag_number<std::uint64_t>(t, flag,
                                                       "an integer from 0 to 18446744073709551615");
                 }};
const Flag kRange{"--range", "maximum slant range, metres (overrides sonar.range_m)",
                  [](const SimulationOverrides& o) { return o.range_m.has_value(); },
                  [](SimulationOverrides& o, const std::string& t, std::string_view flag) {
                    o.range_m = flag_number<double>(t, flag, "a number (metres)");
                  }};
const Flag kSamples{"--samples", "samples per channel (overrides sonar.samples)",
                    [](const SimulationOverrides& o) { return o.samples.has_value(); },
                    [](SimulationOverrides& o, const std::string& t, std::string_view flag) {
                      o.samples = flag_number<std::size_t>(t, flag, "a whole number");
                    }};
const Flag kQuality{
    "--quality", "renderer quality: fast, default or high",
    [](const SimulationOverrides& o) { return o.quality.has_value(); },
    [](SimulationOverrides& o, const std::string& t, std::string_view) { o.quality = t; }};

// Option{section, key, unit, kind, lo, hi, lo_open, flag, word, choices, constraint, get, set}
Option real(std::string_view sec, std::string_view key, std::string_view unit, double lo, double hi,
            bool lo_open, double (*get)(const S&), void (*set)(S&, double),
            const Flag* flag = nullptr) {
  return {sec, key, unit, Kind::real, lo, hi, lo_open, flag, "", {}, "", get, set};
}
Option integer(std::string_view sec, std::string_view key, double lo, double hi, bool lo_open,
               double (*get)(const S&), void (*set)(S&, double), const Flag* flag = nullptr) {
  return {sec, key, "", Kind::integer, lo, hi, lo_open, flag, "", {}, "", get, set};
}
Option boolean(std::string_view sec, std::string_view key, double (*get)(const S&),
               void (*set)(S&, double)) {
  return {sec, key, "", Kind::boolean, 0, 1, false, nullptr, "", {}, "", get, set};
}
Option choice(std::string_view sec, std::string_view key, std::vector<std::string_view> names,
              std::string_view constraint, double (*get)(const S&), void (*set)(S&, double)) {
  return {sec,        key, "", Kind::choice, 0, 0, false, nullptr, "", std::move(names),
          constraint, get, set};
}

// The rows of `sonar`: the sonar, its beams and pulse.
void add_sonar_options(std::vector<Option>& t) {
  t.push_back(
      real("sonar", "frequency_khz", "kHz", 0, 1e5, true, SCALED(config.sonar.frequency_hz, 1e3)));
  t.push_back(
      real("sonar", "range_m", "m", 0, 1e5, true, PLAIN(config.sonar.max_range_m), &kRange));
  t.push_back(integer("sonar", "samples", 1, 65535, false, PLAIN(config.sonar.samples_per_channel),
                      &kSamples));
  t.push_back(real("sonar", "sound_speed_m_s", "m/s", 1300, 1700, false,
                   PLAIN(config.sonar.sound_speed_m_s)));
  t.push_back(real("sonar", "tilt_deg", "deg", -90, 90, false, DEG(config.sonar.tilt_rad)));
  t.push_back(real("sonar", "horizontal_beam_deg", "deg", 0, 89, true,
                   DEG(config.sonar.horizontal_beam_width_rad)));
  t.push_back(
      real("sonar", "ping_period_s", "s", 0, 1e3, false, PLAIN(config.sonar.ping_period_s)));
  t.push_back(choice(
      "sonar.vertical_beam", "shape", {"gaussian", "paper", "sinc", "table", "uniform"},
      "one of gaussian, paper, sinc, table, uniform",
      [](const S& s) {
        switch (s.config.sonar.vertical_beam.shape) {
          case VerticalBeamShape::gaussian:
            return 0.0;
          case VerticalBeamShape::paper_sine_pair:
            return 1.0;
          case VerticalBeamShape::sinc:
            return 2.0;
          case VerticalBeamShape::table:
            return 3.0;
          case VerticalBeamShape::uniform:
            break;
        }
        return 4.0;
      },
      [](S& s, double v) {
        constexpr VerticalBeamShape shapes[] = {
            VerticalBeamShape::gaussian, VerticalBeamShape::paper_sine_pair,
            VerticalBeamShape::sinc, VerticalBeamShape::table, VerticalBeamShape::uniform};
        s.config.sonar.vertical_beam.shape = shapes[static_cast<std::size_t>(v)];
      }));
  t.push_back(real("sonar.vertical_beam", "width_deg", "deg", 0, 180, true,
                   DEG(config.sonar.vertical_beam.width_3db_rad)));
  t.push_back(real("sonar.vertical_beam", "upper_half_width_deg", "deg", 0, 180, true,
                   DEG(config.sonar.vertical_beam.upper_half_width_rad)));
  t.push_back(real("sonar.vertical_beam", "lower_half_width_deg", "deg", 0, 180, true,
                   DEG(config.sonar.vertical_beam.lower_half_width_rad)));
  t.push_back(real("sonar.vertical_beam", "height_over_wavelength", "", 0, 1e4, true,
                   PLAIN(config.sonar.vertical_beam.height_over_wavelength)));
  t.push_back(choice(
      "sonar.pulse", "type", {"cw", "chirp"}, "cw or chirp",
      [](const S& s) { return s.config.sonar.pulse == SonarConfig::Pulse::kChirp ? 1.0 : 0.0; },
      [](S& s, double v) {
        s.config.sonar.pulse = v != 0.0 ? SonarConfig::Pulse::kChirp : SonarConfig::Pulse::kCw;
      }));
  t.push_back(real("sonar.pulse", "length_us", "us", 0, 1e6, false,
                   SCALED(config.sonar.pulse_length_s, 1e-6)));
  t.push_back(real("sonar.pulse", "bandwidth_khz", "kHz", 0, 1e5, true,
                   SCALED(config.sonar.bandwidth_hz, 1e3)));
}

// The rows of `render`: the backscatter model and the render quality.
void add_render_options(std::vector<Option>& t) {
  t.push_back(choice(
      "render", "backscatter", {"paper", "lambert"}, "paper or lambert",
      [](const S& s) {
        return s.config.physics.backscatter == BackscatterModel::lambert ? 1.0 : 0.0;
      },
      [](S& s, double v) {
        s.config.physics.backscatter =
            v != 0.0 ? BackscatterModel::lambert : BackscatterModel::paper;
      }));
  t.push_back(boolean("render", "shadows", BOOL(config.physics.shadows)));
  t.push_back(boolean("render", "spreading", BOOL(config.physics.spreading)));
  t.push_back(boolean("render", "beam_pattern", BOOL(config.physics.beam_pattern)));
  t.push_back(boolean("render", "absorption", BOOL(config.physics.absorption)));
  t.push_back(boolean("render", "object_glints", BOOL(config.physics.object_glints)));
  t.push_back(
      real("render", "calibration_k", "", 0, 1e30, true, PLAIN(config.physics.calibration_k)));
  t.push_back(real("render.water", "temperature_c", "degC", -2, 40, false,
                   PLAIN(config.physics.water.temperature_c)));
  t.push_back(real("render.water", "salinity_psu", "psu", 0, 45, false,
                   PLAIN(config.physics.water.salinity_psu)));
  t.push_back(real("render.water", "ph", "", 6, 9, false, PLAIN(config.physics.water.ph)));
  t.push_back(
      real("render.water", "depth_m", "m", 0, 12000, false, PLAIN(config.physics.water.depth_m)));
  t.push_back(integer("render.quality", "grid_subdivisions", 1, 64, false,
                      PLAIN(config.quality.profile.grid_subdivisions), &kQuality));
  t.push_back(integer("render.quality", "object_segments", 2, 256, false,
                      PLAIN(config.quality.profile.object_segments), &kQuality));
  t.push_back(boolean("render.quality", "solid_resting_objects",
                      BOOL(config.quality.profile.solid_resting_objects)));
  t.push_back(integer("render.quality", "gauss_points", 1, 5, false,
                      PLAIN(config.quality.gauss_points), &kQuality));
  Option planes = integer(
      "render.quality", "along_track_planes", 1, 64, false,
      [](const S& s) {
        const int k = s.config.quality.along_track_planes;
        return k == QualityConfig::kAutoPlanes ? kNaN : static_cast<double>(k);
      },
      [](S& s, double v) {
        s.config.quality.along_track_planes =
            std::isnan(v) ? QualityConfig::kAutoPlanes : static_cast<int>(v);
      },
      &kQuality);
  planes.word = "auto";
  t.push_back(planes);
  t.push_back(real("render.quality", "along_track_tolerance_db", "dB", 0, 40, true,
                   PLAIN(config.quality.along_track_tolerance_db), &kQuality));
  Option small =
      boolean("render.quality", "small_object_planes", BOOL(config.quality.small_object_planes));
  small.flag = &kQuality;
  t.push_back(small);
}

// The rows of `noise`: the noise model and its correlations.
void add_noise_options(std::vector<Option>& t) {
  t.push_back(choice(
      "noise", "model", {"none", "paper", "speckle"}, "none, paper or speckle",
      [](const S& s) { return static_cast<double>(static_cast<int>(s.config.noise.model)); },
      [](S& s, double v) { s.config.noise.model = static_cast<NoiseConfig::Model>(v); }));
  t.push_back(real("noise", "uniform_half_width", "", 0, 1, false,
                   PLAIN(config.noise.paper_uniform_half_width)));
  // The paper's gamma (docs/physics.md §1.6); not given: the half-width above.
  t.push_back(real("noise", "uniform_variance", "", 0, 1.0 / 3.0, false,
                   PLAIN(config.noise.paper_uniform_variance)));
  t.push_back(
      real("noise", "snr_db", "dB", -100, 200, false, PLAIN(config.noise.snr_at_max_range_db)));
  t.push_back(boolean("noise", "texture", BOOL(config.noise.texture)));
  t.push_back(
      boolean("noise", "along_track_correlation", BOOL(config.noise.along_track_correlation)));
  t.push_back(boolean("noise", "aperture_translation", BOOL(config.noise.aperture_translation)));
  t.push_back(boolean("noise", "range_correlation", BOOL(config.noise.range_correlation)));
  t.push_back(
      real("noise", "freeze_cell_m", "m", 0, 1e3, false, PLAIN(config.noise.freeze_cell_m)));
}

// The rows of `output`: gain, display, products and the mosaic's processing.
void add_output_options(std::vector<Option>& t) {
  t.push_back(choice(
      "output", "tvg", {"spherical", "none"}, "spherical (k log R + 2 a alpha R) or none",
      [](const S& s) { return s.config.output.tvg == TvgLaw::none ? 1.0 : 0.0; },
      [](S& s, double v) { s.config.output.tvg = v != 0.0 ? TvgLaw::none : TvgLaw::spherical; }));
  t.push_back(real("output", "tvg_spreading_db_per_decade", "dB", 0, 60, false,
                   PLAIN(config.output.tvg_spreading_db_per_decade)));
  t.push_back(real("output", "tvg_absorption_share", "", 0, 1, false,
                   PLAIN(config.output.tvg_absorption_share)));
  Option gain = real("output", "gain_db", "dB", -150, 150, false, PLAIN(config.output.gain_db));
  gain.word = "auto";
  t.push_back(gain);
  t.push_back(choice(
      "output", "sample_format", {"u16", "u8", "f32"}, "u16, u8 or f32",
      [](const S& s) {
        return s.sample_format == "u8" ? 1.0 : s.sample_format == "f32" ? 2.0 : 0.0;
      },
      [](S& s, double v) {
        // The sample range of each XTF sample format (docs/xtf.md). f32 holds the counts of the
        // u16 profile (full scale 32767, clipped there), unrounded: the same image as u16.
        static constexpr const char* names[] = {"u16", "u8", "f32"};
        s.sample_format = names[static_cast<std::size_t>(v)];
        s.config.output.max_value = v == 1.0 ? 255.0 : 32767.0;
        s.config.output.round_to_integer = v != 2.0;
      }));
  t.push_back(choice(
      "output", "quantity", {"amplitude", "intensity"}, "amplitude or intensity",
      [](const S& s) { return s.config.output.quantity == SampleQuantity::intensity ? 1.0 : 0.0; },
      [](S& s, double v) {
        s.config.output.quantity = v != 0.0 ? SampleQuantity::intensity : SampleQuantity::amplitude;
      }));
  t.push_back(choice(
      "output", "detector", {"max", "mean"}, "max or mean",
      [](const S& s) { return s.config.output.detector == DetectorMode::mean ? 1.0 : 0.0; },
      [](S& s, double v) {
        s.config.output.detector = v != 0.0 ? DetectorMode::mean : DetectorMode::max;
      }));
  t.push_back(integer("output", "detector_sub_samples", 1, 16, false,
                      PLAIN(config.output.detector_sub_samples)));
  t.push_back(real("output", "seabed_median_dbfs", "dB", -80, 0, false,
                   PLAIN(config.output.seabed_median_dbfs)));
  t.push_back(choice(
      "output", "normalise", {"none", "per_ping_max"}, "none or per_ping_max",
      [](const S& s) {
        return s.config.output.normalise == OutputScaling::Normalise::per_ping_max ? 1.0 : 0.0;
      },
      [](S& s, double v) {
        s.config.output.normalise =
            v != 0.0 ? OutputScaling::Normalise::per_ping_max : OutputScaling::Normalise::none;
      }));
  t.push_back(choice(
      "output", "display", {"db", "linear"}, "db or linear",
      [](const S& s) { return s.display_linear ? 1.0 : 0.0; },
      [](S& s, double v) { s.display_linear = v != 0.0; }));
  t.push_back(boolean("output", "truth", BOOL(config.truth)));
  t.push_back(choice(
      "output", "truth_grazing", {"hundredths", "float"}, "hundredths or float",
      [](const S& s) { return s.truth_grazing == TruthGrazing::float32 ? 1.0 : 0.0; },
      [](S& s, double v) {
        s.truth_grazing = v != 0.0 ? TruthGrazing::float32 : TruthGrazing::hundredths;
      }));
  t.push_back(
      boolean("output", "allow_more_than_8192_samples", BOOL(allow_more_than_8192_samples)));
  // output.bag_truth: the truth topics of the ROS bags (docs/robotics.md, "Truth topics").
  t.push_back(boolean("output", "bag_truth", BOOL(bag_truth)));
  // output.jsf: true, the alias of "jsf" in output.formats (read after this table, which it
  // then overrides: formats/config/simulation_file.cpp).
  t.push_back(boolean(
      "output", "jsf", [](const S& s) { return s.writes_format("jsf") ? 1.0 : 0.0; },
      [](S& s, double v) {
        std::erase(s.output_formats, "jsf");
        if (v != 0.0) s.output_formats.emplace_back("jsf");
      }));
  // output.mosaic: the processing of simulate's mosaic (docs/scene-format.md).
  t.push_back(choice(
      "output.mosaic", "nadir", {"blank", "fill", "raw"}, "blank, fill or raw",
      [](const S& s) { return static_cast<double>(static_cast<int>(s.mosaic_processing.nadir)); },
      [](S& s, double v) {
        s.mosaic_processing.nadir = static_cast<MosaicProcessing::Nadir>(static_cast<int>(v));
      }));
  t.push_back(choice(
      "output.mosaic", "gain_normalisation", {"off", "range", "angle"}, "off, range or angle",
      [](const S& s) { return static_cast<double>(static_cast<int>(s.mosaic_processing.gain)); },
      [](S& s, double v) {
        s.mosaic_processing.gain = static_cast<GainNormalisation>(static_cast<int>(v));
      }));
}

// The rows of `sensor`: the sensor effects, each a level or `off`.
void add_sensor_options(std::vector<Option>& t) {
  auto sensor_level = [](std::string_view key, std::string_view unit, double lo, double hi,
                         double (*get)(const S&), void (*set)(S&, double)) {
    Option o = real("sensor", key, unit, lo, hi, false, get, set);
    o.word = "off";
    return o;
  };
  t.push_back(
      sensor_level("noise_floor_dbfs", "dB", -300, 0, PLAIN(config.sensor.noise_floor_dbfs)));
  t.push_back(sensor_level("volume_reverberation_db", "dB", -300, 0,
                           PLAIN(config.sensor.volume_reverberation_db)));
  t.push_back(sensor_level("shadow_fill_db", "dB", -300, 0, PLAIN(config.sensor.shadow_fill_db)));
  t.push_back(sensor_level("first_return_reflection_db", "dB", -300, 0,
                           PLAIN(config.sensor.first_return_reflection_db)));
  t.push_back(real("sensor", "first_return_rms_slope", "", 0, 1, true,
                   PLAIN(config.sensor.first_return_rms_slope)));
  t.push_back(
      real("sensor", "side_lobe_db", "dB", -300, 0, false, PLAIN(config.sensor.side_lobe_db)));
  t.push_back(sensor_level("ring_down_m", "m", 0, 1e4, PLAIN(config.sensor.ring_down_m)));
  t.push_back(sensor_level("volume_texture_shape", "", 0.01, 1000,
                           PLAIN(config.sensor.volume_texture_shape)));
  t.push_back(sensor_level("shadow_fill_texture_shape", "", 0.01, 1000,
                           PLAIN(config.sensor.shadow_fill_texture_shape)));
  t.push_back(real("sensor", "volume_patch_along_track_m", "m", 1e-3, 1e6, false,
                   PLAIN(config.sensor.volume_patch_along_track_m)));
  t.push_back(real("sensor", "volume_patch_range_m", "m", 0, 1e6, false,
                   PLAIN(config.sensor.volume_patch_range_m)));
  t.push_back(real("sensor", "shadow_fill_patch_along_track_m", "m", 1e-3, 1e6, false,
                   PLAIN(config.sensor.shadow_fill_patch_along_track_m)));
  t.push_back(real("sensor", "shadow_fill_patch_range_m", "m", 1e-3, 1e6, false,
                   PLAIN(config.sensor.shadow_fill_patch_range_m)));
}

// The rows of `limits`: the run's size limits.
void add_limits_options(std::vector<Option>& t) {
  t.push_back(integer("limits", "max_pings", 0, 1e15, true, PLAIN(limits.max_pings)));
  t.push_back(real("limits", "max_output_gb", "GB", 0, 1e6, true, PLAIN(limits.max_output_gb)));
  t.push_back(real("limits", "max_memory_gb", "GB", 0, 1e6, true, PLAIN(limits.max_memory_gb)));
}

// The rows of `survey`: the vehicle and its disturbance.
void add_survey_options(std::vector<Option>& t) {
  t.push_back(real("survey", "speed_m_s", "m/s", 0, 100, true, PLAIN(vehicle.speed_m_s)));
  t.push_back(real("survey", "altitude_m", "m", 0, 12000, true, PLAIN(vehicle.altitude_m)));
  t.push_back(real(
      "survey", "depth_m", "m", 0, 12000, false, [](const S& s) { return s.vehicle.depth_m; },
      [](S& s, double v) {
        s.vehicle.depth_m = v;
        s.vehicle.depth_mode = VehicleConfig::DepthMode::kDepth;
      }));
  t.push_back(real("survey", "altitude_time_constant_s", "s", 0, 1e4, false,
                   PLAIN(vehicle.altitude_time_constant_s)));
  t.push_back(real("survey", "layback_m", "m", 0, 1e4, false, PLAIN(vehicle.layback_m)));
  t.push_back(real("survey", "turn_time_s", "s", -kInf, kInf, false, PLAIN(vehicle.turn_time_s)));
  t.push_back(real("survey", "turn_radius_m", "m", 0, 1e5, false, PLAIN(vehicle.turn_radius_m)));
  t.push_back(real("survey.disturbance", "roll_deg", "deg", 0, kMaxAttitudeDeg, false,
                   DEG(vehicle.disturbance.roll_amplitude_rad)));
  t.push_back(real("survey.disturbance", "pitch_deg", "deg", 0, kMaxAttitudeDeg, false,
                   DEG(vehicle.disturbance.pitch_amplitude_rad)));
  t.push_back(real("survey.disturbance", "yaw_deg", "deg", 0, 180, false,
                   DEG(vehicle.disturbance.yaw_amplitude_rad)));
  t.push_back(real("survey.disturbance", "heave_m", "m", 0, 100, false,
                   PLAIN(vehicle.disturbance.heave_amplitude_m)));
  t.push_back(real("survey.disturbance", "period_s", "s", 0, 1e4, true,
                   PLAIN(vehicle.disturbance.period_s)));
  t.push_back(real("survey.disturbance", "altitude_m", "m", 0, 1000, false,
                   PLAIN(vehicle.disturbance.altitude_wander_m)));
  t.push_back(real("survey.disturbance", "heading_wander_deg", "deg", 0, 45, false,
                   DEG(vehicle.disturbance.heading_wander_rad)));
  t.push_back(real("survey.disturbance", "wander_period_s", "s", 0, 1e5, true,
                   PLAIN(vehicle.disturbance.wander_period_s)));
}

// The option table: the seed, then each section's rows (all() keeps this order).
std::vector<Option> make_table() {
  std::vector<Option> t;
  t.push_back({"",
               "seed",
               "",
               Kind::seed,
               0,
               kInf,
               false,
               &kSeed,
               "",
               {},
               "",
               [](const S& s) { return static_cast<double>(s.config.seed); },
               [](S& s, double v) { s.config.seed = static_cast<std::uint64_t>(v); }});
  add_sonar_options(t);
  add_render_options(t);
  add_noise_options(t);
  add_output_options(t);
  add_sensor_options(t);
  add_limits_options(t);
  add_survey_options(t);
  return t;
}

#undef PLAIN
#undef SCALED
#undef DEG
#undef BOOL

}  // namespace

std::string Option::path() const {
  return section.empty() ? std::string(key) : std::string(section) + "." + std::string(key);
}

std::string Option::bounds() const {
  std::ostringstream c;
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo) c << (lo_open ? "> " : ">= ") << lo;
  if (has_hi) c << (has_lo ? " and <= " : "<= ") << hi;
  return c.str();
}

std::string Option::constraint() const {
  if (kind == Kind::choice) return std::string(choice_constraint);
  if (kind == Kind::boolean) return "true or false";
  if (!std::isfinite(lo) && !std::isfinite(hi)) return "a finite number";
  return std::string(key) + " " + bounds();
}

bool Option::accepts(double v) const {
  return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
}

const std::vector<Option>& all() {
  static const std::vector<Option> table = make_table();
  return table;
}

std::vector<const Option*> in_section(std::string_view section) {
  std::vector<const Option*> out;
  for (const Option& o : all()) {
    if (o.section == section) out.push_back(&o);
  }
  return out;
}

const std::vector<const Flag*>& flags() {
  static const std::vector<const Flag*> list = [] {
    std::vector<const Flag*> out;
    for (const Option& o : all()) {
      if (o.flag && std::find(out.begin(), out.end(), o.flag) == out.end()) out.push_back(o.flag);
    }
    return out;
  }();
  return list;
}

const Option& at(std::string_view path) {
  for (const Option& o : all()) {
    if (o.path() == path) return o;
  }
  throw std::out_of_range("no option " + std::string(path));
}

std::uint64_t seed_of(const SimulationSetup& s) {
  return s.config.seed;
}

void read(const yaml::Fields& f, const Option& o, SimulationSetup& s) {
  const std::string key(o.key);
  switch (o.kind) {
    case Kind::seed:
      if (f.given(key)) s.config.seed = f.seed(key, 0);
      return;
    case Kind::boolean:
      if (f.given(key)) o.set(s, f.boolean(key, false) ? 1.0 : 0.0);
      return;
    case Kind::choice: {
      if (!f.given(key)) return;
      const std::string name = f.text(key);
      for (std::size_t i = 0; i < o.choices.size(); ++i) {
        if (o.choices[i] == name) return o.set(s, static_cast<double>(i));
      }
      f.fail_value(key, std::string(o.choice_constraint));
    }
    case Kind::real:
    case Kind::integer: {
      if (!f.given(key)) {
        // The struct's default must itself be allowed: a value without a usable default (a
        // chirp's bandwidth) is required.
        const double d = o.get(s);
        if (!std::isnan(d) && !o.accepts(d)) f.fail_value(key, o.constraint());
        return;
      }
      if (!o.word.empty() && f.node()[key].IsScalar() && f.node()[key].Scalar() == o.word) {
        return o.set(s, kNaN);
      }
      const double v = f.number(key);
      if (!o.accepts(v)) f.fail_value(key, o.constraint());
      if (o.kind == Kind::integer && v != std::floor(v)) {
        f.fail_value(key, std::string(o.key) + " a whole number");
      }
      return o.set(s, v);
    }
  }
}

void read_all(const yaml::Fields& f, std::string_view section, SimulationSetup& s) {
  for (const Option* o : in_section(section)) read(f, *o, s);
}

YAML::Node emit(const Option& o, const SimulationSetup& s) {
  YAML::Node n;
  const double v = o.kind == Kind::seed ? 0.0 : o.get(s);
  switch (o.kind) {
    case Kind::seed:
      n = s.config.seed;
      break;
    case Kind::boolean:
      n = v != 0.0;
      break;
    case Kind::choice:
      n = std::string(o.choices[static_cast<std::size_t>(v)]);
      break;
    case Kind::integer:
      if (std::isnan(v)) {
        n = std::string(o.word);
      } else {
        n = static_cast<std::int64_t>(v);
      }
      break;
    case Kind::real:
      if (std::isnan(v)) {
        n = std::string(o.word);
      } else {
        n = v;
      }
      break;
  }
  return n;
}

}  // namespace sonarsynth::options

namespace sonarsynth {

std::vector<OverrideFlag> override_flags() {
  std::vector<OverrideFlag> out;
  for (const options::Flag* f : options::flags()) {
    out.push_back({std::string(f->name.substr(2)), std::string(f->help)});
  }
  return out;
}

void set_override(SimulationOverrides& overrides, const std::string& name,
                  const std::string& text) {
  for (const options::Flag* f : options::flags()) {
    if (f->name.substr(2) == name) return f->parse(overrides, text, f->name);
  }
  throw std::invalid_argument("set_override: no flag --" + name);
}

}  // namespace sonarsynth
