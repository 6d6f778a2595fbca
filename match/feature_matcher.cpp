// SPDX-License-Identifier: MIT
#include "sonarsynth/match/feature_matcher.hpp"

#include <chrono>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "sonarsynth/enum_names.hpp"
#include "sonarsynth/error.hpp"

namespace sonarsynth::match {
namespace {

cv::Ptr<cv::Feature2D> make_detector(Detector d, const MatchOptions& o) {
  switch (d) {
    case Detector::sift:
      return cv::SIFT::create(o.max_features);
    case Detector::brisk:
      return cv::BRISK::create();
    case Detector::orb:
      return cv::ORB::create(o.max_features);
    case Detector::akaze:
      return cv::AKAZE::create();
  }
  throw InputError("unknown detector");
}

/// Detects in the (eroded) mask, keeps the strongest max_features, describes.
void detect(const MatchImage& img, Detector d, const MatchOptions& o, std::vector<cv::KeyPoint>& kp,
            cv::Mat& desc) {
  cv::Mat mask = img.mask;  // shares img.mask's pixels: erode into a new buffer, never in place
  if (o.mask_margin_px > 0) {
    mask = cv::Mat();
    const int k = 2 * o.mask_margin_px + 1;
    cv::erode(img.mask, mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)),
              cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  const cv::Ptr<cv::Feature2D> f = make_detector(d, o);
  f->detect(img.grey, kp, mask);
  cv::KeyPointsFilter::retainBest(kp, o.max_features);
  f->compute(img.grey, kp, desc);
}

constexpr EnumName<Detector> kDetectorNames[] = {{Detector::sift, "sift"},
                                                 {Detector::brisk, "brisk"},
                                                 {Detector::orb, "orb"},
                                                 {Detector::akaze, "akaze"}};
constexpr EnumName<TransformModel> kModelNames[] = {{TransformModel::homography, "homography"},
                                                    {TransformModel::affine, "affine"},
                                                    {TransformModel::similarity, "similarity"}};

}  // namespace

std::vector<Detector> all_detectors() {
  return {Detector::sift, Detector::brisk, Detector::orb, Detector::akaze};
}

Detector parse_detector(const std::string& text, const char* option) {
  if (text == "a-kaze") return Detector::akaze;
  return parse_enum(kDetectorNames, text, std::string("--") + option);
}

const char* detector_name(Detector detector) {
  return enum_name(kDetectorNames, detector);
}

TransformModel parse_model(const std::string& text, const char* option) {
  return parse_enum(kModelNames, text, std::string("--") + option);
}

const char* model_name(TransformModel model) {
  return enum_name(kModelNames, model);
}

void MatchOptions::validate() const {
  if (detectors.empty())
    throw InputError("detectors: none given. Violated constraint: at least one");
  if (!(ratio > 0 && ratio <= 1)) {
    throw InputError("ratio = " + std::to_string(ratio) + ". Violated constraint: 0 < ratio <= 1");
  }
  if (!(ransac_threshold_px > 0)) {
    throw InputError("RANSAC threshold = " + std::to_string(ransac_threshold_px) +
                     " px. Violated constraint: > 0");
  }
  if (ransac_iterations < 1) {
    throw InputError("RANSAC iterations = " + std::to_string(ransac_iterations) +
                     ". Violated constraint: >= 1");
  }
  if (!(ransac_confidence > 0 && ransac_confidence < 1)) {
    throw InputError("RANSAC confidence = " + std::to_string(ransac_confidence) +
                     ". Violated constraint: 0 < confidence < 1");
  }
  if (max_features < 1) {
    throw InputError("max features = " + std::to_string(max_features) +
                     ". Violated constraint: >= 1");
  }
  if (mask_margin_px < 0) {
    throw InputError("mask margin = " + std::to_string(mask_margin_px) +
                     " px. Violated constraint: >= 0");
  }
}

cv::Point2d apply_transform(const cv::Matx33d& t, cv::Point2d p) {
  const cv::Vec3d q = t * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

DetectorResult match_features(const MatchImage& a, const MatchImage& b, Detector detector,
                              const MatchOptions& options) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  DetectorResult r;
  r.detector = detector;
  cv::Mat desc_a, desc_b;
  detect(a, detector, options, r.kp_a, desc_a);
  detect(b, detector, options, r.kp_b, desc_b);
  r.keypoints_a = r.kp_a.size();
  r.keypoints_b = r.kp_b.size();

  std::vector<cv::DMatch> good;
  if (!desc_a.empty() && !desc_b.empty()) {
    const int norm = detector == Detector::sift ? cv::NORM_L2 : cv::NORM_HAMMING;
    cv::BFMatcher matcher(norm);
    std::vector<std::vector<cv::DMatch>> knn;
    matcher.knnMatch(desc_a, desc_b, knn, 2);
    for (const auto& m : knn) {
      if (m.size() == 2 && m[0].distance < static_cast<float>(options.ratio) * m[1].distance) {
        good.push_back(m[0]);
      }
    }
  }
  r.matches = good.size();

  std::vector<cv::Point2f> src, dst;
  for (const cv::DMatch& m : good) {
    src.push_back(r.kp_a[static_cast<std::size_t>(m.queryIdx)].pt);
    dst.push_back(r.kp_b[static_cast<std::size_t>(m.trainIdx)].pt);
  }
  std::vector<std::uint8_t> inlier_mask;
  cv::Mat model;
  const auto iters = static_cast<std::size_t>(options.ransac_iterations);
  switch (options.model) {
    case TransformModel::homography:
      if (good.size() >= 4) {
        model = cv::findHomography(src, dst, cv::RANSAC, options.ransac_threshold_px, inlier_mask,
                                   options.ransac_iterations, options.ransac_confidence);
      }
      break;
    case TransformModel::affine:
      if (good.size() >= 3) {
        model = cv::estimateAffine2D(src, dst, inlier_mask, cv::RANSAC, options.ransac_threshold_px,
                                     iters, options.ransac_confidence);
      }
      break;
    case TransformModel::similarity:
      if (good.size() >= 2) {
        model = cv::estimateAffinePartial2D(src, dst, inlier_mask, cv::RANSAC,
                                            options.ransac_threshold_px, iters,
                                            options.ransac_confidence);
      }
      break;
  }
  if (!model.empty()) {
    cv::Matx33d t = cv::Matx33d::eye();
    for (int i = 0; i < model.rows; ++i) {
      for (int j = 0; j < 3; ++j) t(i, j) = model.at<double>(i, j);
    }
    r.transform = t;
    for (std::size_t i = 0; i < good.size() && i < inlier_mask.size(); ++i) {
      if (inlier_mask[i]) r.inlier_matches.push_back(good[i]);
    }
  }
  r.inliers = r.inlier_matches.size();
  r.inlier_ratio =
      r.matches > 0 ? static_cast<double>(r.inliers) / static_cast<double>(r.matches) : 0.0;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace sonarsynth::match
