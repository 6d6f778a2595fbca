// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/height_grid.hpp"

namespace sonarsynth {

/// How to read a bathymetry raster.
struct GridReadOptions {
  /// true: the raster stores depths (positive down) and is negated; false: elevations (up).
  bool depth_positive_down = false;
  /// 1-based band index, >= 1 and <= the raster's band count.
  int band = 1;
  /// Warp only: maximum error of GDAL's approximate coordinate transformer, in output pixels,
  /// >= 0 (0 = exact transformation of every pixel).
  double warp_error_threshold_px = 0.01;
  /// Largest grid accepted, in nodes (after warping); 0 = no limit but memory. A larger grid is
  /// refused with a FormatError naming its size before its storage is allocated.
  std::size_t max_nodes = 0;

  /// Throws InputError naming the violated constraint.
  void validate() const;
};

/// A bathymetry grid in the local frame of a UTM/UPS zone, and where it came from.
struct LoadedGrid {
  GeoFrame frame;               ///< zone + origin; frame.geodetic_from_local() georeferences nodes
  HeightGrid grid;              ///< elevations (up positive), metres; NaN = nodata
  std::string source_crs_wkt;   ///< CRS of the raster as read (WKT2)
  std::string driver;           ///< GDAL driver short name, e.g. "GTiff", "BAG"
  bool warped = false;          ///< true if the raster was resampled (bilinear) into the zone
  std::size_t valid_count = 0;  ///< number of non-NaN nodes
};

/// Reads one band of any raster GDAL opens (GeoTIFF, BAG, ASCII grid, ...).
///
/// A raster in a WGS 84 UTM/UPS CRS (EPSG 326zz/327zz/32661/32761 or an equivalent definition;
/// only the horizontal part of a compound CRS counts) with a north-up geotransform is read as is:
/// the frame is its zone with the origin at the grid centre rounded to whole kilometres, the nodes
/// are the pixel centres. Anything else (geographic, other projections or datums, rotated
/// geotransforms) is warped with bilinear resampling into the UTM/UPS zone of the raster's centre,
/// in square cells the size of the smaller side of a source pixel (no direction is downsampled,
/// so a surface linear in the source coordinates is reproduced exactly). Nodata values and NaN
/// become NaN. The heights are read straight into the grid's storage: peak memory is about one copy
/// of the grid.
///
/// Throws FormatError naming the path for a missing or unreadable file, no geotransform, no or
/// unknown CRS, a zero cell size, no valid node or no cell with 4 valid nodes; InputError for bad
/// options (e.g. a band that does not exist).
LoadedGrid read_height_grid(const std::string& path, const GridReadOptions& options = {});

/// How to write a grid as GeoTIFF.
struct GridWriteOptions {
  bool overwrite = false;  ///< replace an existing file
  /// GDAL GTiff creation options; they override the defaults TILED=YES, BLOCKXSIZE=256,
  /// BLOCKYSIZE=256, COMPRESS=DEFLATE, PREDICTOR=3, BIGTIFF=IF_SAFER.
  std::vector<std::pair<std::string, std::string>> creation_options;
  /// Dataset metadata items (e.g. the generator's effective parameters and seed).
  std::vector<std::pair<std::string, std::string>> metadata;
};

/// Writes the grid as a float32 GeoTIFF in the frame's EPSG CRS, NaN nodata, AREA_OR_POINT=Area
/// (pixel corners at node -/+ half a cell), band description "elevation" in unit "m", metadata
/// items SONARSYNTH_VERSION, SONARSYNTH_QUANTITY, SONARSYNTH_UNITS, SONARSYNTH_NODATA after
/// the options' own. Written under a temporary name and renamed when
/// complete; on any error nothing is left at `path`. Throws FormatError naming the path.
void write_height_grid_geotiff(const std::string& path, const GeoFrame& frame,
                               const HeightGrid& grid, const GridWriteOptions& options = {});

}  // namespace sonarsynth
