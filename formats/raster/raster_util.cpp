// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/raster/raster_util.hpp"

#include <cpl_string.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <vector>

#include "sonarsynth/error.hpp"

namespace sonarsynth::raster {
namespace {

[[noreturn]] void fail(const char* who, const std::string& path, const std::string& msg) {
  const std::string gdal_msg = gdal::last_error_message();
  throw FormatError(std::string(who) + ": " + path + ": " + msg +
                    (gdal_msg.empty() ? "" : ": " + gdal_msg));
}

void check_size(std::size_t cols, std::size_t rows, const char* who, const std::string& path) {
  if (cols == 0 || rows == 0 || cols > static_cast<std::size_t>(INT_MAX) ||
      rows > static_cast<std::size_t>(INT_MAX)) {
    fail(who, path,
         "image of " + std::to_string(cols) + " x " + std::to_string(rows) +
             " pixels cannot be written");
  }
}

/// A read-only dataset whose rows come from a RowSource when GDAL reads them: plain reads bypass
/// GDAL's block cache (which would otherwise keep up to GDAL_CACHEMAX of the image) and only the
/// current row of all bands is held. Rows are meant to be read top to bottom, as CreateCopy
/// does; reading an earlier row rewinds the source. An exception thrown by the source becomes a
/// GDAL error, so that the read (and the copy) fails with its message.
class StreamingDataset final : public GDALDataset {
 public:
  StreamingDataset(int cols, int rows, int bands, GDALDataType type, RowSource& source);

  /// Copies rows [y0, y0 + ny) x columns [x0, x0 + nx) of `band_count` bands (1-based numbers
  /// in `band_map`) to `out` with the given spacing (bytes) and buffer type.
  CPLErr read(int x0, int y0, int nx, int ny, int band_count, const int* band_map, void* out,
              GDALDataType out_type, GSpacing pixel_space, GSpacing line_space,
              GSpacing band_space);

 protected:
  CPLErr IRasterIO(GDALRWFlag flag, int x0, int y0, int nx, int ny, void* data, int buf_nx,
                   int buf_ny, GDALDataType buf_type, int band_count, BandMap band_map,
                   GSpacing pixel_space, GSpacing line_space, GSpacing band_space,
                   GDALRasterIOExtraArg* extra) override;

 private:
  /// Row y of all bands, or nullptr after a GDAL error.
  const unsigned char* row(int y);

  RowSource& source_;
  GDALDataType type_;
  std::size_t band_bytes_;  ///< one band of one row
  std::vector<unsigned char> row_;
  int have_ = -1;  ///< row held in row_
  int next_ = 0;   ///< row the source produces next
};

class StreamingBand final : public DirectReadBand<StreamingDataset> {
 public:
  StreamingBand(StreamingDataset* ds, int band, GDALDataType type, int cols, int rows) {
    poDS = ds;
    nBand = band;
    eDataType = type;
    nRasterXSize = cols;
    nRasterYSize = rows;
    nBlockXSize = cols;  // a block is one row
    nBlockYSize = 1;
    eAccess = GA_ReadOnly;
  }

 protected:
  CPLErr IReadBlock(int /*x_block*/, int y_block, void* data) override {
    return dataset().read(0, y_block, nRasterXSize, 1, 1, &nBand, data, eDataType,
                          GDALGetDataTypeSizeBytes(eDataType), 0, 0);
  }
};

StreamingDataset::StreamingDataset(int cols, int rows, int bands, GDALDataType type,
                                   RowSource& source)
    : source_(source),
      type_(type),
      band_bytes_(static_cast<std::size_t>(cols) *
                  static_cast<std::size_t>(GDALGetDataTypeSizeBytes(type))) {
  nRasterXSize = cols;
  nRasterYSize = rows;
  eAccess = GA_ReadOnly;
  for (int b = 1; b <= bands; ++b) SetBand(b, new StreamingBand(this, b, type, cols, rows));
  row_.resize(band_bytes_ * static_cast<std::size_t>(bands));
}

const unsigned char* StreamingDataset::row(int y) {
  if (y == have_) return row_.data();
  try {
    if (y < next_) {
      source_.rewind();
      next_ = 0;
    }
    have_ = -1;
    for (; next_ <= y; ++next_) source_.next(row_.data());
    have_ = y;
    return row_.data();
  } catch (const std::exception& e) {
    next_ = nRasterYSize;  // start again (rewind) at the next request
    CPLError(CE_Failure, CPLE_AppDefined, "%s", e.what());
    return nullptr;
  }
}

CPLErr StreamingDataset::read(int x0, int y0, int nx, int ny, int band_count, const int* band_map,
                              void* out, GDALDataType out_type, GSpacing pixel_space,
                              GSpacing line_space, GSpacing band_space) {
  const std::size_t pixel_bytes = band_bytes_ / static_cast<std::size_t>(nRasterXSize);
  for (int j = 0; j < ny; ++j) {
    const unsigned char* r = row(y0 + j);
    if (!r) return CE_Failure;
    for (int k = 0; k < band_count; ++k) {
      const unsigned char* src = r + static_cast<std::size_t>(band_map[k] - 1) * band_bytes_ +
                                 static_cast<std::size_t>(x0) * pixel_bytes;
      GDALCopyWords(src, type_, static_cast<int>(pixel_bytes),
                    static_cast<unsigned char*>(out) + j * line_space + k * band_space, out_type,
                    static_cast<int>(pixel_space), nx);
    }
  }
  return CE_None;
}

CPLErr StreamingDataset::IRasterIO(GDALRWFlag flag, int x0, int y0, int nx, int ny, void* data,
                                   int buf_nx, int buf_ny, GDALDataType buf_type, int band_count,
                                   BandMap band_map, GSpacing pixel_space, GSpacing line_space,
                                   GSpacing band_space, GDALRasterIOExtraArg* extra) {
  if (plain_read(flag, x0, y0, nx, ny, buf_nx, buf_ny, extra)) {
    return read(x0, y0, nx, ny, band_count, band_map, data, buf_type, pixel_space, line_space,
                band_space);
  }
  return GDALDataset::IRasterIO(flag, x0, y0, nx, ny, data, buf_nx, buf_ny, buf_type, band_count,
                                band_map, pixel_space, line_space, band_space, extra);
}

}  // namespace

bool plain_read(GDALRWFlag flag, int x0, int y0, int nx, int ny, int buf_nx, int buf_ny,
                const GDALRasterIOExtraArg* extra) {
  const bool integer_window =
      !extra || !extra->bFloatingPointWindowValidity ||
      (extra->dfXOff == x0 && extra->dfYOff == y0 && extra->dfXSize == nx && extra->dfYSize == ny);
  return flag == GF_Read && buf_nx == nx && buf_ny == ny && integer_window;
}

gdal::DatasetPtr create_mem(std::size_t cols, std::size_t rows, int bands, GDALDataType type,
                            const char* who, const std::string& path) {
  gdal::ensure_registered();
  check_size(cols, rows, who, path);
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  if (!mem) fail(who, path, "GDAL has no MEM driver");
  GDALDataset* ds =
      mem->Create("", static_cast<int>(cols), static_cast<int>(rows), bands, type, nullptr);
  if (!ds) fail(who, path, "cannot allocate an in-memory image");
  return gdal::DatasetPtr(ds);
}

gdal::DatasetPtr wrap_mem(std::size_t cols, std::size_t rows, GDALDataType type,
                          const std::vector<const void*>& bands, const char* who,
                          const std::string& path) {
  gdal::DatasetPtr ds = create_mem(cols, rows, 0, type, who, path);
  for (const void* data : bands) {
    char pointer[64] = {};
    CPLPrintPointer(pointer, const_cast<void*>(data), sizeof pointer - 1);
    CPLStringList options;
    options.SetNameValue("DATAPOINTER", pointer);
    if (ds->AddBand(type, options.List()) != CE_None) {
      fail(who, path, "cannot wrap an in-memory band");
    }
  }
  return ds;
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
  const auto cached_writes = gdal::lock_cached_writes();
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

namespace {

/// Sets what `labels` says on `ds` (`band_values`: also the colour table, units and nodata,
/// which a streamed CreateCopy source cannot give).
void describe(GDALDataset& ds, const RasterLabels& labels, int bands, bool band_values) {
  for (const auto& [k, v] : labels.metadata) ds.SetMetadataItem(k.c_str(), v.c_str());
  for (std::size_t b = 0; b < labels.descriptions.size(); ++b) {
    ds.GetRasterBand(static_cast<int>(b) + 1)->SetDescription(labels.descriptions[b].c_str());
  }
  for (std::size_t b = 0; b < labels.band_metadata.size(); ++b) {
    for (const auto& [k, v] : labels.band_metadata[b]) {
      ds.GetRasterBand(static_cast<int>(b) + 1)->SetMetadataItem(k.c_str(), v.c_str());
    }
  }
  if (!band_values) return;
  if (!labels.color_table.empty()) {
    GDALColorTable table;
    for (std::size_t i = 0; i < labels.color_table.size(); ++i) {
      const auto& c = labels.color_table[i];
      const GDALColorEntry e{c[0], c[1], c[2], c[3]};
      table.SetColorEntry(static_cast<int>(i), &e);
    }
    ds.GetRasterBand(1)->SetColorTable(&table);
  }
  for (std::size_t b = 0; b < labels.units.size(); ++b) {
    ds.GetRasterBand(static_cast<int>(b) + 1)->SetUnitType(labels.units[b].c_str());
  }
  for (std::size_t b = 0; b < labels.scales.size(); ++b) {
    if (!std::isnan(labels.scales[b])) {
      ds.GetRasterBand(static_cast<int>(b) + 1)->SetScale(labels.scales[b]);
    }
  }
  for (std::size_t b = 0; b < labels.offsets.size(); ++b) {
    if (!std::isnan(labels.offsets[b])) {
      ds.GetRasterBand(static_cast<int>(b) + 1)->SetOffset(labels.offsets[b]);
    }
  }
  if (labels.has_nodata) {
    for (int b = 1; b <= bands; ++b) ds.GetRasterBand(b)->SetNoDataValue(labels.nodata);
  }
}

}  // namespace

void describe_dataset(GDALDataset& ds, const RasterLabels& labels, int bands) {
  describe(ds, labels, bands, true);
}

void stream_to_file(RowSource& source, std::size_t cols, std::size_t rows, int bands,
                    GDALDataType type, const char* driver_name, const std::string& temp_path,
                    const std::vector<std::pair<std::string, std::string>>& creation_options,
                    const RasterLabels& labels, const char* who, const std::string& final_path) {
  gdal::ensure_registered();
  check_size(cols, rows, who, final_path);
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name);
  if (!driver) fail(who, final_path, std::string("GDAL has no ") + driver_name + " driver");
  // The streamed source of a CreateCopy has no unit or nodata to give (its bands are read-only
  // views of the rows); the drivers written that way (PNG) could not store them anyway.
  if (!CPLFetchBool(driver->GetMetadata(), GDAL_DCAP_CREATE, false)) {
    gdal::DatasetPtr src(
        new StreamingDataset(static_cast<int>(cols), static_cast<int>(rows), bands, type, source));
    describe(*src, labels, bands, false);
    copy_to_file(*src, driver_name, temp_path, creation_options, who, final_path);
    return;
  }
  std::vector<StreamTarget> targets(1);
  StreamTarget& t = targets[0];
  t.source = &source;
  t.bands = bands;
  t.type = type;
  t.temp_path = temp_path;
  t.creation_options = creation_options;
  t.labels = labels;
  t.final_path = final_path;
  stream_to_files(targets, cols, rows, driver_name, who);
}

void stream_to_files(std::vector<StreamTarget>& targets, std::size_t cols, std::size_t rows,
                     const char* driver_name, const char* who) {
  gdal::ensure_registered();
  for (const StreamTarget& t : targets) check_size(cols, rows, who, t.final_path);
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name);
  const std::string& first = targets.empty() ? std::string() : targets[0].final_path;
  if (!driver) fail(who, first, std::string("GDAL has no ") + driver_name + " driver");
  if (!CPLFetchBool(driver->GetMetadata(), GDAL_DCAP_CREATE, false)) {
    fail(who, first, std::string("the ") + driver_name + " driver cannot create files");
  }
  struct Open {
    gdal::DatasetPtr ds;
    std::size_t block_cols = 1, block_rows = 1;
    std::size_t type_bytes = 0;
    std::size_t band_bytes = 0;  ///< of a row
    /// Whole blocks handed to the driver (WriteBlock), which encodes and writes each at once:
    /// bands stored apart (one band, or INTERLEAVE=BAND), so a block is one band's. Otherwise
    /// rows go through RasterIO and the block cache.
    bool direct = false;
    std::vector<unsigned char> rows;   ///< direct: a row of blocks; else one row
    std::vector<unsigned char> block;  ///< direct: one block
    std::vector<unsigned char> pad;    ///< direct: one block of nodata (0 without)
  };
  std::vector<Open> open(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const StreamTarget& t = targets[i];
    Open& o = open[i];
    CPLStringList co;
    for (const auto& [k, v] : t.creation_options) co.SetNameValue(k.c_str(), v.c_str());
    CPLErrorReset();
    o.ds.reset(driver->Create(t.temp_path.c_str(), static_cast<int>(cols), static_cast<int>(rows),
                              t.bands, t.type, co.List()));
    if (!o.ds) fail(who, t.final_path, std::string("cannot create ") + driver_name);
    describe(*o.ds, t.labels, t.bands, true);
    int block_cols = 0, block_rows = 0;
    o.ds->GetRasterBand(1)->GetBlockSize(&block_cols, &block_rows);
    o.block_cols = static_cast<std::size_t>(std::max(1, block_cols));
    o.block_rows = static_cast<std::size_t>(std::max(1, block_rows));
    o.type_bytes = static_cast<std::size_t>(GDALGetDataTypeSizeBytes(t.type));
    o.band_bytes = o.type_bytes * cols;
    const char* interleave = o.ds->GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
    o.direct = std::string(driver_name) == "GTiff" &&
               (t.bands == 1 || (interleave && std::string(interleave) == "BAND"));
    const auto n_bands = static_cast<std::size_t>(t.bands);
    o.rows.resize(o.band_bytes * n_bands * (o.direct ? o.block_rows : 1));
    if (o.direct) {
      const std::size_t pixels = o.block_cols * o.block_rows;
      o.block.resize(pixels * o.type_bytes);
      o.pad.resize(pixels * o.type_bytes);
      // What GDAL puts in the part of an edge block outside the image: the nodata value.
      if (t.labels.has_nodata) {
        GDALCopyWords64(&t.labels.nodata, GDT_Float64, 0, o.pad.data(), t.type,
                        static_cast<int>(o.type_bytes), static_cast<GPtrDiff_t>(pixels));
      }
    }
  }
  // Blocks of the row of blocks that ends at image row `last` (a partial one at the bottom).
  auto write_blocks = [&](const StreamTarget& t, Open& o, std::size_t last) {
    const std::size_t by = last / o.block_rows;
    const std::size_t r0 = by * o.block_rows;
    const std::size_t n_rows = last + 1 - r0;
    const std::size_t n_bands = static_cast<std::size_t>(t.bands);
    for (int b = 1; b <= t.bands; ++b) {
      const auto band = static_cast<std::size_t>(b - 1);
      for (std::size_t bx = 0; bx * o.block_cols < cols; ++bx) {
        const std::size_t c0 = bx * o.block_cols;
        const std::size_t n_cols = std::min(o.block_cols, cols - c0);
        if (n_cols < o.block_cols || n_rows < o.block_rows) o.block = o.pad;
        for (std::size_t r = 0; r < n_rows; ++r) {
          const unsigned char* src =
              o.rows.data() + (r * n_bands + band) * o.band_bytes + c0 * o.type_bytes;
          std::memcpy(o.block.data() + r * o.block_cols * o.type_bytes, src, n_cols * o.type_bytes);
        }
        if (o.ds->GetRasterBand(b)->WriteBlock(static_cast<int>(bx), static_cast<int>(by),
                                               o.block.data()) != CE_None) {
          fail(who, t.final_path,
               "cannot write the blocks of rows " + std::to_string(r0) + " to " +
                   std::to_string(last));
        }
      }
    }
  };
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < targets.size(); ++i) {
      const StreamTarget& t = targets[i];
      Open& o = open[i];
      if (o.direct) {
        const std::size_t in_block = r % o.block_rows;
        t.source->next(o.rows.data() + in_block * o.band_bytes * static_cast<std::size_t>(t.bands));
        if (in_block + 1 == o.block_rows || r + 1 == rows) write_blocks(t, o, r);
        continue;
      }
      t.source->next(o.rows.data());
      const auto cached_writes = gdal::lock_cached_writes();
      const auto type_bytes = static_cast<GSpacing>(o.type_bytes);
      const auto band_bytes = static_cast<GSpacing>(o.band_bytes);
      if (o.ds->RasterIO(GF_Write, 0, static_cast<int>(r), static_cast<int>(cols), 1, o.rows.data(),
                         static_cast<int>(cols), 1, t.type, t.bands, nullptr, type_bytes,
                         band_bytes, band_bytes, nullptr) != CE_None) {
        fail(who, t.final_path, "cannot write row " + std::to_string(r));
      }
      // A completed row of blocks goes to the file and leaves the cache.
      if ((r + 1) % o.block_rows == 0 || r + 1 == rows) o.ds->FlushCache(false);
    }
  }
  for (std::size_t i = 0; i < targets.size(); ++i) {
    gdal::close_checked(std::move(open[i].ds), targets[i].final_path, who);
    std::error_code ec;  // as in copy_to_file()
    std::filesystem::remove(targets[i].temp_path + ".aux.xml", ec);
  }
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace sonarsynth::raster
