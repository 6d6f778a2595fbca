// SPDX-License-Identifier: MIT
// `sonarsynth match`: with OpenCV it matches and writes JSON and an image; without it, it says so
// and fails. The test checks whichever case applies to this build.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_test_util.hpp"

#ifdef SONARSYNTH_HAVE_OPENCV
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#endif

namespace fs = std::filesystem;
using sonarsynth::test::run_cli;

namespace {

class MatchCli : public sonarsynth::test::ScratchDirTest {
 protected:
  std::string p(const std::string& name) const { return (dir_ / name).string(); }
};

#ifndef SONARSYNTH_HAVE_OPENCV

TEST_F(MatchCli, WithoutOpenCvFailsWithAClearMessage) {
  const auto r = run_cli("match a.png b.png", dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(
      r.err.find("sonarsynth match: this build has no OpenCV (install libopencv-dev and rebuild)"),
      std::string::npos)
      << r.err;
  EXPECT_TRUE(r.out.empty());
}

#else

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Blobs on a noisy background, and the same shifted by (9, -6) pixels.
void write_pair(const std::string& a_path, const std::string& b_path) {
  cv::RNG rng(5);
  cv::Mat img(240, 320, CV_8UC1, cv::Scalar(100));
  cv::Mat noise(img.size(), CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 50);
  img += noise;
  for (int i = 0; i < 80; ++i) {
    cv::circle(img, cv::Point(rng.uniform(0, 320), rng.uniform(0, 240)), rng.uniform(3, 12),
               cv::Scalar(rng.uniform(0, 256)), cv::FILLED);
  }
  cv::GaussianBlur(img, img, cv::Size(0, 0), 0.8);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 9, 0, 1, -6);
  cv::Mat b;
  cv::warpAffine(img, b, shift, img.size(), cv::INTER_NEAREST, cv::BORDER_CONSTANT,
                 cv::Scalar(100));
  ASSERT_TRUE(cv::imwrite(a_path, img));
  ASSERT_TRUE(cv::imwrite(b_path, b));
}

TEST_F(MatchCli, MatchesAndWritesJsonAndImage) {
  write_pair(p("a.png"), p("b.png"));
  const auto r =
      run_cli("match " + p("a.png") + " " + p("b.png") + " --prefilter none,median --json " +
                  p("r.json") + " --image " + p("m.png"),
              dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* det : {"sift", "brisk", "orb", "akaze"}) {
    EXPECT_NE(r.out.find(det), std::string::npos) << r.out;
  }
  const std::string json = slurp(p("r.json"));
  for (const char* key :
       {"\"image_a\"", "\"results\"", "\"keypoints_a\"", "\"keypoints_b\"", "\"matches\"",
        "\"inliers\"", "\"inlier_ratio\"", "\"transform\"", "\"transform_rms_m\": null",
        "\"prefilter\": \"median\"", "\"detector\": \"akaze\"", "\"georeferenced\": false"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
  // Eight rows (2 pre-filters x 4 detectors).
  std::size_t rows = 0;
  for (auto pos = json.find("\"detector\""); pos != std::string::npos;
       pos = json.find("\"detector\"", pos + 1)) {
    ++rows;
  }
  EXPECT_EQ(rows, 8u);
  const cv::Mat drawn = cv::imread(p("m.png"));
  ASSERT_FALSE(drawn.empty());
  EXPECT_EQ(drawn.cols, 640);  // A and B side by side
}

TEST_F(MatchCli, BadInputFailsNamingTheFileAndWritesNothing) {
  write_pair(p("a.png"), p("b.png"));
  auto r = run_cli("match " + p("a.png") + " " + p("missing.png") + " --json " + p("r.json"), dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(p("missing.png")), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("r.json")));

  std::ofstream(p("notes.txt")) << "not an image\n";
  r = run_cli("match " + p("notes.txt") + " " + p("b.png"), dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(p("notes.txt")), std::string::npos) << r.err;

  r = run_cli("match " + p("a.png") + " " + p("b.png") + " --detectors surf", dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--detectors = 'surf'"), std::string::npos) << r.err;

  r = run_cli("match " + p("a.png") + " " + p("b.png") + " --overlap", dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("not georeferenced"), std::string::npos) << r.err;

  std::ofstream(p("old.json")) << "keep";
  r = run_cli("match " + p("a.png") + " " + p("b.png") + " --json " + p("old.json"), dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("already exists"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(p("old.json")), "keep");
}

#endif

}  // namespace
