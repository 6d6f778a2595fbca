// SPDX-License-Identifier: MIT
#pragma once
// Images for feature matching: any GDAL raster (PNG waterfall, GeoTIFF mosaic) or a ping range of
// an XTF file, as 8-bit grey with a validity mask and, when georeferenced, the geotransform.

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "sonarsynth/bottom_track.hpp"

namespace sonarsynth::match {

/// GDAL's affine geotransform: x = g[0] + col g[1] + row g[2], y = g[3] + col g[4] + row g[5],
/// (col, row) at pixel corners.
using GeoTransform = std::array<double, 6>;

struct MatchImage {
  std::string name;  ///< the source (path, with the ping range for XTF), for messages and reports
  cv::Mat grey;      ///< CV_8UC1
  cv::Mat mask;      ///< CV_8UC1, same size: 255 = data, 0 = nodata
  std::optional<GeoTransform> geotransform;
  std::string crs_wkt;  ///< CRS of the geotransform ("" if none)

  /// World coordinates of an image point (OpenCV convention: pixel centres at integers).
  /// Requires a geotransform.
  cv::Point2d world(cv::Point2d pixel) const;
  /// Inverse of world().
  cv::Point2d pixel(cv::Point2d world_xy) const;
};

/// How sources are turned into 8-bit images.
struct ImageSourceOptions {
  /// XTF only: pings [first_ping, last_ping] (0-based among pings with samples, inclusive);
  /// last_ping < 0 = to the end.
  std::int64_t first_ping = 0;
  std::int64_t last_ping = -1;
  /// XTF/JSF only: columns in ground range on a flat bottom (as `sonarsynth waterfall --slant`).
  bool slant_correct = true;
  /// XTF/JSF with slant_correct: where each ping's altitude comes from, as for `waterfall` and
  /// `mosaic` (docs/conversion.md; auto: the header's unless missing, <= 0 or disagreeing with
  /// the bottom tracked from the first return).
  AltitudeSource altitude_source = AltitudeSource::kAuto;
  /// Non-8-bit rasters and XTF are linear intensities, displayed in dB between these percentiles.
  double lo_percentile = 1.0;
  double hi_percentile = 99.0;
  /// Largest image accepted (columns x rows).
  std::int64_t max_pixels = std::int64_t{1} << 28;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Loads `path`: an XTF file (extension .xtf) as a waterfall of a ping range, otherwise any raster
/// GDAL reads. 8-bit rasters: 1 band grey, 3-4 bands RGB(A) converted to grey; other types: band 1
/// as linear intensity in dB. GDAL's mask (nodata, alpha) and NaN become the mask. Throws
/// FormatError naming the file for a missing or unreadable file, InputError for a bad option.
MatchImage load_image(const std::string& path, const ImageSourceOptions& options = {});

/// An axis-aligned rectangle in world coordinates (the images' CRS).
struct WorldBounds {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  /// Throws InputError unless min < max on both axes.
  void validate() const;
};

/// Parses "MINX,MINY,MAXX,MAXY"; throws InputError naming `option`.
WorldBounds parse_bounds(const std::string& text, const char* option);

/// The pixels of a north-up georeferenced image whose centres lie inside `bounds`, with the
/// geotransform moved accordingly. Throws InputError if the image is not georeferenced, rotated,
/// or has no pixel inside.
MatchImage crop_to_bounds(const MatchImage& image, const WorldBounds& bounds);

/// The intersection of the extents of two georeferenced images. Throws InputError if either is
/// not georeferenced, the CRSs differ, or they do not overlap.
WorldBounds overlap_bounds(const MatchImage& a, const MatchImage& b);

}  // namespace sonarsynth::match
