// SPDX-License-Identifier: MIT
#include "sonarsynth/match/match_accuracy.hpp"

#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>

namespace sonarsynth::match {

std::optional<GeoAccuracy> geo_accuracy(const MatchImage& a, const MatchImage& b,
                                        const DetectorResult& result, double tolerance_m) {
  if (!a.geotransform || !b.geotransform || !result.transform || result.inlier_matches.empty()) {
    return std::nullopt;
  }
  if (!a.crs_wkt.empty() && !b.crs_wkt.empty() && a.crs_wkt != b.crs_wkt) {
    OGRSpatialReference sa, sb;
    sa.importFromWkt(a.crs_wkt.c_str());
    sb.importFromWkt(b.crs_wkt.c_str());
    if (!sa.IsSame(&sb)) return std::nullopt;
  }
  GeoAccuracy acc;
  double sum_t = 0, sum_m = 0;
  for (const cv::DMatch& m : result.inlier_matches) {
    const cv::Point2d pa = result.kp_a[static_cast<std::size_t>(m.queryIdx)].pt;
    const cv::Point2d pb = result.kp_b[static_cast<std::size_t>(m.trainIdx)].pt;
    const cv::Point2d truth = a.world(pa);  // where this ground point is, in both images
    const double et = cv::norm(b.world(apply_transform(*result.transform, pa)) - truth);
    const double em = cv::norm(b.world(pb) - truth);
    sum_t += et * et;
    sum_m += em * em;
    acc.transform_max_m = std::max(acc.transform_max_m, et);
    if (em < tolerance_m) ++acc.correct_inliers;
  }
  const auto n = static_cast<double>(result.inlier_matches.size());
  acc.transform_rms_m = std::sqrt(sum_t / n);
  acc.match_rms_m = std::sqrt(sum_m / n);
  return acc;
}

}  // namespace sonarsynth::match
