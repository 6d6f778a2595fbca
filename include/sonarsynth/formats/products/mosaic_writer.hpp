// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/colormap.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth {

/// The mosaic pixel side, metres, of `mosaic`, `simulate` (--res) and Python unless told
/// otherwise.
inline constexpr double kDefaultMosaicPixelM = 0.25;

enum class MosaicRasterFormat {
  cog,    ///< Cloud-Optimized GeoTIFF (GDAL COG driver)
  gtiff,  ///< plain tiled GeoTIFF with internal overviews
};

/// "COG"/"cog" or "GTiff"/"gtiff"; throws InputError "<what> = '<text>'. Violated constraint:
/// COG or GTiff" for anything else.
MosaicRasterFormat parse_mosaic_raster_format(const std::string& text, const std::string& what);

/// How write_mosaic() writes a MosaicImage and its companions.
struct MosaicWriteOptions {
  MosaicRasterFormat format = MosaicRasterFormat::cog;
  bool count_band = false;  ///< add band 2 "count" (float32, exact below 2^24)
  bool overwrite = false;   ///< replace existing files
  /// Driver creation options; they override the defaults (COG: BLOCKSIZE=512,
  /// COMPRESS=DEFLATE, PREDICTOR=3, OVERVIEW_RESAMPLING=AVERAGE, BIGTIFF=IF_SAFER; GTiff:
  /// TILED=YES, BLOCKXSIZE=BLOCKYSIZE=512, COMPRESS=DEFLATE, PREDICTOR=3, BIGTIFF=IF_SAFER).
  std::vector<std::pair<std::string, std::string>> creation_options;
  /// Dataset metadata items of every GeoTIFF written (e.g. the command line, or the run's
  /// run_metadata()); the writer adds SONARSYNTH_VERSION, SONARSYNTH_QUANTITY, SONARSYNTH_UNITS
  /// and SONARSYNTH_NODATA of each file.
  std::vector<std::pair<std::string, std::string>> metadata;
  /// What the mosaic's values are (band 1 description, SONARSYNTH_QUANTITY) and their unit (band
  /// 1 unit type, SONARSYNTH_UNITS): the samples' own, gridded linearly. XTF sample values
  /// (after TVG and gain, docs/physics.md §1.2; simulate says amplitude or intensity, §1.10).
  std::string quantity = "backscatter (the XTF sample values, gridded linearly)";
  std::string units = "counts";

  /// 8-bit display copy, RGBA (alpha 0 = nodata): GeoTIFF, or PNG if the name ends in .png
  /// (not georeferenced). Empty = none. The dB of the linear value between the
  /// [lo_percentile, hi_percentile] percentiles of the finite values is mapped to [0, 1] and
  /// through `colormap`.
  std::string rgb_path;
  Colormap colormap = Colormap::black_brown_yellow;
  double lo_percentile = 1.0;
  double hi_percentile = 99.0;
  /// > 0: the display copy maps value / linear_full_scale linearly instead (the percentiles are
  /// unused): the founding paper's grey level, docs/paper-model.md.
  double linear_full_scale = 0.0;
  /// true: the display copy maps 10 log10(value) from lo_db (0) to hi_db (1) instead of the
  /// percentiles (one window for every image of a dataset, docs/labels.md).
  bool fixed_db = false;
  double lo_db = 0.0;
  double hi_db = 90.0;
  /// Truth mosaic (int32 GeoTIFF on the same grid, band "object_id", nodata INT32_MIN, nearest
  /// overviews) if the image has labels. Empty = none.
  std::string labels_path;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// Writes the mosaic as float32 in the frame's EPSG CRS (326zz/327zz), NaN nodata,
/// AREA_OR_POINT=Area with the geotransform origin at the corner of the top-left pixel, band
/// description and unit from the options, average overviews (of linear values) down to
/// < 256 pixels; the GeoTIFF display copy has averaged overviews too (alpha as the mask) and the
/// band descriptions red, green, blue, "alpha (0 = nodata)" and SONARSYNTH_DISPLAY_SCALE. Every
/// output is written under a temporary name and renamed only when all are complete; on error
/// nothing is left under the final names. Throws FormatError naming the path, InputError for bad
/// options.
void write_mosaic(const std::string& path, const GeoFrame& frame, const MosaicImage& image,
                  const MosaicWriteOptions& options = {});

/// write_mosaic() of the image `grid` gives (MosaicGrid::finish()), without building it: the grid
/// is finalized (MosaicGrid::finalize(): nothing can be added afterwards) and every file is
/// written window by window from its tiles, memory about two rows of tiles per file (and GDAL's
/// chunk buffers), not the image; the display copy and the truth mosaic are written one after
/// the other beside the mosaic. `label_map` (optional) maps the gridded labels of a window to
/// what the truth mosaic stores, in place. The files are those of write_mosaic(path, frame,
/// grid.finish(), options) with the labels mapped: the same pixels at full resolution and in the
/// overviews, metadata, georeferencing and layout. A temporary GeoTIFF of overview levels is
/// written next to each GeoTIFF with overviews and removed whatever happens.
void write_mosaic(const std::string& path, const GeoFrame& frame, MosaicGrid& grid,
                  const MosaicWriteOptions& options = {},
                  const std::function<void(std::span<std::int32_t>)>& label_map = {});

/// "<dir>/<stem>_rgb.tif" for "<dir>/<stem>.<ext>".
std::string default_rgb_path(const std::string& mosaic_path);

}  // namespace sonarsynth
