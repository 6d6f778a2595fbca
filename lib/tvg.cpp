// SPDX-License-Identifier: MIT
#include "sonarsynth/tvg.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

void Tvg::validate() const {
  if (!(std::isfinite(absorption_db_per_m) && absorption_db_per_m >= 0.0)) {
    throw InputError("tvg: absorption_db_per_m = " + std::to_string(absorption_db_per_m) +
                     ". Violated constraint: absorption_db_per_m >= 0");
  }
  if (!(spreading_db_per_decade >= 0.0 && spreading_db_per_decade <= 60.0)) {
    throw InputError("tvg: spreading_db_per_decade = " + std::to_string(spreading_db_per_decade) +
                     ". Violated constraint: 0 <= spreading_db_per_decade <= 60");
  }
  if (!(absorption_share >= 0.0 && absorption_share <= 1.0)) {
    throw InputError("tvg: absorption_share = " + std::to_string(absorption_share) +
                     ". Violated constraint: 0 <= absorption_share <= 1");
  }
  if (!std::isfinite(constant_db)) {
    throw InputError("tvg: constant_db = " + std::to_string(constant_db) +
                     ". Violated constraint: constant_db finite");
  }
  if (!(std::isfinite(min_range_m) && min_range_m > 0.0)) {
    throw InputError("tvg: min_range_m = " + std::to_string(min_range_m) +
                     ". Violated constraint: min_range_m > 0");
  }
}

double Tvg::gain_db(double slant_range_m) const {
  if (law == TvgLaw::none) return constant_db;
  // k log10 R + 2 a alpha R; k = 30, a = 1 compensates seabed reverberation (area grows as r),
  // docs/physics.md §1.2.
  const double r = std::max(slant_range_m, min_range_m);
  return spreading_db_per_decade * std::log10(r) +
         2.0 * absorption_share * absorption_db_per_m * r + constant_db;
}

namespace {
void scale_by_tvg(const Tvg& tvg, double first_range_m, double spacing_m, double sign,
                  std::vector<double>& intensity) {
  tvg.validate();
  if (!std::isfinite(first_range_m) || !(std::isfinite(spacing_m) && spacing_m > 0.0)) {
    throw InputError("tvg: first_range_m = " + std::to_string(first_range_m) + ", spacing_m = " +
                     std::to_string(spacing_m) + ". Violated constraint: finite, spacing_m > 0");
  }
  for (std::size_t i = 0; i < intensity.size(); ++i) {
    const double r = first_range_m + static_cast<double>(i) * spacing_m;
    intensity[i] *= std::pow(10.0, sign * tvg.gain_db(r) / 10.0);
  }
}
}  // namespace

void apply_tvg(const Tvg& tvg, double first_range_m, double spacing_m,
               std::vector<double>& intensity) {
  scale_by_tvg(tvg, first_range_m, spacing_m, +1.0, intensity);
}

void remove_tvg(const Tvg& tvg, double first_range_m, double spacing_m,
                std::vector<double>& intensity) {
  scale_by_tvg(tvg, first_range_m, spacing_m, -1.0, intensity);
}

void Quantizer::validate() const {
  if (!std::isfinite(gain_db)) {
    throw InputError("quantizer: gain_db = " + std::to_string(gain_db) +
                     ". Violated constraint: gain_db finite");
  }
  if (!(std::isfinite(max_value) && max_value > 0.0)) {
    throw InputError("quantizer: max_value = " + std::to_string(max_value) +
                     ". Violated constraint: max_value > 0");
  }
}

std::vector<float> quantize(const std::vector<double>& intensity, const Quantizer& q,
                            std::size_t* clipped_count) {
  q.validate();
  const double g = std::pow(10.0, q.gain_db / 10.0);
  std::vector<float> out(intensity.size());
  std::size_t clipped = 0;
  for (std::size_t i = 0; i < intensity.size(); ++i) {
    double v = intensity[i] * g;
    if (!(v > 0.0)) v = 0.0;  // negative or NaN
    if (v > q.max_value) {
      v = q.max_value;
      ++clipped;
    }
    if (q.round_to_integer) v = std::floor(v + 0.5);
    out[i] = static_cast<float>(v);
  }
  if (clipped_count != nullptr) *clipped_count = clipped;
  return out;
}

std::vector<double> dequantize(const std::vector<float>& samples, const Quantizer& q) {
  q.validate();
  const double inv_g = std::pow(10.0, -q.gain_db / 10.0);
  std::vector<double> out(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) out[i] = static_cast<double>(samples[i]) * inv_g;
  return out;
}

}  // namespace sonarsynth
