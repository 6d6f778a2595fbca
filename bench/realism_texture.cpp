// SPDX-License-Identifier: MIT
// The realism measures 1 and 6 (seabed texture); definitions in docs/realism.md.
#include <algorithm>
#include <string>

#include "realism_common.hpp"
#include "realism_stats.hpp"
#include "sonarsynth/error.hpp"

namespace bench::realism {

using namespace detail;

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

namespace {

// Measure 7: across-track tiles (near, mid, far), one per block of across_tile_pings pings: the
// lag-1 pairs of each ping's ratio row in the tile and the periodogram of its complete rows.
class AcrossTileRows {
 public:
  AcrossTileRows(std::size_t pings, std::span<const FirstReturn> returns, const Layout& l,
                 const Options& o, Texture& t)
      : returns_(returns),
        l_(l),
        o_(o),
        t_(t),
        an_(o.across_tile_samples),
        far_end_(index_at(o.across_far_range * l.range_m, l)),
        cos_table_(an_),
        sin_table_(an_),
        row_(an_) {
    const std::size_t nblocks = (pings + o.across_tile_pings - 1) / o.across_tile_pings;
    t.across_min_pairs = o.tile_min_fill * static_cast<double>(o.across_tile_pings * (an_ - 1));
    for (auto& place : t.across_tiles) {
      place.resize(nblocks);
      for (Texture::AcrossTile& tile : place) {
        tile.spectrum.assign(an_ / 2 + 1, 0.0);
        tile.sides = 1.0;
      }
    }
    for (std::size_t m = 0; m < an_; ++m) {
      const double a = 2.0 * std::numbers::pi * static_cast<double>(m) / static_cast<double>(an_);
      cos_table_[m] = std::cos(a);
      sin_table_[m] = std::sin(a);
    }
  }

  // Adds ping k's ratio row (NaN outside the seabed or where the box is too empty).
  void add(std::size_t k, const std::vector<double>& ratio) {
    const std::array<std::size_t, 3> start = starts(k);
    for (std::size_t p = 0; p < 3; ++p) {
      const std::size_t s0 = start[p];
      if (s0 >= l_.n) continue;
      Texture::AcrossTile& tile = t_.across_tiles[p][k / o_.across_tile_pings];
      bool complete = true;
      for (std::size_t i = s0; i < s0 + an_; ++i) {
        if (!std::isfinite(ratio[i])) {
          complete = false;
          continue;
        }
        if (i + 1 < s0 + an_ && std::isfinite(ratio[i + 1])) {
          t_.across[p].add(ratio[i], ratio[i + 1]);
          tile.lag1.add(ratio[i], ratio[i + 1]);
        }
      }
      if (complete) add_periodogram(ratio, s0, tile);
    }
  }

 private:
  // First sample of each place's tile row in ping k (n if the row does not fit).
  std::array<std::size_t, 3> starts(std::size_t k) const {
    std::array<std::size_t, 3> start{l_.n, l_.n, l_.n};
    if (!returns_[k].found) return start;
    const double r0 = returns_[k].range_m;
    start[0] = index_at(o_.across_near_r0 * r0, l_);
    const std::size_t centre =
        index_at(0.5 * (o_.across_near_r0 * r0 + o_.across_far_range * l_.range_m), l_);
    start[1] = centre >= an_ / 2 ? centre - an_ / 2 : l_.n;
    start[2] = far_end_ >= an_ ? far_end_ - an_ : l_.n;
    for (std::size_t& s0 : start)
      if (s0 + an_ > l_.n) s0 = l_.n;
    return start;
  }

  // Periodogram of the mean-removed row ratio[s0, s0 + an), bins 0 .. an / 2, into the tile.
  void add_periodogram(const std::vector<double>& ratio, std::size_t s0,
                       Texture::AcrossTile& tile) {
    double mean = 0.0;
    for (std::size_t m = 0; m < an_; ++m) mean += ratio[s0 + m];
    mean /= static_cast<double>(an_);
    for (std::size_t m = 0; m < an_; ++m) row_[m] = ratio[s0 + m] - mean;
    for (std::size_t f = 0; f <= an_ / 2; ++f) {
      double re = 0.0, im = 0.0;
      for (std::size_t m = 0; m < an_; ++m) {
        const std::size_t w = (f * m) % an_;
        re += row_[m] * cos_table_[w];
        im -= row_[m] * sin_table_[w];
      }
      tile.spectrum[f] += re * re + im * im;
    }
    tile.rows += 1.0;
  }

  std::span<const FirstReturn> returns_;
  const Layout& l_;
  const Options& o_;
  Texture& t_;
  std::size_t an_, far_end_;
  std::vector<double> cos_table_, sin_table_, row_;
};

}  // namespace

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
  AcrossTileRows across(pings.size(), returns, l, o, t);
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
    across.add(k, cur);
    std::swap(prev, cur);
  };
  for_each_box(pings.size(), l.n, o.box_pings / 2, o.box_samples / 2, add_row, visit);
  flush();
  return t;
}

}  // namespace bench::realism
