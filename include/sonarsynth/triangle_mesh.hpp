// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sonarsynth {

/// A triangle mesh object (docs/physics.md §2.1, docs/scene-format.md "mesh"): vertices in the
/// local frame (x east, y north, z up, metres), triangles as vertex indices wound
/// counter-clockwise seen from outside the solid (the right-hand normal points out), one
/// material per triangle. Indexed by a bounding-volume hierarchy over the triangles' horizontal
/// extent, so that cutting it with a vertical beam plane visits only the triangles the plane
/// crosses (and the tree nodes above them), not the whole mesh.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertex_m;
  std::vector<std::array<std::uint32_t, 3>> triangle;
  std::vector<std::uint16_t> material;  ///< per triangle: index into the MaterialTable

  /// A node of the hierarchy: its horizontal bounds; a leaf (count > 0) holds
  /// order[first .. first + count), an inner node has the children `first` and `first` + 1.
  struct Node {
    double lo_x, lo_y, hi_x, hi_y;
    std::uint32_t first, count;
  };
  std::vector<Node> nodes;
  std::vector<std::uint32_t> order;  ///< triangle indices in leaf order

  /// Builds the hierarchy; call after the last change to the triangles. Throws InputError
  /// (naming `what`) on an index out of range, a non-finite vertex or a size mismatch.
  void build_index(const std::string& what);
  /// Triangles whose horizontal bounds may meet the vertical plane through `origin_xy_m` along
  /// the unit vector `dir` (the whole plane: a section is cut where it is used); `out` is
  /// cleared first. Cost: the tree nodes whose bounds the plane crosses.
  void triangles_near_plane(const Eigen::Vector2d& origin_xy_m, const Eigen::Vector2d& dir,
                            std::vector<std::uint32_t>& out) const;
  /// Lowest and highest z of the mesh on the vertical line through (x, y); false if the line
  /// meets no triangle.
  bool vertical_extent(double x_m, double y_m, double& z_bottom_m, double& z_top_m) const;
  /// Axis-aligned bounds of the vertices (min x, y, z; max x, y, z).
  void bounds(Eigen::Vector3d& lo_m, Eigen::Vector3d& hi_m) const;
};

}  // namespace sonarsynth
