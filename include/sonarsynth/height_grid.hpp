// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace sonarsynth {

/// Placement of a regular grid of nodes in the local frame (see GeoFrame).
/// Node (col, row) sits at x = x0_m + col * dx_m, y = y0_m + row * dy_m. dy_m is negative for
/// north-up rasters (row 0 = north edge), as GDAL stores them; no flip or copy is made.
/// Each node is the centre of a cell of size |dx| x |dy| (GDAL's AREA_OR_POINT=Area pixel).
struct GridGeometry {
  double x0_m = 0.0;   ///< x of node (0, 0), local frame, metres
  double y0_m = 0.0;   ///< y of node (0, 0), local frame, metres
  double dx_m = 1.0;   ///< node spacing along columns, metres, > 0
  double dy_m = -1.0;  ///< node spacing along rows, metres, != 0 (negative = north-up)
  std::size_t cols = 0;
  std::size_t rows = 0;

  double x_of_col(double col) const { return x0_m + col * dx_m; }
  double y_of_row(double row) const { return y0_m + row * dy_m; }
  double col_of_x(double x_m) const { return (x_m - x0_m) / dx_m; }
  double row_of_y(double y_m) const { return (y_m - y0_m) / dy_m; }
  std::size_t size() const { return cols * rows; }
  /// Throws InputError unless spacing is finite and non-zero and the grid has >= 2 x 2 nodes.
  void validate(const char* what) const;
};

/// Heights beyond the deepest ocean and the highest land, metres: a node whose |height| exceeds
/// it (+-inf, 1e38 and the like) is an undeclared nodata marker, a hole, not seabed
/// (docs/scene-format.md, "Bathymetry").
inline constexpr float kMaxAbsHeight_m = 12000.0f;
/// Whether `h` is a height (|h| <= kMaxAbsHeight_m) rather than a hole or nodata marker.
inline bool is_height(float h) {
  return std::abs(h) <= kMaxAbsHeight_m;
}

/// Why `heights_m` (row-major over `g`, NaN = hole) cannot be a seabed, or "" if it can: no valid
/// node, or no cell whose 4 nodes are valid (the surface needs one). The same rule for grids
/// read from files and built in code.
std::string seabed_grid_problem(const GridGeometry& g, const std::vector<float>& heights_m);

/// Why the valid heights `lo` .. `hi` (metres, up positive, the sea surface at 0) cannot be a
/// seabed, or "": a seabed wholly above sea level (lo > 0) has no water over it.
std::string seabed_above_sea_level_problem(double lo_m, double hi_m);

/// How a HeightGrid's surface runs between its nodes (docs/physics.md, "Seabed interpolation").
enum class Interpolation {
  /// Bilinear patches: continuous, its slope jumps at every grid line (facets show the cells).
  kBilinear,
  /// Cubic convolution with a = -0.5 (Catmull-Rom, separable over the 4 x 4 nodes around the
  /// cell): interpolates the nodes, C1 (slope continuous across grid lines), reproduces
  /// polynomials up to degree 2. Along the outer cells the missing row/column is extrapolated as
  /// 3 f0 - 3 f1 + f2 (exact for quadratics). A cell whose 4 x 4 nodes include a hole is
  /// bilinear, so holes are the same as with kBilinear.
  kBicubic,
};

/// Height, slope and validity of the surface at a point.
struct HeightSample {
  double z_m;   ///< height (elevation, up positive), metres; NaN where there is no seabed
  double dzdx;  ///< surface gradient along x (dimensionless)
  double dzdy;  ///< surface gradient along y
  bool valid() const { return z_m == z_m; }
  /// Upward unit normal (-dz/dx, -dz/dy, 1)/|.|.
  Eigen::Vector3d normal() const;
};

/// One point of a vertical profile: distance along the line and seabed height.
struct ProfilePoint {
  double s_m;  ///< distance from the line start, metres
  double z_m;  ///< seabed height, metres, NaN in a hole or outside the grid
};

/// Seabed heights on a regular grid (float32, NaN = nodata hole), in the local frame.
/// The surface between nodes is bilinear, or bicubic (set_interpolation); every query (height_m,
/// sample, profile) uses the grid's interpolation. Heights are elevations (up positive).
/// The storage is moved in, never copied: a grid of several GB costs its size once.
class HeightGrid {
 public:
  HeightGrid() = default;
  /// heights_m.size() must equal geometry.size(); row-major, row 0 first.
  HeightGrid(GridGeometry geometry, std::vector<float> heights_m);

  const GridGeometry& geometry() const { return geometry_; }
  const std::vector<float>& heights() const { return heights_; }
  std::vector<float>& mutable_heights() { return heights_; }
  float node(std::size_t col, std::size_t row) const {
    return heights_[row * geometry_.cols + col];
  }
  bool empty() const { return heights_.empty(); }
  /// Frees the heights: the grid is empty() after (its geometry stays). For the owner of a grid
  /// that nothing reads any more (run_simulation frees the scene's once the products are done
  /// with it: SurveyProductOptions::after_last_bathymetry_use).
  void release_heights() { std::vector<float>().swap(heights_); }

  Interpolation interpolation() const { return interpolation_; }
  void set_interpolation(Interpolation i) { interpolation_ = i; }

  /// Height at (x, y); NaN outside the grid or if any of the 4 nodes of its cell is a hole.
  double height_m(double x_m, double y_m) const;
  /// Height and analytic gradient of the surface at (x, y).
  HeightSample sample(double x_m, double y_m) const;

  /// Segments per cell of a bicubic profile (see profile()).
  static constexpr int kBicubicSegmentsPerCell = 8;

  /// Profile of the surface along the horizontal line start + s * dir, 0 <= s <= length.
  /// Points are placed at s = 0, s = length and at every crossing of a grid line (where the
  /// restriction of the surface is not smooth); between consecutive crossings a bilinear
  /// surface is a quadratic in s, approximated by `subdivisions` equal segments
  /// (1 = chord between crossings; error of the chord <= |d2z/ds2| h^2 / 8). A bicubic surface
  /// is a polynomial of degree up to 6 in s within a cell: each crossing is cut into segments
  /// that advance at most 1 / max(subdivisions, kBicubicSegmentsPerCell) of a cell along the
  /// grid axis the line runs closest to (docs/physics.md, "Seabed interpolation").
  /// Cost: O(cells crossed x subdivisions), x 8 at most for bicubic; independent of the grid
  /// size.
  /// `dir` must be a unit vector. `out` is cleared first (reuse it to avoid allocations).
  void profile(const Eigen::Vector2d& start_m, const Eigen::Vector2d& dir, double length_m,
               int subdivisions, std::vector<ProfilePoint>& out) const;

  /// Bounds of the node area in the local frame: (min x, min y, max x, max y).
  Eigen::Vector4d bounds() const;
  /// Centre of the node area in the local frame, metres: the origin of the scene file's
  /// positions (`east_m`/`north_m`, docs/scene-format.md "Positions").
  Eigen::Vector2d centre_xy_m() const {
    const Eigen::Vector4d b = bounds();
    return {0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])};
  }
  /// Minimum and maximum of the valid heights (NaN, NaN if there are none).
  std::pair<double, double> height_range() const;
  std::size_t count_valid() const;

 private:
  HeightSample sample_bicubic(double fc, double fr) const;

  GridGeometry geometry_;
  std::vector<float> heights_;
  Interpolation interpolation_ = Interpolation::kBilinear;
};

/// Nodes of spacing cell_m over the node area of `g`: the same first node and axis directions,
/// floor(span / cell_m + 1e-9) + 1 nodes per axis (span = (cols - 1) |dx|, likewise for rows),
/// so the last node lies within cell_m of the original last one. Throws InputError unless
/// cell_m is finite and > 0; the caller bounds the size (it is not allocated here).
GridGeometry refined_geometry(const GridGeometry& g, double cell_m);

/// `grid` evaluated (with its own interpolation) at every node of `target`, as a bilinear grid
/// (holes where `grid` has none: outside it or in its holes). Multi-threaded over rows
/// (num_threads 0 = hardware concurrency); the result does not depend on the thread count.
HeightGrid resample(const HeightGrid& grid, const GridGeometry& target, unsigned num_threads = 0);

}  // namespace sonarsynth
