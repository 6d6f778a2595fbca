// SPDX-License-Identifier: MIT
// Label chips (docs/labels.md): chip records placed on the scene's geometry, chip images and
// samples as windows of their sources, one display window, decimated waterfalls and bad settings.
#include <gtest/gtest.h>

#include "labels_test_util.hpp"

namespace sonarsynth {
namespace {

using namespace labels_test;

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
