// SPDX-License-Identifier: MIT
// The label sets of the whole images (waterfalls and mosaic) and the files that describe them
// (docs/labels.md); the chips are cut in label_chips.cpp.
#include "sonarsynth/formats/config/label_sets.hpp"

#include <algorithm>
#include <utility>

#include "sonarsynth/formats/config/label_set_parts.hpp"

namespace sonarsynth::labels {
namespace label_parts {

Raster open(const fs::path& dir, const std::string& name) {
  Raster r;
  r.path = (dir / name).string();
  r.ds = gdal::open_raster(r.path, kWho);
  r.cols = static_cast<std::size_t>(r.ds->GetRasterXSize());
  r.rows = static_cast<std::size_t>(r.ds->GetRasterYSize());
  return r;
}

/// The image's bands shown in a chip: grey, or red green blue (an alpha band is dropped).
std::vector<int> colour_bands(const Raster& r) {
  const int n = r.ds->GetRasterCount();
  if (n >= 3) return {1, 2, 3};
  return {1};
}

}  // namespace label_parts

using namespace label_parts;

namespace {

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

std::vector<Piece> whole_image_pieces(ImageLabels& il) {
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
  return acc.pieces();
}

/// Whole images: a box is truncated when it touches the image's edge (the survey may have cut
/// the object there).
std::vector<bool> edge_truncated(const std::vector<Piece>& pieces, std::size_t cols,
                                 std::size_t rows) {
  std::vector<bool> out;
  for (const Piece& p : pieces) {
    const Box& b = p.box;
    out.push_back(b.x0 == 0 || b.y0 == 0 || b.x1 == cols || b.y1 == rows);
  }
  return out;
}

/// The boxes of a whole image: its COCO image and annotations, YOLO text (and image link) and
/// VOC XML.
void emit_image(const fs::path& dir, const LabelImage& li, const std::vector<Piece>& pieces,
                std::size_t cols, std::size_t rows, std::size_t bands,
                const LabelSetOptions& options, Json& coco, LabelSetResult& result) {
  const std::vector<bool> truncated = edge_truncated(pieces, cols, rows);
  result.boxes += pieces.size();
  const std::string stem = fs::path(li.image).stem().string();
  if (options.coco) {
    const auto image_id = static_cast<int>(coco["images"].size()) + 1;
    coco["images"].push_back({{"id", image_id},
                              {"file_name", li.image},
                              {"width", cols},
                              {"height", rows},
                              {"class_mask", li.classes},
                              {"instance_mask", li.instance}});
    add_annotations(coco, image_id, pieces, cols, rows, options, truncated);
  }
  if (options.yolo) {
    const fs::path image = fs::path("yolo") / "images" / li.image;
    link_or_copy(dir / li.image, dir / image);
    const fs::path rel = fs::path("yolo") / "labels" / (stem + ".txt");
    write_text(dir / rel, yolo_text(pieces, cols, rows));
    result.files.push_back(image);
    result.files.push_back(rel);
  }
  if (options.voc) {
    const fs::path rel = fs::path("voc") / "Annotations" / (stem + ".xml");
    write_text(dir / rel, voc_xml(".", li.image, cols, rows, bands, pieces, truncated));
    result.files.push_back(rel);
  }
}

/// The output's label directories.
void create_label_dirs(const fs::path& dir, const LabelSetOptions& options) {
  if (options.yolo) {
    for (const char* sub : {"images", "labels"}) fs::create_directories(dir / "yolo" / sub);
  }
  if (options.voc) fs::create_directories(dir / "voc" / "Annotations");
  if (options.chips) {
    for (const char* sub : {"images", "masks"}) fs::create_directories(dir / "chips" / sub);
    if (options.chip_samples != LabelOutput::ChipSamples::none) {
      fs::create_directories(dir / "chips" / "samples");
    }
    if (options.yolo) fs::create_directories(dir / "chips" / "labels");
    if (options.voc) fs::create_directories(dir / "chips" / "voc" / "Annotations");
  }
}

}  // namespace

LabelSetResult write_label_sets(const fs::path& dir, const std::vector<LabelImage>& waterfalls,
                                const std::vector<LabelImage>& mosaic,
                                const LabelSetOptions& options, const LabelContext& context,
                                LabelPass* pass) {
  LabelSetResult result;
  if (!options.any()) return result;
  gdal::ensure_registered();
  create_label_dirs(dir, options);
  ChipSinks chips{coco_document("sonarsynth chips of the waterfalls and the mosaic"), {}};
  const std::pair<const char*, const std::vector<LabelImage>*> sets[2] = {
      {"waterfalls", &waterfalls}, {"mosaic", &mosaic}};
  for (const auto& [set, images] : sets) {
    Json coco = coco_document(std::string("sonarsynth ") + set);
    for (const LabelImage& li : *images) {
      // A waterfall labelled in the pass that wrote it, else read back from its files.
      LabelPass::Line* l = pass && !li.line.empty() ? pass->line(li.line) : nullptr;
      if (l && l->label_rows == 0) {
        // No label rows came (no truth for the line): its chip images go, it is read back.
        for (const std::string& stem : l->image_chips) remove_files(dir, chip_files(stem, options));
        l = nullptr;
      }
      if (l) finish_line(*l, dir, options);
      ImageLabels il;
      std::vector<Piece> pieces;
      std::size_t cols = 0, rows = 0, bands = 0;
      if (l) {
        il.image = open(dir, li.image);
        bands = colour_bands(il.image).size();
        cols = l->label_cols;
        rows = l->label_rows;
        if (options.chips && !emit_line_chips(dir, li, *l, options, context, chips, result)) {
          l = nullptr;  // the image is not on the labels' grid: as read back (a note)
        } else if (il.image.cols != cols || il.image.rows != rows) {
          l = nullptr;
        }
        if (l) pieces = l->whole.pieces();
      }
      if (!l) {
        if (!open_image(dir, li, il, result.notes)) continue;
        cols = il.cls.cols;
        rows = il.cls.rows;
        bands = colour_bands(il.image).size();
        if (options.coco || options.yolo || options.voc) pieces = whole_image_pieces(il);
        if (options.chips) write_chips(dir, li, il, options, context, chips, result);
      }
      if (options.coco || options.yolo || options.voc) {
        emit_image(dir, li, pieces, cols, rows, bands, options, coco, result);
      }
    }
    if (options.coco && !images->empty()) {
      const std::string name = std::string(set) + ".coco.json";
      write_text(dir / name, coco.dump(1) + "\n");
      result.files.emplace_back(name);
    }
  }
  if (options.yolo) {
    write_text(dir / "yolo" / "data.yaml", data_yaml());
    result.files.push_back(fs::path("yolo") / "data.yaml");
  }
  if (options.chips) {
    write_text(dir / "chips" / "chips.jsonl", chips.jsonl);
    result.files.push_back(fs::path("chips") / "chips.jsonl");
    if (options.coco) {
      write_text(dir / "chips" / "coco.json", chips.coco.dump(1) + "\n");
      result.files.push_back(fs::path("chips") / "coco.json");
    }
    if (options.yolo) {
      write_text(dir / "chips" / "data.yaml", data_yaml());
      result.files.push_back(fs::path("chips") / "data.yaml");
    }
  }
  return result;
}

}  // namespace sonarsynth::labels
