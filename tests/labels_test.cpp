// SPDX-License-Identifier: MIT
// Machine-learning labels (docs/labels.md): the class and instance rasters of a run, and the
// COCO / YOLO boxes and chips computed from them, checked against the rasters read back with GDAL
// and boxes recomputed here independently.
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

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// Two boxes well apart on either side of one line, on a flat seabed.
const char* const kScene = R"(
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

const char* const kLabels =
    "output: {labels: {coco: true, yolo: true, chips: {size_px: 64, stride_px: 48}}}\n";

using Raster = test::LabelRaster;
using test::BoxRow;
using test::brute_boxes;
using test::category_of;
Raster read(const fs::path& path) {
  return test::read_label_raster(path);
}

// The 8-connected pieces of a window with their pixels (x, y relative to the window), in the
// order of brute_boxes.
struct BrutePiece {
  BoxRow box;
  std::set<std::pair<std::size_t, std::size_t>> pixels;  // (x, y)
};
std::vector<BrutePiece> brute_pieces(const Raster& cls, const Raster& inst, std::size_t x0 = 0,
                                     std::size_t y0 = 0, std::size_t w = 0, std::size_t h = 0) {
  if (w == 0) {
    w = cls.cols;
    h = cls.rows;
  }
  auto key = [&](std::size_t x, std::size_t y) {
    const std::size_t i = (y0 + y) * cls.cols + x0 + x;
    const std::uint32_t k = inst.values[i];
    const int c = category_of(cls.values[i]);
    if (k == labels::kInstanceNodata || c == 0) return std::pair<std::uint32_t, int>{0, 0};
    return std::pair<std::uint32_t, int>{k, c};
  };
  std::vector<int> piece(w * h, -1);
  std::vector<BrutePiece> out;
  for (std::size_t y = 0; y < h; ++y) {
    for (std::size_t x = 0; x < w; ++x) {
      const auto k = key(x, y);
      if (k.first == 0 || piece[y * w + x] >= 0) continue;
      BrutePiece p;
      p.box = {k.first, static_cast<std::size_t>(k.second), x, y, x + 1, y + 1};
      std::vector<std::pair<std::size_t, std::size_t>> stack = {{x, y}};
      piece[y * w + x] = static_cast<int>(out.size());
      while (!stack.empty()) {
        const auto [px, py] = stack.back();
        stack.pop_back();
        p.pixels.insert({px, py});
        p.box = {p.box[0],
                 p.box[1],
                 std::min(p.box[2], px),
                 std::min(p.box[3], py),
                 std::max(p.box[4], px + 1),
                 std::max(p.box[5], py + 1)};
        for (std::size_t ny = py == 0 ? 0 : py - 1; ny <= std::min(py + 1, h - 1); ++ny) {
          for (std::size_t nx = px == 0 ? 0 : px - 1; nx <= std::min(px + 1, w - 1); ++nx) {
            if (piece[ny * w + nx] < 0 && key(nx, ny) == k) {
              piece[ny * w + nx] = static_cast<int>(out.size());
              stack.push_back({nx, ny});
            }
          }
        }
      }
      out.push_back(std::move(p));
    }
  }
  std::sort(out.begin(), out.end(),
            [](const BrutePiece& a, const BrutePiece& b) { return a.box < b.box; });
  return out;
}

// COCO uncompressed RLE decoded (column-major counts, alternating from 0): the pixels set.
std::set<std::pair<std::size_t, std::size_t>> decode_rle(const json& rle) {
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
std::set<std::pair<std::size_t, std::size_t>> rasterise_polygons(const json& polygons,
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
std::vector<std::string> xml_all(const std::string& xml, const std::string& tag) {
  std::vector<std::string> out;
  const std::string open = "<" + tag + ">", close = "</" + tag + ">";
  for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at)) {
    const std::size_t end = xml.find(close, at);
    out.push_back(xml.substr(at + open.size(), end - at - open.size()));
    at = end;
  }
  return out;
}
std::string xml_one(const std::string& xml, const std::string& tag) {
  const auto all = xml_all(xml, tag);
  EXPECT_EQ(all.size(), 1u) << tag;
  return all.empty() ? std::string() : all[0];
}

std::string file_text(const fs::path& p) {
  std::ifstream is(p, std::ios::binary);
  EXPECT_TRUE(is.good()) << p;
  return std::string(std::istreambuf_iterator<char>(is), {});
}

BoxRow box_row(const json& a) {
  const auto& b = a["bbox"];
  const std::size_t x = b[0], y = b[1], w = b[2], h = b[3];
  return {
      a["object_id"].get<std::size_t>(), a["category_id"].get<std::size_t>(), x, y, x + w, y + h};
}

json read_json(const fs::path& p) {
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

// What GDAL reports of a GeoTIFF's layout: IMAGE_STRUCTURE LAYOUT ("" if none), the file offset
// of the first block of band 1 at full resolution and of each overview, the pixels of band 1 at
// every level (as double), and whether it is tiled.
struct FileLayout {
  std::string layout;
  std::vector<long long> offsets;
  std::vector<std::vector<double>> levels;
  bool tiled = false;
};
FileLayout file_layout(const fs::path& path) {
  FileLayout out;
  GDALDataset* ds = GDALDataset::Open(path.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return out;
  const char* layout = ds->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
  out.layout = layout ? layout : "";
  GDALRasterBand* band = ds->GetRasterBand(1);
  int bx = 0, by = 0;
  band->GetBlockSize(&bx, &by);
  out.tiled = bx < ds->GetRasterXSize() || by < ds->GetRasterYSize();
  std::vector<GDALRasterBand*> levels = {band};
  for (int o = 0; o < band->GetOverviewCount(); ++o) levels.push_back(band->GetOverview(o));
  for (GDALRasterBand* b : levels) {
    const char* offset = b->GetMetadataItem("BLOCK_OFFSET_0_0", "TIFF");
    out.offsets.push_back(offset ? std::stoll(offset) : -1);
    std::vector<double> v(static_cast<std::size_t>(b->GetXSize()) *
                          static_cast<std::size_t>(b->GetYSize()));
    if (b->RasterIO(GF_Read, 0, 0, b->GetXSize(), b->GetYSize(), v.data(), b->GetXSize(),
                    b->GetYSize(), GDT_Float64, 0, 0, nullptr) != CE_None) {
      v.clear();
    }
    out.levels.push_back(std::move(v));
  }
  GDALClose(ds);
  return out;
}

// A shadow run takes the id of the object sample just before it; a run after seabed is 0.
TEST(SideInstances, ShadowRunsFollowTheirCaster) {
  using C = SampleClass;
  const std::vector<C> cls = {C::water_column, C::seabed, C::object, C::object,
                              C::shadow,       C::shadow, C::seabed, C::shadow,
                              C::object,       C::seabed, C::shadow, C::no_seabed};
  const std::vector<std::int32_t> id = {-1, 0, 5, 5, -1, -1, 0, -1, 9, 0, -1, -1};
  std::vector<std::uint32_t> out;
  labels::side_instances(cls, id, out);
  EXPECT_EQ(out, (std::vector<std::uint32_t>{0, 0, 5, 5, 5, 5, 0, 0, 9, 0, 0, 0}));
}

// The truth waterfall's label rasters (one spool, one pass) against the label waterfall's (a
// spool of their own): every pixel, the band type, nodata and items alike, over rows of varying
// side lengths (empty sides, padding) with object and shadow runs and ids beyond float's exact
// range (2^24) and negative ones.
TEST(TruthWaterfall, LabelRastersAreThoseOfTheLabelWaterfall) {
  const fs::path dir =
      fs::temp_directory_path() / ("sonarsynth_truth_labels_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::mt19937 rng(17);
  std::uniform_int_distribution<std::size_t> len(0, 90);
  std::uniform_int_distribution<int> cls(0, 4), run(1, 6);
  const std::int32_t ids[] = {-1, 0, 3, 16777217, 2147483647, -5, 16777216 + 3};
  std::uniform_int_distribution<std::size_t> pick(0, std::size(ids) - 1);
  TruthWaterfall truth(dir);
  labels::LabelWaterfall label(dir);
  for (int p = 0; p < 300; ++p) {
    std::vector<SampleClass> c[2];
    std::vector<std::int32_t> id[2];
    std::vector<float> g[2];
    for (int s = 0; s < 2; ++s) {
      const std::size_t n = p % 7 == s ? 0 : len(rng);
      while (c[s].size() < n) {
        const auto k = static_cast<SampleClass>(cls(rng));
        const std::int32_t v = ids[pick(rng)];
        for (int r = run(rng); r > 0 && c[s].size() < n; --r) {
          c[s].push_back(k);
          id[s].push_back(v);
          g[s].push_back(0.25f);
        }
      }
    }
    truth.add_ping(c[0], c[1], id[0], id[1], g[0], g[1]);
    label.add_ping(c[0], c[1], id[0], id[1]);
  }
  const std::vector<std::pair<std::string, std::string>> items = {{"RUN", "test"}};
  truth.write_with_labels((dir / "truth.tif").string(), (dir / "class.tif").string(),
                          (dir / "instance.tif").string(), false, items);
  label.write((dir / "class_ref.tif").string(), (dir / "instance_ref.tif").string(), false, items);
  for (const char* name : {"class", "instance"}) {
    const Raster got = read(dir / (std::string(name) + ".tif"));
    const Raster want = read(dir / (std::string(name) + "_ref.tif"));
    EXPECT_EQ(got.cols, want.cols) << name;
    EXPECT_EQ(got.rows, 300u) << name;
    EXPECT_EQ(got.type, want.type) << name;
    EXPECT_EQ(got.has_nodata, want.has_nodata) << name;
    EXPECT_EQ(got.nodata, want.nodata) << name;
    EXPECT_EQ(got.band_items, want.band_items) << name;
    EXPECT_TRUE(got.values == want.values) << name;
  }
  // Hand-worked row: port NEAR -> FAR seabed, object 2^24 + 1, shadow (its caster), starboard
  // empty; columns port FAR -> NEAR | starboard.
  TruthWaterfall one(dir);
  const std::vector<SampleClass> port = {SampleClass::seabed, SampleClass::object,
                                         SampleClass::shadow};
  const std::vector<std::int32_t> port_id = {0, 16777217, -1};
  const std::vector<float> port_g = {0.1f, 0.2f, 0.3f};
  one.add_ping(port, {}, port_id, {}, port_g, {});
  one.write_with_labels((dir / "one.tif").string(), (dir / "one_class.tif").string(),
                        (dir / "one_instance.tif").string(), false, items);
  EXPECT_EQ(read(dir / "one_class.tif").values,
            (std::vector<std::uint32_t>{3, 2, 1, 255, 255, 255}));
  EXPECT_EQ(
      read(dir / "one_instance.tif").values,
      (std::vector<std::uint32_t>{16777217, 16777217, 0, 0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu}));
  fs::remove_all(dir);
}

// `--of GTiff` (set_cog_layout(false)): plain tiled GeoTIFFs, each image before its overviews
// in the file where the default has the COG layout (overviews first), with the same pixels at
// every level.
TEST(TruthWaterfall, PlainLayoutHasTheImageFirstAndTheSamePixels) {
  const fs::path dir =
      fs::temp_directory_path() / ("sonarsynth_truth_plain_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  TruthWaterfall truth(dir);
  for (std::int32_t p = 0; p < 300; ++p) {  // 300 rows: one overview level
    std::vector<SampleClass> c(120, SampleClass::seabed);
    std::vector<std::int32_t> id(120, 0);
    std::vector<float> g(120, 0.5f);
    for (std::size_t i = 40 + static_cast<std::size_t>(p % 30); i < 60; ++i) {
      c[i] = SampleClass::object;
      id[i] = 7 + p / 100;
    }
    truth.add_ping(c, c, id, id, g, g);
  }
  const std::vector<std::pair<std::string, std::string>> items = {{"RUN", "test"}};
  truth.write_with_labels((dir / "truth.tif").string(), (dir / "class.tif").string(),
                          (dir / "instance.tif").string(), false, items);
  truth.set_cog_layout(false);
  truth.write_with_labels((dir / "truth_plain.tif").string(), (dir / "class_plain.tif").string(),
                          (dir / "instance_plain.tif").string(), false, items);
  for (const char* name : {"truth", "class", "instance"}) {
    const FileLayout cog = file_layout(dir / (std::string(name) + ".tif"));
    const FileLayout plain = file_layout(dir / (std::string(name) + "_plain.tif"));
    ASSERT_EQ(cog.levels.size(), 2u) << name << ": 300 rows give one overview";
    ASSERT_EQ(plain.levels.size(), cog.levels.size()) << name;
    EXPECT_LT(cog.offsets[1], cog.offsets[0]) << name << ": COG layout, overview first";
    EXPECT_LT(plain.offsets[0], plain.offsets[1]) << name << ": image first";
    EXPECT_EQ(plain.layout, "") << name;
    if (std::string(name) != "truth") {
      EXPECT_EQ(cog.layout, "COG") << name;
    }
    EXPECT_TRUE(plain.levels == cog.levels) << name;
    EXPECT_TRUE(plain.tiled) << name;
  }
  fs::remove_all(dir);
}

// The mosaic's one gridded code carries class, object id and caster: decoding returns the plain
// truth label (as before the labels existed) and the two rasters.
// An object in separate pieces gets a box per piece; pieces touching by a corner, or joined
// further down (a U), are one; its shadow is boxed on its own. Boxes worked out by hand.
TEST(BoxAccumulator, OneBoxPerConnectedPiece) {
  // a: object 5, A: shadow of 5, b: object 6, c: object 9, o: object with instance 0,
  // n: nodata, '.': seabed.
  const std::vector<std::string> image = {
      "............",  //
      ".aaa...aa...",  //
      ".aaa...aa.n.",  //
      ".AAA........",  //
      ".b.b..c.....",  //
      ".b.b...c..o.",  //
      ".bbb........",  //
      "..........a.",
  };
  labels::BoxAccumulator acc;
  for (std::size_t y = 0; y < image.size(); ++y) {
    std::vector<std::uint8_t> cls;
    std::vector<std::uint32_t> inst;
    for (char ch : image[y]) {
      const bool object = ch == 'a' || ch == 'b' || ch == 'c' || ch == 'o';
      cls.push_back(ch == 'n' ? labels::kClassNodata : object ? 2 : ch == 'A' ? 3 : 1);
      inst.push_back(ch == 'a' || ch == 'A' ? 5u
                     : ch == 'b'            ? 6u
                     : ch == 'c'            ? 9u
                     : ch == 'n'            ? labels::kInstanceNodata
                                            : 0u);
    }
    acc.add_row(y, cls, inst);
  }
  using Row = std::array<std::uint64_t, 7>;  // instance, category, x0, y0, x1, y1, pixels
  std::vector<Row> got;
  for (const labels::Box& b : acc.boxes()) {
    got.push_back(
        {b.instance, static_cast<std::uint64_t>(b.category), b.x0, b.y0, b.x1, b.y1, b.pixels});
  }
  const std::vector<Row> expected = {
      {5, 1, 1, 1, 4, 3, 6}, {5, 1, 7, 1, 9, 3, 4}, {5, 1, 10, 7, 11, 8, 1},
      {5, 2, 1, 3, 4, 4, 3}, {6, 1, 1, 4, 4, 7, 7}, {9, 1, 6, 4, 8, 6, 2},
  };
  EXPECT_EQ(got, expected);
}

TEST(MosaicLabelCodes, RoundTrip) {
  using C = SampleClass;
  const labels::MosaicLabelCodes codes({2'000'000'000, 4, 4, 17});
  const std::vector<C> cls = {C::seabed, C::object, C::shadow,
                              C::object, C::shadow, C::water_column};
  const std::vector<std::int32_t> id = {0, 2'000'000'000, -1, 4, -1, -1};
  std::vector<std::int32_t> code;
  codes.encode(cls, id, code);
  code.push_back(MosaicImage::kNoLabel);
  std::vector<std::uint8_t> c;
  std::vector<std::uint32_t> inst;
  codes.decode(code, c, inst);
  EXPECT_EQ(code,
            (std::vector<std::int32_t>{0, 2'000'000'000, -1, 4, -1, -1, MosaicImage::kNoLabel}));
  EXPECT_EQ(c, (std::vector<std::uint8_t>{1, 2, 3, 2, 3, 0, 255}));
  EXPECT_EQ(inst, (std::vector<std::uint32_t>{0, 2'000'000'000, 2'000'000'000, 4, 4, 0,
                                              labels::kInstanceNodata}));
  EXPECT_THROW(codes.encode(std::vector<C>{C::object}, std::vector<std::int32_t>{5}, code),
               FormatError);
}

TEST_F(LabelsTest, RastersBoxesAndChipsAgreeWithTheTruth) {
  const fs::path out = dir_ / "out";
  const RunResult r = run(kLabels, out);
  const std::set<std::string> table = {"water_column", "seabed", "object", "shadow", "no_seabed"};
  std::set<std::uint32_t> seen_objects;
  for (const auto& [image, cls_name, inst_name] :
       {std::tuple<std::string, std::string, std::string>{"a_waterfall.png", "a_truth_class.tif",
                                                          "a_truth_instance.tif"},
        {"mosaic_rgb.tif", "truth_mosaic_class.tif", "truth_mosaic_instance.tif"}}) {
    SCOPED_TRACE(image);
    const Raster cls = read(out / cls_name);
    const Raster inst = read(out / inst_name);
    ASSERT_EQ(cls.type, GDT_Byte);
    ASSERT_EQ(inst.type, GDT_UInt32);
    ASSERT_TRUE(cls.has_nodata);
    EXPECT_EQ(cls.nodata, 255.0);
    ASSERT_TRUE(inst.has_nodata);
    EXPECT_EQ(inst.nodata, 4294967295.0);
    for (std::uint32_t c = 0; c < labels::kClassCount; ++c) {
      EXPECT_TRUE(table.count(cls.band_items.at("CLASS_" + std::to_string(c))));
    }
    ASSERT_EQ(cls.values.size(), inst.values.size());
    for (std::size_t i = 0; i < cls.values.size(); ++i) {
      const std::uint32_t c = cls.values[i];
      ASSERT_TRUE(c < labels::kClassCount || c == 255) << c;
      ASSERT_EQ(c == 255, inst.values[i] == labels::kInstanceNodata) << i;
      if (c == 2) {
        ASSERT_TRUE(inst.values[i] == 3 || inst.values[i] == 7) << inst.values[i];
      }
      if (c == 2) seen_objects.insert(inst.values[i]);
      if (c != 2 && c != 3 && c != 255) {
        ASSERT_EQ(inst.values[i], 0u);
      }
    }
    // COCO: the boxes recomputed here from the rasters.
    const std::string set = image == "mosaic_rgb.tif" ? "mosaic" : "waterfalls";
    const json coco = read_json(out / (set + ".coco.json"));
    ASSERT_EQ(coco["images"].size(), 1u);
    EXPECT_EQ(coco["images"][0]["file_name"], image);
    EXPECT_EQ(coco["images"][0]["width"], cls.cols);
    EXPECT_EQ(coco["images"][0]["height"], cls.rows);
    const auto expected = brute_boxes(cls, inst);
    std::vector<BoxRow> got;
    for (const json& a : coco["annotations"]) got.push_back(box_row(a));
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected);
    // Both objects boxed, with their shadows.
    for (std::size_t k : {3u, 7u}) {
      for (std::size_t c : {1u, 2u}) {
        EXPECT_TRUE(std::any_of(got.begin(), got.end(),
                                [&](const BoxRow& b) { return b[0] == k && b[1] == c; }))
            << k << " " << c;
      }
    }
    // Every pixel of an object (or its shadow) is in a box of that object (or shadow), and an
    // object box holds no pixel of another object.
    for (std::size_t y = 0; y < cls.rows; ++y) {
      for (std::size_t x = 0; x < cls.cols; ++x) {
        const std::size_t i = y * cls.cols + x;
        const std::uint32_t k = inst.values[i];
        const auto c = static_cast<std::size_t>(category_of(cls.values[i]));
        bool boxed = false;
        for (const BoxRow& b : got) {
          const bool inside = x >= b[2] && x < b[4] && y >= b[3] && y < b[5];
          if (inside && b[0] == k && b[1] == c) boxed = true;
          if (inside && b[1] == 1 && c == 1) {
            ASSERT_EQ(k, b[0]) << x << "," << y;
          }
        }
        if (c != 0 && k != 0 && k != labels::kInstanceNodata) {
          ASSERT_TRUE(boxed) << x << "," << y;
        }
      }
    }
    // YOLO: the same boxes, normalised.
    std::ifstream yolo(out / "yolo" / "labels" / (fs::path(image).stem().string() + ".txt"));
    std::size_t lines = 0;
    int c = 0;
    double xc = 0, yc = 0, w = 0, h = 0;
    std::vector<std::array<double, 5>> yolo_boxes;
    while (yolo >> c >> xc >> yc >> w >> h) yolo_boxes.push_back({double(c), xc, yc, w, h});
    ASSERT_EQ(yolo_boxes.size(), coco["annotations"].size());
    for (const json& a : coco["annotations"]) {
      const auto& yb = yolo_boxes[lines++];
      const auto& b = a["bbox"];
      EXPECT_EQ(yb[0], a["category_id"].get<int>() - 1);
      const double W = static_cast<double>(cls.cols), H = static_cast<double>(cls.rows);
      EXPECT_NEAR(yb[1], (b[0].get<double>() + 0.5 * b[2].get<double>()) / W, 1e-6);
      EXPECT_NEAR(yb[2], (b[1].get<double>() + 0.5 * b[3].get<double>()) / H, 1e-6);
      EXPECT_NEAR(yb[3], b[2].get<double>() / W, 1e-6);
      EXPECT_NEAR(yb[4], b[3].get<double>() / H, 1e-6);
    }
  }
  EXPECT_EQ(seen_objects, (std::set<std::uint32_t>{3, 7}));

  // Chips: each chip's masks are the window of the full rasters, its boxes those of the window.
  const json chips = read_json(out / "chips" / "coco.json");
  ASSERT_GT(chips["images"].size(), 0u);
  std::map<int, std::vector<BoxRow>> chip_boxes;
  for (const json& a : chips["annotations"])
    chip_boxes[a["image_id"].get<int>()].push_back(box_row(a));
  for (auto& [id, boxes] : chip_boxes) std::sort(boxes.begin(), boxes.end());
  std::map<std::string, std::pair<Raster, Raster>> sources;
  sources["a_waterfall.png"] = {read(out / "a_truth_class.tif"),
                                read(out / "a_truth_instance.tif")};
  sources["mosaic_rgb.tif"] = {read(out / "truth_mosaic_class.tif"),
                               read(out / "truth_mosaic_instance.tif")};
  std::size_t with_boxes = 0;
  for (const json& im : chips["images"]) {
    const auto& [cls, inst] = sources.at(im["source_image"].get<std::string>());
    const std::size_t x0 = im["source_x0"], y0 = im["source_y0"];
    ASSERT_EQ(im["width"], 64);
    const Raster mask = read(out / "chips" / im["class_mask"].get<std::string>());
    ASSERT_EQ(mask.cols, 64u);
    std::size_t nodata = 0;
    for (std::size_t y = 0; y < 64; ++y) {
      for (std::size_t x = 0; x < 64; ++x) {
        ASSERT_EQ(mask.values[y * 64 + x], cls.values[(y0 + y) * cls.cols + x0 + x]);
        nodata += mask.values[y * 64 + x] == 255;
      }
    }
    EXPECT_LE(nodata, 64u * 64u / 2u);
    const auto expected = brute_boxes(cls, inst, x0, y0, 64, 64);
    EXPECT_EQ(chip_boxes[im["id"].get<int>()], expected) << im["file_name"];
    with_boxes += !expected.empty();
    EXPECT_TRUE(fs::exists(out / "chips" / im["file_name"].get<std::string>()));
    const fs::path yolo = out / "chips" / "labels" /
                          (fs::path(im["file_name"].get<std::string>()).stem().string() + ".txt");
    EXPECT_TRUE(fs::exists(yolo));
  }
  EXPECT_GT(with_boxes, 0u);
  // Every file listed exists.
  for (const fs::path& f : r.files) EXPECT_TRUE(fs::exists(f)) << f;
}

// The same files whatever the thread count; a run replaces an earlier one's label directories.
TEST_F(LabelsTest, ByteIdenticalForAnyThreadCount) {
  run(kLabels, dir_ / "one", 1);
  run(kLabels, dir_ / "two", 1);
  run(kLabels, dir_ / "two", 2, true);
  const auto bytes = [](const fs::path& p) {
    std::ifstream is(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(is), {});
  };
  std::size_t compared = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "one")) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), dir_ / "one");
    const std::string ext = rel.extension().string();
    if (ext != ".tif" && ext != ".json" && ext != ".txt" && ext != ".png") continue;
    ASSERT_TRUE(fs::exists(dir_ / "two" / rel)) << rel;
    EXPECT_EQ(bytes(e.path()), bytes(dir_ / "two" / rel)) << rel;
    ++compared;
  }
  EXPECT_GT(compared, 10u);
}

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

// chips/chips.jsonl places each chip: its window, pings and samples; the ground positions and
// box coordinates agree with the scene's geometry (flat seabed 7 m below the sonar, the line
// along grid east at north 0) and with PROJ's projection of the object positions.
TEST_F(LabelsTest, ChipRecordsPlaceTheChips) {
  const fs::path out = dir_ / "out";
  run(kLabels, out);
  const json chips = read_json(out / "chips" / "coco.json");
  std::map<std::string, json> images;
  for (const json& im : chips["images"]) images[im["file_name"]] = im;
  // The mosaic's CRS, and (E0, N0) of the scene's centre (43 N, 5 E) in it.
  GDALAllRegister();
  auto* ds = static_cast<GDALDataset*>(GDALOpen((out / "mosaic_rgb.tif").c_str(), GA_ReadOnly));
  ASSERT_NE(ds, nullptr);
  OGRSpatialReference utm(*ds->GetSpatialRef());
  GDALClose(ds);
  OGRSpatialReference wgs84;
  wgs84.importFromEPSG(4326);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_utm(
      OGRCreateCoordinateTransformation(&wgs84, &utm));
  std::unique_ptr<OGRCoordinateTransformation> to_geo(
      OGRCreateCoordinateTransformation(&utm, &wgs84));
  ASSERT_TRUE(to_utm && to_geo);
  double e0 = 5.0, n0 = 43.0;
  ASSERT_TRUE(to_utm->Transform(1, &e0, &n0));
  const double dr = 25.0 / 500.0, altitude = 5.0;
  std::ifstream is(out / "chips" / "chips.jsonl");
  std::string line;
  std::size_t records = 0, centres = 0, object_boxes = 0;
  while (std::getline(is, line)) {
    const json r = json::parse(line);
    SCOPED_TRACE(line.substr(0, 120));
    ++records;
    ASSERT_TRUE(images.count(r["file"]));
    const json& im = images[r["file"]];
    EXPECT_EQ(r["source_image"], im["source_image"]);
    EXPECT_EQ(r["pixel_box"], json({im["source_x0"], im["source_y0"], 64, 64}));
    const std::size_t x0 = im["source_x0"], y0 = im["source_y0"];
    // Lat / lon of a point against PROJ's inverse projection of its easting / northing.
    const auto check_geo = [&](const json& p) {
      if (p.is_null()) return;
      double e = p["easting_m"], n = p["northing_m"];
      ASSERT_TRUE(to_geo->Transform(1, &e, &n));
      EXPECT_NEAR(p["lon_deg"].get<double>(), e, 1e-8);
      EXPECT_NEAR(p["lat_deg"].get<double>(), n, 1e-8);
    };
    check_geo(r["centre"]);
    for (const json& c : r["corners"]) check_geo(c);
    if (r["source_image"] == "a_waterfall.png") {
      EXPECT_EQ(r["line"], "a");
      EXPECT_EQ(r["pings"], json({y0, y0 + 63}));
      EXPECT_EQ(r["columns"], json({x0, x0 + 63}));
      EXPECT_EQ(r.contains("port_samples"), x0 < 500);
      EXPECT_EQ(r.contains("starboard_samples"), x0 + 64 > 500);
      // The centre pixel's ground position: across track at the flat-seabed ground range of its
      // sample's slant range (port = north of the line, starboard = south).
      const std::size_t c = x0 + 32;
      const double slant = (static_cast<double>(c < 500 ? 499 - c : c - 500) + 0.5) * dr;
      if (r.contains("centre") && !r["centre"].is_null() && slant > altitude + 1.0) {
        const double ground = std::sqrt(slant * slant - altitude * altitude);
        const double north = r["centre"]["northing_m"].get<double>() - n0;
        EXPECT_NEAR(std::abs(north), ground, 2.0 * dr);
        EXPECT_EQ(north > 0.0, c < 500);
        ++centres;
      }
      for (const json& b : r["boxes"]) {
        const std::vector<double> across = b["across_track_slant_m"];
        const std::vector<double> along = b["along_track_m"];
        EXPECT_LT(across[0], across[1]);
        EXPECT_LE(along[0], along[1]);
        if (b["category_id"] != 1 || b["truncated"] != 0) continue;
        // Object 3 (3 m along east around east -10, 9 m north: port, 10.3 m slant to its
        // near top) and object 7 (2 m around east 15, 11 m south: starboard).
        const double along_mid = 0.5 * (along[0] + along[1]);
        if (b["object_id"] == 3) {
          EXPECT_NEAR(along_mid, 30.0, 2.0);
          EXPECT_LT(across[1], 0.0);
          EXPECT_GT(across[0], -std::hypot(9.0 + 1.0, altitude) - 1.0);
          EXPECT_LT(across[1], -std::hypot(9.0 - 1.0, altitude - 1.2) + 1.0);
        } else {
          EXPECT_NEAR(along_mid, 55.0, 2.0);
          EXPECT_GT(across[0], 0.0);
          EXPECT_GT(across[0], std::hypot(11.0 - 1.0, altitude - 1.0) - 1.0);
          EXPECT_LT(across[1], std::hypot(11.0 + 1.0, altitude) + 1.0);
        }
        ++object_boxes;
      }
    } else {
      for (const json& b : r["boxes"]) {
        if (b["category_id"] != 1 || b["truncated"] != 0) continue;
        const std::vector<double> east = b["easting_m"], north = b["northing_m"];
        const bool three = b["object_id"] == 3;
        const double ex = e0 + (three ? -10.0 : 15.0), ny = n0 + (three ? 9.0 : -11.0);
        EXPECT_GT(ex, east[0] - 1.5);
        EXPECT_LT(ex, east[1] + 1.5);
        EXPECT_GT(ny, north[0] - 1.5);
        EXPECT_LT(ny, north[1] + 1.5);
        ++object_boxes;
      }
    }
  }
  EXPECT_EQ(records, chips["images"].size());
  EXPECT_GT(centres, 0u);
  EXPECT_GT(object_boxes, 1u);
}

// output.display_window_db: two runs 10 dB apart show a sample value with the same colour,
// the colour of the window's mapping computed here (the display map of include/sonarsynth/
// colormap.hpp: red = 255 x 1.25 v below v = 0.8).
TEST_F(LabelsTest, OneDisplayWindowForEveryImage) {
  // (The raw gridding: gain normalisation would bring both runs' mosaics to one level, and the
  // window is what is tested here.)
  const std::string window =
      "output: {display_window_db: [-60, -5], mosaic: {gain_normalisation: off, nadir: raw}, "
      "seabed_median_dbfs: ";
  run(window + "-30}\n", dir_ / "low");
  run(window + "-20}\n", dir_ / "high");
  std::vector<double> medians;
  for (const std::string run_dir : {"low", "high"}) {
    GDALAllRegister();
    auto* v =
        static_cast<GDALDataset*>(GDALOpen((dir_ / run_dir / "mosaic.tif").c_str(), GA_ReadOnly));
    auto* c = static_cast<GDALDataset*>(
        GDALOpen((dir_ / run_dir / "mosaic_rgb.tif").c_str(), GA_ReadOnly));
    ASSERT_TRUE(v && c);
    const int w = v->GetRasterXSize(), h = v->GetRasterYSize();
    std::vector<float> value(std::size_t(w) * std::size_t(h));
    std::vector<std::uint8_t> red(value.size()), alpha(value.size());
    ASSERT_EQ(v->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, w, h, value.data(), w, h, GDT_Float32, 0,
                                            0, nullptr),
              CE_None);
    ASSERT_EQ(c->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, w, h, red.data(), w, h, GDT_Byte, 0, 0,
                                            nullptr),
              CE_None);
    ASSERT_EQ(c->GetRasterBand(4)->RasterIO(GF_Read, 0, 0, w, h, alpha.data(), w, h, GDT_Byte, 0, 0,
                                            nullptr),
              CE_None);
    GDALClose(v);
    GDALClose(c);
    const double full_scale_db = 10.0 * std::log10(32767.0);
    std::size_t compared = 0;
    std::vector<double> db;
    for (std::size_t i = 0; i < value.size(); ++i) {
      if (alpha[i] != 255 || !(value[i] > 0.0f)) continue;
      const double d = 10.0 * std::log10(double(value[i])) - full_scale_db;
      db.push_back(d);
      const double level = std::clamp((d + 60.0) / 55.0, 0.0, 1.0);
      if (level > 0.78) continue;
      ASSERT_NEAR(double(red[i]), std::round(255.0 * 1.25 * level), 1.0) << i;
      ++compared;
    }
    EXPECT_GT(compared, 1000u);
    std::nth_element(db.begin(), db.begin() + std::ptrdiff_t(db.size() / 2), db.end());
    medians.push_back(db[db.size() / 2]);
  }
  // The two runs' levels do differ (so per-image windows would show them alike): 10 dB of
  // amplitude are 5 of the display's 10 log10 of the amplitude samples.
  EXPECT_GT(medians[1] - medians[0], 4.0);
}

// Chip images are windows of their source images (colormap), or the grey level of the display
// window computed here; sample chips are the XTF samples of the window (read back from the XTF
// file) or the mosaic's values.
TEST_F(LabelsTest, ChipImagesAndSamplesAreWindowsOfTheirSources) {
  const std::string chips = "coco: true, chips: {size_px: 64, stride_px: 48}";
  run("output: {labels: {" + chips + ", chip_samples: f32}}\n", dir_ / "colour");
  run("output: {display_window_db: [-60, -5], labels: {" + chips +
          ", chip_color: grey, chip_samples: u16}}\n",
      dir_ / "grey");
  // The XTF samples of the line as a waterfall image (the file read back).
  WaterfallOptions wo;
  Waterfall wf(wo);
  add_file_pings(dir_ / "colour" / "a.xtf", wf, wo);
  const std::vector<float> xtf = wf.image();
  const std::size_t xtf_cols = wf.cols();
  const auto read_all = [](const fs::path& p, int band, GDALDataType type, auto& out) {
    GDALAllRegister();
    auto* ds = static_cast<GDALDataset*>(GDALOpen(p.c_str(), GA_ReadOnly));
    EXPECT_NE(ds, nullptr) << p;
    if (!ds) return std::size_t{0};
    const int w = ds->GetRasterXSize(), h = ds->GetRasterYSize();
    out.resize(std::size_t(w) * std::size_t(h));
    EXPECT_EQ(ds->GetRasterBand(band)->RasterIO(GF_Read, 0, 0, w, h, out.data(), w, h, type, 0, 0,
                                                nullptr),
              CE_None);
    GDALClose(ds);
    return std::size_t(w);
  };
  std::size_t colour_checked = 0, grey_checked = 0;
  for (const std::string run_dir : {"colour", "grey"}) {
    const fs::path out = dir_ / run_dir;
    const json coco = read_json(out / "chips" / "coco.json");
    ASSERT_GT(coco["images"].size(), 0u);
    std::vector<float> mosaic;
    const std::size_t mosaic_cols = read_all(out / "mosaic.tif", 1, GDT_Float32, mosaic);
    std::map<std::string, std::pair<std::vector<std::uint8_t>, std::size_t>> images;
    for (const json& im : coco["images"]) {
      SCOPED_TRACE(im["file_name"].get<std::string>());
      const std::string source = im["source_image"];
      const std::size_t x0 = im["source_x0"], y0 = im["source_y0"];
      const bool waterfall = source == "a_waterfall.png";
      ASSERT_TRUE(im.contains("samples"));
      std::vector<float> samples;
      read_all(out / "chips" / im["samples"].get<std::string>(), 1, GDT_Float32, samples);
      ASSERT_EQ(samples.size(), 64u * 64u);
      for (std::size_t y = 0; y < 64; ++y) {
        for (std::size_t x = 0; x < 64; ++x) {
          const float want = waterfall ? xtf[(y0 + y) * xtf_cols + x0 + x]
                                       : mosaic[(y0 + y) * mosaic_cols + x0 + x];
          const float got = samples[y * 64 + x];
          if (run_dir == "colour" || std::isnan(want)) {
            if (std::isnan(want)) {
              ASSERT_TRUE(run_dir == "grey" ? got == 65535.0f : std::isnan(got));
            } else {
              ASSERT_EQ(got, want);
            }
          } else {
            ASSERT_EQ(got, std::round(want));
          }
        }
      }
      if (run_dir == "colour") {
        // The chip is the window of its source image, band for band.
        for (int band = 1; band <= 3; ++band) {
          std::vector<std::uint8_t> chip;
          read_all(out / "chips" / im["file_name"].get<std::string>(), band, GDT_Byte, chip);
          const std::string key = source + std::to_string(band);
          if (!images.count(key)) {
            images[key].second = read_all(out / source, band, GDT_Byte, images[key].first);
          }
          const auto& [whole, cols] = images[key];
          for (std::size_t y = 0; y < 64; ++y) {
            for (std::size_t x = 0; x < 64; ++x) {
              ASSERT_EQ(chip[y * 64 + x], whole[(y0 + y) * cols + x0 + x]);
            }
          }
        }
        ++colour_checked;
      } else {
        std::vector<std::uint8_t> grey;
        read_all(out / "chips" / im["file_name"].get<std::string>(), 1, GDT_Byte, grey);
        const double full_scale_db = 10.0 * std::log10(32767.0);
        for (std::size_t y = 0; y < 64; ++y) {
          for (std::size_t x = 0; x < 64; ++x) {
            const float v = waterfall ? xtf[(y0 + y) * xtf_cols + x0 + x]
                                      : mosaic[(y0 + y) * mosaic_cols + x0 + x];
            double level = 0.0;
            if (v > 0.0f) {
              level = std::clamp((10.0 * std::log10(double(v)) - full_scale_db + 60.0) / 55.0, 0.0,
                                 1.0);
            }
            ASSERT_NEAR(double(grey[y * 64 + x]), std::isnan(v) ? 0.0 : 255.0 * level, 0.5001);
          }
        }
        ++grey_checked;
      }
    }
  }
  EXPECT_GT(colour_checked, 2u);
  EXPECT_GT(grey_checked, 2u);
}

// A waterfall decimated along track gets no boxes or chips (a note says so): the chips cut while
// it was written are removed, and every file left in chips/ is one the run lists.
TEST_F(LabelsTest, DecimatedWaterfallLeavesNoChips) {
  std::ofstream(scene_) << kScene << kLabels;
  RunOptions o;
  o.products.waterfall_max_pixels = 1000 * 300;
  const fs::path out = dir_ / "out";
  const RunResult r = run_simulation(scene_, out, o);
  EXPECT_TRUE(std::any_of(r.notes.begin(), r.notes.end(), [](const std::string& n) {
    return n.find("a_waterfall.png: no boxes or chips") != std::string::npos;
  }));
  std::set<fs::path> listed(r.files.begin(), r.files.end());
  std::size_t chips = 0;
  for (const auto& e : fs::recursive_directory_iterator(out / "chips")) {
    if (!e.is_regular_file()) continue;
    EXPECT_TRUE(listed.count(e.path())) << e.path();
    EXPECT_EQ(e.path().filename().string().rfind("a_waterfall", 0), std::string::npos) << e.path();
    ++chips;
  }
  EXPECT_GT(chips, 0u);  // the mosaic's
  const json coco = read_json(out / "waterfalls.coco.json");
  EXPECT_TRUE(coco["images"].empty());
}

TEST_F(LabelsTest, BadSettingsNameFieldAndValue) {
  const auto message = [&](const std::string& extra) {
    try {
      run(extra, dir_ / "bad");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("output: {labels: {chips: {size_px: 8}}}\n")
                .find("output.labels.chips.size_px = '8'"),
            std::string::npos);
  EXPECT_NE(message("output: {labels: {chips: {max_nodata_fraction: 1}}}\n")
                .find("output.labels.chips.max_nodata_fraction = '1'"),
            std::string::npos);
  EXPECT_NE(message("output: {labels: {cocoa: true}}\n").find("cocoa"), std::string::npos);
  EXPECT_NE(message("output: {truth: false, labels: {yolo: true}}\n").find("output.truth"),
            std::string::npos);
  EXPECT_NE(message("output: {labels: {coco: true, segmentation: blob}}\n")
                .find("output.labels.segmentation = 'blob'. Violated constraint: one of rle, "
                      "polygon, none"),
            std::string::npos);
  EXPECT_NE(message("output: {display_window_db: [-5, -60]}\n").find("output.display_window_db = "),
            std::string::npos);
  EXPECT_NE(message("output: {display: linear, display_window_db: [-60, -5]}\n")
                .find("output.display_window_db"),
            std::string::npos);
  EXPECT_NE(message("output: {labels: {chips: true, chip_color: sepia}}\n")
                .find("output.labels.chip_color = 'sepia'. Violated constraint: one of grey, "
                      "colormap"),
            std::string::npos);
  EXPECT_NE(message("output: {labels: {chips: true, chip_samples: u8}}\n")
                .find("output.labels.chip_samples = 'u8'. Violated constraint: one of none, "
                      "u16, f32"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

}  // namespace
}  // namespace sonarsynth
