// SPDX-License-Identifier: MIT
// The chips of the label sets: image chips with their masks and labels, cut in the pass that
// writes a waterfall (LabelPass) or read back from an image's files (docs/labels.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <optional>
#include <set>

#include "sonarsynth/colormap.hpp"
#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/formats/config/label_set_parts.hpp"
#include "sonarsynth/formats/products/truth_labels.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"

namespace sonarsynth::labels {
namespace label_parts {
namespace {

int category_of(std::uint8_t cls) {
  if (cls == static_cast<std::uint8_t>(SampleClass::object)) return kCategoryObject;
  if (cls == static_cast<std::uint8_t>(SampleClass::shadow)) return kCategoryShadow;
  return 0;
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

/// Where a chip cut a piece: a pixel of the same instance and category lies across a chip edge,
/// next (by a side or a corner) to a pixel of the piece on that edge. `key(x, y)` gives the
/// category and instance of a source pixel (in the loaded window).
template <class Key>
std::vector<bool> chip_truncated(const std::vector<Piece>& pieces, std::size_t top,
                                 std::size_t left, std::size_t size, std::size_t cols,
                                 std::size_t rows, const Key& key) {
  std::vector<bool> out;
  for (const Piece& p : pieces) {
    const std::pair<int, std::uint32_t> k{p.box.category, p.box.instance};
    bool cut = false;
    const auto same = [&](std::size_t x, std::size_t y) { return key(x, y) == k; };
    for (const PixelRun& r : p.runs) {
      if (cut) break;
      const std::size_t y = top + r.y, xa = left + r.x0, xb = left + r.x1;  // [xa, xb)
      const std::size_t lo = xa > 0 ? xa - 1 : 0, hi = std::min(xb + 1, cols);
      if (r.y == 0 && top > 0) {
        for (std::size_t x = lo; x < hi && !cut; ++x) cut = same(x, y - 1);
      }
      if (r.y + 1 == size && top + size < rows) {
        for (std::size_t x = lo; x < hi && !cut; ++x) cut = same(x, y + 1);
      }
      const std::size_t ya = y > 0 ? y - 1 : 0, yb = std::min(y + 2, rows);
      if (r.x0 == 0 && left > 0) {
        for (std::size_t yy = ya; yy < yb && !cut; ++yy) cut = same(left - 1, yy);
      }
      if (r.x1 == size && left + size < cols) {
        for (std::size_t yy = ya; yy < yb && !cut; ++yy) cut = same(left + size, yy);
      }
    }
    out.push_back(cut);
  }
  return out;
}

std::string chip_stem(const std::string& stem, std::size_t top, std::size_t left) {
  char suffix[64];
  std::snprintf(suffix, sizeof suffix, "_r%06zu_c%06zu", top, left);
  return stem + suffix;
}

/// Cuts the labels of the chip at (top, left) from the rows `cls_row(y)`, `inst_row(y)` (the
/// rows top - 1 .. top + size where they exist): false (nothing written) if it has too much
/// nodata, else writes its masks and fills `cut`.
template <class ClsRow, class InstRow>
bool cut_chip(const fs::path& dir, const std::string& stem, std::size_t top, std::size_t left,
              std::size_t rows, std::size_t cols, const LabelSetOptions& options,
              const ClsRow& cls_row, const InstRow& inst_row, ChipScratch& scratch, ChipCut& cut) {
  const std::size_t size = options.chip_size_px;
  const auto limit =
      static_cast<std::size_t>(options.chip_max_nodata_fraction * static_cast<double>(size * size));
  scratch.cls.resize(size * size);
  scratch.inst.resize(size * size);
  std::size_t nodata = 0;
  BoxAccumulator acc;
  for (std::size_t r = 0; r < size; ++r) {
    const std::uint8_t* c = cls_row(top + r) + left;
    const std::uint32_t* k = inst_row(top + r) + left;
    std::copy(c, c + size, scratch.cls.begin() + static_cast<std::ptrdiff_t>(r * size));
    std::copy(k, k + size, scratch.inst.begin() + static_cast<std::ptrdiff_t>(r * size));
    nodata += static_cast<std::size_t>(std::count(c, c + size, kClassNodata));
    acc.add_row(r, {c, size}, {k, size});
  }
  if (nodata == size * size || nodata > limit) return false;
  write_small(dir / "chips" / "masks" / (stem + "_class.tif"), size, GDT_Byte, {scratch.cls.data()},
              "GTiff", true, kClassNodata);
  write_small(dir / "chips" / "masks" / (stem + "_instance.tif"), size, GDT_UInt32,
              {scratch.inst.data()}, "GTiff", true, kInstanceNodata);
  const auto key = [&](std::size_t x, std::size_t y) {
    const std::uint32_t k = inst_row(y)[x];
    const int c = category_of(cls_row(y)[x]);
    if (k == 0 || k == kInstanceNodata || c == 0) return std::pair<int, std::uint32_t>{0, 0};
    return std::pair<int, std::uint32_t>{c, k};
  };
  cut.top = top;
  cut.left = left;
  cut.pieces = acc.pieces();
  cut.truncated = chip_truncated(cut.pieces, top, left, size, cols, rows, key);
  return true;
}

/// The rows of a band-sequential chip buffer (size x size per band).
class ChipRows final : public raster::RowSource {
 public:
  ChipRows(const std::uint8_t* data, std::size_t size, std::size_t bands)
      : data_(data), size_(size), bands_(bands) {}
  void next(void* out) override {
    auto* o = static_cast<std::uint8_t*>(out);
    for (std::size_t b = 0; b < bands_; ++b) {
      const std::uint8_t* p = data_ + (b * size_ + row_) * size_;
      std::copy(p, p + size_, o + b * size_);
    }
    ++row_;
  }
  void rewind() override { row_ = 0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_, bands_, row_ = 0;
};

/// No sample in a u16 sample chip (sonarsynth's u16 samples reach 32767 at most).
constexpr std::uint16_t kU16SampleNodata = 65535;

/// Writes the chip's image (colour bands `colour_row(b, y)`, or grey from the display values
/// `display_row(y)`) and, if asked, its sample chip (`value_row(y)`).
template <class ColourRow, class DisplayRow, class ValueRow>
void write_chip_image(const fs::path& dir, const std::string& stem, std::size_t top,
                      std::size_t left, std::size_t bands, const LabelSetOptions& options,
                      const ColourRow& colour_row, const DisplayRow& display_row,
                      const ValueRow& value_row, ChipScratch& scratch) {
  const std::size_t size = options.chip_size_px;
  const bool grey = options.chip_color == LabelOutput::ChipColor::grey;
  const std::size_t out_bands = grey ? 1 : bands;
  scratch.colour.resize(out_bands * size * size);
  for (std::size_t r = 0; r < size; ++r) {
    if (grey) {
      const float* v = display_row(top + r) + left;
      for (std::size_t i = 0; i < size; ++i) {
        scratch.colour[r * size + i] = colormap(Colormap::grey, static_cast<double>(v[i])).r;
      }
    } else {
      for (std::size_t b = 0; b < bands; ++b) {
        const std::uint8_t* p = colour_row(b, top + r) + left;
        std::copy(p, p + size,
                  scratch.colour.begin() + static_cast<std::ptrdiff_t>((b * size + r) * size));
      }
    }
  }
  // Through the waterfall's PNG writer (ISA-L's deflate) rather than GDAL's PNG driver (zlib
  // level 6), which took most of the chips' time.
  ChipRows source(scratch.colour.data(), size, out_bands);
  const std::string png = (dir / "chips" / "images" / (stem + ".png")).string();
  raster::stream_to_png(source, size, size, static_cast<int>(out_bands), {}, png, kWho, png);
  if (options.chip_samples == LabelOutput::ChipSamples::none) return;
  scratch.values.resize(size * size);
  for (std::size_t r = 0; r < size; ++r) {
    const float* v = value_row(top + r) + left;
    std::copy(v, v + size, scratch.values.begin() + static_cast<std::ptrdiff_t>(r * size));
  }
  const fs::path path = dir / "chips" / "samples" / (stem + ".tif");
  if (options.chip_samples == LabelOutput::ChipSamples::f32) {
    write_small(path, size, GDT_Float32, {scratch.values.data()}, "GTiff", true, NAN);
    return;
  }
  scratch.u16.resize(size * size);
  for (std::size_t i = 0; i < size * size; ++i) {
    const float v = scratch.values[i];
    scratch.u16[i] = std::isnan(v) ? kU16SampleNodata
                                   : static_cast<std::uint16_t>(std::clamp(
                                         std::lround(static_cast<double>(v)), 0L, 65534L));
  }
  write_small(path, size, GDT_UInt16, {scratch.u16.data()}, "GTiff", true, kU16SampleNodata);
}

}  // namespace

/// The files of one chip, relative to the output directory.
std::vector<fs::path> chip_files(const std::string& stem, const LabelSetOptions& options) {
  std::vector<fs::path> f = {fs::path("chips") / "images" / (stem + ".png"),
                             fs::path("chips") / "masks" / (stem + "_class.tif"),
                             fs::path("chips") / "masks" / (stem + "_instance.tif")};
  if (options.chip_samples != LabelOutput::ChipSamples::none) {
    f.push_back(fs::path("chips") / "samples" / (stem + ".tif"));
  }
  return f;
}

namespace {

/// The chip's boxes: YOLO text, VOC XML, its COCO image and annotations and its record.
void emit_chip(const fs::path& dir, const LabelImage& li, const std::string& stem,
               const ChipCut& cut, std::size_t cols, std::size_t bands,
               const LabelSetOptions& options, const LabelContext& context, const ChipFrame& frame,
               ChipSinks& sinks, LabelSetResult& result) {
  const std::size_t size = options.chip_size_px;
  const std::vector<fs::path> files = chip_files(stem, options);
  result.files.insert(result.files.end(), files.begin(), files.end());
  if (options.yolo) {
    const fs::path rel = fs::path("chips") / "labels" / (stem + ".txt");
    write_text(dir / rel, yolo_text(cut.pieces, size, size));
    result.files.push_back(rel);
  }
  const std::size_t depth = options.chip_color == LabelOutput::ChipColor::grey ? 1 : bands;
  if (options.voc) {
    const fs::path rel = fs::path("chips") / "voc" / "Annotations" / (stem + ".xml");
    write_text(dir / rel, voc_xml("chips/images", stem + ".png", size, size, depth, cut.pieces,
                                  cut.truncated));
    result.files.push_back(rel);
  }
  if (options.coco) {
    Json& coco = sinks.coco;
    const auto image_id = static_cast<int>(coco["images"].size()) + 1;
    Json im = {{"id", image_id},
               {"file_name", "images/" + stem + ".png"},
               {"width", size},
               {"height", size},
               {"class_mask", "masks/" + stem + "_class.tif"},
               {"instance_mask", "masks/" + stem + "_instance.tif"}};
    if (options.chip_samples != LabelOutput::ChipSamples::none) {
      im["samples"] = "samples/" + stem + ".tif";
    }
    im["source_image"] = li.image;
    im["source_x0"] = cut.left;
    im["source_y0"] = cut.top;
    coco["images"].push_back(std::move(im));
    add_annotations(coco, image_id, cut.pieces, size, size, options, cut.truncated);
  }
  sinks.jsonl += chip_record("images/" + stem + ".png", li, frame, context, cut.top, cut.left, size,
                             cols, cut.pieces, cut.truncated)
                     .dump() +
                 "\n";
  ++result.chips;
}

/// Cuts the chips of the band at `top` from the line's label rows (rows top - 1 .. top + size
/// where they exist; `rows` the rows known to exist).
void cut_band(LabelPass::Line& l, const fs::path& dir, const LabelSetOptions& o, std::size_t top,
              std::size_t rows) {
  const std::size_t size = o.chip_size_px, window = size + 2, cols = l.label_cols;
  const auto cls_row = [&](std::size_t y) { return l.cls.data() + (y % window) * cols; };
  const auto inst_row = [&](std::size_t y) { return l.inst.data() + (y % window) * cols; };
  for (std::size_t left = 0; left + size <= cols; left += o.chip_stride_px) {
    ChipCut cut;
    if (cut_chip(dir, chip_stem(l.stem, top, left), top, left, rows, cols, o, cls_row, inst_row,
                 l.label_scratch, cut)) {
      l.chips.push_back(std::move(cut));
    }
  }
}

}  // namespace

/// The chips of one image read back from its files; appends to the chip documents and result.
void write_chips(const fs::path& dir, const LabelImage& li, ImageLabels& il,
                 const LabelSetOptions& options, const LabelContext& context, ChipSinks& sinks,
                 LabelSetResult& result) {
  const std::size_t size = options.chip_size_px, stride = options.chip_stride_px;
  const std::size_t rows = il.cls.rows, cols = il.cls.cols;
  if (rows < size || cols < size) return;
  const ChipFrame frame = chip_frame(li, rows, il.image.ds.get(), context);
  const std::vector<int> colour = colour_bands(il.image);
  // The chip's rows and one more above and below (where a chip cuts a piece).
  const std::size_t window = size + 2;
  RowWindow img(il.image, colour, GDT_Byte, window);
  RowWindow cls(il.cls, {1}, GDT_Byte, window);
  RowWindow inst(il.inst, {1}, GDT_UInt32, window);
  // The sample values (grey chips, sample chips): a float raster on the same grid.
  const bool need_values = options.chip_color == LabelOutput::ChipColor::grey ||
                           options.chip_samples != LabelOutput::ChipSamples::none;
  Raster values;
  std::optional<RowWindow> val;
  DisplayRange range = context.display;
  std::vector<float> display;
  if (need_values) {
    if (li.values.empty()) {
      throw FormatError(std::string(kWho) + ": " + li.image +
                        ": no sample values for grey or sample chips");
    }
    values = open(dir, li.values);
    if (!context.display_fixed) {
      // The display copy's window: the percentiles of its values (robust_db_range's).
      std::vector<float> all(values.cols * values.rows);
      if (values.ds->GetRasterBand(1)->RasterIO(
              GF_Read, 0, 0, static_cast<int>(values.cols), static_cast<int>(values.rows),
              all.data(), static_cast<int>(values.cols), static_cast<int>(values.rows), GDT_Float32,
              0, 0, nullptr) != CE_None) {
        throw FormatError(std::string(kWho) + ": cannot read " + values.path);
      }
      range = robust_db_range(all, 1.0, 99.0);
    }
    val.emplace(values, std::vector<int>{1}, GDT_Float32, window);
    display.resize(window * cols);
  }
  ChipScratch scratch;
  const auto cls_row = [&](std::size_t y) { return cls.row<std::uint8_t>(0, y); };
  const auto inst_row = [&](std::size_t y) { return inst.row<std::uint32_t>(0, y); };
  const auto colour_row = [&](std::size_t b, std::size_t y) { return img.row<std::uint8_t>(b, y); };
  const auto value_row = [&](std::size_t y) { return val->row<float>(0, y); };
  const auto display_row = [&](std::size_t y) {
    float* d = display.data() + (y % window) * cols;
    const float* v = value_row(y);
    for (std::size_t i = 0; i < cols; ++i) d[i] = static_cast<float>(range.value(v[i]));
    return d;
  };
  for (std::size_t top = 0; top + size <= rows; top += stride) {
    const std::size_t first = top > 0 ? top - 1 : 0;
    img.move_to(first);
    cls.move_to(first);
    inst.move_to(first);
    if (val) val->move_to(first);
    for (std::size_t left = 0; left + size <= cols; left += stride) {
      const std::string stem = chip_stem(li.stem, top, left);
      ChipCut cut;
      if (!cut_chip(dir, stem, top, left, rows, cols, options, cls_row, inst_row, scratch, cut)) {
        continue;
      }
      write_chip_image(dir, stem, top, left, colour.size(), options, colour_row, display_row,
                       value_row, scratch);
      emit_chip(dir, li, stem, cut, cols, colour.size(), options, context, frame, sinks, result);
    }
  }
}

/// The bands of chips left when the line's last label row has come (no row below them).
void finish_line(LabelPass::Line& l, const fs::path& dir, const LabelSetOptions& o) {
  if (!o.chips) return;
  for (; l.next_top + o.chip_size_px <= l.label_rows; l.next_top += o.chip_stride_px) {
    cut_band(l, dir, o, l.next_top, l.label_rows);
  }
}

void remove_files(const fs::path& dir, const std::vector<fs::path>& files) {
  for (const fs::path& f : files) {
    std::error_code ec;
    fs::remove(dir / f, ec);
  }
}

/// The chips of a line cut in the pass: the records of those kept, the files of the others
/// removed; false (all its chip files removed) if the image and its labels differ in size.
bool emit_line_chips(const fs::path& dir, const LabelImage& li, LabelPass::Line& l,
                     const LabelSetOptions& options, const LabelContext& context, ChipSinks& sinks,
                     LabelSetResult& result) {
  const bool usable = l.image_rows == l.label_rows && l.image_cols == l.label_cols;
  std::set<std::string> kept;
  if (usable) {
    const ChipFrame frame = chip_frame(li, l.label_rows, nullptr, context);
    for (const ChipCut& cut : l.chips) {
      const std::string stem = chip_stem(l.stem, cut.top, cut.left);
      kept.insert(stem);
      emit_chip(dir, li, stem, cut, l.label_cols, l.bands, options, context, frame, sinks, result);
    }
  } else {
    for (const ChipCut& cut : l.chips) {
      remove_files(dir, chip_files(chip_stem(l.stem, cut.top, cut.left), options));
    }
  }
  for (const std::string& stem : l.image_chips) {
    if (!kept.count(stem)) remove_files(dir, chip_files(stem, options));
  }
  return usable;
}

}  // namespace label_parts

using namespace label_parts;

LabelPass::LabelPass(fs::path dir, LabelSetOptions options)
    : dir_(std::move(dir)), options_(options) {
  if (!options_.chips) return;
  for (const char* sub : {"images", "masks"}) fs::create_directories(dir_ / "chips" / sub);
  if (options_.chip_samples != LabelOutput::ChipSamples::none) {
    fs::create_directories(dir_ / "chips" / "samples");
  }
}

LabelPass::~LabelPass() = default;

LabelPass::Line& LabelPass::get(const std::string& name) {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::unique_ptr<Line>& l = lines_[name];
  if (!l) {
    l = std::make_unique<Line>();
    l->stem = name + "_waterfall";
  }
  return *l;
}

LabelPass::Line* LabelPass::line(const std::string& name) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = lines_.find(name);
  return it == lines_.end() ? nullptr : it->second.get();
}

Waterfall::RowTap LabelPass::image_tap(const std::string& name) {
  if (!options_.chips) return {};
  Line* l = &get(name);
  return [l, dir = dir_, o = options_](std::size_t row, std::span<const float> linear,
                                       std::span<const float> display,
                                       std::span<const std::uint8_t> colour, std::size_t bands) {
    const std::size_t size = o.chip_size_px, cols = linear.size();
    if (row == 0) {
      l->image_cols = cols;
      l->bands = bands;
      l->colour.assign(size * bands * cols, 0);
      l->linear.assign(size * cols, 0.0f);
      l->display.assign(size * cols, 0.0f);
    }
    if (cols != l->image_cols || bands != l->bands) return;  // not a waterfall of one width
    const std::size_t slot = row % size;
    std::copy(colour.begin(), colour.end(),
              l->colour.begin() + static_cast<std::ptrdiff_t>(slot * bands * cols));
    std::copy(linear.begin(), linear.end(),
              l->linear.begin() + static_cast<std::ptrdiff_t>(slot * cols));
    std::copy(display.begin(), display.end(),
              l->display.begin() + static_cast<std::ptrdiff_t>(slot * cols));
    l->image_rows = row + 1;
    if (row + 1 < size || (row + 1 - size) % o.chip_stride_px != 0) return;
    const std::size_t top = row + 1 - size;
    const auto colour_row = [&](std::size_t b, std::size_t y) {
      return l->colour.data() + ((y % size) * bands + b) * cols;
    };
    const auto display_row = [&](std::size_t y) { return l->display.data() + (y % size) * cols; };
    const auto value_row = [&](std::size_t y) { return l->linear.data() + (y % size) * cols; };
    for (std::size_t left = 0; left + size <= cols; left += o.chip_stride_px) {
      const std::string stem = chip_stem(l->stem, top, left);
      write_chip_image(dir, stem, top, left, bands, o, colour_row, display_row, value_row,
                       l->image_scratch);
      l->image_chips.push_back(stem);
    }
  };
}

TruthWaterfall::LabelRowTap LabelPass::label_tap(const std::string& name) {
  Line* l = &get(name);
  return [l, dir = dir_, o = options_](std::size_t row, std::span<const std::uint8_t> cls,
                                       std::span<const std::uint32_t> inst) {
    const std::size_t size = o.chip_size_px, window = size + 2, cols = cls.size();
    if (row == 0) {
      l->label_cols = cols;
      if (o.chips) {
        l->cls.assign(window * cols, 0);
        l->inst.assign(window * cols, 0);
      }
    }
    l->whole.add_row(row, cls, inst);
    l->label_rows = row + 1;
    if (!o.chips) return;
    std::copy(cls.begin(), cls.end(),
              l->cls.begin() + static_cast<std::ptrdiff_t>((row % window) * cols));
    std::copy(inst.begin(), inst.end(),
              l->inst.begin() + static_cast<std::ptrdiff_t>((row % window) * cols));
    // A band of chips is cut when the row below it has come (where a chip cuts a piece).
    for (; l->next_top + size <= row; l->next_top += o.chip_stride_px) {
      cut_band(*l, dir, o, l->next_top, l->label_rows);
    }
  };
}

}  // namespace sonarsynth::labels
