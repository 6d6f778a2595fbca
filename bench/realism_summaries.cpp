// SPDX-License-Identifier: MIT
// The summaries the realism measures accumulate (level histograms, moments, Pearson sums,
// quantiles) and the options' validation; definitions in docs/realism.md.
#include <algorithm>
#include <string>

#include "realism_stats.hpp"
#include "sonarsynth/error.hpp"

namespace bench::realism {

namespace {

using sonarsynth::InputError;

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

void Options::validate() const {
  auto odd = [](std::size_t v, const char* name) {
    if (v == 0 || v % 2 == 0)
      throw InputError(std::string("realism: option ") + name + " = " + std::to_string(v) +
                       " (must be odd and >= 1)");
  };
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw InputError(std::string("realism: option ") + name + " = " + std::to_string(v) +
                       " (must be > 0)");
  };
  odd(smooth_samples, "smooth_samples");
  odd(box_pings, "box_pings");
  odd(box_samples, "box_samples");
  odd(shadow_box_pings, "shadow_box_pings");
  odd(shadow_box_samples, "shadow_box_samples");
  odd(reference_pings, "reference_pings");
  positive(detect_below_db, "detect_below_db");
  positive(hold_m, "hold_m");
  positive(rise_span_m, "rise_span_m");
  positive(rise_step_r0, "rise_step_r0");
  positive(rise_span_r0, "rise_span_r0");
  positive(shadow_below_db, "shadow_below_db");
  positive(band_m, "band_m");
  if (!(reference_begin >= 0.0 && reference_begin < reference_end && reference_end <= 1.0))
    throw InputError("realism: options reference_begin/end = " + std::to_string(reference_begin) +
                     "/" + std::to_string(reference_end) + " (need 0 <= begin < end <= 1)");
  if (!(near_begin_r0 < near_end_r0) || !(seabed_begin_r0 > 0.0) || !(water_end_r0 > 0.0) ||
      !(seabed_end_range > 0.0 && seabed_end_range <= 1.0))
    throw InputError(
        "realism: region options out of order (need near_begin_r0 < near_end_r0, "
        "seabed_begin_r0 > 0, water_end_r0 > 0, 0 < seabed_end_range <= 1)");
  if (correlation_bands == 0 || tile_pings == 0 || spacing_lag == 0)
    throw InputError("realism: options correlation_bands, tile_pings and spacing_lag must be >= 1");
  if (grazing_edges_rad.size() < 2 ||
      !std::is_sorted(grazing_edges_rad.begin(), grazing_edges_rad.end()))
    throw InputError("realism: option grazing_edges_rad needs at least two increasing edges");
  if (!(tile_min_fill > 0.0 && tile_min_fill <= 1.0))
    throw InputError("realism: option tile_min_fill = " + std::to_string(tile_min_fill) +
                     " (need 0 < fill <= 1)");
  if (across_tile_pings == 0 || across_tile_samples < 8 || across_tile_samples % 8 != 0)
    throw InputError("realism: options across_tile_pings >= 1 and across_tile_samples = " +
                     std::to_string(across_tile_samples) + " (need a multiple of 8)");
  positive(across_near_r0, "across_near_r0");
  positive(across_far_range, "across_far_range");
  positive(edge_shadow_m, "edge_shadow_m");
  positive(edge_lit_m, "edge_lit_m");
  positive(water_stats_end_r0, "water_stats_end_r0");
  positive(clip_near_m, "clip_near_m");
  positive(monotone_until_m, "monotone_until_m");
  if (!(monotone_tol_db >= 0.0)) throw InputError("realism: option monotone_tol_db < 0");
  if (water_block_pings == 0) throw InputError("realism: option water_block_pings = 0");
  if (!(edge_window_begin_m < edge_window_end_m))
    throw InputError("realism: options edge_window_begin_m/end_m out of order");
  if (!(far_begin_range < far_end_range && far_end_range <= 1.0) ||
      !(near_ref_begin_r0 < near_ref_end_r0))
    throw InputError(
        "realism: options far_begin/end_range or near_ref_begin/end_r0 out of order (need "
        "begin < end, far_end_range <= 1)");
  for (double d : profile_offsets_m)
    if (!(d >= 0.0) || !std::isfinite(d))
      throw InputError("realism: option profile_offsets_m has " + std::to_string(d) +
                       " (need offsets >= 0)");
}

void LevelHistogram::add_value(double value) {
  add_db(level_db(value));
}

void LevelHistogram::add_db(double db) {
  ++count_;
  if (!(db > -kInf)) {
    ++nonpositive_;  // -inf (value <= 0) or NaN
    return;
  }
  const double pos = (db - kMinDb) / kBinDb;
  if (pos < 0.0) {
    ++below_;
  } else if (pos >= static_cast<double>(kBins)) {
    ++above_;
  } else {
    if (bins_.empty()) bins_.assign(kBins, 0);
    ++bins_[static_cast<std::size_t>(pos)];
  }
}

void LevelHistogram::merge(const LevelHistogram& o) {
  if (!o.bins_.empty()) {
    if (bins_.empty()) bins_.assign(kBins, 0);
    for (std::size_t i = 0; i < kBins; ++i) bins_[i] += o.bins_[i];
  }
  nonpositive_ += o.nonpositive_;
  below_ += o.below_;
  above_ += o.above_;
  count_ += o.count_;
}

double LevelHistogram::quantile_db(double q) const {
  if (count_ == 0) return kNaN;
  const auto rank = static_cast<std::uint64_t>(
      std::floor(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_ - 1)));
  std::uint64_t seen = nonpositive_;
  if (rank < seen) return -kInf;
  seen += below_;
  if (rank < seen) return kMinDb;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    seen += bins_[i];
    if (rank < seen) return kMinDb + (static_cast<double>(i) + 0.5) * kBinDb;
  }
  return kMinDb + static_cast<double>(kBins) * kBinDb;
}

double Moments::stddev() const {
  if (n <= 0.0) return kNaN;
  const double m = sum / n;
  return std::sqrt(std::max(0.0, sum_sq / n - m * m));
}

double Moments3::cv() const {
  if (n <= 0.0) return kNaN;
  const double m = s1 / n;
  return std::sqrt(std::max(0.0, s2 / n - m * m)) / m;
}

double Moments3::skewness() const {
  if (n <= 0.0) return kNaN;
  const double m = s1 / n;
  const double m2 = s2 / n - m * m;
  const double m3 = s3 / n - 3.0 * m * (s2 / n) + 2.0 * m * m * m;
  return m2 > 0.0 ? m3 / std::pow(m2, 1.5) : kNaN;
}

void PearsonSums::add(double x, double y) {
  n += 1.0;
  a += x;
  b += y;
  aa += x * x;
  bb += y * y;
  ab += x * y;
}

void PearsonSums::merge(const PearsonSums& o) {
  n += o.n;
  a += o.a;
  b += o.b;
  aa += o.aa;
  bb += o.bb;
  ab += o.ab;
}

double PearsonSums::correlation() const {
  if (n < 2.0) return kNaN;
  const double ma = a / n, mb = b / n;
  const double va = aa / n - ma * ma, vb = bb / n - mb * mb;
  if (!(va > 0.0) || !(vb > 0.0)) return kNaN;
  return (ab / n - ma * mb) / std::sqrt(va * vb);
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(v.size() - 1, lo + 1);
  const double f = pos - static_cast<double>(lo);
  if (v[lo] == v[hi] || f == 0.0) return v[lo];
  if (!std::isfinite(v[lo]) || !std::isfinite(v[hi])) return f < 0.5 ? v[lo] : v[hi];
  return v[lo] + f * (v[hi] - v[lo]);
}

double rise_width_10_90(const std::vector<double>& p, double low, double high) {
  if (!(high > low) || p.size() < 2) return kNaN;
  // First upward crossing of `level` at or after position `from`, interpolated linearly.
  auto crossing = [&](double level, double from) {
    for (auto j = static_cast<std::size_t>(std::max(0.0, std::floor(from))); j + 1 < p.size();
         ++j) {
      if (p[j] >= level && static_cast<double>(j) >= from) return static_cast<double>(j);
      if (p[j] < level && p[j + 1] >= level) {
        const double x = static_cast<double>(j) + (level - p[j]) / (p[j + 1] - p[j]);
        if (x >= from) return x;
      }
    }
    return kNaN;
  };
  const double x10 = crossing(low + 0.1 * (high - low), 0.0);
  if (std::isnan(x10)) return kNaN;
  const double x90 = crossing(low + 0.9 * (high - low), x10);
  return x90 - x10;
}

}  // namespace bench::realism
