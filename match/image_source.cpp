// SPDX-License-Identifier: MIT
#include "sonarsynth/match/image_source.hpp"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/formats/registry/sidescan_source.hpp"
#include "sonarsynth/formats/registry/sonar_formats.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth::match {
namespace {

constexpr const char* kWho = "match";

/// Linear intensities (NaN = nodata) -> 8-bit dB display and mask.
void linear_to_grey(const std::vector<float>& linear, int cols, int rows,
                    const ImageSourceOptions& o, MatchImage& img) {
  const DisplayRange range = robust_db_range(linear, o.lo_percentile, o.hi_percentile);
  img.grey = cv::Mat(rows, cols, CV_8UC1, cv::Scalar(0));
  img.mask = cv::Mat(rows, cols, CV_8UC1, cv::Scalar(0));
  for (int r = 0; r < rows; ++r) {
    auto* g = img.grey.ptr<std::uint8_t>(r);
    auto* m = img.mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      const float v = linear[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) +
                             static_cast<std::size_t>(c)];
      if (!std::isfinite(v)) continue;
      const double d = range.value(v);
      g[c] = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(d, 0.0, 1.0)));
      m[c] = 255;
    }
  }
}

MatchImage load_sonar_file(const std::string& path, const ImageSourceOptions& o) {
  if (!std::filesystem::exists(path)) {
    throw FormatError(std::string(kWho) + ": cannot open " + path + ": no such file");
  }
  WaterfallOptions wo;
  wo.slant_correct = o.slant_correct;
  wo.altitude_source = o.altitude_source;
  Waterfall wf(wo);
  const WaterfallResult r = add_file_pings(path, wf, wo, o.first_ping, o.last_ping);
  if (wf.rows() == 0) {
    throw FormatError(std::string(kWho) + ": " + path + ": no ping with samples in pings " +
                      std::to_string(o.first_ping) + ":" +
                      (o.last_ping < 0 ? std::string("end") : std::to_string(o.last_ping)) +
                      " (the file has " + std::to_string(r.pings_with_samples) + ")");
  }
  if (static_cast<std::int64_t>(wf.rows() * wf.cols()) > o.max_pixels) {
    throw InputError(std::string(kWho) + ": " + path + ": waterfall of " +
                     std::to_string(wf.cols()) + " x " + std::to_string(wf.rows()) +
                     " pixels is too large; choose a smaller ping range");
  }
  MatchImage img;
  img.name = path + "[pings " + std::to_string(o.first_ping) + ":" +
             std::to_string(o.first_ping + static_cast<std::int64_t>(wf.rows()) - 1) + "]";
  linear_to_grey(wf.image(), static_cast<int>(wf.cols()), static_cast<int>(wf.rows()), o, img);
  return img;
}

void read_band(GDALRasterBand* band, GDALDataType type, void* data, int cols, int rows,
               const std::string& path) {
  if (band->RasterIO(GF_Read, 0, 0, cols, rows, data, cols, rows, type, 0, 0) != CE_None) {
    throw FormatError(std::string(kWho) + ": cannot read " + path + ": " +
                      gdal::last_error_message());
  }
}

MatchImage load_raster(const std::string& path, const ImageSourceOptions& o) {
  gdal::DatasetPtr ds = gdal::open_raster(path, kWho);
  const int cols = ds->GetRasterXSize();
  const int rows = ds->GetRasterYSize();
  const int bands = ds->GetRasterCount();
  if (bands < 1 || cols < 1 || rows < 1) {
    throw FormatError(std::string(kWho) + ": " + path + ": no raster band");
  }
  if (static_cast<std::int64_t>(cols) * rows > o.max_pixels) {
    throw InputError(std::string(kWho) + ": " + path + ": " + std::to_string(cols) + " x " +
                     std::to_string(rows) + " pixels is too large (max " +
                     std::to_string(o.max_pixels) + ")");
  }
  MatchImage img;
  img.name = path;
  GDALRasterBand* b1 = ds->GetRasterBand(1);
  if (b1->GetRasterDataType() == GDT_Byte) {
    std::vector<int> colour;  // bands that are not alpha
    for (int i = 1; i <= bands && colour.size() < 3; ++i) {
      if (ds->GetRasterBand(i)->GetColorInterpretation() != GCI_AlphaBand) colour.push_back(i);
    }
    if (colour.size() >= 3) {
      cv::Mat rgb[3];
      for (int k = 0; k < 3; ++k) {
        rgb[k] = cv::Mat(rows, cols, CV_8UC1);
        read_band(ds->GetRasterBand(colour[static_cast<std::size_t>(k)]), GDT_Byte, rgb[k].data,
                  cols, rows, path);
      }
      cv::Mat merged;
      cv::merge(rgb, 3, merged);
      cv::cvtColor(merged, img.grey, cv::COLOR_RGB2GRAY);
    } else {
      img.grey = cv::Mat(rows, cols, CV_8UC1);
      read_band(b1, GDT_Byte, img.grey.data, cols, rows, path);
    }
    img.mask = cv::Mat(rows, cols, CV_8UC1);
    read_band(b1->GetMaskBand(), GDT_Byte, img.mask.data, cols, rows, path);
    cv::threshold(img.mask, img.mask, 0, 255, cv::THRESH_BINARY);
  } else {
    std::vector<float> linear(static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows));
    read_band(b1, GDT_Float32, linear.data(), cols, rows, path);
    cv::Mat gdal_mask(rows, cols, CV_8UC1);
    read_band(b1->GetMaskBand(), GDT_Byte, gdal_mask.data, cols, rows, path);
    for (std::size_t i = 0; i < linear.size(); ++i) {
      if (gdal_mask.data[i] == 0) linear[i] = std::numeric_limits<float>::quiet_NaN();
    }
    linear_to_grey(linear, cols, rows, o, img);
  }
  GeoTransform gt{};
  if (ds->GetGeoTransform(gt.data()) == CE_None &&
      !(gt[0] == 0 && gt[1] == 1 && gt[2] == 0 && gt[3] == 0 && gt[4] == 0 && gt[5] == 1)) {
    img.geotransform = gt;
    if (const OGRSpatialReference* srs = ds->GetSpatialRef()) {
      char* wkt = nullptr;
      if (srs->exportToWkt(&wkt) == OGRERR_NONE && wkt) img.crs_wkt = wkt;
      CPLFree(wkt);
    }
  }
  return img;
}

}  // namespace

cv::Point2d MatchImage::world(cv::Point2d p) const {
  if (!geotransform) throw InputError(std::string(kWho) + ": " + name + " is not georeferenced");
  const GeoTransform& g = *geotransform;
  const double c = p.x + 0.5, r = p.y + 0.5;
  return {g[0] + c * g[1] + r * g[2], g[3] + c * g[4] + r * g[5]};
}

cv::Point2d MatchImage::pixel(cv::Point2d w) const {
  if (!geotransform) throw InputError(std::string(kWho) + ": " + name + " is not georeferenced");
  const GeoTransform& g = *geotransform;
  const double det = g[1] * g[5] - g[2] * g[4];
  const double dx = w.x - g[0], dy = w.y - g[3];
  const double c = (g[5] * dx - g[2] * dy) / det;
  const double r = (-g[4] * dx + g[1] * dy) / det;
  return {c - 0.5, r - 0.5};
}

void ImageSourceOptions::validate() const {
  if (first_ping < 0) {
    throw InputError("first ping = " + std::to_string(first_ping) +
                     ". Violated constraint: first ping >= 0");
  }
  if (last_ping >= 0 && last_ping < first_ping) {
    throw InputError("ping range " + std::to_string(first_ping) + ":" + std::to_string(last_ping) +
                     ". Violated constraint: first <= last");
  }
  if (!(lo_percentile >= 0 && lo_percentile < hi_percentile && hi_percentile <= 100)) {
    throw InputError("percentiles " + std::to_string(lo_percentile) + ", " +
                     std::to_string(hi_percentile) + ". Violated constraint: 0 <= lo < hi <= 100");
  }
  if (max_pixels < 1) throw InputError("max_pixels must be >= 1");
}

MatchImage load_image(const std::string& path, const ImageSourceOptions& options) {
  options.validate();
  // Sonar files (any format of the format list) by extension or by content.
  if (sonar_format_for_extension(path)) return load_sonar_file(path, options);
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec) && identify_sonar_format(path)) {
    return load_sonar_file(path, options);
  }
  return load_raster(path, options);
}

void WorldBounds::validate() const {
  if (!(std::isfinite(min_x) && std::isfinite(min_y) && std::isfinite(max_x) &&
        std::isfinite(max_y) && min_x < max_x && min_y < max_y)) {
    std::ostringstream os;
    os.precision(12);
    os << "bounds " << min_x << "," << min_y << "," << max_x << "," << max_y
       << ". Violated constraint: finite, min < max on both axes";
    throw InputError(os.str());
  }
}

WorldBounds parse_bounds(const std::string& text, const char* option) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      v.clear();
      break;
    }
  }
  if (v.size() != 4) {
    throw InputError(std::string("--") + option + " = '" + text +
                     "'. Violated constraint: four numbers MINX,MINY,MAXX,MAXY");
  }
  WorldBounds b{v[0], v[1], v[2], v[3]};
  try {
    b.validate();
  } catch (const InputError& e) {
    throw InputError(std::string("--") + option + ": " + e.what());
  }
  return b;
}

MatchImage crop_to_bounds(const MatchImage& image, const WorldBounds& bounds) {
  bounds.validate();
  if (!image.geotransform) {
    throw InputError(std::string(kWho) + ": " + image.name +
                     " is not georeferenced: it cannot be cropped to world bounds");
  }
  const GeoTransform& g = *image.geotransform;
  if (g[2] != 0 || g[4] != 0) {
    throw InputError(std::string(kWho) + ": " + image.name +
                     " is rotated (not north-up): it cannot be cropped to world bounds");
  }
  // Pixel centres inside: x = g0 + (c + 0.5) g1 in [min_x, max_x], same for rows.
  auto range = [](double origin, double step, double lo, double hi, int n) {
    double a = (lo - origin) / step - 0.5, b = (hi - origin) / step - 0.5;
    if (a > b) std::swap(a, b);
    const int first = std::max(0, static_cast<int>(std::ceil(a)));
    const int last = std::min(n - 1, static_cast<int>(std::floor(b)));
    return std::pair{first, last};
  };
  const auto [c0, c1] = range(g[0], g[1], bounds.min_x, bounds.max_x, image.grey.cols);
  const auto [r0, r1] = range(g[3], g[5], bounds.min_y, bounds.max_y, image.grey.rows);
  if (c1 < c0 || r1 < r0) {
    std::ostringstream os;
    os.precision(12);
    os << kWho << ": " << image.name << " has no pixel inside the bounds " << bounds.min_x << ","
       << bounds.min_y << "," << bounds.max_x << "," << bounds.max_y;
    throw InputError(os.str());
  }
  const cv::Rect roi(c0, r0, c1 - c0 + 1, r1 - r0 + 1);
  MatchImage out;
  out.name = image.name;
  out.grey = image.grey(roi).clone();
  out.mask = image.mask(roi).clone();
  out.crs_wkt = image.crs_wkt;
  GeoTransform moved = g;
  moved[0] = g[0] + c0 * g[1];
  moved[3] = g[3] + r0 * g[5];
  out.geotransform = moved;
  return out;
}

WorldBounds overlap_bounds(const MatchImage& a, const MatchImage& b) {
  for (const MatchImage* m : {&a, &b}) {
    if (!m->geotransform) {
      throw InputError(std::string(kWho) + ": " + m->name +
                       " is not georeferenced: no overlap can be computed");
    }
  }
  if (!a.crs_wkt.empty() && !b.crs_wkt.empty()) {
    OGRSpatialReference sa, sb;
    sa.importFromWkt(a.crs_wkt.c_str());
    sb.importFromWkt(b.crs_wkt.c_str());
    if (!sa.IsSame(&sb)) {
      throw InputError(std::string(kWho) + ": " + a.name + " and " + b.name +
                       " are in different CRSs");
    }
  }
  auto extent = [](const MatchImage& m) {
    const cv::Point2d p0 = m.world({-0.5, -0.5});
    const cv::Point2d p1 = m.world({m.grey.cols - 0.5, m.grey.rows - 0.5});
    return WorldBounds{std::min(p0.x, p1.x), std::min(p0.y, p1.y), std::max(p0.x, p1.x),
                       std::max(p0.y, p1.y)};
  };
  const WorldBounds ea = extent(a), eb = extent(b);
  const WorldBounds o{std::max(ea.min_x, eb.min_x), std::max(ea.min_y, eb.min_y),
                      std::min(ea.max_x, eb.max_x), std::min(ea.max_y, eb.max_y)};
  if (!(o.min_x < o.max_x && o.min_y < o.max_y)) {
    throw InputError(std::string(kWho) + ": " + a.name + " and " + b.name + " do not overlap");
  }
  return o;
}

}  // namespace sonarsynth::match
