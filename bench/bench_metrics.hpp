// SPDX-License-Identifier: MIT
// Per-bin error of a rendered ping against a reference, in dB, and the small helpers the
// benchmark drivers share: medians, wall-clock timing, peak RSS, CSV output, Pareto front.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

namespace bench {

/// Bins where the reference is below kFloorRel x (median of the reference's non-zero bins) are
/// ignored (water column, shadows, beyond the seabed).
inline constexpr double kFloorRel = 1e-3;
/// A bin the method leaves empty (or at < 1e-4 of the reference) counts as this many dB.
inline constexpr double kCapDb = 40.0;

/// Accumulates |10 log10(got / ref)| over many bins (pings). Bins next to a reference bin below
/// the floor (a shadow or first-return edge) are accumulated separately ("edge").
struct ErrorStats {
  double sum_sq_db = 0.0;
  double worst_db = 0.0;
  std::size_t bins = 0;
  double edge_sum_sq_db = 0.0;
  double edge_worst_db = 0.0;
  std::size_t edge_bins = 0;
  std::size_t empty = 0;      ///< method bin empty where the reference is lit
  std::size_t nonfinite = 0;  ///< method bins that are NaN / inf / negative

  /// Adds one ping (or side): got and ref have the same size; ranges [begin, end) of bins are
  /// compared in blocks of `block` (one side each) so that edges do not span sides.
  void add(const std::vector<double>& got, const std::vector<double>& ref, std::size_t block);
  double rms_db() const;
  double edge_rms_db() const;
  /// RMS over every compared bin, interior and edge.
  double all_rms_db() const;
  double empty_fraction() const;
};

/// One compared bin's error (see ErrorStats::add for which bins are compared).
struct BinError {
  double error_db = 0.0;  ///< |10 log10(got / ref)|, capped at kCapDb
  std::size_t index = 0;  ///< bin index in the compared vector
  bool edge = false;      ///< next to a reference bin below the floor
};

/// The `count` largest errors of `got` against `ref` (same bins, floor and cap as ErrorStats::add),
/// largest first, appended to `out` (which is kept sorted and cut to `count`); `offset` is added
/// to the indices (e.g. ping x bins).
void worst_bins(const std::vector<double>& got, const std::vector<double>& ref, std::size_t block,
                std::size_t count, std::size_t offset, std::vector<BinError>& out);

double median(std::vector<double> v);
double now_s();
/// Peak resident set size of this process, MiB (getrusage).
double peak_rss_mib();

/// Points on the lower-left Pareto front of (time, error) (smaller is better in both). Errors
/// are exact; times are measurements: j dominates i when error_j <= error_i, time_j <= time_i
/// and either error_j < error_i or time_j < (1 - time_tolerance) time_i, so two settings of equal
/// error whose times differ by less than the measurement noise are both on the front.
std::vector<bool> pareto_front(const std::vector<double>& time, const std::vector<double>& error,
                               double time_tolerance = 0.0);

/// Opens `path` for writing (directories must exist); throws std::runtime_error on failure.
std::FILE* open_csv(const std::string& path, const char* header);

}  // namespace bench
