// SPDX-License-Identifier: MIT
// Datasets ready for detector training (docs/dataset.md): labels declared in the spec, the
// dataset-level COCO / YOLO files merged over the items, the train/val/test split, growth.
// Boxes are checked against the label rasters read back with GDAL and flood-filled here.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "cli_test_util.hpp"
#include "label_check_util.hpp"
#include "sonarsynth/formats/config/dataset.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::read_text;
using test::snapshot;

// The number after `<tag>` at `from` in `xml` (VOC: one value per tag).
std::size_t xml_number(const std::string& xml, const std::string& tag, std::size_t from) {
  const std::size_t at = xml.find("<" + tag + ">", from);
  EXPECT_NE(at, std::string::npos) << tag;
  return at == std::string::npos ? 0 : std::stoul(xml.substr(at + tag.size() + 2));
}

// Small items (a 4 m line, 10 m range, 128 samples) with objects in every one, so that a
// few hundred items render in seconds.
std::string spec_text(std::size_t count) {
  return "name: labelled\nseed: 7\ncount: " + std::to_string(count) + R"(
location: {lat_deg: 43.0, lon_deg: 5.0}
seabed: {depth_m: [9, 11], cell_m: 0.5, material: sand, roughness: {rms_m: 0.02, wavelength_m: 5}}
objects:
  count: [1, 2]
  across_track_m: [2, 6]
  types:
    rock: {diameter_m: [0.6, 1.2]}
    box: {length_m: [1, 2], width_m: [0.6, 1], height_m: [0.5, 0.9]}
survey: {line_length_m: 4, altitude_m: [3, 4], speed_m_s: 2}
sonar: {preset: seascan-hds-600, range_m: 10, samples: 128}
noise: {model: speckle, snr_db: 20}
run:
  quality: fast
  products:
    waterfalls: true
    truth: true
    labels: {coco: true, yolo: true, voc: true,
             chips: {size_px: 32, stride_px: 32, max_nodata_fraction: 0.9}}
  split: {train: 0.8, val: 0.1, test: 0.1}
)";
}

DatasetSpec spec(std::size_t count) {
  return load_dataset_spec_from_string(spec_text(count), "labelled.yaml");
}

json read_json(const fs::path& p) {
  return json::parse(read_text(p));
}

// The items of each split, as the manifest of dataset `d` records them.
std::map<std::string, std::set<std::size_t>> manifest_splits(const fs::path& d) {
  std::map<std::string, std::set<std::size_t>> split_items;
  std::istringstream m(read_text(d / "manifest.jsonl"));
  std::string line;
  while (std::getline(m, line)) {
    const json j = json::parse(line);
    split_items[j["split"].get<std::string>()].insert(j["index"].get<std::size_t>());
  }
  return split_items;
}

// Pascal VOC: the split's list names every chip's XML (`images` of them); its boxes (1-based,
// inclusive) are the chip's COCO boxes (`coco_of_file`, by image file).
void check_voc_chips(const fs::path& d, const std::string& split,
                     std::map<std::string, std::vector<test::BoxRow>>& coco_of_file,
                     std::size_t images) {
  std::istringstream list(read_text(d / ("voc_chips_" + split + ".txt")));
  std::string xml_path;
  std::size_t xml_files = 0;
  while (std::getline(list, xml_path)) {
    ++xml_files;
    const std::string xml = read_text(d / xml_path);
    const std::size_t name_at = xml.find("<filename>") + 10;
    const std::string image = xml.substr(name_at, xml.find("</filename>") - name_at);
    const std::string item_dir = xml_path.substr(0, std::string("items/000000").size());
    const std::string key = item_dir + "/chips/images/" + image;
    ASSERT_EQ(coco_of_file.count(key), 1u) << xml_path;
    std::vector<test::BoxRow> voc;
    for (std::size_t at = xml.find("<object>"); at != std::string::npos;
         at = xml.find("<object>", at + 1)) {
      const std::size_t name = xml.find("<name>", at) + 6;
      voc.push_back({xml_number(xml, "object_id", at),
                     xml.compare(name, 6, "object") == 0 ? std::size_t{1} : std::size_t{2},
                     xml_number(xml, "xmin", at) - 1, xml_number(xml, "ymin", at) - 1,
                     xml_number(xml, "xmax", at), xml_number(xml, "ymax", at)});
    }
    std::sort(voc.begin(), voc.end());
    EXPECT_EQ(voc, coco_of_file[key]) << xml_path;
  }
  EXPECT_EQ(xml_files, images) << split;
}

// The YOLO lists of dataset `d` name images whose label file is where Ultralytics looks for it,
// each of an item of the split; `listed`: the count of images listed.
void check_yolo_chip_lists(const fs::path& d,
                           const std::map<std::string, std::set<std::size_t>>& split_items,
                           std::size_t& listed) {
  listed = 0;
  for (const auto& [split, items] : split_items) {
    std::istringstream list(read_text(d / ("yolo_chips_" + split + ".txt")));
    std::string line;
    while (std::getline(list, line)) {
      ASSERT_EQ(line.rfind("./items/", 0), 0u) << line;
      const fs::path image = d / line.substr(2);
      EXPECT_TRUE(fs::exists(image)) << line;
      const fs::path label =
          image.parent_path().parent_path() / "labels" / (image.stem().string() + ".txt");
      EXPECT_TRUE(fs::exists(label)) << label;
      const std::size_t item = std::stoul(line.substr(8, 6));
      EXPECT_EQ(items.count(item), 1u) << line;
      ++listed;
    }
  }
}

class DatasetLabels : public test::ScratchDirTest {};

// The target's 200 items grown to 250; under the sanitizers (10-20x slower) 20 grown to 25,
// which runs every code path the same.
#ifdef SONARSYNTH_TEST_SANITIZED
constexpr std::size_t kItems = 20, kGrown = 25;
#else
constexpr std::size_t kItems = 200, kGrown = 250;
#endif

TEST_F(DatasetLabels, TwoHundredItemsMergeSplitRepeatAndGrow) {
  const fs::path d = dir_ / "d";
  DatasetRunOptions one_thread;
  one_thread.threads = 1;
  const DatasetRunResult r = run_dataset(spec(kItems), d, one_thread);
  ASSERT_EQ(r.done, kItems);
  ASSERT_EQ(r.failed, 0u);

  // Split: every item's split in the manifest, each within one item of its fraction.
  std::map<std::string, std::set<std::size_t>> split_items = manifest_splits(d);
  const std::map<std::string, double> fraction = {{"train", 0.8}, {"val", 0.1}, {"test", 0.1}};
  for (const auto& [name, f] : fraction) {
    EXPECT_LE(
        std::abs(static_cast<double>(split_items[name].size()) - static_cast<double>(kItems) * f),
        1.0)
        << name;
  }

  // Merged COCO files: every image exists and belongs to an item of the split; every box of a
  // whole waterfall equals a connected piece of its item's label rasters and vice versa.
  std::size_t boxes_checked = 0;
  for (const auto& [split, items] : split_items) {
    for (const std::string set : {"waterfalls", "chips"}) {
      const fs::path merged = d / "annotations" / (set + "_" + split + ".coco.json");
      ASSERT_TRUE(fs::exists(merged)) << merged;
      const json coco = read_json(merged);
      EXPECT_TRUE(coco["licenses"].is_array());
      std::map<long long, std::vector<test::BoxRow>> by_image;
      for (const auto& a : coco["annotations"]) {
        const auto& b = a["bbox"];
        const std::size_t x = b[0], y = b[1], w = b[2], h = b[3];
        by_image[a["image_id"].get<long long>()].push_back({a["object_id"].get<std::size_t>(),
                                                            a["category_id"].get<std::size_t>(), x,
                                                            y, x + w, y + h});
      }
      std::set<std::size_t> seen_items;
      std::map<std::string, std::vector<test::BoxRow>> coco_of_file;  // for the VOC check
      for (const auto& im : coco["images"]) {
        auto boxes = by_image[im["id"].get<long long>()];
        std::sort(boxes.begin(), boxes.end());
        coco_of_file[im["file_name"].get<std::string>()] = boxes;
        const std::string file = im["file_name"];
        EXPECT_TRUE(fs::exists(d / file)) << file;
        for (const auto& [key, value] : im.items()) {
          if (key.ends_with("_mask")) {
            EXPECT_TRUE(fs::exists(d / value.get<std::string>())) << key << " " << value;
          }
        }
        const std::size_t item = im["item"];
        EXPECT_EQ(items.count(item), 1u) << file << " in split " << split;
        seen_items.insert(item);
        if (set != "waterfalls") continue;
        const fs::path item_dir = d / dataset_item_dir(item);
        const auto cls = test::read_label_raster(item_dir / "L1_truth_class.tif");
        const auto inst = test::read_label_raster(item_dir / "L1_truth_instance.tif");
        auto got = by_image[im["id"].get<long long>()];
        std::sort(got.begin(), got.end());
        EXPECT_EQ(got, test::brute_boxes(cls, inst)) << file;
        boxes_checked += got.size();
      }
      if (set == "waterfalls") {
        EXPECT_EQ(seen_items, items) << split;
      } else {
        ASSERT_NO_FATAL_FAILURE(check_voc_chips(d, split, coco_of_file, coco["images"].size()));
      }
    }
  }
  EXPECT_GE(boxes_checked, kItems);  // every item has objects: at least one box each

  // YOLO: the lists name images whose label file is where Ultralytics looks for it.
  EXPECT_TRUE(fs::exists(d / "data.yaml"));
  std::size_t listed = 0;
  ASSERT_NO_FATAL_FAILURE(check_yolo_chip_lists(d, split_items, listed));
  EXPECT_GE(listed, kItems);

  // A second run into another directory: the same bytes, file for file.
  run_dataset(spec(kItems), dir_ / "again", one_thread);
  const auto first = snapshot(d);
  const auto again = snapshot(dir_ / "again");
  EXPECT_EQ(again.size(), first.size());
  for (const auto& [path, bytes] : first) {  // (not EXPECT_EQ of the maps: its diff is huge)
    const auto it = again.find(path);
    EXPECT_TRUE(it != again.end() && it->second == bytes) << path << " differs";
  }

  // count 200 -> 250: only the new items are rendered; the first ones keep their bytes.
  const DatasetRunResult grown = run_dataset(spec(kGrown), d, one_thread);
  EXPECT_EQ(grown.done, kGrown - kItems);
  EXPECT_EQ(grown.skipped, kItems);
  const auto after = snapshot(d / "items");
  for (const auto& [path, bytes] : first) {
    if (path.rfind("items/", 0) != 0) continue;
    ASSERT_EQ(after.count(path.substr(6)), 1u) << path;
    EXPECT_EQ(after.at(path.substr(6)), bytes) << path;
  }
  EXPECT_EQ(read_json(d / "summary.json")["done"], kGrown);
}

}  // namespace
}  // namespace sonarsynth
