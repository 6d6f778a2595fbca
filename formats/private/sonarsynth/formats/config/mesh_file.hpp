// SPDX-License-Identifier: MIT
// Internal to sonarsynth::formats: triangle meshes read from OBJ, PLY, STL, glTF and the other
// formats assimp reads (docs/scene-format.md "mesh").
#pragma once

#include <string>
#include <vector>

#include "sonarsynth/triangle_mesh.hpp"

namespace sonarsynth::mesh_file {

/// A model as read: vertices in the file's frame (welded: equal positions are one vertex, so
/// the triangles of different materials share their edges), triangles with the file's winding,
/// `material[t]` = the file's material index of triangle t.
struct Model {
  TriangleMesh mesh;
  std::vector<std::string> material_names;  ///< by file material index
  std::size_t skipped_faces = 0;            ///< points and lines (not triangles)
};

/// True when this build reads mesh files (it was built with assimp).
bool available();

/// Reads `path`; with `y_up` the file's y axis is up (glTF), and is turned to z up. Throws
/// InputError naming the file if it is missing, unreadable, has no triangles, or this build has
/// no assimp.
Model load(const std::string& path, bool y_up);

}  // namespace sonarsynth::mesh_file
