// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "sonarsynth/scene.hpp"

namespace sonarsynth {

/// Options for load_scene().
struct SceneLoadOptions {
  unsigned num_threads = 0;  ///< for bathymetry generation; 0 = hardware concurrency
  /// Replaces the file's top-level `seed` (the command line's --seed): a generated bathymetry
  /// without its own `bathymetry.generate.seed` takes this one.
  std::optional<std::uint64_t> seed;
};

/// Reads a scene file (YAML, format in docs/scene-format.md) and builds the Scene: bathymetry
/// read through GDAL or generated, materials, the seabed material map (default, classification
/// raster, polygons inline or from vector files) and objects (inline or from GeoJSON/Shapefile
/// layers), every geographic position turned into the local frame with GeographicLib.
/// Relative file paths are relative to the scene file's directory. The sections `survey`,
/// `sonar`, `noise`, `render` and `output` are left to the simulator.
///
/// Throws InputError / FormatError naming the file, the key path and the bad value.
Scene load_scene(const std::string& path, const SceneLoadOptions& options = {});

/// As load_scene(), from YAML text in memory: `name` stands for the file in messages and in
/// the default scene name, relative file paths are relative to `base_dir`.
Scene load_scene_from_string(const std::string& yaml_text, const std::string& name,
                             const std::filesystem::path& base_dir,
                             const SceneLoadOptions& options = {});

}  // namespace sonarsynth
