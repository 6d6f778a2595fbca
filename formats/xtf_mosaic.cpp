// SPDX-License-Identifier: MIT
#include "sonarsynth/formats/xtf_mosaic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "sonarsynth/error.hpp"
#include "sonarsynth/formats/xtf/reader.hpp"

namespace sonarsynth {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct NavPoint {
  Geodetic position;
  double margin_m;  ///< slant range (+ layback if applied): how far samples can reach
};

bool has_samples(const xtf::SonarPing& s) {
  return (!s.port.empty() || !s.starboard.empty()) && s.slant_range_m > 0.0 &&
         std::isfinite(s.slant_range_m);
}

bool has_geographic_nav(const xtf::Reader& reader, const xtf::PingRecord& ping) {
  return ping.nav_valid && reader.file_header().NavUnits == 3;
}

}  // namespace

void XtfMosaicOptions::validate() const {
  if (!(pixel_size_m > 0.0) || !std::isfinite(pixel_size_m)) {
    std::ostringstream os;
    os << "xtf mosaic: pixel_size_m (--res) = " << pixel_size_m
       << ". Violated constraint: pixel_size_m > 0";
    throw InputError(os.str());
  }
  gridding.validate();
}

double first_return_range_m(const std::vector<float>& s, double slant_range_m) {
  if (s.empty()) return kNaN;
  const float peak = *std::max_element(s.begin(), s.end());
  if (!(peak > 0.0f)) return kNaN;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] >= 0.5f * peak) {
      return (static_cast<double>(i) + 0.5) * slant_range_m / static_cast<double>(s.size());
    }
  }
  return kNaN;
}

XtfMosaicResult mosaic_xtf(const std::vector<std::filesystem::path>& files,
                           const XtfMosaicOptions& options, const LoadedGrid* bathymetry) {
  options.validate();
  if (files.empty()) throw InputError("xtf mosaic: no input file");
  XtfMosaicResult result;
  result.files = files.size();

  // Pass 1: navigation, extent, sanity of every file.
  std::vector<NavPoint> nav;
  xtf::Packet packet;
  for (const auto& path : files) {
    xtf::Reader reader(path);
    std::size_t with_samples = 0;
    std::size_t pings = 0;
    while (reader.next(packet)) {
      if (packet.kind != xtf::PacketKind::kPing) continue;
      ++pings;
      const xtf::SonarPing& s = packet.ping.sonar;
      if (!has_samples(s)) continue;
      ++with_samples;
      if (!has_geographic_nav(reader, packet.ping)) continue;
      const double layback = packet.ping.header.Layback;
      const double margin = options.apply_layback && std::isfinite(layback) && layback > 0.0
                                ? s.slant_range_m + layback
                                : s.slant_range_m;
      nav.push_back({s.sensor_position, margin});
    }
    if (with_samples == 0) {
      throw FormatError("xtf mosaic: " + path.string() + ": no sonar channel (no ping of " +
                        std::to_string(pings) + " has port or starboard samples)");
    }
  }
  if (nav.empty()) {
    throw FormatError(
        "xtf mosaic: no ping has valid navigation in " +
        (files.size() == 1 ? files.front().string() : std::to_string(files.size()) + " files") +
        " (SensorX/Ycoordinate zero, invalid, or not geographic: NavUnits != 3)");
  }

  // Frame: the zone of the centroid (longitude averaged on the circle: dateline-safe).
  double lat = 0.0, sx = 0.0, sy = 0.0;
  for (const auto& p : nav) {
    lat += p.position.lat_rad;
    sx += std::cos(p.position.lon_rad);
    sy += std::sin(p.position.lon_rad);
  }
  const Geodetic centroid{lat / static_cast<double>(nav.size()), std::atan2(sy, sx), 0.0};
  result.frame = bathymetry ? bathymetry->frame : GeoFrame::around(centroid);
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const auto& p : nav) {
    const Eigen::Vector2d xy = result.frame.local_from_geodetic(p.position);
    lo = lo.cwiseMin((xy.array() - p.margin_m).matrix());
    hi = hi.cwiseMax((xy.array() + p.margin_m).matrix());
  }
  nav.clear();
  nav.shrink_to_fit();
  const GridGeometry geometry = MosaicGrid::geometry_covering(lo, hi, options.pixel_size_m);
  MosaicGrid grid(geometry, options.gridding, bathymetry ? &bathymetry->grid : nullptr);

  // Pass 2: gridding.
  for (const auto& path : files) {
    xtf::Reader reader(path);
    while (reader.next(packet)) {
      if (packet.kind != xtf::PacketKind::kPing) continue;
      ++result.pings;
      const xtf::SonarPing& s = packet.ping.sonar;
      if (!has_samples(s)) {
        ++result.pings_no_samples;
        continue;
      }
      if (!has_geographic_nav(reader, packet.ping)) {
        ++result.pings_no_navigation;
        grid.break_line();
        continue;
      }
      MosaicPing mp;
      mp.sensor_xy_m = result.frame.local_from_geodetic(s.sensor_position);
      mp.heading_grid_rad = result.frame.grid_azimuth_from_true_rad(s.heading_rad, mp.sensor_xy_m);
      mp.pitch_rad = std::isfinite(s.pitch_rad) && std::abs(s.pitch_rad) < rad_from_deg(45.0)
                         ? s.pitch_rad
                         : 0.0;
      mp.slant_range_m = s.slant_range_m;
      if (options.apply_layback) {
        const double layback = packet.ping.header.Layback;
        if (std::isfinite(layback) && layback > 0.0) {
          mp.sensor_xy_m -= layback * Eigen::Vector2d(std::sin(mp.heading_grid_rad),
                                                      std::cos(mp.heading_grid_rad));
        }
      }
      double altitude = s.altitude_m;
      if (!(altitude > 0.0) || !std::isfinite(altitude)) {
        altitude = kNaN;
        if (options.bottom_pick) {
          const double rp = first_return_range_m(s.port, s.slant_range_m);
          const double rs = first_return_range_m(s.starboard, s.slant_range_m);
          const double picked = std::isnan(rp) ? rs : (std::isnan(rs) ? rp : 0.5 * (rp + rs));
          if (picked > 0.0) {
            altitude = picked;
            ++result.pings_bottom_picked;
          }
        }
        if (std::isnan(altitude)) {
          ++result.pings_no_altitude;
          continue;
        }
      }
      mp.altitude_m = altitude;
      mp.port = s.port;
      mp.starboard = s.starboard;
      const MosaicAddStats st = grid.add(mp);
      if (st.samples_placed > 0) ++result.pings_gridded;
      result.samples_placed += st.samples_placed;
      result.fill_points += st.fill_points + st.along_fill_points;
    }
    grid.break_line();  // no along-track fill from one file into the next
    result.reader_anomalies += reader.total_anomalies();
  }
  result.image = grid.finish();
  return result;
}

}  // namespace sonarsynth
