// SPDX-License-Identifier: MIT
// Definition: bench/first_return_change_point.hpp and docs/conversion.md.
#include "first_return_change_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bench {

std::size_t two_level_change_point(const std::vector<double>& x, std::size_t b, std::size_t e) {
  if (e < b + 4) return b;
  double sum = x[b], total = 0.0, total2 = 0.0;
  for (std::size_t i = b; i < e; ++i) {
    total += x[i];
    total2 += x[i] * x[i];
  }
  double best = std::numeric_limits<double>::infinity();
  std::size_t at = b;
  for (std::size_t c = b + 2; c + 2 <= e; ++c) {
    sum += x[c - 1];
    const double n1 = static_cast<double>(c - b), n2 = static_cast<double>(e - c);
    const double m1 = sum / n1, m2 = (total - sum) / n2;
    const double sse = total2 - n1 * m1 * m1 - n2 * m2 * m2;
    if (sse < best) {
      best = sse;
      at = c;
    }
  }
  return at;
}

std::ptrdiff_t change_point_first_return(std::span<const float> side, std::size_t window_samples) {
  const std::size_t n = side.size();
  if (n == 0 || window_samples < 2) return -1;
  std::vector<double> db(n);
  double largest = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    db[i] = std::isfinite(side[i]) ? std::abs(static_cast<double>(side[i])) : 0.0;
    largest = std::max(largest, db[i]);
  }
  if (!(largest > 0.0)) return -1;
  for (double& v : db) v = 20.0 * std::log10(std::max(v, 1e-6 * largest));
  std::vector<double> sorted = db;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2),
                   sorted.end());
  const double median = sorted[n / 2];
  std::size_t start = 0;
  while (start < n && db[start] > median) ++start;
  if (start + 8 > n) return -1;
  std::size_t c = two_level_change_point(db, start, n);
  for (int iteration = 0; iteration < 100; ++iteration) {
    const std::size_t next = two_level_change_point(db, start, std::min(n, c + window_samples));
    if (next == c) break;
    c = next;
  }
  return static_cast<std::ptrdiff_t>(c);
}

}  // namespace bench
