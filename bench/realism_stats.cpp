// SPDX-License-Identifier: MIT
// The realism measures; definitions in docs/realism.md.
#include "realism_stats.hpp"

#include <algorithm>
#include <string>

#include "sonarsynth/error.hpp"

namespace bench::realism {

namespace {

using sonarsynth::InputError;

constexpr double kInf = std::numeric_limits<double>::infinity();

double median_of(std::vector<double>& v) {
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

Layout check_layout(std::span<const Ping> pings) {
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
Layout check_layout(std::span<const Ping> pings, std::span<const FirstReturn> returns) {
  if (returns.size() != pings.size())
    throw InputError("realism: " + std::to_string(returns.size()) + " first returns for " +
                     std::to_string(pings.size()) + " pings (need one per ping)");
  return check_layout(pings);
}

/// Index of the first sample whose centre (i + 0.5) dr is at or beyond `range_m`, in [0, n].
std::size_t index_at(double range_m, const Layout& l) {
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

Regions regions(const FirstReturn& fr, const Layout& l, const Options& o) {
  Regions r;
  if (!fr.found) return r;
  r.water = {fr.water_begin, std::max(fr.water_begin, index_at(o.water_end_r0 * fr.range_m, l))};
  const std::size_t nb = index_at(o.near_begin_r0 * fr.range_m, l);
  r.near = {nb, std::max(nb, index_at(o.near_end_r0 * fr.range_m, l))};
  const std::size_t sb = index_at(o.seabed_begin_r0 * fr.range_m, l);
  r.seabed = {sb, std::max(sb, index_at(o.seabed_end_range * l.range_m, l))};
  return r;
}

std::vector<double> levels_of(const std::vector<float>& v) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = level_db(v[i]);
  return out;
}

/// Centred running median of `w` (odd) levels; the window is cut at the ends.
std::vector<double> running_median(const std::vector<double>& level, std::size_t w) {
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

double median_between(const std::vector<double>& level, Span s) {
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

}  // namespace

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

// ---- Measures 1 and 6: seabed texture ----------------------------------------------------------

void Texture::merge(const Texture& o) {
  ratio.merge(o.ratio);
  db.merge(o.db);
  if (std::isnan(band_m)) band_m = o.band_m;
  if (bands.size() < o.bands.size()) bands.resize(o.bands.size());
  for (std::size_t b = 0; b < o.bands.size(); ++b) bands[b].merge(o.bands[b]);
  tile_contrast.insert(tile_contrast.end(), o.tile_contrast.begin(), o.tile_contrast.end());
  tile_db_std.insert(tile_db_std.end(), o.tile_db_std.begin(), o.tile_db_std.end());
  if (grazing_edges_rad.empty()) grazing_edges_rad = o.grazing_edges_rad;
  if (grazing_ratio.size() < o.grazing_ratio.size()) grazing_ratio.resize(o.grazing_ratio.size());
  if (grazing_db.size() < o.grazing_db.size()) grazing_db.resize(o.grazing_db.size());
  for (std::size_t c = 0; c < o.grazing_ratio.size(); ++c)
    grazing_ratio[c].merge(o.grazing_ratio[c]);
  for (std::size_t c = 0; c < o.grazing_db.size(); ++c) grazing_db[c].merge(o.grazing_db[c]);
  if (tile_lag1.size() < o.tile_lag1.size()) tile_lag1.resize(o.tile_lag1.size());
  for (std::size_t b = 0; b < o.tile_lag1.size(); ++b)
    tile_lag1[b].insert(tile_lag1[b].end(), o.tile_lag1[b].begin(), o.tile_lag1[b].end());
  if (std::isnan(across_min_pairs)) across_min_pairs = o.across_min_pairs;
  for (std::size_t p = 0; p < across.size(); ++p) {
    across[p].merge(o.across[p]);
    if (across_tiles[p].size() < o.across_tiles[p].size())
      across_tiles[p].resize(o.across_tiles[p].size());
    for (std::size_t b = 0; b < o.across_tiles[p].size(); ++b)
      across_tiles[p][b].merge(o.across_tiles[p][b]);
  }
}

void Texture::AcrossTile::merge(const AcrossTile& o) {
  lag1.merge(o.lag1);
  if (spectrum.size() < o.spectrum.size()) spectrum.resize(o.spectrum.size(), 0.0);
  for (std::size_t f = 0; f < o.spectrum.size(); ++f) spectrum[f] += o.spectrum[f];
  rows += o.rows;
  sides += o.sides;
}

std::vector<double> Texture::tile_across_lag1(std::size_t place) const {
  std::vector<double> out;
  for (const AcrossTile& t : across_tiles[place]) {
    if (!(t.sides > 0.0) || !(t.lag1.n >= across_min_pairs * t.sides)) continue;
    const double c = t.lag1.correlation();
    if (std::isfinite(c)) out.push_back(c);
  }
  return out;
}

namespace {

/// Quarter q (0..3) of the bins 1 .. N/2 of a summed periodogram, mean over the quarter / mean
/// over all those bins.
double quarter_of(const std::vector<double>& spectrum, std::size_t q) {
  if (spectrum.size() < 9 || q > 3) return kNaN;
  const std::size_t half = spectrum.size() - 1, quarter = half / 4;
  double all = 0.0, part = 0.0;
  for (std::size_t f = 1; f <= half; ++f) {
    all += spectrum[f];
    if (f > q * quarter && f <= (q + 1) * quarter) part += spectrum[f];
  }
  if (!(all > 0.0)) return kNaN;
  return (part / static_cast<double>(quarter)) / (all / static_cast<double>(half));
}

}  // namespace

double Texture::spectrum_quarter(std::size_t q) const {
  std::vector<double> sum;
  for (const auto& tiles : across_tiles)
    for (const AcrossTile& t : tiles) {
      if (sum.size() < t.spectrum.size()) sum.resize(t.spectrum.size(), 0.0);
      for (std::size_t f = 0; f < t.spectrum.size(); ++f) sum[f] += t.spectrum[f];
    }
  return quarter_of(sum, q);
}

double Texture::median_tile_spectrum_quarter(std::size_t q) const {
  std::vector<double> v;
  for (const auto& tiles : across_tiles)
    for (const AcrossTile& t : tiles)
      if (t.sides > 0.0 && t.lag1.n >= across_min_pairs * t.sides) {
        const double x = quarter_of(t.spectrum, q);
        if (std::isfinite(x)) v.push_back(x);
      }
  return quantile(std::move(v), 0.5);
}

std::size_t Texture::spectrum_rows() const {
  double rows = 0.0;
  for (const auto& tiles : across_tiles)
    for (const AcrossTile& t : tiles) rows += t.rows;
  return static_cast<std::size_t>(rows);
}

Texture seabed_texture(std::span<const Ping> pings, Side side, std::span<const FirstReturn> returns,
                       const Options& o) {
  o.validate();
  const Layout l = check_layout(pings, returns);
  std::vector<Span> seabed(pings.size());
  for (std::size_t k = 0; k < pings.size(); ++k) seabed[k] = regions(returns[k], l, o).seabed;
  const std::size_t nbands = o.correlation_bands;
  Texture t;
  t.band_m = l.range_m / static_cast<double>(nbands);
  t.bands.resize(nbands);
  t.tile_lag1.resize(nbands);
  t.grazing_edges_rad = o.grazing_edges_rad;
  const std::size_t nclasses = o.grazing_edges_rad.size() - 1;
  t.grazing_ratio.resize(nclasses);
  t.grazing_db.resize(nclasses);
  // Grazing-angle class of sample i of a ping whose first return is at r0 (nclasses if none).
  auto class_of = [&](std::size_t i, double r0) {
    const double g = std::asin(std::min(1.0, r0 / ((static_cast<double>(i) + 0.5) * l.dr)));
    const auto it = std::upper_bound(o.grazing_edges_rad.begin(), o.grazing_edges_rad.end(), g);
    if (it == o.grazing_edges_rad.begin() || it == o.grazing_edges_rad.end()) return nclasses;
    return static_cast<std::size_t>(it - o.grazing_edges_rad.begin()) - 1;
  };
  const double min_count = static_cast<double>(o.box_pings * o.box_samples) / 2.0;
  auto band_of = [&](std::size_t i) { return std::min(nbands - 1, i * nbands / l.n); };
  // The tiles of the current block of pings, one per band.
  struct Tile {
    Moments ratio, db;
    PearsonSums lag1;
    std::size_t pings = 0;
  };
  std::vector<Tile> tiles(nbands);
  std::vector<std::size_t> band_samples(nbands, 0);
  for (std::size_t i = 0; i < l.n; ++i) ++band_samples[band_of(i)];
  auto flush = [&]() {
    for (std::size_t b = 0; b < nbands; ++b) {
      Tile& tile = tiles[b];
      const double size = static_cast<double>(tile.pings * band_samples[b]);
      if (tile.pings > 0 && tile.ratio.n >= o.tile_min_fill * size) {
        t.tile_contrast.push_back(tile.ratio.stddev() / tile.ratio.mean());
        t.tile_db_std.push_back(tile.db.stddev());
        const double c = tile.lag1.correlation();
        if (std::isfinite(c)) t.tile_lag1[b].push_back(c);
      }
      tile = Tile{};
    }
  };
  // Channel a: sample values; channel b: 10 log10 of the positive ones.
  auto add_row = [&](std::size_t k, double sign, Cols& c) {
    const std::vector<float>& v = pings[k].samples(side);
    for (std::size_t i = seabed[k].begin; i < seabed[k].end; ++i) {
      c.a[i] += sign * v[i];
      c.na[i] += sign;
      if (v[i] > 0.0f) {
        c.b[i] += sign * 10.0 * std::log10(static_cast<double>(v[i]));
        c.nb[i] += sign;
      }
    }
  };
  // Measure 7: across-track tiles (near, mid, far), one per block of across_tile_pings pings.
  const std::size_t an = o.across_tile_samples;
  const std::size_t nblocks = (pings.size() + o.across_tile_pings - 1) / o.across_tile_pings;
  t.across_min_pairs = o.tile_min_fill * static_cast<double>(o.across_tile_pings * (an - 1));
  for (auto& place : t.across_tiles) {
    place.resize(nblocks);
    for (Texture::AcrossTile& tile : place) {
      tile.spectrum.assign(an / 2 + 1, 0.0);
      tile.sides = 1.0;
    }
  }
  std::vector<double> cos_table(an), sin_table(an), row(an);
  for (std::size_t m = 0; m < an; ++m) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(m) / static_cast<double>(an);
    cos_table[m] = std::cos(a);
    sin_table[m] = std::sin(a);
  }
  const std::size_t far_end = index_at(o.across_far_range * l.range_m, l);
  // First sample of each place's tile row in ping k (n if the row does not fit).
  auto across_starts = [&](std::size_t k) {
    std::array<std::size_t, 3> start{l.n, l.n, l.n};
    if (!returns[k].found) return start;
    const double r0 = returns[k].range_m;
    start[0] = index_at(o.across_near_r0 * r0, l);
    const std::size_t centre =
        index_at(0.5 * (o.across_near_r0 * r0 + o.across_far_range * l.range_m), l);
    start[1] = centre >= an / 2 ? centre - an / 2 : l.n;
    start[2] = far_end >= an ? far_end - an : l.n;
    for (std::size_t& s0 : start)
      if (s0 + an > l.n) s0 = l.n;
    return start;
  };
  auto add_across = [&](std::size_t k, const std::vector<double>& ratio) {
    const std::array<std::size_t, 3> start = across_starts(k);
    for (std::size_t p = 0; p < 3; ++p) {
      const std::size_t s0 = start[p];
      if (s0 >= l.n) continue;
      Texture::AcrossTile& tile = t.across_tiles[p][k / o.across_tile_pings];
      bool complete = true;
      for (std::size_t i = s0; i < s0 + an; ++i) {
        if (!std::isfinite(ratio[i])) {
          complete = false;
          continue;
        }
        if (i + 1 < s0 + an && std::isfinite(ratio[i + 1])) {
          t.across[p].add(ratio[i], ratio[i + 1]);
          tile.lag1.add(ratio[i], ratio[i + 1]);
        }
      }
      if (!complete) continue;
      // Periodogram of the mean-removed row, bins 0 .. an / 2.
      double mean = 0.0;
      for (std::size_t m = 0; m < an; ++m) mean += ratio[s0 + m];
      mean /= static_cast<double>(an);
      for (std::size_t m = 0; m < an; ++m) row[m] = ratio[s0 + m] - mean;
      for (std::size_t f = 0; f <= an / 2; ++f) {
        double re = 0.0, im = 0.0;
        for (std::size_t m = 0; m < an; ++m) {
          const std::size_t w = (f * m) % an;
          re += row[m] * cos_table[w];
          im -= row[m] * sin_table[w];
        }
        tile.spectrum[f] += re * re + im * im;
      }
      tile.rows += 1.0;
    }
  };
  std::vector<double> prev(l.n, kNaN), cur(l.n, kNaN);
  auto visit = [&](std::size_t k, const Cols& box) {
    if (k % o.tile_pings == 0) flush();
    for (Tile& tile : tiles) ++tile.pings;
    const std::vector<float>& v = pings[k].samples(side);
    std::fill(cur.begin(), cur.end(), kNaN);
    for (std::size_t i = seabed[k].begin; i < seabed[k].end; ++i) {
      Tile& tile = tiles[band_of(i)];
      const std::size_t c = class_of(i, returns[k].range_m);
      if (box.na[i] >= min_count && box.a[i] > 0.0) {
        cur[i] = v[i] / (box.a[i] / box.na[i]);
        t.ratio.add(cur[i]);
        tile.ratio.add(cur[i]);
        if (c < nclasses) t.grazing_ratio[c].add(cur[i]);
      }
      if (v[i] > 0.0f && box.nb[i] >= min_count) {
        const double d = 10.0 * std::log10(static_cast<double>(v[i])) - box.b[i] / box.nb[i];
        t.db.add(d);
        tile.db.add(d);
        if (c < nclasses) t.grazing_db[c].add(d);
      }
      if (k > 0 && std::isfinite(prev[i]) && std::isfinite(cur[i])) {
        t.bands[band_of(i)].add(prev[i], cur[i]);
        tile.lag1.add(prev[i], cur[i]);
      }
    }
    add_across(k, cur);
    std::swap(prev, cur);
  };
  for_each_box(pings.size(), l.n, o.box_pings / 2, o.box_samples / 2, add_row, visit);
  flush();
  return t;
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

Shadows shadows(std::span<const Ping> pings, Side side, std::span<const FirstReturn> returns,
                const Options& o) {
  o.validate();
  const Layout l = check_layout(pings, returns);
  const std::size_t np = pings.size();
  std::vector<Span> seabed(np);
  for (std::size_t k = 0; k < np; ++k) seabed[k] = regions(returns[k], l, o).seabed;

  // Lit reference: per ping and range band the median level of the band's seabed samples (at
  // least half the band), then the median of that over reference_pings pings centred on the ping.
  const auto nbands = static_cast<std::size_t>(std::ceil(l.range_m / o.band_m));
  auto band_of = [&](std::size_t i) {
    return std::min(nbands - 1,
                    static_cast<std::size_t>((static_cast<double>(i) + 0.5) * l.dr / o.band_m));
  };
  std::vector<double> band_median(np * nbands, kNaN), band_level;
  std::vector<std::size_t> band_size(nbands, 0);
  for (std::size_t i = 0; i < l.n; ++i) ++band_size[band_of(i)];
  for (std::size_t k = 0; k < np; ++k) {
    const std::vector<float>& v = pings[k].samples(side);
    for (std::size_t i = seabed[k].begin; i < seabed[k].end;) {
      const std::size_t b = band_of(i);
      band_level.clear();
      for (; i < seabed[k].end && band_of(i) == b; ++i) band_level.push_back(level_db(v[i]));
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

  Shadows s;
  // Per sample: 0 not examined, 1 lit, 2 shadow.
  enum : std::uint8_t { kNone = 0, kLit = 1, kShadow = 2 };
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
      const double ref = reference[k * nbands + band_of(i)];
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

  // Measure 9: CV of each contiguous shadow region (4-connected), by flood fill.
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

  // Measure 10: far edges of shadow runs, profiles aligned on the last shadow sample.
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
  return s;
}

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
