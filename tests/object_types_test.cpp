// SPDX-License-Identifier: MIT
// The object table (include/sonarsynth/object_types.hpp) is the vocabulary of scene files,
// dataset specs and add_scene_object (Python's add_object): each of its types is accepted by all
// of them as the table describes it, and a value outside a parameter's bounds gets the same
// "Violated constraint" text from each, naming its own file, key path and value.
#include "sonarsynth/object_types.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "error_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/config/scene_objects.hpp"

namespace sonarsynth {
namespace {

using test::error_of;

const std::string kBase = R"(name: vocabulary
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [80, 80], cell_m: 1, depth_m: 15}
)";

Scene scene_with(const std::string& entry) {
  return load_scene_from_string(kBase + "objects:\n  - " + entry + "\n", "scene.yaml",
                                SONARSYNTH_SAMPLES_DIR);
}

// A spec that draws one object of `type`, its keys given as `keys` (a flow map body).
std::string spec_with(const std::string& type, const std::string& keys) {
  return R"(name: vocabulary
seed: 3
count: 2
location: {lat_deg: 43.0, lon_deg: 5.0}
seabed: {depth_m: 12, cell_m: 0.5}
objects:
  count: 1
  across_track_m: [2, 6]
  types:
    )" + type +
         ": {" + keys + R"(}
survey: {line_length_m: 6, altitude_m: 4, speed_m_s: 3}
sonar: {preset: seascan-hds-600, range_m: 10, samples: 200}
)";
}

std::string constraint_of(const std::string& message) {
  const auto at = message.find("Violated constraint: ");
  return at == std::string::npos ? "" : message.substr(at + 21);
}

TEST(ObjectTypes, NamesAreUniqueAndFound) {
  std::set<std::string_view> names;
  for (const ObjectType& t : object_types()) {
    EXPECT_TRUE(names.insert(t.name).second) << t.name;
    EXPECT_EQ(find_object_type(t.name), &t);
    EXPECT_TRUE(t.takes("type") && t.takes("position")) << t.name;
    for (const ObjectParam& p : t.params) {
      EXPECT_TRUE(t.takes(p.key) || !t.part_keys.empty()) << t.name << "." << p.key;
      EXPECT_LT(p.lo, p.hi);
    }
    for (const ObjectSpecKey& k : t.spec_keys) {
      const ObjectParam* p = t.param(k.param);
      ASSERT_NE(p, nullptr) << t.name << "." << k.key;
      EXPECT_TRUE(p->accepts(k.spec_default)) << t.name << "." << k.key;
    }
  }
  EXPECT_EQ(find_object_type("cone"), nullptr);
  EXPECT_EQ(object_type_names(), "pipe, cylinder, box, rock, wreck, moored, mesh");
  EXPECT_EQ(object_type_names(true), "pipe, box, rock, moored, mesh");
}

TEST(ObjectTypes, ShapeNamesFromTheTable) {
  EXPECT_STREQ(to_string(ObjectShape::kCylinder), "cylinder");
  EXPECT_STREQ(to_string(ObjectShape::kBox), "box");
  EXPECT_STREQ(to_string(ObjectShape::kEllipsoid), "ellipsoid");
  EXPECT_STREQ(to_string(ObjectShape::kMesh), "mesh");
}

TEST(ObjectTypes, EveryTypeIsAcceptedByTheSceneFileAndAddSceneObject) {
  for (const ObjectType& t : object_types()) {
    SCOPED_TRACE(std::string(t.name));
    const Scene s = scene_with(std::string(t.example));
    ASSERT_EQ(s.object_records.size(), 1u);
    EXPECT_EQ(s.object_records[0].type, t.name);
    ASSERT_FALSE(s.objects.primitives().empty());
    for (const ObjectPrimitive& p : s.objects.primitives()) EXPECT_EQ(p.shape, t.shape);
    // The same entry added to a scene built without it: the same primitives.
    Scene built = load_scene_from_string(kBase, "scene.yaml", SONARSYNTH_SAMPLES_DIR);
    add_scene_object(built, yaml::Fields(YAML::Load(std::string(t.example)), "p", "add_object"),
                     SONARSYNTH_SAMPLES_DIR);
    ASSERT_EQ(built.objects.primitives().size(), s.objects.primitives().size());
    for (std::size_t i = 0; i < s.objects.primitives().size(); ++i) {
      EXPECT_EQ(built.objects.primitives()[i].half_extent_m,
                s.objects.primitives()[i].half_extent_m);
      EXPECT_EQ(built.objects.primitives()[i].base_z_m, s.objects.primitives()[i].base_z_m);
    }
  }
}

TEST(ObjectTypes, EveryDatasetTypeIsAcceptedWithItsDefaultsAndItsItemsLoad) {
  int drawn = 0;
  for (const ObjectType& t : object_types()) {
    if (!t.in_dataset_spec()) continue;
    SCOPED_TRACE(std::string(t.name));
    // Every key at its table default, written out; the mesh names a shipped model.
    std::string keys = t.shape == ObjectShape::kMesh ? "models: mine" : "";
    for (const ObjectSpecKey& k : t.spec_keys) {
      keys +=
          (keys.empty() ? "" : ", ") + std::string(k.key) + ": " + std::to_string(k.spec_default);
    }
    const DatasetSpec spec =
        load_dataset_spec_from_string(spec_with(std::string(t.name), keys), "spec.yaml");
    ASSERT_EQ(spec.object_types.size(), 1u);
    const DatasetItemScene item = dataset_item_scene(spec, 0);
    EXPECT_EQ(item.object_counts.at(std::string(t.name)), 1);
    const Scene s = load_scene_from_string(item.yaml, "item.yaml", ".");
    ASSERT_EQ(s.object_records.size(), 1u);
    EXPECT_EQ(s.object_records[0].type, t.name);
    // The item holds each drawn key at the default (a fixed range draws its one value).
    for (const ObjectSpecKey& k : t.spec_keys) {
      EXPECT_DOUBLE_EQ(item.drawn_numbers.at("objects[0]." + std::string(k.key)), k.spec_default)
          << k.key;
    }
    // Left out, each key takes the same default: the same item.
    const std::string bare = t.shape == ObjectShape::kMesh ? "models: mine" : "";
    EXPECT_EQ(
        dataset_item_scene(
            load_dataset_spec_from_string(spec_with(std::string(t.name), bare), "spec.yaml"), 0)
            .yaml,
        item.yaml);
    ++drawn;
  }
  EXPECT_EQ(drawn, 5);
}

// A bad value of a parameter a scene file and a dataset spec both name: the same constraint
// text, from the table, from the scene file, the spec and add_scene_object, each naming its
// own file, key path and value.
TEST(ObjectTypes, ABadParameterGetsTheSameMessageFromEveryFrontEnd) {
  struct Case {
    const char* type;
    const char* key;
    const char* entry;  // the scene entry, the bad value last
    const char* value;
  };
  const Case cases[] = {
      {"rock", "diameter_m", "{type: rock, position: {east_m: 0, north_m: 0}, diameter_m: ", "-1"},
      {"rock", "diameter_m",
       "{type: rock, position: {east_m: 0, north_m: 0}, diameter_m: ", "2000"},
      {"pipe", "length_m",
       "{type: pipe, position: {east_m: 0, north_m: 0}, diameter_m: 1, "
       "length_m: ",
       "0"},
      {"moored", "height_m",
       "{type: moored, position: {east_m: 0, north_m: 0}, diameter_m: 1, "
       "height_m: ",
       "20000"},
      {"mesh", "scale",
       "{type: mesh, file: models/mine.obj, position: {east_m: 0, north_m: 0}, "
       "scale: ",
       "0"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.type) + "." + c.key + " = " + c.value);
    const std::string expected = find_object_type(c.type)->param(c.key)->constraint();
    const std::string entry = std::string(c.entry) + c.value + "}";
    const std::string in_file = error_of([&] { scene_with(entry); });
    EXPECT_EQ(in_file, "scene.yaml: objects[0]." + std::string(c.key) + " = '" + c.value +
                           "'. Violated constraint: " + expected);
    Scene scene = load_scene_from_string(kBase, "scene.yaml", SONARSYNTH_SAMPLES_DIR);
    const std::string added = error_of([&] {
      add_scene_object(scene, yaml::Fields(YAML::Load(entry), "sim", "add_object"),
                       SONARSYNTH_SAMPLES_DIR);
    });
    EXPECT_EQ(added, "sim: add_object." + std::string(c.key) + " = '" + c.value +
                         "'. Violated constraint: " + expected);
    const std::string keys = std::string(c.type) == "mesh"
                                 ? std::string("models: mine, ") + c.key + ": " + c.value
                                 : std::string(c.key) + ": " + c.value;
    const std::string in_spec =
        error_of([&] { load_dataset_spec_from_string(spec_with(c.type, keys), "spec.yaml"); });
    // The spec's range of a scale is drawn, not written [x, y, z]: the bound without the form.
    const std::string bound = find_object_type(c.type)->param(c.key)->constraint(c.key);
    EXPECT_EQ(constraint_of(in_spec), bound) << in_spec;
    EXPECT_EQ(bound, expected.substr(0, bound.size()));
    EXPECT_NE(in_spec.find("spec.yaml: objects.types." + std::string(c.type) + "." + c.key +
                           " = '" + c.value + "'"),
              std::string::npos)
        << in_spec;
  }
}

// A box's size: the spec names its parts, the scene file the list; one bound.
TEST(ObjectTypes, BoxSizePartsShareTheSceneBound) {
  const ObjectParam& size = *find_object_type("box")->param("size_m");
  const std::string in_file = error_of(
      [&] { scene_with("{type: box, position: {east_m: 0, north_m: 0}, size_m: [1, 1001, 1]}"); });
  EXPECT_EQ(constraint_of(in_file), size.constraint());
  const std::string in_spec = error_of(
      [&] { load_dataset_spec_from_string(spec_with("box", "width_m: 1001"), "spec.yaml"); });
  EXPECT_EQ(constraint_of(in_spec), size.constraint("width_m"));
  EXPECT_EQ(size.constraint("width_m"), "width_m > 0 and <= 1000");
}

}  // namespace
}  // namespace sonarsynth
