// SPDX-License-Identifier: MIT
// Bottom tracking from the first return and empirical across-track gain normalisation: what
// survey software does to real side-scan before slant-range correction and mosaicking
// (docs/conversion.md gives the definitions and the reasons for the defaults).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace sonarsynth {

/// Parameters of the first-return detector (docs/conversion.md).
struct BottomTrackOptions {
  /// Centred running mean of the samples before detection (odd, >= 1).
  std::size_t smooth_samples = 5;
  /// Threshold between the water level (5th percentile of the smoothed side) and the seabed
  /// level (75th percentile) in dB: water x (seabed / water)^fraction, fraction in (0, 1).
  double threshold_fraction = 0.4;
  /// A pick needs seabed / water >= this ratio (linear amplitude); else no pick.
  double min_contrast = 2.0;
  /// The median of the smoothed samples over the hold_samples from the crossing must stay
  /// above the threshold (rejects an isolated spike in the water column).
  std::size_t hold_samples = 15;
  /// Move the threshold crossing back to the leading edge: where the level reaches the middle
  /// (in dB) of the water column's level and the seabed's level at the crossing, repeated
  /// while it moves (docs/conversion.md); false keeps the crossing.
  bool leading_edge = true;
  /// Along-track median window, in pings (odd, >= 1).
  std::size_t median_pings = 9;
  /// A side's pick farther than this many samples from its along-track median is an outlier
  /// and is replaced by the median.
  double outlier_samples = 4.0;
  /// auto: the header altitude is used unless the tracked one differs from it by more than
  /// max(disagree_samples sample intervals, disagree_fraction x tracked altitude).
  double disagree_samples = 4.0;
  double disagree_fraction = 0.05;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Index of the first-return sample of one side (samples NEAR -> FAR; any linear amplitude):
/// after skipping the samples above the threshold at the start (transmit pulse), the first
/// sample whose smoothed value reaches the threshold and whose following hold_samples have a
/// smoothed median above it too, moved back to the first raw sample at or above the threshold
/// within the smoothing window; with leading_edge, then moved back to the leading edge.
/// -1 if none (too short, no contrast, nothing above).
std::ptrdiff_t first_return_sample(std::span<const float> near_to_far,
                                   const BottomTrackOptions& options = {});

/// Tracks the bottom of a line: per ping and side first returns, median-filtered along track,
/// combined into one altitude per ping. Keeps two doubles per ping.
class BottomTracker {
 public:
  explicit BottomTracker(BottomTrackOptions options = {});
  /// Appends one ping (sides NEAR -> FAR, either may be empty); slant_range_m is the far edge of
  /// the last sample (sample i covers [i, i + 1) x slant_range / n).
  void add_ping(std::span<const float> port, std::span<const float> starboard,
                double slant_range_m);
  /// The tracked altitude of every ping added (metres, the centre of the first-return sample),
  /// NaN where neither side nor the along-track neighbours give one. Port and starboard picks
  /// that are along-track outliers are replaced by their along-track median; the altitude is the
  /// mean of the sides (one side if the other has none).
  std::vector<double> altitudes_m() const;
  /// One side's first-return range per ping after the along-track filter (0 port, 1 starboard).
  std::vector<double> side_ranges_m(int side) const;
  std::size_t pings() const { return port_m_.size(); }

 private:
  BottomTrackOptions options_;
  std::vector<double> port_m_, starboard_m_, sample_m_;
};

/// Where the altitude of a ping comes from.
enum class AltitudeSource : std::uint8_t {
  kHeader,  ///< the header's only (pings without a positive altitude are skipped)
  kTrack,   ///< the tracked one only (pings without a pick are skipped)
  kAuto,    ///< the header's unless missing, <= 0, or disagreeing with the tracked one
};
/// "header", "track", "auto"; throws InputError naming `what` otherwise.
AltitudeSource parse_altitude_source(const std::string& text, const std::string& what);
const char* to_string(AltitudeSource s);

/// The altitude chosen for one ping (NaN if none) and whether the tracked one was used.
struct AltitudeChoice {
  double altitude_m;
  bool tracked;
  bool header_disagreed;  ///< the header altitude was positive but disagreed (auto)
};
AltitudeChoice choose_altitude(AltitudeSource source, double header_m, double tracked_m,
                               double sample_m, const BottomTrackOptions& options = {});

/// Across-track gain normalisation (docs/conversion.md): how samples are binned.
enum class GainNormalisation : std::uint8_t { kOff, kRange, kAngle };
GainNormalisation parse_gain_normalisation(const std::string& text, const std::string& what);
const char* to_string(GainNormalisation g);

/// Empirical across-track gain: the mean level (dB, i.e. a geometric mean, so that bright
/// targets weigh little) of the seabed samples of all pings added, per side and per bin of
/// slant range (kRange: bins of range_bin_m) or of depression angle below horizontal
/// (kAngle: asin(altitude / slant range), bins of angle_bin_rad); gain(bin) brings the bin's
/// mean level to the mean level of all bins of its side. Only samples beyond the altitude and
/// > 0 are counted; bins with fewer than min_count samples take the gains of the nearest bins
/// that have enough, interpolated in log (beyond the last: the last's; 1 if none has).
class GainNormaliser {
 public:
  GainNormaliser(GainNormalisation mode, double range_bin_m = 0.25,
                 double angle_bin_rad = 0.00872664625997164788 /* 0.5 degree */,
                 std::size_t min_count = 50);
  /// Accumulates one ping (does nothing when mode is kOff or altitude_m is not > 0).
  void add_ping(std::span<const float> port, std::span<const float> starboard, double slant_range_m,
                double altitude_m);
  /// Computes the gains from what was added; add_ping must not be called afterwards.
  void finish();
  /// Multiplies the samples of one ping by their bin's gain (after finish()).
  void apply(std::vector<float>& port, std::vector<float>& starboard, double slant_range_m,
             double altitude_m) const;
  /// Gain (linear amplitude factor) of a sample at this slant range on side 0 (port) or 1.
  double gain(int side, double range_m, double altitude_m) const;
  GainNormalisation mode() const { return mode_; }
  /// The bin of each sample of a side of n samples of dr metres (sample i at slant range
  /// (i + 0.5) dr): floor(r / range_bin) or floor(asin(altitude / r) / angle_bin), -1 for
  /// r <= altitude. The angle bins by runs: the bin falls as the range grows, so each run's end
  /// is predicted from the bin's edge and checked on both sides (a few asin per bin, not one
  /// per sample); every step of the per-sample form is monotonic in r, so the bins are the same.
  void bins_of_ping(std::size_t n, double dr, double altitude_m,
                    std::vector<std::ptrdiff_t>& bins) const;

 private:
  std::ptrdiff_t bin_of(double range_m, double altitude_m) const;
  GainNormalisation mode_;
  double range_bin_m_, angle_bin_rad_;
  std::size_t min_count_;
  std::vector<double> sum_log_[2];
  std::vector<std::uint64_t> count_[2];
  std::vector<double> gain_[2];
  std::vector<std::ptrdiff_t> bins_;  ///< add_ping's scratch
};

}  // namespace sonarsynth
