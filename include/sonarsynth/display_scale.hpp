// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <span>

namespace sonarsynth {

/// The dB window a display product maps to [0, 1]. Values are linear intensities; the window
/// is in dB (10 log10), applied to display copies only — data products stay linear.
struct DisplayRange {
  double lo_db = 0.0;  ///< maps to 0
  double hi_db = 1.0;  ///< maps to 1, > lo_db

  /// Display value in [0, 1] of a linear intensity: NaN for NaN (nodata), 0 for values <= 0.
  double value(float linear) const;
};

/// Percentiles (in [0, 100], lo < hi) of 10 log10 of the finite positive values, from a regular
/// subsample of at most `max_samples` values; a window of 1 dB if they coincide. Returns
/// {0, 1} if there is no finite positive value.
DisplayRange robust_db_range(std::span<const float> linear, double lo_percentile = 1.0,
                             double hi_percentile = 99.0, std::size_t max_samples = 1'000'000);

}  // namespace sonarsynth
