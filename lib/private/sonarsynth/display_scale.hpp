// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace sonarsynth {

/// The dB window a display product maps to [0, 1]. Values are linear intensities; the window
/// is in dB (10 log10), applied to display copies only — data products stay linear.
struct DisplayRange {
  double lo_db = 0.0;  ///< maps to 0
  double hi_db = 1.0;  ///< maps to 1, > lo_db
  /// > 0: linear display instead, value = linear / linear_full_scale (the founding paper's grey
  /// level I of eq. 1 with K = 1/Imax, docs/paper-model.md); lo_db and hi_db are then unused.
  double linear_full_scale = 0.0;

  /// Display value in [0, 1] of a linear intensity: NaN for NaN (nodata), 0 for values <= 0.
  double value(float linear) const;
  /// What the window is, for SONARSYNTH_DISPLAY_SCALE: "10 log10(linear) from A dB (0) to B dB
  /// (1)" or "linear: value / F (1)".
  std::string describe() const;
};

/// Percentiles (in [0, 100], lo < hi) of 10 log10 of the finite positive values, from a regular
/// subsample of at most `max_samples` values; a window of 1 dB if they coincide. Returns
/// {0, 1} if there is no finite positive value.
DisplayRange robust_db_range(std::span<const float> linear, double lo_percentile = 1.0,
                             double hi_percentile = 99.0, std::size_t max_samples = 1'000'000);

/// robust_db_range of values that arrive in pieces (an image streamed row by row): add() the
/// `count` values in order, then range() returns exactly what robust_db_range would on all of
/// them, holding only the subsample (at most 2 x max_samples + 1 floats, whatever `count`).
class DbRangeSampler {
 public:
  explicit DbRangeSampler(std::size_t count, std::size_t max_samples = 1'000'000);
  /// The next values of the sequence.
  void add(std::span<const float> linear);
  /// Throws InputError unless 0 <= lo_percentile < hi_percentile <= 100.
  DisplayRange range(double lo_percentile, double hi_percentile);

 private:
  std::size_t stride_;
  std::size_t seen_ = 0;  ///< values added so far
  /// The subsample's finite positive values, linear (log10 is monotonic: the percentiles are
  /// the same values; only the two picked are converted to dB).
  std::vector<float> values_;
};

}  // namespace sonarsynth
