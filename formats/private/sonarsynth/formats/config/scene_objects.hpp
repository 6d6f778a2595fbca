// SPDX-License-Identifier: MIT
// Internal to sonarsynth::formats and the Python module: one entry of a scene file's `objects`
// list added to a scene built elsewhere, through the scene-file reader's own object table (its
// types, keys, defaults, checks and messages: docs/scene-format.md "Objects").
#pragma once

#include <filesystem>

#include "sonarsynth/formats/config/yaml_fields.hpp"
#include "sonarsynth/scene.hpp"

namespace sonarsynth {

/// Adds the object(s) of `entry` to `scene` as a scene file whose `objects` list held it after
/// the scene's objects would: a `type` (pipe, cylinder, box, rock, wreck, moored, mesh) with its
/// keys, or a vector layer (`file` without `type: mesh`). Positions {east_m, north_m} are metres
/// from the centre of the bathymetry grid, as in the file. Without an `id` an object takes the
/// one above the scene's largest id; a given id must not be taken. Relative paths are relative
/// to `base_dir`. Appends the Scene::object_records entry and rebuilds the object index. Throws
/// InputError naming entry.file(), the key path under entry.path() and the value; `scene` is
/// unchanged then.
void add_scene_object(Scene& scene, const yaml::Fields& entry,
                      const std::filesystem::path& base_dir);

}  // namespace sonarsynth
