// SPDX-License-Identifier: MIT
// Machine-learning labels (docs/labels.md): the class and instance rasters of a run, and the
// COCO / YOLO boxes and chips computed from them, checked against the rasters read back with GDAL
// and boxes recomputed here independently.
#include <gtest/gtest.h>

#include "labels_test_util.hpp"

namespace sonarsynth {
namespace {

using namespace labels_test;

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

// The label rasters' types, nodata, class table and values: objects 3 and 7 (into `seen`), a
// shadow's caster, 0 elsewhere.
void check_label_rasters(const Raster& cls, const Raster& inst, std::set<std::uint32_t>& seen) {
  const std::set<std::string> table = {"water_column", "seabed", "object", "shadow", "no_seabed"};
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
    if (c == 2) seen.insert(inst.values[i]);
    if (c != 2 && c != 3 && c != 255) {
      ASSERT_EQ(inst.values[i], 0u);
    }
  }
}

// Every pixel of an object (or its shadow) is in a box of that object (or shadow), and an
// object box holds no pixel of another object.
void check_every_labelled_pixel_boxed(const Raster& cls, const Raster& inst,
                                      const std::vector<BoxRow>& got) {
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
}

// YOLO text `path`: the boxes of the COCO annotations, normalised to the image's size.
void check_yolo_is_coco(const fs::path& path, const json& coco, std::size_t cols,
                        std::size_t rows) {
  std::ifstream yolo(path);
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
    const double W = static_cast<double>(cols), H = static_cast<double>(rows);
    EXPECT_NEAR(yb[1], (b[0].get<double>() + 0.5 * b[2].get<double>()) / W, 1e-6);
    EXPECT_NEAR(yb[2], (b[1].get<double>() + 0.5 * b[3].get<double>()) / H, 1e-6);
    EXPECT_NEAR(yb[3], b[2].get<double>() / W, 1e-6);
    EXPECT_NEAR(yb[4], b[3].get<double>() / H, 1e-6);
  }
}

// Each chip's masks are the window of the full rasters of the run in `out`, its boxes those of
// the window.
void check_chips(const fs::path& out) {
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
}

TEST_F(LabelsTest, RastersBoxesAndChipsAgreeWithTheTruth) {
  const fs::path out = dir_ / "out";
  const RunResult r = run(kLabels, out);
  std::set<std::uint32_t> seen_objects;
  for (const auto& [image, cls_name, inst_name] :
       {std::tuple<std::string, std::string, std::string>{"a_waterfall.png", "a_truth_class.tif",
                                                          "a_truth_instance.tif"},
        {"mosaic_rgb.tif", "truth_mosaic_class.tif", "truth_mosaic_instance.tif"}}) {
    SCOPED_TRACE(image);
    const Raster cls = read(out / cls_name);
    const Raster inst = read(out / inst_name);
    ASSERT_NO_FATAL_FAILURE(check_label_rasters(cls, inst, seen_objects));
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
    ASSERT_NO_FATAL_FAILURE(check_every_labelled_pixel_boxed(cls, inst, got));
    ASSERT_NO_FATAL_FAILURE(
        check_yolo_is_coco(out / "yolo" / "labels" / (fs::path(image).stem().string() + ".txt"),
                           coco, cls.cols, cls.rows));
  }
  EXPECT_EQ(seen_objects, (std::set<std::uint32_t>{3, 7}));

  ASSERT_NO_FATAL_FAILURE(check_chips(out));
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

}  // namespace
}  // namespace sonarsynth
