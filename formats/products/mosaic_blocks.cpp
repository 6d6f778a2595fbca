// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/products/mosaic_blocks.hpp"

#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/io/atomic_file.hpp"
#include "sonarsynth/formats/raster/raster_util.hpp"

namespace sonarsynth::raster {
namespace {

class GridDataset final : public GDALDataset {
 public:
  GridDataset(const MosaicGrid& grid, int bands, GDALDataType type, WindowBands fill);

  /// Copies columns [x0, x0 + nx) x rows [y0, y0 + ny) of `band_count` bands (1-based numbers in
  /// `band_map`) to `out` with the given spacing (bytes) and buffer type.
  CPLErr read(int x0, int y0, int nx, int ny, int band_count, const int* band_map, void* out,
              GDALDataType out_type, GSpacing pixel_space, GSpacing line_space,
              GSpacing band_space);

  CPLErr GetGeoTransform(double* gt) override {
    std::copy_n(gt_, 6, gt);
    return has_gt_ ? CE_None : CE_Failure;
  }
  CPLErr SetGeoTransform(double* gt) override {
    std::copy_n(gt, 6, gt_);
    has_gt_ = true;
    return CE_None;
  }
  const OGRSpatialReference* GetSpatialRef() const override { return srs_ ? &*srs_ : nullptr; }
  /// Per band (from band 1), the bands shown as its overviews (borrowed; empty: none).
  void set_overviews(std::vector<std::vector<GDALRasterBand*>> overviews);
  CPLErr SetSpatialRef(const OGRSpatialReference* srs) override {
    srs_.reset();
    if (srs) srs_ = *srs;
    return CE_None;
  }

 protected:
  CPLErr IRasterIO(GDALRWFlag flag, int x0, int y0, int nx, int ny, void* data, int buf_nx,
                   int buf_ny, GDALDataType buf_type, int band_count, BandMap band_map,
                   GSpacing pixel_space, GSpacing line_space, GSpacing band_space,
                   GDALRasterIOExtraArg* extra) override {
    if (plain_read(flag, x0, y0, nx, ny, buf_nx, buf_ny, extra)) {
      return read(x0, y0, nx, ny, band_count, band_map, data, buf_type, pixel_space, line_space,
                  band_space);
    }
    return GDALDataset::IRasterIO(flag, x0, y0, nx, ny, data, buf_nx, buf_ny, buf_type, band_count,
                                  band_map, pixel_space, line_space, band_space, extra);
  }

 private:
  /// The bands of a row of tiles (full width): band b at b x band_bytes.
  struct Rows {
    int tile_row = -1;  ///< -1: none
    std::size_t band_bytes = 0;
    std::vector<unsigned char> values;
  };
  /// Row of tiles `tile_row`, computed if it is not one of the two held (replacing the older);
  /// nullptr after a GDAL error.
  const Rows* rows_of(int tile_row);

  const MosaicGrid& grid_;
  int bands_;
  GDALDataType type_;
  std::size_t type_bytes_;
  WindowBands fill_;
  MosaicImage window_;                      ///< one tile of the finished image
  std::vector<unsigned char> tile_values_;  ///< its bands
  /// Two rows of tiles: a row of blocks twice the tiles' height is read without recomputing.
  std::array<Rows, 2> held_;
  std::size_t next_slot_ = 0;
  double gt_[6] = {0, 1, 0, 0, 0, 1};
  bool has_gt_ = false;
  std::optional<OGRSpatialReference> srs_;
};

class GridBand final : public DirectReadBand<GridDataset> {
 public:
  GridBand(GridDataset* ds, int band, GDALDataType type, int cols, int rows, int block) {
    poDS = ds;
    nBand = band;
    eDataType = type;
    nRasterXSize = cols;
    nRasterYSize = rows;
    nBlockXSize = std::min(block, cols);
    nBlockYSize = std::min(block, rows);
    eAccess = GA_ReadOnly;
  }

  double GetNoDataValue(int* success) override {
    if (success) *success = has_nodata_;
    return nodata_;
  }
  CPLErr SetNoDataValue(double v) override {
    nodata_ = v;
    has_nodata_ = true;
    return CE_None;
  }
  const char* GetUnitType() override { return unit_.c_str(); }
  CPLErr SetUnitType(const char* unit) override {
    unit_ = unit ? unit : "";
    return CE_None;
  }
  GDALColorInterp GetColorInterpretation() override {
    return interp_ == GCI_Undefined && table_ ? GCI_PaletteIndex : interp_;
  }
  CPLErr SetColorInterpretation(GDALColorInterp interp) override {
    interp_ = interp;
    return CE_None;
  }
  GDALColorTable* GetColorTable() override { return table_.get(); }
  int GetOverviewCount() override { return static_cast<int>(overviews_.size()); }
  GDALRasterBand* GetOverview(int i) override {
    return i >= 0 && i < GetOverviewCount() ? overviews_[static_cast<std::size_t>(i)] : nullptr;
  }
  /// Bands of another dataset shown as this band's overviews (borrowed; empty: none).
  void set_overviews(std::vector<GDALRasterBand*> overviews) { overviews_ = std::move(overviews); }
  CPLErr SetColorTable(GDALColorTable* table) override {
    table_.reset(table ? table->Clone() : nullptr);
    return CE_None;
  }

 protected:
  CPLErr IReadBlock(int x_block, int y_block, void* data) override {
    // Only resampled reads come here (plain ones bypass the blocks); the part of an edge block
    // outside the image is zero.
    const int x0 = x_block * nBlockXSize;
    const int y0 = y_block * nBlockYSize;
    const int nx = std::min(nBlockXSize, nRasterXSize - x0);
    const int ny = std::min(nBlockYSize, nRasterYSize - y0);
    const int type_bytes = GDALGetDataTypeSizeBytes(eDataType);
    std::memset(data, 0,
                static_cast<std::size_t>(nBlockXSize) * static_cast<std::size_t>(nBlockYSize) *
                    static_cast<std::size_t>(type_bytes));
    return dataset().read(x0, y0, nx, ny, 1, &nBand, data, eDataType, type_bytes,
                          static_cast<GSpacing>(nBlockXSize) * type_bytes, 0);
  }

 private:
  double nodata_ = 0.0;
  int has_nodata_ = FALSE;
  std::string unit_;
  GDALColorInterp interp_ = GCI_Undefined;
  std::unique_ptr<GDALColorTable> table_;
  std::vector<GDALRasterBand*> overviews_;
};

void GridDataset::set_overviews(std::vector<std::vector<GDALRasterBand*>> overviews) {
  for (int b = 1; b <= nBands; ++b) {
    auto* band = static_cast<GridBand*>(GetRasterBand(b));
    const auto i = static_cast<std::size_t>(b - 1);
    band->set_overviews(i < overviews.size() ? std::move(overviews[i])
                                             : std::vector<GDALRasterBand*>());
  }
}

GridDataset::GridDataset(const MosaicGrid& grid, int bands, GDALDataType type, WindowBands fill)
    : grid_(grid),
      bands_(bands),
      type_(type),
      type_bytes_(static_cast<std::size_t>(GDALGetDataTypeSizeBytes(type))),
      fill_(std::move(fill)) {
  nRasterXSize = static_cast<int>(grid.geometry().cols);
  nRasterYSize = static_cast<int>(grid.geometry().rows);
  eAccess = GA_ReadOnly;
  const int block = static_cast<int>(grid.tile_px());
  for (int b = 1; b <= bands; ++b) {
    SetBand(b, new GridBand(this, b, type, nRasterXSize, nRasterYSize, block));
  }
}

const GridDataset::Rows* GridDataset::rows_of(int tile_row) {
  for (Rows& r : held_) {
    if (r.tile_row == tile_row) return &r;
  }
  Rows& r = held_[next_slot_];
  next_slot_ = (next_slot_ + 1) % held_.size();
  r.tile_row = -1;
  try {
    // Tile by tile: the window read and its bands are a tile's, copied into the row.
    const std::size_t tile = grid_.tile_px();
    const auto cols = static_cast<std::size_t>(nRasterXSize);
    const std::size_t row0 = static_cast<std::size_t>(tile_row) * tile;
    const std::size_t rows = std::min(tile, static_cast<std::size_t>(nRasterYSize) - row0);
    r.band_bytes = cols * rows * type_bytes_;
    r.values.resize(r.band_bytes * static_cast<std::size_t>(bands_));
    for (std::size_t col0 = 0; col0 < cols; col0 += tile) {
      const std::size_t n = std::min(tile, cols - col0);
      grid_.read_window(col0, row0, n, rows, window_);
      const std::size_t tile_band_bytes = n * rows * type_bytes_;
      tile_values_.assign(tile_band_bytes * static_cast<std::size_t>(bands_), 0);
      fill_(window_, tile_values_.data(), tile_band_bytes);
      for (std::size_t b = 0; b < static_cast<std::size_t>(bands_); ++b) {
        for (std::size_t j = 0; j < rows; ++j) {
          std::memcpy(r.values.data() + b * r.band_bytes + (j * cols + col0) * type_bytes_,
                      tile_values_.data() + b * tile_band_bytes + j * n * type_bytes_,
                      n * type_bytes_);
        }
      }
    }
    r.tile_row = tile_row;
    return &r;
  } catch (const std::exception& e) {
    CPLError(CE_Failure, CPLE_AppDefined, "%s", e.what());
    return nullptr;
  }
}

CPLErr GridDataset::read(int x0, int y0, int nx, int ny, int band_count, const int* band_map,
                         void* out, GDALDataType out_type, GSpacing pixel_space,
                         GSpacing line_space, GSpacing band_space) {
  const int tile = static_cast<int>(grid_.tile_px());
  const auto cols = static_cast<std::size_t>(nRasterXSize);
  for (int j = 0; j < ny;) {
    const int y = y0 + j;
    const Rows* r = rows_of(y / tile);
    if (!r) return CE_Failure;
    const int end = std::min(y0 + ny, (y / tile + 1) * tile);
    for (; y0 + j < end; ++j) {
      const std::size_t pixel =
          static_cast<std::size_t>((y0 + j) % tile) * cols + static_cast<std::size_t>(x0);
      for (int k = 0; k < band_count; ++k) {
        const unsigned char* band =
            r->values.data() + static_cast<std::size_t>(band_map[k] - 1) * r->band_bytes;
        GDALCopyWords(band + pixel * type_bytes_, type_, static_cast<int>(type_bytes_),
                      static_cast<unsigned char*>(out) + j * line_space + k * band_space, out_type,
                      static_cast<int>(pixel_space), nx);
      }
    }
  }
  return CE_None;
}

/// The blocks of `ds` and of its overviews read and written so far leave GDAL's block cache
/// (clean ones are dropped, dirty ones written), as they would when the cache is full. Only
/// between GDAL calls on `ds`, never from a progress callback: GDAL calls those with a block of
/// the band it reads locked (GDALRasterBand::IRasterIO reading whole rows of blocks), and a
/// locked block that is flushed leaves the band but stays in the cache, where it outlives the
/// band and the eviction that reaches it reads the freed band (a crash).
void flush_blocks(GDALDataset& ds) {
  for (int b = 1; b <= ds.GetRasterCount(); ++b) {
    GDALRasterBand* band = ds.GetRasterBand(b);
    band->FlushCache(false);
    for (int o = 0; o < band->GetOverviewCount(); ++o) band->GetOverview(o)->FlushCache(false);
  }
}

/// Removes a temporary file when it goes out of scope (listed for the signal handler meanwhile).
class TemporaryFile {
 public:
  explicit TemporaryFile(std::string path) : path_(std::move(path)) { register_temporary(path_); }
  ~TemporaryFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
    unregister_temporary(path_);
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace

gdal::DatasetPtr grid_dataset(const MosaicGrid& grid, int bands, GDALDataType type,
                              WindowBands fill) {
  return gdal::DatasetPtr(new GridDataset(grid, bands, type, std::move(fill)));
}

std::vector<int> overview_factors(std::size_t cols, std::size_t rows) {
  std::vector<int> f;
  const std::size_t largest = std::max(cols, rows);
  for (std::size_t factor = 2; largest / (factor / 2) > 256; factor *= 2) {
    f.push_back(static_cast<int>(factor));
  }
  return f;
}

void copy_with_overviews(GDALDataset& src, const char* resampling,
                         const std::vector<std::pair<std::string, std::string>>& creation_options,
                         const std::string& temp_path, const char* who,
                         const std::string& final_path) {
  const auto cached_writes = gdal::lock_cached_writes();
  auto fail = [&](const std::string& what) {
    const std::string msg = gdal::last_error_message();
    throw FormatError(std::string(who) + ": " + final_path + ": " + what +
                      (msg.empty() ? "" : ": " + msg));
  };
  auto* grid_src = dynamic_cast<GridDataset*>(&src);
  if (!grid_src) throw std::logic_error("copy_with_overviews: the source is not a grid_dataset");
  std::vector<int> factors = overview_factors(static_cast<std::size_t>(src.GetRasterXSize()),
                                              static_cast<std::size_t>(src.GetRasterYSize()));
  if (factors.empty()) {
    copy_to_file(src, "GTiff", temp_path, creation_options, who, final_path);
    return;
  }
  // 1. The overview levels in a temporary uncompressed GeoTIFF next to the output.
  TemporaryFile levels(temp_path + ".levels.tif");
  const int bands = src.GetRasterCount();
  GDALRasterBand* first = src.GetRasterBand(1);
  CPLStringList co;
  co.SetNameValue("TILED", "YES");
  co.SetNameValue("INTERLEAVE", "BAND");
  co.SetNameValue("BIGTIFF", "IF_SAFER");
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!gtiff) fail("GDAL has no GTiff driver");
  CPLErrorReset();
  gdal::DatasetPtr ds(gtiff->Create(levels.path().c_str(), src.GetRasterXSize(),
                                    src.GetRasterYSize(), bands, first->GetRasterDataType(),
                                    co.List()));
  if (!ds) fail("cannot create " + levels.path());
  int has_nodata = 0;
  const double nodata = first->GetNoDataValue(&has_nodata);
  if (has_nodata) ds->GetRasterBand(1)->SetNoDataValue(nodata);
  std::vector<int> band_list;
  for (int b = 1; b <= bands; ++b) band_list.push_back(b);
  if (ds->BuildOverviews("NONE", static_cast<int>(factors.size()), factors.data(), bands,
                         band_list.data(), nullptr, nullptr) != CE_None) {
    fail("cannot create overviews");
  }
  // 2. The full resolution copied in once, a row of blocks at a time: the regeneration below
  // reads it once per band and level (16 times for the display copy's four bands), and `src`
  // computes its pixels afresh at every read (the display colours, or spilled tiles read back).
  // Band by band: colour interpretations (an alpha band is the others' mask) as in `src`.
  for (int b = 1; b <= bands; ++b) {
    ds->GetRasterBand(b)->SetColorInterpretation(src.GetRasterBand(b)->GetColorInterpretation());
  }
  {
    int block_cols = 0, block_rows = 0;
    ds->GetRasterBand(1)->GetBlockSize(&block_cols, &block_rows);
    const int cols = src.GetRasterXSize(), rows = src.GetRasterYSize();
    const GDALDataType type = first->GetRasterDataType();
    const auto type_bytes = static_cast<std::size_t>(GDALGetDataTypeSizeBytes(type));
    std::vector<unsigned char> buffer(static_cast<std::size_t>(cols) *
                                      static_cast<std::size_t>(block_rows) * type_bytes *
                                      static_cast<std::size_t>(bands));
    for (int y = 0; y < rows; y += block_rows) {
      const int n = std::min(block_rows, rows - y);
      if (src.RasterIO(GF_Read, 0, y, cols, n, buffer.data(), cols, n, type, bands, nullptr, 0, 0,
                       0, nullptr) != CE_None ||
          ds->RasterIO(GF_Write, 0, y, cols, n, buffer.data(), cols, n, type, bands, nullptr, 0, 0,
                       0, nullptr) != CE_None) {
        fail("cannot copy rows " + std::to_string(y) + " to the overview levels' file");
      }
      flush_blocks(*ds);
    }
  }
  // 3. Computed from that copy as MEMDataset::IBuildOverviews computes them (the same GDAL
  // routine on the same pixels: the overviews of write_mosaic() of the whole image): averaging
  // resamplings one level at a time from the full resolution, band by band; the others all
  // levels at once.
  const bool per_level = STARTS_WITH_CI(resampling, "AVER");
  const int n_levels = static_cast<int>(factors.size());
  for (int level = 0; level < (per_level ? n_levels : 1); ++level) {
    for (int b = 1; b <= bands; ++b) {
      std::vector<GDALRasterBandH> targets;
      GDALRasterBand* band = ds->GetRasterBand(b);
      for (int o = per_level ? level : 0; o < (per_level ? level + 1 : n_levels); ++o) {
        targets.push_back(GDALRasterBand::ToHandle(band->GetOverview(o)));
      }
      if (GDALRegenerateOverviews(GDALRasterBand::ToHandle(band), static_cast<int>(targets.size()),
                                  targets.data(), resampling, nullptr, nullptr) != CE_None) {
        fail("cannot compute overviews");
      }
      flush_blocks(*ds);
    }
  }
  // 4. The output: the full resolution image from `src`, its overviews copied from the levels
  // before it.
  std::vector<std::vector<GDALRasterBand*>> overviews(static_cast<std::size_t>(bands));
  for (int b = 1; b <= bands; ++b) {
    for (int o = 0; o < n_levels; ++o) {
      overviews[static_cast<std::size_t>(b - 1)].push_back(ds->GetRasterBand(b)->GetOverview(o));
    }
  }
  grid_src->set_overviews(std::move(overviews));
  CPLStringList out_co;
  for (const auto& [k, v] : creation_options) out_co.SetNameValue(k.c_str(), v.c_str());
  out_co.SetNameValue("COPY_SRC_OVERVIEWS", "YES");
  CPLErrorReset();
  GDALDataset* out =
      gtiff->CreateCopy(temp_path.c_str(), &src, FALSE, out_co.List(), nullptr, nullptr);
  grid_src->set_overviews({});
  if (!out) fail("cannot write GTiff");
  gdal::close_checked(gdal::DatasetPtr(out), final_path, who);
  std::error_code ec;
  std::filesystem::remove(temp_path + ".aux.xml", ec);
}

void copy_plain_with_overviews(
    GDALDataset& src, const char* resampling,
    const std::vector<std::pair<std::string, std::string>>& creation_options,
    const std::string& temp_path, const char* who, const std::string& final_path) {
  const auto cached_writes = gdal::lock_cached_writes();
  copy_to_file(src, "GTiff", temp_path, creation_options, who, final_path);
  std::vector<int> factors = overview_factors(static_cast<std::size_t>(src.GetRasterXSize()),
                                              static_cast<std::size_t>(src.GetRasterYSize()));
  if (factors.empty()) return;
  CPLErrorReset();
  gdal::DatasetPtr ds(GDALDataset::Open(temp_path.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE));
  if (!ds) {
    throw FormatError(std::string(who) + ": " + final_path +
                      ": cannot reopen to add overviews: " + gdal::last_error_message());
  }
  std::vector<int> bands;
  for (int b = 1; b <= ds->GetRasterCount(); ++b) bands.push_back(b);
  if (ds->BuildOverviews(resampling, static_cast<int>(factors.size()), factors.data(),
                         static_cast<int>(bands.size()), bands.data(), nullptr,
                         nullptr) != CE_None) {
    throw FormatError(std::string(who) + ": " + final_path +
                      ": cannot build overviews: " + gdal::last_error_message());
  }
  gdal::close_checked(std::move(ds), final_path, who);
}

namespace {

/// Internal overviews of every band of `ds` (GTiff, opened for update) at `factors`, band b
/// computed with `resampling[b - 1]` (the last entry for further bands; NEAREST if empty).
template <typename Fail>
void add_overviews(GDALDataset& ds, std::vector<int>& factors,
                   const std::vector<std::string>& resampling, const Fail& fail) {
  const int bands = ds.GetRasterCount();
  std::vector<int> band_list;
  for (int b = 1; b <= bands; ++b) band_list.push_back(b);
  // The levels' IFDs and blocks, then their pixels band by band with the band's resampling
  // (the GTiff driver builds internal overviews for all bands at once only).
  if (ds.BuildOverviews("NONE", static_cast<int>(factors.size()), factors.data(), bands,
                        band_list.data(), nullptr, nullptr) != CE_None) {
    fail("cannot create overviews");
  }
  for (int b = 1; b <= bands; ++b) {
    GDALRasterBand* band = ds.GetRasterBand(b);
    std::vector<GDALRasterBandH> targets;
    for (int o = 0; o < band->GetOverviewCount(); ++o) {
      targets.push_back(GDALRasterBand::ToHandle(band->GetOverview(o)));
    }
    const std::string& method =
        resampling.empty()
            ? std::string("NEAREST")
            : resampling[std::min(resampling.size(), static_cast<std::size_t>(b)) - 1];
    if (GDALRegenerateOverviews(GDALRasterBand::ToHandle(band), static_cast<int>(targets.size()),
                                targets.data(), method.c_str(), nullptr, nullptr) != CE_None) {
      fail("cannot compute overviews");
    }
    flush_blocks(ds);
  }
}

/// Sets `gcps` (if it has points) on `ds`.
template <typename Fail>
void set_gcps(GDALDataset& ds, const GroundControl& gcps, const Fail& fail) {
  if (gcps.points.empty()) return;
  std::vector<GDAL_GCP> list(gcps.points.size());
  std::vector<std::string> ids(gcps.points.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const GroundControl::Point& p = gcps.points[i];
    ids[i] = std::to_string(i + 1);
    list[i].pszId = ids[i].data();
    list[i].pszInfo = const_cast<char*>("");
    list[i].dfGCPPixel = p.pixel;
    list[i].dfGCPLine = p.line;
    list[i].dfGCPX = p.easting_m;
    list[i].dfGCPY = p.northing_m;
    list[i].dfGCPZ = 0.0;
  }
  OGRSpatialReference srs;
  srs.importFromEPSG(gcps.epsg);
  if (ds.SetGCPs(static_cast<int>(list.size()), list.data(), &srs) != CE_None) {
    fail("cannot set the ground control points");
  }
}

}  // namespace

void copy_adding_overviews(const std::string& from, const std::string& to,
                           const std::vector<std::string>& resampling,
                           const std::vector<std::pair<std::string, std::string>>& creation_options,
                           const GroundControl& gcps, const char* who,
                           const std::string& final_path, bool cog_layout) {
  TemporaryFile source_file(from);
  const auto cached_writes = gdal::lock_cached_writes();
  auto fail = [&](const std::string& what) {
    const std::string msg = gdal::last_error_message();
    throw FormatError(std::string(who) + ": " + final_path + ": " + what +
                      (msg.empty() ? "" : ": " + msg));
  };
  gdal::ensure_registered();
  CPLErrorReset();
  gdal::DatasetPtr ds(GDALDataset::Open(from.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE));
  if (!ds) fail("cannot reopen " + from);
  std::vector<int> factors = overview_factors(static_cast<std::size_t>(ds->GetRasterXSize()),
                                              static_cast<std::size_t>(ds->GetRasterYSize()));
  if (cog_layout && !factors.empty()) add_overviews(*ds, factors, resampling, fail);
  set_gcps(*ds, gcps, fail);
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!gtiff) fail("GDAL has no GTiff driver");
  CPLStringList co;
  for (const auto& [k, v] : creation_options) co.SetNameValue(k.c_str(), v.c_str());
  if (cog_layout && !factors.empty()) co.SetNameValue("COPY_SRC_OVERVIEWS", "YES");
  CPLErrorReset();
  GDALDataset* out = gtiff->CreateCopy(to.c_str(), ds.get(), FALSE, co.List(), nullptr, nullptr);
  if (!out) fail("cannot write GTiff");
  gdal::close_checked(gdal::DatasetPtr(out), final_path, who);
  if (!cog_layout && !factors.empty()) {
    // A plain tiled GeoTIFF: the image written and closed first, its overviews appended.
    gdal::DatasetPtr copy(GDALDataset::Open(to.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE));
    if (!copy) fail("cannot reopen " + to + " to add overviews");
    add_overviews(*copy, factors, resampling, fail);
    gdal::close_checked(std::move(copy), final_path, who);
  }
  ds.reset();
  std::error_code ec;
  std::filesystem::remove(to + ".aux.xml", ec);
  std::filesystem::remove(from + ".aux.xml", ec);
}

}  // namespace sonarsynth::raster
