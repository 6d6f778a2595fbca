// SPDX-License-Identifier: MIT
#pragma once
// Private helpers of the raster writers (mosaic, waterfall): in-memory or streamed datasets
// copied to a file through any GDAL driver.

#include <gdal_priv.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/height_grid.hpp"

namespace sonarsynth::raster {

/// An empty MEM dataset; throws FormatError("<who>: ... <path>") on failure.
gdal::DatasetPtr create_mem(std::size_t cols, std::size_t rows, int bands, GDALDataType type,
                            const char* who, const std::string& path);

/// A MEM dataset whose bands are views of the caller's row-major buffers of `type` (no copy), in
/// order; they must outlive the dataset and are not written to unless the caller writes to a
/// band. Throws FormatError("<who>: ... <path>") on failure.
gdal::DatasetPtr wrap_mem(std::size_t cols, std::size_t rows, GDALDataType type,
                          const std::vector<const void*>& bands, const char* who,
                          const std::string& path);

// BANDMAP_TYPE (GDAL >= 3.7) is int* unless GDAL_BANDMAP_TYPE_CONST_SAFE is defined.
#ifdef BANDMAP_TYPE
using BandMap = BANDMAP_TYPE;
#else
using BandMap = int*;
#endif

/// An IRasterIO call that is a plain read: no resampling, no fractional window.
bool plain_read(GDALRWFlag flag, int x0, int y0, int nx, int ny, int buf_nx, int buf_ny,
                const GDALRasterIOExtraArg* extra);

/// A read-only band whose plain reads go straight to its dataset's `read(x0, y0, nx, ny,
/// band_count, band_map, out, out_type, pixel_space, line_space, band_space)`, bypassing GDAL's
/// block cache; resampled reads (overviews, thumbnails) go through the blocks (IReadBlock),
/// writes fail there.
template <typename Dataset>
class DirectReadBand : public GDALRasterBand {
 protected:
  Dataset& dataset() { return *static_cast<Dataset*>(poDS); }
  CPLErr IRasterIO(GDALRWFlag flag, int x0, int y0, int nx, int ny, void* data, int buf_nx,
                   int buf_ny, GDALDataType buf_type, GSpacing pixel_space, GSpacing line_space,
                   GDALRasterIOExtraArg* extra) override {
    if (plain_read(flag, x0, y0, nx, ny, buf_nx, buf_ny, extra)) {
      return dataset().read(x0, y0, nx, ny, 1, &nBand, data, buf_type, pixel_space, line_space, 0);
    }
    return GDALRasterBand::IRasterIO(flag, x0, y0, nx, ny, data, buf_nx, buf_ny, buf_type,
                                     pixel_space, line_space, extra);
  }
};

/// The rows of an image, produced in order for stream_to_file().
class RowSource {
 public:
  virtual ~RowSource() = default;
  /// Writes the next row (the first after construction or rewind()) to `out`: band b (from 0)
  /// at `out` + b x cols pixels of the dataset's type.
  virtual void next(void* out) = 0;
  /// Starts again at the first row.
  virtual void rewind() = 0;
};

/// What a streamed file says it holds: dataset metadata items (domain "") and, per band (from
/// band 1; fewer entries leave the rest unset), a description and a unit type; a nodata value
/// for every band if `nodata` is set.
struct RasterLabels {
  std::vector<std::pair<std::string, std::string>> metadata;
  std::vector<std::string> descriptions;
  std::vector<std::string> units;
  bool has_nodata = false;
  double nodata = 0.0;
  /// Per band (from band 1): metadata items of the band (domain "").
  std::vector<std::vector<std::pair<std::string, std::string>>> band_metadata;
  /// Colour table of band 1 (r, g, b, a of the values 0, 1, ...), GTiff only; empty = none.
  std::vector<std::array<short, 4>> color_table;
  /// Per band (from band 1): GDAL scale and offset (value = offset + scale x stored); NaN or
  /// absent = none set.
  std::vector<double> scales;
  std::vector<double> offsets;
};

/// Sets everything `labels` says on `ds` (its `bands` bands): metadata, descriptions, band
/// metadata, colour table, units, nodata.
void describe_dataset(GDALDataset& ds, const RasterLabels& labels, int bands);

/// Writes the `rows` rows of `source` to `temp_path` through driver `driver` (creation options as
/// for copy_to_file(), labelled with `labels`) without holding the image:
/// a driver that can create files (GTiff) gets the rows one at a time and each completed row of
/// blocks is flushed, so GDAL's block cache does not fill up with the image; others (PNG) get a
/// CreateCopy from a dataset whose reads are served row by row from `source`, bypassing the
/// block cache. Closes the file and checks for errors like copy_to_file(). An exception thrown
/// by `source` propagates (GTiff) or fails the copy with its message (PNG).
void stream_to_file(RowSource& source, std::size_t cols, std::size_t rows, int bands,
                    GDALDataType type, const char* driver, const std::string& temp_path,
                    const std::vector<std::pair<std::string, std::string>>& creation_options,
                    const RasterLabels& labels, const char* who, const std::string& final_path);

/// One file of stream_to_files(): as the arguments of stream_to_file() (the driver must be able
/// to create files: GTiff).
struct StreamTarget {
  RowSource* source = nullptr;
  int bands = 1;
  GDALDataType type = GDT_Byte;
  std::string temp_path;
  std::vector<std::pair<std::string, std::string>> creation_options;
  RasterLabels labels;
  std::string final_path;
};

/// Writes several files of the same size at once, row r of every file before row r + 1 of any:
/// sources that share one reader (e.g. bands of one spool row) then read their rows once. Each
/// file is what stream_to_file() writes from the same source and arguments.
void stream_to_files(std::vector<StreamTarget>& targets, std::size_t cols, std::size_t rows,
                     const char* driver, const char* who);

/// Writes the `rows` rows of `source` (1 band: grey, or 3: red, green, blue; 8 bits) to
/// `temp_path` as a PNG through libpng, row by row, with `metadata` in tEXt chunks as GDAL's PNG
/// driver writes them (WRITE_METADATA_AS_TEXT), no row filter (GDAL's driver always applies
/// libpng's adaptive filters: twice the CPU for a larger file here) and the image data
/// compressed by ISA-L's igzip (level 3). Throws
/// FormatError("<who>: <final_path>: ...") on failure; an exception of `source` propagates.
void stream_to_png(RowSource& source, std::size_t cols, std::size_t rows, int bands,
                   const std::vector<std::pair<std::string, std::string>>& metadata,
                   const std::string& temp_path, const char* who, const std::string& final_path);

/// North-up geotransform with the origin at the corner of the top-left pixel (nodes of
/// `geometry` are pixel centres), the frame's EPSG CRS and AREA_OR_POINT=Area.
void set_georeferencing(GDALDataset& ds, const GeoFrame& frame, const GridGeometry& geometry,
                        const char* who, const std::string& path);

/// CreateCopy of `src` to `temp_path` with driver `driver` and creation options; closes the copy
/// and checks for errors. `final_path` names the output in messages.
void copy_to_file(GDALDataset& src, const char* driver, const std::string& temp_path,
                  const std::vector<std::pair<std::string, std::string>>& creation_options,
                  const char* who, const std::string& final_path);

/// Lower-case extension of a path, with the dot (".png"), or "".
std::string lower_extension(const std::string& path);

}  // namespace sonarsynth::raster
