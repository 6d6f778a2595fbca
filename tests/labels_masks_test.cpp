// SPDX-License-Identifier: MIT
// Label masks (docs/labels.md): COCO RLE masks and polygons against the instance raster's
// pieces, VOC boxes against COCO's, and the YOLO directories as Ultralytics datasets.
#include <gtest/gtest.h>

#include "labels_test_util.hpp"

namespace sonarsynth {
namespace {

using namespace labels_test;

// Every annotation's RLE mask (decoded here) is its piece of the instance raster, pixel for
// pixel; its box is the mask's and its area the mask's pixels. VOC boxes are the COCO boxes in
// VOC's 1-based inclusive numbers; a chip's box is truncated where the chip cut the piece.
TEST_F(LabelsTest, MasksAndVocBoxesAreThoseOfTheInstancePieces) {
  const fs::path out = dir_ / "out";
  run("output: {labels: {coco: true, voc: true, chips: {size_px: 64, stride_px: 48}}}\n", out);
  std::map<std::string, std::pair<Raster, Raster>> sources;
  sources["a_waterfall.png"] = {read(out / "a_truth_class.tif"),
                                read(out / "a_truth_instance.tif")};
  sources["mosaic_rgb.tif"] = {read(out / "truth_mosaic_class.tif"),
                               read(out / "truth_mosaic_instance.tif")};
  // The annotations of one image against the pieces of its window (x0, y0, w, h).
  std::size_t checked = 0, truncated_boxes = 0;
  const auto check = [&](const json& anns, const std::string& voc_xml, const Raster& cls,
                         const Raster& inst, std::size_t x0, std::size_t y0, std::size_t w,
                         std::size_t h, bool chip) {
    const auto pieces = brute_pieces(cls, inst, x0, y0, w, h);
    ASSERT_EQ(anns.size(), pieces.size());
    const std::vector<std::string> objects = xml_all(voc_xml, "object");
    ASSERT_EQ(objects.size(), anns.size());
    for (std::size_t i = 0; i < anns.size(); ++i) {
      const json& a = anns[i];
      const BoxRow b = box_row(a);
      const auto it = std::find_if(pieces.begin(), pieces.end(),
                                   [&](const BrutePiece& p) { return p.box == b; });
      ASSERT_NE(it, pieces.end());
      const auto mask = decode_rle(a["segmentation"]);
      EXPECT_EQ(a["segmentation"]["size"], json({h, w}));
      ASSERT_EQ(mask, it->pixels);
      EXPECT_EQ(a["area"].get<std::size_t>(), mask.size());
      // The box is the mask's bounding box.
      std::size_t mx0 = w, my0 = h, mx1 = 0, my1 = 0;
      for (const auto& [x, y] : mask) {
        mx0 = std::min(mx0, x);
        my0 = std::min(my0, y);
        mx1 = std::max(mx1, x + 1);
        my1 = std::max(my1, y + 1);
      }
      EXPECT_EQ((BoxRow{b[0], b[1], mx0, my0, mx1, my1}), b);
      // Truncated: whole images where the box touches the edge; chips where a pixel of the same
      // instance and category lies across the chip's edge next to a pixel of the piece.
      bool cut = false;
      if (chip) {
        for (const auto& [x, y] : mask) {
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              const long sx = long(x0 + x) + dx, sy = long(y0 + y) + dy;
              if (sx < 0 || sy < 0 || sx >= long(cls.cols) || sy >= long(cls.rows)) continue;
              const bool outside =
                  sx < long(x0) || sy < long(y0) || sx >= long(x0 + w) || sy >= long(y0 + h);
              const std::size_t j = std::size_t(sy) * cls.cols + std::size_t(sx);
              if (outside && inst.values[j] == b[0] &&
                  std::size_t(category_of(cls.values[j])) == b[1]) {
                cut = true;
              }
            }
          }
        }
      } else {
        cut = b[2] == 0 || b[3] == 0 || b[4] == w || b[5] == h;
      }
      EXPECT_EQ(a["truncated"].get<int>(), cut ? 1 : 0);
      truncated_boxes += cut;
      // VOC: the same box, 1-based and inclusive.
      const std::string& o = objects[i];
      EXPECT_EQ(xml_one(o, "name"), b[1] == 1 ? "object" : "shadow");
      EXPECT_EQ(std::stoul(xml_one(o, "object_id")), b[0]);
      EXPECT_EQ(std::stoul(xml_one(o, "xmin")), b[2] + 1);
      EXPECT_EQ(std::stoul(xml_one(o, "ymin")), b[3] + 1);
      EXPECT_EQ(std::stoul(xml_one(o, "xmax")), b[4]);
      EXPECT_EQ(std::stoul(xml_one(o, "ymax")), b[5]);
      EXPECT_EQ(std::stoi(xml_one(o, "truncated")), cut ? 1 : 0);
      EXPECT_EQ(xml_one(o, "difficult"), "0");
      ++checked;
    }
  };
  for (const std::string set : {"waterfalls", "mosaic"}) {
    const json coco = read_json(out / (set + ".coco.json"));
    EXPECT_TRUE(coco["licenses"].is_array());
    EXPECT_TRUE(coco["licenses"].empty());
    ASSERT_EQ(coco["images"].size(), 1u);
    const json& im = coco["images"][0];
    const auto& [cls, inst] = sources.at(im["file_name"].get<std::string>());
    const std::string xml =
        file_text(out / "voc" / "Annotations" /
                  (fs::path(im["file_name"].get<std::string>()).stem().string() + ".xml"));
    EXPECT_EQ(xml_one(xml, "filename"), im["file_name"].get<std::string>());
    EXPECT_EQ(std::stoul(xml_one(xml, "width")), cls.cols);
    EXPECT_EQ(std::stoul(xml_one(xml, "height")), cls.rows);
    check(coco["annotations"], xml, cls, inst, 0, 0, cls.cols, cls.rows, false);
  }
  const json chips = read_json(out / "chips" / "coco.json");
  EXPECT_TRUE(chips["licenses"].is_array());
  std::map<int, json> chip_anns;
  for (const json& a : chips["annotations"]) chip_anns[a["image_id"].get<int>()].push_back(a);
  for (const json& im : chips["images"]) {
    SCOPED_TRACE(im["file_name"].get<std::string>());
    const auto& [cls, inst] = sources.at(im["source_image"].get<std::string>());
    const std::string stem = fs::path(im["file_name"].get<std::string>()).stem().string();
    const std::string xml = file_text(out / "chips" / "voc" / "Annotations" / (stem + ".xml"));
    EXPECT_EQ(xml_one(xml, "filename"), stem + ".png");
    EXPECT_TRUE(fs::exists(out / "chips" / xml_one(xml, "folder").substr(6) / (stem + ".png")));
    const json anns = chip_anns.count(im["id"]) ? chip_anns[im["id"]] : json::array();
    check(anns, xml, cls, inst, im["source_x0"], im["source_y0"], 64, 64, true);
  }
  EXPECT_GT(checked, 20u);
  EXPECT_GT(truncated_boxes, 0u);
}

// Polygons (rasterised here) cover exactly their pieces; `none` leaves the masks out.
TEST_F(LabelsTest, PolygonsCoverTheirPiecesAndNoneLeavesThemOut) {
  run("output: {labels: {coco: true, segmentation: polygon}}\n", dir_ / "poly");
  run("output: {labels: {coco: true, segmentation: none}}\n", dir_ / "none");
  std::size_t checked = 0;
  for (const auto& [set, cls_name, inst_name] :
       {std::tuple<std::string, std::string, std::string>{"waterfalls", "a_truth_class.tif",
                                                          "a_truth_instance.tif"},
        {"mosaic", "truth_mosaic_class.tif", "truth_mosaic_instance.tif"}}) {
    const Raster cls = read(dir_ / "poly" / cls_name);
    const Raster inst = read(dir_ / "poly" / inst_name);
    const auto pieces = brute_pieces(cls, inst);
    const json coco = read_json(dir_ / "poly" / (set + ".coco.json"));
    ASSERT_EQ(coco["annotations"].size(), pieces.size());
    for (const json& a : coco["annotations"]) {
      const BoxRow b = box_row(a);
      const auto it = std::find_if(pieces.begin(), pieces.end(),
                                   [&](const BrutePiece& p) { return p.box == b; });
      ASSERT_NE(it, pieces.end());
      bool inside_box = false;
      EXPECT_EQ(rasterise_polygons(a["segmentation"], b, inside_box), it->pixels);
      EXPECT_TRUE(inside_box);
      EXPECT_EQ(a["area"].get<std::size_t>(), it->pixels.size());
      ++checked;
    }
    const json bare = read_json(dir_ / "none" / (set + ".coco.json"));
    ASSERT_EQ(bare["annotations"].size(), pieces.size());
    for (const json& a : bare["annotations"]) EXPECT_FALSE(a.contains("segmentation"));
  }
  EXPECT_GT(checked, 4u);
}

// yolo/ and chips/ are Ultralytics datasets: data.yaml, images/ beside labels/ (same stems).
TEST_F(LabelsTest, YoloIsAnUltralyticsDataset) {
  const fs::path out = dir_ / "out";
  run(kLabels, out);
  for (const std::string root : {"yolo", "chips"}) {
    const std::string yaml = file_text(out / root / "data.yaml");
    // No `path:`: the dataset root is the file's directory, and the file is the same wherever
    // the run is written (a dataset item is staged elsewhere, then renamed).
    EXPECT_EQ(yaml.find("path:"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("\ntrain: images\n"), std::string::npos);
    EXPECT_NE(yaml.find("\nval: images\n"), std::string::npos);
    EXPECT_NE(yaml.find("\nnames:\n  0: object\n  1: shadow\n"), std::string::npos);
    std::size_t images = 0;
    for (const auto& e : fs::directory_iterator(out / root / "images")) {
      // Ultralytics: the label file is the image's path with /images/ -> /labels/, .txt.
      std::string label = e.path().string();
      label.replace(label.rfind("/images/"), 8, "/labels/");
      EXPECT_TRUE(fs::exists(fs::path(label).replace_extension(".txt"))) << e.path();
      ++images;
    }
    EXPECT_GT(images, 0u);
  }
  EXPECT_EQ(file_text(out / "yolo" / "images" / "a_waterfall.png"),
            file_text(out / "a_waterfall.png"));
  EXPECT_EQ(file_text(out / "yolo" / "images" / "mosaic_rgb.tif"),
            file_text(out / "mosaic_rgb.tif"));
}

}  // namespace
}  // namespace sonarsynth
