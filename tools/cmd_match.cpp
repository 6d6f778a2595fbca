// SPDX-License-Identifier: MIT
// `sonarsynth match A B`: feature matching between two sonar images (waterfalls, mosaic patches or
// XTF ping ranges) with SIFT, BRISK, ORB and A-KAZE, as the founding paper validated its images.
// Needs OpenCV; without it the command exists and says so.
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"

#ifdef SONARSYNTH_HAVE_OPENCV
#include <cstdint>
#include <fstream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/products/output_paths.hpp"
#include "sonarsynth/match/feature_matcher.hpp"
#include "sonarsynth/match/image_source.hpp"
#include "sonarsynth/match/match_accuracy.hpp"
#include "sonarsynth/match/match_report.hpp"
#include "sonarsynth/match/prefilter.hpp"
#endif

namespace sonarsynth::cli {

#ifndef SONARSYNTH_HAVE_OPENCV

int run_match(const std::vector<std::string>& /*args*/) {
  std::cerr << "sonarsynth match: this build has no OpenCV (install libopencv-dev and rebuild)\n";
  return 1;
}

#else

namespace {

namespace m = sonarsynth::match;

const char* const kUsage =
    "usage: sonarsynth match A B [options]\n\n"
    "Matches features between two images as the founding paper validated its simulated images:\n"
    "optional speckle pre-filter (median, bilateral), detection and description (SIFT, BRISK,\n"
    "ORB, A-KAZE), nearest-neighbour distance ratio test, RANSAC (homography, affine or\n"
    "similarity). Reports keypoints, matches, inliers and inlier ratio per pre-filter and\n"
    "detector as a table (or JSON), and optionally an image of the inlier matches.\n"
    "A and B: any raster GDAL reads (waterfall PNG, mosaic GeoTIFF: float mosaics are shown in dB\n"
    "between the 1st and 99th percentiles) or XTF files (a waterfall of --pings-a/--pings-b).\n"
    "When both are georeferenced in the same CRS, the error of the estimated transform at the\n"
    "inliers is reported in metres (truth: a ground point has the same world coordinates in both).";

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

/// "FIRST:LAST" (LAST may be empty = to the end).
void parse_pings(const std::string& text, const char* option, m::ImageSourceOptions& o) {
  const auto colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument(text);
    std::size_t used = 0;
    const std::string first = text.substr(0, colon), last = text.substr(colon + 1);
    o.first_ping = std::stoll(first, &used);
    if (used != first.size()) throw std::invalid_argument(text);
    o.last_ping = -1;
    if (!last.empty()) {
      o.last_ping = std::stoll(last, &used);
      if (used != last.size()) throw std::invalid_argument(text);
    }
    o.validate();
  } catch (const std::exception&) {
    throw InputError(std::string("--") + option + " = '" + text +
                     "'. Violated constraint: FIRST:LAST or FIRST: with 0 <= FIRST <= LAST");
  }
}

/// Writes bytes to an AtomicOutput's temporary file; throws FormatError naming the final path.
void write_bytes(const AtomicOutput& out, const char* data, std::size_t size) {
  std::ofstream f(out.temp_path(), std::ios::binary);
  f.write(data, static_cast<std::streamsize>(size));
  f.close();
  if (!f) throw FormatError("match: cannot write " + out.final_path().string());
}

}  // namespace

int run_match(const std::vector<std::string>& args) {
  po::options_description opts("options");
  std::string path_a, path_b, detectors = "sift,brisk,orb,akaze", prefilters = "none";
  std::string model = "homography", pings_a, pings_b, bounds, json_path, image_path,
              altitude_source = "auto";
  m::MatchOptions mo;
  m::PrefilterOptions pf;
  double tolerance_m = 1.0;
  // clang-format off
  opts.add_options()
    ("a", po::value(&path_a)->required(), "image A (positional)")
    ("b", po::value(&path_b)->required(), "image B (positional)")
    ("detectors", po::value(&detectors)->default_value(detectors),
     "comma-separated: sift, brisk, orb, akaze")
    ("prefilter", po::value(&prefilters)->default_value(prefilters),
     "comma-separated, each run separately: none, median, bilateral")
    ("median-ksize", po::value(&pf.median_ksize)->default_value(5), "median kernel, odd >= 3")
    ("bilateral-d", po::value(&pf.bilateral_diameter)->default_value(5), "bilateral diameter, px")
    ("bilateral-sigma-colour", po::value(&pf.bilateral_sigma_colour)->default_value(30),
     "bilateral range sigma, grey levels")
    ("bilateral-sigma-space", po::value(&pf.bilateral_sigma_space)->default_value(3),
     "bilateral spatial sigma, px")
    ("ratio", po::value(&mo.ratio)->default_value(0.8, "0.8"),
     "nearest-neighbour distance ratio, (0, 1]")
    ("model", po::value(&model)->default_value(model), "RANSAC model: homography, affine, similarity")
    ("ransac-px", po::value(&mo.ransac_threshold_px)->default_value(3.0, "3"),
     "RANSAC inlier threshold, pixels")
    ("max-features", po::value(&mo.max_features)->default_value(5000),
     "keep the strongest N keypoints per image")
    ("margin", po::value(&mo.mask_margin_px)->default_value(8),
     "no keypoint within this many pixels of nodata")
    ("tolerance", po::value(&tolerance_m)->default_value(1.0, "1"),
     "georeferenced: an inlier is correct if its pair is within this many metres of the truth")
    ("pings-a", po::value(&pings_a), "XTF A: ping range FIRST:LAST (0-based, inclusive)")
    ("pings-b", po::value(&pings_b), "XTF B: ping range FIRST:LAST")
    ("no-slant-correct", "sonar files: keep slant-range columns")
    ("altitude-source", po::value(&altitude_source)->default_value("auto"),
     "sonar files: auto | header | track: altitude for slant->ground (as for mosaic)")
    ("bounds", po::value(&bounds),
     "georeferenced: crop both to MINX,MINY,MAXX,MAXY (their CRS)")
    ("overlap", "georeferenced: crop both to the intersection of their extents")
    ("json", po::value(&json_path), "write the results as JSON to this file ('-' = stdout)")
    ("image", po::value(&image_path), "write the inlier matches as a PNG")
    ("overwrite", "replace existing output files")
    ("quiet,q", "no table on stdout");
  // clang-format on
  po::positional_options_description pos;
  pos.add("a", 1).add("b", 1);
  po::variables_map vm;
  if (!parse(args, opts, pos, vm, kUsage)) return 0;

  mo.detectors.clear();
  for (const std::string& d : split_list(detectors)) {
    mo.detectors.push_back(m::parse_detector(d, "detectors"));
  }
  std::vector<m::Prefilter> filters;
  for (const std::string& p : split_list(prefilters)) {
    filters.push_back(m::parse_prefilter(p, "prefilter"));
  }
  if (filters.empty()) throw InputError("--prefilter is empty. Violated constraint: at least one");
  mo.model = m::parse_model(model, "model");
  mo.validate();
  pf.validate();
  if (!(tolerance_m > 0)) {
    throw InputError("--tolerance = " + std::to_string(tolerance_m) + ". Violated constraint: > 0");
  }
  m::ImageSourceOptions so_a, so_b;
  if (!pings_a.empty()) parse_pings(pings_a, "pings-a", so_a);
  if (!pings_b.empty()) parse_pings(pings_b, "pings-b", so_b);
  so_a.slant_correct = so_b.slant_correct = vm.count("no-slant-correct") == 0;
  so_a.altitude_source = so_b.altitude_source =
      parse_altitude_source(altitude_source, "--altitude-source");
  std::optional<m::WorldBounds> crop;
  if (!bounds.empty()) crop = m::parse_bounds(bounds, "bounds");
  if (crop && vm.count("overlap")) {
    throw InputError("--bounds and --overlap exclude each other");
  }
  const bool overwrite = vm.count("overwrite") > 0;
  // Refuse existing outputs and missing directories before the work.
  std::unique_ptr<AtomicOutput> json_out, image_out;
  refuse_output_over_input({json_path, image_path}, {path_a, path_b});
  if (!json_path.empty() && json_path != "-") {
    json_out = std::make_unique<AtomicOutput>(json_path, overwrite);
  }
  if (!image_path.empty()) image_out = std::make_unique<AtomicOutput>(image_path, overwrite);

  m::MatchImage a = m::load_image(path_a, so_a);
  m::MatchImage b = m::load_image(path_b, so_b);
  if (vm.count("overlap")) crop = m::overlap_bounds(a, b);
  if (crop) {
    a = m::crop_to_bounds(a, *crop);
    b = m::crop_to_bounds(b, *crop);
  }

  m::MatchReport report;
  report.image_a = a.name;
  report.image_b = b.name;
  report.width_a = a.grey.cols;
  report.height_a = a.grey.rows;
  report.width_b = b.grey.cols;
  report.height_b = b.grey.rows;
  report.georeferenced = a.geotransform.has_value() && b.geotransform.has_value();
  report.options = mo;
  report.tolerance_m = tolerance_m;
  for (const m::Prefilter f : filters) {
    m::MatchImage fa = a, fb = b;
    fa.grey = m::apply_prefilter(a.grey, f, pf);
    fb.grey = m::apply_prefilter(b.grey, f, pf);
    for (const m::Detector d : mo.detectors) {
      m::MatchRow row;
      row.prefilter = f;
      row.result = m::match_features(fa, fb, d, mo);
      row.accuracy = m::geo_accuracy(fa, fb, row.result, tolerance_m);
      report.rows.push_back(std::move(row));
    }
  }

  const std::string json = m::format_json(report);
  if (json_out) write_bytes(*json_out, json.data(), json.size());
  if (image_out) {
    std::vector<std::uint8_t> png;
    const cv::Mat drawn = m::draw_inlier_matches(a.grey, b.grey, report.rows);
    if (drawn.empty() || !cv::imencode(".png", drawn, png)) {
      throw FormatError("match: cannot encode the match image " + image_path);
    }
    write_bytes(*image_out, reinterpret_cast<const char*>(png.data()), png.size());
  }
  if (json_out) json_out->commit();
  if (image_out) image_out->commit();
  if (json_path == "-") {
    std::cout << json;
  } else if (!vm.count("quiet")) {
    std::cout << m::format_table(report);
  }
  return 0;
}

#endif

}  // namespace sonarsynth::cli
