// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/gdal_util.hpp"

#include <cpl_error.h>
#include <gdal_priv.h>

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
    CPLSetErrorHandler(error_handler);
  });
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
