// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/formats/products/output_paths.hpp"
#include "sonarsynth/formats/products/xtf_mosaic.hpp"

namespace sonarsynth {

/// What `sonarsynth mosaic` and Python's sonarsynth.mosaic() make (docs/conversion.md): sonar
/// files of any listed format gridded into one GeoTIFF mosaic and its display copy.
struct MosaicRequest {
  std::vector<std::filesystem::path> inputs;  ///< sonar files, >= 1 (format read from content)
  std::filesystem::path output;               ///< the float32 GeoTIFF mosaic
  XtfMosaicOptions options;                   ///< pixel size, rule, altitude source, ...
  /// Format, creation options, count band, overwrite, display copy (rgb_path; empty: none) and
  /// metadata; SONARSYNTH_MOSAIC_RULE, SONARSYNTH_ALTITUDE_SOURCE and
  /// SONARSYNTH_GAIN_NORMALISATION are appended to `write.metadata` from `options`.
  MosaicWriteOptions write;
  /// Slant->ground against this elevation grid (any GDAL raster; its UTM zone is used); empty:
  /// a flat bottom at each ping's altitude.
  std::filesystem::path bathymetry;
  bool bathymetry_depth_positive = false;  ///< `bathymetry` stores depths (positive down)
  /// Each warning as it arises (skipped files, dropped pings, reader anomalies, ...), before the
  /// mosaic is written; the summary lists them too.
  std::function<void(const std::string&)> on_warning;
  /// The names error messages give the arguments (the CLI's flags by default).
  struct ArgumentNames {
    std::string output = "-o";
    std::string rgb = "--rgb";
    std::string bathymetry = "--bathymetry";
    std::string depth_positive = "--depth-positive";
  } names;
};

/// What mosaic_files() did: the counts of XtfMosaicResult (its image released once written),
/// the warnings, and the files written.
struct MosaicSummary {
  XtfMosaicResult result;  ///< result.image.geometry kept, its pixel vectors emptied
  std::vector<std::string> warnings;
  std::filesystem::path output;
  std::filesystem::path rgb_path;  ///< empty: no display copy
  double pixel_size_m = 0.0;

  /// The line `sonarsynth mosaic` prints on success ("wrote m.tif: 812 x 640 pixels of 0.25 m,
  /// EPSG:32631, ..."), without the newline.
  std::string text() const;
};

/// Grids `request.inputs` (mosaic_xtf()) and writes the mosaic and its display copy
/// (write_mosaic()). Before any file is read: refuses outputs that name the same file or an
/// input, existing outputs without write.overwrite, and invalid options (InputError naming the
/// argument). Throws InputError when a bathymetry does not overlap the survey, FormatError
/// naming every input when no ping could be gridded (and the errors of mosaic_xtf() and
/// write_mosaic()); nothing is left under the output names on error.
MosaicSummary mosaic_files(const MosaicRequest& request);

/// "mean" (weighted_mean), "max" or "nearest"; throws InputError "<what> = '<text>'. Violated
/// constraint: one of mean, max, nearest" for anything else.
MosaicRule parse_mosaic_rule(const std::string& text, const std::string& what);
const char* to_string(MosaicRule rule);  ///< "mean", "max", "nearest"

}  // namespace sonarsynth
