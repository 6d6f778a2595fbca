// SPDX-License-Identifier: MIT
#include "sonarsynth/match/match_report.hpp"

#include <cmath>
#include <cstdio>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "sonarsynth/formats/json_text.hpp"

namespace sonarsynth::match {
namespace {}  // namespace

std::string format_table(const MatchReport& report) {
  std::ostringstream os;
  os << "A: " << report.image_a << " (" << report.width_a << " x " << report.height_a << ")\n"
     << "B: " << report.image_b << " (" << report.width_b << " x " << report.height_b << ")\n"
     << "ratio test " << report.options.ratio << ", RANSAC " << model_name(report.options.model)
     << " " << report.options.ransac_threshold_px << " px\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-10s %-6s %7s %7s %8s %8s %7s %9s %9s %7s\n", "prefilter",
                "det", "kp_a", "kp_b", "matches", "inliers", "ratio", "correct", "rms_m", "time_s");
  os << line;
  for (const MatchRow& row : report.rows) {
    const DetectorResult& r = row.result;
    std::string rms = "-", correct = "-";
    if (row.accuracy) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.3f", row.accuracy->transform_rms_m);
      rms = buf;
      correct = std::to_string(row.accuracy->correct_inliers);
    }
    std::snprintf(line, sizeof line, "%-10s %-6s %7zu %7zu %8zu %8zu %7.3f %9s %9s %7.2f\n",
                  prefilter_name(row.prefilter), detector_name(r.detector), r.keypoints_a,
                  r.keypoints_b, r.matches, r.inliers, r.inlier_ratio, correct.c_str(), rms.c_str(),
                  r.seconds);
    os << line;
  }
  return os.str();
}

std::string format_json(const MatchReport& report) {
  const MatchOptions& o = report.options;
  std::ostringstream os;
  os << "{\n  \"image_a\": {\"source\": " << json::string_literal(report.image_a)
     << ", \"width\": " << report.width_a << ", \"height\": " << report.height_a << "},\n"
     << "  \"image_b\": {\"source\": " << json::string_literal(report.image_b)
     << ", \"width\": " << report.width_b << ", \"height\": " << report.height_b << "},\n"
     << "  \"georeferenced\": " << (report.georeferenced ? "true" : "false") << ",\n"
     << "  \"options\": {\"ratio\": " << json::number(o.ratio)
     << ", \"model\": " << json::string_literal(model_name(o.model))
     << ", \"ransac_threshold_px\": " << json::number(o.ransac_threshold_px)
     << ", \"ransac_iterations\": " << o.ransac_iterations
     << ", \"ransac_confidence\": " << json::number(o.ransac_confidence)
     << ", \"max_features\": " << o.max_features << ", \"mask_margin_px\": " << o.mask_margin_px
     << ", \"tolerance_m\": " << json::number(report.tolerance_m) << "},\n  \"results\": [";
  for (std::size_t i = 0; i < report.rows.size(); ++i) {
    const MatchRow& row = report.rows[i];
    const DetectorResult& r = row.result;
    os << (i ? "," : "")
       << "\n    {\"prefilter\": " << json::string_literal(prefilter_name(row.prefilter))
       << ", \"detector\": " << json::string_literal(detector_name(r.detector))
       << ", \"keypoints_a\": " << r.keypoints_a << ", \"keypoints_b\": " << r.keypoints_b
       << ", \"matches\": " << r.matches << ", \"inliers\": " << r.inliers
       << ", \"inlier_ratio\": " << json::number(r.inlier_ratio) << ", \"transform\": ";
    if (r.transform) {
      os << "[";
      for (int k = 0; k < 9; ++k)
        os << (k ? ", " : "") << json::number((*r.transform)(k / 3, k % 3));
      os << "]";
    } else {
      os << "null";
    }
    if (row.accuracy) {
      os << ", \"transform_rms_m\": " << json::number(row.accuracy->transform_rms_m)
         << ", \"transform_max_m\": " << json::number(row.accuracy->transform_max_m)
         << ", \"match_rms_m\": " << json::number(row.accuracy->match_rms_m)
         << ", \"correct_inliers\": " << row.accuracy->correct_inliers;
    } else {
      os << ", \"transform_rms_m\": null, \"transform_max_m\": null, \"match_rms_m\": null, "
            "\"correct_inliers\": null";
    }
    os << ", \"seconds\": " << json::number(r.seconds) << "}";
  }
  os << "\n  ]\n}\n";
  return os.str();
}

cv::Mat draw_inlier_matches(const cv::Mat& a, const cv::Mat& b, const std::vector<MatchRow>& rows) {
  std::vector<cv::Mat> panels;
  for (const MatchRow& row : rows) {
    const DetectorResult& r = row.result;
    cv::Mat panel;
    cv::drawMatches(a, r.kp_a, b, r.kp_b, r.inlier_matches, panel, cv::Scalar(0, 255, 0),
                    cv::Scalar(0, 0, 255), std::vector<char>(),
                    cv::DrawMatchesFlags::NOT_DRAW_SINGLE_POINTS);
    const std::string label = std::string(detector_name(r.detector)) + " / " +
                              prefilter_name(row.prefilter) + ": " + std::to_string(r.inliers) +
                              " inliers of " + std::to_string(r.matches) + " matches";
    cv::rectangle(panel,
                  cv::Rect(0, 0, std::min(panel.cols, 12 * static_cast<int>(label.size())), 24),
                  cv::Scalar(0, 0, 0), cv::FILLED);
    cv::putText(panel, label, cv::Point(4, 18), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    panels.push_back(panel);
  }
  cv::Mat out;
  if (!panels.empty()) cv::vconcat(panels, out);
  return out;
}

}  // namespace sonarsynth::match
