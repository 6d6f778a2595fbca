// SPDX-License-Identifier: MIT
#include "label_sets.hpp"

#include <gdal_priv.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
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

/// Ultralytics YOLO dataset description of `root` (images/ beside labels/).
std::string data_yaml(const fs::path& root) {
  return "# sonarsynth labels (docs/labels.md): an Ultralytics YOLO dataset. The label file of\n"
         "# images/<stem>.<ext> is labels/<stem>.txt. Train and val list the same images: split\n"
         "# them as the experiment needs.\n"
         "path: " +
         root.string() +
         "\n"
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

ChipFrame chip_frame(const LabelImage& li, ImageLabels& il, const LabelContext& context) {
  ChipFrame f;
  if (!li.line.empty()) {
    for (std::size_t l = 0; l < context.line_names.size(); ++l) {
      if (context.line_names[l] == li.line && context.tracks && l < context.tracks->size() &&
          (*context.tracks)[l].along_track_m.size() == il.cls.rows) {
        f.track = &(*context.tracks)[l];
      }
    }
  } else {
    f.geo = il.image.ds->GetGeoTransform(f.gt) == CE_None;
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

/// The chips of one image; appends to the chip documents and result.
void write_chips(const fs::path& dir, const LabelImage& li, ImageLabels& il,
                 const LabelSetOptions& options, const LabelContext& context, ChipSinks& sinks,
                 LabelSetResult& result) {
  const std::size_t size = options.chip_size_px, stride = options.chip_stride_px;
  const std::size_t rows = il.cls.rows, cols = il.cls.cols;
  if (rows < size || cols < size) return;
  const ChipFrame frame = chip_frame(li, il, context);
  const std::vector<int> colour = colour_bands(il.image);
  // The chip's rows and one more above and below (where a chip cuts a piece).
  const std::size_t window = size + 2;
  RowWindow img(il.image, colour, GDT_Byte, window);
  RowWindow cls(il.cls, {1}, GDT_Byte, window);
  RowWindow inst(il.inst, {1}, GDT_UInt32, window);
  std::vector<std::uint8_t> chip_img(colour.size() * size * size), chip_cls(size * size);
  std::vector<std::uint32_t> chip_inst(size * size);
  const auto limit =
      static_cast<std::size_t>(options.chip_max_nodata_fraction * static_cast<double>(size * size));
  const auto key = [&](std::size_t x, std::size_t y) {
    const std::uint32_t k = inst.row<std::uint32_t>(0, y)[x];
    const int c = category_of(cls.row<std::uint8_t>(0, y)[x]);
    if (k == 0 || k == kInstanceNodata || c == 0) return std::pair<int, std::uint32_t>{0, 0};
    return std::pair<int, std::uint32_t>{c, k};
  };
  for (std::size_t top = 0; top + size <= rows; top += stride) {
    const std::size_t first = top > 0 ? top - 1 : 0;
    img.move_to(first);
    cls.move_to(first);
    inst.move_to(first);
    for (std::size_t left = 0; left + size <= cols; left += stride) {
      std::size_t nodata = 0;
      BoxAccumulator acc;
      for (std::size_t r = 0; r < size; ++r) {
        const std::uint8_t* c = cls.row<std::uint8_t>(0, top + r) + left;
        const std::uint32_t* k = inst.row<std::uint32_t>(0, top + r) + left;
        std::copy(c, c + size, chip_cls.begin() + static_cast<std::ptrdiff_t>(r * size));
        std::copy(k, k + size, chip_inst.begin() + static_cast<std::ptrdiff_t>(r * size));
        nodata += static_cast<std::size_t>(std::count(c, c + size, kClassNodata));
        acc.add_row(r, {c, size}, {k, size});
      }
      if (nodata == size * size || nodata > limit) continue;
      for (std::size_t r = 0; r < size; ++r) {
        for (std::size_t b = 0; b < colour.size(); ++b) {
          const std::uint8_t* p = img.row<std::uint8_t>(b, top + r) + left;
          std::copy(p, p + size,
                    chip_img.begin() + static_cast<std::ptrdiff_t>((b * size + r) * size));
        }
      }
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
      const std::vector<Piece> pieces = acc.pieces();
      const std::vector<bool> truncated = chip_truncated(pieces, top, left, size, cols, rows, key);
      if (options.yolo) {
        const fs::path rel = fs::path("chips") / "labels" / (stem + ".txt");
        write_text(dir / rel, yolo_text(pieces, size, size));
        result.files.push_back(rel);
      }
      if (options.voc) {
        const fs::path rel = fs::path("chips") / "voc" / "Annotations" / (stem + ".xml");
        write_text(dir / rel, voc_xml("chips/images", stem + ".png", size, size, colour.size(),
                                      pieces, truncated));
        result.files.push_back(rel);
      }
      if (options.coco) {
        Json& coco = sinks.coco;
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
        add_annotations(coco, image_id, pieces, size, size, options, truncated);
      }
      sinks.jsonl += chip_record("images/" + stem + ".png", li, frame, context, top, left, size,
                                 cols, pieces, truncated)
                         .dump() +
                     "\n";
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
  // The rows of the label rasters: the pings with truth (formats/survey_products.cpp).
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
    const bool have = k < s.truth_ground_x_m.size() && k < s.truth_ground_y_m.size();
    t.ground_x_m.push_back(have ? s.truth_ground_x_m[k] : NAN);
    t.ground_y_m.push_back(have ? s.truth_ground_y_m[k] : NAN);
  }
}

LabelSetResult write_label_sets(const fs::path& dir, const std::vector<LabelImage>& waterfalls,
                                const std::vector<LabelImage>& mosaic,
                                const LabelSetOptions& options, const LabelContext& context) {
  LabelSetResult result;
  if (!options.any()) return result;
  gdal::ensure_registered();
  const fs::path root = context.final_dir.empty() ? fs::absolute(dir) : context.final_dir;
  if (options.yolo) {
    for (const char* sub : {"images", "labels"}) fs::create_directories(dir / "yolo" / sub);
  }
  if (options.voc) fs::create_directories(dir / "voc" / "Annotations");
  if (options.chips) {
    for (const char* sub : {"images", "masks"}) fs::create_directories(dir / "chips" / sub);
    if (options.yolo) fs::create_directories(dir / "chips" / "labels");
    if (options.voc) fs::create_directories(dir / "chips" / "voc" / "Annotations");
  }
  ChipSinks chips{coco_document("sonarsynth chips of the waterfalls and the mosaic"), {}};
  const std::pair<const char*, const std::vector<LabelImage>*> sets[2] = {
      {"waterfalls", &waterfalls}, {"mosaic", &mosaic}};
  for (const auto& [set, images] : sets) {
    Json coco = coco_document(std::string("sonarsynth ") + set);
    for (const LabelImage& li : *images) {
      ImageLabels il;
      if (!open_image(dir, li, il, result.notes)) continue;
      const std::size_t cols = il.cls.cols, rows = il.cls.rows;
      if (options.coco || options.yolo || options.voc) {
        const std::vector<Piece> pieces = whole_image_pieces(il);
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
          write_text(dir / rel, voc_xml(".", li.image, cols, rows, colour_bands(il.image).size(),
                                        pieces, truncated));
          result.files.push_back(rel);
        }
      }
      if (options.chips) write_chips(dir, li, il, options, context, chips, result);
    }
    if (options.coco && !images->empty()) {
      const std::string name = std::string(set) + ".coco.json";
      write_text(dir / name, coco.dump(1) + "\n");
      result.files.emplace_back(name);
    }
  }
  if (options.yolo) {
    write_text(dir / "yolo" / "data.yaml", data_yaml(root / "yolo"));
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
      write_text(dir / "chips" / "data.yaml", data_yaml(root / "chips"));
      result.files.push_back(fs::path("chips") / "data.yaml");
    }
  }
  return result;
}

}  // namespace sonarsynth::labels
