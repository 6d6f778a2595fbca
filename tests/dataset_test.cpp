// SPDX-License-Identifier: MIT
// The dataset generator (docs/dataset.md): spec validation, items as pure functions of (spec,
// seed, index), atomic and resumable items, shards that partition the items, failures recorded
// with their index and seed.
#include "sonarsynth/formats/dataset.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_test_util.hpp"
#include "dataset_test_spec.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/scene_file.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using test::read_text;
using test::ScratchDirTest;
using test::snapshot;
using test::tiny_spec;

DatasetSpec tiny(int count, const std::string& extra = "") {
  return load_dataset_spec_from_string(tiny_spec(count, extra), "tiny.yaml");
}

// The InputError message of loading `text`, or "" if it loads.
std::string spec_error(const std::string& text) {
  try {
    load_dataset_spec_from_string(text, "bad.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(DatasetSpec, ErrorsNameTheFileTheFieldAndTheValue) {
  const std::string good = tiny_spec(3);
  ASSERT_EQ(spec_error(good), "");
  struct Case {
    std::string from, to;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"count: 3", "count: 0", {"bad.yaml", "count = '0'", "count >= 1"}},
      {"seed: 99", "seed: -4", {"bad.yaml", "seed = '-4'"}},
      {"material: {sand: 2, mud: 1}",
       "material: {sand: 2, lava: 1}",
       {"bad.yaml", "seabed.material", "'lava'", "mud"}},
      {"preset: seascan-hds-600", "preset: klein", {"sonar.preset", "'klein'", "klein-3900-445"}},
      {"count: [1, 3]", "count: [3, 1]", {"objects.count", "lo <= hi"}},
      {"count: [1, 3]", "count: [1, 2.5]", {"objects.count", "integers"}},
      {"burial: [0, 0.3]", "burial: [0, 1.5]", {"objects.burial", "1.5", "<= 0.99"}},
      {"depth_m: [10, 14]", "depth_m: [4, 14]", {"seabed.depth_m = '4'", "survey.altitude_m"}},
      {"height_m: [2, 3]", "height_m: [0.3, 3]", {"objects.types.moored.height_m"}},
      {"model: speckle", "model: gaussian", {"noise.model", "'gaussian'", "speckle"}},
      {"quality: fast", "quality: turbo", {"run.quality", "turbo"}},
      {"seabed:", "seabeds:", {"bad.yaml", "seabeds"}},
      {"line_length_m: 6", "line_length_m: -6", {"survey.line_length_m", "-6"}},
      {"speed_m_s: 3", "speed_m_s: [1, 2, 3]", {"survey.speed_m_s", "[lo, hi]"}},
      {"rock: {weight: 2,", "rock: {weight: 0,", {"objects.types.rock.weight", "0"}},
  };
  for (const Case& c : cases) {
    const std::string msg = spec_error(replaced(good, c.from, c.to));
    ASSERT_FALSE(msg.empty()) << c.to;
    for (const std::string& e : c.expected) {
      EXPECT_NE(msg.find(e), std::string::npos) << c.to << " -> " << msg << " (wanted " << e << ")";
    }
  }
  EXPECT_NE(spec_error("name: x\ncount: 2\n").find("seed"), std::string::npos);
  EXPECT_NE(spec_error("seed: 1\ncount: 2\nobjects: {count: 2}\n").find("objects.types"),
            std::string::npos);
}

// The bundled dataset specs (samples/datasets/) load, and their items are valid scene files.
TEST(DatasetSpec, BundledSpecsLoad) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(SONARSYNTH_SAMPLES_DIR) / "datasets")) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    const DatasetSpec s = load_dataset_spec(e.path().string());
    SceneLoadOptions lo;
    lo.num_threads = 1;
    EXPECT_NO_THROW(load_scene_from_string(dataset_item_scene(s, 0).yaml, "item.yaml", ".", lo));
    ++n;
  }
  EXPECT_GE(n, 1u);
}

TEST(DatasetSpec, ParseShard) {
  EXPECT_EQ(parse_shard("0/1", "--shard"), (std::pair<std::size_t, std::size_t>{0, 1}));
  EXPECT_EQ(parse_shard("2/3", "--shard"), (std::pair<std::size_t, std::size_t>{2, 3}));
  for (const std::string bad : {"3/3", "1/0", "-1/2", "a/b", "1", "1/", "/2", "1/2/3"}) {
    try {
      parse_shard(bad, "--shard");
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--shard = '" + bad + "'"), std::string::npos);
    }
  }
}

TEST(DatasetSpec, ItemsDependOnlyOnSeedAndIndex) {
  const DatasetSpec a = tiny(3), b = tiny(50);
  const DatasetSpec c =
      load_dataset_spec_from_string(replaced(tiny_spec(3), "seed: 99", "seed: 7"), "tiny.yaml");
  std::set<std::uint64_t> seeds;
  for (std::size_t i = 0; i < 3; ++i) {
    // The count does not enter an item: item i of a larger dataset is the same scene.
    EXPECT_EQ(dataset_item_scene(a, i).yaml, dataset_item_scene(b, i).yaml);
    EXPECT_EQ(dataset_item_seed(a, i), dataset_item_seed(b, i));
    seeds.insert(dataset_item_seed(a, i));
    seeds.insert(dataset_item_seed(c, i));
  }
  EXPECT_EQ(seeds.size(), 6u);  // distinct across indices and spec seeds
  EXPECT_THROW(dataset_item_scene(a, 3), InputError);
}

TEST(DatasetSpec, DrawnScenesLoadAndHoldTheirObjects) {
  const DatasetSpec s = tiny(40);
  std::map<std::string, int> total;
  for (std::size_t i = 0; i < s.count; ++i) {
    const DatasetItemScene item = dataset_item_scene(s, i);
    int n = 0;
    for (const auto& [type, k] : item.object_counts) {
      n += k;
      total[type] += k;
    }
    EXPECT_GE(n, 1);
    EXPECT_LE(n, 3);
    // The scene reader accepts the drawn file: objects on the grid, depths and sizes valid.
    SceneLoadOptions lo;
    lo.num_threads = 1;
    const Scene scene = load_scene_from_string(item.yaml, "item.yaml", ".", lo);
    std::set<int> ids;
    for (const auto& p : scene.objects.primitives()) ids.insert(static_cast<int>(p.id));
    EXPECT_EQ(static_cast<int>(ids.size()), n) << item.yaml;
  }
  // Every type with a weight is drawn in 40 scenes of 1-3 objects.
  for (const std::string t : {"rock", "box", "pipe", "moored"}) EXPECT_GT(total[t], 0) << t;
}

class DatasetRun : public ScratchDirTest {};

TEST_F(DatasetRun, ItemAloneEqualsItemInAFullRunAndRepeats) {
  const DatasetSpec s = tiny(3);
  const DatasetRunResult full = run_dataset(s, dir_ / "full");
  ASSERT_EQ(full.done, 3u);
  EXPECT_EQ(full.failed, 0u);
  prepare_dataset_dir(s, dir_ / "alone");
  const DatasetItemResult r = run_dataset_item(s, dir_ / "alone", 2, 1);
  EXPECT_EQ(r.status, "done");
  EXPECT_EQ(r.seed, dataset_item_seed(s, 2));
  const auto item2 = snapshot(dir_ / "full" / dataset_item_dir(2));
  EXPECT_EQ(snapshot(dir_ / "alone" / dataset_item_dir(2)), item2);
  EXPECT_NE(snapshot(dir_ / "full" / dataset_item_dir(1)), item2);
  for (const std::string f : {"L1.xtf", "L1_truth.tif", "L1_waterfall.png", "effective.yaml",
                              "scene.yaml", "item.json"}) {
    EXPECT_EQ(item2.count(f), 1u) << f;
  }
  // The same item again, with another thread count, into a third directory: the same bytes.
  prepare_dataset_dir(s, dir_ / "again");
  run_dataset_item(s, dir_ / "again", 2, 3);
  EXPECT_EQ(snapshot(dir_ / "again" / dataset_item_dir(2)), item2);
  // Nothing is left in the staging area.
  EXPECT_TRUE(fs::is_empty(dir_ / "full" / ".work"));
  // The manifest: one line per item, in order, with what item.json says.
  std::istringstream m(read_text(dir_ / "full" / "manifest.jsonl"));
  std::string line;
  std::size_t i = 0;
  for (; std::getline(m, line); ++i) {
    const auto j = nlohmann::json::parse(line);
    EXPECT_EQ(j["index"].get<std::size_t>(), i);
    EXPECT_EQ(j["seed"].get<std::uint64_t>(), dataset_item_seed(s, i));
    EXPECT_EQ(j["status"], "done");
    EXPECT_EQ(j,
              nlohmann::json::parse(read_text(dir_ / "full" / dataset_item_dir(i) / "item.json")));
    for (const auto& f : j["files"]) EXPECT_TRUE(fs::exists(dir_ / "full" / f.get<std::string>()));
    EXPECT_GT(j["pings"].get<int>(), 0);
  }
  EXPECT_EQ(i, 3u);
  const auto summary = nlohmann::json::parse(read_text(dir_ / "full" / "summary.json"));
  EXPECT_EQ(summary["done"], 3);
  EXPECT_EQ(summary["pending"], 0);
}

TEST_F(DatasetRun, ShardsPartitionTheItemsAndARerunResumes) {
  const DatasetSpec s = tiny(5);
  // A crashed attempt leaves a staging directory behind; it is not an item.
  fs::create_directories(dir_ / "d" / ".work" / "000001.deadhost.1");
  std::vector<std::set<std::size_t>> shards(3);
  for (std::size_t k = 0; k < 3; ++k) {
    DatasetRunOptions o;
    o.shard_index = k;
    o.shard_count = 3;
    o.threads = 1;
    for (const auto& r : run_dataset(s, dir_ / "d", o).items) {
      EXPECT_EQ(r.status, "done");
      EXPECT_EQ(r.index % 3, k);
      shards[k].insert(r.index);
    }
  }
  std::set<std::size_t> all;
  for (const auto& sh : shards) {
    for (std::size_t i : sh) EXPECT_TRUE(all.insert(i).second) << i << " in two shards";
  }
  EXPECT_EQ(all, (std::set<std::size_t>{0, 1, 2, 3, 4}));
  // A rerun of the whole dataset renders nothing and changes nothing.
  const auto before = snapshot(dir_ / "d" / "items");
  const DatasetRunResult again = run_dataset(s, dir_ / "d");
  EXPECT_EQ(again.skipped, 5u);
  EXPECT_EQ(again.done, 0u);
  EXPECT_EQ(snapshot(dir_ / "d" / "items"), before);
  // Sharded then whole equals whole at once (manifest and summary included).
  run_dataset(s, dir_ / "whole");
  const auto a = snapshot(dir_ / "d"), b = snapshot(dir_ / "whole");
  for (const std::string f : {"manifest.jsonl", "summary.json", "spec.yaml"}) {
    EXPECT_EQ(a.at(f), b.at(f)) << f;
  }
  // An item removed is rendered again on the next run, identical.
  const auto item3 = snapshot(dir_ / "d" / dataset_item_dir(3));
  fs::remove_all(dir_ / "d" / dataset_item_dir(3));
  const DatasetRunResult resumed = run_dataset(s, dir_ / "d");
  EXPECT_EQ(resumed.done, 1u);
  EXPECT_EQ(resumed.skipped, 4u);
  EXPECT_EQ(snapshot(dir_ / "d" / dataset_item_dir(3)), item3);
}

TEST_F(DatasetRun, AnotherSpecInTheSameDirectoryIsRefused) {
  prepare_dataset_dir(tiny(2), dir_ / "d");
  try {
    prepare_dataset_dir(tiny(3), dir_ / "d");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another spec"), std::string::npos) << e.what();
  }
}

TEST_F(DatasetRun, FailedItemsAreRecordedWithIndexAndSeed) {
  // 9000 samples: refused by the scene reader (more than XTF readers accept), in every item. (A
  // spec file asking for them is refused when loaded; a spec changed in code is not checked.)
  DatasetSpec s = tiny(2);
  s.samples = 9000;
  const std::string seed1 = std::to_string(dataset_item_seed(s, 1));
  prepare_dataset_dir(s, dir_ / "d");
  try {
    run_dataset_item(s, dir_ / "d", 1);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("item 1 (seed " + seed1 + ")"), std::string::npos) << msg;
    EXPECT_NE(msg.find("8192"), std::string::npos) << msg;
  }
  const DatasetRunResult r = run_dataset(s, dir_ / "d");
  EXPECT_EQ(r.failed, 2u);
  EXPECT_FALSE(fs::exists(dir_ / "d" / dataset_item_dir(1)));
  std::istringstream m(read_text(dir_ / "d" / "manifest.jsonl"));
  std::string line;
  std::getline(m, line);
  std::getline(m, line);
  const auto j = nlohmann::json::parse(line);
  EXPECT_EQ(j["index"], 1);
  EXPECT_EQ(std::to_string(j["seed"].get<std::uint64_t>()), seed1);
  EXPECT_EQ(j["status"], "failed");
  EXPECT_NE(j["error"].get<std::string>().find("8192"), std::string::npos);
  const auto summary = nlohmann::json::parse(read_text(dir_ / "d" / "summary.json"));
  EXPECT_EQ(summary["failed"], 2);
  EXPECT_EQ(summary["failures"][1]["index"], 1);
}

TEST_F(DatasetRun, CommandLine) {
  const fs::path spec = write("spec.yaml", tiny_spec(2));
  const auto r = test::run_cli(
      "dataset " + spec.string() + " -o " + (dir_ / "d").string() + " --shard 1/2 --threads 1",
      dir_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "d" / dataset_item_dir(1) / "item.json"));
  EXPECT_FALSE(fs::exists(dir_ / "d" / dataset_item_dir(0)));
  EXPECT_NE(read_text(dir_ / "d" / "manifest.jsonl").find("\"status\":\"pending\""),
            std::string::npos);
  const fs::path bad = write("bad.yaml", replaced(tiny_spec(2), "count: 2", "count: -2"));
  const auto e = test::run_cli("dataset " + bad.string() + " -o " + (dir_ / "e").string(), dir_);
  EXPECT_NE(e.exit_code, 0);
  EXPECT_NE(e.err.find("bad.yaml: count = '-2'"), std::string::npos) << e.err;
  const auto s = test::run_cli(
      "dataset " + spec.string() + " -o " + (dir_ / "d").string() + " --shard 2/2", dir_);
  EXPECT_NE(s.exit_code, 0);
  EXPECT_NE(s.err.find("--shard = '2/2'"), std::string::npos) << s.err;
}

}  // namespace
}  // namespace sonarsynth
