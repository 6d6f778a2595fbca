// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/raster/gdal_grid.hpp"

#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <new>
#include <string>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth {
namespace {

constexpr const char* kReader = "grid reader";
constexpr const char* kWriter = "grid writer";
// Rows are read and written in strips of about this many bytes; GDAL's block cache is flushed
// after each strip so that it never holds more than one strip besides the grid itself.
constexpr std::size_t kStripBytes = std::size_t{32} << 20;

[[noreturn]] void fail(const char* who, const std::string& path, const std::string& msg) {
  throw FormatError(std::string(who) + ": " + path + ": " + msg);
}

std::string gdal_message() {
  const std::string m = gdal::last_error_message();
  return m.empty() ? "" : ": " + m;
}

// EPSG code of the WGS 84 UTM/UPS CRS that `srs` is equivalent to (horizontal part), or 0.
int wgs84_utmups_epsg(const OGRSpatialReference& srs) {
  if (!srs.IsProjected()) return 0;
  int north = 0;
  const int zone = srs.GetUTMZone(&north);
  std::vector<int> candidates;
  if (zone >= 1 && zone <= 60) {
    candidates.push_back((north ? 32600 : 32700) + zone);
  } else {
    candidates = {32661, 32761};
  }
  const char* const same_options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES",
                                      "CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS", nullptr};
  for (const int code : candidates) {
    OGRSpatialReference ref;
    if (ref.importFromEPSG(code) != OGRERR_NONE) continue;
    if (srs.IsSame(&ref, same_options)) return code;
  }
  return 0;
}

GeoFrame frame_for_epsg(int epsg, double centre_e, double centre_n) {
  const double oe = std::round(centre_e / 1000.0) * 1000.0;
  const double on = std::round(centre_n / 1000.0) * 1000.0;
  if (epsg == 32661) return GeoFrame(0, true, oe, on);
  if (epsg == 32761) return GeoFrame(0, false, oe, on);
  return GeoFrame(epsg % 100, epsg / 100 == 326, oe, on);
}

// Reads `band` (whole raster) as float32 straight into `out`, strip by strip.
void read_band(const std::string& path, GDALRasterBand* band, GDALDataset* also_flush, int cols,
               int rows, float* out) {
  const std::size_t row_bytes = static_cast<std::size_t>(cols) * sizeof(float);
  int block_x = 0, block_y = 0;
  band->GetBlockSize(&block_x, &block_y);
  const std::size_t by = static_cast<std::size_t>(std::max(1, block_y));
  const std::size_t strip_rows =
      std::max<std::size_t>(1, kStripBytes / (row_bytes * by)) * by;  // whole block rows
  for (std::size_t r0 = 0; r0 < static_cast<std::size_t>(rows); r0 += strip_rows) {
    const int n = static_cast<int>(std::min(strip_rows, static_cast<std::size_t>(rows) - r0));
    const CPLErr err = band->RasterIO(GF_Read, 0, static_cast<int>(r0), cols, n,
                                      out + r0 * static_cast<std::size_t>(cols), cols, n,
                                      GDT_Float32, 0, 0, nullptr);
    if (err != CE_None) {
      fail(kReader, path,
           "reading rows " + std::to_string(r0) + ".." + std::to_string(r0 + n) + " failed" +
               gdal_message());
    }
    band->FlushCache(false);
    if (also_flush) also_flush->FlushCache(false);
  }
}

// Reads an axis-aligned raster whose CRS is WGS 84 UTM/UPS `epsg`.
LoadedGrid read_aligned(const std::string& path, GDALDataset* ds, GDALRasterBand* band,
                        GDALDataset* also_flush, int epsg, const GridReadOptions& options) {
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None) fail(kReader, path, "no geotransform after warping");
  const int cols = ds->GetRasterXSize();
  const int rows = ds->GetRasterYSize();
  const double centre_e = gt[0] + 0.5 * gt[1] * cols;
  const double centre_n = gt[3] + 0.5 * gt[5] * rows;
  GeoFrame frame = frame_for_epsg(epsg, centre_e, centre_n);

  GridGeometry g;
  g.cols = static_cast<std::size_t>(cols);
  g.rows = static_cast<std::size_t>(rows);
  g.dx_m = gt[1];
  g.dy_m = gt[5];
  g.x0_m = gt[0] + 0.5 * gt[1] - frame.origin_easting_m();
  g.y0_m = gt[3] + 0.5 * gt[5] - frame.origin_northing_m();
  try {
    g.validate(kReader);
  } catch (const InputError& e) {
    fail(kReader, path, e.what());
  }

  if (options.max_nodes > 0 && g.size() > options.max_nodes) {
    fail(kReader, path,
         "grid of " + std::to_string(g.cols) + " x " + std::to_string(g.rows) +
             " nodes. Violated constraint: nodes <= max_nodes = " +
             std::to_string(options.max_nodes));
  }
  std::vector<float> heights;
  try {
    heights.resize(g.size());
  } catch (const std::bad_alloc&) {
    fail(kReader, path,
         "cannot allocate " + std::to_string(g.size() * sizeof(float)) + " bytes for the grid");
  }
  read_band(path, band, also_flush, cols, rows, heights.data());

  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  const float nodata_f = static_cast<float>(nodata);
  const bool use_nodata = has_nodata != 0 && !std::isnan(nodata);
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const float sign = options.depth_positive_down ? -1.0f : 1.0f;
  // Nodata markers, declared or not (no height: is_height), become holes.
  std::size_t valid = 0;
  for (float& h : heights) {
    if (!is_height(h) || (use_nodata && h == nodata_f)) {
      h = kNaN;
    } else {
      h *= sign;
      ++valid;
    }
  }
  if (const std::string problem = seabed_grid_problem(g, heights); !problem.empty())
    fail(kReader, path, problem);
  return LoadedGrid{frame, HeightGrid(g, std::move(heights)), "", "", false, valid};
}

}  // namespace

void GridReadOptions::validate() const {
  if (band < 1) {
    throw InputError("grid reader: band = " + std::to_string(band) +
                     ". Violated constraint: band >= 1");
  }
  if (!(warp_error_threshold_px >= 0.0) || !std::isfinite(warp_error_threshold_px)) {
    throw InputError(
        "grid reader: warp_error_threshold_px = " + std::to_string(warp_error_threshold_px) +
        ". Violated constraint: warp_error_threshold_px >= 0");
  }
}

namespace {

/// read_height_grid() of a raster not aligned with a UTM/UPS zone: band options.band of `src`
/// (CRS `srs`, geotransform `gt`) warped bilinearly into the zone of the raster's centre.
LoadedGrid read_warped(const std::string& path, GDALDataset& src, const OGRSpatialReference& srs,
                       const double (&gt)[6], const std::string& crs_label,
                       const std::string& source_wkt, const GridReadOptions& options) {
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84(
      OGRCreateCoordinateTransformation(&srs, &wgs84));
  if (!to_wgs84) {
    fail(kReader, path, "unknown CRS '" + crs_label + "' (no transformation to WGS 84)");
  }
  const double half_c = 0.5 * src.GetRasterXSize();
  const double half_r = 0.5 * src.GetRasterYSize();
  double cx = gt[0] + gt[1] * half_c + gt[2] * half_r;
  double cy = gt[3] + gt[4] * half_c + gt[5] * half_r;
  if (!to_wgs84->Transform(1, &cx, &cy) || !std::isfinite(cx) || !std::isfinite(cy)) {
    fail(kReader, path,
         "the raster's centre cannot be transformed from '" + crs_label + "' to WGS 84");
  }
  Geodetic centre;
  centre.lat_rad = rad_from_deg(cy);
  centre.lon_rad = rad_from_deg(cx);
  const int target_epsg = GeoFrame::around(centre).epsg();

  // Output cells: square, the smaller of the source pixel's two sides (measured at the centre in
  // the target zone). Every direction is then upsampled (ratio <= 1), where GDAL's bilinear is
  // the plain 2 x 2 interpolation; when downsampling GDAL widens the kernel, whose discrete
  // weights then no longer reproduce even a linear surface exactly.
  OGRSpatialReference target;
  target.importFromEPSG(target_epsg);
  target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_target(
      OGRCreateCoordinateTransformation(&srs, &target));
  double px[3] = {half_c, half_c + 1.0, half_c};
  double py[3] = {half_r, half_r, half_r + 1.0};
  double tx[3], ty[3];
  for (int i = 0; i < 3; ++i) {
    tx[i] = gt[0] + gt[1] * px[i] + gt[2] * py[i];
    ty[i] = gt[3] + gt[4] * px[i] + gt[5] * py[i];
  }
  if (!to_target || !to_target->Transform(3, tx, ty)) {
    fail(kReader, path,
         "cannot transform from '" + crs_label + "' to EPSG:" + std::to_string(target_epsg) +
             gdal_message());
  }
  const double res_m =
      std::min(std::hypot(tx[1] - tx[0], ty[1] - ty[0]), std::hypot(tx[2] - tx[0], ty[2] - ty[0]));
  if (!(res_m > 0.0) || !std::isfinite(res_m)) {
    fail(kReader, path,
         "zero or undefined cell size after projecting to EPSG:" + std::to_string(target_epsg));
  }

  // One band only (gdalwarp 3.6 warps every band): an in-memory VRT selecting it.
  gdal::DatasetPtr selected;
  GDALDatasetH warp_input = GDALDataset::ToHandle(&src);
  if (src.GetRasterCount() > 1) {
    CPLStringList targs;
    targs.AddString("-of");
    targs.AddString("VRT");
    targs.AddString("-b");
    targs.AddString(std::to_string(options.band).c_str());
    GDALTranslateOptions* topts = GDALTranslateOptionsNew(targs.List(), nullptr);
    int usage_error = 0;
    GDALDatasetH h = GDALTranslate("", warp_input, topts, &usage_error);
    GDALTranslateOptionsFree(topts);
    if (!h)
      fail(kReader, path, "cannot select band " + std::to_string(options.band) + gdal_message());
    selected.reset(GDALDataset::FromHandle(h));
    warp_input = h;
  }
  CPLStringList wargs;
  for (const char* a : {"-of", "VRT", "-r", "bilinear", "-ot", "Float32", "-dstnodata", "nan"}) {
    wargs.AddString(a);
  }
  wargs.AddString("-s_srs");
  wargs.AddString(source_wkt.c_str());
  wargs.AddString("-t_srs");
  wargs.AddString(("EPSG:" + std::to_string(target_epsg)).c_str());
  wargs.AddString("-tr");
  wargs.AddString(CPLSPrintf("%.17g", res_m));
  wargs.AddString(CPLSPrintf("%.17g", res_m));
  wargs.AddString("-et");
  wargs.AddString(std::to_string(options.warp_error_threshold_px).c_str());
  GDALWarpAppOptions* wopts = GDALWarpAppOptionsNew(wargs.List(), nullptr);
  int usage_error = 0;
  GDALDatasetH warped_h = GDALWarp("", nullptr, 1, &warp_input, wopts, &usage_error);
  GDALWarpAppOptionsFree(wopts);
  if (!warped_h) {
    fail(kReader, path,
         "cannot warp from '" + crs_label + "' to EPSG:" + std::to_string(target_epsg) +
             gdal_message());
  }
  gdal::DatasetPtr warped(GDALDataset::FromHandle(warped_h));
  LoadedGrid out = read_aligned(path, warped.get(), warped->GetRasterBand(1),
                                selected ? selected.get() : &src, target_epsg, options);
  out.warped = true;
  return out;
}

}  // namespace

LoadedGrid read_height_grid(const std::string& path, const GridReadOptions& options) {
  options.validate();
  gdal::ensure_registered();
  // Plain paths get a clear "does not exist"; GDAL syntaxes (/vsi..., DRIVER:file:...) go to GDAL.
  if (path.rfind("/vsi", 0) != 0 && path.find(':') == std::string::npos) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail(kReader, path, "no such file");
  }

  // BAG: the vertical CRS is a placeholder; ask for the horizontal CRS only.
  CPLStringList open_options;
  GDALDriverH identified = GDALIdentifyDriver(path.c_str(), nullptr);
  if (identified && std::string(GDALGetDriverShortName(identified)) == "BAG") {
    open_options.SetNameValue("REPORT_VERTCRS", "NO");
  }
  gdal::DatasetPtr src = gdal::open_raster(path, kReader, open_options.List());
  const std::string driver = src->GetDriver() ? src->GetDriver()->GetDescription() : "";

  const int band_count = src->GetRasterCount();
  if (options.band > band_count) {
    throw InputError("grid reader: " + path + ": band = " + std::to_string(options.band) +
                     ". Violated constraint: band <= " + std::to_string(band_count) +
                     " (the raster's band count)");
  }
  double gt[6];
  if (src->GetGeoTransform(gt) != CE_None) {
    fail(kReader, path, "no georeferencing (the raster has no geotransform)");
  }
  for (const double v : gt) {
    if (!std::isfinite(v)) fail(kReader, path, "geotransform has a non-finite coefficient");
  }
  const bool rotated = gt[2] != 0.0 || gt[4] != 0.0;
  if (!rotated && (gt[1] == 0.0 || gt[5] == 0.0)) {
    fail(kReader, path,
         "cell size " + std::to_string(gt[1]) + " x " + std::to_string(gt[5]) +
             " (geotransform). Violated constraint: cell size != 0");
  }
  if (rotated && gt[1] * gt[5] - gt[2] * gt[4] == 0.0) {
    fail(kReader, path, "geotransform is singular (zero cell size)");
  }

  const OGRSpatialReference* ds_srs = src->GetSpatialRef();
  if (!ds_srs || ds_srs->IsEmpty()) {
    fail(kReader, path, "no georeferencing (the raster has no coordinate reference system)");
  }
  OGRSpatialReference srs(*ds_srs);
  if (srs.IsCompound()) srs.StripVertical();
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  char* wkt_raw = nullptr;
  const char* const wkt_options[] = {"FORMAT=WKT2", nullptr};
  srs.exportToWkt(&wkt_raw, wkt_options);
  std::string source_wkt = wkt_raw ? wkt_raw : "";
  CPLFree(wkt_raw);
  const char* crs_name = srs.GetName();
  const std::string crs_label = crs_name ? crs_name : "(unnamed)";
  if (srs.IsLocal() || !(srs.IsProjected() || srs.IsGeographic())) {
    fail(kReader, path,
         "unknown CRS '" + crs_label + "' (neither geographic nor projected on a known datum)");
  }

  gdal::require_consistent_geographic_id(srs, path, kReader);

  GDALRasterBand* band = src->GetRasterBand(options.band);
  const int epsg = rotated || gt[1] < 0.0 ? 0 : wgs84_utmups_epsg(srs);
  if (epsg != 0) {
    LoadedGrid out = read_aligned(path, src.get(), band, nullptr, epsg, options);
    out.source_crs_wkt = std::move(source_wkt);
    out.driver = driver;
    return out;
  }

  LoadedGrid out = read_warped(path, *src, srs, gt, crs_label, source_wkt, options);
  out.source_crs_wkt = std::move(source_wkt);
  out.driver = driver;
  return out;
}

void write_height_grid_geotiff(const std::string& path, const GeoFrame& frame,
                               const HeightGrid& grid, const GridWriteOptions& options) {
  const GridGeometry& g = grid.geometry();
  try {
    g.validate(kWriter);
  } catch (const InputError& e) {
    fail(kWriter, path, e.what());
  }
  if (grid.heights().size() != g.size()) fail(kWriter, path, "grid storage does not match size");
  if (g.cols > static_cast<std::size_t>(INT_MAX) || g.rows > static_cast<std::size_t>(INT_MAX)) {
    fail(kWriter, path,
         "grid of " + std::to_string(g.cols) + " x " + std::to_string(g.rows) +
             " nodes is too large for GeoTIFF");
  }
  gdal::ensure_registered();
  AtomicOutput out(path, options.overwrite);
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) fail(kWriter, path, "GDAL has no GTiff driver");

  CPLStringList co;
  co.SetNameValue("TILED", "YES");
  co.SetNameValue("BLOCKXSIZE", "256");
  co.SetNameValue("BLOCKYSIZE", "256");
  co.SetNameValue("COMPRESS", "DEFLATE");
  co.SetNameValue("PREDICTOR", "3");
  co.SetNameValue("BIGTIFF", "IF_SAFER");
  for (const auto& [k, v] : options.creation_options) co.SetNameValue(k.c_str(), v.c_str());

  const int cols = static_cast<int>(g.cols);
  const int rows = static_cast<int>(g.rows);
  const std::string temp = out.temp_path().string();
  CPLErrorReset();  // a failure logged from here on (e.g. a bad creation option) fails the write
  GDALDataset* raw = driver->Create(temp.c_str(), cols, rows, 1, GDT_Float32, co.List());
  if (!raw) fail(kWriter, path, "cannot create GeoTIFF" + gdal_message());
  gdal::DatasetPtr ds(raw);

  // Area pixels: the node is the pixel centre, so the corner is half a cell before it.
  double gt[6] = {g.x0_m - 0.5 * g.dx_m + frame.origin_easting_m(),  g.dx_m, 0.0,
                  g.y0_m - 0.5 * g.dy_m + frame.origin_northing_m(), 0.0,    g.dy_m};
  OGRSpatialReference srs;
  if (srs.importFromEPSG(frame.epsg()) != OGRERR_NONE) {
    fail(kWriter, path, "unknown EPSG:" + std::to_string(frame.epsg()) + gdal_message());
  }
  if (ds->SetGeoTransform(gt) != CE_None || ds->SetSpatialRef(&srs) != CE_None) {
    fail(kWriter, path, "cannot set the georeferencing" + gdal_message());
  }
  ds->SetMetadataItem("AREA_OR_POINT", "Area");
  for (const auto& [k, v] : options.metadata) ds->SetMetadataItem(k.c_str(), v.c_str());
  ds->SetMetadataItem("SONARSYNTH_VERSION", kVersion);
  ds->SetMetadataItem("SONARSYNTH_QUANTITY", "seabed elevation (positive up)");
  ds->SetMetadataItem("SONARSYNTH_UNITS", "m");
  ds->SetMetadataItem("SONARSYNTH_NODATA", "NaN: no height");
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  band->SetDescription("elevation");
  band->SetUnitType("m");

  const std::size_t row_bytes = g.cols * sizeof(float);
  const std::size_t strip_rows = std::max<std::size_t>(1, kStripBytes / (row_bytes * 256)) * 256;
  float* data = const_cast<float*>(grid.heights().data());  // GF_Write only reads the buffer
  for (std::size_t r0 = 0; r0 < g.rows; r0 += strip_rows) {
    const int n = static_cast<int>(std::min(strip_rows, g.rows - r0));
    if (band->RasterIO(GF_Write, 0, static_cast<int>(r0), cols, n, data + r0 * g.cols, cols, n,
                       GDT_Float32, 0, 0, nullptr) != CE_None) {
      fail(kWriter, path, "writing rows failed" + gdal_message());
    }
    if (band->FlushCache(false) != CE_None) fail(kWriter, path, "writing failed" + gdal_message());
  }
  if (CPLGetLastErrorType() >= CE_Failure) {
    fail(kWriter, path, std::string("GDAL reported an error: ") + CPLGetLastErrorMsg());
  }
  gdal::close_checked(std::move(ds), path, kWriter);
  out.commit();
}

}  // namespace sonarsynth
