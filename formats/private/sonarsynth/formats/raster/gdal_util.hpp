// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

class GDALDataset;
class OGRLayer;
class OGRCoordinateTransformation;
class OGRSpatialReference;

namespace sonarsynth::gdal {

/// Registers GDAL's drivers once (thread-safe), limits GDAL's block cache (limit_block_cache())
/// and routes GDAL's error messages so that sonarsynth reports them in its exceptions instead of
/// GDAL printing them.
void ensure_registered();

/// The limit of GDAL's block cache that limit_block_cache() sets: GDAL's default, 5 % of the
/// machine's memory, let the cache hold a whole line's truth raster while its overviews were
/// computed and copied (the peak of `simulate`); the writers read and write a row of blocks at a
/// time, so a small cache costs no CPU (docs/benchmarks.md, "Peak memory: GDAL's block cache").
inline constexpr long long kBlockCacheBytes = 8LL << 20;

/// Sets GDAL's block cache limit (process-wide) to kBlockCacheBytes unless GDAL_CACHEMAX is set,
/// in the environment or as a GDAL configuration option: then GDAL's own reading of it stands.
/// Returns the limit in force.
long long limit_block_cache();

/// Serialises the writes that go through GDAL's block cache (CreateCopy, overviews, RasterIO
/// writes followed by a flush): the cache is the process's, and a dirty block that another
/// thread's use of the cache evicts is written to its file at that moment, so two such writes at
/// once would store their blocks in an order that depends on timing. Under this lock a file's
/// blocks go to it in the same order on every run (docs/labels.md). Whole-block writes
/// (WriteBlock) bypass the cache and need no lock. Recursive: a copy may call another under it.
[[nodiscard]] std::unique_lock<std::recursive_mutex> lock_cached_writes();

struct DatasetCloser {
  void operator()(GDALDataset* ds) const;
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

/// Opens a raster read-only; throws FormatError("<what>: cannot open <path>: <GDAL message>").
DatasetPtr open_raster(const std::string& path, const char* what,
                       const char* const* open_options = nullptr);
/// Opens a vector dataset read-only; throws FormatError naming the path.
DatasetPtr open_vector(const std::string& path, const char* what);
/// One layer of a vector file, with the transformation of its geometries into a target CRS.
struct VectorLayer {
  DatasetPtr dataset;
  OGRLayer* layer = nullptr;  ///< owned by `dataset`
  /// Layer CRS -> EPSG:target (x = easting/longitude, y = northing/latitude); null when the layer
  /// has no CRS and `assume_wgs84` was given (coordinates are taken as longitude, latitude).
  std::unique_ptr<OGRCoordinateTransformation, void (*)(OGRCoordinateTransformation*)> to_target{
      nullptr, nullptr};
};
/// Opens `layer_name` (empty = the first layer) of a vector file and prepares the transformation
/// into EPSG:`target_epsg` in traditional GIS axis order. Throws FormatError naming the path for
/// a missing file or layer, or a CRS that cannot be transformed (or none, unless assume_wgs84).
VectorLayer open_vector_layer(const std::string& path, const std::string& layer_name,
                              int target_epsg, bool assume_wgs84, const char* what);
/// Throws FormatError("<what>: <path>: ...") when the identifier of the CRS's geographic CRS (the
/// CRS itself, or a projected CRS's base) names an authority code that is a different kind of CRS,
/// e.g. GEOGCS[...,AUTHORITY["EPSG","4978"]] where EPSG:4978 is geocentric. The definition and
/// its identifier then contradict each other, and PROJ 9.1 (the version Debian 12 ships)
/// dereferences a null pointer when it looks for a coordinate operation from such a CRS
/// (docs/architecture.md, "Input CRSs"). Call it before OGRCreateCoordinateTransformation on a
/// CRS read from a user's file.
void require_consistent_geographic_id(const OGRSpatialReference& srs, const std::string& path,
                                      const char* what);
/// Closes a dataset that was written, turning a failed close (e.g. a full disk while flushing)
/// into a FormatError naming the path.
void close_checked(DatasetPtr ds, const std::string& path, const char* what);
/// Throws InputError("<who>: creation option KEY=VALUE is not valid for the <driver> driver:
/// <GDAL's reason>") for the first option GDAL's driver `driver` does not accept (unknown key,
/// value out of its list or range), so that a typo is refused before any work is done.
void validate_creation_options(const char* driver,
                               const std::vector<std::pair<std::string, std::string>>& options,
                               const char* who);
/// The message of GDAL's last error, or "" if none.
std::string last_error_message();

}  // namespace sonarsynth::gdal
