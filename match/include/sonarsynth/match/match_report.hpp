// SPDX-License-Identifier: MIT
#pragma once
// Reports of `sonarsynth match`: a text table, JSON, and an image of the inlier matches.

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sonarsynth/match/feature_matcher.hpp"
#include "sonarsynth/match/match_accuracy.hpp"
#include "sonarsynth/match/prefilter.hpp"

namespace sonarsynth::match {

/// One detector run on one pre-filtered pair.
struct MatchRow {
  Prefilter prefilter = Prefilter::none;
  DetectorResult result;
  std::optional<GeoAccuracy> accuracy;
};

struct MatchReport {
  std::string image_a, image_b;
  int width_a = 0, height_a = 0, width_b = 0, height_b = 0;
  bool georeferenced = false;
  MatchOptions options;
  double tolerance_m = 1.0;  ///< for GeoAccuracy::correct_inliers
  std::vector<MatchRow> rows;
};

/// Fixed-width table, one line per row.
std::string format_table(const MatchReport& report);
/// JSON object: images, options and one entry per row (see docs/feature-matching.md).
std::string format_json(const MatchReport& report);
/// The inlier matches of every row, side by side (A left, B right), rows stacked, labelled.
cv::Mat draw_inlier_matches(const cv::Mat& a, const cv::Mat& b, const std::vector<MatchRow>& rows);

}  // namespace sonarsynth::match
