// SPDX-License-Identifier: MIT
#pragma once
// Private helpers of the raster writers (mosaic, waterfall): in-memory datasets copied to a
// file through any GDAL driver.

#include <gdal_priv.h>

#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/gdal_util.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/height_grid.hpp"

namespace sonarsynth::raster {

/// An empty MEM dataset; throws FormatError("<who>: ... <path>") on failure.
gdal::DatasetPtr create_mem(std::size_t cols, std::size_t rows, int bands, GDALDataType type,
                            const char* who, const std::string& path);

/// Writes a whole band from a row-major buffer of `type`.
void write_band(GDALDataset& ds, int band, const void* data, GDALDataType type, const char* who,
                const std::string& path);

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
