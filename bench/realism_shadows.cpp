// SPDX-License-Identifier: MIT
// The realism measure 3 (shadows); definitions in docs/realism.md.
#include <algorithm>
#include <string>

#include "realism_common.hpp"
#include "realism_stats.hpp"
#include "sonarsynth/error.hpp"

namespace bench::realism {

using namespace detail;

void Shadows::merge(const Shadows& o) {
  seabed += o.seabed;
  shadow += o.shadow;
  level.merge(o.level);
  below_lit.merge(o.below_lit);
  shadow_values.merge(o.shadow_values);
  lit_values.merge(o.lit_values);
  region_cv.insert(region_cv.end(), o.region_cv.begin(), o.region_cv.end());
  if (std::isnan(sample_m)) {
    sample_m = o.sample_m;
    edge_before = o.edge_before;
    edge_window_min = o.edge_window_min;
  }
  for (auto [to, from] :
       {std::pair{&edge_window_sum, &o.edge_window_sum}, {&edge_all_sum, &o.edge_all_sum}}) {
    if (to->size() < from->size()) to->resize(from->size(), 0.0);
    for (std::size_t j = 0; j < from->size(); ++j) (*to)[j] += (*from)[j];
  }
  edge_window_count += o.edge_window_count;
  edge_all_count += o.edge_all_count;
}

std::vector<double> Shadows::edge_profile() const {
  const std::size_t count = edge_count();
  const std::vector<double>& sum = edge_in_window() ? edge_window_sum : edge_all_sum;
  std::vector<double> p;
  if (count == 0) return p;
  for (double x : sum) p.push_back(x / static_cast<double>(count));
  return p;
}

double Shadows::edge_width_m() const {
  const std::vector<double> p = edge_profile();
  if (p.size() <= edge_before + 1) return kNaN;
  const std::size_t shadow_n = edge_before + 1, lit_n = p.size() - shadow_n;
  const std::size_t shadow_use = std::max<std::size_t>(1, shadow_n / 2),
                    lit_use = std::max<std::size_t>(1, lit_n / 4);
  double low = 0.0, high = 0.0;
  for (std::size_t j = 0; j < shadow_use; ++j) low += p[j];
  for (std::size_t j = p.size() - lit_use; j < p.size(); ++j) high += p[j];
  low /= static_cast<double>(shadow_use);
  high /= static_cast<double>(lit_use);
  return rise_width_10_90(p, low, high) * sample_m;
}

namespace {

// Per sample of a side: not examined, lit, shadow.
enum SampleState : std::uint8_t { kNone = 0, kLit = 1, kShadow = 2 };

// Range bands of band_m metres: band of sample i (the last band takes the rest).
struct RangeBands {
  RangeBands(const Layout& l, double width_m)
      : n(static_cast<std::size_t>(std::ceil(l.range_m / width_m))), dr(l.dr), band_m(width_m) {}
  std::size_t of(std::size_t i) const {
    return std::min(n - 1, static_cast<std::size_t>((static_cast<double>(i) + 0.5) * dr / band_m));
  }
  std::size_t n;
  double dr, band_m;
};

// Lit reference: per ping and range band the median level of the band's seabed samples (at
// least half the band), then the median of that over reference_pings pings centred on the ping;
// (pings x bands), NaN where none.
std::vector<double> lit_reference(std::span<const Ping> pings, Side side,
                                  const std::vector<Span>& seabed, const Layout& l,
                                  const Options& o, const RangeBands& bands) {
  const std::size_t np = pings.size(), nbands = bands.n;
  std::vector<double> band_median(np * nbands, kNaN), band_level;
  std::vector<std::size_t> band_size(nbands, 0);
  for (std::size_t i = 0; i < l.n; ++i) ++band_size[bands.of(i)];
  for (std::size_t k = 0; k < np; ++k) {
    const std::vector<float>& v = pings[k].samples(side);
    for (std::size_t i = seabed[k].begin; i < seabed[k].end;) {
      const std::size_t b = bands.of(i);
      band_level.clear();
      for (; i < seabed[k].end && bands.of(i) == b; ++i) band_level.push_back(level_db(v[i]));
      if (2 * band_level.size() >= band_size[b])
        band_median[k * nbands + b] = median_of(band_level);
    }
  }
  std::vector<double> reference(np * nbands, kNaN), win;
  const std::size_t h = o.reference_pings / 2;
  for (std::size_t b = 0; b < nbands; ++b)
    for (std::size_t k = 0; k < np; ++k) {
      win.clear();
      for (std::size_t j = k >= h ? k - h : 0; j < std::min(np, k + h + 1); ++j)
        if (std::isfinite(band_median[j * nbands + b])) win.push_back(band_median[j * nbands + b]);
      reference[k * nbands + b] = median_of(win);
    }
  return reference;
}

// Measure 9: CV of each contiguous shadow region (4-connected) of `state` (pings x samples), by
// flood fill, into s.region_cv.
void add_region_cv(std::span<const Ping> pings, Side side, const std::vector<std::uint8_t>& state,
                   const Layout& l, const Options& o, Shadows& s) {
  const std::size_t np = pings.size();
  {
    std::vector<std::uint8_t> seen(state.size(), 0);
    std::vector<std::size_t> stack;
    for (std::size_t start = 0; start < state.size(); ++start) {
      if (state[start] != kShadow || seen[start]) continue;
      Moments m;
      seen[start] = 1;
      stack.assign(1, start);
      while (!stack.empty()) {
        const std::size_t at = stack.back();
        stack.pop_back();
        const std::size_t k = at / l.n, i = at % l.n;
        m.add(pings[k].samples(side)[i]);
        auto visit_at = [&](std::size_t next) {
          if (state[next] == kShadow && !seen[next]) {
            seen[next] = 1;
            stack.push_back(next);
          }
        };
        if (i > 0) visit_at(at - 1);
        if (i + 1 < l.n) visit_at(at + 1);
        if (k > 0) visit_at(at - l.n);
        if (k + 1 < np) visit_at(at + l.n);
      }
      if (m.n >= static_cast<double>(o.shadow_region_min_samples))
        s.region_cv.push_back(m.stddev() / m.mean());
    }
  }
}

// Measure 10: far edges of the shadow runs of `state`, profiles aligned on the last shadow
// sample, into s.
void add_shadow_edges(std::span<const Ping> pings, Side side,
                      const std::vector<std::uint8_t>& state, const Layout& l, const Options& o,
                      Shadows& s) {
  const std::size_t np = pings.size();
  const auto need_shadow = static_cast<std::size_t>(std::ceil(o.edge_shadow_m / l.dr - 1e-9));
  const auto need_lit = static_cast<std::size_t>(std::ceil(o.edge_lit_m / l.dr - 1e-9));
  s.sample_m = l.dr;
  s.edge_before = need_shadow - 1;
  s.edge_window_min = o.edge_window_min;
  s.edge_window_sum.assign(need_shadow + need_lit, 0.0);
  s.edge_all_sum.assign(need_shadow + need_lit, 0.0);
  for (std::size_t k = 0; k < np; ++k) {
    const std::uint8_t* st = &state[k * l.n];
    const std::vector<float>& v = pings[k].samples(side);
    std::size_t run = 0;
    for (std::size_t i = 0; i < l.n; ++i) {
      if (st[i] != kShadow) {
        run = 0;
        continue;
      }
      ++run;
      if (run < need_shadow || i + need_lit >= l.n || st[i + 1] == kShadow) continue;
      bool lit = true;
      for (std::size_t j = i + 1; j <= i + need_lit && lit; ++j) lit = st[j] == kLit;
      if (!lit) continue;
      const double range = (static_cast<double>(i) + 0.5) * l.dr;
      const bool in_window = range >= o.edge_window_begin_m && range < o.edge_window_end_m;
      for (std::size_t j = 0; j < need_shadow + need_lit; ++j) {
        const double x = v[i + 1 + j - need_shadow];
        s.edge_all_sum[j] += x;
        if (in_window) s.edge_window_sum[j] += x;
      }
      ++s.edge_all_count;
      if (in_window) ++s.edge_window_count;
    }
  }
}

}  // namespace

Shadows shadows(std::span<const Ping> pings, Side side, std::span<const FirstReturn> returns,
                const Options& o) {
  o.validate();
  const Layout l = check_layout(pings, returns);
  const std::size_t np = pings.size();
  std::vector<Span> seabed(np);
  for (std::size_t k = 0; k < np; ++k) seabed[k] = regions(returns[k], l, o).seabed;
  const RangeBands bands(l, o.band_m);
  const std::vector<double> reference = lit_reference(pings, side, seabed, l, o, bands);

  Shadows s;
  std::vector<std::uint8_t> state(np * l.n, kNone);
  const double min_count = static_cast<double>(o.shadow_box_pings * o.shadow_box_samples) / 2.0;
  auto add_row = [&](std::size_t k, double sign, Cols& c) {
    const std::vector<float>& v = pings[k].samples(side);
    for (std::size_t i = seabed[k].begin; i < seabed[k].end; ++i) {
      c.a[i] += sign * v[i];
      c.na[i] += sign;
    }
  };
  auto visit = [&](std::size_t k, const Cols& box) {
    const std::vector<float>& v = pings[k].samples(side);
    for (std::size_t i = seabed[k].begin; i < seabed[k].end; ++i) {
      const double ref = reference[k * bands.n + bands.of(i)];
      if (!(box.na[i] >= min_count) || !std::isfinite(ref)) continue;
      ++s.seabed;
      if (level_db(box.a[i] / box.na[i]) >= ref - o.shadow_below_db) {
        state[k * l.n + i] = kLit;
        s.lit_values.add(v[i]);
        continue;
      }
      state[k * l.n + i] = kShadow;
      ++s.shadow;
      s.level.add_value(v[i]);
      s.below_lit.add_db(level_db(v[i]) - ref);
      s.shadow_values.add(v[i]);
    }
  };
  for_each_box(np, l.n, o.shadow_box_pings / 2, o.shadow_box_samples / 2, add_row, visit);
  add_region_cv(pings, side, state, l, o, s);
  add_shadow_edges(pings, side, state, l, o, s);
  return s;
}

}  // namespace bench::realism
