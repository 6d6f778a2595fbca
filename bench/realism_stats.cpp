// SPDX-License-Identifier: MIT
// The realism measures 2, 4 and 5 (first return, levels) and the report of all of them;
// definitions in docs/realism.md. Measures 1 and 6 in realism_texture.cpp, 3 in
// realism_shadows.cpp.
#include "realism_stats.hpp"

#include <algorithm>
#include <string>

#include "realism_common.hpp"
#include "sonarsynth/error.hpp"

namespace bench::realism {

using namespace detail;
using sonarsynth::InputError;

// ---- Measure 4: first bottom return ------------------------------------------------------------

std::vector<FirstReturn> first_returns(std::span<const Ping> pings, Side side, const Options& o) {
  o.validate();
  const Layout l = check_layout(pings);
  const auto hold =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(o.hold_m / l.dr)));
  std::vector<FirstReturn> out(pings.size());
  std::vector<double> win;
  for (std::size_t k = 0; k < pings.size(); ++k) {
    const std::vector<double> level = levels_of(pings[k].samples(side));
    const std::vector<double> smooth = running_median(level, o.smooth_samples);
    // The first sample at or within detect_below_db of `ref` after the transmit pulse, whose
    // following hold samples have a median above the threshold too.
    auto detect = [&](double ref, FirstReturn& fr) {
      const double t = ref - o.detect_below_db;
      if (!std::isfinite(t)) return false;
      std::size_t start = 0;
      while (start < l.n && smooth[start] >= t) ++start;
      for (std::size_t i = start; i + hold <= l.n; ++i) {
        if (smooth[i] < t) continue;
        if (median_between(level, {i, i + hold}) < t) continue;
        fr.water_begin = start;
        fr.index = i;
        fr.range_m = (static_cast<double>(i) + 0.5) * l.dr;
        return true;
      }
      return false;
    };
    auto near_level = [&](const FirstReturn& fr) {
      FirstReturn f = fr;
      f.found = true;
      return median_between(level, regions(f, l, o).near);
    };
    FirstReturn fr;
    const Span far{index_at(o.reference_begin * l.range_m, l),
                   index_at(o.reference_end * l.range_m, l)};
    if (far.end > far.begin && detect(median_between(level, far), fr)) {
      fr.seabed_db = near_level(fr);
      // Once more against the near-seabed level the figures refer to.
      FirstReturn again;
      if (detect(fr.seabed_db, again)) {
        again.seabed_db = near_level(again);
        if (std::isfinite(again.seabed_db)) fr = again;
      }
      fr.found = std::isfinite(fr.seabed_db);
    }
    out[k] = fr;
  }
  return out;
}

void FirstReturnStats::merge(const FirstReturnStats& o) {
  pings += o.pings;
  found += o.found;
  if (std::isnan(sample_m)) sample_m = o.sample_m;
  if (std::isnan(step_r0)) step_r0 = o.step_r0;
  range_m.insert(range_m.end(), o.range_m.begin(), o.range_m.end());
  range_minus_altitude_m.insert(range_minus_altitude_m.end(), o.range_minus_altitude_m.begin(),
                                o.range_minus_altitude_m.end());
  range_over_altitude.insert(range_over_altitude.end(), o.range_over_altitude.begin(),
                             o.range_over_altitude.end());
  if (profile_offsets_m.empty()) profile_offsets_m = o.profile_offsets_m;
  if (std::isnan(monotone_until_m)) monotone_until_m = o.monotone_until_m;
  if (std::isnan(monotone_tol_db)) monotone_tol_db = o.monotone_tol_db;
  for (auto [to, from] : {std::pair{&aligned, &o.aligned},
                          {&aligned_r0, &o.aligned_r0},
                          {&profile_r0, &o.profile_r0},
                          {&profile_altitude, &o.profile_altitude}}) {
    if (to->size() < from->size()) to->resize(from->size());
    for (std::size_t j = 0; j < from->size(); ++j)
      (*to)[j].insert((*to)[j].end(), (*from)[j].begin(), (*from)[j].end());
  }
}

namespace {

/// First offset where the per-offset median reaches -below_db, times `step`; NaN if none.
double first_reaching(const std::vector<std::vector<float>>& profile, double below_db,
                      double step) {
  for (std::size_t j = 0; j < profile.size(); ++j) {
    if (profile[j].empty()) continue;
    std::vector<double> v(profile[j].begin(), profile[j].end());
    if (median_of(v) >= -below_db) return static_cast<double>(j) * step;
  }
  return kNaN;
}

}  // namespace

double FirstReturnStats::rise_m(double below_db) const {
  return first_reaching(aligned, below_db, sample_m);
}

double FirstReturnStats::rise_r0(double below_db) const {
  return first_reaching(aligned_r0, below_db, step_r0);
}

double FirstReturnStats::profile_db(std::size_t j, bool altitude) const {
  const auto& p = altitude ? profile_altitude : profile_r0;
  if (j >= p.size()) return kNaN;
  return quantile(std::vector<double>(p[j].begin(), p[j].end()), 0.5);
}

double FirstReturnStats::profile_max_drop_db() const {
  double peak = -kInf, drop = kNaN;
  for (std::size_t j = 0; j < aligned.size(); ++j) {
    if (static_cast<double>(j) * sample_m > monotone_until_m + 1e-9) break;
    if (aligned[j].empty()) continue;
    std::vector<double> v(aligned[j].begin(), aligned[j].end());
    const double m = median_of(v);
    if (std::isnan(m)) continue;
    peak = std::max(peak, m);
    const double d = std::isfinite(peak) ? peak - m : 0.0;
    drop = std::isnan(drop) ? std::max(0.0, d) : std::max(drop, d);
  }
  return drop;
}

FirstReturnStats first_return_stats(std::span<const Ping> pings, Side side,
                                    std::span<const FirstReturn> returns, const Options& o) {
  const Layout l = check_layout(pings, returns);
  FirstReturnStats s;
  s.sample_m = l.dr;
  s.step_r0 = o.rise_step_r0;
  s.aligned.resize(static_cast<std::size_t>(std::ceil(o.rise_span_m / l.dr)));
  s.aligned_r0.resize(static_cast<std::size_t>(std::ceil(o.rise_span_r0 / o.rise_step_r0)));
  s.profile_offsets_m = o.profile_offsets_m;
  s.monotone_until_m = o.monotone_until_m;
  s.monotone_tol_db = o.monotone_tol_db;
  s.profile_r0.resize(o.profile_offsets_m.size());
  s.profile_altitude.resize(o.profile_offsets_m.size());
  for (std::size_t k = 0; k < pings.size(); ++k) {
    ++s.pings;
    const FirstReturn& fr = returns[k];
    if (!fr.found) continue;
    ++s.found;
    s.range_m.push_back(fr.range_m);
    if (pings[k].altitude_m > 0.0) {
      s.range_minus_altitude_m.push_back(fr.range_m - pings[k].altitude_m);
      s.range_over_altitude.push_back(fr.range_m / pings[k].altitude_m);
    }
    const std::vector<float>& v = pings[k].samples(side);
    for (std::size_t j = 0; j < s.aligned.size() && fr.index + j < l.n; ++j)
      s.aligned[j].push_back(static_cast<float>(level_db(v[fr.index + j]) - fr.seabed_db));
    // Offsets in units of r0 start at the first-return sample itself.
    for (std::size_t j = 0; j < s.aligned_r0.size(); ++j) {
      const std::size_t i =
          j == 0 ? fr.index
                 : index_at(fr.range_m * (1.0 + static_cast<double>(j) * o.rise_step_r0), l);
      if (i >= l.n) break;
      s.aligned_r0[j].push_back(static_cast<float>(level_db(v[i]) - fr.seabed_db));
    }
    // The sample nearest r0 + d is the one whose span [i, i + 1) dr holds it: for r0 at the
    // centre of sample `index`, index + round(d / dr).
    const double altitude = pings[k].altitude_m;
    for (std::size_t j = 0; j < o.profile_offsets_m.size(); ++j) {
      const double d = o.profile_offsets_m[j];
      const double i = static_cast<double>(fr.index) + std::floor(d / l.dr + 0.5);
      if (i < static_cast<double>(l.n))
        s.profile_r0[j].push_back(
            static_cast<float>(level_db(v[static_cast<std::size_t>(i)]) - fr.seabed_db));
      const double ih = std::floor((altitude + d) / l.dr);
      if (altitude > 0.0 && ih < static_cast<double>(l.n))
        s.profile_altitude[j].push_back(
            static_cast<float>(level_db(v[static_cast<std::size_t>(ih)]) - fr.seabed_db));
    }
  }
  return s;
}

// ---- Measures 2 and 5: levels ------------------------------------------------------------------

void Levels::merge(const Levels& o) {
  water.merge(o.water);
  near.merge(o.near);
  seabed.merge(o.seabed);
  lead.merge(o.lead);
  samples += o.samples;
  zeros += o.zeros;
  water_zeros += o.water_zeros;
  seabed_zeros += o.seabed_zeros;
  seabed_dark += o.seabed_dark;
  seabed_clipped += o.seabed_clipped;
  near_clipped += o.near_clipped;
  lead_clipped += o.lead_clipped;
  ping_water_minus_near_db.insert(ping_water_minus_near_db.end(),
                                  o.ping_water_minus_near_db.begin(),
                                  o.ping_water_minus_near_db.end());
  water_stats.merge(o.water_stats);
  for (auto [to, from] : {std::pair{&water_block_cv, &o.water_block_cv},
                          {&water_block_skewness, &o.water_block_skewness},
                          {&water_ping_cv, &o.water_ping_cv},
                          {&far_minus_near_db, &o.far_minus_near_db},
                          {&altitude_over_range, &o.altitude_over_range}})
    to->insert(to->end(), from->begin(), from->end());
  if (std::isnan(water_min) || o.water_min < water_min) water_min = o.water_min;
  water_first_third.merge(o.water_first_third);
  water_last_third.merge(o.water_last_third);
  first_metres += o.first_metres;
  first_metres_clipped += o.first_metres_clipped;
  all.merge(o.all);
}

Levels levels(std::span<const Ping> pings, Side side, std::span<const FirstReturn> returns,
              double clip_value, const Options& o) {
  o.validate();
  const Layout l = check_layout(pings, returns);
  Levels s;
  std::vector<double> water_levels;
  // Measure 11: the water column statistics of the current block of pings.
  Moments3 block;
  auto flush_block = [&]() {
    if (block.n >= static_cast<double>(o.water_block_min_samples)) {
      s.water_block_cv.push_back(block.cv());
      s.water_block_skewness.push_back(block.skewness());
    }
    block = Moments3{};
  };
  const Span far{index_at(o.far_begin_range * l.range_m, l),
                 index_at(o.far_end_range * l.range_m, l)};
  for (std::size_t k = 0; k < pings.size(); ++k) {
    if (k % o.water_block_pings == 0) flush_block();
    const std::vector<float>& v = pings[k].samples(side);
    for (std::size_t i = 0; i < l.n; ++i) {
      ++s.samples;
      if (v[i] == 0.0f) ++s.zeros;
      s.all.add_value(v[i]);
    }
    for (std::size_t i = 0; i < std::min(o.lead_samples, l.n); ++i) {
      s.lead.add_value(v[i]);
      if (v[i] >= clip_value) ++s.lead_clipped;
    }
    if (!returns[k].found) continue;
    const Regions r = regions(returns[k], l, o);
    water_levels.clear();
    for (std::size_t i = r.water.begin; i < r.water.end; ++i) {
      s.water.add_value(v[i]);
      water_levels.push_back(level_db(v[i]));
      if (v[i] == 0.0f) ++s.water_zeros;
    }
    if (!water_levels.empty())
      s.ping_water_minus_near_db.push_back(median_of(water_levels) - returns[k].seabed_db);
    for (std::size_t i = r.near.begin; i < r.near.end; ++i) {
      s.near.add_value(v[i]);
      if (v[i] >= clip_value) ++s.near_clipped;
    }
    for (std::size_t i = r.seabed.begin; i < r.seabed.end; ++i) {
      s.seabed.add_value(v[i]);
      if (v[i] == 0.0f) ++s.seabed_zeros;
      if (v[i] < o.dark_value) ++s.seabed_dark;
      if (v[i] >= clip_value) ++s.seabed_clipped;
    }
    const double r0 = returns[k].range_m;
    // Measure 11: water column statistics over [water_stats_begin, 0.85 r0).
    const std::size_t wb = o.water_stats_begin, we = index_at(o.water_stats_end_r0 * r0, l);
    if (we > wb) {
      const std::size_t third = (we - wb) / 3;
      Moments3 ping;
      for (std::size_t i = wb; i < we; ++i) {
        ping.add(v[i]);
        if (std::isnan(s.water_min) || v[i] < s.water_min) s.water_min = v[i];
        if (i < wb + third) s.water_first_third.add_value(v[i]);
        if (i >= we - third) s.water_last_third.add_value(v[i]);
      }
      s.water_stats.merge(ping);
      block.merge(ping);
      if (we - wb >= o.water_ping_min_samples) s.water_ping_cv.push_back(ping.cv());
    }
    // Measure 13: far range [0.9 R, 0.97 R) against [1.4 r0, 1.6 r0).
    const Span near_ref{index_at(o.near_ref_begin_r0 * r0, l), index_at(o.near_ref_end_r0 * r0, l)};
    if (far.end > far.begin && near_ref.end > near_ref.begin && near_ref.end <= l.n) {
      const std::vector<double> level = levels_of(v);
      const double d = median_between(level, far) - median_between(level, near_ref);
      if (!std::isnan(d)) {
        s.far_minus_near_db.push_back(d);
        if (pings[k].altitude_m > 0.0)
          s.altitude_over_range.push_back(pings[k].altitude_m / l.range_m);
      }
    }
    // Measure 14: samples [r0, r0 + clip_near_m) at full scale.
    for (std::size_t i = returns[k].index; i < index_at(r0 + o.clip_near_m, l); ++i) {
      ++s.first_metres;
      if (v[i] >= clip_value) ++s.first_metres_clipped;
    }
  }
  flush_block();
  return s;
}

// ---- Measure 3: shadows ------------------------------------------------------------------------
// ---- Everything --------------------------------------------------------------------------------

void SideReport::merge(const SideReport& o) {
  first.merge(o.first);
  texture.merge(o.texture);
  levels.merge(o.levels);
  shadows.merge(o.shadows);
}

double max_sample(std::span<const Ping> pings) {
  double m = -kInf;
  for (const Ping& p : pings) {
    for (float v : p.port) m = std::max(m, static_cast<double>(v));
    for (float v : p.starboard) m = std::max(m, static_cast<double>(v));
  }
  return m;
}

double median_ping_spacing_m(std::span<const Ping> pings, std::size_t lag) {
  if (lag == 0) throw InputError("realism: ping spacing lag 0 (need >= 1)");
  std::vector<double> d;
  for (std::size_t k = 0; k + lag < pings.size(); ++k) {
    const Ping &a = pings[k], &b = pings[k + lag];
    if (a.position_valid && b.position_valid)
      d.push_back(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) / static_cast<double>(lag));
  }
  return quantile(std::move(d), 0.5);
}

Report measure(std::span<const Ping> pings, const Options& o) {
  o.validate();
  const Layout l = check_layout(pings);
  Report r;
  r.pings = pings.size();
  r.samples = l.n;
  r.slant_range_m = l.range_m;
  r.max_value = max_sample(pings);
  r.ping_spacing_m = median_ping_spacing_m(pings, o.spacing_lag);
  std::vector<double> altitude;
  for (const Ping& p : pings)
    if (p.altitude_m > 0.0) altitude.push_back(p.altitude_m);
  if (!altitude.empty()) {
    r.altitude_min_m = *std::min_element(altitude.begin(), altitude.end());
    r.altitude_max_m = *std::max_element(altitude.begin(), altitude.end());
    r.altitude_median_m = quantile(std::move(altitude), 0.5);
  }
  for (Side side : {Side::kPort, Side::kStarboard}) {
    const std::vector<FirstReturn> fr = first_returns(pings, side, o);
    SideReport& s = side == Side::kPort ? r.port : r.starboard;
    s.first = first_return_stats(pings, side, fr, o);
    s.texture = seabed_texture(pings, side, fr, o);
    s.levels = levels(pings, side, fr, r.max_value, o);
    s.shadows = shadows(pings, side, fr, o);
  }
  r.pooled = r.port;
  r.pooled.merge(r.starboard);
  return r;
}

}  // namespace bench::realism
