// SPDX-License-Identifier: MIT
// Flat seabeds and the objects placed on them in the beam-profile and solid-object tests.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "sonarsynth/scene.hpp"

namespace sonarsynth::test {

/// A sand seabed `depth_m` deep over [-50, 50] m x [-50, 50] m, on a grid of `cell_m` cells.
inline Scene flat_scene(double cell_m, double depth_m) {
  Scene scene(GeoFrame(19, true, 500000.0, 5000000.0));
  const auto n = static_cast<std::size_t>(100.0 / cell_m) + 1;
  GridGeometry g{-50.0, 50.0, cell_m, -cell_m, n, n};
  scene.bathymetry = HeightGrid(g, std::vector<float>(g.size(), static_cast<float>(-depth_m)));
  scene.material_map = MaterialMap(scene.materials.index_of("sand"));
  return scene;
}

/// A `shape` primitive labelled `id`, of `material`, its footprint centred at `centre_xy_m`, its
/// half sizes `half_extent_m` along u, v and z, u turned `heading_rad` from grid north.
inline ObjectPrimitive primitive(ObjectShape shape, std::int32_t id, std::uint16_t material,
                                 const Eigen::Vector2d& centre_xy_m,
                                 const Eigen::Vector3d& half_extent_m, double heading_rad = 0.0) {
  return {.shape = shape,
          .id = id,
          .material = material,
          .centre_xy_m = centre_xy_m,
          .heading_rad = heading_rad,
          .half_extent_m = half_extent_m,
          .base_z_m = {},
          .mesh = nullptr};
}

/// Rests `object` on `scene`'s seabed (`clearance_m` above it, not embedded), adds it to the
/// scene's objects and rebuilds their index. `what` names the object in errors.
inline void add_on_seabed(Scene& scene, ObjectPrimitive object, const std::string& what,
                          double clearance_m = 0.0) {
  object.place_on_seabed(scene.bathymetry, clearance_m, 0.0, what);
  scene.objects.add(std::move(object));
  scene.objects.build_index();
}

}  // namespace sonarsynth::test
