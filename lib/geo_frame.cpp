// SPDX-License-Identifier: MIT
#include "sonarsynth/geo_frame.hpp"

#include <GeographicLib/UTMUPS.hpp>
#include <cmath>
#include <string>

#include "sonarsynth/error.hpp"

namespace sonarsynth {

GeoFrame::GeoFrame(int zone, bool northp, double origin_easting_m, double origin_northing_m)
    : zone_(zone),
      northp_(northp),
      origin_easting_m_(origin_easting_m),
      origin_northing_m_(origin_northing_m) {
  if (zone < GeographicLib::UTMUPS::MINZONE || zone > GeographicLib::UTMUPS::MAXZONE) {
    throw InputError("geo frame: zone = " + std::to_string(zone) +
                     ". Violated constraint: 0 <= zone <= 60 (0 = UPS)");
  }
  if (!std::isfinite(origin_easting_m) || !std::isfinite(origin_northing_m)) {
    throw InputError("geo frame: origin is not finite");
  }
}

GeoFrame GeoFrame::around(const Geodetic& centre) {
  const double lat = deg_from_rad(centre.lat_rad);
  const double lon = deg_from_rad(centre.lon_rad);
  if (!(std::abs(lat) <= 90.0)) {
    throw InputError("geo frame: lat_deg = " + std::to_string(lat) +
                     ". Violated constraint: -90 <= lat_deg <= 90");
  }
  if (!std::isfinite(lon)) {
    throw InputError("geo frame: lon_deg = " + std::to_string(lon) +
                     ". Violated constraint: finite");
  }
  int zone = 0;
  bool northp = true;
  double x = 0, y = 0;
  GeographicLib::UTMUPS::Forward(lat, lon, zone, northp, x, y);
  return GeoFrame(zone, northp, std::round(x / 1000.0) * 1000.0, std::round(y / 1000.0) * 1000.0);
}

int GeoFrame::epsg() const {
  if (zone_ == GeographicLib::UTMUPS::UPS) return northp_ ? 32661 : 32761;
  return (northp_ ? 32600 : 32700) + zone_;
}

Eigen::Vector2d GeoFrame::local_from_geodetic(const Geodetic& p) const {
  const double lat = deg_from_rad(p.lat_rad);
  const double lon = deg_from_rad(p.lon_rad);
  int zone = 0;
  bool northp = true;
  double x = 0, y = 0, gamma = 0, k = 0;
  try {
    GeographicLib::UTMUPS::Forward(lat, lon, zone, northp, x, y, gamma, k, zone_);
  } catch (const std::exception& e) {
    throw InputError("geo frame: cannot project lat " + std::to_string(lat) + " lon " +
                     std::to_string(lon) + " deg into EPSG:" + std::to_string(epsg()) + ": " +
                     e.what());
  }
  // A point in the other hemisphere of the same zone keeps this frame's false northing.
  if (northp != northp_)
    y += northp_ ? -GeographicLib::UTMUPS::UTMShift() : GeographicLib::UTMUPS::UTMShift();
  return local_from_projected({x, y});
}

Geodetic GeoFrame::geodetic_from_local(const Eigen::Vector2d& xy_m, double z_m) const {
  const Eigen::Vector2d en = projected_from_local(xy_m);
  double lat = 0, lon = 0;
  GeographicLib::UTMUPS::Reverse(zone_, northp_, en.x(), en.y(), lat, lon, /*mgrslimits=*/false);
  return {rad_from_deg(lat), rad_from_deg(lon), z_m};
}

double GeoFrame::convergence_rad(const Eigen::Vector2d& xy_m) const {
  const Eigen::Vector2d en = projected_from_local(xy_m);
  double lat = 0, lon = 0, gamma = 0, k = 0;
  GeographicLib::UTMUPS::Reverse(zone_, northp_, en.x(), en.y(), lat, lon, gamma, k, false);
  return rad_from_deg(gamma);
}

double GeoFrame::scale_factor(const Eigen::Vector2d& xy_m) const {
  const Eigen::Vector2d en = projected_from_local(xy_m);
  double lat = 0, lon = 0, gamma = 0, k = 0;
  GeographicLib::UTMUPS::Reverse(zone_, northp_, en.x(), en.y(), lat, lon, gamma, k, false);
  return k;
}

}  // namespace sonarsynth
