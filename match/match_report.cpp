// SPDX-License-Identifier: MIT
#include "sonarsynth/match/match_report.hpp"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

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
  using Json = nlohmann::ordered_json;  // keys in the order written
  const MatchOptions& o = report.options;
  Json j;
  j["image_a"] = {
      {"source", report.image_a}, {"width", report.width_a}, {"height", report.height_a}};
  j["image_b"] = {
      {"source", report.image_b}, {"width", report.width_b}, {"height", report.height_b}};
  j["georeferenced"] = report.georeferenced;
  j["options"] = {{"ratio", o.ratio},
                  {"model", model_name(o.model)},
                  {"ransac_threshold_px", o.ransac_threshold_px},
                  {"ransac_iterations", o.ransac_iterations},
                  {"ransac_confidence", o.ransac_confidence},
                  {"max_features", o.max_features},
                  {"mask_margin_px", o.mask_margin_px},
                  {"tolerance_m", report.tolerance_m}};
  Json results = Json::array();
  for (const MatchRow& row : report.rows) {
    const DetectorResult& r = row.result;
    Json e = {{"prefilter", prefilter_name(row.prefilter)},
              {"detector", detector_name(r.detector)},
              {"keypoints_a", r.keypoints_a},
              {"keypoints_b", r.keypoints_b},
              {"matches", r.matches},
              {"inliers", r.inliers},
              {"inlier_ratio", r.inlier_ratio},
              {"transform", nullptr}};
    if (r.transform) {
      Json t = Json::array();
      for (int k = 0; k < 9; ++k) t.push_back((*r.transform)(k / 3, k % 3));
      e["transform"] = std::move(t);
    }
    e["transform_rms_m"] = nullptr;
    e["transform_max_m"] = nullptr;
    e["match_rms_m"] = nullptr;
    e["correct_inliers"] = nullptr;
    if (row.accuracy) {
      e["transform_rms_m"] = row.accuracy->transform_rms_m;
      e["transform_max_m"] = row.accuracy->transform_max_m;
      e["match_rms_m"] = row.accuracy->match_rms_m;
      e["correct_inliers"] = row.accuracy->correct_inliers;
    }
    e["seconds"] = r.seconds;
    results.push_back(std::move(e));
  }
  j["results"] = std::move(results);
  // Paths may hold any bytes: invalid UTF-8 is replaced (U+FFFD), never thrown on.
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
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
