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
  const double db = 10.0 * std::log10(static_cast<double>(linear));
  return std::clamp((db - lo_db) / (hi_db - lo_db), 0.0, 1.0);
}

DisplayRange robust_db_range(std::span<const float> linear, double lo_percentile,
                             double hi_percentile, std::size_t max_samples) {
  if (!(lo_percentile >= 0.0 && lo_percentile < hi_percentile && hi_percentile <= 100.0)) {
    std::ostringstream os;
    os << "display scale: percentiles " << lo_percentile << ", " << hi_percentile
       << ". Violated constraint: 0 <= lo < hi <= 100";
    throw InputError(os.str());
  }
  const std::size_t stride =
      std::max<std::size_t>(1, linear.size() / std::max<std::size_t>(1, max_samples));
  std::vector<double> db;
  db.reserve(std::min(linear.size(), max_samples) + 1);
  for (std::size_t i = 0; i < linear.size(); i += stride) {
    const float v = linear[i];
    if (std::isfinite(v) && v > 0.0f) db.push_back(10.0 * std::log10(static_cast<double>(v)));
  }
  if (db.empty()) return {};
  auto pick = [&](double pct) {
    const auto k =
        static_cast<std::size_t>(std::llround(pct / 100.0 * static_cast<double>(db.size() - 1)));
    std::nth_element(db.begin(), db.begin() + static_cast<std::ptrdiff_t>(k), db.end());
    return db[k];
  };
  DisplayRange r{pick(lo_percentile), pick(hi_percentile)};
  if (!(r.hi_db > r.lo_db)) r.hi_db = r.lo_db + 1.0;
  return r;
}

}  // namespace sonarsynth
