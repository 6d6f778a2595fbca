// SPDX-License-Identifier: MIT
#include "sonarsynth/mosaic.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/render_math.hpp"
#include "sonarsynth/spill_file.hpp"  // complete type for ~MosaicGrid

namespace sonarsynth {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMaxPixelsPerSide = 1e5;

[[noreturn]] void bad(const std::string& field, double value, const std::string& constraint) {
  std::ostringstream os;
  os << "mosaic: " << field << " = " << value << ". Violated constraint: " << constraint;
  throw InputError(os.str());
}

/// sin^2 taper of the swath ends, floored at kMinMosaicWeight (see MosaicRule::weighted_mean).
double swath_weight(double ground_m, double swath_m, double taper_fraction) {
  if (taper_fraction <= 0.0 || !(swath_m > 0.0)) return 1.0;
  const double u = std::clamp(ground_m / swath_m, 0.0, 1.0);
  const double t = std::min(u, 1.0 - u) / taper_fraction;
  if (t >= 1.0) return 1.0;
  const double s = render_math::sin_series_half_pi(render_math::kHalfPi * t);  // sin(pi/2 t)
  return std::max(kMinMosaicWeight, s * s);
}

}  // namespace

void MosaicOptions::validate() const {
  if (!(taper_fraction >= 0.0 && taper_fraction <= 0.5)) {
    bad("taper_fraction", taper_fraction, "0 <= taper_fraction <= 0.5");
  }
  if (!(fill_step_px > 0.0 && fill_step_px <= 1.0)) {
    bad("fill_step_px", fill_step_px, "0 < fill_step_px <= 1");
  }
  if (!(max_ping_gap_m > 0.0)) bad("max_ping_gap_m", max_ping_gap_m, "max_ping_gap_m > 0");
  if (!(max_ping_turn_rad > 0.0)) {
    bad("max_ping_turn_rad", max_ping_turn_rad, "max_ping_turn_rad > 0");
  }
  if (profile_subdivisions < 1) {
    bad("profile_subdivisions", profile_subdivisions, "profile_subdivisions >= 1");
  }
  if (!(nadir_blank_m >= 0.0 && std::isfinite(nadir_blank_m))) {
    bad("nadir_blank_m", nadir_blank_m, "nadir_blank_m >= 0");
  }
}

MosaicGrid::MosaicGrid(GridGeometry geometry, MosaicOptions options, const HeightGrid* bathymetry)
    : MosaicGrid(geometry, options, bathymetry, kDefaultTilePx) {}

MosaicGrid::MosaicGrid(GridGeometry geometry, MosaicOptions options, const HeightGrid* bathymetry,
                       std::size_t tile_px)
    : geometry_(geometry), options_(options), bathymetry_(bathymetry), tile_px_(tile_px) {
  options_.validate();
  geometry_.validate("mosaic");
  if (!(geometry_.dx_m > 0.0) || geometry_.dy_m != -geometry_.dx_m) {
    bad("geometry.dy_m", geometry_.dy_m, "north-up square pixels: dx_m > 0 and dy_m == -dx_m");
  }
  if (tile_px_ < 1) bad("tile_px", 0.0, "tile_px >= 1");
  tile_pow2_ = std::has_single_bit(tile_px_);
  tile_shift_ = static_cast<unsigned>(std::countr_zero(tile_px_));
  if (bathymetry_ && bathymetry_->empty()) bathymetry_ = nullptr;
  tiles_x_ = (geometry_.cols + tile_px_ - 1) / tile_px_;
  tiles_y_ = (geometry_.rows + tile_px_ - 1) / tile_px_;
  tiles_.resize(tiles_x_ * tiles_y_);
  last_use_.assign(tiles_.size(), 0);
  spilled_.assign(tiles_.size(), 0);
}

MosaicGrid::~MosaicGrid() = default;
MosaicGrid::MosaicGrid(MosaicGrid&&) noexcept = default;
MosaicGrid& MosaicGrid::operator=(MosaicGrid&&) noexcept = default;

GridGeometry MosaicGrid::geometry_covering(const Eigen::Vector2d& min_xy_m,
                                           const Eigen::Vector2d& max_xy_m, double pixel_m) {
  if (!(pixel_m > 0.0) || !std::isfinite(pixel_m)) bad("pixel size", pixel_m, "pixel size > 0");
  if (!min_xy_m.allFinite() || !max_xy_m.allFinite() || (max_xy_m - min_xy_m).minCoeff() < 0) {
    bad("extent", min_xy_m.x(), "a finite box with min <= max");
  }
  const double left = std::floor(min_xy_m.x() / pixel_m) * pixel_m;
  const double right = std::ceil(max_xy_m.x() / pixel_m) * pixel_m;
  const double bottom = std::floor(min_xy_m.y() / pixel_m) * pixel_m;
  const double top = std::ceil(max_xy_m.y() / pixel_m) * pixel_m;
  const double cols = std::max(2.0, std::round((right - left) / pixel_m));
  const double rows = std::max(2.0, std::round((top - bottom) / pixel_m));
  if (cols > kMaxPixelsPerSide || rows > kMaxPixelsPerSide) {
    bad("pixel size", pixel_m,
        "at most 100000 pixels per side (extent " + std::to_string(right - left) + " x " +
            std::to_string(top - bottom) + " m)");
  }
  GridGeometry g;
  g.dx_m = pixel_m;
  g.dy_m = -pixel_m;
  g.x0_m = left + 0.5 * pixel_m;
  g.y0_m = top - 0.5 * pixel_m;
  g.cols = static_cast<std::size_t>(cols);
  g.rows = static_cast<std::size_t>(rows);
  return g;
}

double MosaicGrid::flat_ground_range_m(double slant_range_m, double altitude_m) {
  if (!(slant_range_m > altitude_m)) return kNaN;
  return std::sqrt((slant_range_m - altitude_m) * (slant_range_m + altitude_m));
}

std::uint64_t MosaicGrid::cell_of(const Eigen::Vector2d& p) const {
  const double c = render_math::floor_fast(geometry_.col_of_x(p.x()) + 0.5);
  const double r = render_math::floor_fast(geometry_.row_of_y(p.y()) + 0.5);
  if (!(c >= 0.0 && r >= 0.0 && c < static_cast<double>(geometry_.cols) &&
        r < static_cast<double>(geometry_.rows))) {
    return kOutside;
  }
  return (static_cast<std::uint64_t>(r) << 32) | static_cast<std::uint64_t>(c);
}

namespace {

/// How far (pixels) short of a pixel edge a run's interval ends: the computed position
/// (start + g dir - origin) / pixel differs from the exact one by a few ulp of at most 10^5
/// pixels (< 1e-10), so every point before it falls in the run's cell.
constexpr double kEdgeMarginPx = 1e-6;

/// The largest g (exclusive) for which u = a + b g stays in [k, k + 1) less the margin, given
/// it holds at some g0 below (u is monotonic in g, and so is its computed value).
double cell_end(double a, double b, double k) {
  if (b > 0.0) return (k + 1.0 - kEdgeMarginPx - a) / b;
  if (b < 0.0) return (k + kEdgeMarginPx - a) / b;
  return std::numeric_limits<double>::infinity();
}

}  // namespace

inline std::uint64_t MosaicGrid::line_cell(double g) {
  LineCells& l = line_;
  if (l.valid && g >= l.lo && g < l.safe) return l.cell;
  const std::uint64_t cell = cell_of(l.start + g * l.dir);
  l.valid = runs_ && cell != kOutside;
  if (l.valid) {
    l.cell = cell;
    l.lo = g;
    l.safe = std::min(cell_end(l.a_col, l.b_col, static_cast<double>(cell & 0xffffffffu)),
                      cell_end(l.a_row, l.b_row, static_cast<double>(cell >> 32)));
  }
  return cell;
}

void MosaicGrid::open_run(std::uint64_t cell) {
  const auto col = static_cast<std::size_t>(cell & 0xffffffffu);
  const auto row = static_cast<std::size_t>(cell >> 32);
  // Shifts and masks for the default (power-of-two) tiles, not four integer divisions.
  std::size_t tx, ty, idx;
  if (tile_pow2_) {
    const std::size_t mask = tile_px_ - 1;
    tx = col >> tile_shift_;
    ty = row >> tile_shift_;
    idx = ((row & mask) << tile_shift_) | (col & mask);
  } else {
    tx = col / tile_px_;
    ty = row / tile_px_;
    idx = (row % tile_px_) * tile_px_ + col % tile_px_;
  }
  Tile& t = tile(tx, ty);
  Run& u = run_;
  u.cell = cell;
  u.tile = &t;
  u.idx = idx;
  u.count = t.count[idx];
  switch (options_.rule) {
    case MosaicRule::weighted_mean:
      u.sum_wi = t.sum_wi[idx];
      u.sum_w = t.sum_w[idx];
      break;
    case MosaicRule::max:
      u.best = t.best[idx];
      break;
    case MosaicRule::nearest:
      u.best = t.best[idx];
      u.best_range = t.best_range[idx];
      break;
  }
  u.labelled = !t.labels.empty();
  if (u.labelled) {
    u.label = t.labels[idx];
    u.label_range = t.label_range[idx];
  }
}

void MosaicGrid::close_run() {
  Run& u = run_;
  if (u.cell == kOutside) return;
  Tile& t = *u.tile;
  t.count[u.idx] = u.count;
  switch (options_.rule) {
    case MosaicRule::weighted_mean:
      t.sum_wi[u.idx] = u.sum_wi;
      t.sum_w[u.idx] = u.sum_w;
      break;
    case MosaicRule::max:
      t.best[u.idx] = u.best;
      break;
    case MosaicRule::nearest:
      t.best[u.idx] = u.best;
      t.best_range[u.idx] = u.best_range;
      break;
  }
  if (u.labelled) {
    t.labels[u.idx] = u.label;
    t.label_range[u.idx] = u.label_range;
  }
  u.cell = kOutside;
}

inline void MosaicGrid::accumulate(std::uint64_t cell, double ground_m, double swath_m, float value,
                                   std::int32_t label, MosaicAddStats& stats) {
  if (cell == kOutside) {
    ++stats.samples_outside;
    return;
  }
  ++stats.samples_placed;
  if (cell != run_.cell) {
    close_run();
    open_run(cell);
  }
  Run& u = run_;
  ++u.count;
  const auto range = static_cast<float>(ground_m);
  switch (options_.rule) {
    case MosaicRule::weighted_mean: {
      const double w = swath_weight(ground_m, swath_m, options_.taper_fraction);
      u.sum_wi += static_cast<float>(w * value);
      u.sum_w += static_cast<float>(w);
      break;
    }
    case MosaicRule::max:
      u.best = std::max(u.best, value);
      break;
    case MosaicRule::nearest:
      if (range < u.best_range) {
        u.best_range = range;
        u.best = value;
      }
      break;
  }
  if (label != MosaicImage::kNoLabel) {
    has_labels_ = true;
    if (!u.labelled) {
      Tile& t = *u.tile;
      if (t.labels.empty()) {
        t.labels.assign(tile_px_ * tile_px_, MosaicImage::kNoLabel);
        t.label_range.assign(tile_px_ * tile_px_, std::numeric_limits<float>::infinity());
        resident_bytes_ += 8 * tile_px_ * tile_px_;
      }
      u.labelled = true;
      u.label = t.labels[u.idx];
      u.label_range = t.label_range[u.idx];
    }
    if (range < u.label_range) {
      u.label_range = range;
      u.label = label;
    }
  }
  if (!runs_) close_run();
}

MosaicAddStats MosaicGrid::add(const MosaicPing& ping) {
  if (finalized_) throw std::logic_error("mosaic: add() after finalize()");
  if (!ping.sensor_xy_m.allFinite()) bad("sensor_xy_m.x", ping.sensor_xy_m.x(), "finite");
  if (!std::isfinite(ping.heading_grid_rad))
    bad("heading_grid_rad", ping.heading_grid_rad, "finite");
  if (!(std::abs(ping.pitch_rad) < 0.5 * kPi)) bad("pitch_rad", ping.pitch_rad, "|pitch| < pi/2");
  if (!(ping.slant_range_m > 0.0) || !std::isfinite(ping.slant_range_m)) {
    bad("slant_range_m", ping.slant_range_m, "slant_range_m > 0");
  }
  if (!(ping.altitude_m > 0.0) || !std::isfinite(ping.altitude_m)) {
    if (!bathymetry_ || std::isnan(ping.sensor_z_m)) {
      bad("altitude_m", ping.altitude_m, "altitude_m > 0");
    }
  }
  if (!ping.port_labels.empty() && ping.port_labels.size() != ping.port.size()) {
    bad("port_labels.size()", static_cast<double>(ping.port_labels.size()), "== port.size()");
  }
  if (!ping.starboard_labels.empty() && ping.starboard_labels.size() != ping.starboard.size()) {
    bad("starboard_labels.size()", static_cast<double>(ping.starboard_labels.size()),
        "== starboard.size()");
  }
  // Frame axes: x east, y north; heading clockwise from grid north.
  const Eigen::Vector2d forward(std::sin(ping.heading_grid_rad), std::cos(ping.heading_grid_rad));
  const Eigen::Vector2d starboard(forward.y(), -forward.x());
  const double along_shift = std::isfinite(ping.altitude_m) && ping.altitude_m > 0
                                 ? ping.altitude_m * std::tan(ping.pitch_rad)
                                 : 0.0;
  const Eigen::Vector2d start = ping.sensor_xy_m + along_shift * forward;
  MosaicAddStats stats;
  ++clock_;
  cached_index_ = kNoTile;
  add_side(ping, 0, ping.port, ping.port_labels, start, -starboard, stats);
  add_side(ping, 1, ping.starboard, ping.starboard_labels, start, starboard, stats);
  close_run();  // the tiles hold every point before they may be spilled
  enforce_budget();
  return stats;
}

void MosaicGrid::ground_ranges(const MosaicPing& ping, std::size_t n, const Eigen::Vector2d& start,
                               const Eigen::Vector2d& dir) {
  ground_.assign(n, kNaN);
  nadir_slant_m_ = kNaN;
  const double dr = ping.slant_range_m / static_cast<double>(n);
  if (!bathymetry_) {
    nadir_slant_m_ = ping.altitude_m;
    for (std::size_t i = 0; i < n; ++i) {
      ground_[i] = flat_ground_range_m((static_cast<double>(i) + 0.5) * dr, ping.altitude_m);
    }
    return;
  }
  double zs = ping.sensor_z_m;
  if (std::isnan(zs)) {
    zs = bathymetry_->height_m(ping.sensor_xy_m.x(), ping.sensor_xy_m.y()) + ping.altitude_m;
  }
  if (!std::isfinite(zs)) return;  // no seabed below the sensor: nothing can be placed
  bathymetry_->profile(start, dir, ping.slant_range_m, options_.profile_subdivisions, profile_);
  // Slant range to each profile point; the first crossing of r is found by one forward sweep
  // because rho is continuous from rho(0): the first crossing of a larger r comes later.
  std::size_t k = 0;
  const std::size_t m = profile_.size();
  // Computed once per point (the sweep below reads each several times).
  rho_m_.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    rho_m_[j] =
        std::isfinite(profile_[j].z_m) ? std::hypot(profile_[j].s_m, zs - profile_[j].z_m) : kNaN;
  }
  if (m > 0 && std::isfinite(profile_[0].z_m)) nadir_slant_m_ = rho_m_[0];
  for (std::size_t i = 0; i < n; ++i) {
    const double r = (static_cast<double>(i) + 0.5) * dr;
    while (k < m && !(std::isfinite(profile_[k].z_m) && rho_m_[k] >= r)) ++k;
    if (k >= m) break;                                            // never reaches the seabed
    if (k == 0 || !std::isfinite(profile_[k - 1].z_m)) continue;  // water column or hole edge
    const double r0 = rho_m_[k - 1];
    const double r1 = rho_m_[k];
    const double t = r1 > r0 ? (r - r0) / (r1 - r0) : 1.0;
    ground_[i] = profile_[k - 1].s_m + t * (profile_[k].s_m - profile_[k - 1].s_m);
  }
}

void MosaicGrid::add_side(const MosaicPing& ping, int side, std::span<const float> values,
                          std::span<const std::int32_t> labels, const Eigen::Vector2d& start,
                          const Eigen::Vector2d& dir, MosaicAddStats& stats) {
  const std::size_t n = values.size();
  if (n == 0) return;
  ground_ranges(ping, n, start, dir);
  const double swath_m = MosaicGrid::flat_ground_range_m(
      ping.slant_range_m, std::isfinite(ping.altitude_m) ? std::max(0.0, ping.altitude_m) : 0.0);
  const double step_m = options_.fill_step_px * geometry_.dx_m;
  const bool have_labels = !labels.empty();
  line_.start = start;
  line_.dir = dir;
  line_.a_col = geometry_.col_of_x(start.x()) + 0.5;
  line_.b_col = dir.x() / geometry_.dx_m;
  line_.a_row = geometry_.row_of_y(start.y()) + 0.5;
  line_.b_row = dir.y() / geometry_.dy_m;
  line_.valid = false;
  std::size_t prev = n;  // index of the previous placed sample
  nadir_ground_m_ = 0.0;
  // The nadir gap: the first seabed sample is no further out than the bin holding the altitude
  // reaches, the next bin centre when the altitude is a bin centre (a tracked one), with a
  // margin for round-off (docs/conversion.md).
  const double dr = ping.slant_range_m / static_cast<double>(n);
  // Blanked first return (nadir_blank_m): those samples are not placed; the fill below then
  // reaches across the blanked slant ranges too.
  const double blank_m = options_.nadir_blank_m;
  if (blank_m > 0.0 && nadir_slant_m_ > 0.0) {
    for (std::size_t i = 0; i < n; ++i) {
      if ((static_cast<double>(i) + 0.5) * dr >= nadir_slant_m_ + blank_m) break;
      ground_[i] = kNaN;
    }
  }
  const double reach_dr = blank_m > 0.0 ? dr + blank_m : dr;
  double nadir_reach_m = options_.nadir_fill && nadir_slant_m_ > 0.0
                             ? 1.001 * std::sqrt((2.0 * nadir_slant_m_ + reach_dr) * reach_dr)
                             : -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double g = ground_[i];
    if (std::isnan(g) || !std::isfinite(values[i])) {
      ++stats.samples_water;
      prev = n;
      continue;
    }
    if (nadir_reach_m >= 0.0) {
      if (g > 0.0 && g <= nadir_reach_m) {
        nadir_sample_ = i;
        nadir_ground_m_ = g;
        const auto fills = static_cast<std::size_t>(std::ceil(g / step_m));
        for (std::size_t j = 0; j < fills; ++j) {
          const double gj = g * static_cast<double>(j) / static_cast<double>(fills);
          const std::size_t before = stats.samples_placed;
          accumulate(line_cell(gj), gj, swath_m, values[i],
                     have_labels ? labels[i] : MosaicImage::kNoLabel, stats);
          if (stats.samples_placed > before) {
            --stats.samples_placed;
            ++stats.fill_points;
          } else {
            --stats.samples_outside;
          }
        }
      }
      nadir_reach_m = -1.0;  // only before the first seabed sample
    }
    if (prev < n) {
      const double gap = g - ground_[prev];
      if (std::abs(gap) > step_m) {
        const auto fills = static_cast<std::size_t>(std::ceil(std::abs(gap) / step_m)) - 1;
        for (std::size_t j = 1; j <= fills; ++j) {
          const double t = static_cast<double>(j) / static_cast<double>(fills + 1);
          const double gj = ground_[prev] + t * gap;
          const auto v = static_cast<float>((1.0 - t) * values[prev] + t * values[i]);
          const std::int32_t lab =
              have_labels ? (t < 0.5 ? labels[prev] : labels[i]) : MosaicImage::kNoLabel;
          const std::size_t before = stats.samples_placed;
          accumulate(line_cell(gj), gj, swath_m, v, lab, stats);
          if (stats.samples_placed > before) {
            --stats.samples_placed;
            ++stats.fill_points;
          } else {
            --stats.samples_outside;
          }
        }
      }
    }
    accumulate(line_cell(g), g, swath_m, values[i], have_labels ? labels[i] : MosaicImage::kNoLabel,
               stats);
    prev = i;
  }
  if (!options_.along_track_fill) return;
  GroundLine& last = previous_[side];
  current_.valid = true;
  current_.start = start;
  current_.dir = dir;
  current_.sensor = ping.sensor_xy_m;
  current_.heading_rad = ping.heading_grid_rad;
  current_.swath_m = swath_m;
  resample_ground_line(values, labels, current_);
  if (last.valid) fill_between(last, current_, stats);
  std::swap(last, current_);
}

void MosaicGrid::break_line() {
  previous_[0].valid = false;
  previous_[1].valid = false;
}

void MosaicGrid::resample_ground_line(std::span<const float> values,
                                      std::span<const std::int32_t> labels,
                                      GroundLine& line) const {
  const double step_m = options_.fill_step_px * geometry_.dx_m;
  double reach = 0.0;
  for (double g : ground_) {
    if (!std::isnan(g)) reach = std::max(reach, g);
  }
  const auto n = static_cast<std::size_t>(std::ceil(reach / step_m));
  line.values.assign(n, std::numeric_limits<float>::quiet_NaN());
  line.labels.assign(labels.empty() ? 0 : n, MosaicImage::kNoLabel);
  for (std::size_t i = 0; i + 1 < ground_.size(); ++i) {
    const double ga = ground_[i];
    const double gb = ground_[i + 1];
    if (std::isnan(ga) || std::isnan(gb) || !std::isfinite(values[i]) ||
        !std::isfinite(values[i + 1])) {
      continue;
    }
    const double lo = std::min(ga, gb);
    const double hi = std::max(ga, gb);
    const double j0 = std::max(0.0, std::ceil(lo / step_m - 0.5));
    for (auto j = static_cast<std::size_t>(j0); j < n; ++j) {
      const double y = (static_cast<double>(j) + 0.5) * step_m;
      if (y > hi) break;
      if (!std::isnan(line.values[j])) continue;  // the first (nearest) crossing wins
      const double t = hi > lo ? (y - ga) / (gb - ga) : 0.0;
      line.values[j] = static_cast<float>((1.0 - t) * values[i] + t * values[i + 1]);
      if (!labels.empty()) line.labels[j] = t < 0.5 ? labels[i] : labels[i + 1];
    }
  }
  // The nadir gap, as add_side filled it.
  for (std::size_t j = 0; j < n && nadir_ground_m_ > 0.0; ++j) {
    if ((static_cast<double>(j) + 0.5) * step_m >= nadir_ground_m_) break;
    if (!std::isnan(line.values[j])) continue;
    line.values[j] = values[nadir_sample_];
    if (!labels.empty()) line.labels[j] = labels[nadir_sample_];
  }
}

void MosaicGrid::fill_between(const GroundLine& a, const GroundLine& b, MosaicAddStats& stats) {
  if ((b.sensor - a.sensor).norm() > options_.max_ping_gap_m) return;
  const double turn = std::remainder(b.heading_rad - a.heading_rad, 2.0 * kPi);
  if (std::abs(turn) > options_.max_ping_turn_rad) return;
  const double step_m = options_.fill_step_px * geometry_.dx_m;
  const std::size_t n = std::min(a.values.size(), b.values.size());
  const bool have_labels = !a.labels.empty() && !b.labels.empty();
  for (std::size_t j = 0; j < n; ++j) {
    const float va = a.values[j];
    const float vb = b.values[j];
    if (std::isnan(va) || std::isnan(vb)) continue;
    const double y = (static_cast<double>(j) + 0.5) * step_m;
    const Eigen::Vector2d pa = a.start + y * a.dir;
    const Eigen::Vector2d pb = b.start + y * b.dir;
    const double d = (pb - pa).norm();
    if (d <= step_m) continue;
    const auto fills = static_cast<std::size_t>(std::ceil(d / step_m)) - 1;
    for (std::size_t k = 1; k <= fills; ++k) {
      const double t = static_cast<double>(k) / static_cast<double>(fills + 1);
      const auto v = static_cast<float>((1.0 - t) * va + t * vb);
      const std::int32_t lab =
          have_labels ? (t < 0.5 ? a.labels[j] : b.labels[j]) : MosaicImage::kNoLabel;
      const std::size_t before = stats.samples_placed;
      splat(pa + t * (pb - pa), y, 0.5 * (a.swath_m + b.swath_m), v, lab, stats);
      if (stats.samples_placed > before) {
        --stats.samples_placed;
        ++stats.along_fill_points;
      } else {
        --stats.samples_outside;
      }
    }
  }
}

}  // namespace sonarsynth
