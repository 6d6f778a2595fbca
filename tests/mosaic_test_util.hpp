// SPDX-License-Identifier: MIT
#pragma once

// Helpers for the mosaic tests: synthetic survey lines written as XTF, GeoTIFFs read back
// through GDAL, and geodesic positions computed independently of the mosaicker
// (GeographicLib::Geodesic on the ellipsoid, UTMUPS for the projection).

#include <gdal_priv.h>
#include <unistd.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cli_test_util.hpp"
#include "sonarsynth/formats/xtf/writer.hpp"
#include "sonarsynth/geo_frame.hpp"
#include "sonarsynth/mosaic.hpp"

namespace sonarsynth::test {

inline std::filesystem::path mosaic_temp_dir(const std::string& name) {
  return fresh_temp_dir("mosaic_" + name);
}

/// Expects `a` and `b` equal bit for bit: intensity, count and labels of every pixel.
inline void expect_same_bits(const MosaicImage& a, const MosaicImage& b, const std::string& what) {
  ASSERT_EQ(a.intensity.size(), b.intensity.size()) << what;
  for (std::size_t i = 0; i < a.intensity.size(); ++i) {
    std::uint32_t x = 0, y = 0;
    std::memcpy(&x, &a.intensity[i], sizeof x);
    std::memcpy(&y, &b.intensity[i], sizeof y);
    ASSERT_EQ(x, y) << what << ", pixel " << i;
  }
  EXPECT_EQ(a.count, b.count) << what;
  EXPECT_EQ(a.labels, b.labels) << what;
}

/// The pixels of `m` that hold at least one sample.
/// A level ping heading grid north at `xy_m`, `altitude_m` above the seabed, its sides' samples
/// spanning `slant_range_m`. The ping views `port` and `starboard`: they must outlive it.
inline MosaicPing level_ping(const Eigen::Vector2d& xy_m, double altitude_m, double slant_range_m,
                             std::span<const float> port, std::span<const float> starboard) {
  MosaicPing p;
  p.sensor_xy_m = xy_m;
  p.altitude_m = altitude_m;
  p.slant_range_m = slant_range_m;
  p.port = port;
  p.starboard = starboard;
  return p;
}

inline std::size_t gridded_pixels(const MosaicImage& m) {
  return static_cast<std::size_t>(
      std::count_if(m.count.begin(), m.count.end(), [](auto c) { return c > 0; }));
}

/// A point `distance_m` from (lat, lon) along true azimuth `azimuth_deg`, degrees.
struct LatLon {
  double lat_deg;
  double lon_deg;
};
inline LatLon direct(LatLon from, double azimuth_deg, double distance_m) {
  LatLon to{};
  GeographicLib::Geodesic::WGS84().Direct(from.lat_deg, from.lon_deg, azimuth_deg, distance_m,
                                          to.lat_deg, to.lon_deg);
  return to;
}

/// A straight survey line: pings every `spacing_m` along true heading `heading_deg` from
/// `start`, flat seabed at `altitude_m` below the fish, `samples` per side over `range_m`, all
/// samples 1 except starboard sample `bright` = 1000 in the pings listed in `bright_pings`
/// (all pings if empty: a bright line; else point targets).
struct LineSpec {
  LatLon start{};
  double heading_deg = 33.0;
  int pings = 200;
  double spacing_m = 0.1;
  double altitude_m = 10.0;
  double range_m = 50.0;
  std::size_t samples = 500;
  std::size_t bright = 299;
  std::vector<int> bright_pings;
};

inline double bright_ground_range_m(const LineSpec& s) {
  const double r =
      (static_cast<double>(s.bright) + 0.5) * s.range_m / static_cast<double>(s.samples);
  return std::sqrt(r * r - s.altitude_m * s.altitude_m);
}

inline LatLon ping_position(const LineSpec& s, int i) {
  return direct(s.start, s.heading_deg, s.spacing_m * i);
}

/// Writes the line; `edit(i, ping)`, if given, may change ping i before it is written and
/// returns false to leave it out.
inline void write_line(const std::filesystem::path& path, const LineSpec& s,
                       const std::function<bool(int, SonarPing&)>& edit = {}) {
  xtf::WriterOptions wo;
  wo.sample_encoding = xtf::SampleEncoding::kFloat32;
  xtf::Writer w(path, wo);
  using namespace std::chrono;
  const UtcTime t0{sys_days{year{2024} / January / 15} + hours{12}};
  for (int i = 0; i < s.pings; ++i) {
    SonarPing p;
    p.time_utc = t0 + milliseconds{100 * i};
    p.ping_number = static_cast<std::uint32_t>(i);
    const LatLon pos = ping_position(s, i);
    p.sensor_position = {rad_from_deg(pos.lat_deg), rad_from_deg(pos.lon_deg), 0.0};
    p.heading_true_rad = rad_from_deg(s.heading_deg);
    p.altitude_m = s.altitude_m;
    p.depth_m = 20.0;
    p.speed_m_s = s.spacing_m / 0.1;
    p.slant_range_m = s.range_m;
    p.port.assign(s.samples, 1.0f);
    p.starboard.assign(s.samples, 1.0f);
    // No bright sample when `bright` is beyond the samples (specs with few samples).
    if (s.bright < s.samples &&
        (s.bright_pings.empty() ||
         std::find(s.bright_pings.begin(), s.bright_pings.end(), i) != s.bright_pings.end())) {
      p.starboard[s.bright] = 1000.0f;
    }
    if (edit && !edit(i, p)) continue;
    w.write_ping(p);
  }
  w.close();
}

/// A float32 band and its geotransform, read through GDAL.
struct Raster {
  int cols = 0;
  int rows = 0;
  double gt[6] = {};
  std::vector<float> data;
  /// Value of the pixel containing projected (e, n); NaN outside.
  float at(double e, double n) const {
    const double c = std::floor((e - gt[0]) / gt[1]);
    const double r = std::floor((n - gt[3]) / gt[5]);
    if (c < 0 || r < 0 || c >= cols || r >= rows) return std::nanf("");
    return data[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) +
                static_cast<std::size_t>(c)];
  }
};

inline Raster read_band(const std::string& path, int band = 1) {
  GDALAllRegister();
  Raster r;
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return r;
  r.cols = ds->GetRasterXSize();
  r.rows = ds->GetRasterYSize();
  ds->GetGeoTransform(r.gt);
  r.data.resize(static_cast<std::size_t>(r.cols) * static_cast<std::size_t>(r.rows));
  if (ds->GetRasterBand(band)->RasterIO(GF_Read, 0, 0, r.cols, r.rows, r.data.data(), r.cols,
                                        r.rows, GDT_Float32, 0, 0, nullptr) != CE_None) {
    r.data.clear();
  }
  GDALClose(ds);
  return r;
}

/// Projected (easting, northing) of a point in UTM zone `zone` (forced, as in the raster; the
/// hemisphere follows the latitude).
inline std::pair<double, double> utm(LatLon p, int zone) {
  int z = 0;
  bool northp = false;
  double e = 0, n = 0;
  GeographicLib::UTMUPS::Forward(p.lat_deg, p.lon_deg, z, northp, e, n, zone);
  return {e, n};
}

/// Three lines over a 100 m x 80 m box (the second crosses the first and the third re-crosses
/// ground the first left long before), speckled values and labels.
template <typename Grid>
inline void survey(Grid& grid) {
  std::mt19937_64 rng(5);
  std::exponential_distribution<float> speckle(0.01f);
  std::vector<float> port(400), stbd(400);
  std::vector<std::int32_t> labels(400);
  const Eigen::Vector2d starts[3] = {{-40, -30}, {-35, 35}, {30, -35}};
  const double headings[3] = {1.2, 2.6, -0.6};
  for (int line = 0; line < 3; ++line) {
    grid.break_line();
    for (int i = 0; i < 150; ++i) {
      for (auto* side : {&port, &stbd}) {
        for (float& v : *side) v = speckle(rng);
      }
      for (std::size_t k = 0; k < labels.size(); ++k) {
        labels[k] = static_cast<std::int32_t>((k / 40 + static_cast<std::size_t>(line)) % 4);
      }
      MosaicPing p;
      p.heading_grid_rad = headings[line];
      p.sensor_xy_m =
          starts[line] +
          0.5 * i * Eigen::Vector2d(std::sin(p.heading_grid_rad), std::cos(p.heading_grid_rad));
      p.altitude_m = 3.0;
      p.slant_range_m = 20.0;
      p.port = port;
      p.starboard = stbd;
      p.port_labels = labels;
      p.starboard_labels = labels;
      grid.add(p);
    }
  }
}

}  // namespace sonarsynth::test
