// SPDX-License-Identifier: MIT
// Helpers shared by the waterfall tests (waterfall_test.cpp, waterfall_rows_test.cpp): random
// pings, the image assembled in memory, colours computed here, rasters read back with GDAL.
#pragma once

#include <gdal_priv.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "sonarsynth/colormap.hpp"
#include "sonarsynth/display_scale.hpp"
#include "sonarsynth/formats/products/waterfall.hpp"

namespace sonarsynth::test {

namespace fs = std::filesystem;

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// One ping: port and starboard samples NEAR -> FAR.
struct Ping {
  std::vector<float> port;
  std::vector<float> stbd;
};

/// Pings with side lengths varying from 0 to `max_side` (the longest reached only at ping
/// `pings` / 2, so the width grows after rows were spooled), speckle-like values with some
/// zeros and NaNs.
inline std::vector<Ping> random_pings(int pings, std::size_t max_side, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> len(0, max_side - 1);
  std::exponential_distribution<float> speckle(0.5f);
  std::uniform_int_distribution<int> special(0, 99);
  auto side = [&](std::size_t n) {
    std::vector<float> v(n);
    for (float& x : v) {
      const int s = special(rng);
      x = s == 0 ? 0.0f : s == 1 ? kNaN : 1e-3f + speckle(rng);
    }
    return v;
  };
  std::vector<Ping> out(static_cast<std::size_t>(pings));
  for (int i = 0; i < pings; ++i) {
    const std::size_t np = i == pings / 2 ? max_side : len(rng);
    const std::size_t ns = i % 7 == 3 ? 0 : len(rng);
    out[static_cast<std::size_t>(i)] = {side(np), side(ns)};
  }
  return out;
}

/// The waterfall layout computed directly: 2 x longest side columns, port FAR -> NEAR then
/// starboard NEAR -> FAR, `pad` elsewhere.
inline std::vector<float> expected_image(const std::vector<Ping>& pings, std::size_t* cols,
                                         float pad) {
  std::size_t side = 0;
  for (const Ping& p : pings) side = std::max({side, p.port.size(), p.stbd.size()});
  *cols = 2 * side;
  std::vector<float> img(*cols * pings.size(), pad);
  for (std::size_t r = 0; r < pings.size(); ++r) {
    for (std::size_t i = 0; i < pings[r].port.size(); ++i) {
      img[r * *cols + side - 1 - i] = pings[r].port[i];
    }
    for (std::size_t i = 0; i < pings[r].stbd.size(); ++i) {
      img[r * *cols + side + i] = pings[r].stbd[i];
    }
  }
  return img;
}

/// random_pings and the image they make (expected_image, NaN padding) with its column count.
struct RandomImage {
  std::vector<Ping> pings;
  std::size_t cols = 0;
  std::vector<float> image;
};
inline RandomImage random_image(int pings, std::size_t max_side, unsigned seed) {
  RandomImage r;
  r.pings = random_pings(pings, max_side, seed);
  r.image = expected_image(r.pings, &r.cols, kNaN);
  return r;
}

inline bool same_float(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

/// Band-sequential u8 colours of a linear image: black for NaN.
inline std::vector<std::uint8_t> colourise(const std::vector<float>& img, DisplayRange range,
                                           Colormap map) {
  const bool grey = map == Colormap::grey;
  const std::size_t n = img.size();
  std::vector<std::uint8_t> out((grey ? 1 : 3) * n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = range.value(img[i]);
    if (std::isnan(v)) continue;
    const Rgb8 c = colormap(map, v);
    out[i] = c.r;
    if (!grey) {
      out[n + i] = c.g;
      out[2 * n + i] = c.b;
    }
  }
  return out;
}

/// All bands of a raster as band-sequential u8 (empty if unreadable); the driver's name.
inline std::vector<std::uint8_t> read_bytes(const std::string& path, int* cols, int* rows,
                                            std::string* driver) {
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return {};
  *cols = ds->GetRasterXSize();
  *rows = ds->GetRasterYSize();
  *driver = ds->GetDriver()->GetDescription();
  const int bands = ds->GetRasterCount();
  const std::size_t n = static_cast<std::size_t>(*cols) * static_cast<std::size_t>(*rows);
  std::vector<std::uint8_t> out(n * static_cast<std::size_t>(bands));
  for (int b = 0; b < bands; ++b) {
    if (ds->GetRasterBand(b + 1)->RasterIO(GF_Read, 0, 0, *cols, *rows,
                                           out.data() + static_cast<std::size_t>(b) * n, *cols,
                                           *rows, GDT_Byte, 0, 0, nullptr) != CE_None) {
      out.clear();
      break;
    }
  }
  GDALClose(ds);
  return out;
}

/// A waterfall of options `o` (spooled in `dir`) holding `pings`, without navigation.
inline Waterfall waterfall_of(WaterfallOptions o, const fs::path& dir,
                              const std::vector<Ping>& pings) {
  o.spool_dir = dir;
  Waterfall wf(o);
  for (const Ping& p : pings) wf.add_ping(p.port, p.stbd, 0.0, 0.0);
  return wf;
}

/// waterfall_of(o, dir, pings) written to `dir` / `name`; returns the file's path.
inline std::string write_waterfall(const WaterfallOptions& o, const std::vector<Ping>& pings,
                                   const fs::path& dir, const std::string& name) {
  const std::string path = (dir / name).string();
  waterfall_of(o, dir, pings).write(path);
  return path;
}

/// The number of positions where two equally long byte images differ (a count, not a dump of
/// millions of pixels, when they do).
inline std::size_t mismatched_bytes(const std::vector<std::uint8_t>& got,
                                    const std::vector<std::uint8_t>& want) {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < want.size(); ++i) bad += got[i] != want[i];
  return bad;
}

/// Open descriptors of this process on files in `dir` (as /proc/self/fd shows them; a spool
/// file reads "<dir>/<name> (deleted)").
inline std::vector<std::string> open_files_in(const fs::path& dir) {
  const std::string prefix = fs::canonical(dir).string() + "/";
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator("/proc/self/fd")) {
    std::error_code ec;
    const std::string target = fs::read_symlink(e.path(), ec).string();
    if (!ec && target.rfind(prefix, 0) == 0) out.push_back(target);
  }
  return out;
}

}  // namespace sonarsynth::test
