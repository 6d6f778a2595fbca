// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/raster/gdal_util.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <mutex>

#include "sonarsynth/error.hpp"

namespace sonarsynth::gdal {
namespace {
thread_local std::string g_last_error;
void CPL_STDCALL error_handler(CPLErr level, CPLErrorNum /*code*/, const char* msg) {
  if (level >= CE_Failure) g_last_error = msg ? msg : "";
  // Warnings (e.g. BAG "cornerPoints not consistent with resolution") are not errors; keep quiet.
}
}  // namespace

void ensure_registered() {
  static std::once_flag once;
  std::call_once(once, [] {
    GDALAllRegister();
    limit_block_cache();
    CPLSetErrorHandler(error_handler);
  });
}

std::unique_lock<std::recursive_mutex> lock_cached_writes() {
  static std::recursive_mutex cached_writes;
  return std::unique_lock<std::recursive_mutex>(cached_writes);
}

long long limit_block_cache() {
  if (CPLGetConfigOption("GDAL_CACHEMAX", nullptr) == nullptr) GDALSetCacheMax64(kBlockCacheBytes);
  return GDALGetCacheMax64();
}

void validate_creation_options(const char* driver_name,
                               const std::vector<std::pair<std::string, std::string>>& options,
                               const char* who) {
  if (options.empty()) return;
  ensure_registered();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name);
  if (!driver) throw FormatError(std::string(who) + ": GDAL has no " + driver_name + " driver");
  // GDAL says what is wrong in warnings: collect them for the message.
  std::string problems;
  CPLPushErrorHandlerEx(
      [](CPLErr, CPLErrorNum, const char* msg) {
        auto* out = static_cast<std::string*>(CPLGetErrorHandlerUserData());
        if (msg) *out += (out->empty() ? "" : "; ") + std::string(msg);
      },
      &problems);
  for (const auto& [key, value] : options) {
    const std::string item = key + "=" + value;
    const char* const list[] = {item.c_str(), nullptr};
    problems.clear();
    if (!GDALValidateCreationOptions(driver, const_cast<char**>(list))) {
      CPLPopErrorHandler();
      throw InputError(std::string(who) + ": creation option " + item + " is not valid for the " +
                       driver_name + " driver" + (problems.empty() ? "" : ": " + problems));
    }
  }
  CPLPopErrorHandler();
}

std::string last_error_message() {
  return g_last_error;
}

void DatasetCloser::operator()(GDALDataset* ds) const {
  if (ds) GDALClose(GDALDataset::ToHandle(ds));
}

DatasetPtr open_raster(const std::string& path, const char* what, const char* const* open_options) {
  ensure_registered();
  g_last_error.clear();
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr,
                                      open_options, nullptr);
  if (!ds) {
    throw FormatError(std::string(what) + ": cannot open raster " + path + ": " +
                      (g_last_error.empty() ? "not a raster GDAL can read" : g_last_error));
  }
  return DatasetPtr(ds);
}

DatasetPtr open_vector(const std::string& path, const char* what) {
  ensure_registered();
  g_last_error.clear();
  GDALDataset* ds =
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!ds) {
    throw FormatError(std::string(what) + ": cannot open vector file " + path + ": " +
                      (g_last_error.empty() ? "not a vector file GDAL can read" : g_last_error));
  }
  return DatasetPtr(ds);
}

void require_consistent_geographic_id(const OGRSpatialReference& srs, const std::string& path,
                                      const char* what) {
  // "GEOGCS" is the CRS itself when it is geographic, else a projected CRS's base.
  const char* auth_raw = srs.GetAuthorityName("GEOGCS");
  const char* code_raw = srs.GetAuthorityCode("GEOGCS");
  if (!auth_raw || !code_raw) return;
  const std::string auth = auth_raw;
  const std::string code = code_raw;
  // Only plain identifiers are looked up (the database, never a file or the network); any other
  // text names no code PROJ can find, so PROJ keeps the definition and nothing needs checking.
  const auto plain = [](const std::string& s) {
    return !s.empty() && s.size() <= 64 && std::all_of(s.begin(), s.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    });
  };
  if (!plain(auth) || !plain(code)) return;
  OGRSpatialReference resolved;
  const char* const options[] = {"ALLOW_NETWORK_ACCESS=NO", "ALLOW_FILE_ACCESS=NO", nullptr};
  CPLPushErrorHandler(CPLQuietErrorHandler);
  const OGRErr err = resolved.SetFromUserInput((auth + ":" + code).c_str(), options);
  CPLPopErrorHandler();
  CPLErrorReset();
  if (err != OGRERR_NONE || resolved.IsGeographic()) return;
  const char* kind = resolved.IsGeocentric()  ? "a geocentric CRS"
                     : resolved.IsProjected() ? "a projected CRS"
                                              : "not a geographic CRS";
  throw FormatError(std::string(what) + ": " + path + ": the CRS's geographic CRS has identifier " +
                    auth + ":" + code + ", which is " + kind +
                    ": the identifier contradicts the definition (correct or remove the " +
                    "identifier in the file's CRS)");
}

VectorLayer open_vector_layer(const std::string& path, const std::string& layer_name,
                              int target_epsg, bool assume_wgs84, const char* what) {
  VectorLayer v;
  v.dataset = open_vector(path, what);
  v.layer =
      layer_name.empty() ? v.dataset->GetLayer(0) : v.dataset->GetLayerByName(layer_name.c_str());
  if (!v.layer) {
    throw FormatError(
        std::string(what) + ": " + path + ": no layer " +
        (layer_name.empty() ? std::string("in the file") : "named '" + layer_name + "'"));
  }
  const OGRSpatialReference* src = v.layer->GetSpatialRef();
  if (!src) {
    if (assume_wgs84) return v;
    throw FormatError(std::string(what) + ": " + path + ": the layer has no CRS");
  }
  require_consistent_geographic_id(*src, path, what);
  OGRSpatialReference target;
  target.importFromEPSG(target_epsg);
  target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  v.to_target = {
      OGRCreateCoordinateTransformation(src, &target),
      [](OGRCoordinateTransformation* ct) { OGRCoordinateTransformation::DestroyCT(ct); }};
  if (!v.to_target) {
    throw FormatError(std::string(what) + ": " + path +
                      ": cannot transform the layer's CRS to EPSG:" + std::to_string(target_epsg));
  }
  return v;
}

void close_checked(DatasetPtr ds, const std::string& path, const char* what) {
  g_last_error.clear();
  GDALDataset* raw = ds.release();
  if (!raw) return;
  // GDAL 3.6's GDALClose returns void: a failure while flushing shows up as a logged error.
  GDALClose(GDALDataset::ToHandle(raw));
  if (!g_last_error.empty()) {
    throw FormatError(std::string(what) + ": writing " + path + " failed: " + g_last_error);
  }
}

}  // namespace sonarsynth::gdal
