// SPDX-License-Identifier: MIT
// libFuzzer target: the bathymetry grid reader (read_height_grid) over arbitrary bytes written
// to a GDAL in-memory file. It must end with a grid or a sonarsynth::Error naming the file; any
// other exception escapes and is reported as a crash, as are crashes, hangs and leaks.
//
// Only the single-file raster formats a bathymetry comes in are let through (GeoTIFF, ASCII and
// Surfer grids); others (notably VRT, whose XML may point at any file, and the HDF5-based BAG,
// whose parser is a separate library) are skipped. Rasters over kMaxPixels and grids over
// kMaxNodes after warping are refused, so that memory stays bounded.
#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/raster/gdal_grid.hpp"

namespace {

constexpr const char* kPath = "/vsimem/sonarsynth_fuzz_grid";
constexpr long long kMaxPixels = 1 << 20;
constexpr std::size_t kMaxNodes = std::size_t{1} << 21;

bool allowed_driver(const std::string& name) {
  return name == "GTiff" || name == "AAIGrid" || name == "GSAG" || name == "GSBG" ||
         name == "GS7BG";
}

// Whether GDAL opens the file as a raster of at most kMaxPixels per band and 4 bands.
bool small_enough() {
  GDALDatasetH ds = GDALOpenEx(kPath, GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!ds) return true;  // the reader reports it
  const long long pixels = static_cast<long long>(GDALGetRasterXSize(ds)) * GDALGetRasterYSize(ds);
  const int bands = GDALGetRasterCount(ds);
  GDALClose(ds);
  return pixels <= kMaxPixels && bands <= 4;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  GDALAllRegister();
  CPLSetErrorHandler(CPLQuietErrorHandler);
  CPLSetConfigOption("GDAL_CACHEMAX", "32");
  CPLSetConfigOption("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");  // no sidecar probing
  CPLSetConfigOption("GTIFF_REPORT_COMPD_CS", "YES");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  VSILFILE* f =
      VSIFileFromMemBuffer(kPath, const_cast<GByte*>(data), static_cast<vsi_l_offset>(size), FALSE);
  if (!f) return 0;
  VSIFCloseL(f);
  GDALDriverH driver = GDALIdentifyDriver(kPath, nullptr);
  if (driver && allowed_driver(GDALGetDriverShortName(driver)) && small_enough()) {
    try {
      sonarsynth::GridReadOptions options;
      options.max_nodes = kMaxNodes;
      options.depth_positive_down = size % 2 == 1;
      const sonarsynth::LoadedGrid grid = sonarsynth::read_height_grid(kPath, options);
      (void)grid;
    } catch (const sonarsynth::Error&) {
      // a clear error naming the file is the expected outcome
    }
  }
  VSIUnlink(kPath);
  return 0;
}
