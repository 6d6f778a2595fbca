// SPDX-License-Identifier: MIT
// The sensor stage of the Simulator (docs/physics.md §1.10): volume reverberation, shadow fill
// and the first bottom return added to the mean echo; speckle looks, receiver noise and the
// detector; the transmit ring-down. Internal.
#pragma once

#include <cstdint>
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
  double fill_power = 0.0;         ///< shadow fill beyond the first return; 0 = off
  double first_return_rho = 0.0;   ///< Kirchhoff reflection coefficient; 0 = off
  double first_return_s2 = 0.0;    ///< RMS slope squared
  double side_lobe_two_way = 0.0;  ///< two-way side-lobe floor of the vertical beam
  double ring_down_m = 0.0;        ///< 0 = off

  /// From the configuration: `seabed_power` is the mean output power of the calibration seabed
  /// (the reference of the "re seabed" levels).
  static SensorModel make(const SimulationConfig& config, double seabed_power,
                          double reference_altitude_m);
};

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
/// shadow fill per sample, already divided by out_gain (empty when off).
struct SensorMeanTables {
  std::vector<double> volume, fill;
  SensorMeanTables() = default;
  SensorMeanTables(const SensorModel& m, const SideParams& side, std::span<const double> out_gain);
};
/// The same with the tables (identical values): no division per sample and ping.
void add_sensor_mean_terms(const SensorModel& m, const SideParams& side,
                           const SensorMeanTables& tables, double altitude_m,
                           double axis_depression_rad, std::span<double> mean);

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
};
/// Per-run factors of along_track_speckle that depend on the sample index only (the lattice
/// step and footprint per range), rebuilt when the spacing, beam or sample count change.
struct AlongTrackTable {
  double sample_spacing_m = 0.0, beam_3db_rad = 0.0;
  std::vector<double> sw;        ///< r theta / sqrt(8 ln 2) per sample
  std::vector<double> inv_step;  ///< 1 / (lattice step) per sample
  void prepare(double sample_spacing_m, double beam_3db_rad, std::size_t samples);
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
  std::vector<double> sub, combined, field, base;
  std::vector<std::uint64_t> keys, noise_keys;
  AlongTrackTable along_track;
};

/// Speckle, receiver noise and detection: `io` holds the mean intensity before TVG on entry and
/// the detected output power on return. Per sub-sample j < m.sub_samples: the speckle of
/// apply_speckle_noise with the keyed words of look j, times out_gain, plus exponential receiver
/// noise of mean m.floor_power keyed by (noise_keys, j); the looks are combined by the detector
/// on the envelope (max, or the square of the mean envelope). Look 0 draws exactly what
/// apply_speckle_noise draws for `keys` and `noise_keys`; look j > 0 the same with seeds of its
/// own. The texture (keyed by `keys`) is the seabed patch's: all looks share it. With `field`,
/// the frozen speckle of each look is along_track_speckle where it is not NaN.
void detect_speckle(const SensorModel& m, const SpeckleNoise& speckle,
                    std::span<const std::uint64_t> keys, std::span<const std::uint64_t> noise_keys,
                    std::span<const double> texture_nu, std::span<const double> out_gain,
                    const AlongTrackField* field, DetectorScratch& scratch, std::span<double> io);

/// Median of the detected output power of a seabed of unit mean power through speckle with
/// texture shape `nu` (0 = none) and the detector, without receiver noise: the automatic gain's
/// speckle correction. Deterministic (fixed keys).
double detected_median_of_unit_mean(const SensorModel& m, double nu, std::uint64_t seed);

}  // namespace sonarsynth
