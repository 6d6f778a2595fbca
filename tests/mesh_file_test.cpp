// SPDX-License-Identifier: MIT
// Mesh objects from files (docs/scene-format.md "mesh"): OBJ with per-face materials and STL
// read through assimp, welded, placed and mapped; bad files and keys named.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/scene.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

const std::string kFlat = R"(
bathymetry:
  generate: {centre: {lat_deg: -33.9, lon_deg: 151.3}, size_m: [100, 80], cell_m: 0.5, depth_m: 25}
objects:
)";

fs::path scratch_dir() {
  const fs::path d =
      fs::temp_directory_path() / ("sonarsynth_mesh_file_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// A unit cube [0, 1]^3 as an OBJ: the top face (z = 1) with material `top`, the rest `side`.
void write_cube_obj(const fs::path& p) {
  std::ofstream f(p);
  f << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
       "usemtl side\nf 1 4 3\nf 1 3 2\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\n"
       "f 4 1 5\nf 4 5 8\nusemtl top\nf 5 6 7\nf 5 7 8\n";
}

void write_cube_stl(const fs::path& p) {
  // The same cube, every facet with its own three vertices (STL shares none).
  const int tris[12][3] = {{1, 4, 3}, {1, 3, 2}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6},
                           {3, 4, 8}, {3, 8, 7}, {4, 1, 5}, {4, 5, 8}, {5, 6, 7}, {5, 7, 8}};
  const int v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  std::ofstream f(p);
  f << "solid cube\n";
  for (const auto& t : tris) {
    f << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const auto& q = v[t[k] - 1];
      f << "   vertex " << q[0] << " " << q[1] << " " << q[2] << "\n";
    }
    f << "  endloop\n endfacet\n";
  }
  f << "endsolid cube\n";
}

#ifndef SONARSYNTH_TEST_HAVE_ASSIMP
TEST(MeshFile, WithoutAssimpAMeshIsAClearError) {
  try {
    load_scene_from_string(
        kFlat + "  - {type: mesh, file: cube.obj, position: {east_m: 0, north_m: 0}}\n", "m.yaml",
        ".");
    ADD_FAILURE() << "accepted a mesh without assimp";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("built without assimp"), std::string::npos) << e.what();
  }
}
#else
TEST(MeshFile, ObjWithFaceMaterialsIsWeldedPlacedAndMapped) {
  const fs::path dir = scratch_dir();
  write_cube_obj(dir / "cube.obj");
  const Scene s = load_scene_from_string(
      kFlat +
          "  - {type: mesh, file: cube.obj, position: {east_m: 3, north_m: -2}, heading_deg: 90,\n"
          "     scale: [4, 2, 1.5], material: concrete, face_materials: {top: rock}}\n",
      "mesh.yaml", dir);
  ASSERT_EQ(s.objects.primitives().size(), 1u);
  const ObjectPrimitive& o = s.objects.primitives()[0];
  ASSERT_EQ(o.shape, ObjectShape::kMesh);
  ASSERT_TRUE(o.mesh);
  const TriangleMesh& m = *o.mesh;
  EXPECT_EQ(m.vertex_m.size(), 8u);  // welded across the two materials
  EXPECT_EQ(m.triangle.size(), 12u);
  std::size_t rock = 0, concrete = 0;
  for (const auto mat : m.material) {
    rock += mat == s.materials.index_of("rock");
    concrete += mat == s.materials.index_of("concrete");
  }
  EXPECT_EQ(rock, 2u);
  EXPECT_EQ(concrete, 10u);
  // Heading 90: model x (4 m) runs east, model y (2 m, to port) runs north; origin at the
  // position (grid centre + (3, -2)); lowest point on the flat seabed at -25 m.
  Eigen::Vector3d lo, hi;
  m.bounds(lo, hi);
  const Eigen::Vector4d bb = s.bathymetry.bounds();
  const Eigen::Vector2d c(0.5 * (bb[0] + bb[2]) + 3.0, 0.5 * (bb[1] + bb[3]) - 2.0);
  EXPECT_NEAR(lo.x(), c.x(), 1e-9);
  EXPECT_NEAR(hi.x(), c.x() + 4.0, 1e-9);
  EXPECT_NEAR(lo.y(), c.y(), 1e-9);
  EXPECT_NEAR(hi.y(), c.y() + 2.0, 1e-9);
  EXPECT_NEAR(lo.z(), -25.0, 1e-5);
  EXPECT_NEAR(hi.z(), -25.0 + 1.5, 1e-5);
  // The file's material by index works too.
  const Scene t = load_scene_from_string(
      kFlat +
          "  - {type: mesh, file: cube.obj, position: {east_m: 0, north_m: 0}, "
          "face_materials: {'1': rock}}\n",
      "mesh.yaml", dir);
  std::set<std::uint16_t> mats(t.objects.primitives()[0].mesh->material.begin(),
                               t.objects.primitives()[0].mesh->material.end());
  EXPECT_EQ(mats.size(), 2u);
  fs::remove_all(dir);
}

TEST(MeshFile, StlIsWelded) {
  const fs::path dir = scratch_dir();
  write_cube_stl(dir / "cube.stl");
  const Scene s = load_scene_from_string(
      kFlat + "  - {type: mesh, file: cube.stl, position: {east_m: 0, north_m: 0}}\n", "stl.yaml",
      dir);
  const TriangleMesh& m = *s.objects.primitives()[0].mesh;
  EXPECT_EQ(m.vertex_m.size(), 8u);
  EXPECT_EQ(m.triangle.size(), 12u);
  fs::remove_all(dir);
}

TEST(MeshFile, BadFilesAndKeysAreNamed) {
  const fs::path dir = scratch_dir();
  write_cube_obj(dir / "cube.obj");
  { std::ofstream(dir / "junk.obj") << "this is not a mesh\n\x01\x02\n"; }
  const auto fails = [&](const std::string& obj, const std::vector<std::string>& what) {
    try {
      load_scene_from_string(kFlat + obj, "bad.yaml", dir);
      ADD_FAILURE() << "accepted " << obj;
    } catch (const InputError& e) {
      for (const auto& w : what) {
        EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
      }
    }
  };
  const std::string at = "position: {east_m: 0, north_m: 0}";
  fails("  - {type: mesh, file: nothere.obj, " + at + "}\n",
        {"bad.yaml", "objects[0].file", "nothere.obj", "not found"});
  fails("  - {type: mesh, file: junk.obj, " + at + "}\n", {"junk.obj", "objects[0].file"});
  fails("  - {type: mesh, file: cube.obj, " + at + ", face_materials: {deck: rock}}\n",
        {"deck", "side, top"});
  fails("  - {type: mesh, file: cube.obj, " + at + ", face_materials: {top: unobtainium}}\n",
        {"unobtainium"});
  fails("  - {type: mesh, file: cube.obj, " + at + ", scale: -2}\n", {"scale", "-2"});
  fails("  - {type: mesh, file: cube.obj, " + at + ", up_axis: x}\n", {"up_axis"});
  fails("  - {type: mesh, file: cube.obj, " + at + ", scales: 2}\n", {"scales"});
  fails("  - {type: mesh, file: cube.obj, position: {east_m: 60, north_m: 0}}\n",
        {"outside the bathymetry grid", "cube.obj"});
  fs::remove_all(dir);
}

TEST(MeshFile, SampleSceneLoads) {
  const Scene s = load_scene(SONARSYNTH_SAMPLES_DIR "/mesh_wreck.yaml");
  ASSERT_EQ(s.objects.primitives().size(), 4u);
  for (const auto& o : s.objects.primitives()) {
    EXPECT_EQ(o.shape, ObjectShape::kMesh);
    EXPECT_GT(o.mesh->triangle.size(), 1000u);
  }
  // The wreck's deck is rust, its hull steel: both used.
  std::set<std::uint16_t> mats(s.objects.primitives()[0].mesh->material.begin(),
                               s.objects.primitives()[0].mesh->material.end());
  EXPECT_TRUE(mats.count(s.materials.index_of("rust")));
  EXPECT_TRUE(mats.count(s.materials.index_of("steel")));
}

#endif

}  // namespace
}  // namespace sonarsynth
