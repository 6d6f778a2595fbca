// SPDX-License-Identifier: MIT
// The dataset's manifest, summary and merged annotation files (docs/dataset.md), rebuilt from the
// items' own records.
#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/dataset.hpp"
#include "sonarsynth/formats/config/dataset_parts.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"

namespace sonarsynth {
namespace {

namespace fs = std::filesystem;
using dataset_files::failure_record;
using dataset_files::read_text;
using dataset_files::write_atomically;
using nlohmann::json;

// The dataset-level annotation files (docs/dataset.md), merged over the done items in index
// order: for each image set of the items' COCO files (waterfalls, mosaic, chips) and each split,
// annotations/<set>[_<split>].coco.json with the file names relative to the dataset directory;
// for YOLO, yolo_<set>[_<split>].txt (image lists in the Ultralytics form "./items/...") and
// data.yaml; for VOC, voc_<set>[_<split>].txt (the XML files).
class AnnotationMerger {
 public:
  AnnotationMerger(const DatasetSpec& spec, const fs::path& dir) : spec_(spec), dir_(dir) {}

  void add_item(const json& record) {
    const std::string item_dir = record.at("dir").get<std::string>();
    const std::string split = record.value("split", std::string("all"));
    const auto index = record.at("index").get<std::size_t>();
    for (const auto& file : record.at("files")) {
      const std::string path = file.get<std::string>();  // items/000042/...
      const std::string rel = path.substr(item_dir.size() + 1);
      const fs::path relp(rel);
      const std::string name = relp.filename().string();
      const std::string parent = relp.parent_path().generic_string();
      if (name.size() > 10 && name.ends_with(".coco.json")) {
        add_coco(name.substr(0, name.size() - 10), split, index, path, item_dir, parent);
      } else if (name == "coco.json" && !parent.empty()) {
        add_coco(fs::path(parent).filename().string(), split, index, path, item_dir, parent);
      } else if (relp.extension() == ".txt" && relp.parent_path().filename() == "labels") {
        // YOLO: <set dir>/labels/<stem>.txt beside <set dir>/images/<stem>.<ext>.
        yolo_labels_.insert(path);
      } else if (relp.parent_path().filename() == "images") {
        images_.push_back({split, path, relp.parent_path().parent_path().generic_string()});
      } else if (relp.extension() == ".xml") {
        // Whole images (voc/Annotations) are the set "images"; chips (chips/voc/...) "chips".
        const std::string set = set_of(parent) == "voc" ? "images" : set_of(parent);
        voc_[{set, split}] += path + "\n";
      }
    }
  }

  std::vector<std::string> write() {
    std::vector<std::string> written;
    for (auto& [key, c] : coco_) {
      const auto& [set, split] = key;
      Json doc;
      doc["info"] = {{"description", "sonarsynth dataset '" + spec_.name + "' (docs/dataset.md)"},
                     {"seed", std::to_string(spec_.seed)},
                     {"split", split}};
      doc["licenses"] = Json::array();
      doc["categories"] = c.categories;
      doc["images"] = std::move(c.images);
      doc["annotations"] = std::move(c.annotations);
      const std::string name =
          "annotations/" + set + (split == "all" ? "" : "_" + split) + ".coco.json";
      write_atomically(dir_ / name, doc.dump(1) + "\n");
      written.push_back(name);
    }
    // YOLO image lists: the images with a label file beside them (Ultralytics' rule: the label
    // of .../images/x.png is .../labels/x.txt).
    std::map<std::pair<std::string, std::string>, std::string> lists;
    for (const auto& im : images_) {
      const fs::path p(im.path);
      const std::string label =
          (p.parent_path().parent_path() / "labels" / p.stem()).generic_string() + ".txt";
      if (!yolo_labels_.count(label)) continue;
      // Whole images (yolo/images) are the set "images"; chips (chips/images) the set "chips".
      const std::string set = set_of(im.set_dir) == "yolo" ? "images" : set_of(im.set_dir);
      lists[{set, im.split}] += "./" + im.path + "\n";
    }
    std::map<std::string, std::vector<std::string>> sets;
    for (const auto& [key, text] : lists) {
      const std::string name =
          "yolo_" + key.first + (key.second == "all" ? "" : "_" + key.second) + ".txt";
      write_atomically(dir_ / name, text);
      written.push_back(name);
      sets[key.first].push_back(key.second);
    }
    for (const auto& [set, splits] : sets) {
      std::ostringstream y;
      y << "# YOLO dataset of the '" << set << "' images of sonarsynth dataset '" << spec_.name
        << "' (docs/dataset.md); paths relative to this file's directory.\n";
      for (const char* sp : {"train", "val", "test"}) {
        const std::string split = spec_.split ? sp : "all";
        const bool has = std::find(splits.begin(), splits.end(), split) != splits.end();
        if (!has && !spec_.split) continue;
        // Ultralytics needs train and val; an empty split points at an empty list.
        const std::string list = "yolo_" + set + (spec_.split ? "_" + split : "") + ".txt";
        if (!has) write_atomically(dir_ / list, "");
        y << sp << ": " << list << "\n";
        if (!spec_.split) {
          if (std::string(sp) == "train") y << "val: " << list << "\n";
          break;
        }
      }
      y << "names:\n  0: object\n  1: shadow\n";
      const std::string name = set == preferred_set(sets) ? "data.yaml" : "data_" + set + ".yaml";
      write_atomically(dir_ / name, y.str());
      written.push_back(name);
    }
    for (const auto& [key, text] : voc_) {
      const std::string name =
          "voc_" + key.first + (key.second == "all" ? "" : "_" + key.second) + ".txt";
      write_atomically(dir_ / name, text);
      written.push_back(name);
    }
    return written;
  }

 private:
  using Json = nlohmann::ordered_json;
  struct Coco {
    Json categories = Json::array();
    Json images = Json::array();
    Json annotations = Json::array();
  };
  struct Image {
    std::string split, path, set_dir;
  };

  // "chips" for chips/..., "yolo" for yolo/..., "item" for files at the item's top.
  static std::string set_of(const std::string& parent_dir) {
    if (parent_dir.empty()) return "item";
    return fs::path(parent_dir).begin()->string();
  }
  static std::string preferred_set(const std::map<std::string, std::vector<std::string>>& sets) {
    return sets.count("chips") ? "chips" : sets.begin()->first;
  }

  void add_coco(const std::string& set, const std::string& split, std::size_t index,
                const std::string& path, const std::string& item_dir, const std::string& parent) {
    const Json in = Json::parse(read_text(dir_ / path));
    Coco& c = coco_[{set, split}];
    if (c.categories.empty()) c.categories = in.value("categories", Json::array());
    if (in.value("categories", Json::array()) != c.categories) {
      throw FormatError((dir_ / path).string() +
                        ": its categories differ from the other items' (not a file of this "
                        "dataset's version)");
    }
    const std::string prefix = item_dir + "/" + (parent.empty() ? "" : parent + "/");
    std::map<long long, long long> image_ids;
    for (Json im : in.value("images", Json::array())) {
      const long long id = static_cast<long long>(c.images.size()) + 1;
      image_ids[im.at("id").get<long long>()] = id;
      im["id"] = id;
      im["file_name"] = prefix + im.at("file_name").get<std::string>();
      // Other files an image entry names (its masks: "class_mask", "instance_mask", ...).
      for (auto& [key, value] : im.items()) {
        if (value.is_string() && (key.ends_with("_mask") || key == "mask")) {
          value = prefix + value.get<std::string>();
        }
      }
      im["item"] = index;
      c.images.push_back(std::move(im));
    }
    for (Json a : in.value("annotations", Json::array())) {
      const auto it = image_ids.find(a.at("image_id").get<long long>());
      if (it == image_ids.end()) {
        throw FormatError((dir_ / path).string() + ": annotation " + a.value("id", Json()).dump() +
                          " refers to image " + a.at("image_id").dump() + ", not in the file");
      }
      a["id"] = static_cast<long long>(c.annotations.size()) + 1;
      a["image_id"] = it->second;
      c.annotations.push_back(std::move(a));
    }
  }

  const DatasetSpec& spec_;
  fs::path dir_;
  std::map<std::pair<std::string, std::string>, Coco> coco_;
  std::set<std::string> yolo_labels_;
  std::vector<Image> images_;
  std::map<std::pair<std::string, std::string>, std::string> voc_;
};

}  // namespace

void write_dataset_manifest(const DatasetSpec& spec, const fs::path& dir) {
  // Written line by line into its temporary file: a dataset of 10^6 items never holds its
  // manifest in memory.
  AtomicOutput manifest_file(dir / "manifest.jsonl", true);
  std::ofstream manifest(manifest_file.temp_path(), std::ios::binary | std::ios::trunc);
  std::size_t done = 0, failed = 0, pending = 0;
  std::uint64_t pings = 0;
  std::map<std::string, long long> objects;
  std::map<std::string, long long> splits;
  json failures = json::array();
  AnnotationMerger annotations(spec, dir);
  for (std::size_t i = 0; i < spec.count; ++i) {
    const fs::path item = dir / dataset_item_dir(i) / "item.json";
    const fs::path failure = failure_record(dir, i);
    json j;
    std::error_code ec;
    if (fs::exists(item)) {
      j = json::parse(read_text(item));
      ++done;
      pings += j.value("pings", std::uint64_t{0});
      for (const auto& [type, n] : j["objects"].items()) objects[type] += n.get<long long>();
      if (j.contains("split")) ++splits[j["split"].get<std::string>()];
      if (spec.labels.any()) annotations.add_item(j);
      // A failure record left beside a done item (a run that failed, then another that did it).
      fs::remove(failure, ec);
    } else if (fs::exists(failure)) {
      j = json::parse(read_text(failure));
      ++failed;
      failures.push_back({{"index", i},
                          {"seed", j["seed"]},
                          {"seed_text", std::to_string(j["seed"].get<std::uint64_t>())},
                          {"error", j["error"]}});
    } else {
      const std::uint64_t seed = dataset_item_seed(spec, i);
      j = {
          {"index", i}, {"seed", seed}, {"seed_text", std::to_string(seed)}, {"status", "pending"}};
      const std::string split = dataset_item_split(spec, i);
      if (!split.empty()) j["split"] = split;
      ++pending;
    }
    j.erase("file_records");  // in item.json; the manifest keeps one line per item short
    manifest << j.dump() << "\n";
  }
  manifest.close();
  if (!manifest) throw FormatError((dir / "manifest.jsonl").string() + ": cannot write");
  manifest_file.commit();
  json summary;
  summary["name"] = spec.name;
  summary["seed"] = spec.seed;
  summary["seed_text"] = std::to_string(spec.seed);
  summary["count"] = spec.count;
  summary["done"] = done;
  summary["failed"] = failed;
  summary["pending"] = pending;
  summary["pings"] = pings;
  summary["objects"] = objects;
  if (spec.split) summary["splits"] = splits;
  summary["failures"] = failures;
  if (spec.labels.any()) {
    std::error_code ec;
    fs::create_directories(dir / "annotations", ec);
    summary["annotation_files"] = annotations.write();
  }
  write_atomically(dir / "summary.json", summary.dump(2) + "\n");
}

}  // namespace sonarsynth
