// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

namespace sonarsynth {

/// A geodetic position on WGS 84. Angles in radians (degrees only at I/O).
struct Geodetic {
  double lat_rad = 0.0;   ///< latitude, [-pi/2, pi/2], north positive
  double lon_rad = 0.0;   ///< longitude, [-pi, pi], east positive
  double height_m = 0.0;  ///< height above the vertical datum of the bathymetry, up positive
};

/// The local metric frame every simulation quantity lives in.
///
/// It is a UTM or UPS zone (GeographicLib::UTMUPS, accurate to 5 nm within a zone) shifted by an
/// origin so that coordinates stay small and exact in double precision:
///   x_m = easting_m  - origin_easting_m    (grid east)
///   y_m = northing_m - origin_northing_m   (grid north)
///   z_m = height up, same datum as the bathymetry
/// Grid north differs from true north by the meridian convergence; use
/// grid_azimuth_from_true_rad() to turn a compass heading into a frame azimuth.
class GeoFrame {
 public:
  /// zone: 1..60 for UTM, 0 for UPS; northp: northern hemisphere (or north pole for UPS).
  GeoFrame(int zone, bool northp, double origin_easting_m, double origin_northing_m);

  /// The standard UTM/UPS zone of `centre` (with the Norway/Svalbard exceptions), origin at
  /// the projected position of `centre` rounded to whole kilometres.
  static GeoFrame around(const Geodetic& centre);

  int zone() const { return zone_; }
  bool northp() const { return northp_; }
  /// EPSG code of the zone's WGS 84 projected CRS (326zz / 327zz, 32661 / 32761 for UPS).
  int epsg() const;
  double origin_easting_m() const { return origin_easting_m_; }
  double origin_northing_m() const { return origin_northing_m_; }

  /// Local (x, y) of a geodetic point; throws InputError if the point cannot be projected
  /// into this zone (e.g. more than about 9 degrees outside it).
  Eigen::Vector2d local_from_geodetic(const Geodetic& p) const;
  Geodetic geodetic_from_local(const Eigen::Vector2d& xy_m, double z_m = 0.0) const;

  Eigen::Vector2d projected_from_local(const Eigen::Vector2d& xy_m) const {
    return {xy_m.x() + origin_easting_m_, xy_m.y() + origin_northing_m_};
  }
  Eigen::Vector2d local_from_projected(const Eigen::Vector2d& en_m) const {
    return {en_m.x() - origin_easting_m_, en_m.y() - origin_northing_m_};
  }

  /// Meridian convergence at a local point: the azimuth of grid north measured clockwise from
  /// true north, radians.
  double convergence_rad(const Eigen::Vector2d& xy_m) const;
  /// Point scale factor of the projection at a local point (grid distance / true distance).
  double scale_factor(const Eigen::Vector2d& xy_m) const;
  /// Converts an azimuth clockwise from true north into one clockwise from grid north.
  double grid_azimuth_from_true_rad(double true_azimuth_rad, const Eigen::Vector2d& xy_m) const {
    return true_azimuth_rad - convergence_rad(xy_m);
  }

 private:
  int zone_;
  bool northp_;
  double origin_easting_m_;
  double origin_northing_m_;
};

/// Degrees <-> radians, for I/O boundaries.
constexpr double kPi = 3.14159265358979323846;
constexpr double rad_from_deg(double deg) {
  return deg * (kPi / 180.0);
}
constexpr double deg_from_rad(double rad) {
  return rad * (180.0 / kPi);
}

}  // namespace sonarsynth
