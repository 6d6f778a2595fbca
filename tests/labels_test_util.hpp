// SPDX-License-Identifier: MIT
// The run, scene and independent decoders shared by the label tests (labels_test.cpp,
// labels_masks_test.cpp, labels_chips_test.cpp): COCO RLE and polygons, VOC XML and the
// 8-connected pieces of the label rasters recomputed here (docs/labels.md).
#pragma once

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "label_check_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/config/label_sets.hpp"
#include "sonarsynth/formats/config/run_simulation.hpp"
#include "sonarsynth/formats/products/truth_labels.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth::labels_test {

namespace fs = std::filesystem;
using nlohmann::json;

// Two boxes well apart on either side of one line, on a flat seabed.
inline constexpr const char* kScene = R"(
name: labels
seed: 11
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [120, 120], cell_m: 0.5, depth_m: 12}
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 2.0
  altitude_m: 5
  lines:
    - {name: a, waypoints: [{east_m: -40, north_m: 0}, {east_m: 40, north_m: 0}]}
objects:
  - {type: box, id: 3, position: {east_m: -10, north_m: 9}, size_m: [3, 1.5, 1.2]}
  - {type: box, id: 7, position: {east_m: 15, north_m: -11}, size_m: [2, 2, 1.0]}
sonar: {frequency_khz: 600, range_m: 25, samples: 500}
)";

inline constexpr const char* kLabels =
    "output: {labels: {coco: true, yolo: true, chips: {size_px: 64, stride_px: 48}}}\n";

using Raster = test::LabelRaster;
using test::BoxRow;
using test::brute_boxes;
using test::category_of;
inline Raster read(const fs::path& path) {
  return test::read_label_raster(path);
}

using test::brute_pieces;
using test::BrutePiece;

// COCO uncompressed RLE decoded (column-major counts, alternating from 0): the pixels set.
inline std::set<std::pair<std::size_t, std::size_t>> decode_rle(const json& rle) {
  const std::size_t h = rle["size"][0], w = rle["size"][1];
  std::set<std::pair<std::size_t, std::size_t>> out;
  std::size_t at = 0;
  bool one = false;
  for (const json& c : rle["counts"]) {
    const std::size_t n = c;
    if (one) {
      for (std::size_t i = at; i < at + n; ++i) out.insert({i / h, i % h});
    }
    at += n;
    one = !one;
  }
  EXPECT_EQ(at, w * h);
  return out;
}

// COCO polygons rasterised in the box [x0, x1) x [y0, y1): the pixels whose centre is inside
// one of them (even-odd rule); false in `inside_box` if a vertex lies outside the box.
inline std::set<std::pair<std::size_t, std::size_t>> rasterise_polygons(const json& polygons,
                                                                        const BoxRow& b,
                                                                        bool& inside_box) {
  std::set<std::pair<std::size_t, std::size_t>> out;
  inside_box = true;
  for (const json& poly : polygons) {
    for (std::size_t i = 0; i + 1 < poly.size(); i += 2) {
      const double x = poly[i], y = poly[i + 1];
      if (x < double(b[2]) || x > double(b[4]) || y < double(b[3]) || y > double(b[5])) {
        inside_box = false;
      }
    }
  }
  for (std::size_t y = b[3]; y < b[5]; ++y) {
    for (std::size_t x = b[2]; x < b[4]; ++x) {
      const double px = static_cast<double>(x) + 0.5, py = static_cast<double>(y) + 0.5;
      for (const json& poly : polygons) {
        const std::size_t n = poly.size() / 2;
        bool inside = false;
        for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
          const double xi = poly[2 * i], yi = poly[2 * i + 1], xj = poly[2 * j],
                       yj = poly[2 * j + 1];
          if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi) {
            inside = !inside;
          }
        }
        if (inside) {
          out.insert({x, y});
          break;
        }
      }
    }
  }
  return out;
}

// The text of each <tag>...</tag> in `xml`, in order.
inline std::vector<std::string> xml_all(const std::string& xml, const std::string& tag) {
  std::vector<std::string> out;
  const std::string open = "<" + tag + ">", close = "</" + tag + ">";
  for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at)) {
    const std::size_t end = xml.find(close, at);
    out.push_back(xml.substr(at + open.size(), end - at - open.size()));
    at = end;
  }
  return out;
}
inline std::string xml_one(const std::string& xml, const std::string& tag) {
  const auto all = xml_all(xml, tag);
  EXPECT_EQ(all.size(), 1u) << tag;
  return all.empty() ? std::string() : all[0];
}

inline std::string file_text(const fs::path& p) {
  std::ifstream is(p, std::ios::binary);
  EXPECT_TRUE(is.good()) << p;
  return std::string(std::istreambuf_iterator<char>(is), {});
}

inline BoxRow box_row(const json& a) {
  const auto& b = a["bbox"];
  const std::size_t x = b[0], y = b[1], w = b[2], h = b[3];
  return {
      a["object_id"].get<std::size_t>(), a["category_id"].get<std::size_t>(), x, y, x + w, y + h};
}

inline json read_json(const fs::path& p) {
  std::ifstream is(p);
  EXPECT_TRUE(is.good()) << p;
  return json::parse(is);
}

class LabelsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sonarsynth_labels_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    scene_ = (dir_ / "scene.yaml").string();
  }
  void TearDown() override { fs::remove_all(dir_); }
  RunResult run(const std::string& extra, const fs::path& out, unsigned threads = 0,
                bool overwrite = false) {
    std::ofstream(scene_) << kScene << extra;
    RunOptions o;
    o.overwrite = overwrite;
    if (threads) o.overrides.threads = threads;
    return run_simulation(scene_, out, o);
  }
  fs::path dir_;
  std::string scene_;
};

}  // namespace sonarsynth::labels_test
