// SPDX-License-Identifier: MIT
#include "raster_util.hpp"

#include <cpl_string.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <filesystem>

#include "sonarsynth/error.hpp"

namespace sonarsynth::raster {
namespace {

[[noreturn]] void fail(const char* who, const std::string& path, const std::string& msg) {
  const std::string gdal_msg = gdal::last_error_message();
  throw FormatError(std::string(who) + ": " + path + ": " + msg +
                    (gdal_msg.empty() ? "" : ": " + gdal_msg));
}

}  // namespace

gdal::DatasetPtr create_mem(std::size_t cols, std::size_t rows, int bands, GDALDataType type,
                            const char* who, const std::string& path) {
  gdal::ensure_registered();
  if (cols == 0 || rows == 0 || cols > static_cast<std::size_t>(INT_MAX) ||
      rows > static_cast<std::size_t>(INT_MAX)) {
    fail(who, path,
         "image of " + std::to_string(cols) + " x " + std::to_string(rows) +
             " pixels cannot be written");
  }
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  if (!mem) fail(who, path, "GDAL has no MEM driver");
  GDALDataset* ds =
      mem->Create("", static_cast<int>(cols), static_cast<int>(rows), bands, type, nullptr);
  if (!ds) fail(who, path, "cannot allocate an in-memory image");
  return gdal::DatasetPtr(ds);
}

void write_band(GDALDataset& ds, int band, const void* data, GDALDataType type, const char* who,
                const std::string& path) {
  const int cols = ds.GetRasterXSize();
  const int rows = ds.GetRasterYSize();
  if (ds.GetRasterBand(band)->RasterIO(GF_Write, 0, 0, cols, rows, const_cast<void*>(data), cols,
                                       rows, type, 0, 0, nullptr) != CE_None) {
    fail(who, path, "cannot fill band " + std::to_string(band));
  }
}

void set_georeferencing(GDALDataset& ds, const GeoFrame& frame, const GridGeometry& g,
                        const char* who, const std::string& path) {
  double gt[6] = {g.x0_m - 0.5 * g.dx_m + frame.origin_easting_m(),  g.dx_m, 0.0,
                  g.y0_m - 0.5 * g.dy_m + frame.origin_northing_m(), 0.0,    g.dy_m};
  OGRSpatialReference srs;
  if (srs.importFromEPSG(frame.epsg()) != OGRERR_NONE) {
    fail(who, path, "unknown EPSG:" + std::to_string(frame.epsg()));
  }
  if (ds.SetGeoTransform(gt) != CE_None || ds.SetSpatialRef(&srs) != CE_None) {
    fail(who, path, "cannot set the georeferencing");
  }
  ds.SetMetadataItem("AREA_OR_POINT", "Area");
}

void copy_to_file(GDALDataset& src, const char* driver_name, const std::string& temp_path,
                  const std::vector<std::pair<std::string, std::string>>& creation_options,
                  const char* who, const std::string& final_path) {
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name);
  if (!driver) fail(who, final_path, std::string("GDAL has no ") + driver_name + " driver");
  CPLStringList co;
  for (const auto& [k, v] : creation_options) co.SetNameValue(k.c_str(), v.c_str());
  CPLErrorReset();
  GDALDataset* out =
      driver->CreateCopy(temp_path.c_str(), &src, FALSE, co.List(), nullptr, nullptr);
  if (!out) fail(who, final_path, std::string("cannot write ") + driver_name);
  gdal::close_checked(gdal::DatasetPtr(out), final_path, who);
  // Some drivers (PNG) write an .aux.xml side-car for what they cannot store; drop it.
  std::error_code ec;
  std::filesystem::remove(temp_path + ".aux.xml", ec);
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace sonarsynth::raster
