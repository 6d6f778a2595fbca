// SPDX-License-Identifier: MIT
#pragma once
// The finished mosaic as a GDAL dataset read window by window from the grid's tiles, so that the
// mosaic files are written without the whole image in memory (formats/products/mosaic_writer.cpp).

#include <gdal_priv.h>

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth::raster {

/// Computes the bands of a window of the finished mosaic: band b (from 0) of the window's
/// pixels, row-major, at `out` + b x `band_bytes`, in the dataset's type.
using WindowBands =
    std::function<void(const MosaicImage& window, unsigned char* out, std::size_t band_bytes)>;

/// A read-only dataset of `bands` bands of `type` over a finalized grid (MosaicGrid::finalize();
/// borrowed, it must outlive the dataset and stay unchanged): reads compute the pixels of the
/// grid's tiles (MosaicGrid::read_window) through `fill`, a row of tiles (full width, all bands)
/// at a time, the last two rows kept. Plain reads bypass GDAL's block cache, so that a
/// CreateCopy holds about two rows of tiles, never the image. Georeferencing, metadata, band
/// description, nodata, unit, colour interpretation and colour table are set as on a MEM
/// dataset (for the copy to take). One thread at a time per dataset (the grid's reads may run
/// in several at once).
gdal::DatasetPtr grid_dataset(const MosaicGrid& grid, int bands, GDALDataType type,
                              WindowBands fill);

/// Overview factors 2, 4, ... down to < 256 pixels on the longer side (none for a small image).
std::vector<int> overview_factors(std::size_t cols, std::size_t rows);

/// Copies `src` (a grid_dataset()) to the GeoTIFF `temp_path` (creation options
/// `creation_options`) with overviews down to < 256 pixels (overview_factors()) computed from
/// `src` with `resampling` and stored before the full resolution image (COPY_SRC_OVERVIEWS): the
/// file a MEM dataset with BuildOverviews' overviews is copied to, without `src` in memory. The
/// overview levels go to an uncompressed temporary GeoTIFF next to `temp_path` (removed
/// whatever happens) that first receives the full resolution once, and are computed from it band
/// by band with GDALRegenerateOverviews as a MEM dataset computes them, their blocks flushed from
/// GDAL's cache after each band (within a band, the cache's limit bounds them: gdal_util.hpp).
/// Throws FormatError("<who>: <final_path>: ...").
void copy_with_overviews(GDALDataset& src, const char* resampling,
                         const std::vector<std::pair<std::string, std::string>>& creation_options,
                         const std::string& temp_path, const char* who,
                         const std::string& final_path);

/// Ground control points of a raster that is not an affine grid (a waterfall in slant range):
/// pixel/line of the pixel's centre (col + 0.5, row + 0.5) and its easting/northing in EPSG:epsg.
struct GroundControl {
  int epsg = 0;
  struct Point {
    double pixel = 0.0, line = 0.0, easting_m = 0.0, northing_m = 0.0;
  };
  std::vector<Point> points;
};

/// Copies `src` to `temp_path` as a plain tiled GeoTIFF (`creation_options`): the full
/// resolution image first, then `resampling` overviews down to < 256 pixels appended to the file
/// (`--of GTiff`; GDAL's COPY_SRC_OVERVIEWS would write the COG layout, which GDAL reports as
/// LAYOUT=COG). Throws FormatError("<who>: <final_path>: ...").
void copy_plain_with_overviews(
    GDALDataset& src, const char* resampling,
    const std::vector<std::pair<std::string, std::string>>& creation_options,
    const std::string& temp_path, const char* who, const std::string& final_path);

/// Makes the tiled GeoTIFF `from` (written, closed) into `to` with internal overviews down to
/// < 256 pixels (overview_factors(); none for a small image), laid out as GDAL's COG validator
/// asks (overviews before the full resolution, COPY_SRC_OVERVIEWS): the levels are built in
/// `from` first, band b with `resampling[b - 1]` (the last entry for further bands; NEAREST for
/// classes and ids, AVERAGE for continuous values), then copied with `creation_options`. `gcps`
/// (if it has points) are set on the copy. `cog_layout` false (`--of GTiff`): a plain tiled
/// GeoTIFF instead, the image first and the same overviews appended after it. `from` is removed
/// afterwards whatever happens. Throws FormatError("<who>: <final_path>: ...").
void copy_adding_overviews(const std::string& from, const std::string& to,
                           const std::vector<std::string>& resampling,
                           const std::vector<std::pair<std::string, std::string>>& creation_options,
                           const GroundControl& gcps, const char* who,
                           const std::string& final_path, bool cog_layout = true);

}  // namespace sonarsynth::raster
