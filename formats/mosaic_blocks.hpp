// SPDX-License-Identifier: MIT
#pragma once
// The finished mosaic as a GDAL dataset read window by window from the grid's tiles, so that the
// mosaic files are written without the whole image in memory (formats/mosaic_writer.cpp).

#include <gdal_priv.h>

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/gdal_util.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth::raster {

/// Computes the bands of a window of the finished mosaic: band b (from 0) of the window's
/// pixels, row-major, at `out` + b x `band_bytes`, in the dataset's type.
using WindowBands =
    std::function<void(const MosaicImage& window, unsigned char* out, std::size_t band_bytes)>;

/// A read-only dataset of `bands` bands of `type` over a finalized grid (MosaicGrid::finalize();
/// borrowed, it must outlive the dataset and stay unchanged): reads compute the pixels of a
/// window of the grid (MosaicGrid::read_window) through `fill`. Plain reads bypass GDAL's block
/// cache: a read within at most two rows of tiles is served from those rows (full width, all
/// bands) kept until a read outside them, a taller read from its own window, so a CreateCopy
/// holds about a row of its blocks, never the image. Georeferencing, metadata, band description,
/// nodata, unit, colour interpretation and colour table are set as on a MEM dataset (for the
/// copy to take). Reading in more than one thread at once is not supported (one dataset per
/// thread: the grid's reads are).
gdal::DatasetPtr grid_dataset(const MosaicGrid& grid, int bands, GDALDataType type,
                              WindowBands fill);

/// Overview factors 2, 4, ... down to < 256 pixels on the longer side (none for a small image).
std::vector<int> overview_factors(std::size_t cols, std::size_t rows);

/// Copies `src` to the GeoTIFF `temp_path` (creation options `creation_options`) with overviews
/// down to < 256 pixels (overview_factors()) computed from `src` with `resampling`, stored before
/// the full resolution image (COPY_SRC_OVERVIEWS), as when a MEM dataset with overviews built by
/// BuildOverviews is copied, the same pixels, without `src` in memory: the full resolution image
/// goes to an uncompressed temporary GeoTIFF next to `temp_path` (removed whatever happens), its
/// overviews are computed band by band as a MEM dataset computes them, then it is copied; the
/// blocks read and written through GDAL's block cache are flushed as the work progresses, so
/// that the cache does not fill with the image. Throws FormatError("<who>: <final_path>: ...").
void copy_with_overviews(GDALDataset& src, const char* resampling,
                         const std::vector<std::pair<std::string, std::string>>& creation_options,
                         const std::string& temp_path, const char* who,
                         const std::string& final_path);

}  // namespace sonarsynth::raster
