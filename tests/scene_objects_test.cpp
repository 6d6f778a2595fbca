// SPDX-License-Identifier: MIT
// add_scene_object: an entry of a scene file's `objects` list added to a scene built elsewhere
// gives the primitives the file gives (automatic ids included), refuses what the file refuses
// with the file's message, and leaves the scene unchanged when it refuses.
#include "sonarsynth/formats/config/scene_objects.hpp"

#include <gtest/gtest.h>

#include <string>

#include "fields_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"

namespace sonarsynth {
namespace {

const std::string kBase = R"(name: objects
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [60, 60], cell_m: 1, depth_m: 15,
             components: [{type: fbm, rms_m: 0.2, wavelength_m: 8, octaves: 2}]}
)";

const char* const kEntries[] = {
    "{type: box, id: 4, position: {east_m: 3, north_m: -2}, heading_deg: 20, size_m: [2, 1, 1]}",
    "{type: rock, position: {east_m: -5, north_m: 6}, diameter_m: 1.5, embed: 0.2}",
    "{type: pipe, start: {east_m: -10, north_m: 0}, end: {east_m: 10, north_m: 4}, diameter_m: "
    "0.5}",
    "{type: wreck, position: {east_m: 0, north_m: 10}, heading_deg: 100, parts: [{size_m: [6, "
    "2, 1.5]}, {offset_m: [-1, 0], size_m: [2, 1.5, 1], lift_m: 1.5}]}",
    "{type: moored, position: {east_m: 8, north_m: 8}, shape: cylinder, length_m: 2, "
    "diameter_m: 0.6, height_m: 3}",
};

Scene with(const std::string& objects) {
  return load_scene_from_string(kBase + objects, "objects.yaml", ".");
}

void add(Scene& scene, const std::string& entry) {
  add_scene_object(scene, yaml::Fields(YAML::Load(entry), "objects.yaml", "objects[0]"), ".");
}

void expect_same_objects(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.objects.primitives().size(), b.objects.primitives().size());
  for (std::size_t i = 0; i < a.objects.primitives().size(); ++i) {
    SCOPED_TRACE("primitive " + std::to_string(i));
    using P = ObjectPrimitive;
    test::expect_equal_fields(a.objects.primitives()[i], b.objects.primitives()[i], &P::shape,
                              &P::id, &P::material, &P::centre_xy_m, &P::heading_rad,
                              &P::half_extent_m, &P::base_z_m, &P::clearance_m);
  }
  ASSERT_EQ(a.object_records.size(), b.object_records.size());
  for (std::size_t i = 0; i < a.object_records.size(); ++i) {
    SCOPED_TRACE("record " + std::to_string(i));
    test::expect_equal_fields(a.object_records[i], b.object_records[i], &ObjectRecord::id,
                              &ObjectRecord::type, &ObjectRecord::material);
  }
}

TEST(AddSceneObject, BuildsWhatTheFileBuilds) {
  std::string list = "objects:\n";
  Scene built = with("");
  for (const char* e : kEntries) {
    list += std::string("  - ") + e + "\n";
    add(built, e);
  }
  const Scene file = with(list);
  ASSERT_EQ(file.object_records.size(), 5u);
  // Ids: 4 given, then 5, 6, 7, 8 automatic, one above the largest.
  EXPECT_EQ(built.object_records.back().id, 8);
  expect_same_objects(file, built);
}

TEST(AddSceneObject, RefusesWithTheFilesMessageAndChangesNothing) {
  const char* const bad[] = {
      "{type: box, position: {east_m: 0, north_m: 0}, size_m: [0, 1, 1]}",
      "{type: pipe, position: {east_m: 0, north_m: 0}, length_m: 3, diameter_m: -1}",
      "{type: box, position: {east_m: 400, north_m: 0}, size_m: [1, 1, 1]}",
      "{type: box, id: 4, position: {east_m: 0, north_m: 0}, size_m: [1, 1, 1]}",
      "{type: wreck, position: {east_m: 0, north_m: 0}, parts: [{size_m: [2, 1, 1]}, {size_m: "
      "[0, 1, 1]}]}",
      "{type: cone}",
  };
  for (const char* e : bad) {
    // In the file, after the box with id 4.
    std::string from_file;
    try {
      with(std::string("objects:\n  - ") + kEntries[0] + "\n  - " + e + "\n");
    } catch (const InputError& x) {
      from_file = x.what();
    }
    ASSERT_FALSE(from_file.empty()) << e;
    Scene built = with("");
    add(built, kEntries[0]);
    const Scene before = built;
    try {
      add_scene_object(built, yaml::Fields(YAML::Load(e), "objects.yaml", "objects[1]"), ".");
      ADD_FAILURE() << "no error: " << e;
    } catch (const InputError& x) {
      EXPECT_EQ(std::string(x.what()), from_file);
    }
    expect_same_objects(before, built);
  }
}

}  // namespace
}  // namespace sonarsynth
