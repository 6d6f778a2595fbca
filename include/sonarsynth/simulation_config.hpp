// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <limits>
#include <string_view>

#include "sonarsynth/absorption.hpp"
#include "sonarsynth/backscatter.hpp"
#include "sonarsynth/scene.hpp"
#include "sonarsynth/sonar.hpp"

/// Everything a simulation is configured with (the YAML `sonar`, `physics`, `quality`, `noise`
/// and `output` sections; docs/scene-format.md): plain values with their defaults; validate()
/// throws InputError naming the field.
namespace sonarsynth {

/// Which physics is on. Every switch that is off costs nothing in the inner loop.
struct PhysicsConfig {
  /// paper (default, reproduces Gwon et al.: per-ray R K Phi cos(theta), equal to Lambert with
  /// mu = R) or lambert (per-material mu).
  BackscatterModel backscatter = BackscatterModel::paper;
  bool shadows = true;
  bool spreading = true;     ///< two-way r^-4
  bool beam_pattern = true;  ///< vertical beam pattern (off: uniform)
  bool absorption = true;    ///< Francois-Garrison from sonar frequency and `water`
  /// Object glints: facets of objects whose material has a specular_rho add its Kirchhoff lobe
  /// (docs/physics.md §1.11). Off: the backscatter law alone (the closed forms of §3).
  bool object_glints = true;
  Seawater water;
  double calibration_k = 1.0;  ///< global constant K, > 0 (never per ping)
};

/// Speed/accuracy knobs of the renderer.
struct QualityConfig {
  /// along_track_planes value that lets the Simulator choose the count (see below).
  static constexpr int kAutoPlanes = 0;
  ProfileOptions profile;
  int gauss_points = 2;  ///< [1, 5]
  /// K beam planes across the horizontal beam, [1, 64], or kAutoPlanes (the default): the fewest
  /// of 1, 3, 5, 9, 15 planes whose estimated along-track error, the RMS dB difference per lit
  /// bin against the next count over a few pilot pings, is at most along_track_tolerance_db. A
  /// smooth seabed gets one plane; one rough on the scale of the beam's along-track footprint
  /// gets as many as it needs.
  int along_track_planes = kAutoPlanes;
  double along_track_tolerance_db = 1.0;  ///< auto only, > 0
  /// Finer planes in the pings that see an object narrower along the track than the planes'
  /// spacing at its range, so that it appears in every ping whose beam covers it, weighted by
  /// the horizontal pattern (docs/physics.md §1.3). Off: such an object shows in the pings
  /// whose planes happen to cross it, at a whole plane's share.
  bool small_object_planes = true;
  void validate() const;

  /// The `--quality` presets, applied over the configured values (docs/scene-format.md):
  /// "fast" = 1 Gauss point, 8 object segments, 1 along-track plane, no small-object planes;
  /// "default" changes nothing;
  /// "high" = 4 grid subdivisions, 3 Gauss points, automatic along-track planes with a 0.25 dB
  /// tolerance. Returns false (and changes nothing) for any other name.
  bool apply_preset(std::string_view name) {
    if (name == "fast") {
      gauss_points = 1;
      profile.object_segments = 8;
      along_track_planes = 1;
      small_object_planes = false;
    } else if (name == "high") {
      profile.grid_subdivisions = 4;
      gauss_points = 3;
      along_track_planes = kAutoPlanes;
      along_track_tolerance_db = 0.25;
    } else if (name != "default") {
      return false;
    }
    return true;
  }
  /// "fast, default or high".
  static constexpr const char* kPresetNames = "fast, default or high";
};

struct NoiseConfig {
  enum class Model {
    kNone,     ///< noise-free intensities
    kPaper,    ///< Gwon eq. (2): I(1 + u) + r
    kSpeckle,  ///< complex Gaussian speckle (+ K texture per material) + thermal noise
  };
  Model model = Model::kSpeckle;
  double paper_uniform_half_width = 0.3;  ///< a of eq. (2), [0, 1]
  /// Signal-to-noise ratio, dB. Speckle model: thermal noise power (added before detection and
  /// before TVG) is this far below a flat seabed of the default material at maximum range.
  /// Paper model (image domain, after TVG): the mean of the Rayleigh term is this far below the
  /// calibrated mid-range seabed level.
  double snr_at_max_range_db = 20.0;
  bool texture = true;  ///< K-distribution texture from the materials' shape nu
  /// Speckle from scatterers frozen per range cell along the track and weighted by the
  /// horizontal beam (docs/physics.md §1.6): consecutive pings correlate as their footprints
  /// overlap. false = speckle frozen per seabed cell of freeze_cell_m.
  bool along_track_correlation = true;
  /// With along_track_correlation: the footprint of the array's near field and the decorrelation
  /// of a translated aperture (docs/physics.md §1.6): pings d apart correlate as the overlap of
  /// the array's co-array, at every range (false: the far-field footprint r theta alone).
  bool aperture_translation = true;
  /// Speckle correlated in range by the system's resolution: the complex echo filtered by the
  /// pulse through its matched filter (docs/physics.md §1.6). false: independent samples.
  bool range_correlation = true;
  /// Size of the seabed cells whose speckle is frozen (the same for every ping that sees them),
  /// metres, >= 0; 0 = the sonar's range resolution.
  double freeze_cell_m = 0.0;
  /// Paper model: the founding paper's gamma, the variance of u ~ U(0, sqrt(12 gamma)) in
  /// eq. (2), [0, 1/3]; NaN (default) = u ~ U(-a, a) with a = paper_uniform_half_width
  /// (docs/physics.md §1.6: the same variance for a = sqrt(3 gamma), shifted by a).
  double paper_uniform_variance = std::numeric_limits<double>::quiet_NaN();
};

/// Time-varied gain law (docs/physics.md §1.2).
enum class TvgLaw {
  none,       ///< G = constant_db only
  spherical,  ///< G(r) = k log10(r) + 2 a alpha r + constant_db (OutputScaling::tvg_*)
};

/// What a stored sample holds (docs/physics.md §1.10).
enum class SampleQuantity {
  amplitude,  ///< the envelope, sqrt of the (TVG'd, scaled) intensity: what side-scan sonars store
  intensity,  ///< the (TVG'd, scaled) intensity, power
};

/// How a stored sample combines its detector sub-samples (OutputScaling::detector_sub_samples).
enum class DetectorMode {
  max,   ///< the largest envelope (peak-hold downsampling)
  mean,  ///< the mean envelope (boxcar downsampling)
};

/// TVG, detection and quantisation into the output sample range.
struct OutputScaling {
  TvgLaw tvg = TvgLaw::spherical;  ///< k log R + 2 a alpha R (alpha = the simulation's)
  /// k, dB per decade of range, [0, 60]. 30 holds a flat seabed's Lambert level flat in range;
  /// real side-scans apply less, so that the far range falls (docs/physics.md §1.2).
  double tvg_spreading_db_per_decade = 20.0;
  /// a, the share of the two-way absorption the TVG compensates, [0, 1].
  double tvg_absorption_share = 1.0;
  /// Stored quantity; amplitude by default, as real side-scan sonars store the envelope.
  SampleQuantity quantity = SampleQuantity::amplitude;
  /// Envelope sub-samples per stored sample, [1, 16]: a real sonar digitises faster than it
  /// stores and keeps the maximum (or mean) of each group. Each sub-sample has its own speckle
  /// and receiver noise (independent looks); 1 = single-look. Speckle model only.
  int detector_sub_samples = 3;
  DetectorMode detector = DetectorMode::max;
  double max_value = 32767.0;  ///< XTF u16 profile
  bool round_to_integer = true;
  /// Gain before quantisation, dB (applied to intensity); NaN = automatic: the median stored
  /// value of a flat seabed of the default material at mid range, speckled by the configured
  /// noise and detector, lands at seabed_median_dbfs (computed once per run, global).
  double gain_db = std::numeric_limits<double>::quiet_NaN();
  /// Target of the automatic gain, dB re max_value: 20 log10(median / max_value) for amplitude,
  /// 10 log10 for intensity. < 0. The default puts the median over a real swath (beam pattern and
  /// grazing angles included) about 12 dB below full scale, as real side-scan sonars do.
  double seabed_median_dbfs = -8.0;
  /// The founding paper's K = 1/Imax (docs/paper-model.md). none (default): the global
  /// calibration above. per_ping_max: every ping is scaled so that its largest noise-free sample
  /// after TVG (over both sides) is max_value, before the noise; gain_db then cancels out. This
  /// breaks the radiometry from ping to ping (a bright target darkens its whole ping): for the
  /// paper preset and display only. Costs a second noise-free render of each ping.
  enum class Normalise { none, per_ping_max };
  Normalise normalise = Normalise::none;
};

/// Sensor effects beyond the seabed echo (docs/physics.md §1.10). Each is off when its level is
/// NaN (`off` in a scene file) and then costs nothing. Levels "re seabed" are relative to the
/// mean stored intensity of a flat seabed of the default material at mid range (the automatic
/// gain's reference), in the TVG'd output domain.
struct SensorConfig {
  /// Receiver noise after TVG and gain (electronics, ADC): RMS level of the stored quantity,
  /// dB re max_value (20 log10 for amplitude). Keeps the water column and shadows off zero.
  double noise_floor_dbfs = -62.0;
  /// Volume reverberation (water-column scatterers), dB re seabed, at the reference altitude;
  /// after the spherical TVG it grows in proportion to the range (volume r^-2 against r^-3).
  double volume_reverberation_db = -33.0;
  /// Shadow fill (multipath and side-lobe energy reaching occluded ranges), dB re seabed,
  /// incoherent, everywhere beyond the first bottom return.
  double shadow_fill_db = -25.0;
  /// First bottom return: near-normal (Kirchhoff) backscatter of the seabed below the sensor,
  ///   sigma(theta) = rho / (8 s^2 cos^4 theta) exp(-tan^2 theta / (2 s^2)),
  /// theta the incidence from the vertical, rho the energy reflection coefficient, s the RMS
  /// slope, seen through the vertical beam with side lobes no lower than side_lobe_db.
  /// NaN rho = off.
  double first_return_reflection_db = -20.0;  ///< 10 log10(rho), <= 0
  double first_return_rms_slope = 0.3;        ///< s, (0, 1]
  /// One-way side-lobe level of the vertical beam towards nadir, dB re the main lobe, <= 0.
  double side_lobe_db = -16.0;
  /// Transmit pulse and ring-down: samples nearer than this slant range (at most a tenth of
  /// the range) saturate, metres, >= 0; NaN or 0 = off.
  double ring_down_m = 0.15;
  /// Patchiness (docs/physics.md §1.10): the volume reverberation and the shadow fill are
  /// multiplied by unit-mean Gamma textures of these shapes, frozen on patches of their own
  /// (along track x slant range): sparse scatterers in the water column (fish,
  /// bubbles, particles) and blotchy multipath in shadows. NaN = uniform.
  double volume_texture_shape = 0.2;
  double shadow_fill_texture_shape = 0.2;
  double volume_patch_along_track_m = 0.3;       ///< > 0 (about the array's footprint)
  double volume_patch_range_m = 0.0;             ///< >= 0; 0 = the sonar's range resolution
  double shadow_fill_patch_along_track_m = 0.5;  ///< > 0
  double shadow_fill_patch_range_m = 0.3;        ///< > 0
  void validate() const;
  /// Every effect off: the bare seabed echo (what the closed forms of docs/physics.md §3 hold
  /// for).
  static SensorConfig none();
};

struct SimulationConfig {
  SonarConfig sonar;
  PhysicsConfig physics;
  QualityConfig quality;
  NoiseConfig noise;
  OutputScaling output;
  SensorConfig sensor;
  bool truth = true;  ///< per-sample truth in the rendered pings
  /// Also output the noise-free samples of every ping (SideOutput::clean_samples), rendered in
  /// the same call as the noisy ones.
  bool clean_samples = false;
  std::uint64_t seed = 1;  ///< every random draw derives from it
  unsigned threads = 0;    ///< 0 = hardware concurrency; output identical for any value
  void validate() const;
};

}  // namespace sonarsynth
