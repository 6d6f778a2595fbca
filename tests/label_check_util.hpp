// SPDX-License-Identifier: MIT
// Independent checks of label boxes shared by the label and dataset tests: a raster read back
// with GDAL, and the boxes of the 8-connected pieces of every (instance, category) found by a
// flood fill (not by the BoxAccumulator the products use).
#pragma once

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sonarsynth/formats/products/truth_labels.hpp"

namespace sonarsynth::test {

struct LabelRaster {
  std::size_t cols = 0, rows = 0;
  std::vector<std::uint32_t> values;  // any band type, read as UInt32
  bool has_nodata = false;
  double nodata = 0.0;
  GDALDataType type = GDT_Unknown;
  std::map<std::string, std::string> band_items;
};

inline LabelRaster read_label_raster(const std::filesystem::path& path) {
  GDALAllRegister();
  auto* ds = static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly));
  EXPECT_NE(ds, nullptr) << path;
  LabelRaster r;
  if (!ds) return r;
  r.cols = static_cast<std::size_t>(ds->GetRasterXSize());
  r.rows = static_cast<std::size_t>(ds->GetRasterYSize());
  GDALRasterBand* b = ds->GetRasterBand(1);
  int ok = 0;
  r.nodata = b->GetNoDataValue(&ok);
  r.has_nodata = ok != 0;
  r.type = b->GetRasterDataType();
  r.values.resize(r.cols * r.rows);
  EXPECT_EQ(b->RasterIO(GF_Read, 0, 0, static_cast<int>(r.cols), static_cast<int>(r.rows),
                        r.values.data(), static_cast<int>(r.cols), static_cast<int>(r.rows),
                        GDT_UInt32, 0, 0, nullptr),
            CE_None);
  if (char** md = b->GetMetadata()) {
    for (char** p = md; *p; ++p) {
      const std::string kv = *p;
      const auto eq = kv.find('=');
      r.band_items[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
  }
  GDALClose(ds);
  return r;
}

/// {instance, category, x0, y0, x1, y1}: a box relative to the window, pixel edges.
using BoxRow = std::array<std::size_t, 6>;

/// COCO category of a class code: object 1, shadow 2, else 0 (no box).
inline int category_of(std::uint32_t cls) {
  return cls == 2 ? 1 : cls == 3 ? 2 : 0;
}

/// The 8-connected pieces of a window with their pixels (x, y relative to the window), in the
/// order of their boxes.
struct BrutePiece {
  BoxRow box;
  std::set<std::pair<std::size_t, std::size_t>> pixels;  // (x, y)
};
inline std::vector<BrutePiece> brute_pieces(const LabelRaster& cls, const LabelRaster& inst,
                                            std::size_t x0 = 0, std::size_t y0 = 0,
                                            std::size_t w = 0, std::size_t h = 0) {
  if (w == 0) {
    w = cls.cols;
    h = cls.rows;
  }
  auto key = [&](std::size_t x, std::size_t y) {
    const std::size_t i = (y0 + y) * cls.cols + x0 + x;
    const std::uint32_t k = inst.values[i];
    const int c = category_of(cls.values[i]);
    if (k == labels::kInstanceNodata || c == 0) return std::pair<std::uint32_t, int>{0, 0};
    return std::pair<std::uint32_t, int>{k, c};
  };
  std::vector<int> piece(w * h, -1);
  std::vector<BrutePiece> out;
  for (std::size_t y = 0; y < h; ++y) {
    for (std::size_t x = 0; x < w; ++x) {
      const auto k = key(x, y);
      if (k.first == 0 || piece[y * w + x] >= 0) continue;
      BrutePiece p;
      p.box = {k.first, static_cast<std::size_t>(k.second), x, y, x + 1, y + 1};
      std::vector<std::pair<std::size_t, std::size_t>> stack = {{x, y}};
      piece[y * w + x] = static_cast<int>(out.size());
      while (!stack.empty()) {
        const auto [px, py] = stack.back();
        stack.pop_back();
        p.pixels.insert({px, py});
        p.box = {p.box[0],
                 p.box[1],
                 std::min(p.box[2], px),
                 std::min(p.box[3], py),
                 std::max(p.box[4], px + 1),
                 std::max(p.box[5], py + 1)};
        for (std::size_t ny = py == 0 ? 0 : py - 1; ny <= std::min(py + 1, h - 1); ++ny) {
          for (std::size_t nx = px == 0 ? 0 : px - 1; nx <= std::min(px + 1, w - 1); ++nx) {
            if (piece[ny * w + nx] < 0 && key(nx, ny) == k) {
              piece[ny * w + nx] = static_cast<int>(out.size());
              stack.push_back({nx, ny});
            }
          }
        }
      }
      out.push_back(std::move(p));
    }
  }
  std::sort(out.begin(), out.end(),
            [](const BrutePiece& a, const BrutePiece& b) { return a.box < b.box; });
  return out;
}

/// The boxes of the 8-connected pieces of every (instance, category) of a window, sorted.
inline std::vector<BoxRow> brute_boxes(const LabelRaster& cls, const LabelRaster& inst,
                                       std::size_t x0 = 0, std::size_t y0 = 0, std::size_t w = 0,
                                       std::size_t h = 0) {
  std::vector<BoxRow> out;
  for (const BrutePiece& p : brute_pieces(cls, inst, x0, y0, w, h)) out.push_back(p.box);
  return out;
}

}  // namespace sonarsynth::test
