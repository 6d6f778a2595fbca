// SPDX-License-Identifier: MIT
// The finished mosaic read window by window from the tiles (MosaicGrid::read_window) and the
// mosaic files written from them (write_mosaic of a MosaicGrid) against the whole image
// (MosaicGrid::finish() of an untiled grid) and the files written from it (write_mosaic of a
// MosaicImage: in-memory GDAL datasets): the same bits in every band at full resolution and in
// every overview, the same metadata; no temporary file left after success or after a failure.
#include "sonarsynth/formats/products/mosaic_blocks.hpp"

#include <cpl_conv.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "mosaic_test_util.hpp"
#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/products/mosaic_writer.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth {
namespace {

using test::survey;

struct Closer {
  void operator()(GDALDataset* ds) const { GDALClose(ds); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, Closer>;

/// What a raster file says and holds: dataset metadata, georeferencing, per band its type,
/// description, unit, nodata, colour interpretation, metadata and mask flags, then (`pixels`)
/// the bytes of every band at full resolution and of every overview.
struct FileFacts {
  std::vector<std::string> facts;
  std::vector<std::vector<unsigned char>> pixels;
};

FileFacts read_file_facts(const std::string& path) {
  FileFacts f;
  DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds) {
    ADD_FAILURE() << "cannot open " << path;
    return f;
  }
  for (char** md = ds->GetMetadata(); md && *md; ++md) f.facts.emplace_back(*md);
  double gt[6] = {};
  ds->GetGeoTransform(gt);
  for (double v : gt) f.facts.push_back(std::to_string(v));
  const char* wkt = ds->GetProjectionRef();
  f.facts.emplace_back(wkt ? wkt : "");
  for (int b = 1; b <= ds->GetRasterCount(); ++b) {
    GDALRasterBand* band = ds->GetRasterBand(b);
    int has_nodata = 0;
    const double nodata = band->GetNoDataValue(&has_nodata);
    f.facts.push_back("band " + std::to_string(b) + " type " +
                      std::to_string(band->GetRasterDataType()) + " '" + band->GetDescription() +
                      "' unit '" + band->GetUnitType() + "' nodata " +
                      (has_nodata ? std::to_string(nodata) : "none") + " interp " +
                      std::to_string(band->GetColorInterpretation()) + " mask " +
                      std::to_string(band->GetMaskFlags()) + " overviews " +
                      std::to_string(band->GetOverviewCount()));
    for (char** md = band->GetMetadata(); md && *md; ++md) f.facts.emplace_back(*md);
    for (int level = -1; level < band->GetOverviewCount(); ++level) {
      GDALRasterBand* r = level < 0 ? band : band->GetOverview(level);
      const int nx = r->GetXSize(), ny = r->GetYSize();
      const auto type = r->GetRasterDataType();
      std::vector<unsigned char> bytes(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) *
                                       static_cast<std::size_t>(GDALGetDataTypeSizeBytes(type)));
      EXPECT_EQ(r->RasterIO(GF_Read, 0, 0, nx, ny, bytes.data(), nx, ny, type, 0, 0, nullptr),
                CE_None);
      f.pixels.push_back(std::move(bytes));
    }
  }
  return f;
}

void expect_same_file(const std::string& a, const std::string& b) {
  const FileFacts fa = read_file_facts(a);
  const FileFacts fb = read_file_facts(b);
  EXPECT_EQ(fa.facts, fb.facts) << a << " vs " << b;
  ASSERT_EQ(fa.pixels.size(), fb.pixels.size()) << a;
  for (std::size_t i = 0; i < fa.pixels.size(); ++i) {
    EXPECT_TRUE(fa.pixels[i] == fb.pixels[i]) << a << " vs " << b << ": raster " << i;
  }
}

std::vector<std::string> names_in(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

/// A map of the gridded labels to stored ones (as the truth codes' decoding is).
std::int32_t relabel(std::int32_t v) {
  return v == MosaicImage::kNoLabel ? v : 10 * v + 1;
}

// 0.125 m pixels: 800 x 640, overviews at 2 and 4; 17-pixel tiles (partial tiles at the right
// and bottom edges) and a budget of a few tiles, so that most tiles are read back from the file.
const GridGeometry kGeometry = MosaicGrid::geometry_covering({-50, -40}, {50, 40}, 0.125);
constexpr std::size_t kTile = 17;
constexpr std::size_t kBudget = 4 * kTile * kTile * 20;

TEST(MosaicBlocks, WindowsAreThoseOfTheWholeImage) {
  const auto dir = test::mosaic_temp_dir("windows");
  MosaicGrid whole(kGeometry, MosaicOptions{}, nullptr, std::max(kGeometry.cols, kGeometry.rows));
  survey(whole);
  const MosaicImage reference = whole.finish();
  MosaicGrid tiled(kGeometry, MosaicOptions{}, nullptr, kTile);
  tiled.spill_to(dir, kBudget);
  survey(tiled);
  ASSERT_GT(tiled.spilled_tiles(), 100u);
  auto check = [&](std::size_t c0, std::size_t r0, std::size_t nc, std::size_t nr) {
    MosaicImage w;
    tiled.read_window(c0, r0, nc, nr, w);
    ASSERT_EQ(w.geometry.cols, nc);
    ASSERT_EQ(w.geometry.rows, nr);
    EXPECT_EQ(w.geometry.x0_m, kGeometry.x0_m + static_cast<double>(c0) * kGeometry.dx_m);
    EXPECT_EQ(w.geometry.y0_m, kGeometry.y0_m + static_cast<double>(r0) * kGeometry.dy_m);
    for (std::size_t r = 0; r < nr; ++r) {
      for (std::size_t c = 0; c < nc; ++c) {
        const std::size_t i = (r0 + r) * kGeometry.cols + c0 + c;
        const std::size_t j = r * nc + c;
        ASSERT_EQ(std::memcmp(&w.intensity[j], &reference.intensity[i], sizeof(float)), 0)
            << "pixel " << c0 + c << ", " << r0 + r;
        ASSERT_EQ(w.count[j], reference.count[i]);
        ASSERT_EQ(w.labels[j], reference.labels[i]);
      }
    }
  };
  for (int pass = 0; pass < 2; ++pass) {  // before and after finalize()
    check(0, 0, kGeometry.cols, kGeometry.rows);
    check(5, 3, 40, 1);                                   // one row across tiles
    check(33, 100, 1, 300);                               // one column
    check(250, 200, 123, 77);                             // tile edges inside
    check(kGeometry.cols - 9, kGeometry.rows - 4, 9, 4);  // the partial corner tile
    tiled.finalize();
  }
  MosaicImage w;
  EXPECT_THROW(tiled.read_window(kGeometry.cols - 3, 0, 4, 1, w), std::out_of_range);
  EXPECT_THROW(tiled.read_window(0, 0, 0, 1, w), std::out_of_range);
  EXPECT_THROW(survey(tiled), std::logic_error);  // nothing is added after finalize()
  std::filesystem::remove_all(dir);
}

TEST(MosaicBlocks, FilesFromTheTilesAreThoseOfTheWholeImage) {
  const auto dir = test::mosaic_temp_dir("blocks");
  const auto spill_dir = dir / "spill";
  const auto whole_dir = dir / "whole";
  const auto tiles_dir = dir / "tiles";
  for (const auto& d : {spill_dir, whole_dir, tiles_dir}) std::filesystem::create_directories(d);
  const GeoFrame frame = GeoFrame::around({rad_from_deg(-33.9), rad_from_deg(18.4), 0.0});
  MosaicGrid grid(kGeometry, MosaicOptions{}, nullptr, kTile);
  grid.spill_to(spill_dir, kBudget);
  survey(grid);
  ASSERT_GT(grid.spilled_tiles(), 100u);
  MosaicImage image = grid.finish();
  for (std::int32_t& v : image.labels) v = relabel(v);
  for (MosaicRasterFormat format : {MosaicRasterFormat::cog, MosaicRasterFormat::gtiff}) {
    const std::string stem = format == MosaicRasterFormat::cog ? "cog" : "gtiff";
    auto options = [&](const std::filesystem::path& d) {
      MosaicWriteOptions wo;
      wo.format = format;
      wo.count_band = true;
      wo.metadata = {{"SONARSYNTH_SEED", "5"}};
      wo.rgb_path = (d / (stem + "_rgb.tif")).string();
      wo.labels_path = (d / (stem + "_truth.tif")).string();
      return wo;
    };
    write_mosaic((whole_dir / (stem + ".tif")).string(), frame, image, options(whole_dir));
    write_mosaic((tiles_dir / (stem + ".tif")).string(), frame, grid, options(tiles_dir),
                 [](std::span<std::int32_t> labels) {
                   for (std::int32_t& v : labels) v = relabel(v);
                 });
    for (const std::string& name : {stem + ".tif", stem + "_rgb.tif", stem + "_truth.tif"}) {
      SCOPED_TRACE(name);
      expect_same_file((whole_dir / name).string(), (tiles_dir / name).string());
    }
  }
  // Only the outputs: no temporary file (the full-resolution levels, the parts) is left.
  EXPECT_EQ(names_in(tiles_dir), names_in(whole_dir));
  EXPECT_EQ(names_in(tiles_dir).size(), 6u);
  {
    DatasetPtr rgb(GDALDataset::Open((tiles_dir / "gtiff_rgb.tif").string().c_str(),
                                     GDAL_OF_RASTER | GDAL_OF_READONLY));
    ASSERT_TRUE(rgb);
    EXPECT_EQ(rgb->GetRasterBand(1)->GetOverviewCount(), 2);  // 800 x 640: 400, 200
  }

  // A failure while the files are written (the label map throws part way): the error names
  // the cause, nothing is left in the directory.
  const auto fail_dir = dir / "fail";
  std::filesystem::create_directories(fail_dir);
  MosaicWriteOptions wo;
  wo.rgb_path = (fail_dir / "m_rgb.tif").string();
  wo.labels_path = (fail_dir / "m_truth.tif").string();
  int calls = 0;
  try {
    write_mosaic((fail_dir / "m.tif").string(), frame, grid, wo, [&calls](std::span<std::int32_t>) {
      if (++calls == 5) throw FormatError("label map failed on purpose");
    });
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("label map failed on purpose"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(std::filesystem::is_empty(fail_dir)) << names_in(fail_dir).size() << " files left";
  std::filesystem::remove_all(dir);
}

/// GDAL's block cache limited to `bytes` for the scope (the previous limit restored after).
class BlockCacheLimit {
 public:
  explicit BlockCacheLimit(GIntBig bytes) : previous_(GDALGetCacheMax64()) {
    GDALSetCacheMax64(bytes);
  }
  ~BlockCacheLimit() { GDALSetCacheMax64(previous_); }
  BlockCacheLimit(const BlockCacheLimit&) = delete;
  BlockCacheLimit& operator=(const BlockCacheLimit&) = delete;

 private:
  GIntBig previous_;
};

/// Writes a tiled 3-band UInt16 GeoTIFF of cols x rows whose pixel (x, y) of band b is
/// (b * 7919 + y * cols + x) mod 65536 (the form the truth and label rasters are written in
/// before copy_adding_overviews).
void write_pattern(const std::string& path, int cols, int rows) {
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  ASSERT_NE(gtiff, nullptr);
  CPLStringList co;
  co.SetNameValue("TILED", "YES");
  co.SetNameValue("BLOCKYSIZE", "64");
  co.SetNameValue("INTERLEAVE", "BAND");
  DatasetPtr ds(gtiff->Create(path.c_str(), cols, rows, 3, GDT_UInt16, co.List()));
  ASSERT_TRUE(ds);
  std::vector<std::uint16_t> row(static_cast<std::size_t>(cols));
  for (int b = 1; b <= 3; ++b) {
    for (int y = 0; y < rows; ++y) {
      for (int x = 0; x < cols; ++x) {
        row[static_cast<std::size_t>(x)] = static_cast<std::uint16_t>(b * 7919 + y * cols + x);
      }
      ASSERT_EQ(ds->GetRasterBand(b)->RasterIO(GF_Write, 0, y, cols, 1, row.data(), cols, 1,
                                               GDT_UInt16, 0, 0, nullptr),
                CE_None);
    }
  }
}

// With GDAL's block cache limited (GDAL_CACHEMAX=8 in a user's environment, or the default
// limit sonarsynth sets), copying a truth or label raster into its final file leaves no block of
// the closed source in the cache: such a block outlives its band, and the eviction that reaches
// it reads the freed band (a crash in GDALRasterBlock::Internalize). One tile wide (GDAL reads
// whole rows of tiles then), in one copy swath (< 1 MB): without overviews (256 rows) and with
// two (600 rows); the copy holds the source's pixels.
TEST(MosaicBlocks, CopyAddingOverviewsLeavesNoBlockBehindInTheCache) {
  gdal::ensure_registered();
  const auto dir = std::filesystem::temp_directory_path() /
                   ("sonarsynth_small_cache_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  constexpr int kCols = 256;
  const BlockCacheLimit cache(8 << 20);
  const GIntBig used_before = GDALGetCacheUsed64();
  int copy = 0;
  for (const auto& [rows, overviews] : {std::pair{256, 0}, {600, 2}}) {
    SCOPED_TRACE("copy " + std::to_string(copy) + ": " + std::to_string(rows) + " rows");
    const std::string from = (dir / ("from" + std::to_string(copy) + ".tif")).string();
    const std::string to = (dir / ("to" + std::to_string(copy) + ".tif")).string();
    ++copy;
    write_pattern(from, kCols, rows);
    raster::copy_adding_overviews(
        from, to, {"NEAREST", "AVERAGE"},
        {{"COMPRESS", "DEFLATE"}, {"INTERLEAVE", "BAND"}, {"TILED", "YES"}, {"BLOCKYSIZE", "64"}},
        {}, "test", to);
    EXPECT_EQ(GDALGetCacheUsed64(), used_before);
    DatasetPtr ds(GDALDataset::Open(to.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    ASSERT_TRUE(ds);
    ASSERT_EQ(ds->GetRasterCount(), 3);
    EXPECT_EQ(ds->GetRasterBand(1)->GetOverviewCount(), overviews);
    std::vector<std::uint16_t> row(kCols);
    for (int b = 1; b <= 3; ++b) {
      for (int y = 0; y < rows; y += 37) {
        ASSERT_EQ(ds->GetRasterBand(b)->RasterIO(GF_Read, 0, y, kCols, 1, row.data(), kCols, 1,
                                                 GDT_UInt16, 0, 0, nullptr),
                  CE_None);
        for (int x = 0; x < kCols; x += 13) {
          ASSERT_EQ(row[static_cast<std::size_t>(x)],
                    static_cast<std::uint16_t>(b * 7919 + y * kCols + x))
              << "band " << b << " (" << x << ", " << y << ")";
        }
      }
    }
  }
  std::filesystem::remove_all(dir);
}

// GDAL's block cache is limited to kBlockCacheBytes when the user set no GDAL_CACHEMAX; a
// GDAL_CACHEMAX set as a configuration option (or in the environment) is left to GDAL.
TEST(MosaicBlocks, BlockCacheLimitUnlessTheUserSetsOne) {
  if (std::getenv("GDAL_CACHEMAX")) GTEST_SKIP() << "GDAL_CACHEMAX is set in the environment";
  gdal::ensure_registered();
  const BlockCacheLimit restore(GDALGetCacheMax64());
  GDALSetCacheMax64(GIntBig{300} << 20);
  EXPECT_EQ(gdal::limit_block_cache(), gdal::kBlockCacheBytes);
  EXPECT_EQ(GDALGetCacheMax64(), gdal::kBlockCacheBytes);
  CPLSetConfigOption("GDAL_CACHEMAX", "300");
  GDALSetCacheMax64(GIntBig{300} << 20);  // as GDAL reads the option
  EXPECT_EQ(gdal::limit_block_cache(), GIntBig{300} << 20);
  CPLSetConfigOption("GDAL_CACHEMAX", nullptr);
}

}  // namespace
}  // namespace sonarsynth
