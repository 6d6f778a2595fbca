// SPDX-License-Identifier: MIT
// The label sets' text: COCO JSON, YOLO text and Pascal VOC XML (docs/labels.md).
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "sonarsynth/formats/config/label_set_parts.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth::labels::label_parts {
namespace {

Json categories() {
  return Json::array({{{"id", kCategoryObject}, {"name", "object"}, {"supercategory", "target"}},
                      {{"id", kCategoryShadow}, {"name", "shadow"}, {"supercategory", "target"}}});
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

}  // namespace

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

}  // namespace sonarsynth::labels::label_parts
