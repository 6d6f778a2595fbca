// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "sonarsynth/beam_profile.hpp"
#include "sonarsynth/scene_object.hpp"
#include "sonarsynth/sonar.hpp"

namespace sonarsynth {

/// K along-track beam planes: azimuths from the across-track direction, evenly across +-1.25
/// horizontal beam widths (0 for K = 1), and their shares of `beta_eff_rad`, weighted by the
/// two-way horizontal pattern and summing to it exactly.
/// The plane at azimuth 0 (for an even count, the one just past it) is `central`: its truth is
/// the ping's.
struct AlongTrackPlanes {
  std::vector<double> azimuth_rad;
  std::vector<double> beta_eff_rad;
  std::size_t central = 0;
  std::size_t size() const { return azimuth_rad.size(); }
};
AlongTrackPlanes make_along_track_planes(const SonarConfig& sonar, int count, double beta_eff_rad);

/// Refines a run's planes for the ping sides that see an object narrower along the track than
/// the planes' spacing at its range (docs/physics.md §1.3, "Objects between the planes"): a post
/// 5 cm wide is then seen in every ping whose beam covers it, weighted by the horizontal
/// pattern, instead of in the one ping whose plane happens to cross it, at full strip weight.
///
/// Planes at multiples of a fine step d are added over each such object's azimuth interval,
/// at least kPlanesPerObject inside it and one outside on each side, so that the planes
/// crossing the object have cells of width d; every plane's share of beta_eff is the two-way
/// pattern's integral over its cell (cells end halfway to the neighbours and at the fan edges
/// +-1.25 beam widths), scaled so that the shares sum to beta_eff exactly: a flat seabed renders
/// identically refined or not. Cost: a few planes more in the pings that see a small object.
class ObjectPlaneRefiner {
 public:
  static constexpr int kPlanesPerObject = 3;
  static constexpr std::size_t kMaxPlanes = 255;

  ObjectPlaneRefiner(const ObjectSet& objects, const SonarConfig& sonar,
                     const AlongTrackPlanes& base, double beta_eff_rad);
  /// False (and `out` untouched) when no object in range of this side needs finer planes; else
  /// `out` holds the refined planes. `across` is the unit ground direction of the side's
  /// central plane, `nadir_xy_m` its origin, `max_y_m` the horizontal range of the planes.
  bool refine(const Eigen::Vector2d& nadir_xy_m, const Eigen::Vector2d& across, double max_y_m,
              AlongTrackPlanes& out, std::vector<double>& scratch) const;
  bool empty() const { return footprints_.empty(); }
  /// Whether the footprint of an object may lie in the planes' fan (+-1.25 horizontal beam
  /// widths) of the ping side at `nadir_xy_m` looking along `across`, within max_y_m: the
  /// conservative test of refine(), which a profile of that side can only confirm.
  bool sees_object(const Eigen::Vector2d& nadir_xy_m, const Eigen::Vector2d& across,
                   double max_y_m) const;

 private:
  struct Footprint {
    Eigen::Vector2d centre_xy_m;
    Eigen::Vector2d corner_xy_m[4];  ///< of the footprint's bounding rectangle (body axes)
    double radius_m;                 ///< centre to the farthest corner
  };
  bool in_fan(const Footprint& f, const Eigen::Vector2d& nadir_xy_m, const Eigen::Vector2d& across,
              double max_y_m) const;
  std::vector<Footprint> footprints_;
  AlongTrackPlanes base_;
  double beam_width_rad_;
  double beta_eff_rad_;
  double half_fan_rad_;
};

/// The slant ranges [r_lo_m, r_hi_m] outside which the objects of a beam-plane profile change
/// nothing in its render (render_side): from the objects' least distance to the sensor (an
/// object occludes only what lies behind it along the sensor's rays) to the largest slant range
/// of the nodes up to the first seabed node past the objects that the objects' horizon (their
/// least tan of depression) no longer hides, i.e. the end of their shadow; r_hi_m = +inf if the
/// shadow reaches the profile's end. Objects are the closed sections and the seabed facets
/// labelled with an object. Returns false (r unchanged) without objects.
bool object_range_window(const BeamProfile& profile, double& r_lo_m, double& r_hi_m);

/// Integral of SonarConfig::horizontal_two_way (for this beam width) over [psi0_rad, psi1_rad]
/// (closed form: the pattern is a Gaussian in azimuth), radians.
double horizontal_two_way_integral(double beam_width_rad, double psi0_rad, double psi1_rad);

}  // namespace sonarsynth
