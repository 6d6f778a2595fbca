// SPDX-License-Identifier: MIT
#pragma once
// Feature matching as in the founding paper: detect and describe (SIFT, BRISK, ORB, A-KAZE),
// nearest-neighbour distance ratio test, RANSAC outlier removal (homography or affine).

#include <cstddef>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sonarsynth/match/image_source.hpp"

namespace sonarsynth::match {

enum class Detector { sift, brisk, orb, akaze };
/// Model fitted by RANSAC: full homography (8 dof), affine (6), similarity (4: rotation, scale,
/// translation).
enum class TransformModel { homography, affine, similarity };

/// The four detectors, in the paper's order.
std::vector<Detector> all_detectors();
/// "sift", "brisk", "orb", "akaze" (or "a-kaze"); throws InputError naming `option` otherwise.
Detector parse_detector(const std::string& text, const char* option);
const char* detector_name(Detector detector);
TransformModel parse_model(const std::string& text, const char* option);
const char* model_name(TransformModel model);

struct MatchOptions {
  std::vector<Detector> detectors = all_detectors();
  double ratio = 0.8;  ///< Lowe's ratio: best / second-best descriptor distance < ratio, (0, 1]
  TransformModel model = TransformModel::homography;
  double ransac_threshold_px = 3.0;  ///< reprojection error of an inlier, pixels, > 0
  int ransac_iterations = 5000;      ///< >= 1
  double ransac_confidence = 0.995;  ///< (0, 1)
  int max_features = 5000;           ///< SIFT and ORB keep the strongest this many, >= 1
  /// Keypoints closer than this to nodata (or the image edge of the data) are not detected:
  /// the edge of a swath is a strong but meaningless feature. >= 0.
  int mask_margin_px = 8;

  /// Throws InputError naming the option and the violated constraint.
  void validate() const;
};

struct DetectorResult {
  Detector detector = Detector::sift;
  std::size_t keypoints_a = 0;
  std::size_t keypoints_b = 0;
  std::size_t matches = 0;  ///< after the ratio test
  std::size_t inliers = 0;  ///< after RANSAC (0 if no model could be fitted)
  double inlier_ratio = 0;  ///< inliers / matches (0 without matches)
  /// Image A pixel -> image B pixel (3x3; last row 0 0 1 for affine models), if fitted.
  std::optional<cv::Matx33d> transform;
  std::vector<cv::KeyPoint> kp_a, kp_b;
  std::vector<cv::DMatch> inlier_matches;  ///< queryIdx into kp_a, trainIdx into kp_b
  double seconds = 0;                      ///< wall time of detection, matching and RANSAC
};

/// Matches `a` against `b` with one detector. Only pixels with mask 255 (eroded by the margin)
/// take keypoints.
DetectorResult match_features(const MatchImage& a, const MatchImage& b, Detector detector,
                              const MatchOptions& options);

/// Applies a 3x3 transform to a point.
cv::Point2d apply_transform(const cv::Matx33d& t, cv::Point2d p);

}  // namespace sonarsynth::match
