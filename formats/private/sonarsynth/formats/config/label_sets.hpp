// SPDX-License-Identifier: MIT
#pragma once
// Private helper of run_simulation: bounding boxes and instance masks (COCO JSON, YOLO text,
// Pascal VOC XML) and image chips computed from the label rasters written by the survey
// products (formats/private/sonarsynth/formats/products/truth_labels.hpp), read back from the
// output directory, and the track of each line recorded while it renders for the chips' positions
// (docs/labels.md).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/formats/config/simulation_file.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/ping_sink.hpp"

namespace sonarsynth::labels {

/// output.labels of the simulation file (include/sonarsynth/formats/config/simulation_file.hpp).
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

/// Pixels x0..x1 - 1 of row y.
struct PixelRun {
  std::size_t y = 0, x0 = 0, x1 = 0;
};

/// One connected piece: its box and its pixels as runs sorted by (y, x0).
struct Piece {
  Box box;
  std::vector<PixelRun> runs;
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
  /// The pieces of boxes() (same order) with their pixels.
  std::vector<Piece> pieces() const;

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
  std::vector<std::pair<PixelRun, std::size_t>> runs_;  ///< every run with its part
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
  std::string line;      ///< the survey line of a waterfall; empty for the mosaic
  /// A float raster of the sample values on the same grid (grey and sample chips read back:
  /// "mosaic.tif"); empty if none.
  std::string values;
};

/// What the rendered pings of one line say about its waterfall rows (one per ping with truth):
/// the distance along the sensor's track and the truth's ground position of some columns.
struct LineTrack {
  std::vector<double> along_track_m;  ///< per row: sensor track length from the first row
  std::vector<std::size_t> columns;   ///< the columns recorded, ascending
  /// Per row, per column of `columns`: the truth's ground x / y (local frame, metres; NaN none).
  std::vector<double> ground_x_m, ground_y_m;
  /// The ground x / y of (row, column) if the column was recorded (else false).
  bool ground_xy(std::size_t row, std::size_t column, double& x_m, double& y_m) const;
};

/// The columns of a `cols`-wide image whose ground positions the chip records need: each chip's
/// first, centre (left + size / 2) and last column.
std::vector<std::size_t> chip_columns(std::size_t cols, const LabelSetOptions& options);

/// Records a LineTrack per line while the survey renders (a cheap inline sink).
class TrackRecorder final : public PingSink {
 public:
  /// `columns`: of the waterfall (port FAR -> NEAR | starboard NEAR -> FAR, 2 x `side` wide).
  TrackRecorder(std::size_t lines, std::size_t side, std::vector<std::size_t> columns);
  void begin_line(std::size_t line) override;
  void ping(const RenderedPing& p) override;
  const std::vector<LineTrack>& tracks() const { return tracks_; }

 private:
  std::size_t side_;
  std::vector<std::size_t> columns_;
  std::vector<LineTrack> tracks_;
  LineTrack* current_ = nullptr;
  Eigen::Vector2d last_xy_ = Eigen::Vector2d::Zero();
};

/// What the label sets need besides the files: the run's geometry.
struct LabelContext {
  const GeoFrame* frame = nullptr;  ///< the scene's (mosaic chips' and ground positions)
  double sample_spacing_m = 0.0;    ///< slant range per waterfall column (sonar samples)
  std::size_t side_cols = 0;        ///< waterfall columns per side (samples per channel)
  /// Per line (LabelImage::line, same order as the survey's lines) with their names.
  std::vector<std::string> line_names;
  const std::vector<LineTrack>* tracks = nullptr;
  /// The output directory's final absolute path (data.yaml's `path`); empty: `dir`.
  std::filesystem::path final_dir;
  /// The display window of the images when it is fixed (output.display_window_db or
  /// output.display: linear); else each image's own percentiles.
  bool display_fixed = false;
  DisplayRange display;
};

/// The label sets of the waterfalls made in the same pass as the images (docs/labels.md): taps
/// on each line's image rows (Waterfall::write) and label rows (TruthWaterfall::
/// write_with_labels) find the boxes and cut the chips as the rows are written, on the threads
/// that write them. write_label_sets() then only writes the text files.
class LabelPass {
 public:
  /// `dir`: the output directory being written (chips go to its chips/).
  LabelPass(std::filesystem::path dir, LabelSetOptions options);
  ~LabelPass();
  LabelPass(const LabelPass&) = delete;
  LabelPass& operator=(const LabelPass&) = delete;
  /// The taps of the line `name` (stem of its chips: "<name>_waterfall").
  Waterfall::RowTap image_tap(const std::string& name);
  TruthWaterfall::LabelRowTap label_tap(const std::string& name);
  struct Line;
  /// The line's state once its images are written (nullptr if its taps never ran).
  Line* line(const std::string& name) const;

 private:
  std::filesystem::path dir_;
  LabelSetOptions options_;
  mutable std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Line>> lines_;
  Line& get(const std::string& name);
};

/// What write_label_sets() wrote.
struct LabelSetResult {
  std::vector<std::filesystem::path> files;  ///< relative to the output directory
  std::vector<std::string> notes;            ///< e.g. an image skipped (decimated waterfall)
  std::size_t chips = 0;
  std::size_t boxes = 0;  ///< of the whole images
};

/// COCO uncompressed RLE of a piece in an image `width` x `height`: counts of alternating runs
/// of 0 and 1 in column-major order, starting with 0 (docs/labels.md).
std::vector<std::uint64_t> coco_rle_counts(const Piece& piece, std::size_t width,
                                           std::size_t height);

/// Writes, in `dir`: with coco, `<set>.coco.json` for the `waterfalls` (set "waterfalls") and
/// the `mosaic` images (set "mosaic"); with yolo, yolo/data.yaml, yolo/images/<image> (a hard
/// link) and yolo/labels/<image stem>.txt; with voc, voc/Annotations/<image stem>.xml; with
/// chips, chips/images, chips/masks, chips/chips.jsonl and (coco / yolo / voc)
/// chips/coco.json, chips/data.yaml + chips/labels, chips/voc/Annotations. Throws FormatError
/// naming the file that cannot be read or written.
LabelSetResult write_label_sets(const std::filesystem::path& dir,
                                const std::vector<LabelImage>& waterfalls,
                                const std::vector<LabelImage>& mosaic,
                                const LabelSetOptions& options, const LabelContext& context = {},
                                LabelPass* pass = nullptr);

}  // namespace sonarsynth::labels
