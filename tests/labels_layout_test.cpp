// SPDX-License-Identifier: MIT
// The truth and label rasters' file layout (docs/labels.md): the default COG layout and the plain
// tiled GeoTIFF of `--of GTiff`, read back through GDAL.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/products/waterfall.hpp"
#include "sonarsynth/rendered_ping.hpp"

namespace sonarsynth {
namespace {
namespace fs = std::filesystem;

// What GDAL reports of a GeoTIFF's layout: IMAGE_STRUCTURE LAYOUT ("" if none), the file offset
// of the first block of band 1 at full resolution and of each overview, the pixels of band 1 at
// every level (as double), and whether it is tiled.
struct FileLayout {
  std::string layout;
  std::vector<long long> offsets;
  std::vector<std::vector<double>> levels;
  bool tiled = false;
};
FileLayout file_layout(const fs::path& path) {
  FileLayout out;
  GDALDataset* ds = GDALDataset::Open(path.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return out;
  const char* layout = ds->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
  out.layout = layout ? layout : "";
  GDALRasterBand* band = ds->GetRasterBand(1);
  int bx = 0, by = 0;
  band->GetBlockSize(&bx, &by);
  out.tiled = bx < ds->GetRasterXSize() || by < ds->GetRasterYSize();
  std::vector<GDALRasterBand*> levels = {band};
  for (int o = 0; o < band->GetOverviewCount(); ++o) levels.push_back(band->GetOverview(o));
  for (GDALRasterBand* b : levels) {
    const char* offset = b->GetMetadataItem("BLOCK_OFFSET_0_0", "TIFF");
    out.offsets.push_back(offset ? std::stoll(offset) : -1);
    std::vector<double> v(static_cast<std::size_t>(b->GetXSize()) *
                          static_cast<std::size_t>(b->GetYSize()));
    if (b->RasterIO(GF_Read, 0, 0, b->GetXSize(), b->GetYSize(), v.data(), b->GetXSize(),
                    b->GetYSize(), GDT_Float64, 0, 0, nullptr) != CE_None) {
      v.clear();
    }
    out.levels.push_back(std::move(v));
  }
  GDALClose(ds);
  return out;
}

// `--of GTiff` (set_cog_layout(false)): plain tiled GeoTIFFs, each image before its overviews
// in the file where the default has the COG layout (overviews first), with the same pixels at
// every level.
TEST(TruthWaterfall, PlainLayoutHasTheImageFirstAndTheSamePixels) {
  const fs::path dir =
      fs::temp_directory_path() / ("sonarsynth_truth_plain_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  TruthWaterfall truth(dir);
  for (std::int32_t p = 0; p < 300; ++p) {  // 300 rows: one overview level
    std::vector<SampleClass> c(120, SampleClass::seabed);
    std::vector<std::int32_t> id(120, 0);
    std::vector<float> g(120, 0.5f);
    for (std::size_t i = 40 + static_cast<std::size_t>(p % 30); i < 60; ++i) {
      c[i] = SampleClass::object;
      id[i] = 7 + p / 100;
    }
    truth.add_ping(c, c, id, id, g, g);
  }
  const std::vector<std::pair<std::string, std::string>> items = {{"RUN", "test"}};
  truth.write_with_labels((dir / "truth.tif").string(), (dir / "class.tif").string(),
                          (dir / "instance.tif").string(), false, items);
  truth.set_cog_layout(false);
  truth.write_with_labels((dir / "truth_plain.tif").string(), (dir / "class_plain.tif").string(),
                          (dir / "instance_plain.tif").string(), false, items);
  for (const char* name : {"truth", "class", "instance"}) {
    const FileLayout cog = file_layout(dir / (std::string(name) + ".tif"));
    const FileLayout plain = file_layout(dir / (std::string(name) + "_plain.tif"));
    ASSERT_EQ(cog.levels.size(), 2u) << name << ": 300 rows give one overview";
    ASSERT_EQ(plain.levels.size(), cog.levels.size()) << name;
    EXPECT_LT(cog.offsets[1], cog.offsets[0]) << name << ": COG layout, overview first";
    EXPECT_LT(plain.offsets[0], plain.offsets[1]) << name << ": image first";
    EXPECT_EQ(plain.layout, "") << name;
    if (std::string(name) != "truth") {
      EXPECT_EQ(cog.layout, "COG") << name;
    }
    EXPECT_TRUE(plain.levels == cog.levels) << name;
    EXPECT_TRUE(plain.tiled) << name;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarsynth
