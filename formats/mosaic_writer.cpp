// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/mosaic_writer.hpp"

#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "raster_util.hpp"
#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/atomic_file.hpp"
#include "sonarsynth/formats/gdal_util.hpp"
#include "sonarsynth/version.hpp"

namespace sonarsynth {
namespace {

constexpr const char* kWho = "mosaic writer";

using KeyValues = std::vector<std::pair<std::string, std::string>>;

void set_default(KeyValues& kv, const std::string& key, const std::string& value) {
  for (const auto& [k, v] : kv) {
    if (k == key) return;
  }
  kv.emplace_back(key, value);
}

const char* colormap_name(Colormap c) {
  return c == Colormap::grey ? "grey" : "black-brown-yellow";
}

std::vector<int> overview_factors(const GridGeometry& g) {
  std::vector<int> f;
  const std::size_t largest = std::max(g.cols, g.rows);
  for (std::size_t factor = 2; largest / (factor / 2) > 256; factor *= 2) {
    f.push_back(static_cast<int>(factor));
  }
  return f;
}

/// Overviews of every band of `mem` down to < 256 pixels (none for a small image), computed
/// with `resampling`; true if any were built.
bool build_overviews(GDALDataset& mem, const GridGeometry& g, const char* resampling,
                     const std::string& path) {
  std::vector<int> factors = overview_factors(g);
  if (factors.empty()) return false;
  std::vector<int> bands_list;
  for (int b = 1; b <= mem.GetRasterCount(); ++b) bands_list.push_back(b);
  if (mem.BuildOverviews(resampling, static_cast<int>(factors.size()), factors.data(),
                         mem.GetRasterCount(), bands_list.data(), nullptr, nullptr) != CE_None) {
    throw FormatError(std::string(kWho) + ": " + path +
                      ": cannot build overviews: " + gdal::last_error_message());
  }
  return true;
}

/// The run's items, then what this file holds (the writer's word wins over the run's).
void set_metadata(GDALDataset& ds, const MosaicWriteOptions& options, const std::string& quantity,
                  const std::string& units) {
  for (const auto& [k, v] : options.metadata) ds.SetMetadataItem(k.c_str(), v.c_str());
  ds.SetMetadataItem("SONARSYNTH_VERSION", kVersion);
  ds.SetMetadataItem("SONARSYNTH_QUANTITY", quantity.c_str());
  ds.SetMetadataItem("SONARSYNTH_UNITS", units.c_str());
}

void write_intensity(const std::string& path, const std::string& temp, const GeoFrame& frame,
                     const MosaicImage& image, const MosaicWriteOptions& options) {
  const GridGeometry& g = image.geometry;
  // The bands are views of the image (and of the count as float): no copy of the image.
  std::vector<float> count;
  std::vector<const void*> views = {image.intensity.data()};
  if (options.count_band) {
    count.assign(image.count.begin(), image.count.end());
    views.push_back(count.data());
  }
  gdal::DatasetPtr mem = raster::wrap_mem(g.cols, g.rows, GDT_Float32, views, kWho, path);
  raster::set_georeferencing(*mem, frame, g, kWho, path);
  set_metadata(*mem, options, options.quantity, options.units);
  mem->SetMetadataItem("SONARSYNTH_NODATA", "NaN: no sample gridded into the pixel");
  GDALRasterBand* b1 = mem->GetRasterBand(1);
  b1->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  b1->SetDescription(options.quantity.c_str());
  b1->SetUnitType(options.units.c_str());
  if (options.count_band) {
    GDALRasterBand* b2 = mem->GetRasterBand(2);
    b2->SetDescription("count");
    b2->SetUnitType("contributions (samples and fill points) per pixel");
  }
  KeyValues co = options.creation_options;  // user options win over the defaults below
  const char* driver = "COG";
  if (options.format == MosaicRasterFormat::gtiff) {
    driver = "GTiff";
    if (build_overviews(*mem, g, "AVERAGE", path)) set_default(co, "COPY_SRC_OVERVIEWS", "YES");
    set_default(co, "TILED", "YES");
    set_default(co, "BLOCKXSIZE", "512");
    set_default(co, "BLOCKYSIZE", "512");
  } else {
    set_default(co, "BLOCKSIZE", "512");
    set_default(co, "OVERVIEW_RESAMPLING", "AVERAGE");
  }
  set_default(co, "COMPRESS", "DEFLATE");
  set_default(co, "PREDICTOR", "3");
  set_default(co, "BIGTIFF", "IF_SAFER");
  raster::copy_to_file(*mem, driver, temp, co, kWho, path);
}

void write_rgb(const std::string& path, const std::string& temp, const GeoFrame& frame,
               const MosaicImage& image, const MosaicWriteOptions& options) {
  const GridGeometry& g = image.geometry;
  const bool linear = options.linear_full_scale > 0.0;
  DisplayRange range{0.0, 1.0, options.linear_full_scale};
  if (!linear)
    range = robust_db_range(image.intensity, options.lo_percentile, options.hi_percentile);
  const std::size_t n = g.size();
  std::vector<std::uint8_t> rgba(4 * n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = range.value(image.intensity[i]);
    if (std::isnan(v)) continue;
    const Rgb8 c = colormap(options.colormap, v);
    rgba[i] = c.r;
    rgba[n + i] = c.g;
    rgba[2 * n + i] = c.b;
    rgba[3 * n + i] = 255;
  }
  std::vector<const void*> views;
  for (std::size_t b = 0; b < 4; ++b) views.push_back(rgba.data() + b * n);
  gdal::DatasetPtr mem = raster::wrap_mem(g.cols, g.rows, GDT_Byte, views, kWho, path);
  const bool png = raster::lower_extension(path) == ".png";
  if (!png) raster::set_georeferencing(*mem, frame, g, kWho, path);
  std::ostringstream scale;
  scale << range.describe();
  if (!linear) scale << ", percentiles " << options.lo_percentile << " / " << options.hi_percentile;
  if (!png) {
    set_metadata(*mem, options,
                 std::string("display colour: ") + colormap_name(options.colormap) +
                     " colormap of the " + (linear ? "linear" : "dB") + " value of " +
                     options.quantity,
                 "none (8-bit colour)");
    mem->SetMetadataItem("SONARSYNTH_DISPLAY_SCALE", scale.str().c_str());
    mem->SetMetadataItem("SONARSYNTH_NODATA", "alpha 0: no sample gridded into the pixel");
  }
  const GDALColorInterp interp[4] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand};
  const char* names[4] = {"red", "green", "blue", "alpha (0 = nodata)"};
  for (int b = 0; b < 4; ++b) {
    mem->GetRasterBand(b + 1)->SetColorInterpretation(interp[b]);
    if (!png) mem->GetRasterBand(b + 1)->SetDescription(names[b]);
  }
  KeyValues co;
  if (!png) {
    // Overviews like the float mosaic's (averaged colours; the alpha band is the mask), stored
    // after the full-resolution image as a cloud-optimised GeoTIFF has them.
    co = {{"TILED", "YES"}, {"COMPRESS", "DEFLATE"}, {"PHOTOMETRIC", "RGB"}, {"ALPHA", "YES"}};
    if (build_overviews(*mem, g, "AVERAGE", path)) co.emplace_back("COPY_SRC_OVERVIEWS", "YES");
  }
  raster::copy_to_file(*mem, png ? "PNG" : "GTiff", temp, co, kWho, path);
}

void write_labels(const std::string& path, const std::string& temp, const GeoFrame& frame,
                  const MosaicImage& image, const MosaicWriteOptions& options) {
  const GridGeometry& g = image.geometry;
  gdal::DatasetPtr mem =
      raster::wrap_mem(g.cols, g.rows, GDT_Int32, {image.labels.data()}, kWho, path);
  raster::set_georeferencing(*mem, frame, g, kWho, path);
  set_metadata(*mem, options, "truth object id of the sample nearest to nadir", "none (id)");
  mem->SetMetadataItem("SONARSYNTH_OBJECT_ID_CODES",
                       "0 = seabed, -1 = none (no seabed or object echo), > 0 = the scene "
                       "object with that id");
  mem->SetMetadataItem("SONARSYNTH_NODATA", "-2147483648: no sample in the pixel");
  GDALRasterBand* b = mem->GetRasterBand(1);
  b->SetNoDataValue(static_cast<double>(MosaicImage::kNoLabel));
  b->SetDescription("object_id");
  KeyValues co = {{"TILED", "YES"}, {"COMPRESS", "DEFLATE"}, {"BIGTIFF", "IF_SAFER"}};
  // Ids are not averaged: an overview pixel is one of its source pixels.
  if (build_overviews(*mem, g, "NEAREST", path)) co.emplace_back("COPY_SRC_OVERVIEWS", "YES");
  raster::copy_to_file(*mem, "GTiff", temp, co, kWho, path);
}

}  // namespace

void MosaicWriteOptions::validate() const {
  if (!(lo_percentile >= 0.0 && lo_percentile < hi_percentile && hi_percentile <= 100.0)) {
    std::ostringstream os;
    os << "mosaic writer: lo_percentile = " << lo_percentile
       << ", hi_percentile = " << hi_percentile
       << ". Violated constraint: 0 <= lo_percentile < hi_percentile <= 100";
    throw InputError(os.str());
  }
  if (!(linear_full_scale >= 0.0 && std::isfinite(linear_full_scale))) {
    throw InputError("mosaic writer: linear_full_scale = " + std::to_string(linear_full_scale) +
                     ". Violated constraint: linear_full_scale >= 0 (0 = dB scaling)");
  }
  // The display copy's format follows its name: a name ending in anything else would get a
  // file whose contents do not match it.
  const std::string ext = raster::lower_extension(rgb_path);
  if (!rgb_path.empty() && ext != ".tif" && ext != ".tiff" && ext != ".png") {
    throw InputError("mosaic writer: display copy " + rgb_path +
                     ": unsupported extension. Violated constraint: .tif, .tiff (GeoTIFF) or "
                     ".png (PNG)");
  }
  gdal::validate_creation_options(format == MosaicRasterFormat::gtiff ? "GTiff" : "COG",
                                  creation_options, kWho);
}

std::string default_rgb_path(const std::string& mosaic_path) {
  std::filesystem::path p(mosaic_path);
  return (p.parent_path() / (p.stem().string() + "_rgb.tif")).string();
}

void write_mosaic(const std::string& path, const GeoFrame& frame, const MosaicImage& image,
                  const MosaicWriteOptions& options) {
  options.validate();
  const GridGeometry& g = image.geometry;
  if (image.intensity.size() != g.size() || image.count.size() != g.size()) {
    throw InputError(std::string(kWho) + ": " + path + ": image buffers do not match the grid");
  }
  gdal::ensure_registered();
  // Claim every output first (existing files without overwrite fail before anything is written).
  AtomicOutput main_out(path, options.overwrite);
  std::optional<AtomicOutput> rgb_out;
  std::optional<AtomicOutput> labels_out;
  if (!options.rgb_path.empty()) rgb_out.emplace(options.rgb_path, options.overwrite);
  const bool labels = !options.labels_path.empty() && !image.labels.empty();
  if (labels) labels_out.emplace(options.labels_path, options.overwrite);

  // The three files at once, each on a thread of its own (independent GDAL datasets reading
  // the same image); every thread is joined before the outputs are committed or discarded.
  std::future<void> rgb_job, labels_job;
  if (rgb_out) {
    rgb_job = std::async(std::launch::async, [&] {
      write_rgb(options.rgb_path, rgb_out->temp_path().string(), frame, image, options);
    });
  }
  if (labels_out) {
    labels_job = std::async(std::launch::async, [&] {
      write_labels(options.labels_path, labels_out->temp_path().string(), frame, image, options);
    });
  }
  std::exception_ptr error;
  try {
    write_intensity(path, main_out.temp_path().string(), frame, image, options);
  } catch (...) {
    error = std::current_exception();
  }
  for (std::future<void>* job : {&rgb_job, &labels_job}) {
    try {
      if (job->valid()) job->get();
    } catch (...) {
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  main_out.commit();
  if (rgb_out) rgb_out->commit();
  if (labels_out) labels_out->commit();
}

}  // namespace sonarsynth
