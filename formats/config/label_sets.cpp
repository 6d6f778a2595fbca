// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/config/label_sets.hpp"

#include <gdal_priv.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

#include "sonarsynth/formats/raster/raster_util.hpp"
#include "sonarsynth/colormap.hpp"
#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/version.hpp"
#include "sonarsynth/formats/products/truth_labels.hpp"

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
  doc["licenses"] = Json::array();
  doc["images"] = Json::array();
  doc["annotations"] = Json::array();
  doc["categories"] = categories();
  return doc;
}

/// The piece as rectangles of pixel edges (runs of equal extent in consecutive rows merged),
/// each a COCO polygon [x0, y0, x1, y0, x1, y1, x0, y1]: together exactly the piece's pixels.
Json polygons(const Piece& piece) {
  struct Rect {
    std::size_t x0, x1, y0, y1;
  };
  std::vector<Rect> rects;
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> open;  // (x0, x1) -> rect
  for (const PixelRun& r : piece.runs) {
    const auto it = open.find({r.x0, r.x1});
    if (it != open.end() && rects[it->second].y1 == r.y) {
      rects[it->second].y1 = r.y + 1;
    } else {
      open[{r.x0, r.x1}] = rects.size();
      rects.push_back({r.x0, r.x1, r.y, r.y + 1});
    }
  }
  Json out = Json::array();
  for (const Rect& q : rects) out.push_back({q.x0, q.y0, q.x1, q.y0, q.x1, q.y1, q.x0, q.y1});
  return out;
}

Json segmentation(const Piece& piece, std::size_t width, std::size_t height,
                  LabelOutput::Segmentation mode) {
  if (mode == LabelOutput::Segmentation::polygon) return polygons(piece);
  return {{"size", {height, width}}, {"counts", coco_rle_counts(piece, width, height)}};
}

void add_annotations(Json& doc, int image_id, const std::vector<Piece>& pieces, std::size_t width,
                     std::size_t height, const LabelSetOptions& options,
                     const std::vector<bool>& truncated) {
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Box& b = pieces[i].box;
    const auto id = static_cast<int>(doc["annotations"].size()) + 1;
    Json a = {{"id", id}, {"image_id", image_id}, {"category_id", b.category}};
    if (options.segmentation != LabelOutput::Segmentation::none) {
      a["segmentation"] = segmentation(pieces[i], width, height, options.segmentation);
    }
    a["area"] = b.pixels;
    a["bbox"] = {b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0};
    a["iscrowd"] = 0;
    a["object_id"] = b.instance;
    a["truncated"] = truncated[i] ? 1 : 0;
    doc["annotations"].push_back(std::move(a));
  }
}

std::string yolo_text(const std::vector<Piece>& pieces, std::size_t width, std::size_t height) {
  std::string s;
  char line[160];
  const auto w = static_cast<double>(width), h = static_cast<double>(height);
  for (const Piece& piece : pieces) {
    const Box& b = piece.box;
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

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// Pascal VOC annotation of one image: `folder` and `filename` of the image (relative to the
/// output directory), bndbox in VOC's 1-based inclusive pixel numbers (docs/labels.md).
std::string voc_xml(const std::string& folder, const std::string& filename, std::size_t width,
                    std::size_t height, std::size_t depth, const std::vector<Piece>& pieces,
                    const std::vector<bool>& truncated) {
  std::ostringstream os;
  os << "<annotation>\n"
     << "  <folder>" << xml_escape(folder) << "</folder>\n"
     << "  <filename>" << xml_escape(filename) << "</filename>\n"
     << "  <source><database>sonarsynth</database><annotation>docs/labels.md</annotation>"
     << "</source>\n"
     << "  <size><width>" << width << "</width><height>" << height << "</height><depth>" << depth
     << "</depth></size>\n"
     << "  <segmented>0</segmented>\n";
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Box& b = pieces[i].box;
    os << "  <object>\n"
       << "    <name>" << (b.category == kCategoryObject ? "object" : "shadow") << "</name>\n"
       << "    <object_id>" << b.instance << "</object_id>\n"
       << "    <pose>Unspecified</pose>\n"
       << "    <truncated>" << (truncated[i] ? 1 : 0) << "</truncated>\n"
       << "    <difficult>0</difficult>\n"
       << "    <bndbox><xmin>" << b.x0 + 1 << "</xmin><ymin>" << b.y0 + 1 << "</ymin><xmax>" << b.x1
       << "</xmax><ymax>" << b.y1 << "</ymax></bndbox>\n"
       << "  </object>\n";
  }
  os << "</annotation>\n";
  return os.str();
}

/// `link` a hard link to `target` (a copy where the file system cannot link).
void link_or_copy(const fs::path& target, const fs::path& link) {
  std::error_code ec;
  fs::remove(link, ec);
  fs::create_hard_link(target, link, ec);
  if (!ec) return;
  fs::copy_file(target, link, fs::copy_options::overwrite_existing, ec);
  if (ec) {
    throw FormatError(std::string(kWho) + ": " + link.string() + ": cannot link or copy " +
                      target.string() + ": " + ec.message());
  }
}

/// Ultralytics YOLO dataset description of the directory it is written in (images/ beside
/// labels/). No `path:`: Ultralytics then takes the directory of this file (give it the file's
/// absolute path), and the file stays the same wherever the directory is written or moved.
std::string data_yaml() {
  return "# sonarsynth labels (docs/labels.md): an Ultralytics YOLO dataset. The label file of\n"
         "# images/<stem>.<ext> is labels/<stem>.txt. Train and val list the same images: split\n"
         "# them as the experiment needs. The dataset root is this file's directory.\n"
         "train: images\n"
         "val: images\n"
         "names:\n"
         "  0: object\n"
         "  1: shadow\n";
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

/// {"x_m", "y_m", "lat_deg", "lon_deg"} of a local point, or null if unknown.
Json ground_point(const LabelContext& context, double x_m, double y_m) {
  if (!std::isfinite(x_m) || !std::isfinite(y_m)) return nullptr;
  Json p = {{"x_m", x_m}, {"y_m", y_m}};
  if (context.frame) {
    const Eigen::Vector2d en = context.frame->projected_from_local({x_m, y_m});
    const Geodetic g = context.frame->geodetic_from_local({x_m, y_m});
    p["easting_m"] = en.x();
    p["northing_m"] = en.y();
    p["lat_deg"] = deg_from_rad(g.lat_rad);
    p["lon_deg"] = deg_from_rad(g.lon_rad);
  }
  return p;
}

/// The source image's geometry for the chip records (chips.jsonl, docs/labels.md).
struct ChipFrame {
  const LineTrack* track = nullptr;  ///< a waterfall's
  bool geo = false;                  ///< a georeferenced image (the mosaic)
  double gt[6] = {0, 1, 0, 0, 0, 1};
};

ChipFrame chip_frame(const LabelImage& li, std::size_t rows, GDALDataset* image,
                     const LabelContext& context) {
  ChipFrame f;
  if (!li.line.empty()) {
    for (std::size_t l = 0; l < context.line_names.size(); ++l) {
      if (context.line_names[l] == li.line && context.tracks && l < context.tracks->size() &&
          (*context.tracks)[l].along_track_m.size() == rows) {
        f.track = &(*context.tracks)[l];
      }
    }
  } else if (image) {
    f.geo = image->GetGeoTransform(f.gt) == CE_None;
  }
  return f;
}

/// The provenance record of one chip (a line of chips/chips.jsonl, docs/labels.md).
Json chip_record(const std::string& file, const LabelImage& li, const ChipFrame& f,
                 const LabelContext& context, std::size_t top, std::size_t left, std::size_t size,
                 std::size_t cols, const std::vector<Piece>& pieces,
                 const std::vector<bool>& truncated) {
  Json r = {{"file", file}, {"source_image", li.image}, {"pixel_box", {left, top, size, size}}};
  const std::size_t crow = top + size / 2, ccol = left + size / 2;
  const std::size_t corner_px[4][2] = {{top, left},
                                       {top, left + size - 1},
                                       {top + size - 1, left + size - 1},
                                       {top + size - 1, left}};
  Json boxes = Json::array();
  if (!li.line.empty()) {
    const std::size_t side = cols / 2;
    const double dr = context.sample_spacing_m;
    r["line"] = li.line;
    r["pings"] = {top, top + size - 1};
    r["columns"] = {left, left + size - 1};
    Json sides = Json::array();
    if (left < side) {
      sides.push_back("port");
      // Port columns run FAR -> NEAR: column c is sample side - 1 - c (0 = nearest).
      r["port_samples"] = {side - std::min(side, left + size), side - 1 - left};
    }
    if (left + size > side) {
      sides.push_back("starboard");
      r["starboard_samples"] = {std::max(left, side) - side, left + size - 1 - side};
    }
    r["sides"] = sides;
    double x = NAN, y = NAN;
    if (f.track && f.track->ground_xy(crow, ccol, x, y)) r["centre"] = ground_point(context, x, y);
    Json corners = Json::array();
    for (const auto& c : corner_px) {
      x = y = NAN;
      if (f.track) f.track->ground_xy(c[0], c[1], x, y);
      corners.push_back(ground_point(context, x, y));
    }
    r["corners"] = corners;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const Box& b = pieces[i].box;
      Json jb = {{"object_id", b.instance},
                 {"category_id", b.category},
                 {"truncated", truncated[i] ? 1 : 0},
                 {"bbox_px", {b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0}}};
      if (f.track) {
        jb["along_track_m"] = {f.track->along_track_m[top + b.y0],
                               f.track->along_track_m[top + b.y1 - 1]};
      }
      // Signed slant range of the box's column edges: port negative, starboard positive.
      jb["across_track_slant_m"] = {
          (static_cast<double>(left + b.x0) - static_cast<double>(side)) * dr,
          (static_cast<double>(left + b.x1) - static_cast<double>(side)) * dr};
      boxes.push_back(std::move(jb));
    }
  } else if (f.geo) {
    const auto east = [&](double col) { return f.gt[0] + col * f.gt[1] + 0.0 * f.gt[2]; };
    const auto north = [&](double row) { return f.gt[3] + row * f.gt[5]; };
    const auto point = [&](double col, double row) {
      const Eigen::Vector2d en(east(col), north(row));
      if (!context.frame) return Json{{"easting_m", en.x()}, {"northing_m", en.y()}};
      const Eigen::Vector2d xy = context.frame->local_from_projected(en);
      return ground_point(context, xy.x(), xy.y());
    };
    r["centre"] = point(static_cast<double>(ccol) + 0.5, static_cast<double>(crow) + 0.5);
    Json corners = Json::array();
    for (const auto& c : corner_px) {
      corners.push_back(point(static_cast<double>(c[1]) + 0.5, static_cast<double>(c[0]) + 0.5));
    }
    r["corners"] = corners;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const Box& b = pieces[i].box;
      const auto x0 = static_cast<double>(left + b.x0), x1 = static_cast<double>(left + b.x1);
      const auto y0 = static_cast<double>(top + b.y0), y1 = static_cast<double>(top + b.y1);
      boxes.push_back(
          {{"object_id", b.instance},
           {"category_id", b.category},
           {"truncated", truncated[i] ? 1 : 0},
           {"bbox_px", {b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0}},
           {"easting_m", {std::min(east(x0), east(x1)), std::max(east(x0), east(x1))}},
           {"northing_m", {std::min(north(y0), north(y1)), std::max(north(y0), north(y1))}}});
    }
  }
  r["boxes"] = boxes;
  return r;
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

struct ChipSinks {
  Json coco;
  std::string jsonl;
};

std::string chip_stem(const std::string& stem, std::size_t top, std::size_t left) {
  char suffix[64];
  std::snprintf(suffix, sizeof suffix, "_r%06zu_c%06zu", top, left);
  return stem + suffix;
}

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
    runs_.push_back({{y, r.x0, r.x1}, r.part});
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

std::vector<Piece> BoxAccumulator::pieces() const {
  const auto find = [this](std::size_t p) {
    while (parent_[p] != p) p = parent_[p];
    return p;
  };
  std::vector<std::size_t> index(parts_.size(), 0);
  std::vector<Piece> out;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    if (parent_[i] != i) continue;
    index[i] = out.size();
    out.push_back({parts_[i], {}});
  }
  // Runs were recorded row by row, left to right: each piece's stay sorted by (y, x0).
  for (const auto& [run, part] : runs_) out[index[find(part)]].runs.push_back(run);
  std::sort(out.begin(), out.end(), [](const Piece& p, const Piece& q) {
    const Box &a = p.box, &b = q.box;
    return std::tie(a.instance, a.category, a.y0, a.x0, a.y1, a.x1) <
           std::tie(b.instance, b.category, b.y0, b.x0, b.y1, b.x1);
  });
  return out;
}

std::vector<std::uint64_t> coco_rle_counts(const Piece& piece, std::size_t width,
                                           std::size_t height) {
  const Box& b = piece.box;
  const std::size_t bw = b.x1 - b.x0, bh = b.y1 - b.y0;
  // The piece's pixels in its box, column-major.
  std::vector<std::uint8_t> mask(bw * bh, 0);
  for (const PixelRun& r : piece.runs) {
    for (std::size_t x = r.x0; x < r.x1; ++x) mask[(x - b.x0) * bh + (r.y - b.y0)] = 1;
  }
  // Runs of 1 in the image's column-major order (pixel index x height + y), joined across
  // columns where one ends at the bottom row and the next starts at the top.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> ones;  // [start, end)
  for (std::size_t x = 0; x < bw; ++x) {
    for (std::size_t y = 0; y < bh; ++y) {
      if (!mask[x * bh + y]) continue;
      const std::uint64_t at = static_cast<std::uint64_t>(b.x0 + x) * height + (b.y0 + y);
      if (!ones.empty() && ones.back().second == at) {
        ones.back().second = at + 1;
      } else {
        ones.push_back({at, at + 1});
      }
    }
  }
  std::vector<std::uint64_t> counts;
  std::uint64_t at = 0;
  for (const auto& [start, end] : ones) {
    counts.push_back(start - at);
    counts.push_back(end - start);
    at = end;
  }
  const std::uint64_t total = static_cast<std::uint64_t>(width) * height;
  if (at < total) counts.push_back(total - at);
  return counts;
}

bool LineTrack::ground_xy(std::size_t row, std::size_t column, double& x_m, double& y_m) const {
  const auto it = std::lower_bound(columns.begin(), columns.end(), column);
  if (it == columns.end() || *it != column || row >= along_track_m.size()) return false;
  const std::size_t i = row * columns.size() + static_cast<std::size_t>(it - columns.begin());
  x_m = ground_x_m[i];
  y_m = ground_y_m[i];
  return true;
}

std::vector<std::size_t> chip_columns(std::size_t cols, const LabelSetOptions& options) {
  std::vector<std::size_t> out;
  const std::size_t size = options.chip_size_px, stride = options.chip_stride_px;
  for (std::size_t left = 0; left + size <= cols; left += stride) {
    out.insert(out.end(), {left, left + size / 2, left + size - 1});
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

TrackRecorder::TrackRecorder(std::size_t lines, std::size_t side, std::vector<std::size_t> columns)
    : side_(side), columns_(std::move(columns)), tracks_(lines) {}

void TrackRecorder::begin_line(std::size_t line) {
  if (line >= tracks_.size()) tracks_.resize(line + 1);
  current_ = &tracks_[line];
  current_->columns = columns_;
}

void TrackRecorder::ping(const RenderedPing& p) {
  // The rows of the label rasters: the pings with truth (formats/products/survey_products.cpp).
  if (!current_ || p.port.truth_class.empty()) return;
  LineTrack& t = *current_;
  const Eigen::Vector2d xy = p.pose.sensor_xy_m;
  t.along_track_m.push_back(
      t.along_track_m.empty() ? 0.0 : t.along_track_m.back() + (xy - last_xy_).norm());
  last_xy_ = xy;
  for (const std::size_t c : columns_) {
    // Port columns run FAR -> NEAR (column c is port sample side - 1 - c), starboard NEAR -> FAR.
    const SideOutput& s = c < side_ ? p.port : p.starboard;
    const std::size_t k = c < side_ ? side_ - 1 - c : c - side_;
    const Eigen::Vector2d g = k < s.truth_ground_range_m.size()
                                  ? s.truth_ground_xy(k)
                                  : Eigen::Vector2d::Constant(SideOutput::kNoPosition);
    t.ground_x_m.push_back(g.x());
    t.ground_y_m.push_back(g.y());
  }
}

struct LabelPass::Line {
  std::string stem;  ///< of the chips: "<line>_waterfall"
  // The image side (the waterfall writer's thread): the last chip_size_px rows.
  std::size_t image_rows = 0, image_cols = 0, bands = 0;
  std::vector<std::uint8_t> colour;  ///< rows of bands x cols, row y in slot y % size
  std::vector<float> linear, display;
  std::vector<std::string> image_chips;  ///< stems of the chip images written
  ChipScratch image_scratch;
  // The label side (the truth writer's thread): the last chip_size_px + 2 rows.
  std::size_t label_rows = 0, label_cols = 0;
  BoxAccumulator whole;
  std::vector<std::uint8_t> cls;
  std::vector<std::uint32_t> inst;
  std::size_t next_top = 0;    ///< the next band of chips to cut
  std::vector<ChipCut> chips;  ///< the chips kept, their masks written
  ChipScratch label_scratch;
};

namespace {

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

/// The bands of chips left when the line's last label row has come (no row below them).
void finish_line(LabelPass::Line& l, const fs::path& dir, const LabelSetOptions& o) {
  if (!o.chips) return;
  for (; l.next_top + o.chip_size_px <= l.label_rows; l.next_top += o.chip_stride_px) {
    cut_band(l, dir, o, l.next_top, l.label_rows);
  }
}

}  // namespace

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

namespace {

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
