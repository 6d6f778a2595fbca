// SPDX-License-Identifier: MIT
// Feature matching (OpenCV builds only): known transforms are recovered, georeferenced accuracy
// is measured against the true (identity) world transform, bad input is reported.
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_test_util.hpp"
#include "error_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/match/feature_matcher.hpp"
#include "sonarsynth/match/image_source.hpp"
#include "sonarsynth/match/match_accuracy.hpp"
#include "sonarsynth/match/match_report.hpp"
#include "sonarsynth/match/prefilter.hpp"

namespace fs = std::filesystem;
namespace m = sonarsynth::match;
using sonarsynth::test::expect_error;

namespace {

/// A textured scene with blobs and boxes of many sizes and grey levels (reproducible).
cv::Mat textured_scene(int cols, int rows, std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat img(rows, cols, CV_8UC1, cv::Scalar(110));
  cv::Mat noise(rows, cols, CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 60);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.5);
  img += noise;
  for (int i = 0; i < 120; ++i) {
    const cv::Point c(rng.uniform(0, cols), rng.uniform(0, rows));
    const int r = rng.uniform(3, 14);
    const cv::Scalar v(rng.uniform(0, 256));
    if (i % 2) {
      cv::circle(img, c, r, v, cv::FILLED, cv::LINE_AA);
    } else {
      cv::rectangle(img, cv::Rect(c.x, c.y, r * 2, r + 3), v, cv::FILLED);
    }
  }
  cv::GaussianBlur(img, img, cv::Size(0, 0), 0.8);
  return img;
}

class MatchTest : public sonarsynth::test::ScratchDirTest {
 protected:
  /// Writes a grey image as a north-up GeoTIFF in UTM 52N with the given top-left corner.
  std::string write_geotiff(const std::string& name, const cv::Mat& grey, double x0, double y0,
                            double pixel_m) {
    GDALAllRegister();
    const std::string path = (dir_ / name).string();
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDataset* ds = drv->Create(path.c_str(), grey.cols, grey.rows, 1, GDT_Byte, nullptr);
    double gt[6] = {x0, pixel_m, 0, y0, 0, -pixel_m};
    ds->SetGeoTransform(gt);
    OGRSpatialReference srs;
    srs.importFromEPSG(32652);
    ds->SetSpatialRef(&srs);
    EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, grey.cols, grey.rows, grey.data,
                                             grey.cols, grey.rows, GDT_Byte, 0, 0),
              CE_None);
    GDALClose(ds);
    return path;
  }
};

TEST_F(MatchTest, RecoversAKnownRotationAndShiftWithEveryDetector) {
  const cv::Mat a = textured_scene(480, 360, 7);
  // B = A rotated by 8 degrees about (240, 180) and shifted by (12.5, -7.25) pixels.
  cv::Mat rot = cv::getRotationMatrix2D(cv::Point2f(240, 180), 8.0, 1.0);
  rot.at<double>(0, 2) += 12.5;
  rot.at<double>(1, 2) += -7.25;
  cv::Mat b;
  cv::warpAffine(a, b, rot, a.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(110));
  const cv::Matx33d truth(rot.at<double>(0, 0), rot.at<double>(0, 1), rot.at<double>(0, 2),
                          rot.at<double>(1, 0), rot.at<double>(1, 1), rot.at<double>(1, 2), 0, 0,
                          1);
  ASSERT_TRUE(cv::imwrite((dir_ / "a.png").string(), a));
  ASSERT_TRUE(cv::imwrite((dir_ / "b.png").string(), b));
  const m::MatchImage ia = m::load_image((dir_ / "a.png").string());
  const m::MatchImage ib = m::load_image((dir_ / "b.png").string());
  ASSERT_EQ(ia.grey.size(), a.size());
  EXPECT_EQ(cv::norm(ia.grey, a, cv::NORM_INF), 0.0);  // PNG via GDAL is lossless
  EXPECT_FALSE(ia.geotransform.has_value());

  for (const m::TransformModel model : {m::TransformModel::homography, m::TransformModel::affine}) {
    for (const m::Detector d : m::all_detectors()) {
      SCOPED_TRACE(std::string(m::detector_name(d)) + " " + m::model_name(model));
      m::MatchOptions o;
      o.model = model;
      const m::DetectorResult r = m::match_features(ia, ib, d, o);
      EXPECT_GE(r.inliers, 20u);
      EXPECT_GE(r.matches, r.inliers);
      EXPECT_NEAR(r.inlier_ratio, static_cast<double>(r.inliers) / static_cast<double>(r.matches),
                  1e-12);
      ASSERT_TRUE(r.transform.has_value());
      double worst = 0;
      for (double x = 100; x <= 380; x += 40) {
        for (double y = 80; y <= 280; y += 40) {
          const cv::Point2d est = m::apply_transform(*r.transform, {x, y});
          const cv::Point2d tru = m::apply_transform(truth, {x, y});
          worst = std::max(worst, cv::norm(est - tru));
        }
      }
      EXPECT_LT(worst, 1.0) << "pixels";
      EXPECT_FALSE(m::geo_accuracy(ia, ib, r).has_value());  // not georeferenced
    }
  }
}

TEST_F(MatchTest, UnrelatedImagesGiveFewInliers) {
  const m::MatchImage ia = [&] {
    cv::imwrite((dir_ / "a.png").string(), textured_scene(400, 300, 1));
    return m::load_image((dir_ / "a.png").string());
  }();
  cv::imwrite((dir_ / "b.png").string(), textured_scene(400, 300, 2));
  const m::MatchImage ib = m::load_image((dir_ / "b.png").string());
  m::MatchOptions o;
  o.model = m::TransformModel::similarity;
  o.ransac_threshold_px = 1.0;
  for (const m::Detector d : m::all_detectors()) {
    SCOPED_TRACE(m::detector_name(d));
    EXPECT_LT(m::match_features(ia, ib, d, o).inliers, 10u);
  }
}

TEST_F(MatchTest, GeoreferencedCropsMeasureTheTransformErrorInMetres) {
  const double px = 0.25;
  const cv::Mat world = textured_scene(560, 420, 11);
  // Two overlapping crops of the same world: A from pixel (0, 0), B from pixel (60, 40).
  const cv::Mat a = world(cv::Rect(0, 0, 440, 340)).clone();
  const cv::Mat b = world(cv::Rect(60, 40, 440, 340)).clone();
  const double x0 = 500000.0, y0 = 3880000.0;
  const std::string pa = write_geotiff("a.tif", a, x0, y0, px);
  const std::string pb = write_geotiff("b.tif", b, x0 + 60 * px, y0 - 40 * px, px);
  // B mislabelled: its georeferencing 5 m east of the truth.
  const std::string pbad = write_geotiff("bad.tif", b, x0 + 60 * px + 5.0, y0 - 40 * px, px);
  const m::MatchImage ia = m::load_image(pa), ib = m::load_image(pb), ibad = m::load_image(pbad);
  ASSERT_TRUE(ia.geotransform && ib.geotransform);
  // Pixel <-> world round trip, pixel centres at integers.
  const cv::Point2d w = ia.world({0, 0});
  EXPECT_DOUBLE_EQ(w.x, x0 + 0.5 * px);
  EXPECT_DOUBLE_EQ(w.y, y0 - 0.5 * px);
  EXPECT_LT(cv::norm(ib.pixel(ia.world({100, 70})) - cv::Point2d(40, 30)), 1e-9);

  for (const m::Detector d : m::all_detectors()) {
    SCOPED_TRACE(m::detector_name(d));
    const m::DetectorResult r = m::match_features(ia, ib, d, {});
    ASSERT_GE(r.inliers, 20u);
    const auto acc = m::geo_accuracy(ia, ib, r);
    ASSERT_TRUE(acc.has_value());
    EXPECT_LT(acc->transform_rms_m, 0.5 * px);
    EXPECT_LT(acc->match_rms_m, 1.0 * px);
    EXPECT_EQ(acc->correct_inliers, r.inliers);
    const auto bad = m::geo_accuracy(ia, ibad, r);
    ASSERT_TRUE(bad.has_value());
    EXPECT_NEAR(bad->transform_rms_m, 5.0, 0.5 * px);
    EXPECT_EQ(bad->correct_inliers, 0u);
  }

  // The overlap of the two crops is the world area they share: identical pixels in both.
  const m::WorldBounds o = m::overlap_bounds(ia, ib);
  EXPECT_DOUBLE_EQ(o.min_x, x0 + 60 * px);
  EXPECT_DOUBLE_EQ(o.max_y, y0 - 40 * px);
  const m::MatchImage ca = m::crop_to_bounds(ia, o), cb = m::crop_to_bounds(ib, o);
  ASSERT_EQ(ca.grey.size(), cv::Size(380, 300));
  ASSERT_EQ(cb.grey.size(), ca.grey.size());
  EXPECT_EQ(cv::norm(ca.grey, cb.grey, cv::NORM_INF), 0.0);
  EXPECT_LT(cv::norm(ca.world({0, 0}) - cb.world({0, 0})), 1e-9);
}

TEST_F(MatchTest, MaskExcludesNodataFromDetection) {
  cv::Mat a = textured_scene(300, 200, 3);
  // Left half nodata: zero with a GeoTIFF nodata value of 0.
  a(cv::Rect(0, 0, 150, 200)).setTo(0);
  const std::string p = write_geotiff("a.tif", a, 500000, 3880000, 0.25);
  {
    GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(p.c_str(), GA_Update));
    ds->GetRasterBand(1)->SetNoDataValue(0);
    GDALClose(ds);
  }
  const m::MatchImage img = m::load_image(p);
  EXPECT_EQ(cv::countNonZero(img.mask(cv::Rect(0, 0, 150, 200))), 0);
  m::MatchOptions o;
  o.mask_margin_px = 8;
  const m::DetectorResult r = m::match_features(img, img, m::Detector::orb, o);
  ASSERT_GT(r.keypoints_a, 0u);
  for (const cv::KeyPoint& k : r.kp_a) EXPECT_GE(k.pt.x, 150 + 8 - 1);
  // Matching leaves the image's mask alone: a second run gives the same result.
  EXPECT_EQ(cv::countNonZero(img.mask), cv::countNonZero(m::load_image(p).mask));
  const m::DetectorResult again = m::match_features(img, img, m::Detector::orb, o);
  EXPECT_EQ(again.keypoints_a, r.keypoints_a);
  EXPECT_EQ(again.inliers, r.inliers);
}

TEST(Prefilter, MedianRemovesIsolatedSpeckleAndBilateralKeepsEdges) {
  cv::Mat img(40, 40, CV_8UC1, cv::Scalar(50));
  img(cv::Rect(20, 0, 20, 40)).setTo(200);  // a step edge
  img.at<std::uint8_t>(10, 5) = 255;        // a speckle spike
  m::PrefilterOptions o;
  const cv::Mat med = m::apply_prefilter(img, m::Prefilter::median, o);
  EXPECT_EQ(med.at<std::uint8_t>(10, 5), 50);
  EXPECT_EQ(med.at<std::uint8_t>(10, 19), 50);
  EXPECT_EQ(med.at<std::uint8_t>(10, 20), 200);
  const cv::Mat bil = m::apply_prefilter(img, m::Prefilter::bilateral, o);
  EXPECT_NEAR(bil.at<std::uint8_t>(30, 18), 50, 2);
  EXPECT_NEAR(bil.at<std::uint8_t>(30, 21), 200, 2);
  EXPECT_EQ(cv::norm(m::apply_prefilter(img, m::Prefilter::none, o), img, cv::NORM_INF), 0.0);
  o.median_ksize = 4;
  EXPECT_THROW(m::apply_prefilter(img, m::Prefilter::median, o), sonarsynth::InputError);
}

TEST(MatchOptions, ValidateNamesTheViolatedConstraint) {
  m::MatchOptions o;
  o.ratio = 0;
  expect_error([&] { o.validate(); }, {"ratio"}, "ratio 0");
  EXPECT_THROW(m::parse_detector("surf", "detectors"), sonarsynth::InputError);
  EXPECT_EQ(m::parse_detector("a-kaze", "detectors"), m::Detector::akaze);
  EXPECT_THROW(m::parse_bounds("1,2,3", "bounds"), sonarsynth::InputError);
  EXPECT_THROW(m::parse_bounds("3,2,1,4", "bounds"), sonarsynth::InputError);
  const m::WorldBounds b = m::parse_bounds("1,2,3.5,4", "bounds");
  EXPECT_DOUBLE_EQ(b.max_x, 3.5);
}

TEST_F(MatchTest, BadInputNamesTheFile) {
  const std::string missing = (dir_ / "missing.png").string();
  expect_error<sonarsynth::FormatError>([&] { m::load_image(missing); }, {missing},
                                        "a missing file");
  const std::string text = (dir_ / "notes.png").string();
  std::ofstream(text) << "not an image\n";
  expect_error<sonarsynth::FormatError>([&] { m::load_image(text); }, {text}, "a text file");
  const std::string xtf = (dir_ / "none.xtf").string();
  EXPECT_THROW(m::load_image(xtf), sonarsynth::FormatError);
  // A PNG without georeferencing cannot be cropped to world bounds.
  cv::imwrite((dir_ / "a.png").string(), textured_scene(50, 40, 1));
  const m::MatchImage a = m::load_image((dir_ / "a.png").string());
  EXPECT_THROW(m::crop_to_bounds(a, {0, 0, 10, 10}), sonarsynth::InputError);
}

TEST(MatchReport, JsonAndTableHaveEveryField) {
  m::MatchReport rep;
  rep.image_a = "a \"quoted\".png";
  rep.image_b = "b.png";
  m::MatchRow row;
  row.result.detector = m::Detector::akaze;
  row.result.matches = 10;
  row.result.inliers = 7;
  row.result.inlier_ratio = 0.7;
  row.result.transform = cv::Matx33d::eye();
  row.accuracy = m::GeoAccuracy{0.125, 0.25, 0.5, 6};
  rep.rows.push_back(row);
  const std::string json = m::format_json(rep);
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(json)) << json;
  EXPECT_EQ(j["image_a"]["source"], "a \"quoted\".png");
  EXPECT_EQ(j["image_b"]["source"], "b.png");
  EXPECT_TRUE(j["options"].is_object());
  ASSERT_EQ(j["results"].size(), 1u);
  const nlohmann::json& r = j["results"][0];
  EXPECT_EQ(r["prefilter"], "none");
  EXPECT_EQ(r["detector"], "akaze");
  EXPECT_TRUE(r.contains("keypoints_a"));
  EXPECT_TRUE(r.contains("keypoints_b"));
  EXPECT_EQ(r["matches"], 10);
  EXPECT_EQ(r["inliers"], 7);
  EXPECT_EQ(r["inlier_ratio"], 0.7);
  EXPECT_EQ(r["transform"], nlohmann::json({1, 0, 0, 0, 1, 0, 0, 0, 1}));
  EXPECT_EQ(r["transform_rms_m"], 0.125);
  EXPECT_EQ(r["match_rms_m"], 0.25);
  EXPECT_EQ(r["transform_max_m"], 0.5);
  EXPECT_EQ(r["correct_inliers"], 6);
  const std::string table = m::format_table(rep);
  EXPECT_NE(table.find("akaze"), std::string::npos);
  EXPECT_NE(table.find("0.125"), std::string::npos);
}

}  // namespace
