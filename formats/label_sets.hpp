// SPDX-License-Identifier: MIT
#pragma once
// Private helper of run_simulation: bounding boxes (COCO JSON, YOLO text) and image chips
// computed from the label rasters written by the survey products (formats/truth_labels.hpp),
// read back from the output directory (docs/labels.md).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "sonarsynth/formats/simulation_file.hpp"

namespace sonarsynth::labels {

/// output.labels of the simulation file (include/sonarsynth/formats/simulation_file.hpp).
using LabelSetOptions = LabelOutput;

/// COCO category ids (YOLO class index = id - 1).
inline constexpr int kCategoryObject = 1;
inline constexpr int kCategoryShadow = 2;

/// The extent of one connected piece of an instance's pixels of one category in an image:
/// columns [x0, x1), rows [y0, y1) (pixel edges), and its pixel count.
struct Box {
  std::uint32_t instance = 0;
  int category = 0;  ///< kCategoryObject or kCategoryShadow
  std::size_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::uint64_t pixels = 0;
};

/// Boxes of an image fed row by row: one box per connected component (8-connected: pixels
/// touching by a side or a corner) of the pixels of one instance > 0 in one category (class
/// object: category object; class shadow: category shadow). An object whose pixels fall in two
/// separate pieces gets two boxes. Sorted by (instance, category, y0, x0, y1, x1).
class BoxAccumulator {
 public:
  /// Row `y`, pixels from column `x_offset`. Rows are connected to the previous call's only if
  /// they are consecutive (y = previous y + 1) with the same `x_offset` and width.
  void add_row(std::size_t y, std::span<const std::uint8_t> cls,
               std::span<const std::uint32_t> instance, std::size_t x_offset = 0);
  std::vector<Box> boxes() const;

 private:
  /// Pixels x0..x1 - 1 of one row with one (instance, category), part of component `part`.
  struct Run {
    std::size_t x0, x1;
    std::uint32_t instance;
    int category;
    std::size_t part;
  };
  std::size_t root(std::size_t part);
  void join(std::size_t a, std::size_t b);

  std::vector<Box> parts_;           ///< per component; valid at the roots
  std::vector<std::size_t> parent_;  ///< union-find over parts_
  std::vector<Run> previous_, current_;
  std::size_t previous_y_ = 0, previous_offset_ = 0, previous_width_ = 0;
  bool has_previous_ = false;
};

/// One image to label: its file and the label rasters on the same pixel grid (names relative
/// to the output directory).
struct LabelImage {
  std::string image;     ///< e.g. "line1_waterfall.png", "mosaic_rgb.tif"
  std::string classes;   ///< e.g. "line1_truth_class.tif"
  std::string instance;  ///< e.g. "line1_truth_instance.tif"
  std::string stem;      ///< chip names: "<stem>_r<row>_c<col>"
};

/// What write_label_sets() wrote.
struct LabelSetResult {
  std::vector<std::filesystem::path> files;  ///< relative to the output directory
  std::vector<std::string> notes;            ///< e.g. an image skipped (decimated waterfall)
  std::size_t chips = 0;
  std::size_t boxes = 0;  ///< of the whole images
};

/// Writes, in `dir`: with coco, `<set>.coco.json` for the `waterfalls` (set "waterfalls") and
/// the `mosaic` images (set "mosaic"); with yolo, `yolo/<image stem>.txt` and yolo/classes.txt;
/// with chips, chips/images, chips/masks and (coco / yolo) chips/coco.json, chips/labels. Throws
/// FormatError naming the file that cannot be read or written.
LabelSetResult write_label_sets(const std::filesystem::path& dir,
                                const std::vector<LabelImage>& waterfalls,
                                const std::vector<LabelImage>& mosaic,
                                const LabelSetOptions& options);

}  // namespace sonarsynth::labels
