// SPDX-License-Identifier: MIT
// Internal to sonarsynth::formats: the `bathymetry` section of a scene file (a raster, optionally
// resampled finer with generated components added, or a generated grid). docs/scene-format.md.
#pragma once

#include <filesystem>
#include <string>

#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/scene.hpp"

namespace sonarsynth::scene_bathymetry {

/// The scene's frame and bathymetry from the document `top` (its `bathymetry` section, and
/// `seed` and `limits.max_memory_gb` at the top level); everything else of the Scene is left at
/// its default. Throws InputError naming the file, key and value.
Scene load(const yaml::Fields& top, const std::string& path, const std::filesystem::path& base_dir,
           const SceneLoadOptions& options);

}  // namespace sonarsynth::scene_bathymetry
