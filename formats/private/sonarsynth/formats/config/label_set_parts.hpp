// SPDX-License-Identifier: MIT
#pragma once
// Internal parts of the label sets (label_sets.hpp, docs/labels.md), shared by the files that
// write them: label_sets.cpp (whole images), label_documents.cpp (COCO, YOLO, VOC text),
// label_chips.cpp (chips and the label pass), label_chip_records.cpp (chip provenance records).

#include <gdal_priv.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/label_sets.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"

namespace sonarsynth::labels::label_parts {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
inline constexpr const char* kWho = "labels";

/// A raster of the output directory opened for reading.
struct Raster {
  gdal::DatasetPtr ds;
  std::size_t cols = 0, rows = 0;
  std::string path;
};

/// Opens `name` in `dir`; throws FormatError naming the file if it cannot.
Raster open(const fs::path& dir, const std::string& name);

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
    const std::size_t end = std::min(top + height_, r_.rows);
    for (std::size_t y = std::max(top, loaded_end_); y < end; ++y) {
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
    loaded_end_ = std::max(loaded_end_, end);
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

/// An image and its label rasters (class and instance).
struct ImageLabels {
  Raster image, cls, inst;
};

/// The image's bands shown in a chip: grey, or red green blue (an alpha band is dropped).
std::vector<int> colour_bands(const Raster& r);

// COCO, YOLO and Pascal VOC text (label_documents.cpp).

/// An empty COCO document (info, licenses, categories) described by `description`.
Json coco_document(const std::string& description);
/// Appends the pieces of image `image_id` (width x height) to the COCO document's annotations.
void add_annotations(Json& doc, int image_id, const std::vector<Piece>& pieces, std::size_t width,
                     std::size_t height, const LabelSetOptions& options,
                     const std::vector<bool>& truncated);
/// YOLO text of the pieces' boxes (class, centre, size; relative to the image).
std::string yolo_text(const std::vector<Piece>& pieces, std::size_t width, std::size_t height);
/// Writes `text` to `path`; throws FormatError naming the file if it cannot.
void write_text(const fs::path& path, const std::string& text);
/// Pascal VOC annotation of one image: `folder` and `filename` of the image (relative to the
/// output directory), bndbox in VOC's 1-based inclusive pixel numbers (docs/labels.md).
std::string voc_xml(const std::string& folder, const std::string& filename, std::size_t width,
                    std::size_t height, std::size_t depth, const std::vector<Piece>& pieces,
                    const std::vector<bool>& truncated);
/// `link` a hard link to `target` (a copy where the file system cannot link).
void link_or_copy(const fs::path& target, const fs::path& link);
/// Ultralytics YOLO dataset description of the directory it is written in (images/ beside
/// labels/).
std::string data_yaml();

// Chip provenance (label_chip_records.cpp).

/// The source image's geometry for the chip records (chips.jsonl, docs/labels.md).
struct ChipFrame {
  const LineTrack* track = nullptr;  ///< a waterfall's
  bool geo = false;                  ///< a georeferenced image (the mosaic)
  double gt[6] = {0, 1, 0, 0, 0, 1};
};

/// The frame of the image `li` with `rows` rows: its line's track, or `image`'s geotransform.
ChipFrame chip_frame(const LabelImage& li, std::size_t rows, GDALDataset* image,
                     const LabelContext& context);

/// The provenance record of one chip (a line of chips/chips.jsonl, docs/labels.md).
Json chip_record(const std::string& file, const LabelImage& li, const ChipFrame& f,
                 const LabelContext& context, std::size_t top, std::size_t left, std::size_t size,
                 std::size_t cols, const std::vector<Piece>& pieces,
                 const std::vector<bool>& truncated);

// Chips (label_chips.cpp).

struct ChipSinks {
  Json coco;
  std::string jsonl;
};

/// A chip's labels: its window, pieces and where the chip cut them.
struct ChipCut {
  std::size_t top = 0, left = 0;
  std::vector<Piece> pieces;
  std::vector<bool> truncated;
};

/// Scratch buffers of one chip.
struct ChipScratch {
  std::vector<std::uint8_t> cls, colour;
  std::vector<std::uint32_t> inst;
  std::vector<float> values;
  std::vector<std::uint16_t> u16;
};

/// The files of one chip, relative to the output directory.
std::vector<fs::path> chip_files(const std::string& stem, const LabelSetOptions& options);

/// Removes `files` (relative to `dir`), ignoring those that do not exist.
void remove_files(const fs::path& dir, const std::vector<fs::path>& files);

/// The chips of one image read back from its files; appends to the chip documents and result.
void write_chips(const fs::path& dir, const LabelImage& li, ImageLabels& il,
                 const LabelSetOptions& options, const LabelContext& context, ChipSinks& sinks,
                 LabelSetResult& result);

}  // namespace sonarsynth::labels::label_parts

namespace sonarsynth::labels {

struct LabelPass::Line {
  std::string stem;  ///< of the chips: "<line>_waterfall"
  // The image side (the waterfall writer's thread): the last chip_size_px rows.
  std::size_t image_rows = 0, image_cols = 0, bands = 0;
  std::vector<std::uint8_t> colour;  ///< rows of bands x cols, row y in slot y % size
  std::vector<float> linear, display;
  std::vector<std::string> image_chips;  ///< stems of the chip images written
  label_parts::ChipScratch image_scratch;
  // The label side (the truth writer's thread): the last chip_size_px + 2 rows.
  std::size_t label_rows = 0, label_cols = 0;
  BoxAccumulator whole;
  std::vector<std::uint8_t> cls;
  std::vector<std::uint32_t> inst;
  std::size_t next_top = 0;                 ///< the next band of chips to cut
  std::vector<label_parts::ChipCut> chips;  ///< the chips kept, their masks written
  label_parts::ChipScratch label_scratch;
};

namespace label_parts {

/// The bands of chips left when the line's last label row has come (no row below them).
void finish_line(LabelPass::Line& l, const fs::path& dir, const LabelSetOptions& o);

/// The chips of a line cut in the pass: the records of those kept, the files of the others
/// removed; false (all its chip files removed) if the image and its labels differ in size.
bool emit_line_chips(const fs::path& dir, const LabelImage& li, LabelPass::Line& l,
                     const LabelSetOptions& options, const LabelContext& context, ChipSinks& sinks,
                     LabelSetResult& result);

}  // namespace label_parts
}  // namespace sonarsynth::labels
