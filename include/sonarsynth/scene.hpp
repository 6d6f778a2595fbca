// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/height_grid.hpp"
#include "sonarsynth/material.hpp"
#include "sonarsynth/scene_object.hpp"

namespace sonarsynth {

/// Everything the renderer sees: bathymetry in a local frame, seabed materials and objects.
/// Built in memory (the formats layer reads files into it); the core never touches files.
struct Scene {
  explicit Scene(GeoFrame f) : frame(f) {}

  GeoFrame frame;         ///< local frame <-> geodetic
  HeightGrid bathymetry;  ///< elevations, up positive, NaN = hole
  MaterialTable materials = MaterialTable::defaults();
  MaterialMap material_map;  ///< seabed material at each point
  ObjectSet objects;         ///< analytic primitives on the seabed (index built)
  std::string name;
};

/// How finely the beam-plane profile samples the scene.
struct ProfileOptions {
  /// Segments per grid-cell crossing of the bilinear seabed (HeightGrid::profile), [1, 64].
  int grid_subdivisions = 1;
  /// Segments across a curved object section (pipe, rock), [2, 256].
  int object_segments = 16;
  /// Objects resting on the seabed also enter as closed sections (as objects off it always do):
  /// their true lower boundary (docs/physics.md §2.1, §3.15). false: they enter the seabed's
  /// height profile with vertical walls at their footprint edges (the earlier heightfield).
  bool solid_resting_objects = true;
  void validate() const;
};

}  // namespace sonarsynth
