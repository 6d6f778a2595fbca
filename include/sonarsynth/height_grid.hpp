// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
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

/// Height, slope and validity of the bilinear surface at a point.
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
/// The surface between nodes is bilinear. Heights are elevations (up positive).
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

  /// Bilinear height at (x, y); NaN outside the grid or if any of the 4 nodes is a hole.
  double height_m(double x_m, double y_m) const;
  /// Height and analytic gradient of the bilinear patch containing (x, y).
  HeightSample sample(double x_m, double y_m) const;

  /// Profile of the bilinear surface along the horizontal line start + s * dir, 0 <= s <= length.
  /// Points are placed at s = 0, s = length and at every crossing of a grid line (where the
  /// restriction of the bilinear surface is not smooth); between consecutive crossings the
  /// surface is a quadratic in s, approximated by `subdivisions` equal segments
  /// (1 = chord between crossings; error of the chord <= |d2z/ds2| h^2 / 8).
  /// Cost: O(cells crossed x subdivisions); independent of the grid size.
  /// `dir` must be a unit vector. `out` is cleared first (reuse it to avoid allocations).
  void profile(const Eigen::Vector2d& start_m, const Eigen::Vector2d& dir, double length_m,
               int subdivisions, std::vector<ProfilePoint>& out) const;

  /// Bounds of the node area in the local frame: (min x, min y, max x, max y).
  Eigen::Vector4d bounds() const;
  /// Minimum and maximum of the valid heights (NaN, NaN if there are none).
  std::pair<double, double> height_range() const;
  std::size_t count_valid() const;

 private:
  GridGeometry geometry_;
  std::vector<float> heights_;
};

}  // namespace sonarsynth
