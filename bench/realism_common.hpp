// SPDX-License-Identifier: MIT
// The helpers the realism measures share (bench/realism_stats.cpp, realism_texture.cpp,
// realism_shadows.cpp): the pings' layout, the seabed regions after the first return, levels and
// their running medians, box sums.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "realism_stats.hpp"
#include "sonarsynth/error.hpp"

namespace bench::realism::detail {

using sonarsynth::InputError;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

inline double median_of(std::vector<double>& v) {
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Layout shared by every ping: samples per side and sample spacing.
struct Layout {
  std::size_t n = 0;
  double dr = 0.0;
  double range_m = 0.0;
};

inline Layout check_layout(std::span<const Ping> pings) {
  if (pings.empty()) throw InputError("realism: no pings to measure");
  Layout l;
  l.n = pings[0].port.size();
  l.range_m = pings[0].slant_range_m;
  if (l.n == 0 || !(l.range_m > 0.0) || !std::isfinite(l.range_m))
    throw InputError("realism: ping 0 has " + std::to_string(l.n) +
                     " port samples and slant range " + std::to_string(l.range_m) +
                     " m (need samples and a range > 0)");
  for (std::size_t k = 0; k < pings.size(); ++k) {
    const Ping& p = pings[k];
    if (p.port.size() != l.n || p.starboard.size() != l.n)
      throw InputError("realism: ping " + std::to_string(k) + " has " +
                       std::to_string(p.port.size()) + " port and " +
                       std::to_string(p.starboard.size()) + " starboard samples; ping 0 has " +
                       std::to_string(l.n) + " per side (every ping must share one layout)");
    if (std::abs(p.slant_range_m - l.range_m) > 1e-6 * l.range_m)
      throw InputError("realism: ping " + std::to_string(k) + " has slant range " +
                       std::to_string(p.slant_range_m) + " m; ping 0 has " +
                       std::to_string(l.range_m) + " m (every ping must share one layout)");
  }
  l.dr = l.range_m / static_cast<double>(l.n);
  return l;
}

/// The same, and one first return per ping.
inline Layout check_layout(std::span<const Ping> pings, std::span<const FirstReturn> returns) {
  if (returns.size() != pings.size())
    throw InputError("realism: " + std::to_string(returns.size()) + " first returns for " +
                     std::to_string(pings.size()) + " pings (need one per ping)");
  return check_layout(pings);
}

/// Index of the first sample whose centre (i + 0.5) dr is at or beyond `range_m`, in [0, n].
inline std::size_t index_at(double range_m, const Layout& l) {
  const double i = std::ceil(range_m / l.dr - 0.5);
  if (!(i > 0.0)) return 0;
  return i >= static_cast<double>(l.n) ? l.n : static_cast<std::size_t>(i);
}

struct Span {
  std::size_t begin = 0, end = 0;
  bool contains(std::size_t i) const { return i >= begin && i < end; }
};

struct Regions {
  Span water, near, seabed;
};

inline Regions regions(const FirstReturn& fr, const Layout& l, const Options& o) {
  Regions r;
  if (!fr.found) return r;
  r.water = {fr.water_begin, std::max(fr.water_begin, index_at(o.water_end_r0 * fr.range_m, l))};
  const std::size_t nb = index_at(o.near_begin_r0 * fr.range_m, l);
  r.near = {nb, std::max(nb, index_at(o.near_end_r0 * fr.range_m, l))};
  const std::size_t sb = index_at(o.seabed_begin_r0 * fr.range_m, l);
  r.seabed = {sb, std::max(sb, index_at(o.seabed_end_range * l.range_m, l))};
  return r;
}

inline std::vector<double> levels_of(const std::vector<float>& v) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = level_db(v[i]);
  return out;
}

/// Centred running median of `w` (odd) levels; the window is cut at the ends.
inline std::vector<double> running_median(const std::vector<double>& level, std::size_t w) {
  const std::size_t h = w / 2;
  std::vector<double> out(level.size()), win;
  for (std::size_t i = 0; i < level.size(); ++i) {
    const std::size_t a = i >= h ? i - h : 0, b = std::min(level.size(), i + h + 1);
    win.assign(level.begin() + static_cast<std::ptrdiff_t>(a),
               level.begin() + static_cast<std::ptrdiff_t>(b));
    out[i] = median_of(win);
  }
  return out;
}

inline double median_between(const std::vector<double>& level, Span s) {
  std::vector<double> win(level.begin() + static_cast<std::ptrdiff_t>(s.begin),
                          level.begin() + static_cast<std::ptrdiff_t>(s.end));
  return median_of(win);
}

/// Box sums of two masked channels (a, b) over a centred box of (2 hp + 1) pings x (2 hs + 1)
/// samples, one ping at a time. add_row(k, sign, cols) adds (sign +1) or removes (-1) ping k's
/// masked samples to the column sums; visit(k, box) receives the box sums of ping k.
struct Cols {
  std::vector<double> a, na, b, nb;
  explicit Cols(std::size_t n) : a(n), na(n), b(n), nb(n) {}
};

template <class AddRow, class Visit>
void for_each_box(std::size_t pings, std::size_t n, std::size_t hp, std::size_t hs, AddRow add_row,
                  Visit visit) {
  Cols cols(n), box(n);
  std::vector<double> pa(n + 1), pna(n + 1), pb(n + 1), pnb(n + 1);
  for (std::size_t k = 0; k <= std::min(hp, pings - 1); ++k) add_row(k, 1.0, cols);
  for (std::size_t k = 0; k < pings; ++k) {
    if (k > 0 && k + hp < pings) add_row(k + hp, 1.0, cols);
    if (k > hp) add_row(k - hp - 1, -1.0, cols);
    for (std::size_t i = 0; i < n; ++i) {
      pa[i + 1] = pa[i] + cols.a[i];
      pna[i + 1] = pna[i] + cols.na[i];
      pb[i + 1] = pb[i] + cols.b[i];
      pnb[i + 1] = pnb[i] + cols.nb[i];
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t lo = i >= hs ? i - hs : 0, hi = std::min(n, i + hs + 1);
      box.a[i] = pa[hi] - pa[lo];
      box.na[i] = pna[hi] - pna[lo];
      box.b[i] = pb[hi] - pb[lo];
      box.nb[i] = pnb[hi] - pnb[lo];
    }
    visit(k, static_cast<const Cols&>(box));
  }
}

}  // namespace bench::realism::detail
