// SPDX-License-Identifier: MIT
#include "sonarsynth/height_grid.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "sonarsynth/error.hpp"
#include "worker_threads.hpp"

namespace sonarsynth {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Integer grid-line indices strictly inside (a, b) visited in the direction from a to b, as s.
// Appends s = (line - a_idx) / didx_ds for each line crossed; only lines lo..hi (those of the
// grid's nodes: beyond them every height is NaN, and a long ray over a tiny grid would otherwise
// cost one point per cell size along its whole length).
void append_crossings(double idx_start, double idx_per_s, double length_m, double lo, double hi,
                      std::vector<double>& s) {
  if (idx_per_s == 0.0) return;
  const double idx_end = idx_start + idx_per_s * length_m;
  if (idx_per_s > 0) {
    for (double k = std::max(std::floor(idx_start) + 1.0, lo); k < idx_end && k <= hi; k += 1.0) {
      s.push_back((k - idx_start) / idx_per_s);
    }
  } else {
    for (double k = std::min(std::ceil(idx_start) - 1.0, hi); k > idx_end && k >= lo; k -= 1.0) {
      s.push_back((k - idx_start) / idx_per_s);
    }
  }
}
// Catmull-Rom (cubic convolution, a = -0.5) weights of the nodes -1, 0, 1, 2 at t in [0, 1], and
// their derivatives d/dt.
void catmull_rom(double t, double w[4], double dw[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
  dw[0] = 0.5 * (-3.0 * t2 + 4.0 * t - 1.0);
  dw[1] = 0.5 * (9.0 * t2 - 10.0 * t);
  dw[2] = 0.5 * (-9.0 * t2 + 8.0 * t + 1.0);
  dw[3] = 0.5 * (3.0 * t2 - 2.0 * t);
}

// Fills the missing ends of four values at nodes -1, 0, 1, 2 (has[k] false) by extrapolation:
// 3 f0 - 3 f1 + f2 (exact for quadratics) where three real nodes exist, else linearly.
void extend(double* f, std::size_t stride, const bool has[4]) {
  double& a = f[0];
  const double b = f[stride], c = f[2 * stride];
  double& d = f[3 * stride];
  if (!has[0]) a = has[3] ? 3.0 * b - 3.0 * c + d : 2.0 * b - c;
  if (!has[3]) d = has[0] ? 3.0 * c - 3.0 * b + a : 2.0 * c - b;
}
}  // namespace

void GridGeometry::validate(const char* what) const {
  auto fail = [&](const std::string& msg) { throw InputError(std::string(what) + ": " + msg); };
  if (!(std::isfinite(dx_m) && dx_m > 0.0)) {
    fail("cell size x: dx_m = " + std::to_string(dx_m) +
         ". Violated constraint: cell size > 0 and finite");
  }
  if (!(std::isfinite(dy_m) && dy_m != 0.0)) {
    fail("cell size y: dy_m = " + std::to_string(dy_m) +
         ". Violated constraint: cell size != 0 and finite");
  }
  if (!std::isfinite(x0_m))
    fail("x0_m = " + std::to_string(x0_m) + ". Violated constraint: finite");
  if (!std::isfinite(y0_m))
    fail("y0_m = " + std::to_string(y0_m) + ". Violated constraint: finite");
  if (cols < 2 || rows < 2) {
    fail("grid of " + std::to_string(cols) + " x " + std::to_string(rows) +
         " nodes. Violated constraint: at least 2 x 2 nodes");
  }
}

std::string seabed_grid_problem(const GridGeometry& g, const std::vector<float>& heights_m) {
  // The surface needs at least one cell whose 4 nodes are valid.
  for (std::size_t r = 0; r + 1 < g.rows; ++r) {
    const float* a = heights_m.data() + r * g.cols;
    const float* b = a + g.cols;
    for (std::size_t c = 0; c + 1 < g.cols; ++c) {
      if (a[c] == a[c] && a[c + 1] == a[c + 1] && b[c] == b[c] && b[c + 1] == b[c + 1]) return "";
    }
  }
  const auto valid = static_cast<std::size_t>(
      std::count_if(heights_m.begin(), heights_m.end(), [](float z) { return z == z; }));
  if (valid == 0) return "every node is nodata (no valid height in the grid)";
  return std::to_string(valid) + " valid nodes but no 2 x 2 block of valid nodes (no seabed cell)";
}

std::string seabed_above_sea_level_problem(double lo_m, double hi_m) {
  if (!(lo_m > 0.0)) return "";
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "the seabed is above sea level everywhere (heights %.4g .. %.4g m)", lo_m, hi_m);
  return std::string(buf) +
         ". Violated constraint: bathymetry heights < 0 somewhere (the sea surface is height 0, "
         "heights are elevations, up positive)";
}

Eigen::Vector3d HeightSample::normal() const {
  return Eigen::Vector3d(-dzdx, -dzdy, 1.0).normalized();
}

HeightGrid::HeightGrid(GridGeometry geometry, std::vector<float> heights_m)
    : geometry_(geometry), heights_(std::move(heights_m)) {
  geometry_.validate("height grid");
  if (heights_.size() != geometry_.size()) {
    throw InputError("height grid: " + std::to_string(heights_.size()) + " heights for " +
                     std::to_string(geometry_.size()) + " nodes");
  }
}

HeightSample HeightGrid::sample(double x_m, double y_m) const {
  const GridGeometry& g = geometry_;
  const double fc = g.col_of_x(x_m);
  const double fr = g.row_of_y(y_m);
  const double max_c = static_cast<double>(g.cols - 1);
  const double max_r = static_cast<double>(g.rows - 1);
  if (!(fc >= 0.0 && fr >= 0.0 && fc <= max_c && fr <= max_r)) return {kNaN, kNaN, kNaN};
  if (interpolation_ == Interpolation::kBicubic) return sample_bicubic(fc, fr);
  const double c0 = std::min(std::floor(fc), max_c - 1.0);
  const double r0 = std::min(std::floor(fr), max_r - 1.0);
  const double u = fc - c0;
  const double v = fr - r0;
  const std::size_t i = static_cast<std::size_t>(r0) * g.cols + static_cast<std::size_t>(c0);
  const double z00 = heights_[i];
  const double z10 = heights_[i + 1];
  const double z01 = heights_[i + g.cols];
  const double z11 = heights_[i + g.cols + 1];
  const double a = z10 - z00;                        // d/du along the row
  const double b = z01 - z00;                        // d/dv
  const double c = z11 - z10 - z01 + z00;            // twist
  const double z = z00 + a * u + b * v + c * u * v;  // NaN if any node is a hole
  return {z, (a + c * v) / g.dx_m, (b + c * u) / g.dy_m};
}

// (fc, fr) inside the node area, checked by sample().
HeightSample HeightGrid::sample_bicubic(double fc, double fr) const {
  const GridGeometry& g = geometry_;
  const double max_c = static_cast<double>(g.cols - 1);
  const double max_r = static_cast<double>(g.rows - 1);
  const double c0 = std::min(std::floor(fc), max_c - 1.0);
  const double r0 = std::min(std::floor(fr), max_r - 1.0);
  const auto ic = static_cast<std::ptrdiff_t>(c0), ir = static_cast<std::ptrdiff_t>(r0);
  const auto cols = static_cast<std::ptrdiff_t>(g.cols), rows = static_cast<std::ptrdiff_t>(g.rows);
  // The 4 x 4 nodes around the cell, f[row][col], rows/cols -1..2 relative to (ic, ir).
  double f[4][4] = {};
  bool has_c[4], has_r[4];
  for (int k = 0; k < 4; ++k) {
    has_c[k] = ic - 1 + k >= 0 && ic - 1 + k < cols;
    has_r[k] = ir - 1 + k >= 0 && ir - 1 + k < rows;
  }
  for (int j = 0; j < 4; ++j) {
    if (!has_r[j]) continue;
    const float* row = heights_.data() + (ir - 1 + j) * cols;
    for (int k = 0; k < 4; ++k) {
      if (has_c[k]) f[j][k] = row[ic - 1 + k];
    }
    extend(f[j], 1, has_c);
  }
  for (int k = 0; k < 4; ++k) extend(&f[0][k], 4, has_r);
  bool finite = true;
  for (int j = 0; j < 4; ++j) {
    for (int k = 0; k < 4; ++k) finite = finite && f[j][k] == f[j][k];
  }
  if (!finite) {
    // A hole among the 16 nodes: this cell is bilinear (NaN if one of its corners is a hole).
    const double u = fc - c0, v = fr - r0;
    const double a = f[1][2] - f[1][1], b = f[2][1] - f[1][1];
    const double c = f[2][2] - f[1][2] - f[2][1] + f[1][1];
    return {f[1][1] + a * u + b * v + c * u * v, (a + c * v) / g.dx_m, (b + c * u) / g.dy_m};
  }
  double wu[4], dwu[4], wv[4], dwv[4];
  catmull_rom(fc - c0, wu, dwu);
  catmull_rom(fr - r0, wv, dwv);
  double z = 0.0, dzdu = 0.0, dzdv = 0.0;
  for (int j = 0; j < 4; ++j) {
    double row = 0.0, drow = 0.0;
    for (int k = 0; k < 4; ++k) {
      row += wu[k] * f[j][k];
      drow += dwu[k] * f[j][k];
    }
    z += wv[j] * row;
    dzdu += wv[j] * drow;
    dzdv += dwv[j] * row;
  }
  return {z, dzdu / g.dx_m, dzdv / g.dy_m};
}

double HeightGrid::height_m(double x_m, double y_m) const {
  return sample(x_m, y_m).z_m;
}

void HeightGrid::profile(const Eigen::Vector2d& start_m, const Eigen::Vector2d& dir,
                         double length_m, int subdivisions, std::vector<ProfilePoint>& out) const {
  out.clear();
  if (!(length_m >= 0.0)) return;
  subdivisions = std::max(subdivisions, 1);
  const GridGeometry& g = geometry_;
  // Grid-line crossings along columns and rows, each already sorted by s; merge them.
  thread_local std::vector<double> sx, sy, s;
  sx.clear();
  sy.clear();
  s.clear();
  append_crossings(g.col_of_x(start_m.x()), dir.x() / g.dx_m, length_m, 0.0,
                   static_cast<double>(g.cols) - 1.0, sx);
  append_crossings(g.row_of_y(start_m.y()), dir.y() / g.dy_m, length_m, 0.0,
                   static_cast<double>(g.rows) - 1.0, sy);
  s.reserve(sx.size() + sy.size() + 2);
  s.push_back(0.0);
  std::merge(sx.begin(), sx.end(), sy.begin(), sy.end(), std::back_inserter(s));
  s.push_back(length_m);
  // Bicubic: segments of at most 1 / per_cell of a cell along the grid axis the line runs
  // closest to (index units per metre: idx_per_m); at most per_cell per crossing.
  const bool cubic = interpolation_ == Interpolation::kBicubic;
  const int per_cell = cubic ? std::max(subdivisions, kBicubicSegmentsPerCell) : subdivisions;
  const double idx_per_m = std::max(std::abs(dir.x() / g.dx_m), std::abs(dir.y() / g.dy_m));
  const auto segments = [&](double len) {
    if (!cubic) return subdivisions;
    const double n = std::ceil(len * idx_per_m * per_cell - 1e-9);
    return n >= per_cell ? per_cell : std::max(1, static_cast<int>(n));
  };
  out.reserve(s.size() * static_cast<std::size_t>(per_cell));
  const double min_gap = 1e-9 * std::max(1.0, length_m);
  double last = -1.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const int n = k > 0 ? segments(s[k] - s[k - 1]) : 1;
    if (n > 1) {
      const double h = (s[k] - s[k - 1]) / n;
      for (int m = 1; m < n; ++m) {
        const double sm = s[k - 1] + m * h;
        if (sm - last > min_gap) {
          const Eigen::Vector2d p = start_m + sm * dir;
          out.push_back({sm, height_m(p.x(), p.y())});
          last = sm;
        }
      }
    }
    if (s[k] - last > min_gap || k == 0) {
      const Eigen::Vector2d p = start_m + s[k] * dir;
      out.push_back({s[k], height_m(p.x(), p.y())});
      last = s[k];
    }
  }
}

Eigen::Vector4d HeightGrid::bounds() const {
  const GridGeometry& g = geometry_;
  const double xa = g.x0_m, xb = g.x_of_col(static_cast<double>(g.cols - 1));
  const double ya = g.y0_m, yb = g.y_of_row(static_cast<double>(g.rows - 1));
  return {std::min(xa, xb), std::min(ya, yb), std::max(xa, xb), std::max(ya, yb)};
}

std::pair<double, double> HeightGrid::height_range() const {
  float lo = std::numeric_limits<float>::infinity();
  float hi = -lo;
  for (float z : heights_) {
    if (z == z) {
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  }
  if (lo > hi) return {kNaN, kNaN};
  return {lo, hi};
}

std::size_t HeightGrid::count_valid() const {
  return static_cast<std::size_t>(
      std::count_if(heights_.begin(), heights_.end(), [](float z) { return z == z; }));
}

GridGeometry refined_geometry(const GridGeometry& g, double cell_m) {
  if (!(std::isfinite(cell_m) && cell_m > 0.0)) {
    throw InputError("refined grid: cell_m = " + std::to_string(cell_m) +
                     ". Violated constraint: cell_m > 0");
  }
  const auto nodes = [cell_m](double cell, std::size_t n) {
    const double k = std::floor(static_cast<double>(n - 1) * std::abs(cell) / cell_m + 1e-9) + 1;
    if (!(k <= 1e9)) {
      throw InputError("refined grid: cell_m = " + std::to_string(cell_m) +
                       " m gives more than 1e9 nodes along an axis");
    }
    return static_cast<std::size_t>(k);
  };
  GridGeometry r = g;
  r.dx_m = cell_m;
  r.dy_m = std::copysign(cell_m, g.dy_m);
  r.cols = nodes(g.dx_m, g.cols);
  r.rows = nodes(g.dy_m, g.rows);
  return r;
}

HeightGrid resample(const HeightGrid& grid, const GridGeometry& target, unsigned num_threads) {
  target.validate("resampled grid");
  std::vector<float> z(target.size());
  // Blocks of rows handed out in turn; each node depends on its position only.
  constexpr std::size_t kBlock = 16;
  std::atomic<std::size_t> next{0};
  detail::WorkerPool pool(detail::worker_thread_count(num_threads), [&](unsigned) {
    for (std::size_t r0 = next.fetch_add(kBlock); r0 < target.rows; r0 = next.fetch_add(kBlock)) {
      for (std::size_t r = r0; r < std::min(target.rows, r0 + kBlock); ++r) {
        const double y = target.y_of_row(static_cast<double>(r));
        float* out = z.data() + r * target.cols;
        for (std::size_t c = 0; c < target.cols; ++c) {
          out[c] = static_cast<float>(grid.height_m(target.x_of_col(static_cast<double>(c)), y));
        }
      }
    }
  });
  pool.start();
  pool.finish();
  return HeightGrid(target, std::move(z));
}

}  // namespace sonarsynth
