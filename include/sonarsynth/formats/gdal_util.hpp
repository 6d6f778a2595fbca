// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <string>

class GDALDataset;

namespace sonarsynth::gdal {

/// Registers GDAL's drivers once (thread-safe) and routes GDAL's error messages so that
/// sonarsynth reports them in its exceptions instead of GDAL printing them.
void ensure_registered();

struct DatasetCloser {
  void operator()(GDALDataset* ds) const;
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

/// Opens a raster read-only; throws FormatError("<what>: cannot open <path>: <GDAL message>").
DatasetPtr open_raster(const std::string& path, const char* what,
                       const char* const* open_options = nullptr);
/// Opens a vector dataset read-only; throws FormatError naming the path.
DatasetPtr open_vector(const std::string& path, const char* what);
/// Closes a dataset that was written, turning a failed close (e.g. a full disk while flushing)
/// into a FormatError naming the path.
void close_checked(DatasetPtr ds, const std::string& path, const char* what);
/// The message of GDAL's last error, or "" if none.
std::string last_error_message();

}  // namespace sonarsynth::gdal
