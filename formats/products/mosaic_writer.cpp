// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/mosaic_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <sstream>

#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/products/mosaic_blocks.hpp"
#include "sonarsynth/formats/raster/gdal_util.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"
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

/// Where a GeoTIFF's overviews are made: on the in-memory source, or through a temporary file
/// (raster::copy_with_overviews(): a source streamed from the grid's tiles); copied before the
/// full resolution image (COPY_SRC_OVERVIEWS) either way.
enum class Overviews { on_source, on_file };

/// Overviews of every band of `mem` down to < 256 pixels (none for a small image), computed
/// with `resampling`; true if any were built.
bool build_overviews(GDALDataset& mem, const GridGeometry& g, const char* resampling,
                     const std::string& path) {
  std::vector<int> factors = raster::overview_factors(g.cols, g.rows);
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

/// Copies `src` to `temp` as a GeoTIFF (`co`) with `resampling` overviews made as `overviews`
/// says, in the COG layout (overviews before the image) unless `format` is gtiff.
void copy_with_overviews(GDALDataset& src, const GridGeometry& g, Overviews overviews,
                         const char* resampling, KeyValues co, const std::string& temp,
                         const std::string& path, MosaicRasterFormat format) {
  if (format == MosaicRasterFormat::gtiff) {
    raster::copy_plain_with_overviews(src, resampling, co, temp, kWho, path);
    return;
  }
  if (overviews == Overviews::on_source && build_overviews(src, g, resampling, path)) {
    set_default(co, "COPY_SRC_OVERVIEWS", "YES");
  }
  if (overviews == Overviews::on_file) {
    raster::copy_with_overviews(src, resampling, co, temp, kWho, path);
    return;
  }
  raster::copy_to_file(src, "GTiff", temp, co, kWho, path);
}

/// The run's items, then what this file holds (the writer's word wins over the run's).
void set_metadata(GDALDataset& ds, const MosaicWriteOptions& options, const std::string& quantity,
                  const std::string& units) {
  for (const auto& [k, v] : options.metadata) ds.SetMetadataItem(k.c_str(), v.c_str());
  ds.SetMetadataItem("SONARSYNTH_VERSION", kVersion);
  ds.SetMetadataItem("SONARSYNTH_QUANTITY", quantity.c_str());
  ds.SetMetadataItem("SONARSYNTH_UNITS", units.c_str());
}

/// mosaic.tif from `src` (intensity, and count as float if options.count_band).
void write_intensity(const std::string& path, const std::string& temp, const GeoFrame& frame,
                     GDALDataset& src, const GridGeometry& g, const MosaicWriteOptions& options,
                     Overviews overviews) {
  raster::set_georeferencing(src, frame, g, kWho, path);
  set_metadata(src, options, options.quantity, options.units);
  src.SetMetadataItem("SONARSYNTH_NODATA", "NaN: no sample gridded into the pixel");
  GDALRasterBand* b1 = src.GetRasterBand(1);
  b1->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  b1->SetDescription(options.quantity.c_str());
  b1->SetUnitType(options.units.c_str());
  if (options.count_band) {
    GDALRasterBand* b2 = src.GetRasterBand(2);
    b2->SetDescription("count");
    b2->SetUnitType("contributions (samples and fill points) per pixel");
  }
  KeyValues co = options.creation_options;  // user options win over the defaults below
  // DEFLATE level 1 unless the codec was chosen: on the paper survey's mosaic 0.61x level 6's
  // CPU for a file 1.6 % larger (docs/benchmarks.md, "Products at codec speed").
  const bool default_codec =
      std::none_of(co.begin(), co.end(), [](const auto& kv) { return kv.first == "COMPRESS"; });
  set_default(co, "COMPRESS", "DEFLATE");
  if (default_codec) {
    set_default(co, options.format == MosaicRasterFormat::gtiff ? "ZLEVEL" : "LEVEL", "1");
  }
  set_default(co, "PREDICTOR", "3");
  set_default(co, "BIGTIFF", "IF_SAFER");
  if (options.format == MosaicRasterFormat::gtiff) {
    set_default(co, "TILED", "YES");
    set_default(co, "BLOCKXSIZE", "512");
    set_default(co, "BLOCKYSIZE", "512");
    copy_with_overviews(src, g, overviews, "AVERAGE", co, temp, path, options.format);
    return;
  }
  // The COG driver computes the overviews from the source itself, into a temporary file it
  // compresses with ZSTD by default: 6 MB of compressor state per band (17 MB of the end phase's
  // heap with three bands' buffers); LZW keeps a few kB, the same overviews (lossless either
  // way). Set for this thread only, restored after.
  set_default(co, "BLOCKSIZE", "512");
  set_default(co, "OVERVIEW_RESAMPLING", "AVERAGE");
  const char* before = CPLGetThreadLocalConfigOption("COG_TMP_COMPRESSION", nullptr);
  const std::optional<std::string> saved =
      before ? std::optional<std::string>(before) : std::nullopt;
  if (!CPLGetConfigOption("COG_TMP_COMPRESSION", nullptr)) {
    CPLSetThreadLocalConfigOption("COG_TMP_COMPRESSION", "LZW");
  }
  try {
    raster::copy_to_file(src, "COG", temp, co, kWho, path);
  } catch (...) {
    CPLSetThreadLocalConfigOption("COG_TMP_COMPRESSION", saved ? saved->c_str() : nullptr);
    throw;
  }
  CPLSetThreadLocalConfigOption("COG_TMP_COMPRESSION", saved ? saved->c_str() : nullptr);
}

/// The display colours of `intensity` (n values) for range `range`: bands r, g, b, alpha at
/// `out` + b x n.
void display_colours(std::span<const float> intensity, const DisplayRange& range, Colormap map,
                     std::uint8_t* out) {
  const std::size_t n = intensity.size();
  std::fill_n(out, 4 * n, std::uint8_t{0});
  for (std::size_t i = 0; i < n; ++i) {
    const double v = range.value(intensity[i]);
    if (std::isnan(v)) continue;
    const Rgb8 c = colormap(map, v);
    out[i] = c.r;
    out[n + i] = c.g;
    out[2 * n + i] = c.b;
    out[3 * n + i] = 255;
  }
}

/// mosaic_rgb from `src` (the 4 bands of display_colours() for `range`).
void write_rgb(const std::string& path, const std::string& temp, const GeoFrame& frame,
               GDALDataset& src, const GridGeometry& g, const MosaicWriteOptions& options,
               const DisplayRange& range, Overviews overviews) {
  const bool linear = options.linear_full_scale > 0.0;
  const bool png = raster::lower_extension(path) == ".png";
  if (!png) raster::set_georeferencing(src, frame, g, kWho, path);
  std::ostringstream scale;
  scale << range.describe();
  if (!linear && !options.fixed_db) {
    scale << ", percentiles " << options.lo_percentile << " / " << options.hi_percentile;
  }
  if (!png) {
    set_metadata(src, options,
                 std::string("display colour: ") + colormap_name(options.colormap) +
                     " colormap of the " + (linear ? "linear" : "dB") + " value of " +
                     options.quantity,
                 "none (8-bit colour)");
    src.SetMetadataItem("SONARSYNTH_DISPLAY_SCALE", scale.str().c_str());
    src.SetMetadataItem("SONARSYNTH_NODATA", "alpha 0: no sample gridded into the pixel");
  }
  const GDALColorInterp interp[4] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand};
  const char* names[4] = {"red", "green", "blue", "alpha (0 = nodata)"};
  for (int b = 0; b < 4; ++b) {
    src.GetRasterBand(b + 1)->SetColorInterpretation(interp[b]);
    if (!png) src.GetRasterBand(b + 1)->SetDescription(names[b]);
  }
  if (png) {
    raster::copy_to_file(src, "PNG", temp, {}, kWho, path);
    return;
  }
  // Overviews like the float mosaic's (averaged colours; the alpha band is the mask). DEFLATE
  // level 1: on the paper scene's display copy a third of level 6's time for a file 3.7 %
  // larger (docs/benchmarks.md, "The waterfall's deflate stream and the display copy's level").
  copy_with_overviews(src, g, overviews, "AVERAGE",
                      {{"TILED", "YES"},
                       {"COMPRESS", "DEFLATE"},
                       {"ZLEVEL", "1"},
                       {"PHOTOMETRIC", "RGB"},
                       {"ALPHA", "YES"}},
                      temp, path, options.format);
}

/// truth_mosaic.tif from `src` (int32 truth labels).
void write_labels(const std::string& path, const std::string& temp, const GeoFrame& frame,
                  GDALDataset& src, const GridGeometry& g, const MosaicWriteOptions& options,
                  Overviews overviews) {
  raster::set_georeferencing(src, frame, g, kWho, path);
  set_metadata(src, options, "truth object id of the sample nearest to nadir", "none (id)");
  src.SetMetadataItem("SONARSYNTH_OBJECT_ID_CODES",
                      "0 = seabed, -1 = none (no seabed or object echo), > 0 = the scene "
                      "object with that id");
  src.SetMetadataItem("SONARSYNTH_NODATA", "-2147483648: no sample in the pixel");
  GDALRasterBand* b = src.GetRasterBand(1);
  b->SetNoDataValue(static_cast<double>(MosaicImage::kNoLabel));
  b->SetDescription("object_id");
  // Ids are not averaged: an overview pixel is one of its source pixels.
  copy_with_overviews(src, g, overviews, "NEAREST",
                      {{"TILED", "YES"}, {"COMPRESS", "DEFLATE"}, {"BIGTIFF", "IF_SAFER"}}, temp,
                      path, options.format);
}

/// The three files at once, each on a thread of its own (`intensity`, `rgb`, `labels` write
/// them to the temporary path given; `rgb` and `labels` may be empty: no such file), or with
/// `companions_in_turn` the display copy then the truth mosaic on one thread beside the mosaic
/// (two threads: the memory of two writers at a time); every thread is joined before the
/// outputs are committed or discarded.
using Job = std::function<void(const std::string& temp)>;
void write_files(const std::string& path, const MosaicWriteOptions& options, const Job& intensity,
                 const Job& rgb, const Job& labels, bool companions_in_turn) {
  gdal::ensure_registered();
  // Claim every output first (existing files without overwrite fail before anything is written).
  AtomicOutput main_out(path, options.overwrite);
  std::optional<AtomicOutput> rgb_out;
  std::optional<AtomicOutput> labels_out;
  if (rgb) rgb_out.emplace(options.rgb_path, options.overwrite);
  if (labels) labels_out.emplace(options.labels_path, options.overwrite);
  std::future<void> rgb_job, labels_job;
  if (companions_in_turn && (rgb_out || labels_out)) {
    rgb_job = std::async(std::launch::async, [&] {
      if (rgb_out) rgb(rgb_out->temp_path().string());
      if (labels_out) labels(labels_out->temp_path().string());
    });
  } else if (rgb_out) {
    rgb_job = std::async(std::launch::async, [&] { rgb(rgb_out->temp_path().string()); });
  }
  if (labels_out && !companions_in_turn) {
    labels_job = std::async(std::launch::async, [&] { labels(labels_out->temp_path().string()); });
  }
  std::exception_ptr error;
  try {
    intensity(main_out.temp_path().string());
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

MosaicRasterFormat parse_mosaic_raster_format(const std::string& text, const std::string& what) {
  if (text == "COG" || text == "cog") return MosaicRasterFormat::cog;
  if (text == "GTiff" || text == "gtiff") return MosaicRasterFormat::gtiff;
  throw InputError(what + " = '" + text + "'. Violated constraint: COG or GTiff");
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
  // The bands are views of the image (and of the count as float, and of the colours): MEM
  // datasets, overviews built in memory and copied before the full resolution image.
  const Job intensity = [&](const std::string& temp) {
    std::vector<float> count;
    std::vector<const void*> views = {image.intensity.data()};
    if (options.count_band) {
      count.assign(image.count.begin(), image.count.end());
      views.push_back(count.data());
    }
    gdal::DatasetPtr mem = raster::wrap_mem(g.cols, g.rows, GDT_Float32, views, kWho, path);
    write_intensity(path, temp, frame, *mem, g, options, Overviews::on_source);
  };
  Job rgb, labels;
  if (!options.rgb_path.empty()) {
    rgb = [&](const std::string& temp) {
      DisplayRange range{options.lo_db, options.hi_db, options.linear_full_scale};
      if (!(options.linear_full_scale > 0.0) && !options.fixed_db) {
        range = robust_db_range(image.intensity, options.lo_percentile, options.hi_percentile);
      }
      const std::size_t n = g.size();
      std::vector<std::uint8_t> rgba(4 * n);
      display_colours(image.intensity, range, options.colormap, rgba.data());
      std::vector<const void*> views;
      for (std::size_t b = 0; b < 4; ++b) views.push_back(rgba.data() + b * n);
      gdal::DatasetPtr mem =
          raster::wrap_mem(g.cols, g.rows, GDT_Byte, views, kWho, options.rgb_path);
      write_rgb(options.rgb_path, temp, frame, *mem, g, options, range, Overviews::on_source);
    };
  }
  if (!options.labels_path.empty() && !image.labels.empty()) {
    labels = [&](const std::string& temp) {
      gdal::DatasetPtr mem = raster::wrap_mem(g.cols, g.rows, GDT_Int32, {image.labels.data()},
                                              kWho, options.labels_path);
      write_labels(options.labels_path, temp, frame, *mem, g, options, Overviews::on_source);
    };
  }
  write_files(path, options, intensity, rgb, labels, false);
}

void write_mosaic(const std::string& path, const GeoFrame& frame, MosaicGrid& grid,
                  const MosaicWriteOptions& options,
                  const std::function<void(std::span<std::int32_t>)>& label_map) {
  options.validate();
  grid.finalize();
  const GridGeometry& g = grid.geometry();
  gdal::ensure_registered();
  // Every file is read from the grid's tiles window by window
  // (formats/private/sonarsynth/formats/products/mosaic_blocks.hpp); the GeoTIFFs' overview levels
  // are computed in a temporary file (raster::copy_with_overviews).
  const Job intensity = [&](const std::string& temp) {
    const bool count_band = options.count_band;
    gdal::DatasetPtr src = raster::grid_dataset(
        grid, count_band ? 2 : 1, GDT_Float32,
        [count_band](const MosaicImage& w, unsigned char* out, std::size_t band_bytes) {
          std::memcpy(out, w.intensity.data(), band_bytes);
          if (count_band) {
            auto* count = reinterpret_cast<float*>(out + band_bytes);
            std::copy(w.count.begin(), w.count.end(), count);
          }
        });
    write_intensity(path, temp, frame, *src, g, options, Overviews::on_file);
  };
  Job rgb, labels;
  if (!options.rgb_path.empty()) {
    rgb = [&](const std::string& temp) {
      DisplayRange range{options.lo_db, options.hi_db, options.linear_full_scale};
      if (!(options.linear_full_scale > 0.0) && !options.fixed_db) {
        // The percentiles of robust_db_range over the image, its values fed in row-major order
        // a row of tiles at a time: the same subsample, the same range.
        DbRangeSampler sampler(g.size());
        MosaicImage rows;
        for (std::size_t r = 0; r < g.rows; r += grid.tile_px()) {
          grid.read_window(0, r, g.cols, std::min(grid.tile_px(), g.rows - r), rows);
          sampler.add(rows.intensity);
        }
        range = sampler.range(options.lo_percentile, options.hi_percentile);
      }
      const Colormap map = options.colormap;
      gdal::DatasetPtr src = raster::grid_dataset(
          grid, 4, GDT_Byte,
          [range, map](const MosaicImage& w, unsigned char* out, std::size_t /*band_bytes*/) {
            display_colours(w.intensity, range, map, out);
          });
      write_rgb(options.rgb_path, temp, frame, *src, g, options, range, Overviews::on_file);
    };
  }
  if (!options.labels_path.empty() && grid.has_labels()) {
    labels = [&](const std::string& temp) {
      gdal::DatasetPtr src = raster::grid_dataset(
          grid, 1, GDT_Int32, [&](const MosaicImage& w, unsigned char* out, std::size_t) {
            auto* ids = reinterpret_cast<std::int32_t*>(out);
            std::copy(w.labels.begin(), w.labels.end(), ids);
            if (label_map) label_map(std::span<std::int32_t>(ids, w.labels.size()));
          });
      write_labels(options.labels_path, temp, frame, *src, g, options, Overviews::on_file);
    };
  }
  write_files(path, options, intensity, rgb, labels, true);
}

}  // namespace sonarsynth
