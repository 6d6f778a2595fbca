// SPDX-License-Identifier: MIT
#include "label_sets.hpp"

#include <gdal_priv.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <tuple>
#include <utility>

#include "raster_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/gdal_util.hpp"
#include "sonarsynth/version.hpp"
#include "truth_labels.hpp"

namespace sonarsynth::labels {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
constexpr const char* kWho = "labels";

struct Raster {
  gdal::DatasetPtr ds;
  std::size_t cols = 0, rows = 0;
  std::string path;
};

Raster open(const fs::path& dir, const std::string& name) {
  Raster r;
  r.path = (dir / name).string();
  r.ds = gdal::open_raster(r.path, kWho);
  r.cols = static_cast<std::size_t>(r.ds->GetRasterXSize());
  r.rows = static_cast<std::size_t>(r.ds->GetRasterYSize());
  return r;
}

/// Rows [top, top + height) of some bands of a raster, read forward only (a PNG is decoded once
/// however the window moves): a ring of rows indexed by row % height.
class RowWindow {
 public:
  RowWindow(Raster& r, std::vector<int> bands, GDALDataType type, std::size_t height)
      : r_(r),
        bands_(std::move(bands)),
        type_(type),
        tsize_(static_cast<std::size_t>(GDALGetDataTypeSizeBytes(type))),
        height_(height),
        data_(height * bands_.size() * r.cols * tsize_) {}
  /// `top` never decreases between calls.
  void move_to(std::size_t top) {
    for (std::size_t y = std::max(top, loaded_end_); y < top + height_; ++y) {
      unsigned char* row = data_.data() + (y % height_) * bands_.size() * r_.cols * tsize_;
      const auto band_bytes = static_cast<GSpacing>(r_.cols * tsize_);
      if (r_.ds->RasterIO(GF_Read, 0, static_cast<int>(y), static_cast<int>(r_.cols), 1, row,
                          static_cast<int>(r_.cols), 1, type_, static_cast<int>(bands_.size()),
                          bands_.data(), static_cast<GSpacing>(tsize_), band_bytes, band_bytes,
                          nullptr) != CE_None) {
        throw FormatError(std::string(kWho) + ": cannot read row " + std::to_string(y) + " of " +
                          r_.path + ": " + gdal::last_error_message());
      }
    }
    loaded_end_ = std::max(loaded_end_, top + height_);
  }
  /// Band index b (into `bands`), absolute row y (in the window), column x.
  template <class T>
  const T* row(std::size_t b, std::size_t y) const {
    return reinterpret_cast<const T*>(data_.data() +
                                      ((y % height_) * bands_.size() + b) * r_.cols * tsize_);
  }
  std::size_t bands() const { return bands_.size(); }

 private:
  Raster& r_;
  std::vector<int> bands_;
  GDALDataType type_;
  std::size_t tsize_, height_;
  std::size_t loaded_end_ = 0;
  std::vector<unsigned char> data_;
};

Json categories() {
  return Json::array({{{"id", kCategoryObject}, {"name", "object"}, {"supercategory", "target"}},
                      {{"id", kCategoryShadow}, {"name", "shadow"}, {"supercategory", "target"}}});
}

Json coco_document(const std::string& description) {
  Json doc;
  doc["info"] = {{"description", description},
                 {"version", kVersion},
                 {"contributor", "sonarsynth"},
                 {"labels_doc", "docs/labels.md"}};
  doc["images"] = Json::array();
  doc["annotations"] = Json::array();
  doc["categories"] = categories();
  return doc;
}

void add_annotations(Json& doc, int image_id, const std::vector<Box>& boxes) {
  for (const Box& b : boxes) {
    const auto id = static_cast<int>(doc["annotations"].size()) + 1;
    doc["annotations"].push_back({{"id", id},
                                  {"image_id", image_id},
                                  {"category_id", b.category},
                                  {"bbox", {b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0}},
                                  {"area", b.pixels},
                                  {"iscrowd", 0},
                                  {"object_id", b.instance}});
  }
}

std::string yolo_text(const std::vector<Box>& boxes, std::size_t width, std::size_t height) {
  std::string s;
  char line[160];
  const auto w = static_cast<double>(width), h = static_cast<double>(height);
  for (const Box& b : boxes) {
    std::snprintf(line, sizeof line, "%d %.6f %.6f %.6f %.6f\n", b.category - 1,
                  0.5 * static_cast<double>(b.x0 + b.x1) / w,
                  0.5 * static_cast<double>(b.y0 + b.y1) / h, static_cast<double>(b.x1 - b.x0) / w,
                  static_cast<double>(b.y1 - b.y0) / h);
    s += line;
  }
  return s;
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream os(path, std::ios::binary);
  os << text;
  os.close();
  if (!os) throw FormatError(std::string(kWho) + ": " + path.string() + ": cannot write");
}

/// The image's bands shown in a chip: grey, or red green blue (an alpha band is dropped).
std::vector<int> colour_bands(const Raster& r) {
  const int n = r.ds->GetRasterCount();
  if (n >= 3) return {1, 2, 3};
  return {1};
}

struct ImageLabels {
  Raster image, cls, inst;
};

/// Opens an image and its label rasters; false (and a note) if their sizes differ.
bool open_image(const fs::path& dir, const LabelImage& li, ImageLabels& out,
                std::vector<std::string>& notes) {
  out.image = open(dir, li.image);
  out.cls = open(dir, li.classes);
  out.inst = open(dir, li.instance);
  if (out.image.cols != out.cls.cols || out.image.rows != out.cls.rows ||
      out.inst.cols != out.cls.cols || out.inst.rows != out.cls.rows) {
    notes.push_back(li.image + ": no boxes or chips (the image is " +
                    std::to_string(out.image.cols) + " x " + std::to_string(out.image.rows) +
                    " pixels, its labels " + std::to_string(out.cls.cols) + " x " +
                    std::to_string(out.cls.rows) + ": a waterfall decimated along track)");
    return false;
  }
  return true;
}

std::vector<Box> whole_image_boxes(ImageLabels& il) {
  constexpr std::size_t kStrip = 256;
  BoxAccumulator acc;
  const std::size_t rows = il.cls.rows, cols = il.cls.cols;
  RowWindow cls(il.cls, {1}, GDT_Byte, std::min(kStrip, rows));
  RowWindow inst(il.inst, {1}, GDT_UInt32, std::min(kStrip, rows));
  for (std::size_t y = 0; y < rows; ++y) {
    if (y % kStrip == 0) {
      const std::size_t top = std::min(y, rows - std::min(kStrip, rows));
      cls.move_to(top);
      inst.move_to(top);
    }
    acc.add_row(y, {cls.row<std::uint8_t>(0, y), cols}, {inst.row<std::uint32_t>(0, y), cols});
  }
  return acc.boxes();
}

/// Writes a small raster (band-sequential buffer) through `driver`.
void write_small(const fs::path& path, std::size_t size, GDALDataType type,
                 const std::vector<const void*>& bands, const char* driver, bool nodata,
                 double nodata_value) {
  gdal::DatasetPtr mem = raster::wrap_mem(size, size, type, bands, kWho, path.string());
  if (nodata) mem->GetRasterBand(1)->SetNoDataValue(nodata_value);
  std::vector<std::pair<std::string, std::string>> co;
  if (std::string(driver) == "GTiff") co = {{"COMPRESS", "DEFLATE"}};
  raster::copy_to_file(*mem, driver, path.string(), co, kWho, path.string());
}

/// The chips of one image; appends to the chip COCO document and result.
void write_chips(const fs::path& dir, const LabelImage& li, ImageLabels& il,
                 const LabelSetOptions& options, Json& coco, LabelSetResult& result) {
  const std::size_t size = options.chip_size_px, stride = options.chip_stride_px;
  if (il.cls.rows < size || il.cls.cols < size) return;
  const std::vector<int> colour = colour_bands(il.image);
  RowWindow img(il.image, colour, GDT_Byte, size);
  RowWindow cls(il.cls, {1}, GDT_Byte, size);
  RowWindow inst(il.inst, {1}, GDT_UInt32, size);
  std::vector<std::uint8_t> chip_img(colour.size() * size * size), chip_cls(size * size);
  std::vector<std::uint32_t> chip_inst(size * size);
  const auto limit =
      static_cast<std::size_t>(options.chip_max_nodata_fraction * static_cast<double>(size * size));
  for (std::size_t top = 0; top + size <= il.cls.rows; top += stride) {
    img.move_to(top);
    cls.move_to(top);
    inst.move_to(top);
    for (std::size_t left = 0; left + size <= il.cls.cols; left += stride) {
      std::size_t nodata = 0;
      BoxAccumulator acc;
      for (std::size_t r = 0; r < size; ++r) {
        const std::uint8_t* c = cls.row<std::uint8_t>(0, top + r) + left;
        const std::uint32_t* k = inst.row<std::uint32_t>(0, top + r) + left;
        std::copy(c, c + size, chip_cls.begin() + static_cast<std::ptrdiff_t>(r * size));
        std::copy(k, k + size, chip_inst.begin() + static_cast<std::ptrdiff_t>(r * size));
        nodata += static_cast<std::size_t>(std::count(c, c + size, kClassNodata));
        for (std::size_t b = 0; b < colour.size(); ++b) {
          const std::uint8_t* p = img.row<std::uint8_t>(b, top + r) + left;
          std::copy(p, p + size,
                    chip_img.begin() + static_cast<std::ptrdiff_t>((b * size + r) * size));
        }
        acc.add_row(r, {c, size}, {k, size});
      }
      if (nodata == size * size || nodata > limit) continue;
      char suffix[64];
      std::snprintf(suffix, sizeof suffix, "_r%06zu_c%06zu", top, left);
      const std::string stem = li.stem + suffix;
      std::vector<const void*> views;
      for (std::size_t b = 0; b < colour.size(); ++b) views.push_back(&chip_img[b * size * size]);
      write_small(dir / "chips" / "images" / (stem + ".png"), size, GDT_Byte, views, "PNG", false,
                  0.0);
      write_small(dir / "chips" / "masks" / (stem + "_class.tif"), size, GDT_Byte,
                  {chip_cls.data()}, "GTiff", true, kClassNodata);
      write_small(dir / "chips" / "masks" / (stem + "_instance.tif"), size, GDT_UInt32,
                  {chip_inst.data()}, "GTiff", true, kInstanceNodata);
      result.files.push_back(fs::path("chips") / "images" / (stem + ".png"));
      result.files.push_back(fs::path("chips") / "masks" / (stem + "_class.tif"));
      result.files.push_back(fs::path("chips") / "masks" / (stem + "_instance.tif"));
      const std::vector<Box> boxes = acc.boxes();
      if (options.yolo) {
        const fs::path rel = fs::path("chips") / "labels" / (stem + ".txt");
        write_text(dir / rel, yolo_text(boxes, size, size));
        result.files.push_back(rel);
      }
      if (options.coco) {
        const auto image_id = static_cast<int>(coco["images"].size()) + 1;
        coco["images"].push_back({{"id", image_id},
                                  {"file_name", "images/" + stem + ".png"},
                                  {"width", size},
                                  {"height", size},
                                  {"class_mask", "masks/" + stem + "_class.tif"},
                                  {"instance_mask", "masks/" + stem + "_instance.tif"},
                                  {"source_image", li.image},
                                  {"source_x0", left},
                                  {"source_y0", top}});
        add_annotations(coco, image_id, boxes);
      }
      ++result.chips;
    }
  }
}

}  // namespace

std::size_t BoxAccumulator::root(std::size_t part) {
  while (parent_[part] != part) {
    parent_[part] = parent_[parent_[part]];
    part = parent_[part];
  }
  return part;
}

void BoxAccumulator::join(std::size_t a, std::size_t b) {
  a = root(a);
  b = root(b);
  if (a == b) return;
  if (b < a) std::swap(a, b);
  Box& keep = parts_[a];
  const Box& gone = parts_[b];
  keep.x0 = std::min(keep.x0, gone.x0);
  keep.y0 = std::min(keep.y0, gone.y0);
  keep.x1 = std::max(keep.x1, gone.x1);
  keep.y1 = std::max(keep.y1, gone.y1);
  keep.pixels += gone.pixels;
  parent_[b] = a;
}

void BoxAccumulator::add_row(std::size_t y, std::span<const std::uint8_t> cls,
                             std::span<const std::uint32_t> instance, std::size_t x_offset) {
  // Runs of this row: consecutive pixels of one (instance > 0, category).
  current_.clear();
  for (std::size_t i = 0; i < cls.size(); ++i) {
    const std::uint32_t k = instance[i];
    int category = 0;
    if (k != 0 && k != kInstanceNodata) {
      if (cls[i] == static_cast<std::uint8_t>(SampleClass::object)) category = kCategoryObject;
      if (cls[i] == static_cast<std::uint8_t>(SampleClass::shadow)) category = kCategoryShadow;
    }
    if (category == 0) continue;
    const std::size_t x = x_offset + i;
    if (!current_.empty() && current_.back().x1 == x && current_.back().instance == k &&
        current_.back().category == category) {
      ++current_.back().x1;
    } else {
      current_.push_back({x, x + 1, k, category, 0});
    }
  }
  const bool adjacent = has_previous_ && y == previous_y_ + 1 && x_offset == previous_offset_ &&
                        cls.size() == previous_width_;
  if (!adjacent) previous_.clear();
  // Each run joins the components of the runs of the previous row with its key that touch it by
  // a side or a corner (columns [x0 - 1, x1]); both rows' runs are sorted and disjoint.
  std::size_t first = 0;
  for (Run& r : current_) {
    while (first < previous_.size() && previous_[first].x1 < r.x0) ++first;
    bool joined = false;
    for (std::size_t j = first; j < previous_.size() && previous_[j].x0 <= r.x1; ++j) {
      const Run& p = previous_[j];
      if (p.instance != r.instance || p.category != r.category) continue;
      if (!joined) {
        r.part = root(p.part);
        joined = true;
      } else {
        join(r.part, p.part);
        r.part = root(r.part);
      }
    }
    if (!joined) {
      r.part = parts_.size();
      parts_.push_back({r.instance, r.category, r.x0, y, r.x0, y, 0});
      parent_.push_back(r.part);
    }
    Box& b = parts_[root(r.part)];
    b.x0 = std::min(b.x0, r.x0);
    b.x1 = std::max(b.x1, r.x1);
    b.y0 = std::min(b.y0, y);
    b.y1 = std::max(b.y1, y + 1);
    b.pixels += r.x1 - r.x0;
  }
  std::swap(previous_, current_);
  previous_y_ = y;
  previous_offset_ = x_offset;
  previous_width_ = cls.size();
  has_previous_ = true;
}

std::vector<Box> BoxAccumulator::boxes() const {
  std::vector<Box> out;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    if (parent_[i] == i) out.push_back(parts_[i]);
  }
  std::sort(out.begin(), out.end(), [](const Box& a, const Box& b) {
    return std::tie(a.instance, a.category, a.y0, a.x0, a.y1, a.x1) <
           std::tie(b.instance, b.category, b.y0, b.x0, b.y1, b.x1);
  });
  return out;
}

LabelSetResult write_label_sets(const fs::path& dir, const std::vector<LabelImage>& waterfalls,
                                const std::vector<LabelImage>& mosaic,
                                const LabelSetOptions& options) {
  LabelSetResult result;
  if (!options.any()) return result;
  gdal::ensure_registered();
  if (options.yolo) fs::create_directories(dir / "yolo");
  if (options.chips) {
    for (const char* sub : {"images", "masks"}) fs::create_directories(dir / "chips" / sub);
    if (options.yolo) fs::create_directories(dir / "chips" / "labels");
  }
  Json chip_coco = coco_document("sonarsynth chips of the waterfalls and the mosaic");
  const std::pair<const char*, const std::vector<LabelImage>*> sets[2] = {
      {"waterfalls", &waterfalls}, {"mosaic", &mosaic}};
  for (const auto& [set, images] : sets) {
    Json coco = coco_document(std::string("sonarsynth ") + set);
    for (const LabelImage& li : *images) {
      ImageLabels il;
      if (!open_image(dir, li, il, result.notes)) continue;
      if (options.coco || options.yolo) {
        const std::vector<Box> boxes = whole_image_boxes(il);
        result.boxes += boxes.size();
        if (options.coco) {
          const auto image_id = static_cast<int>(coco["images"].size()) + 1;
          coco["images"].push_back({{"id", image_id},
                                    {"file_name", li.image},
                                    {"width", il.cls.cols},
                                    {"height", il.cls.rows},
                                    {"class_mask", li.classes},
                                    {"instance_mask", li.instance}});
          add_annotations(coco, image_id, boxes);
        }
        if (options.yolo) {
          const fs::path rel = fs::path("yolo") / (fs::path(li.image).stem().string() + ".txt");
          write_text(dir / rel, yolo_text(boxes, il.cls.cols, il.cls.rows));
          result.files.push_back(rel);
        }
      }
      if (options.chips) write_chips(dir, li, il, options, chip_coco, result);
    }
    if (options.coco && !images->empty()) {
      const std::string name = std::string(set) + ".coco.json";
      write_text(dir / name, coco.dump(1) + "\n");
      result.files.emplace_back(name);
    }
  }
  if (options.yolo) {
    write_text(dir / "yolo" / "classes.txt", "object\nshadow\n");
    result.files.push_back(fs::path("yolo") / "classes.txt");
  }
  if (options.chips && options.coco) {
    write_text(dir / "chips" / "coco.json", chip_coco.dump(1) + "\n");
    result.files.push_back(fs::path("chips") / "coco.json");
  }
  return result;
}

}  // namespace sonarsynth::labels
