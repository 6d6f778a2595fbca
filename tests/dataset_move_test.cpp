// SPDX-License-Identifier: MIT
// A dataset directory with mesh objects can be moved: its items name the models by their copies
// in the directory, relative to the item (docs/dataset.md, "Mesh objects").
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "cli_test_util.hpp"
#include "dataset_test_spec.hpp"
#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;

class DatasetMove : public test::ScratchDirTest {};

// The `file` of every mesh object of the scene file `path`.
std::vector<std::string> mesh_files(const fs::path& path) {
  std::vector<std::string> out;
  for (const YAML::Node& o : YAML::LoadFile(path.string())["objects"]) {
    if (o["type"].as<std::string>() == "mesh") out.push_back(o["file"].as<std::string>());
  }
  return out;
}

TEST_F(DatasetMove, MeshModelsAreCopiedAndNamedRelativelySoTheDirectoryCanMove) {
  // A spec naming a model beside it, objects mostly meshes.
  fs::create_directories(dir_ / "specs" / "models");
  fs::copy_file(fs::path(SONARSYNTH_SAMPLES_DIR) / "models" / "mine.obj",
                dir_ / "specs" / "models" / "mine.obj");
  std::string text = test::tiny_spec(4);
  const std::string moored = "    moored: {diameter_m: [0.4, 0.8], height_m: [2, 3]}\n";
  text.replace(text.find(moored), moored.size(),
               "    mesh: {weight: 100, models: models/mine.obj}\n");
  const fs::path spec_path = write("specs/spec.yaml", text);
  const DatasetSpec spec = load_dataset_spec(spec_path.string());
  std::size_t index = 0;
  while (index < spec.count && dataset_item_scene(spec, index).object_counts.count("mesh") == 0) {
    ++index;
  }
  ASSERT_LT(index, spec.count);

  const fs::path dir = dir_ / "d";
  prepare_dataset_dir(spec, dir);
  ASSERT_EQ(run_dataset_item(spec, dir, index, 1).status, "done");
  const fs::path item = dir / dataset_item_dir(index);
  for (const char* name : {"scene.yaml", "effective.yaml"}) {
    const std::vector<std::string> files = mesh_files(item / name);
    ASSERT_FALSE(files.empty()) << name;
    for (const std::string& f : files) EXPECT_EQ(f, "../../models/mine.obj") << name;
  }
  EXPECT_EQ(test::read_text(dir / "models" / "mine.obj"),
            test::read_text(dir_ / "specs" / "models" / "mine.obj"));

  // Moved, and the spec's model gone: the item's scene and effective configuration still load
  // with every object, and simulating the scene again gives the item's XTF, byte for byte.
  const fs::path moved = dir_ / "elsewhere" / "moved";
  fs::create_directories(moved.parent_path());
  fs::rename(dir, moved);
  fs::remove(dir_ / "specs" / "models" / "mine.obj");
  const fs::path moved_item = moved / dataset_item_dir(index);
  const auto objects =
      static_cast<std::size_t>(dataset_item_scene(spec, index).drawn_numbers.at("objects.count"));
  for (const char* name : {"scene.yaml", "effective.yaml"}) {
    const SimulationSetup setup = load_simulation((moved_item / name).string());
    EXPECT_EQ(setup.scene.objects.primitives().size(), objects) << name;
  }
  RunOptions run;
  run.overrides.quality = spec.quality;
  run.overrides.threads = 1;
  run.products.mosaic = spec.mosaic;
  run.products.waterfalls = spec.waterfalls;
  run.products.truth = spec.truth;
  run_simulation((moved_item / "scene.yaml").string(), dir_ / "again", run);
  EXPECT_EQ(test::read_text(dir_ / "again" / "L1.xtf"), test::read_text(moved_item / "L1.xtf"));
}

}  // namespace
}  // namespace sonarsynth
