// SPDX-License-Identifier: MIT
// Statistics that say whether a side-scan record behaves like a real one (docs/realism.md): seabed
// contrast, water column, shadows, first bottom return, full scale and clipping, along-track
// correlation (measures 1-6); across-track correlation and spectrum, shadow fill and edges, water
// column statistics, first-return profile, far vs near range, near-range clipping, level
// percentiles and altitude (measures 7-16). Each figure is defined in docs/realism.md; the
// constants below are the choices documented there. Bench support only: not part of the installed
// API.
//
// Levels are 20 log10 of stored sample values (dB re one count); "x dB below" compares levels.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

namespace bench::realism {

enum class Side : std::uint8_t { kPort, kStarboard };

/// One ping as the measures see it. Every ping of a record has the same number of samples per
/// side and the same slant range (the driver keeps the most common layout).
struct Ping {
  std::vector<float> port;       ///< stored values, NEAR -> FAR
  std::vector<float> starboard;  ///< stored values, NEAR -> FAR
  double altitude_m = 0.0;       ///< header altitude; <= 0 = none
  double slant_range_m = 0.0;    ///< far edge of the last sample; sample i covers [i, i+1) x dr
  double x_m = 0.0;              ///< position in a local metric frame (east)
  double y_m = 0.0;              ///< (north)
  bool position_valid = false;
  const std::vector<float>& samples(Side side) const {
    return side == Side::kPort ? port : starboard;
  }
};

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kDeg = std::numbers::pi / 180.0;  ///< one degree in radians (for I/O)

/// The definitions' parameters (docs/realism.md gives the reasons for each default).
struct Options {
  // First return (measure 4).
  double detect_below_db = 20.0;   ///< first return: within this of the seabed level
  std::size_t smooth_samples = 5;  ///< centred running median of levels (odd)
  double hold_m = 0.3;             ///< ... and the median of the next hold_m stays above
  double reference_begin = 0.5;    ///< detector's first seabed reference: median over
  double reference_end = 0.9;      ///<   [begin, end) x slant range
  double rise_span_m = 4.0;        ///< aligned first-return profile length
  double rise_step_r0 = 0.005;     ///< ... and in units of r0: step and length
  double rise_span_r0 = 0.3;
  // Regions (multiples of the first-return range r0, or fractions of the slant range R).
  double seabed_begin_r0 = 1.2;  ///< seabed: [1.2 r0, 0.9 R)
  double seabed_end_range = 0.9;
  double near_begin_r0 = 1.2;  ///< near seabed: [1.2 r0, 1.5 r0)
  double near_end_r0 = 1.5;
  double water_end_r0 = 0.9;     ///< water column: [end of transmit, 0.9 r0)
  std::size_t lead_samples = 4;  ///< "leading samples"
  double dark_value = 16.0;      ///< seabed samples below this count as dark
  // Local mean (measures 1 and 6): a centred box of pings x samples over seabed samples.
  std::size_t box_pings = 5;
  std::size_t box_samples = 31;
  // Shadows (measure 3).
  std::size_t shadow_box_pings = 3;  ///< smoothing box of the detection level
  std::size_t shadow_box_samples = 9;
  double shadow_below_db = 10.0;      ///< shadow: smoothed level this far below reference
  double band_m = 1.0;                ///< reference: range band width
  std::size_t reference_pings = 201;  ///< ... running median over this many pings
  // Tiles (measures 1 and 6): ping blocks x range bands, each summarised on its own.
  std::size_t correlation_bands = 10;  ///< equal slant-range bands over [0, R)
  std::size_t tile_pings = 32;         ///< pings per tile
  double tile_min_fill = 0.5;          ///< a tile counts if this share of it is seabed
  std::size_t spacing_lag = 10;        ///< ping spacing: median |p(k + lag) - p(k)| / lag
  /// Grazing-angle classes of measure 1 (flat seabed: asin(r0 / r)), edges in radians.
  std::vector<double> grazing_edges_rad = {0.0,       5 * kDeg,  10 * kDeg, 15 * kDeg,
                                           20 * kDeg, 30 * kDeg, 45 * kDeg, 90 * kDeg};
  // Across-track texture (measure 7): tiles of pings x samples at three places per ping side.
  std::size_t across_tile_pings = 64;
  std::size_t across_tile_samples = 128;  ///< also the periodogram length (even)
  double across_near_r0 = 1.5;            ///< "near" tile starts at 1.5 r0
  double across_far_range = 0.8;          ///< "far" tile ends at 0.8 R; "mid" centred between
  // Shadow fill and edges (measures 9 and 10).
  std::size_t shadow_region_min_samples = 50;  ///< regions counted for the median region CV
  double edge_shadow_m = 0.5;                  ///< shadow run at least this long ...
  double edge_lit_m = 1.0;                     ///< ... followed by this much lit seabed
  double edge_window_begin_m = 15.0;           ///< preferred transitions: slant range in
  double edge_window_end_m = 25.0;             ///<   [begin, end) ...
  std::size_t edge_window_min = 20;            ///< ... if there are at least this many
  // Water column statistics (measure 11): samples [water_stats_begin, 0.85 r0).
  std::size_t water_stats_begin = 20;
  double water_stats_end_r0 = 0.85;
  std::size_t water_block_pings = 64;
  std::size_t water_ping_min_samples = 10;  ///< ping sides with fewer are not summarised
  std::size_t water_block_min_samples = 100;
  // First return profile (measure 12): offsets from r0 (and from the header altitude).
  std::vector<double> profile_offsets_m = {0.0, 0.03, 0.06, 0.09, 0.2, 0.5, 0.9};
  double monotone_until_m = 0.5;  ///< monotone check of the median profile over [0, this]
  double monotone_tol_db = 1.0;   ///< ... allowing drops below an earlier maximum up to this
  // Far range vs near range (measure 13) and near-range clipping (measure 14).
  double far_begin_range = 0.9;  ///< far: [0.9 R, 0.97 R)
  double far_end_range = 0.97;
  double near_ref_begin_r0 = 1.4;  ///< near: [1.4 r0, 1.6 r0)
  double near_ref_end_r0 = 1.6;
  double clip_near_m = 2.0;  ///< near-range clipping: samples [r0, r0 + 2 m)
  void validate() const;
};

/// Levels (dB) in 0.01 dB bins over [-100, 200) dB; values <= 0 are counted apart (level -inf).
class LevelHistogram {
 public:
  void add_value(double value);
  void add_db(double db);
  void merge(const LevelHistogram& other);
  std::uint64_t count() const { return count_; }
  /// The q-quantile (0..1) of the levels: -inf when it falls among values <= 0, NaN if empty.
  double quantile_db(double q) const;
  double median_db() const { return quantile_db(0.5); }

 private:
  static constexpr double kMinDb = -100.0;
  static constexpr double kBinDb = 0.01;
  static constexpr std::size_t kBins = 30000;
  std::vector<std::uint64_t> bins_;
  std::uint64_t nonpositive_ = 0;
  std::uint64_t below_ = 0;
  std::uint64_t above_ = 0;
  std::uint64_t count_ = 0;
};

/// Count, mean and population standard deviation.
struct Moments {
  double n = 0.0, sum = 0.0, sum_sq = 0.0;
  void add(double x) {
    n += 1.0;
    sum += x;
    sum_sq += x * x;
  }
  void merge(const Moments& o) {
    n += o.n;
    sum += o.sum;
    sum_sq += o.sum_sq;
  }
  double mean() const { return n > 0.0 ? sum / n : kNaN; }
  double stddev() const;
};

/// Count and the first three power sums: mean, population CV and skewness.
struct Moments3 {
  double n = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  void add(double x) {
    n += 1.0;
    s1 += x;
    s2 += x * x;
    s3 += x * x * x;
  }
  void merge(const Moments3& o) {
    n += o.n;
    s1 += o.s1;
    s2 += o.s2;
    s3 += o.s3;
  }
  double mean() const { return n > 0.0 ? s1 / n : kNaN; }
  /// Population standard deviation / mean.
  double cv() const;
  /// Population skewness m3 / m2^1.5.
  double skewness() const;
};

/// Pearson correlation of pairs (a, b).
struct PearsonSums {
  double n = 0.0, a = 0.0, b = 0.0, aa = 0.0, bb = 0.0, ab = 0.0;
  void add(double x, double y);
  void merge(const PearsonSums& o);
  double correlation() const;
};

/// Quantile (0..1, linear interpolation) of a list; NaN if empty.
double quantile(std::vector<double> values, double q);

/// 20 log10(value), -inf for value <= 0.
inline double level_db(double value) {
  return value > 0.0 ? 20.0 * std::log10(value) : -std::numeric_limits<double>::infinity();
}

// ---- Measure 4: first bottom return ------------------------------------------------------------

struct FirstReturn {
  bool found = false;
  std::size_t water_begin = 0;  ///< end of the transmit pulse: first sample of the water column
  std::size_t index = 0;        ///< first seabed sample
  double range_m = kNaN;        ///< (index + 0.5) x sample spacing
  double seabed_db = kNaN;      ///< median level over the near seabed [1.2, 1.5) x range_m
};

/// The first return of one side of every ping (docs/realism.md, measure 4).
std::vector<FirstReturn> first_returns(std::span<const Ping> pings, Side side,
                                       const Options& options);

struct FirstReturnStats {
  std::size_t pings = 0;
  std::size_t found = 0;
  double sample_m = kNaN;
  double step_r0 = kNaN;
  std::vector<double> range_m;                 ///< per ping with a return
  std::vector<double> range_minus_altitude_m;  ///< per ping with a return and an altitude
  std::vector<double> range_over_altitude;
  /// aligned[j][p]: level of sample index + j of ping p minus that ping's seabed_db.
  std::vector<std::vector<float>> aligned;
  /// aligned_r0[j][p]: the same at range r0 (1 + j step_r0).
  std::vector<std::vector<float>> aligned_r0;
  /// Measure 12: profile_offsets_m (Options) and, per offset, the level of the sample nearest
  /// r0 + d (profile_r0) and H + d (profile_altitude, pings with H > 0) minus seabed_db.
  std::vector<double> profile_offsets_m;
  std::vector<std::vector<float>> profile_r0, profile_altitude;
  double monotone_until_m = kNaN;
  double monotone_tol_db = kNaN;
  void merge(const FirstReturnStats& o);
  /// Median over pings of profile_r0[j] (profile_altitude[j] if `altitude`).
  double profile_db(std::size_t j, bool altitude = false) const;
  /// Largest drop of the per-sample median of `aligned` below its running maximum over offsets
  /// [0, monotone_until_m]; the profile counts as monotone if this is <= monotone_tol_db.
  double profile_max_drop_db() const;
  /// Distance from the first return to where the per-offset median of `aligned` first reaches
  /// -below_db; NaN if it never does within the profile.
  double rise_m(double below_db) const;
  /// The same distance from `aligned_r0`, as a fraction of r0.
  double rise_r0(double below_db) const;
};

FirstReturnStats first_return_stats(std::span<const Ping> pings, Side side,
                                    std::span<const FirstReturn> returns, const Options& options);

// ---- Measures 1 and 6: seabed texture ----------------------------------------------------------

struct Texture {
  Moments ratio;  ///< sample / local mean, every seabed sample
  Moments db;     ///< 10 log10(sample) - local mean of 10 log10(sample)
  double band_m = kNaN;
  std::vector<PearsonSums> bands;  ///< lag-1 along-track pairs of ratios, per range band
  /// Per tile (tile_pings pings x one range band) that is seabed enough: std/mean of the ratio,
  /// std of the dB difference; per band, the tiles' lag-1 correlations.
  std::vector<double> tile_contrast, tile_db_std;
  std::vector<std::vector<double>> tile_lag1;
  /// Per grazing-angle class (Options::grazing_edges_rad): ratio and dB differences.
  std::vector<double> grazing_edges_rad;
  std::vector<Moments> grazing_ratio, grazing_db;
  /// Measure 7, one tile: lag-1 pairs of ratios (i, i + 1) of the same ping; the summed
  /// periodogram (bins 0 .. samples / 2) of the mean-removed ratios of its complete rows, and
  /// their count; how many sides it pools.
  struct AcrossTile {
    PearsonSums lag1;
    std::vector<double> spectrum;
    double rows = 0.0;
    double sides = 0.0;
    void merge(const AcrossTile& o);
  };
  /// Per place (near, mid, far): all pairs, and the tiles by block of pings (pooled: the block's
  /// tiles of both sides merged). A tile counts if it has tile_min_fill x its pairs per side.
  std::array<PearsonSums, 3> across;
  std::array<std::vector<AcrossTile>, 3> across_tiles;
  double across_min_pairs = kNaN;  ///< per side and tile
  void merge(const Texture& o);
  double contrast() const { return ratio.stddev() / ratio.mean(); }
  double median_tile_contrast() const { return quantile(tile_contrast, 0.5); }
  double median_tile_db_std() const { return quantile(tile_db_std, 0.5); }
  double median_tile_lag1(std::size_t band) const { return quantile(tile_lag1[band], 0.5); }
  /// The lag-1 correlations of the tiles of a place that count.
  std::vector<double> tile_across_lag1(std::size_t place) const;
  double median_tile_across_lag1(std::size_t place) const {
    return quantile(tile_across_lag1(place), 0.5);
  }
  /// Mean periodogram over quarter q (0..3) of the bins 1 .. N/2 (DC excluded: it is zero after
  /// the mean is removed), divided by the mean over all of them: 1 1 1 1 for white noise. Over
  /// every row of every tile of the three places.
  double spectrum_quarter(std::size_t q) const;
  /// The same per tile (every place, tiles that count), then the median over tiles.
  double median_tile_spectrum_quarter(std::size_t q) const;
  std::size_t spectrum_rows() const;
};

Texture seabed_texture(std::span<const Ping> pings, Side side, std::span<const FirstReturn> returns,
                       const Options& options);

// ---- Measures 2 and 5: levels, zeros, full scale, clipping -------------------------------------

struct Levels {
  LevelHistogram water, near, seabed, lead;
  std::uint64_t samples = 0, zeros = 0;
  std::uint64_t water_zeros = 0, seabed_zeros = 0, seabed_dark = 0;
  std::uint64_t seabed_clipped = 0, near_clipped = 0, lead_clipped = 0;
  std::vector<double> ping_water_minus_near_db;  ///< per ping with a first return
  // Measure 11: water column samples [water_stats_begin, water_stats_end_r0 x r0).
  Moments3 water_stats;                ///< every such sample
  std::vector<double> water_block_cv;  ///< per block of water_block_pings pings
  std::vector<double> water_block_skewness;
  std::vector<double> water_ping_cv;  ///< per ping side
  double water_min = kNaN;            ///< lowest value
  LevelHistogram water_first_third, water_last_third;
  // Measure 13: per ping side, median level over [0.9 R, 0.97 R) minus over [1.4 r0, 1.6 r0);
  // and altitude / R over the same ping sides (those with H > 0).
  std::vector<double> far_minus_near_db, altitude_over_range;
  // Measure 14: samples [r0, r0 + clip_near_m) and those of them at full scale.
  std::uint64_t first_metres = 0, first_metres_clipped = 0;
  // Measure 15: every sample.
  LevelHistogram all;
  void merge(const Levels& o);
  double water_trend_db() const {
    return water_last_third.median_db() - water_first_third.median_db();
  }
};

/// `clip_value`: a sample >= this counts as clipped (the largest value of the file).
Levels levels(std::span<const Ping> pings, Side side, std::span<const FirstReturn> returns,
              double clip_value, const Options& options);

// ---- Measure 3: shadows ------------------------------------------------------------------------

struct Shadows {
  std::uint64_t seabed = 0;  ///< seabed samples examined
  std::uint64_t shadow = 0;
  LevelHistogram level;      ///< levels of the shadow samples
  LevelHistogram below_lit;  ///< level minus the lit reference at the same range, per sample
  // Measure 9: values of shadow and lit (examined, not shadow) seabed samples; per contiguous
  // shadow region (4-connected over pings x samples) of at least shadow_region_min_samples, CV.
  Moments shadow_values, lit_values;
  std::vector<double> region_cv;
  // Measure 10: far edges of shadow runs (shadow -> lit going out in range). Profile offsets
  // -(a - 1) .. b samples from the last shadow sample (a, b: edge_shadow_m, edge_lit_m in
  // samples); summed values per offset, for the transitions in the range window and for all.
  double sample_m = kNaN;
  std::size_t edge_before = 0;  ///< a - 1: profile index of offset 0
  std::vector<double> edge_window_sum, edge_all_sum;
  std::size_t edge_window_count = 0, edge_all_count = 0;
  std::size_t edge_window_min = 0;
  void merge(const Shadows& o);
  double cv_shadow() const { return shadow_values.stddev() / shadow_values.mean(); }
  double cv_lit() const { return lit_values.stddev() / lit_values.mean(); }
  /// True if the range window has edge_window_min transitions (the edge figures use it).
  bool edge_in_window() const { return edge_window_count >= edge_window_min; }
  std::size_t edge_count() const { return edge_in_window() ? edge_window_count : edge_all_count; }
  /// 10-90 % width (m) of the mean edge profile, from the shadow level (mean over the first
  /// half of the shadow offsets) to the lit level (mean over the last quarter of the lit ones).
  double edge_width_m() const;
  /// The mean edge profile (values per offset, offset 0 at edge_before); empty if no edge.
  std::vector<double> edge_profile() const;
};

/// 10-90 % rise width, in samples, of a profile going from a low to a high level: `low` and
/// `high` are the levels, and the positions (linear interpolation between samples) are the
/// first upward crossing of low + 0.1 (high - low) and the first crossing of low + 0.9 (high -
/// low) after it. NaN if either is missing or high <= low.
double rise_width_10_90(const std::vector<double>& profile, double low, double high);

Shadows shadows(std::span<const Ping> pings, Side side, std::span<const FirstReturn> returns,
                const Options& options);

// ---- Everything --------------------------------------------------------------------------------

struct SideReport {
  FirstReturnStats first;
  Texture texture;
  Levels levels;
  Shadows shadows;
  void merge(const SideReport& o);
};

struct Report {
  std::size_t pings = 0;
  std::size_t samples = 0;  ///< per side
  double slant_range_m = kNaN;
  double max_value = kNaN;       ///< the largest sample of the record (clip level, full scale)
  double ping_spacing_m = kNaN;  ///< median distance between consecutive valid positions
  /// Measure 16: header altitude over the pings with H > 0 (NaN if none).
  double altitude_min_m = kNaN, altitude_median_m = kNaN, altitude_max_m = kNaN;
  SideReport port, starboard, pooled;
};

/// Largest sample value over both sides of every ping.
double max_sample(std::span<const Ping> pings);
/// Ping spacing: the median over k of |p(k + lag) - p(k)| / lag over pings whose positions are
/// both valid (robust to navigation held or quantised between pings); NaN if none.
double median_ping_spacing_m(std::span<const Ping> pings, std::size_t lag);

/// All measures, per side and pooled. Throws sonarsynth::InputError if the pings do not share
/// one layout (samples per side, slant range) or are empty.
Report measure(std::span<const Ping> pings, const Options& options = {});

}  // namespace bench::realism
