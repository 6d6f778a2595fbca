// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/height_grid.hpp"
#include "sonarsynth/material.hpp"
#include "sonarsynth/scene_object.hpp"

namespace sonarsynth {

/// One object as the scene file declares it: what the truth target list reports besides the
/// primitives (docs/labels.md, "Target list"). The primitives of `Scene::objects` with the same
/// id make it up (a wreck's boxes share one).
struct ObjectRecord {
  std::int32_t id = 0;
  std::string name;      ///< as given; empty if none
  std::string type;      ///< the scene file's type: pipe, cylinder, box, rock, wreck, moored, mesh
  std::string material;  ///< material name
  /// The position the file gives (a pipe given by start and end: their midpoint), local frame, m.
  Eigen::Vector2d position_xy_m = Eigen::Vector2d::Zero();
  double heading_rad = 0.0;     ///< grid azimuth of the long axis, radians
  double clearance_m = 0.0;     ///< gap above the seabed (moored: of its lowest point), metres
  double embed_fraction = 0.0;  ///< fraction of the height sunk into the seabed, [0, 1)
};

/// Everything the renderer sees: bathymetry in a local frame, seabed materials and objects.
/// Built in memory (the formats layer reads files into it); the core never touches files.
struct Scene {
  explicit Scene(GeoFrame f) : frame(f) {}

  GeoFrame frame;         ///< local frame <-> geodetic
  HeightGrid bathymetry;  ///< elevations, up positive, NaN = hole
  MaterialTable materials = MaterialTable::defaults();
  MaterialMap material_map;  ///< seabed material at each point
  ObjectSet objects;         ///< analytic primitives on the seabed (index built)
  /// The objects as declared, one per id (scene files fill it; may be empty for a scene built
  /// in code, the target list then has one entry per primitive id).
  std::vector<ObjectRecord> object_records;
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
