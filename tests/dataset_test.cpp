// SPDX-License-Identifier: MIT
// The dataset generator (docs/dataset.md): spec validation, items as pure functions of (spec,
// seed, index), atomic and resumable items, shards that partition the items, failures recorded
// with their index and seed.
#include "sonarsynth/formats/config/dataset.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "cli_test_util.hpp"
#include "dataset_test_spec.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/scene_file.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"

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

class DatasetRun : public ScratchDirTest {
 protected:
  /// Runs `sonarsynth dataset <spec> -o <dir_/out> <options>` in dir_.
  test::CliResult dataset_cli(const fs::path& spec, const std::string& out,
                              const std::string& options = "") {
    return test::run_cli(
        "dataset " + spec.string() + " -o " + (dir_ / out).string() + " " + options, dir_);
  }
  /// Expects item 1 of the run into dir_/out done and item 0 not started.
  void expect_item_1_only(const std::string& out) {
    EXPECT_TRUE(fs::exists(dir_ / out / dataset_item_dir(1) / "item.json"));
    EXPECT_FALSE(fs::exists(dir_ / out / dataset_item_dir(0)));
  }
};

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
    auto record =
        nlohmann::json::parse(read_text(dir_ / "full" / dataset_item_dir(i) / "item.json"));
    // The file records (sizes and SHA-256) stay in item.json; the rest is the manifest line.
    ASSERT_TRUE(record.contains("file_records"));
    record.erase("file_records");
    EXPECT_EQ(j, record);
    EXPECT_EQ(j["seed_text"], std::to_string(dataset_item_seed(s, i)));
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
    prepare_dataset_dir(
        load_dataset_spec_from_string(replaced(tiny_spec(2), "seed: 99", "seed: 98"), "b.yaml"),
        dir_ / "d");
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

  // The same failure recorded by record_dataset_failure (a runner of its own) in another
  // directory: the same record, byte for byte, and the same manifest line.
  const std::string error = j["error"].get<std::string>();
  prepare_dataset_dir(s, dir_ / "e");
  record_dataset_failure(s, dir_ / "e", 1, error);
  EXPECT_EQ(read_text(dir_ / "e" / "failed" / "000001.json"),
            read_text(dir_ / "d" / "failed" / "000001.json"));
  write_dataset_manifest(s, dir_ / "e");
  std::istringstream me(read_text(dir_ / "e" / "manifest.jsonl"));
  std::string line_e;
  std::getline(me, line_e);
  std::getline(me, line_e);
  EXPECT_EQ(line_e, line);
  EXPECT_THROW(record_dataset_failure(s, dir_ / "e", 2, error), InputError);
}

TEST_F(DatasetRun, CommandLine) {
  const fs::path spec = write("spec.yaml", tiny_spec(2));
  const auto r = dataset_cli(spec, "d", "--shard 1/2 --threads 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  expect_item_1_only("d");
  EXPECT_NE(read_text(dir_ / "d" / "manifest.jsonl").find("\"status\":\"pending\""),
            std::string::npos);
  const fs::path bad = write("bad.yaml", replaced(tiny_spec(2), "count: 2", "count: -2"));
  const auto e = dataset_cli(bad, "e");
  EXPECT_NE(e.exit_code, 0);
  EXPECT_NE(e.err.find("bad.yaml: count = '-2'"), std::string::npos) << e.err;
  const auto s = dataset_cli(spec, "d", "--shard 2/2");
  EXPECT_NE(s.exit_code, 0);
  EXPECT_NE(s.err.find("--shard = '2/2'"), std::string::npos) << s.err;
}

TEST(DatasetSpec, SplitHoldsItsFractionsInEveryPrefixOfTheItems) {
  // Independent count: for every n <= 2000 the items 0..n-1 of each split number n f +- 1.
  const std::vector<std::array<double, 3>> fractions = {
      {0.8, 0.1, 0.1}, {0.7, 0.2, 0.1}, {1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.5, 0.0},
      {0.0, 0.0, 1.0}, {0.9, 0.0, 0.1}, {0.05, 0.9, 0.05},           {0.61, 0.27, 0.12}};
  for (const auto& f : fractions) {
    std::ostringstream extra;
    extra << "run: {quality: fast, split: {train: " << std::setprecision(17) << f[0]
          << ", val: " << f[1] << ", test: " << 1.0 - f[0] - f[1] << "}}\n";
    const DatasetSpec s = load_dataset_spec_from_string(
        replaced(tiny_spec(2000), "run: {quality: fast}\n", extra.str()), "split.yaml");
    ASSERT_TRUE(s.split);
    std::array<double, 3> count = {0, 0, 0};
    for (std::size_t i = 0; i < 2000; ++i) {
      const std::string sp = dataset_item_split(s, i);
      const int k = sp == "train" ? 0 : sp == "val" ? 1 : sp == "test" ? 2 : -1;
      ASSERT_GE(k, 0) << sp;
      count[static_cast<std::size_t>(k)] += 1;
      const double n = static_cast<double>(i + 1);
      for (std::size_t c = 0; c < 3; ++c) {
        ASSERT_LE(std::abs(count[c] - n * f[c]), 1.0 + 1e-9)
            << "fractions " << f[0] << "/" << f[1] << "/" << f[2] << ", n " << n << ", split " << c;
      }
    }
  }
  EXPECT_EQ(dataset_item_split(tiny(3), 0), "");  // no run.split: no split
  EXPECT_NE(spec_error(replaced(tiny_spec(3), "run: {quality: fast}",
                                "run: {split: {train: 0.8, val: 0.1, test: 0.2}}"))
                .find("bad.yaml: run.split: train + val + test = 1.1"),
            std::string::npos);
  EXPECT_NE(spec_error(replaced(tiny_spec(3), "run: {quality: fast}",
                                "run: {split: {train: 0.8, valid: 0.2}}"))
                .find("run.split.valid"),
            std::string::npos);
}

TEST(DatasetSpec, LabelsTakeTheSceneFilesBlockAndGoIntoEveryItemsScene) {
  const std::string with =
      replaced(tiny_spec(3), "run: {quality: fast}",
               "run: {products: {labels: {coco: true, chips: {size_px: 32}}}}");
  const DatasetSpec s = load_dataset_spec_from_string(with, "l.yaml");
  EXPECT_TRUE(s.labels.coco);
  EXPECT_TRUE(s.labels.chips);
  EXPECT_EQ(s.labels.chip_size_px, 32u);
  // The drawn scene carries the block; the scene reader reads the same settings from it.
  const DatasetItemScene item = dataset_item_scene(s, 1);
  const SimulationSetup setup =
      load_simulation_from_string(item.yaml, "item.yaml", fs::temp_directory_path());
  EXPECT_TRUE(setup.labels.coco);
  EXPECT_FALSE(setup.labels.yolo);
  EXPECT_TRUE(setup.labels.chips);
  EXPECT_EQ(setup.labels.chip_size_px, 32u);
  // One display window for every item: the default, or run.display_window_db.
  ASSERT_TRUE(setup.display_window_db);
  EXPECT_EQ(*setup.display_window_db, (std::pair<double, double>{-28.0, 0.0}));
  const DatasetSpec windowed = load_dataset_spec_from_string(
      replaced(tiny_spec(3), "run: {quality: fast}", "run: {display_window_db: [-30, -5]}"),
      "w.yaml");
  for (std::size_t i = 0; i < 3; ++i) {
    const SimulationSetup si = load_simulation_from_string(dataset_item_scene(windowed, i).yaml,
                                                           "item.yaml", fs::temp_directory_path());
    EXPECT_EQ(*si.display_window_db, (std::pair<double, double>{-30.0, -5.0}));
  }
  EXPECT_NE(spec_error(
                replaced(tiny_spec(3), "run: {quality: fast}", "run: {display_window_db: [0, -5]}"))
                .find("bad.yaml: run.display_window_db"),
            std::string::npos);
  // The errors of the scene reader, at the spec's key.
  const std::string e1 = spec_error(
      replaced(tiny_spec(3), "run: {quality: fast}", "run: {products: {labels: {cocoa: true}}}"));
  EXPECT_NE(e1.find("bad.yaml: run.products.labels.cocoa"), std::string::npos) << e1;
  const std::string e2 = spec_error(replaced(tiny_spec(3), "run: {quality: fast}",
                                             "run: {products: {labels: {chips: {size_px: 3}}}}"));
  EXPECT_NE(e2.find("run.products.labels.chips.size_px"), std::string::npos) << e2;
  const std::string e3 =
      spec_error(replaced(tiny_spec(3), "run: {quality: fast}",
                          "run: {products: {truth: false, labels: {coco: true}}}"));
  EXPECT_NE(e3.find("labels need the truth"), std::string::npos) << e3;
}

TEST(DatasetSpec, TheSpecFileIsCheckedBeforeItIsRead) {
  for (const std::string path : {"/dev/zero", "/nonexistent/spec.yaml", "/tmp", ""}) {
    try {
      load_dataset_spec(path);
      FAIL() << path;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path.empty() ? "''" : path), std::string::npos) << msg;
    }
  }
  const std::string big(kMaxDatasetSpecBytes + 1, '#');
  try {
    load_dataset_spec_from_string(big, "big.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("big.yaml: 1048577 bytes"), std::string::npos) << e.what();
  }
  // Aliases that expand a few lines into 10^9 nodes are refused like in scene files.
  std::string bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  for (char c = 'b'; c <= 'j'; ++c) {
    const char prev = static_cast<char>(c - 1);
    bomb += std::string(1, c) + ": &" + c + " [*" + prev + ", *" + prev + ", *" + prev + ", *" +
            prev + ", *" + prev + ", *" + prev + ", *" + prev + ", *" + prev + ", *" + prev +
            ", *" + prev + "]\n";
  }
  EXPECT_THROW(load_dataset_spec_from_string(bomb, "bomb.yaml"), FormatError);
}

TEST(DatasetSpec, ParseItemRange) {
  EXPECT_EQ(parse_item_range("3:7", "--items"), (std::pair<std::size_t, std::size_t>{3, 7}));
  EXPECT_EQ(parse_item_range(":7", "--items"), (std::pair<std::size_t, std::size_t>{0, 7}));
  EXPECT_EQ(parse_item_range("5:", "--items").first, 5u);
  for (const std::string bad : {"7:3", "3:3", "3", "a:b", "-1:4", "1:2:3"}) {
    try {
      parse_item_range(bad, "--items");
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--items = '" + bad + "'"), std::string::npos)
          << e.what();
    }
  }
}

TEST_F(DatasetRun, RaisingCountGrowsTheDatasetAndAnItemRangeRendersASlice) {
  run_dataset(tiny(3), dir_ / "d");
  const auto first3 = snapshot(dir_ / "d" / "items");
  // count 3 -> 5: only items 3 and 4 are rendered; the first three keep their bytes.
  const DatasetRunResult grown = run_dataset(tiny(5), dir_ / "d");
  EXPECT_EQ(grown.done, 2u);
  EXPECT_EQ(grown.skipped, 3u);
  for (const auto& [path, bytes] : first3)
    EXPECT_EQ(snapshot(dir_ / "d" / "items").at(path), bytes);
  EXPECT_EQ(read_text(dir_ / "d" / "spec.yaml"), tiny(5).text);
  // The grown dataset equals one made with count 5 at once.
  run_dataset(tiny(5), dir_ / "at_once");
  EXPECT_EQ(snapshot(dir_ / "d"), snapshot(dir_ / "at_once"));
  // A slice: items 1 and 2 of a fresh directory, nothing else.
  DatasetRunOptions o;
  o.first_item = 1;
  o.end_item = 3;
  const DatasetRunResult slice = run_dataset(tiny(5), dir_ / "slice", o);
  EXPECT_EQ(slice.done, 2u);
  EXPECT_EQ(slice.items.front().index, 1u);
  EXPECT_FALSE(fs::exists(dir_ / "slice" / dataset_item_dir(0)));
  EXPECT_FALSE(fs::exists(dir_ / "slice" / dataset_item_dir(3)));
  EXPECT_EQ(snapshot(dir_ / "slice" / dataset_item_dir(2)),
            snapshot(dir_ / "d" / dataset_item_dir(2)));
  o.first_item = 5;
  o.end_item = 9;
  EXPECT_THROW(run_dataset(tiny(5), dir_ / "slice", o), InputError);
}

TEST_F(DatasetRun, ADamagedItemIsRenderedAgainNotReportedDone) {
  const DatasetSpec s = tiny(2);
  run_dataset(s, dir_ / "d");
  const auto item1 = snapshot(dir_ / "d" / dataset_item_dir(1));
  fs::remove(dir_ / "d" / dataset_item_dir(1) / "L1.xtf");
  DatasetRunResult r = run_dataset(s, dir_ / "d");
  EXPECT_EQ(r.done, 1u);
  EXPECT_EQ(r.repaired, 1u);
  EXPECT_NE(r.items[1].repaired.find("L1.xtf is missing"), std::string::npos)
      << r.items[1].repaired;
  EXPECT_EQ(snapshot(dir_ / "d" / dataset_item_dir(1)), item1);
  // A file changed in place (same size) is found with verify, by its SHA-256.
  {
    std::fstream f(dir_ / "d" / dataset_item_dir(1) / "scene.yaml",
                   std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(0);
    f.put('%');
  }
  EXPECT_EQ(run_dataset(s, dir_ / "d").skipped, 2u);  // sizes only: not seen
  DatasetRunOptions o;
  o.verify = true;
  r = run_dataset(s, dir_ / "d", o);
  EXPECT_EQ(r.repaired, 1u);
  EXPECT_NE(r.items[1].repaired.find("another SHA-256"), std::string::npos);
  EXPECT_EQ(snapshot(dir_ / "d" / dataset_item_dir(1)), item1);
  // Every recorded SHA-256 is the file's (checked with the system's sha256sum).
  const auto record =
      nlohmann::json::parse(read_text(dir_ / "d" / dataset_item_dir(1) / "item.json"));
  const auto f0 = record["file_records"][0];
  const fs::path out = dir_ / "sum.txt";
  const std::string cmd =
      "sha256sum '" + (dir_ / "d" / dataset_item_dir(1) / f0["path"].get<std::string>()).string() +
      "' > '" + out.string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_EQ(read_text(out).substr(0, 64), f0["sha256"].get<std::string>());
}

TEST_F(DatasetRun, OrphanedStagingIsRemovedAndThreadsOfOneProcessDoNotCollide) {
  const DatasetSpec s = tiny(2);
  prepare_dataset_dir(s, dir_ / "d");
  // A child that has exited: its pid is no longer running (kill -9 of a run leaves this).
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  std::string h(host);
  for (char& c : h) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-')) c = '_';
  }
  const fs::path dead = dir_ / "d" / ".work" / ("000001." + h + "." + std::to_string(child) + ".0");
  const fs::path other_host = dir_ / "d" / ".work" / "000001.otherhost.1.0";
  const fs::path live =
      dir_ / "d" / ".work" / ("000001." + h + "." + std::to_string(::getpid()) + ".99");
  for (const auto& p : {dead, other_host, live}) fs::create_directories(p / "item");
  prepare_dataset_dir(s, dir_ / "d");
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(other_host));  // may belong to a run on another machine
  EXPECT_TRUE(fs::exists(live));        // this process is running
  fs::remove_all(other_host);
  fs::remove_all(live);
  // Four threads of one process on the same two items: each item done once, no failure.
  std::vector<std::thread> threads;
  std::atomic<int> errors{0};
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      try {
        run_dataset_item(s, dir_ / "d", static_cast<std::size_t>(t % 2), 1);
      } catch (const std::exception&) {
        ++errors;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(errors.load(), 0);
  EXPECT_TRUE(fs::is_empty(dir_ / "d" / ".work"));
  EXPECT_TRUE(fs::is_empty(dir_ / "d" / "failed"));
  run_dataset(s, dir_ / "once");
  EXPECT_EQ(snapshot(dir_ / "d" / "items"), snapshot(dir_ / "once" / "items"));
}

TEST_F(DatasetRun, CommandLineRefusesAnEmptyOutputAndANonFileSpec) {
  const fs::path spec = write("spec.yaml", tiny_spec(2));
  const auto before = snapshot(dir_);
  const auto e = test::run_cli("dataset " + spec.string() + " -o ''", dir_);
  EXPECT_NE(e.exit_code, 0);
  EXPECT_NE(e.err.find("-o ''"), std::string::npos) << e.err;
  EXPECT_EQ(snapshot(dir_), before);  // nothing written into the working directory
  const auto z = test::run_cli("dataset /dev/zero -o " + (dir_ / "z").string(), dir_);
  EXPECT_NE(z.exit_code, 0);
  EXPECT_NE(z.err.find("/dev/zero: not a regular file"), std::string::npos) << z.err;
  EXPECT_FALSE(fs::exists(dir_ / "z"));
  const auto i = dataset_cli(spec, "i", "--items 1:2 --threads 1");
  EXPECT_EQ(i.exit_code, 0) << i.err;
  expect_item_1_only("i");
}

}  // namespace
}  // namespace sonarsynth
