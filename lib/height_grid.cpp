// SPDX-License-Identifier: MIT
#include "sonarsynth/height_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "sonarsynth/error.hpp"

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
}  // namespace

void GridGeometry::validate(const char* what) const {
  auto fail = [&](const std::string& msg) { throw InputError(std::string(what) + ": " + msg); };
  if (!(std::isfinite(dx_m) && dx_m > 0.0)) {
    fail("cell size x = " + std::to_string(dx_m) + " m. Violated constraint: cell size > 0");
  }
  if (!(std::isfinite(dy_m) && dy_m != 0.0)) {
    fail("cell size y = " + std::to_string(dy_m) + " m. Violated constraint: cell size != 0");
  }
  if (!std::isfinite(x0_m) || !std::isfinite(y0_m)) fail("origin is not finite");
  if (cols < 2 || rows < 2) {
    fail("grid of " + std::to_string(cols) + " x " + std::to_string(rows) +
         " nodes. Violated constraint: at least 2 x 2 nodes");
  }
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
  out.reserve(s.size() * static_cast<std::size_t>(subdivisions));
  const double min_gap = 1e-9 * std::max(1.0, length_m);
  double last = -1.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (k > 0 && subdivisions > 1) {
      const double h = (s[k] - s[k - 1]) / subdivisions;
      for (int m = 1; m < subdivisions; ++m) {
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

}  // namespace sonarsynth
