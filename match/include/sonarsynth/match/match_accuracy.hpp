// SPDX-License-Identifier: MIT
#pragma once
// Matching accuracy against truth for georeferenced images: a ground point has the same world
// coordinates in both images, so the true A -> B transform is the identity in world coordinates.

#include <cstddef>
#include <optional>

#include "sonarsynth/match/feature_matcher.hpp"
#include "sonarsynth/match/image_source.hpp"

namespace sonarsynth::match {

struct GeoAccuracy {
  /// RMS over the inliers of |world_B(T p_A) - world_A(p_A)|, metres: the error of the
  /// estimated transform T at the matched points.
  double transform_rms_m = 0;
  /// RMS over the inliers of |world_B(p_B) - world_A(p_A)|: the error of the matched keypoint
  /// pairs themselves.
  double match_rms_m = 0;
  /// Largest |world_B(T p_A) - world_A(p_A)| over the inliers, metres.
  double transform_max_m = 0;
  /// Inliers whose keypoint pair is within the tolerance of the truth (match error < tolerance):
  /// RANSAC's inliers that are really the same ground point.
  std::size_t correct_inliers = 0;
};

/// Accuracy of a result; nullopt if either image is not georeferenced, the CRSs differ, or no
/// transform was fitted.
/// `tolerance_m` (> 0) decides which inliers are correct.
std::optional<GeoAccuracy> geo_accuracy(const MatchImage& a, const MatchImage& b,
                                        const DetectorResult& result, double tolerance_m = 1.0);

}  // namespace sonarsynth::match
