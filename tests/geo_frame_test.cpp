// SPDX-License-Identifier: MIT
#include "sonarsynth/geo_frame.hpp"

#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>

#include "sonarsynth/error.hpp"

namespace sonarsynth {
namespace {

Geodetic deg(double lat, double lon) {
  return {rad_from_deg(lat), rad_from_deg(lon), 0.0};
}

// Round trip geodetic -> local -> geodetic; error measured as a geodesic distance.
double round_trip_error_m(const GeoFrame& f, const Geodetic& p) {
  const Geodetic q = f.geodetic_from_local(f.local_from_geodetic(p));
  double s12 = 0;
  GeographicLib::Geodesic::WGS84().Inverse(deg_from_rad(p.lat_rad), deg_from_rad(p.lon_rad),
                                           deg_from_rad(q.lat_rad), deg_from_rad(q.lon_rad), s12);
  return s12;
}

TEST(GeoFrame, ChoosesStandardZoneAndEpsg) {
  const GeoFrame north = GeoFrame::around(deg(48.45, -68.83));  // St. Lawrence: UTM 19N
  EXPECT_EQ(north.zone(), 19);
  EXPECT_TRUE(north.northp());
  EXPECT_EQ(north.epsg(), 32619);
  const GeoFrame south = GeoFrame::around(deg(-33.86, 151.21));  // Sydney: UTM 56S
  EXPECT_EQ(south.zone(), 56);
  EXPECT_FALSE(south.northp());
  EXPECT_EQ(south.epsg(), 32756);
  EXPECT_EQ(GeoFrame::around(deg(60.5, 5.5)).zone(), 32);       // Norway exception (32V)
  EXPECT_EQ(GeoFrame::around(deg(-89.0, 10.0)).epsg(), 32761);  // UPS south
}

TEST(GeoFrame, OriginNearCentreKeepsCoordinatesSmall) {
  const Geodetic c = deg(43.0678, -70.7048);
  const GeoFrame f = GeoFrame::around(c);
  const Eigen::Vector2d xy = f.local_from_geodetic(c);
  EXPECT_LT(xy.norm(), 800.0);  // rounded to whole kilometres
}

TEST(GeoFrame, RoundTripsNorthSouthAndAcrossZoneBoundary) {
  for (const Geodetic& p : {deg(48.45, -68.83), deg(-33.86, 151.21), deg(0.001, 3.0),
                            deg(-0.001, 3.0), deg(78.2, 15.6)}) {
    const GeoFrame f = GeoFrame::around(p);
    EXPECT_LT(round_trip_error_m(f, p), 1e-6) << p.lat_rad << " " << p.lon_rad;
  }
  // A frame in zone 31 (lon 0..6 E) used for points just across the boundary at 6 E, and a
  // survey that straddles the equator: still exact to GeographicLib's accuracy.
  const GeoFrame z31 = GeoFrame::around(deg(0.01, 5.99));
  ASSERT_EQ(z31.zone(), 31);
  EXPECT_LT(round_trip_error_m(z31, deg(0.01, 6.02)), 1e-6);
  EXPECT_LT(round_trip_error_m(z31, deg(-0.01, 6.02)), 1e-6);
  // The projection is continuous across the equator inside one frame.
  const Eigen::Vector2d a = z31.local_from_geodetic(deg(1e-6, 5.99));
  const Eigen::Vector2d b = z31.local_from_geodetic(deg(-1e-6, 5.99));
  EXPECT_NEAR((a - b).norm(), 0.2211, 1e-3);  // 2e-6 deg of latitude = 0.221 m
}

TEST(GeoFrame, LocalDistancesMatchGeodesicsToScaleFactor) {
  // Two points 1 km apart in the local frame, near the zone edge where k ~ 1.0006.
  const GeoFrame f = GeoFrame::around(deg(-45.0, 170.9));
  const Eigen::Vector2d p(200.0, 300.0), q(900.0, 1014.0);
  const Geodetic gp = f.geodetic_from_local(p), gq = f.geodetic_from_local(q);
  double s12 = 0;
  GeographicLib::Geodesic::WGS84().Inverse(deg_from_rad(gp.lat_rad), deg_from_rad(gp.lon_rad),
                                           deg_from_rad(gq.lat_rad), deg_from_rad(gq.lon_rad), s12);
  const double k = f.scale_factor(0.5 * (p + q));
  EXPECT_NEAR((q - p).norm() / k, s12, 1e-3);
}

TEST(GeoFrame, ConvergenceTurnsTrueIntoGridAzimuth) {
  // East of the central meridian in the north, grid north is east of true north (gamma > 0).
  const GeoFrame f = GeoFrame::around(deg(48.45, -68.83));  // zone 19, CM -69
  const Eigen::Vector2d p = f.local_from_geodetic(deg(48.45, -67.0));
  EXPECT_GT(f.convergence_rad(p), 0.0);
  // Walk due north (true) 1 km from p with GeographicLib and compare directions.
  double lat2 = 0, lon2 = 0;
  GeographicLib::Geodesic::WGS84().Direct(48.45, -67.0, 0.0, 1000.0, lat2, lon2);
  const Eigen::Vector2d q = f.local_from_geodetic(deg(lat2, lon2));
  const double grid_az = std::atan2(q.x() - p.x(), q.y() - p.y());
  EXPECT_NEAR(grid_az, f.grid_azimuth_from_true_rad(0.0, p), 1e-5);
}

TEST(GeoFrame, RejectsBadZone) {
  EXPECT_THROW(GeoFrame(61, true, 0, 0), InputError);
}

TEST(GeoFrame, AroundNamesTheBadCoordinate) {
  const auto message = [](double lat_deg, double lon_deg) {
    try {
      (void)GeoFrame::around({rad_from_deg(lat_deg), rad_from_deg(lon_deg), 0.0});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(57.0, INFINITY).find("lon_deg = inf. Violated constraint: finite"),
            std::string::npos)
      << message(57.0, INFINITY);
  EXPECT_EQ(message(57.0, INFINITY).find("lat_deg"), std::string::npos);
  EXPECT_EQ(message(57.0, INFINITY).find("latitude"), std::string::npos);
  EXPECT_NE(message(57.0, NAN).find("lon_deg = nan"), std::string::npos);
  EXPECT_NE(message(95.0, 5.0).find("lat_deg = 95"), std::string::npos);
  EXPECT_EQ(message(-90.0, 5.0), "");
}

}  // namespace
}  // namespace sonarsynth
