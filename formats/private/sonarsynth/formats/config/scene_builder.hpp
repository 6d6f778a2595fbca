// SPDX-License-Identifier: MIT
#pragma once
// Internal to the scene file reader (include/sonarsynth/formats/config/scene_file.hpp): the state
// shared while building one scene. Its objects are read in scene_file.cpp, its material polygons,
// classification raster and object layers in scene_layers.cpp.

#include <cstdint>
#include <filesystem>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/object_types.hpp"

namespace sonarsynth::scene_reader {

namespace fs = std::filesystem;
using yaml::Fields;

// State shared while building one scene.
struct Builder {
  Scene& scene;
  fs::path base_dir;
  Eigen::Vector2d centre_xy_m;  // centre of the bathymetry grid, local frame
  std::set<std::int32_t> used_ids;
  std::int32_t next_id = 1;

  // A position: {lat_deg, lon_deg} or {east_m, north_m} (metres from the grid centre, grid axes).
  Eigen::Vector2d position(const Fields& f, const std::string& key) const;

  // The entry's `material` (else `fallback`) as an index of the scene's material table.
  std::uint16_t material(const Fields& f, const char* fallback) const;

  // The entry's `id` (unique in the scene), or the next free one.
  std::int32_t take_id(const Fields& f);

  // Places `p` on the seabed (clearance above it or embedded) and adds it to the scene.
  void place(ObjectPrimitive p, const Fields& f, double clearance_m, double embed);

  // The object's entry in the target list (Scene::object_records).
  void record(const Fields& o, std::int32_t id, const std::string& type,
              const Eigen::Vector2d& xy_m, double heading_rad, double clearance_m, double embed,
              const char* default_material);

  // The keys an entry of `t` takes (include/sonarsynth/object_types.hpp).
  static std::set<std::string> keys_of(std::span<const std::string_view> keys);

  // Parameter `key` of `t`, checked against the table's bounds, with the table's message.
  static double param(const Fields& f, const ObjectType& t, const std::string& key,
                      double fallback = 0.0);

  // The half sizes of a `size_m: [length, width, height]` list.
  static Eigen::Vector3d half_size(const Fields& f, const ObjectType& t);

  // What every type reads before its own keys.
  struct Pose {
    double clearance_m, embed, heading_rad;
  };

  // One inline entry of `objects` (docs/scene-format.md "objects").
  void add_object(const Fields& o);

  // Boxes sharing one id (docs/scene-format.md "objects").
  void add_wreck(const Fields& o, const ObjectType& t, const Pose& pose);

  // A target held off the seabed by a tether (not rendered): a sphere or a level horizontal
  // cylinder whose centre is height_m above the seabed under it.
  void add_moored(const Fields& o, const ObjectType& t);

  // A triangle mesh from a file (docs/scene-format.md "mesh").
  void add_mesh(const Fields& o, const ObjectType& t, const Pose& pose);

  // Objects from a vector layer: each feature's attributes are read as the keys of an inline
  // object; a Point gives `position`, a LineString a pipe from its first to its last vertex.
  void add_object_layer(const Fields& f);

  // A polygon of material `m` in the scene's material map.
  void add_polygon_rings(const std::vector<std::vector<Eigen::Vector2d>>& rings, std::uint16_t m);

  // One entry of seabed.polygons: read from a vector file or given inline.
  void add_polygons(const Fields& f);

  // A classification raster, warped (nearest neighbour) onto the scene's UTM zone.
  void set_classification(const Fields& f);
};

}  // namespace sonarsynth::scene_reader
