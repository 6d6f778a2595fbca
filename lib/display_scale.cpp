// SPDX-License-Identifier: MIT
#include "sonarsynth/display_scale.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

double DisplayRange::value(float linear) const {
  if (std::isnan(linear)) return std::numeric_limits<double>::quiet_NaN();
  if (!(linear > 0.0f)) return 0.0;
  if (linear_full_scale > 0.0) {
    return std::clamp(static_cast<double>(linear) / linear_full_scale, 0.0, 1.0);
  }
  const double db = 10.0 * std::log10(static_cast<double>(linear));
  return std::clamp((db - lo_db) / (hi_db - lo_db), 0.0, 1.0);
}

std::string DisplayRange::describe() const {
  std::ostringstream os;
  if (linear_full_scale > 0.0) {
    os << "linear: value / " << linear_full_scale << " (1)";
  } else {
    os << "10 log10(linear) from " << lo_db << " dB (0) to " << hi_db << " dB (1)";
  }
  return os.str();
}

namespace {

void check_percentiles(double lo_percentile, double hi_percentile) {
  if (!(lo_percentile >= 0.0 && lo_percentile < hi_percentile && hi_percentile <= 100.0)) {
    std::ostringstream os;
    os << "display scale: percentiles " << lo_percentile << ", " << hi_percentile
       << ". Violated constraint: 0 <= lo < hi <= 100";
    throw InputError(os.str());
  }
}

}  // namespace

DisplayRange robust_db_range(std::span<const float> linear, double lo_percentile,
                             double hi_percentile, std::size_t max_samples) {
  check_percentiles(lo_percentile, hi_percentile);
  DbRangeSampler sampler(linear.size(), max_samples);
  sampler.add(linear);
  return sampler.range(lo_percentile, hi_percentile);
}

DbRangeSampler::DbRangeSampler(std::size_t count, std::size_t max_samples)
    : stride_(std::max<std::size_t>(1, count / std::max<std::size_t>(1, max_samples))) {
  values_.reserve(std::min(count, max_samples) + 1);
}

void DbRangeSampler::add(std::span<const float> linear) {
  // Every stride-th value of the whole sequence: indices 0, stride, 2 stride, ...
  const std::size_t first = (stride_ - seen_ % stride_) % stride_;
  for (std::size_t i = first; i < linear.size(); i += stride_) {
    const float v = linear[i];
    if (std::isfinite(v) && v > 0.0f) values_.push_back(v);
  }
  seen_ += linear.size();
}

DisplayRange DbRangeSampler::range(double lo_percentile, double hi_percentile) {
  check_percentiles(lo_percentile, hi_percentile);
  if (values_.empty()) return {};
  auto pick = [&](double pct) {
    const auto k = static_cast<std::size_t>(
        std::llround(pct / 100.0 * static_cast<double>(values_.size() - 1)));
    std::nth_element(values_.begin(), values_.begin() + static_cast<std::ptrdiff_t>(k),
                     values_.end());
    return 10.0 * std::log10(static_cast<double>(values_[k]));
  };
  DisplayRange r{pick(lo_percentile), pick(hi_percentile)};
  if (!(r.hi_db > r.lo_db)) r.hi_db = r.lo_db + 1.0;
  return r;
}

}  // namespace sonarsynth
