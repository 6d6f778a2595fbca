// SPDX-License-Identifier: MIT
// Definitions and defaults: docs/conversion.md.
#include "sonarsynth/bottom_track.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "sonarsynth/enum_names.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

constexpr EnumName<AltitudeSource> kAltitudeSourceNames[] = {{AltitudeSource::kHeader, "header"},
                                                             {AltitudeSource::kTrack, "track"},
                                                             {AltitudeSource::kAuto, "auto"}};

constexpr EnumName<GainNormalisation> kGainNormalisationNames[] = {
    {GainNormalisation::kOff, "off"},
    {GainNormalisation::kRange, "range"},
    {GainNormalisation::kAngle, "angle"}};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The water level and the seabed level of a side: percentiles of its smoothed samples (the
// seabed one high enough for a water column of up to about half the range).
constexpr double kWaterPercentile = 0.05;
constexpr double kSeabedPercentile = 0.75;

double median_of(std::vector<double>& v) {
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  const double hi = *mid;
  const double lo = *std::max_element(v.begin(), mid);
  return 0.5 * (lo + hi);
}

/// Along-track: each pick replaced by the median of its window when it is missing or an
/// outlier (farther than `tolerance_m` from that median).
std::vector<double> despike(const std::vector<double>& picks, std::size_t window,
                            double tolerance_m) {
  const std::size_t n = picks.size();
  const std::size_t half = window / 2;
  std::vector<double> out(n, kNaN);
  std::vector<double> w;
  for (std::size_t k = 0; k < n; ++k) {
    w.clear();
    const std::size_t a = k >= half ? k - half : 0;
    const std::size_t b = std::min(n, k + half + 1);
    for (std::size_t j = a; j < b; ++j) {
      if (std::isfinite(picks[j])) w.push_back(picks[j]);
    }
    const double med = median_of(w);
    const double p = picks[k];
    out[k] = std::isfinite(p) && std::isfinite(med) && std::abs(p - med) <= tolerance_m
                 ? p
                 : med;  // NaN when the window has no pick
  }
  return out;
}

/// The leading edge below a coarse pick (docs/conversion.md): the water level is the median of
/// the dB levels from the end of the transmit pulse to the coarse pick's smoothing window, the
/// seabed level the median over the hold samples from the coarse pick; the edge is the first
/// sample after the pulse (up to hold samples past the coarse pick) whose 3-sample running
/// median reaches the middle of the two levels in dB and whose following hold samples have a
/// median there too, moved back to the first raw sample of that 3-sample window at the middle.
std::size_t leading_edge(std::span<const float> s, std::size_t start, std::size_t coarse,
                         double floor_amplitude, const BottomTrackOptions& o) {
  const std::size_t n = s.size();
  const std::size_t hold = o.hold_samples;
  const std::size_t guard = o.smooth_samples / 2 + 1;
  if (coarse < start + guard + hold / 2 || coarse + hold > n) return coarse;
  const auto db = [&](std::size_t i) {
    const double v = std::isfinite(s[i]) ? std::abs(static_cast<double>(s[i])) : 0.0;
    return 20.0 * std::log10(std::max(v, floor_amplitude));
  };
  std::vector<double> win;
  for (std::size_t i = start; i < coarse - guard; ++i) win.push_back(db(i));
  const double water_db = median_of(win);
  win.clear();
  for (std::size_t i = coarse; i < coarse + hold; ++i) win.push_back(db(i));
  const double seabed_db = median_of(win);
  if (!(seabed_db > water_db)) return coarse;
  const double mid_db = 0.5 * (water_db + seabed_db);
  for (std::size_t j = start + 1; j + hold <= n && j <= coarse + hold; ++j) {
    win = {db(j - 1), db(j), db(std::min(n - 1, j + 1))};
    if (median_of(win) < mid_db) continue;
    win.clear();
    for (std::size_t k = j; k < j + hold; ++k) win.push_back(db(k));
    if (median_of(win) < mid_db) continue;
    // As for the coarse pick: the first raw sample of the running median's window that reaches
    // the level is the edge.
    for (std::size_t k = j - 1; k <= j + 1; ++k) {
      if (k >= start && db(k) >= mid_db) return k;
    }
    return j;
  }
  return coarse;
}

void require(bool ok, const std::string& field, double value, const std::string& constraint) {
  if (ok) return;
  std::ostringstream os;
  os << "bottom tracking: " << field << " = " << value << ". Violated constraint: " << constraint;
  throw InputError(os.str());
}

}  // namespace

void BottomTrackOptions::validate() const {
  require(smooth_samples >= 1 && smooth_samples % 2 == 1, "smooth_samples",
          static_cast<double>(smooth_samples), "odd and >= 1");
  require(threshold_fraction > 0.0 && threshold_fraction < 1.0, "threshold_fraction",
          threshold_fraction, "0 < threshold_fraction < 1");
  require(min_contrast >= 1.0, "min_contrast", min_contrast, ">= 1");
  require(hold_samples >= 1, "hold_samples", static_cast<double>(hold_samples), ">= 1");
  require(median_pings >= 1 && median_pings % 2 == 1, "median_pings",
          static_cast<double>(median_pings), "odd and >= 1");
  require(outlier_samples > 0.0, "outlier_samples", outlier_samples, "> 0");
  require(disagree_samples > 0.0, "disagree_samples", disagree_samples, "> 0");
  require(disagree_fraction >= 0.0, "disagree_fraction", disagree_fraction, ">= 0");
}

std::ptrdiff_t first_return_sample(std::span<const float> s, const BottomTrackOptions& o) {
  const std::size_t n = s.size();
  if (n < o.hold_samples + o.smooth_samples) return -1;
  // Centred running mean (truncated at the ends), of |sample| (signed formats are amplitudes).
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = std::isfinite(s[i]) ? std::abs(static_cast<double>(s[i])) : 0.0;
    prefix[i + 1] = prefix[i] + v;
  }
  const std::size_t half = o.smooth_samples / 2;
  std::vector<double> smooth(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i >= half ? i - half : 0;
    const std::size_t b = std::min(n, i + half + 1);
    smooth[i] = (prefix[b] - prefix[a]) / static_cast<double>(b - a);
  }
  std::vector<double> sorted = smooth;
  const auto pct = [&](double q) {
    const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(n - 1));
    std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
    return sorted[static_cast<std::size_t>(k)];
  };
  const double water = pct(kWaterPercentile);
  const double seabed = pct(kSeabedPercentile);
  if (!(seabed > 0.0) || !(seabed >= o.min_contrast * water)) return -1;
  // Between the levels in dB (a geometric interpolation; a zero water level counts as the
  // seabed level / 1000, i.e. 60 dB of contrast).
  const double w = std::max(water, seabed * 1e-3);
  const double t = w * std::pow(seabed / w, o.threshold_fraction);
  std::size_t start = 0;
  while (start < n && smooth[start] >= t) ++start;  // transmit pulse / ring-down
  std::vector<double> hold;
  for (std::size_t i = start; i + o.hold_samples <= n; ++i) {
    if (smooth[i] < t) continue;
    hold.assign(smooth.begin() + static_cast<std::ptrdiff_t>(i),
                smooth.begin() + static_cast<std::ptrdiff_t>(i + o.hold_samples));
    if (median_of(hold) < t) continue;
    // The running mean rises up to `half` samples before the onset: the first raw sample at or
    // above the threshold within the window is the onset.
    const std::size_t a = std::max(start, i >= half ? i - half : 0);
    std::size_t coarse = i;
    for (std::size_t j = a; j <= std::min(n - 1, i + half); ++j) {
      if (std::abs(static_cast<double>(s[j])) >= t) {
        coarse = j;
        break;
      }
    }
    if (!o.leading_edge) return static_cast<std::ptrdiff_t>(coarse);
    // Again from the edge while it moves earlier: a crossing far up a slow rise has seabed in
    // its water window.
    for (int again = 0; again < 20; ++again) {
      const std::size_t edge = leading_edge(s, start, coarse, seabed * 1e-3, o);
      if (edge >= coarse) break;
      coarse = edge;
    }
    return static_cast<std::ptrdiff_t>(coarse);
  }
  return -1;
}

BottomTracker::BottomTracker(BottomTrackOptions options) : options_(options) {
  options_.validate();
}

void BottomTracker::add_ping(std::span<const float> port, std::span<const float> starboard,
                             double slant_range_m) {
  const auto pick = [&](std::span<const float> side) {
    if (side.empty() || !(slant_range_m > 0.0) || !std::isfinite(slant_range_m)) return kNaN;
    const std::ptrdiff_t i = first_return_sample(side, options_);
    if (i < 0) return kNaN;
    return (static_cast<double>(i) + 0.5) * slant_range_m / static_cast<double>(side.size());
  };
  port_m_.push_back(pick(port));
  starboard_m_.push_back(pick(starboard));
  const std::size_t n = std::max(port.size(), starboard.size());
  sample_m_.push_back(n > 0 ? slant_range_m / static_cast<double>(n) : kNaN);
}

std::vector<double> BottomTracker::side_ranges_m(int side) const {
  std::vector<double> dr = sample_m_;
  const double sample = median_of(dr);
  const double tol = options_.outlier_samples * (std::isfinite(sample) ? sample : 0.0);
  return despike(side == 0 ? port_m_ : starboard_m_, options_.median_pings, tol);
}

std::vector<double> BottomTracker::altitudes_m() const {
  const std::vector<double> p = side_ranges_m(0);
  const std::vector<double> s = side_ranges_m(1);
  std::vector<double> out(p.size(), kNaN);
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (std::isfinite(p[k]) && std::isfinite(s[k])) {
      out[k] = 0.5 * (p[k] + s[k]);
    } else {
      out[k] = std::isfinite(p[k]) ? p[k] : s[k];
    }
  }
  return out;
}

AltitudeSource parse_altitude_source(const std::string& text, const std::string& what) {
  return parse_enum(kAltitudeSourceNames, text, what);
}

const char* to_string(AltitudeSource s) {
  return enum_name(kAltitudeSourceNames, s);
}

AltitudeChoice choose_altitude(AltitudeSource source, double header_m, double tracked_m,
                               double sample_m, const BottomTrackOptions& o) {
  const bool header_ok = std::isfinite(header_m) && header_m > 0.0;
  const bool track_ok = std::isfinite(tracked_m) && tracked_m > 0.0;
  switch (source) {
    case AltitudeSource::kHeader:
      return {header_ok ? header_m : kNaN, false, false};
    case AltitudeSource::kTrack:
      return {track_ok ? tracked_m : kNaN, track_ok, false};
    case AltitudeSource::kAuto:
      break;
  }
  if (!track_ok) return {header_ok ? header_m : kNaN, false, false};
  if (!header_ok) return {tracked_m, true, false};
  const double tol = std::max(o.disagree_samples * (std::isfinite(sample_m) ? sample_m : 0.0),
                              o.disagree_fraction * tracked_m);
  if (std::abs(header_m - tracked_m) > tol) return {tracked_m, true, true};
  return {header_m, false, false};
}

GainNormalisation parse_gain_normalisation(const std::string& text, const std::string& what) {
  return parse_enum(kGainNormalisationNames, text, what);
}

const char* to_string(GainNormalisation g) {
  return enum_name(kGainNormalisationNames, g);
}

GainNormaliser::GainNormaliser(GainNormalisation mode, double range_bin_m, double angle_bin_rad,
                               std::size_t min_count)
    : mode_(mode), range_bin_m_(range_bin_m), angle_bin_rad_(angle_bin_rad), min_count_(min_count) {
  require(range_bin_m > 0.0 && std::isfinite(range_bin_m), "gain range_bin_m", range_bin_m, "> 0");
  require(angle_bin_rad > 0.0 && angle_bin_rad < 0.5 * std::numbers::pi, "gain angle_bin_rad",
          angle_bin_rad, "0 < angle_bin_rad < pi / 2");
  require(min_count >= 1, "gain min_count", static_cast<double>(min_count), ">= 1");
}

std::ptrdiff_t GainNormaliser::bin_of(double r, double altitude_m) const {
  if (!(r > altitude_m) || !std::isfinite(r)) return -1;
  if (mode_ == GainNormalisation::kRange) return static_cast<std::ptrdiff_t>(r / range_bin_m_);
  const double depression = std::asin(std::clamp(altitude_m / r, 0.0, 1.0));
  return static_cast<std::ptrdiff_t>(depression / angle_bin_rad_);
}

void GainNormaliser::bins_of_ping(std::size_t n, double dr, double altitude_m,
                                  std::vector<std::ptrdiff_t>& bins) const {
  bins.resize(n);
  const auto bin_at = [&](std::size_t i) {
    return bin_of((static_cast<double>(i) + 0.5) * dr, altitude_m);
  };
  std::size_t i = 0;
  // The water column (r <= altitude), then bins that never grow with the range: every operation
  // of bin_of is monotonic in r (asin included), so a run that starts and ends with one bin
  // holds it throughout.
  while (i < n && !((static_cast<double>(i) + 0.5) * dr > altitude_m)) bins[i++] = -1;
  if (mode_ != GainNormalisation::kAngle || !std::isfinite(dr) || !(dr > 0.0)) {
    for (; i < n; ++i) bins[i] = bin_at(i);
    return;
  }
  while (i < n) {
    const std::ptrdiff_t b = bin_at(i);
    // Bin b ends where the depression falls below b * angle_bin: r > altitude / sin(b bin).
    const double edge_r = altitude_m / std::sin(static_cast<double>(b) * angle_bin_rad_);
    const double guess = std::ceil(edge_r / dr - 0.5);
    std::size_t j = n;
    if (guess < static_cast<double>(n)) {
      j = guess > static_cast<double>(i + 1) ? static_cast<std::size_t>(guess) : i + 1;
    }
    while (j < n && bin_at(j) == b) ++j;
    while (j > i + 1 && bin_at(j - 1) != b) --j;
    std::fill(bins.begin() + static_cast<std::ptrdiff_t>(i),
              bins.begin() + static_cast<std::ptrdiff_t>(j), b);
    i = j;
  }
}

void GainNormaliser::add_ping(std::span<const float> port, std::span<const float> starboard,
                              double slant_range_m, double altitude_m) {
  if (mode_ == GainNormalisation::kOff || !(altitude_m > 0.0) || !std::isfinite(altitude_m)) {
    return;
  }
  int side = 0;
  for (std::span<const float> s : {port, starboard}) {
    const double dr = slant_range_m / static_cast<double>(s.size());
    bins_of_ping(s.size(), dr, altitude_m, bins_);
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double v = s[i];
      if (!(v > 0.0) || !std::isfinite(v)) continue;
      const std::ptrdiff_t b = bins_[i];
      if (b < 0) continue;
      const auto ub = static_cast<std::size_t>(b);
      if (ub >= sum_log_[side].size()) {
        sum_log_[side].resize(ub + 1, 0.0);
        count_[side].resize(ub + 1, 0);
      }
      sum_log_[side][ub] += std::log(v);
      ++count_[side][ub];
    }
    ++side;
  }
}

void GainNormaliser::finish() {
  double total = 0.0;
  double n = 0.0;
  for (int side = 0; side < 2; ++side) {
    for (std::size_t b = 0; b < sum_log_[side].size(); ++b) {
      if (count_[side][b] < min_count_) continue;
      total += sum_log_[side][b];
      n += static_cast<double>(count_[side][b]);
    }
  }
  const double ref = n > 0.0 ? total / n : 0.0;  // mean log over both sides
  for (int side = 0; side < 2; ++side) {
    const std::size_t nb = sum_log_[side].size();
    gain_[side].assign(nb, kNaN);
    for (std::size_t b = 0; b < nb; ++b) {
      if (count_[side][b] < min_count_) continue;
      gain_[side][b] = std::exp(ref - sum_log_[side][b] / static_cast<double>(count_[side][b]));
    }
    // Sparse bins: interpolated in log between the nearest bins on each side that have a gain
    // (the nearest one's beyond the last, 1 if none has).
    std::vector<std::size_t> valid;
    for (std::size_t b = 0; b < nb; ++b) {
      if (std::isfinite(gain_[side][b])) valid.push_back(b);
    }
    for (std::size_t b = 0; b < nb; ++b) {
      if (std::isfinite(gain_[side][b])) continue;
      if (valid.empty()) {
        gain_[side][b] = 1.0;
        continue;
      }
      const auto up = std::lower_bound(valid.begin(), valid.end(), b);
      if (up == valid.begin()) {
        gain_[side][b] = gain_[side][*up];
      } else if (up == valid.end()) {
        gain_[side][b] = gain_[side][valid.back()];
      } else {
        const std::size_t lo = *(up - 1), hi = *up;
        const double f = static_cast<double>(b - lo) / static_cast<double>(hi - lo);
        gain_[side][b] =
            std::exp((1.0 - f) * std::log(gain_[side][lo]) + f * std::log(gain_[side][hi]));
      }
    }
  }
}

double GainNormaliser::gain(int side, double range_m, double altitude_m) const {
  if (mode_ == GainNormalisation::kOff) return 1.0;
  const std::vector<double>& g = gain_[side == 0 ? 0 : 1];
  if (g.empty() || !(altitude_m > 0.0)) return 1.0;
  const std::ptrdiff_t b = bin_of(range_m, altitude_m);
  if (b < 0) return 1.0;
  return g[std::min(static_cast<std::size_t>(b), g.size() - 1)];
}

void GainNormaliser::apply(std::vector<float>& port, std::vector<float>& starboard,
                           double slant_range_m, double altitude_m) const {
  if (mode_ == GainNormalisation::kOff) return;
  std::vector<std::ptrdiff_t> bins;
  int side = 0;
  for (std::vector<float>* s : {&port, &starboard}) {
    const std::vector<double>& gains = gain_[side];
    ++side;
    // gain() sample by sample, the bins by runs.
    if (gains.empty() || !(altitude_m > 0.0)) continue;  // gain 1
    bins_of_ping(s->size(), slant_range_m / static_cast<double>(s->size()), altitude_m, bins);
    for (std::size_t i = 0; i < s->size(); ++i) {
      if (bins[i] < 0) continue;
      const double g = gains[std::min(static_cast<std::size_t>(bins[i]), gains.size() - 1)];
      (*s)[i] = static_cast<float>(static_cast<double>((*s)[i]) * g);
    }
  }
}

}  // namespace sonarsynth
