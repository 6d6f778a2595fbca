// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/mesh_file.hpp"

#include <algorithm>
#include <filesystem>
#include <tuple>

#include "sonarsynth/error.hpp"

#ifdef SONARSYNTH_HAVE_ASSIMP
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#endif

namespace sonarsynth::mesh_file {

bool available() {
#ifdef SONARSYNTH_HAVE_ASSIMP
  return true;
#else
  return false;
#endif
}

Model load(const std::string& path, bool y_up) {
#ifndef SONARSYNTH_HAVE_ASSIMP
  (void)y_up;
  throw InputError(path +
                   ": cannot read a mesh: this sonarsynth was built without assimp (install "
                   "libassimp-dev and rebuild, docs/scene-format.md)");
#else
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path + ": mesh file not found (or not a regular file)");
  }
  Assimp::Importer importer;
  // Triangulate polygons, apply the node transforms (glTF and others place meshes by nodes).
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || scene->mNumMeshes == 0) {
    const std::string why = importer.GetErrorString();
    throw InputError(path + ": cannot read the mesh" + (why.empty() ? "" : " (" + why + ")") +
                     ". Violated constraint: a triangle mesh assimp reads (OBJ, PLY, STL, glTF)");
  }
  Model m;
  for (unsigned i = 0; i < scene->mNumMaterials; ++i) {
    m.material_names.emplace_back(scene->mMaterials[i]->GetName().C_Str());
  }
  // Every mesh's vertices, then a weld of equal positions (assimp splits a model by material
  // and duplicates vertices with different normals).
  std::vector<Eigen::Vector3d> raw;
  std::vector<std::array<std::uint32_t, 3> > tris;
  for (unsigned k = 0; k < scene->mNumMeshes; ++k) {
    const aiMesh* mesh = scene->mMeshes[k];
    const auto base = static_cast<std::uint32_t>(raw.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      const double x = p.x, y = p.y, z = p.z;
      raw.push_back(y_up ? Eigen::Vector3d(x, -z, y) : Eigen::Vector3d(x, y, z));
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) {
        ++m.skipped_faces;
        continue;
      }
      tris.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
      m.mesh.material.push_back(
          static_cast<std::uint16_t>(std::min<unsigned>(mesh->mMaterialIndex, 65535u)));
    }
  }
  if (tris.empty()) {
    throw InputError(path + ": the mesh has no triangles (" + std::to_string(m.skipped_faces) +
                     " points or lines)");
  }
  std::vector<std::uint32_t> order(raw.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto key = [&](std::uint32_t i) { return std::tie(raw[i].x(), raw[i].y(), raw[i].z()); };
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  std::vector<std::uint32_t> weld(raw.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || key(order[i]) != key(order[i - 1])) {
      m.mesh.vertex_m.push_back(raw[order[i]]);
    }
    weld[order[i]] = static_cast<std::uint32_t>(m.mesh.vertex_m.size() - 1);
  }
  for (auto& t : tris) {
    for (auto& i : t) i = weld[i];
  }
  m.mesh.triangle = std::move(tris);
  return m;
#endif
}

}  // namespace sonarsynth::mesh_file
