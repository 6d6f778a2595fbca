// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sonarsynth/height_grid.hpp"
#include "sonarsynth/triangle_mesh.hpp"

namespace sonarsynth {

enum class ObjectShape : std::uint8_t {
  kCylinder,   ///< horizontal cylinder (pipe), axis along the body u axis
  kBox,        ///< rectangular box, edges along the body axes
  kEllipsoid,  ///< ellipsoid (rock), semi-axes along the body axes
  kMesh,       ///< triangle mesh (`mesh`); centre, heading and half sizes give its footprint box
};

const char* to_string(ObjectShape s);

/// A solid primitive on (or above) the seabed, in the local frame (GeoFrame).
///
/// Body axes: u along `heading_rad` (azimuth clockwise from grid north, i.e. direction
/// (sin h, cos h) in x-east/y-north), v to the right of u, z up. The primitive is analytic, so the
/// renderer sees it at full resolution however coarse the bathymetry grid is; only the cells
/// a ping plane crosses are ever evaluated.
struct ObjectPrimitive {
  ObjectShape shape = ObjectShape::kBox;
  std::int32_t id = 1;         ///< label in the truth products, > 0; a wreck's boxes share one id
  std::uint16_t material = 0;  ///< index into the MaterialTable
  Eigen::Vector2d centre_xy_m = Eigen::Vector2d::Zero();  ///< footprint centre, local frame
  double heading_rad = 0.0;  ///< azimuth of the body u axis from grid north, radians
  /// Half sizes along u, v and z, metres, > 0. Cylinder: (half length, radius, radius).
  Eigen::Vector3d half_extent_m = Eigen::Vector3d::Ones();
  /// Height of the body's lowest point (z, local frame) along u, sampled every base_step_m from
  /// u = -half length to u = +half length. One value = flat base. Set by place_on_seabed().
  std::vector<float> base_z_m;
  double base_step_m = 0.0;
  /// Gap between the seabed and the body, metres, >= 0 (set by place_on_seabed). A body with a
  /// gap (free span, moored target) always enters the beam plane as a closed section; one
  /// without does too unless ProfileOptions::solid_resting_objects is false.
  double clearance_m = 0.0;
  /// kMesh: the triangles, placed in the local frame (place_mesh), with their index built.
  std::shared_ptr<const TriangleMesh> mesh;

  Eigen::Vector2d axis_u() const;
  /// (u, v) body coordinates of a local point.
  Eigen::Vector2d body_from_local(const Eigen::Vector2d& xy_m) const;
  /// Height of the body's lowest point at axial position u (interpolated, clamped).
  double base_at(double u_m) const;
  /// Vertical extent of the solid at (x, y); false outside the footprint.
  bool vertical_extent(double x_m, double y_m, double& z_bottom_m, double& z_top_m) const;
  /// Interval of s where start + s * dir (dir unit) crosses the footprint; false if it misses.
  bool footprint_interval(const Eigen::Vector2d& start_m, const Eigen::Vector2d& dir, double& s0_m,
                          double& s1_m) const;
  /// Footprint bounding box (min x, min y, max x, max y), local frame.
  Eigen::Vector4d bbox() const;

  /// Rests the primitive on the seabed: cylinders drape along their axis (sampled at the grid
  /// spacing), boxes and ellipsoids take the seabed height under their centre. `clearance_m` > 0
  /// lifts the body above the seabed (a free span); `embed_fraction` in [0, 1) sinks it by that
  /// fraction of its height. Throws InputError if the seabed under the footprint is missing.
  void place_on_seabed(const HeightGrid& seabed, double clearance_m, double embed_fraction,
                       const std::string& what);
  /// Throws InputError naming the violated constraint.
  void validate(const std::string& what) const;
};

/// Where a mesh model goes. Model frame: x forward (along the heading), y to port, z up,
/// metres (right-handed, so the winding of the triangles is kept).
struct MeshPlacement {
  Eigen::Vector2d position_xy_m = Eigen::Vector2d::Zero();  ///< model origin, local frame
  double heading_rad = 0.0;                         ///< azimuth of the model x axis from grid north
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();  ///< per model axis, > 0
  double clearance_m = 0.0;     ///< gap between the seabed and the model's lowest point, >= 0
  double embed_fraction = 0.0;  ///< sinks the model by this fraction of its height, [0, 1)
};

/// The mesh object of `model` (model frame, per-triangle materials set) placed as `where` says:
/// scaled, turned to the heading, its origin at the position and its lowest point on the seabed
/// under the position (plus the clearance, minus the embedding). Builds the mesh's index.
/// Throws InputError (naming `what`) if the model is empty or bad, or the seabed under the
/// footprint is missing.
ObjectPrimitive place_mesh(TriangleMesh model, const MeshPlacement& where, const HeightGrid& seabed,
                           std::int32_t id, std::uint16_t material, const std::string& what);

/// All objects of a scene, with a bucket index so that a query along a ping's line costs the
/// buckets it crosses and the objects in them, not the number of objects in the scene.
class ObjectSet {
 public:
  void add(ObjectPrimitive p);
  /// Builds the bucket index; call after the last add().
  void build_index(double bucket_size_m = 16.0);

  const std::vector<ObjectPrimitive>& primitives() const { return primitives_; }
  bool empty() const { return primitives_.empty(); }

  /// Indices of primitives whose footprint may meet the segment start + s dir, s in [0, len].
  /// `out` is cleared first; sorted, without duplicates.
  void candidates_along(const Eigen::Vector2d& start_m, const Eigen::Vector2d& dir, double length_m,
                        std::vector<std::uint32_t>& out) const;
  /// Highest object top at (x, y) (NaN where there is none) and its id (0 if none).
  double top_at(double x_m, double y_m, std::int32_t* id = nullptr) const;

 private:
  std::vector<ObjectPrimitive> primitives_;
  // Bucket grid over the union of the footprints.
  double bucket_m_ = 16.0;
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  std::size_t bucket_cols_ = 0, bucket_rows_ = 0;
  std::vector<std::uint32_t>
      bucket_start_;  // CSR layout: bucket b holds items[start[b]..start[b+1])
  std::vector<std::uint32_t> bucket_items_;
};

}  // namespace sonarsynth
