// SPDX-License-Identifier: MIT
// The sensor stage of the Simulator (docs/physics.md §1.10): volume reverberation, shadow fill
// and the first bottom return added to the mean echo; speckle looks, receiver noise and the
// detector; the transmit ring-down. Internal.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "sonarsynth/noise.hpp"
#include "sonarsynth/render_side.hpp"
#include "sonarsynth/simulation_config.hpp"

namespace sonarsynth {

/// The per-run sensor model, in the output domain (after TVG and gain; "power" = the stored
/// value squared for amplitude output, the stored value for intensity output).
struct SensorModel {
  bool amplitude = true;
  int sub_samples = 1;
  DetectorMode detector = DetectorMode::max;
  double full_scale_power = 0.0;  ///< max_value^2 (amplitude) or max_value (intensity)
  double floor_power = 0.0;       ///< mean receiver-noise power; 0 = off
  double volume_power = 0.0;      ///< volume reverberation at reference_altitude_m; 0 = off
  double reference_altitude_m = 1.0;
  double fill_power = 0.0;              ///< shadow fill beyond the first return; 0 = off
  double first_return_rho = 0.0;        ///< Kirchhoff reflection coefficient; 0 = off
  double first_return_rms_slope = 0.0;  ///< s
  double side_lobe_two_way = 0.0;       ///< two-way side-lobe floor of the vertical beam
  double ring_down_m = 0.0;             ///< 0 = off
  /// What the TVG leaves of the seabed's fall with range, f(r) = r^-e exp(-b r) (1 for the
  /// compensating 30 log R + 2 alpha R): e = (30 - k) / 10, b = 2 (1 - a) alpha ln 10 / 10.
  double tvg_deficit_exponent = 0.0, tvg_deficit_per_m = 0.0;
  double mid_range_m = 1.0;  ///< where the "re seabed" reference seabed is (half the range)
  /// Patchiness of the volume reverberation and the shadow fill (docs/physics.md §1.10): each
  /// is multiplied by a unit-mean Gamma(nu) texture frozen on patches of its own (along-track
  /// position x slant range, metres); nu = 0: uniform.
  double volume_texture_nu = 0.0, fill_texture_nu = 0.0;
  double volume_patch_along_m = 0.3, volume_patch_range_m = 0.05;
  double fill_patch_along_m = 0.5, fill_patch_range_m = 0.3;
  std::uint64_t patch_seed = 0;
  double tvg_deficit(double r) const {
    return std::pow(r, -tvg_deficit_exponent) * std::exp(-tvg_deficit_per_m * r);
  }
  /// Range filter of the complex echo (docs/physics.md §1.6): taps h_k, k = -K .. K, sum
  /// h_k^2 = 1, sample spacing apart; empty = off (each sample's speckle independent in range).
  std::vector<double> range_taps;

  /// From the configuration: `seabed_power` is the mean output power of the calibration seabed
  /// (the reference of the "re seabed" levels).
  static SensorModel make(const SimulationConfig& config, double seabed_power,
                          double reference_altitude_m);
};

/// The range filter's taps of a sonar (empty when the filter would be a single tap): the
/// complex impulse response of the transmitted pulse through its matched filter, integrated
/// over each sample's range cell and normalised to unit power gain. CW pulse of range window
/// W = c tau / 2: a triangle of half-width W; chirp, W = c / (2 B): sinc(x / W), cut at 3 W.
std::vector<double> range_filter_taps(const SonarConfig& sonar);

/// Adds the mean terms of the sensor model to `mean` (linear intensity before TVG, sample i
/// covering slant ranges [i dr, (i + 1) dr)): volume reverberation everywhere, shadow fill from
/// the first return (slant range `altitude_m`) on, and the near-normal first bottom return of a
/// locally flat seabed `altitude_m` below the sensor, integrated per bin in across-track distance
/// (4-point Gauss–Legendre) with the physics of `side` (K, beta_eff, spreading, absorption, the
/// vertical beam at `axis_depression_rad` with the side-lobe floor). `out_gain[i]` converts
/// sample i to the output domain. A non-finite or non-positive altitude skips the terms that
/// need it.
void add_sensor_mean_terms(const SensorModel& m, const SideParams& side, double altitude_m,
                           double axis_depression_rad, std::span<const double> out_gain,
                           std::span<double> mean);

/// The range-only factors of add_sensor_mean_terms, once per run: volume reverberation and
/// shadow fill per sample, already divided by out_gain (empty when off). Also what the calls
/// keep between pings (one SensorMeanTables per thread, used with the model and side it was
/// built for): the first return of the last altitude, and the patch textures' rows of node
/// values (consecutive pings of a side read the same along-track rows). The cached values are
/// those the computation gives, so the output does not depend on which pings a thread rendered
/// before.
struct SensorMeanTables {
  std::vector<double> volume, fill;
  /// The first return at (altitude_m, axis_depression_rad) for `samples` samples: bin
  /// first + k gets values[k] (NaN: nothing added).
  struct FirstReturn {
    double altitude_m = std::numeric_limits<double>::quiet_NaN();
    double axis_depression_rad = std::numeric_limits<double>::quiet_NaN();
    std::size_t samples = 0, first = 0;
    std::vector<double> values;
  } first_return;
  /// A row of a patch texture's node values: texture `stream`, along-track patch `along`, the
  /// value per range patch computed for patches [lo, hi).
  struct TextureRow {
    std::uint64_t stream = 0, along = 0, last_use = 0;
    bool used = false;
    std::size_t lo = 0, hi = 0;
    std::vector<double> nodes;
  };
  std::vector<TextureRow> texture_rows;
  std::uint64_t texture_clock = 0;
  /// Per-run range geometry of a patch texture: per sample its range patch (node) index and the
  /// weight of the next node (empty when off, or when the patches are finer than the samples).
  struct TextureCells {
    std::vector<std::int64_t> cell;
    std::vector<double> weight;
  } volume_cells, fill_cells;
  std::vector<double> texture_nodes;  ///< the nodes at a ping's along-track position (scratch)
  SensorMeanTables() = default;
  SensorMeanTables(const SensorModel& m, const SideParams& side, std::span<const double> out_gain);
};
/// Where a ping side is, for the patch textures: the survey line and side, and the along-track
/// position (metres).
struct PatchKey {
  std::uint64_t line_side = 0;
  double along_track_m = 0.0;
};
/// The same with the tables (identical values): no division per sample and ping, and the first
/// return and texture rows reused from earlier calls where they apply. With `patch` and a texture
/// shape, the volume and fill terms take their patch textures.
void add_sensor_mean_terms(const SensorModel& m, const SideParams& side, SensorMeanTables& tables,
                           double altitude_m, double axis_depression_rad, std::span<double> mean,
                           const PatchKey* patch = nullptr);

/// The speckle field of one side of one ping from scatterers frozen per range cell along the
/// track (docs/physics.md §1.6): sample i (range r = (i + 1/2) dr) sums the complex scatterers
/// of the lattice m sw (sw = r theta / sqrt(8 ln 2), theta the one-way -3 dB horizontal beam),
/// weighted by the two-way amplitude pattern exp(-(m sw - s)^2 / (2 sw^2)) around the ping's
/// along-track position s; the scatterer of (key, i, m, look) is a keyed circular Gaussian.
struct AlongTrackField {
  double along_track_m = 0.0;
  std::uint64_t key = 0;  ///< survey line and side
  double sample_spacing_m = 1.0;
  double beam_3db_rad = 0.0;
  std::uint64_t seed = 0;
  std::size_t first_sample = 0;  ///< the first bottom return's sample
  double ping_spacing_m = 0.0;   ///< distance between consecutive pings; 0 = unknown
  /// Length D of the receiving array along the track, metres; 0 = the far-field footprint alone
  /// (sw as above). With D > 0 the lattice width is the correlation width of a translated
  /// aperture (docs/physics.md §1.6): 1 / sw^2 = 1 / sc^2 + 1 / (sw_far^2 + D^2), sc = D /
  /// sqrt(24) the co-array's width, so that pings d apart correlate as exp(-d^2 / (4 sw^2))
  /// (complex field) whatever the range, as in the array's near field.
  double array_length_m = 0.0;
};
/// Per-run factors of along_track_speckle that depend on the sample index only (the lattice
/// step and footprint per range), rebuilt when the spacing, beam or sample count change, and
/// the lattice's buffers.
struct AlongTrackTable {
  double sample_spacing_m = 0.0, beam_3db_rad = 0.0, array_length_m = 0.0;
  std::vector<double> sw;        ///< lattice width per sample (AlongTrackField::array_length_m)
  std::vector<double> inv_step;  ///< 1 / (lattice step) per sample
  double sw_max = 0.0;           ///< the largest sw (0 without samples; NaN if any is NaN)
  std::vector<float> re, im;
  std::vector<double> norm, pad;
  void prepare(double sample_spacing_m, double beam_3db_rad, std::size_t samples,
               double array_length_m = 0.0);
};

/// Unit-mean speckle power per sample of look `look` into `out` (resized to `samples`).
void along_track_speckle(const AlongTrackField& f, std::size_t samples, int look,
                         AlongTrackTable& table, std::vector<double>& out);
void along_track_speckle(const AlongTrackField& f, std::size_t samples, int look,
                         std::vector<double>& out);
/// Looks first_look .. first_look + looks - 1 at once (the lattice geometry and weights shared):
/// look first_look + j in out[j samples .. (j + 1) samples), the same values as one look at a
/// time. Looks are 0 .. 255 (else std::invalid_argument).
void along_track_speckle_looks(const AlongTrackField& f, std::size_t samples, int first_look,
                               int looks, AlongTrackTable& table, std::vector<double>& out);

/// Reusable buffers of detect_speckle (one per thread).
struct DetectorScratch {
  std::vector<double> sub, combined, field, base, re, im;
  std::vector<std::uint64_t> keys, noise_keys;
  AlongTrackTable along_track;
};

/// Speckle, receiver noise and detection: `io` holds the mean intensity before TVG on entry and
/// the detected output power on return. Per sub-sample (look) j < m.sub_samples: the speckle of
/// apply_speckle_noise's distribution (frozen Exp(1) power keyed by `keys`, thermal noise added
/// before detection keyed by `noise_keys`), times out_gain, plus exponential receiver noise of
/// mean m.floor_power keyed by (noise_keys, j); the looks are combined by the detector on the
/// envelope (max, or the square of the mean envelope). The default sampler draws them in the
/// vector kernels of sensor_kernel.hpp (counter-hash words of their own, docs/physics.md §1.6:
/// detect, or detect_filtered with the range filter); SpeckleSampler::exact as before
/// (apply_speckle_noise per look, looks j > 0 with seeds of their own, no filter). The texture
/// (keyed by `keys`, sensor_kernel::texture) is the seabed patch's: all looks share it. With
/// `field`, the frozen speckle of each look is the along-track lattice's where it applies.
void detect_speckle(const SensorModel& m, const SpeckleNoise& speckle,
                    std::span<const std::uint64_t> keys, std::span<const std::uint64_t> noise_keys,
                    std::span<const double> texture_nu, std::span<const double> out_gain,
                    const AlongTrackField* field, DetectorScratch& scratch, std::span<double> io);

/// Median of the detected output power of a seabed of unit mean power through speckle with
/// texture shape `nu` (0 = none) and the detector, without receiver noise: the automatic gain's
/// speckle correction. Deterministic (fixed keys).
double detected_median_of_unit_mean(const SensorModel& m, double nu, std::uint64_t seed);

}  // namespace sonarsynth
